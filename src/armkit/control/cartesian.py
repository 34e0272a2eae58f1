"""Cartesian straight-line trajectories: a line for the position, SLERP for the orientation.

The tool pose follows

    p(t) = p0 + s(t) (p1 - p0),      R(t) = exp(s(t) theta [k]x) R0

where ``theta k`` is the rotation vector of ``R1 R0^T`` (base frame), i.e. spherical
linear interpolation (SLERP) of the orientation along the shortest arc, and ``s(t)`` is
the quintic time law (0 to 1 with zero velocity and acceleration at both ends). The
tool twist is then ``[s' (p1 - p0); s' theta k]`` and its derivative
``[s'' (p1 - p0); s'' theta k]``, both in the base frame.

Joint space: ``method="ik"`` solves every sample with ``robot.ik(T, near=q_previous)``
so the joint path stays on one branch; ``method="closed-loop"`` follows the poses with
:func:`~armkit.control.motions.track_poses`. Either way the joint velocities come from
``J qd = twist`` and the accelerations from ``J qdd = twist' - J' qd`` at every sample
(``J' qd`` by a central difference along ``qd``), so ``q, qd, qdd`` are consistent.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit._deprecation import renamed_argument
from armkit._time import even_time_grid
from armkit.control._checks import check_positive, check_start
from armkit.control.motions import DEFAULT_DT, track_poses
from armkit.control.resolved_rate import ResolvedRate
from armkit.errors import InputError, JointLimitError, UnreachableError
from armkit.robot import Robot
from armkit.spatial.rotations import axis_angle_from_matrix, matrix_from_axis_angle
from armkit.spatial.transforms import check_transform
from armkit.trajectory import export
from armkit.trajectory.polynomial import quintic

__all__ = ["CartesianTrajectory", "cartesian_line", "line_poses"]

#: Largest joint change [rad or m] allowed between two IK samples before it counts as a jump.
MAX_SAMPLE_STEP = 0.5
#: Position error [m] beyond which the closed loop counts a point as not reached.
REACH_TOLERANCE = 1e-4


@dataclass(frozen=True)
class CartesianTrajectory:
    """A sampled Cartesian straight line in joint space.

    Attributes
    ----------
    t : (K,) array
        Sample times [s].
    q, qd, qdd : (K, n) arrays
        Joint positions [rad or m], velocities [/s] and accelerations [/s^2].
    poses : (K, 4, 4) array
        The tool poses asked for at ``t``.
    method : str
        ``"ik"`` or ``"closed-loop"``.
    """

    t: NDArray[np.float64]
    q: NDArray[np.float64]
    qd: NDArray[np.float64]
    qdd: NDArray[np.float64]
    poses: NDArray[np.float64]
    method: str

    def to_csv(self, path: str | Path, overwrite: bool = False) -> Path:
        """Write ``t, q1..qn, qd1..qdn, qdd1..qddn`` (SI units) as CSV with a header line."""
        return export.write_csv(self, path, overwrite)

    def to_npz(self, path: str | Path, overwrite: bool = False) -> Path:
        """Write the same columns as NPZ, one array per column name."""
        return export.write_npz(self, path, overwrite)


def line_poses(T_start: ArrayLike, T_goal: ArrayLike, t: ArrayLike,
               duration: float) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Poses, twists and twist derivatives of the straight line at times ``t``.

    Parameters
    ----------
    T_start, T_goal : (4, 4) arrays
        End poses [m].
    t : (K,) array
        Times in ``[0, duration]`` [s].
    duration : float
        [s].

    Returns
    -------
    poses : (K, 4, 4) array
    twists : (K, 6) array
        ``[v; w]`` [m/s, rad/s], base frame.
    twist_rates : (K, 6) array
        Their time derivatives [m/s^2, rad/s^2].

    Examples
    --------
    >>> T0, T1 = np.eye(4), np.eye(4)
    >>> T1[:3, 3] = [0.1, 0.0, 0.0]
    >>> poses, twists, _ = line_poses(T0, T1, [0.0, 0.5, 1.0], 1.0)
    >>> poses[:, 0, 3], twists[:, 0]
    (array([0.  , 0.05, 0.1 ]), array([0.    , 0.1875, 0.    ]))
    """
    T_start, T_goal = check_transform(T_start, "T_start"), check_transform(T_goal, "T_goal")
    s, sd, sdd = (x[:, 0] for x in quintic(0.0, 1.0, duration).at_time(t)[:3])
    dp = T_goal[:3, 3] - T_start[:3, 3]
    rotvec = axis_angle_from_matrix(T_goal[:3, :3] @ T_start[:3, :3].T)
    poses = np.broadcast_to(np.eye(4), (s.size, 4, 4)).copy()
    poses[:, :3, :3] = matrix_from_axis_angle(np.outer(s, rotvec)) @ T_start[:3, :3]
    poses[:, :3, 3] = T_start[:3, 3] + np.outer(s, dp)
    direction = np.concatenate([dp, rotvec])
    return poses, np.outer(sd, direction), np.outer(sdd, direction)


