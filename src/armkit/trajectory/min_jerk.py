"""Minimum-jerk trajectories through joint-space waypoints.

One quintic per segment, position, velocity and acceleration continuous at every
interior waypoint. The interior velocities and accelerations are the ones minimising the
total squared jerk ``sum_i integral |q'''(t)|^2 dt`` (the QP of report 000; with only
equality constraints it is a linear solve).

How it is solved
----------------
A quintic on ``[0, T]`` is fixed by its end values ``x = (q0, v0, a0, q1, v1, a1)`` and
its jerk cost is ``x^T H(T) x`` with ``H(T) = D H1 D / T^5``, ``D = diag(1, T, T^2, 1, T,
T^2)`` and ``H1`` the cost matrix of the unit interval. Setting the gradient with respect
to the interior ``(v_k, a_k)`` to zero gives a symmetric positive-definite block-tridiagonal
system (2x2 blocks, bandwidth 3), solved for all joints at once by a banded Cholesky
(:func:`scipy.linalg.solveh_banded`): O(M) time and memory. The solution is the
quintic spline with continuous third and fourth derivatives at the interior waypoints.

Position limits
---------------
The spline can overshoot its waypoints, and so leave a joint's position limits between two
waypoints that are inside them (a short segment after a long one, say). Given
``position_limits``, :func:`min_jerk` keeps every joint inside by holding it at rest
(``v = a = 0``) at chosen waypoints: wherever a segment of joint ``j`` leaves its range
(exact extremes, :func:`~armkit.trajectory.peaks.segment_ranges`), the joint is held at rest at
that segment's waypoint nearer the limit it crossed (the other one if that is held already),
and the spline is solved again with those values fixed (still a banded linear solve, per
joint). Each round holds at least one more waypoint, so this ends after at most ``M - 2``
rounds per joint; once both ends of a segment are at rest, the segment is the rest-to-rest
quintic, which moves monotonically from one waypoint to the other and so stays between
them. Joints and waypoints that never overshoot keep their minimum-jerk values; the result
is the minimum-jerk spline among those with the joint at rest at the held waypoints. Only
fixed, non-zero end velocities or accelerations (``start_velocity`` ...) can leave a segment
outside with both ends fixed: that is a :class:`~armkit.errors.JointLimitError` naming the
joint.
"""

from __future__ import annotations

from functools import cache

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit.chain import LIMIT_TOLERANCE
from armkit.errors import InputError, JointLimitError
from armkit.trajectory._checks import check_durations, check_finite, check_waypoints
from armkit.trajectory.joint_trajectory import JointTrajectory
from armkit.trajectory.peaks import segment_ranges
from armkit.trajectory.polynomial import quintic_coefficients

__all__ = ["min_jerk", "min_jerk_boundary_values", "rest_points"]


@cache
def _unit_cost() -> NDArray[np.float64]:
    """``H1`` (6, 6): the jerk cost of the quintic on ``[0, 1]`` as a form in ``(q0, v0, a0, q1, v1, a1)``."""
    basis = quintic_coefficients(*np.eye(6)[[0, 3]], 1.0, *np.eye(6)[[1, 4, 2, 5]])  # (6 coeffs, 6 inputs)
    jerk = np.array([6.0, 24.0, 60.0])[:, None] * basis[3:]                           # (3, 6)
    gram = 1.0 / (np.arange(3)[:, None] + np.arange(3) + 1.0)                        # integral s^(k+l)
    H1 = jerk.T @ gram @ jerk
    H1.setflags(write=False)
    return H1


def _segment_costs(durations: NDArray[np.float64]) -> NDArray[np.float64]:
    """``H(T_i)`` for every segment, ``(N, 6, 6)``."""
    T = durations[:, None]
    D = np.concatenate([np.ones_like(T), T, T**2] * 2, axis=1)                       # (N, 6)
    return _unit_cost() * D[:, :, None] * D[:, None, :] / durations[:, None, None] ** 5


def _held_at_rest(banded: NDArray[np.float64], held: NDArray[np.bool_]) -> NDArray[np.float64]:
    """``banded`` (upper form, bandwidth 3) with the unknowns ``held`` ``(K,)`` fixed at 0: their rows
    and columns replaced by the identity's (exact, as the fixed value is 0; the right-hand side's
    entries must be 0 too)."""
    banded = banded.copy()
    K = banded.shape[1]
    for u in np.flatnonzero(held):
        banded[:, u] = 0.0                                   # column u: A[u - 3 .. u, u]
        for d in range(1, 4):                                # row u: A[u, u + d]
            if u + d < K:
                banded[3 - d, u + d] = 0.0
        banded[3, u] = 1.0
    return banded


