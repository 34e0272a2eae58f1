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
"""

from __future__ import annotations

from functools import cache

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit.trajectory._checks import check_durations, check_finite, check_waypoints
from armkit.trajectory.joint_trajectory import JointTrajectory
from armkit.trajectory.polynomial import quintic_coefficients

__all__ = ["min_jerk", "min_jerk_boundary_values"]


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


def min_jerk_boundary_values(waypoints: NDArray[np.float64], durations: NDArray[np.float64],
                             start: tuple[NDArray, NDArray], end: tuple[NDArray, NDArray]
                             ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Velocities and accelerations ``(M, n)`` at every waypoint of the minimum-jerk spline.

    ``start`` and ``end`` are the fixed ``(velocity, acceleration)`` at the two ends, ``(n,)`` each.
    Inputs are assumed checked (see :func:`min_jerk`).
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

    solution = solveh_banded(banded, rhs.reshape(K, n), check_finite=False).reshape(M - 2, 2, n)
    velocity[1:-1], acceleration[1:-1] = solution[:, 0], solution[:, 1]
    return velocity, acceleration


def min_jerk(waypoints: ArrayLike, durations: ArrayLike, *, start_velocity: ArrayLike = 0.0,
             end_velocity: ArrayLike = 0.0, start_acceleration: ArrayLike = 0.0,
             end_acceleration: ArrayLike = 0.0) -> JointTrajectory:
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

    Returns
    -------
    JointTrajectory
        Passes through every waypoint at the cumulative times; ``q``, ``qd``, ``qdd`` (and
        ``qddd``) continuous.

    Examples
    --------
    >>> traj = min_jerk([[0.0], [1.0], [0.0]], [1.0, 1.0])
    >>> traj.duration
    2.0
    >>> q, qd, qdd = traj.at_time(1.0)
    >>> q, abs(qd) < 1e-12
    (array([1.]), array([ True]))
    """
    waypoints = check_waypoints(waypoints)
    M, n = waypoints.shape
    durations = check_durations(durations, M - 1)
    ends = [np.broadcast_to(check_finite(value, name), (n,)) for name, value in (
        ("start_velocity", start_velocity), ("start_acceleration", start_acceleration),
        ("end_velocity", end_velocity), ("end_acceleration", end_acceleration))]
    velocity, acceleration = min_jerk_boundary_values(waypoints, durations, (ends[0], ends[1]),
                                                      (ends[2], ends[3]))
    coefficients = quintic_coefficients(waypoints[:-1], waypoints[1:], durations[:, None], velocity[:-1],
                                        velocity[1:], acceleration[:-1], acceleration[1:])
    return JointTrajectory(durations, coefficients, waypoints)

