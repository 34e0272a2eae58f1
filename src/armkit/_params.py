"""Checks of numeric parameters, one per kind: each returns the value as a Python number or
raises one :class:`~armkit.errors.InputError` naming the parameter, the value and the valid range.

``threads=`` means the same everywhere (FK, Jacobians, IK, numeric IK batches, dynamics,
collision scenes, workspace engines): ``None`` is every core, ``1`` to :data:`MAX_THREADS` exactly
that many threads, anything else (``0``, a negative number, a float) is refused
(:func:`thread_count`).
"""

from __future__ import annotations

import math
from numbers import Integral, Real

import numpy as np
from numpy.typing import NDArray

from armkit.errors import InputError

__all__ = ["MAX_COUNT", "MAX_THREADS", "core_ready", "float_array", "non_negative_float", "positive_float",
           "thread_count", "whole_number"]

_FLOAT64 = np.dtype(np.float64)  # native byte order

#: Most threads a batch is split over (more only add start-up cost on any machine made yet).
MAX_THREADS = 1024

#: Largest count (iterations, restarts) the compiled core takes: its 32-bit ``int``.
MAX_COUNT = 2**31 - 1


def _real(value: object) -> float | None:
    """``value`` as a float if it is a real number (not a bool, not a string), else ``None``."""
    if isinstance(value, bool) or not isinstance(value, Real):
        return None
    return float(value)


def positive_float(value: object, name: str, *, maximum: float = math.inf) -> float:
    """``value`` as a finite float in ``(0, maximum]``.

    >>> positive_float(1e-9, "position_tolerance")
    1e-09
    >>> positive_float(-1, "position_tolerance")
    Traceback (most recent call last):
    armkit.errors.InputError: position_tolerance: expected a finite number > 0, got -1
    """
    number = _real(value)
    if number is None or not 0.0 < number <= maximum or not math.isfinite(number):
        bound = "> 0" if maximum == math.inf else f"in (0, {maximum:g}]"
        raise InputError(f"{name}: expected a finite number {bound}, got {value!r}", parameter=name,
                         value=value)
    return number


def float_in_range(value: object, name: str, low: float, high: float, what: str) -> float:
    """``value`` as a float in ``[low, high]`` (a real number: not a bool, not a string), or an
    :class:`InputError` saying it expected ``what`` in that range.

    >>> float_in_range("1e-4", "tol", 1e-12, 0.5, "a relative accuracy")
    Traceback (most recent call last):
    armkit.errors.InputError: tol: expected a relative accuracy from 1e-12 to 0.5, got '1e-4'
    """
    number = _real(value)
    if number is None or not low <= number <= high:
        raise InputError(f"{name}: expected {what} from {low:g} to {high:g}, got {value!r}", parameter=name,
                         value=value)
    return number


def non_negative_float(value: object, name: str, *, infinite: bool = False) -> float:
    """``value`` as a float ``>= 0``, finite unless ``infinite`` allows ``inf`` ("no bound").

    >>> non_negative_float(float("nan"), "damping")
    Traceback (most recent call last):
    armkit.errors.InputError: damping: expected a finite number >= 0, got nan
    >>> non_negative_float(float("inf"), "time_budget", infinite=True)
    inf
    """
    number = _real(value)
    if number is None or not number >= 0.0 or (number == math.inf and not infinite):
        kind = "a number >= 0 (inf: no bound)" if infinite else "a finite number >= 0"
        raise InputError(f"{name}: expected {kind}, got {value!r}", parameter=name, value=value)
    return number


def whole_number(value: object, name: str, *, minimum: int, maximum: int = MAX_COUNT) -> int:
    """``value`` as an int in ``[minimum, maximum]`` (a bool or a float such as ``3.0`` is refused).

    >>> whole_number(10**12, "max_iterations", minimum=1)
    Traceback (most recent call last):
    armkit.errors.InputError: max_iterations: expected a whole number from 1 to 2147483647, got 1000000000000
    """
    if isinstance(value, bool) or not isinstance(value, Integral) or not minimum <= value <= maximum:
        raise InputError(f"{name}: expected a whole number from {minimum} to {maximum}, got {value!r}",
                         parameter=name, value=value)
    return int(value)


def thread_count(value: object, name: str = "threads") -> int:
    """``threads=`` as every armkit function takes it, for the core: ``None`` (every core) gives ``0``,
    a whole number from 1 to :data:`MAX_THREADS` that many threads; anything else (``0``, a negative
    number, a float, a bool) is refused. The one check of the word ``threads``.

    >>> thread_count(None), thread_count(2)
    (0, 2)
    >>> thread_count(0)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    armkit.errors.InputError: threads: expected None (every core) or a whole number of threads from 1 to ...
    """
    if value is None:
        return 0
    if type(value) is int and 1 <= value <= MAX_THREADS:  # the usual call, without the ABC test below
        return value
    if isinstance(value, bool) or not isinstance(value, Integral) or not 1 <= value <= MAX_THREADS:
        raise InputError(f"{name}: expected None (every core) or a whole number of threads from 1 to "
                         f"{MAX_THREADS}, got {value!r}", parameter=name, value=value)
    return int(value)


def float_array(value: object, label: str, expected: str) -> NDArray[np.float64]:
    """``value`` as a C-ordered float64 array (itself if it already is one, :func:`core_ready`);
    its shape and values are the caller's to check.

    >>> float_array([1, 2], "near", "2 joint values").dtype
    dtype('float64')
    >>> float_array("x", "near", "2 joint values")
    Traceback (most recent call last):
    armkit.errors.InputError: near: expected 2 joint values, got 'x'
    """
    if core_ready(value):
        return value
    try:
        return np.ascontiguousarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{label}: expected {expected}, got {value!r}", parameter=label,
                         value=value) from exc


def core_ready(value: object, shape: tuple[int, ...] = (), *, exact: bool = False) -> bool:
    """Whether ``value`` is already what the compiled core takes, so that no copy or check is
    needed before the call: a NumPy array (not a subclass) of native float64, C-ordered, whose
    shape ends with ``shape`` (is ``shape`` with ``exact``). Its values are not looked at (the
    core checks finiteness in its loop). The one readiness test of the package.

    >>> core_ready(np.zeros((3, 6)), (6,)), core_ready(np.zeros((3, 6)), (6,), exact=True)
    (True, False)
    >>> core_ready(np.zeros(6, dtype=">f8"), (6,)), core_ready([0.0] * 6, (6,))
    (False, False)
    """
    if type(value) is not np.ndarray or value.dtype != _FLOAT64 or not value.flags.c_contiguous:
        return False
    if exact:
        return value.shape == shape
    return not shape or value.shape[-len(shape):] == shape
