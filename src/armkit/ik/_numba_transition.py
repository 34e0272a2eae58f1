"""Transitional numba kernels for the modules not yet ported to the compiled core.

:mod:`armkit.ik.solve` (``wrap_angle_into_limits``) and :mod:`armkit.ik.closed_form`
(``_damped_step``) call these from their own numba loops, which cannot call the C++ core.
They import them from :mod:`armkit.ik.numeric` (its module ``__getattr__`` loads this module on
first use, so the numeric solver itself imports no numba). The compiled core has the one real
implementation of each (``wrap_angle_into_limits`` in transform.hpp, ``damped_step`` in
linalg.hpp): delete this module, and the ``__getattr__`` in numeric.py, once solve.py and
closed_form.py call the core.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, vectorize
from numpy.typing import NDArray

from armkit.chain import LIMIT_TOLERANCE

_TWO_PI = 2.0 * math.pi
#: As kSingularDamping in linalg.hpp.
_SINGULAR_DAMPING = 1e-10


@vectorize(["float64(float64, float64, float64, float64)"], cache=True)
def wrap_angle_into_limits(q: float, lower: float, upper: float, reference: float) -> float:
    """A revolute angle shifted by whole turns into ``[lower, upper]`` (a NumPy ufunc; the
    core's ``wrap_angle_into_limits``)."""
    low, high = lower - LIMIT_TOLERANCE, upper + LIMIT_TOLERANCE
    if low <= q <= high and high - low < _TWO_PI:  # fits, and no other shift can: the usual case
        return q
    turns_low = np.ceil((low - q) / _TWO_PI)
    turns_high = np.floor((high - q) / _TWO_PI)
    turns = np.rint((reference - q) / _TWO_PI)
    if turns_low <= turns_high:
        turns = min(max(turns, turns_low), turns_high)
    return q + _TWO_PI * turns


@njit(cache=True)
def _cholesky_solve(A: NDArray[np.float64], b: NDArray[np.float64]) -> bool:
    """The core's ``cholesky_solve``: ``A x = b`` in place, ``False`` if not positive definite."""
    k = b.shape[0]
    for j in range(k):
        d = A[j, j]
        for p in range(j):
            d -= A[j, p] * A[j, p]
        if not d > 0.0:
            return False
        d = math.sqrt(d)
        A[j, j] = d
        for i in range(j + 1, k):
            s = A[i, j]
            for p in range(j):
                s -= A[i, p] * A[j, p]
            A[i, j] = s / d
    for i in range(k):  # L y = b
        s = b[i]
        for p in range(i):
            s -= A[i, p] * b[p]
        b[i] = s / A[i, i]
    for i in range(k - 1, -1, -1):  # L^T x = y
        s = b[i]
        for p in range(i + 1, k):
            s -= A[p, i] * b[p]
        b[i] = s / A[i, i]
    return True


@njit(cache=True)
def _solve_normal_equations(Jm: NDArray[np.float64], em: NDArray[np.float64], damping: float,
                            x: NDArray[np.float64]) -> bool:
    """The damped normal equations of the core's ``damped_step``, by Cholesky."""
    m, n = Jm.shape
    wide = m <= n
    size = x.shape[0]
    A = np.empty((size, size))
    for a in range(size):
        for b in range(a + 1):
            s = 0.0
            if wide:
                for i in range(n):
                    s += Jm[a, i] * Jm[b, i]
            else:
                for k in range(m):
                    s += Jm[k, a] * Jm[k, b]
            A[a, b] = s
        A[a, a] += damping
        if wide:
            x[a] = em[a]
        else:
            s = 0.0
            for k in range(m):
                s += Jm[k, a] * em[k]
            x[a] = s
    return _cholesky_solve(A, x)


@njit(cache=True)
def _damped_step(J: NDArray[np.float64], e: NDArray[np.float64], rows: NDArray[np.int64],
                 sides: NDArray[np.float64], damping: float, dq: NDArray[np.float64]) -> None:
    """The core's ``damped_step`` (linalg.hpp) for closed_form.py's numba Newton steps."""
    m, n = rows.shape[0], J.shape[1]
    Jm, em = np.empty((m, n)), np.empty(m)
    for k in range(m):
        em[k] = e[rows[k]]
    trace = 0.0
    for i in range(n):
        frozen = False
        if sides[i] != 0.0:
            gradient = 0.0
            for k in range(m):
                gradient += em[k] * J[rows[k], i]
            frozen = gradient * sides[i] > 0.0
        for k in range(m):
            Jm[k, i] = 0.0 if frozen else J[rows[k], i]
            trace += Jm[k, i] * Jm[k, i]
    wide = m <= n
    x = np.empty(m if wide else n)
    if not _solve_normal_equations(Jm, em, damping, x) and not _solve_normal_equations(
            Jm, em, damping + _SINGULAR_DAMPING * trace, x):
        for k in range(x.shape[0]):  # J is all zeros: no direction lowers the error
            x[k] = 0.0
    for i in range(n):
        if wide:
            s = 0.0
            for k in range(m):
                s += Jm[k, i] * x[k]
            dq[i] = s
        else:
            dq[i] = x[i]
