"""Calling armkit's numba kernels: without per-call type dispatch, and saying when they compile.

A call to a ``@njit`` function first works out the numba type of every argument; for a
named tuple of a few dozen fields (the chain data the IK kernels take) that costs about
5 us, more than the kernel itself on one pose. :func:`entry_point` resolves the types
once and returns the compiled function for them; its callers keep it per chain.

The kernels are compiled on first use and cached on disk (``cache=True``): the first
run on a machine spends up to a minute compiling, later ones load them in well under a
second. :func:`announce_compilation` lets the command line say so when it happens.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

import numba
from numba.core import event

__all__ = ["announce_compilation", "entry_point"]


def entry_point(kernel: Any, *args: Any) -> Callable[..., Any]:
    """The compiled version of ``kernel`` (an ``@njit`` dispatcher) for the types of ``args``.

    Compiles (or loads from numba's cache) on the first request. The returned function
    must only be called with arguments of exactly those types (array dtypes, dimensions
    and layouts included).
    """
    return kernel.compile(tuple(numba.typeof(a) for a in args))


class _FirstCompile(event.Listener):
    """Calls ``notify`` at the start of the first compilation it hears of."""

    def __init__(self, notify: Callable[[], None]) -> None:
        self.notify_once: Callable[[], None] | None = notify

    def on_start(self, event: event.Event) -> None:
        if self.notify_once is not None:
            notify, self.notify_once = self.notify_once, None
            notify()

    def on_end(self, event: event.Event) -> None:
        pass


@contextmanager
def announce_compilation(notify: Callable[[], None]) -> Iterator[None]:
    """Within the block, call ``notify()`` once when numba starts compiling a kernel.

    Loading a kernel from numba's on-disk cache is not compiling and stays silent.

    >>> with announce_compilation(lambda: print("compiling")):
    ...     pass
    """
    with event.install_listener("numba:compile", _FirstCompile(notify)):
        yield
