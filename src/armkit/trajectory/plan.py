"""A robot's trajectory through waypoints, within its velocity and acceleration limits."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit.dynamics import missing_inertia
from armkit.errors import InputError, JointLimitError
from armkit.robot import Robot
from armkit.trajectory._checks import check_tol, per_joint_limits
from armkit.trajectory.joint_trajectory import JointTrajectory
from armkit.trajectory.min_jerk import min_jerk
from armkit.trajectory.timing import stretch_to_limits
from armkit.trajectory.topp import slowed_to_torque_limits, time_optimal, torque_constraint
from armkit.trajectory.waypoints import joint_waypoints, joint_waypoints_from_poses

__all__ = ["plan_trajectory", "planning_limits"]


def planning_limits(robot: Robot, max_velocity: ArrayLike | None = None,
                    max_acceleration: ArrayLike | None = None
                    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The velocity and acceleration limits ``(n,)`` a plan keeps: the robot's, or those given.

    Parameters
    ----------
    robot : Robot
    max_velocity, max_acceleration : float or (n,) array, optional
        In place of the robot's limits [rad/s or m/s, rad/s^2 or m/s^2]: one value for every
        joint or one per joint (``inf``: none), e.g. for a URDF arm, whose file has no
        acceleration limits. Default: the robot's own.

    Raises
    ------
    InputError
        If a value is not positive, or there are neither one nor ``n`` of them.

    Examples
    --------
    >>> import armkit
    >>> robot = armkit.load("probot-anno")
    >>> planning_limits(robot, max_acceleration=2.0)[1].tolist()
    [2.0, 2.0, 2.0, 2.0, 2.0, 2.0]
    """
    vmax = (robot.max_velocity if max_velocity is None
            else per_joint_limits(max_velocity, robot.n, "max_velocity"))
    amax = (robot.max_acceleration if max_acceleration is None
            else per_joint_limits(max_acceleration, robot.n, "max_acceleration"))
    return np.array(vmax, dtype=float), np.array(amax, dtype=float)


def plan_trajectory(robot: Robot, waypoints: ArrayLike, durations: ArrayLike | None = None, *,
                    poses: bool = False, convention: str = "xyz-fixed", q_start: ArrayLike | None = None,
                    fit_limits: bool = True, tol: float = 1e-4, max_velocity: ArrayLike | None = None,
                    max_acceleration: ArrayLike | None = None, torque_limits: bool | None = None
                    ) -> JointTrajectory:
    """Joint trajectory of ``robot`` through ``waypoints``, at rest at both ends, inside the joint
    position limits all the way.

    With ``durations``, the minimum-jerk spline (stretched to the limits if needed); without,
    the time-optimal timing along the minimum-jerk path (:func:`~armkit.trajectory.topp.time_optimal`),
    within the velocity, acceleration and (where the robot has them) torque limits.

    Position limits are kept by the path itself, before any timing: where the minimum-jerk
    spline would overshoot a limit between two waypoints, the joint comes to rest at the
    waypoint beside the overshoot (:func:`~armkit.trajectory.min_jerk.min_jerk`'s
    ``position_limits``); timing along a path never changes where it goes. Both ways of timing
    treat the velocity, acceleration and torque limits alike: they slow down, never only warn.

    Parameters
    ----------
    robot : Robot
    waypoints : (M, n) or (M, 6) array
        Joint values [rad or m], or with ``poses=True`` tool poses ``x y z a b c`` [m, rad].
    durations : (M - 1,) array, optional
        Segment durations [s]. Segments that would exceed the velocity or acceleration
        limits are lengthened as little as needed, and then the whole trajectory slowed
        uniformly as far as the torque limits need (where ``torque_limits``);
        ``result.stretch`` says by how much, unless ``fit_limits=False``. Default: the
        fastest motion along the path within the limits (:func:`~armkit.trajectory.topp.time_optimal`).
    poses : bool
        Waypoints are tool poses, solved by IK, each nearest the previous solution.
    convention : str
        Angle convention of the poses (default ``"xyz-fixed"``, roll pitch yaw).
    q_start : (n,) array, optional
        Configuration the first pose's IK solution should be nearest (default zeros).
    fit_limits : bool
        Lengthen given ``durations`` as the limits need (default); ``False`` keeps them exactly
        as given, and the velocity, acceleration and torque limits unchecked (the result's
        peaks say what they are). The position limits are kept either way.
    tol : float
        Relative accuracy of each fitted duration, in ``(0, 1)``.
    max_velocity, max_acceleration : float or (n,) array, optional
        Limits in place of the robot's [rad/s or m/s, rad/s^2 or m/s^2], one value or one
        per joint: for an arm whose file gives none (a URDF has no acceleration limits),
        or to move slower (:func:`planning_limits`).
    torque_limits : bool, optional
        Keep the joint torques within ``robot.max_torque`` too (checked at 1 kHz;
        :func:`~armkit.trajectory.topp.slowed_to_torque_limits`). Default: wherever the robot
        has inertial parameters and a torque limit.

    Raises
    ------
    InputError, JointLimitError, UnreachableError
        Bad waypoints, durations, limits or ``tol``, a waypoint outside the joint limits
        (:class:`JointLimitError` naming the joint and its range), an unreachable pose, or a
        torque limit below what gravity needs.

    Examples
    --------
    >>> import armkit
    >>> robot = armkit.load("probot-anno")
    >>> traj = plan_trajectory(robot, [[0, 0, 0, 0, 0, 0], [0.5, -0.3, 0.2, 0, 0.4, 0]], [1.0])
    >>> traj.stretch.round(3)            # 1 s was too fast for the limits
    array([2.876])
    >>> bool((traj.peak_velocity <= robot.max_velocity).all())
    True
    """
    tol = check_tol(tol)
    vmax, amax = planning_limits(robot, max_velocity, max_acceleration)
    q = (joint_waypoints_from_poses(robot, waypoints, convention, q_start) if poses else waypoints)
    q = joint_waypoints(robot, q)
    limited = bool(np.any(np.isfinite(vmax)) or np.any(np.isfinite(amax)))
    use_torques = _has_torque_limits(robot) if torque_limits is None else bool(torque_limits)
    if use_torques and not _has_torque_limits(robot):
        raise InputError("torque_limits=True: the robot needs inertial parameters and a max_torque "
                         "for some joint (docs/dynamics.md)")
    inside = robot.limits
    if durations is None:
        constraints = [torque_constraint(robot)] if use_torques else []
        trajectory = time_optimal(q, vmax, amax, constraints=constraints, position_limits=inside)
        if use_torques:
            trajectory = slowed_to_torque_limits(trajectory, robot)
    elif not fit_limits:
        trajectory = min_jerk(q, durations, position_limits=inside)
    else:
        trajectory = (stretch_to_limits(q, durations, vmax, amax, tol=tol, position_limits=inside)
                      if limited else min_jerk(q, durations, position_limits=inside))
        if use_torques:
            slowed = slowed_to_torque_limits(trajectory, robot)
            trajectory = JointTrajectory(slowed.piece_durations, slowed.coefficients, slowed.waypoints,
                                         trajectory.requested_durations, segment_pieces=slowed.segment_pieces)
    if violations := trajectory.position_limit_violations(robot):  # the path is planned inside: a bug
        raise JointLimitError("; ".join(violations) + " (armkit planned this path inside the limits; please "
                              "report the waypoints)")
    return trajectory


def _has_torque_limits(robot: Robot) -> bool:
    """Whether ``robot`` has inertial parameters and a finite torque limit on some joint."""
    return bool(np.any(np.isfinite(robot.max_torque))) and missing_inertia(robot.chain) is None