def _joint_rates(robot: Robot, q: NDArray[np.float64], twists: NDArray[np.float64],
                 twist_rates: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``qd`` from ``J qd = twist`` and ``qdd`` from ``J qdd = twist' - J' qd`` (least squares)."""
    J_pinv = np.linalg.pinv(robot.jacobian(q))
    qd = np.einsum("kij,kj->ki", J_pinv, twists)
    h = 1e-6
    J_dot_qd = np.einsum("kij,kj->ki", robot.jacobian(q + h * qd) - robot.jacobian(q - h * qd), qd) / (2 * h)
    qdd = np.einsum("kij,kj->ki", J_pinv, twist_rates - J_dot_qd)
    return qd, qdd


def _point(poses: NDArray[np.float64], t: NDArray[np.float64], k: int) -> str:
    return f"the point at t = {t[k]:.4g} s, position {np.round(poses[k, :3, 3], 6).tolist()} m"


def _by_ik(robot: Robot, q0: NDArray[np.float64], poses: NDArray[np.float64],
           t: NDArray[np.float64], max_joint_step: float) -> NDArray[np.float64]:
    q = np.empty((t.size, robot.n))
    q[0] = q0
    for k in range(1, t.size):
        try:
            q[k] = robot.ik(poses[k], near=q[k - 1])
        except UnreachableError as exc:
            raise UnreachableError(f"Cartesian line: {_point(poses, t, k)} is unreachable: {exc}",
                                   exc.position_error, exc.orientation_error) from exc
        except JointLimitError as exc:
            raise JointLimitError(f"Cartesian line: {_point(poses, t, k)} needs joints outside "
                                  f"their limits: {exc}", exc.q, joint=exc.joint, value=exc.value,
                                  limits=exc.limits) from exc
        jump = np.abs(q[k] - q[k - 1])
        if jump.max() > max_joint_step:
            j = int(np.argmax(jump))
            raise UnreachableError(
                f"Cartesian line: at {_point(poses, t, k)} joint {robot.joint_names[j]} jumps by "
                f"{jump[j]:.3g} between samples (an IK branch change at a singularity or limit); "
                f"the line cannot be followed continuously here")
    return q


def _by_closed_loop(robot: Robot, q0: NDArray[np.float64], poses: NDArray[np.float64],
                    t: NDArray[np.float64], duration: float, dt: float) -> NDArray[np.float64]:
    per_sample = max(1, int(np.ceil((t[1] - t[0]) / dt - 1e-9)))
    t_fine = np.linspace(0.0, duration, (t.size - 1) * per_sample + 1)
    fine, _, _ = line_poses(poses[0], poses[-1], t_fine, duration)
    control = ResolvedRate(robot)
    result = track_poses(robot, q0, t_fine, fine, control=control, stop_at_limits=False)
    errors = np.linalg.norm(result.poses[:, :3, 3] - fine[:, :3, 3], axis=-1)
    if errors.max() > REACH_TOLERANCE:
        k = int(np.argmax(errors > REACH_TOLERANCE))
        if result.scale[:k + 1].min() < 1.0:
            reason = "the joint velocity limits hold it back: allow a longer duration"
        elif result.sigma_min[:k + 1].min() < control.threshold:
            reason = (f"near a singularity (smallest singular value "
                      f"{result.sigma_min[:k + 1].min():.3g}) or out of reach")
        else:
            reason = "out of reach"
        raise UnreachableError(
            f"Cartesian line: {_point(fine, t_fine, k)} is not reached by the closed loop "
            f"(tool {errors[k]:.3g} m away): {reason}", float(errors.max()))
    return result.q[::per_sample]


def cartesian_line(robot: Robot, q0: ArrayLike, T_goal: ArrayLike, duration: float, *,
                   rate_hz: float = 100.0, method: str = "ik", dt: float = DEFAULT_DT,
                   max_joint_step: float = MAX_SAMPLE_STEP, rate: float | None = None) -> CartesianTrajectory:
    """A straight tool line from ``robot.fk(q0)`` to ``T_goal``, sampled in joint space.

    Parameters
    ----------
    robot : Robot
    q0 : (n,) array
        Start joint values [rad or m]; they also choose the IK branch.
    T_goal : (4, 4) array
        Goal tool pose [m].
    duration : float
        [s], positive.
    rate_hz : float
        Sampling rate [Hz]; the last sample is at ``duration``.
    method : {"ik", "closed-loop"}
        How the poses become joint values (see the module docstring).
    dt : float
        Control period [s] of the closed loop.
    max_joint_step : float
        Largest change of a joint [rad or m] between two IK samples; more counts as a jump
        of the joint path (an IK branch change) and raises :class:`UnreachableError`.
    rate : float, optional
        Deprecated name of ``rate_hz``; warns.

    Returns
    -------
    CartesianTrajectory
        The joint velocities are whatever the line needs: near a singularity they grow
        without bound, so compare them with ``robot.max_velocity``.

    Raises
    ------
    UnreachableError
        Naming the time and position of the first sample that cannot be reached (or where
        the joint path would jump).
    JointLimitError
        If a sample needs joints outside their limits.

    Examples
    --------
    >>> import armkit
    >>> robot = armkit.load("probot-anno")
    >>> T_goal = robot.fk([0.3, -0.5, 0.4, 0.2, 1.2, -0.3])
    >>> line = cartesian_line(robot, [0, 0, 0, 0, 0, 0], T_goal, duration=2.0, rate_hz=50)
    >>> line.q.shape, bool(np.allclose(robot.fk(line.q[-1]), T_goal))
    ((101, 6), True)
    """
    q0 = check_start(robot, q0)
    T_goal = check_transform(T_goal, "T_goal")
    duration = check_positive(duration, "duration", "s")
    rate_hz = renamed_argument("cartesian_line", "rate", "rate_hz", rate, rate_hz, 100.0)
    rate_hz = check_positive(rate_hz, "rate_hz", "Hz")
    t = even_time_grid(duration, 1.0 / rate_hz)
    poses, twists, twist_rates = line_poses(robot.fk(q0), T_goal, t, duration)
    if method == "ik":
        q = _by_ik(robot, q0, poses, t, check_positive(max_joint_step, "max_joint_step", "rad or m"))
    elif method == "closed-loop":
        q = _by_closed_loop(robot, q0, poses, t, duration, check_positive(dt, "dt", "s"))
    else:
        raise InputError(f"method {method!r}: expected 'ik' or 'closed-loop'")
    qd, qdd = _joint_rates(robot, q, twists, twist_rates)
    return CartesianTrajectory(t, q, qd, qdd, poses, method)
