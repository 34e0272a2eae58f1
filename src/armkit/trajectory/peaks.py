"""Exact peaks of polynomial pieces: the largest ``|d^k q / dt^k|`` and the range of ``q`` on each segment.

The extremes of a polynomial on an interval lie at its ends or at real roots of its
derivative; the roots come from companion-matrix eigenvalues (batched with numpy), so the
peaks are exact to rounding, not sampled.
"""

from __future__ import annotations

import numpy as np
from numpy.polynomial import polynomial as P
from numpy.typing import NDArray

__all__ = ["segment_peaks", "segment_ranges"]

#: A derivative whose leading coefficient is below this fraction of its largest one is
#: treated as one degree lower (its roots found one row at a time).
_DEGENERATE = 1e-12


def _critical_points(c: NDArray[np.float64]) -> NDArray[np.float64]:
    """Candidate arguments in ``[0, 1]`` of the extremes of ``|p|``; ``c`` is ``(m + 1, R)`` ascending."""
    dc = P.polyder(c, axis=0)
    rows = c.shape[1]
    ends = np.broadcast_to([0.0, 1.0], (rows, 2))
    if dc.shape[0] < 2:
        return ends
    lead = dc[-1]
    regular = np.abs(lead) > _DEGENERATE * np.abs(dc).max(axis=0)
    degree = dc.shape[0] - 1
    roots = np.zeros((rows, degree))
    companion = np.zeros((int(regular.sum()), degree, degree))
    companion[:, np.arange(1, degree), np.arange(degree - 1)] = 1.0
    companion[:, :, -1] = -(dc[:-1, regular] / lead[regular]).T
    roots[regular] = np.linalg.eigvals(companion).real
    for r in np.flatnonzero(~regular):
        found = P.polyroots(P.polytrim(dc[:, r], _DEGENERATE * np.abs(dc[:, r]).max())).real
        roots[r, :found.size] = found
    # Real parts of every root, clipped into [0, 1]: a superset of the interior extremes.
    return np.concatenate([ends, np.clip(roots, 0.0, 1.0)], axis=1)


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
    values = _critical_values(coefficients, durations, order)
    scale = np.repeat(durations, n) ** order
    return (np.abs(values).max(axis=1) / scale).reshape(N, n)


def segment_ranges(coefficients: NDArray[np.float64],
                   durations: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Lowest and highest ``q`` on each segment and joint, two ``(N, n)`` arrays [rad or m].

    Parameters are those of :func:`segment_peaks`; the extremes are exact (ends and
    interior turning points), not sampled.
    """
    N, n = coefficients.shape[1:]
    values = _critical_values(coefficients, durations, 0)
    return values.min(axis=1).reshape(N, n), values.max(axis=1).reshape(N, n)


def _critical_values(coefficients: NDArray[np.float64], durations: NDArray[np.float64],
                     order: int) -> NDArray[np.float64]:
    """``d^order q / ds^order`` (``s = t / T_i``) at its candidate extremes, ``(N n, K)``."""
    k1, N, n = coefficients.shape
    powers = np.arange(k1)[:, None, None]
    c = coefficients * durations[None, :, None] ** powers  # polynomials in s = t / T_i
    for _ in range(order):
        c = P.polyder(c, axis=0)
    c = c.reshape(c.shape[0], N * n)
    s = _critical_points(c)                                   # (R, K)
    return np.einsum("rkm,mr->rk", s[..., None] ** np.arange(c.shape[0]), c)
