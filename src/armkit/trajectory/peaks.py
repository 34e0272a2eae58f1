"""Exact peaks of polynomial pieces: the largest ``|d^k q / dt^k|`` and the range of ``q`` on each segment.

The extremes of a polynomial on an interval lie at its ends or at real roots of its
derivative. The core (``cpp/include/armkit/polynomial.hpp``) finds every such root in the
interval from the derivative cascade (between two roots of ``p^(k+1)``, ``p^(k)`` is monotone:
one root at most, found by bracketed Newton steps), so the peaks are exact to rounding, not
sampled, in linear time with no eigenvalue problem.
"""

from __future__ import annotations

import numpy as np
from numpy.polynomial import polynomial as P
from numpy.typing import NDArray

__all__ = ["segment_peaks", "segment_ranges"]


def segment_peaks(coefficients: NDArray[np.float64], durations: NDArray[np.float64],
                  order: int) -> NDArray[np.float64]:
    """Largest ``|d^order q / dt^order|`` on each segment and joint, ``(N, n)``.

    Parameters
    ----------
    coefficients : (k + 1, N, n) array
        Ascending powers of the local time ``t - t_i`` [s] of each segment's polynomials.
    durations : (N,) array
        Segment durations [s].
    order : int
        1 velocity, 2 acceleration, 3 jerk.
    """
    N, n = coefficients.shape[1:]
    low, high = _extremes(coefficients, durations, order)
    scale = np.repeat(durations, n) ** order
    return (np.maximum(-low, high) / scale).reshape(N, n)


def segment_ranges(coefficients: NDArray[np.float64],
                   durations: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Lowest and highest ``q`` on each segment and joint, two ``(N, n)`` arrays [rad or m].

    Parameters are those of :func:`segment_peaks`; the extremes are exact (ends and
    interior turning points), not sampled.
    """
    N, n = coefficients.shape[1:]
    low, high = _extremes(coefficients, durations, 0)
    return low.reshape(N, n), high.reshape(N, n)


def _extremes(coefficients: NDArray[np.float64], durations: NDArray[np.float64],
              order: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Lowest and highest ``d^order q / ds^order`` (``s = t / T_i`` in [0, 1]), two ``(N n,)`` arrays."""
    from armkit import _core

    k1, N, n = coefficients.shape
    powers = np.arange(k1)[:, None, None]
    c = coefficients * durations[None, :, None] ** powers  # polynomials in s = t / T_i
    for _ in range(order):
        c = P.polyder(c, axis=0)
    c = np.ascontiguousarray(c.reshape(c.shape[0], N * n))
    low, high = np.empty(N * n), np.empty(N * n)
    _core.polynomial_extremes(c, low, high)
    return low, high