def min_jerk_boundary_values(waypoints: NDArray[np.float64], durations: NDArray[np.float64],
                             start: tuple[NDArray, NDArray], end: tuple[NDArray, NDArray],
                             rest: NDArray[np.bool_] | None = None
                             ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Velocities and accelerations ``(M, n)`` at every waypoint of the minimum-jerk spline.

    ``start`` and ``end`` are the fixed ``(velocity, acceleration)`` at the two ends, ``(n,)`` each;
    ``rest`` ``(M, n)``, where true at an interior waypoint, holds that joint at rest there
    (module notes). Inputs are assumed checked (see :func:`min_jerk`).
    """
    M, n = waypoints.shape
    velocity = np.empty((M, n))
    acceleration = np.empty((M, n))
    velocity[0], acceleration[0] = start
    velocity[-1], acceleration[-1] = end
    if M == 2:
        return velocity, acceleration
    H = _segment_costs(durations)
    left, right = H[:-1], H[1:]                   # segment ending at / starting from waypoint k
    diagonal = left[:, 4:6, 4:6] + right[:, 1:3, 1:3]                               # (M-2, 2, 2)
    coupling = H[1:-1, 1:3, 4:6]                                                     # (M-3, 2, 2)
    K = 2 * (M - 2)
    banded = np.zeros((4, K))                     # upper form: banded[3 + i - j, j] = A[i, j]
    banded[3, 0::2], banded[3, 1::2] = diagonal[:, 0, 0], diagonal[:, 1, 1]
    banded[2, 1::2] = diagonal[:, 0, 1]
    banded[1, 2::2], banded[0, 3::2] = coupling[:, 0, 0], coupling[:, 0, 1]
    banded[2, 2::2], banded[1, 3::2] = coupling[:, 1, 0], coupling[:, 1, 1]
    q = waypoints
    rhs = -(np.einsum("kij,kjn->kin", left[:, 4:6, [0, 3]], np.stack([q[:-2], q[1:-1]], axis=1))
            + np.einsum("kij,kjn->kin", right[:, 1:3, [0, 3]], np.stack([q[1:-1], q[2:]], axis=1)))
    rhs[0] -= H[0, 4:6, 1:3] @ np.stack(start)
    rhs[-1] -= H[-1, 1:3, 4:6] @ np.stack(end)
    from scipy.linalg import solveh_banded  # here: importing scipy.linalg costs ~0.2 s at start-up

    rhs = rhs.reshape(K, n)
    held = np.zeros((K, n), dtype=bool) if rest is None else np.repeat(rest[1:-1], 2, axis=0)
    solution = np.empty((K, n))
    free = ~held.any(axis=0)
    if free.any():
        solution[:, free] = solveh_banded(banded, rhs[:, free], check_finite=False)
    for j in np.flatnonzero(~free):
        solution[:, j] = solveh_banded(_held_at_rest(banded, held[:, j]),
                                       np.where(held[:, j], 0.0, rhs[:, j]), check_finite=False)
    solution = solution.reshape(M - 2, 2, n)
    velocity[1:-1], acceleration[1:-1] = solution[:, 0], solution[:, 1]
    return velocity, acceleration


def _position_limits(position_limits: ArrayLike, n: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``position_limits`` ``(n, 2)`` [rad or m] as lower and upper ``(n,)`` (``-inf``/``inf``: none)."""
    try:
        limits = np.asarray(position_limits, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InputError(f"position_limits: expected numbers, got {position_limits!r}") from exc
    if limits.shape != (n, 2) or np.isnan(limits).any() or np.any(limits[:, 0] > limits[:, 1]):
        raise InputError(f"position_limits: expected ({n}, 2) rows (lower, upper) with lower <= upper "
                         f"(inf for none), got {limits.tolist()}")
    return limits[:, 0], limits[:, 1]


def _spline(waypoints, durations, start, end, rest):
    velocity, acceleration = min_jerk_boundary_values(waypoints, durations, start, end, rest)
    return quintic_coefficients(waypoints[:-1], waypoints[1:], durations[:, None], velocity[:-1],
                                velocity[1:], acceleration[:-1], acceleration[1:])


def _inside_limits(waypoints, durations, start, end, lower, upper, rest):
    """The spline's coefficients and rest points ``(M, n)``: joints held at rest at more waypoints
    than ``rest`` until every segment stays inside ``lower .. upper`` (module notes)."""
    M, n = waypoints.shape
    rest = rest.copy()
    # a segment may reach its own waypoints, even one within LIMIT_TOLERANCE outside a limit
    ceiling = np.maximum(upper, np.maximum(waypoints[:-1], waypoints[1:]))
    floor = np.minimum(lower, np.minimum(waypoints[:-1], waypoints[1:]))
    while True:
        coefficients = _spline(waypoints, durations, start, end, rest)
        low, high = segment_ranges(coefficients, durations)
        solved = rest.copy()                      # the rest points of the spline just checked
        for i, j in np.argwhere((high > ceiling) | (low < floor)):
            up = high[i, j] > ceiling[i, j]
            ends = sorted((i, i + 1), key=lambda k: -waypoints[k, j] if up else waypoints[k, j])
            free = [k for k in ends if 0 < k < M - 1 and not solved[k, j]]
            if free:
                if not rest[free[0], j] and not any(rest[k, j] > solved[k, j] for k in ends):
                    rest[free[0], j] = True
            elif max(high[i, j] - ceiling[i, j], floor[i, j] - low[i, j]) > LIMIT_TOLERANCE:
                raise JointLimitError(f"joint {j + 1} = {low[i, j]:.6g} .. {high[i, j]:.6g} between "
                                      f"waypoints {i + 1} and {i + 2} is outside its limits "
                                      f"[{lower[j]:.6g}, {upper[j]:.6g}], and its end velocities or "
                                      f"accelerations are fixed there: no spline through them stays inside")
        if (rest == solved).all():
            return coefficients, rest


def _rest_mask(rest: ArrayLike | None, shape: tuple[int, int]) -> NDArray[np.bool_]:
    if rest is None:
        return np.zeros(shape, dtype=bool)
    mask = np.asarray(rest)
    if mask.shape != shape or mask.dtype != bool:
        raise InputError(f"rest: expected a boolean array of shape {shape} (waypoints x joints), got "
                         f"{mask.dtype} {mask.shape}")
    return mask


def rest_points(waypoints: ArrayLike, durations: ArrayLike, position_limits: ArrayLike,
                rest: ArrayLike | None = None) -> NDArray[np.bool_]:
    """Where :func:`min_jerk` with ``position_limits`` holds each joint at rest: ``(M, n)`` bool, at
    least ``rest`` (rest to rest at both ends). See the module notes.

    >>> rest_points([[0.0], [1.0], [0.0]], [1.0, 0.6], [[-1.05, 1.05]])[:, 0].tolist()
    [False, True, False]
    """
    waypoints = check_waypoints(waypoints)
    M, n = waypoints.shape
    durations = check_durations(durations, M - 1)
    zero = (np.zeros(n), np.zeros(n))
    return _inside_limits(waypoints, durations, zero, zero, *_position_limits(position_limits, n),
                          _rest_mask(rest, (M, n)))[1]


def min_jerk(waypoints: ArrayLike, durations: ArrayLike, *, start_velocity: ArrayLike = 0.0,
             end_velocity: ArrayLike = 0.0, start_acceleration: ArrayLike = 0.0,
             end_acceleration: ArrayLike = 0.0, position_limits: ArrayLike | None = None,
             rest: ArrayLike | None = None) -> JointTrajectory:
    """The minimum-jerk piecewise-quintic trajectory through ``waypoints``.

    Parameters
    ----------
    waypoints : (M, n) array
        Joint positions [rad or m], ``M >= 2``; a 1-D array is one joint.
    durations : (M - 1,) array
        Segment durations [s], positive.
    start_velocity, end_velocity : float or (n,) array
        [rad/s or m/s], zero by default (start and end at rest).
    start_acceleration, end_acceleration : float or (n,) array
        [rad/s^2 or m/s^2], zero by default.
    position_limits : (n, 2) array, optional
        Lower and upper position limit per joint [rad or m] (``-inf``/``inf``: none), e.g.
        ``robot.limits``: the spline stays inside them between the waypoints, joints held at
        rest at waypoints where it would leave them (module notes). Waypoints must be inside.
    rest : (M, n) bool array, optional
        Hold joint ``j`` at rest (``v = a = 0``) at interior waypoint ``k`` where ``rest[k, j]``
        (e.g. :func:`rest_points`); the spline is the minimum-jerk one among those that do.

    Returns
    -------
    JointTrajectory
        Passes through every waypoint at the cumulative times; ``q``, ``qd``, ``qdd`` (and
        ``qddd``) continuous.

    Raises
    ------
    JointLimitError
        With ``position_limits``, where fixed non-zero end velocities or accelerations carry a
        joint out of its limits.

    Examples
    --------
    >>> traj = min_jerk([[0.0], [1.0], [0.0]], [1.0, 1.0])
    >>> traj.duration
    2.0
    >>> q, qd, qdd = traj.at_time(1.0)
    >>> q, abs(qd) < 1e-12
    (array([1.]), array([ True]))

    A short segment after a long one overshoots; within limits of +-1.05 it does not:

    >>> waypoints, durations = [[0.0], [1.0], [0.0]], [1.0, 0.6]
    >>> round(float(min_jerk(waypoints, durations).position_range[1][0]), 3)
    1.129
    >>> inside = min_jerk(waypoints, durations, position_limits=[[-1.05, 1.05]])
    >>> round(float(inside.position_range[1][0]), 3), inside.at_time(1.0)[1]   # at rest at the turn
    (1.0, array([0.]))
    """
    waypoints = check_waypoints(waypoints)
    M, n = waypoints.shape
    durations = check_durations(durations, M - 1)
    ends = [np.broadcast_to(check_finite(value, name), (n,)) for name, value in (
        ("start_velocity", start_velocity), ("start_acceleration", start_acceleration),
        ("end_velocity", end_velocity), ("end_acceleration", end_acceleration))]
    start, end = (ends[0], ends[1]), (ends[2], ends[3])
    mask = _rest_mask(rest, (M, n))
    if position_limits is None:
        coefficients = _spline(waypoints, durations, start, end, mask)
    else:
        coefficients = _inside_limits(waypoints, durations, start, end, *_position_limits(position_limits, n),
                                      mask)[0]
    return JointTrajectory(durations, coefficients, waypoints)

