"""Calling numba kernels without numba's per-call type dispatch.

A call to a ``@njit`` function first works out the numba type of every argument; for a
named tuple of a few dozen fields (the chain data the IK kernels take) that costs about
5 us, more than the kernel itself on one pose. :func:`entry_point` resolves the types
once and returns the compiled function for them; its callers keep it per chain.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numba

__all__ = ["entry_point"]


def entry_point(kernel: Any, *args: Any) -> Callable[..., Any]:
    """The compiled version of ``kernel`` (an ``@njit`` dispatcher) for the types of ``args``.

    Compiles (or loads from numba's cache) on the first request. The returned function
    must only be called with arguments of exactly those types (array dtypes, dimensions
    and layouts included).
    """
    return kernel.compile(tuple(numba.typeof(a) for a in args))
