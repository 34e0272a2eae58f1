"""A robot's trajectory through waypoints, within its velocity and acceleration limits."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from armkit.errors import JointLimitError
from armkit.robot import Robot
from armkit.trajectory.joint_trajectory import JointTrajectory
from armkit.trajectory.min_jerk import min_jerk
from armkit.trajectory.timing import stretch_to_limits
from armkit.trajectory.topp import time_optimal
from armkit.trajectory.waypoints import joint_waypoints, joint_waypoints_from_poses

__all__ = ["plan_trajectory"]


def plan_trajectory(robot: Robot, waypoints: ArrayLike, durations: ArrayLike | None = None, *,
                    poses: bool = False, convention: str = "xyz-fixed", q_start: ArrayLike | None = None,
                    fit_limits: bool = True, tol: float = 1e-4) -> JointTrajectory:
    """Joint trajectory of ``robot`` through ``waypoints``, at rest at both ends.

    With ``durations``, the minimum-jerk spline (stretched to the limits if needed); without,
    the time-optimal timing along the minimum-jerk path (:func:`~armkit.trajectory.topp.time_optimal`).

    Parameters
    ----------
    robot : Robot
    waypoints : (M, n) or (M, 6) array
        Joint values [rad or m], or with ``poses=True`` tool poses ``x y z a b c`` [m, rad].
    durations : (M - 1,) array, optional
        Segment durations [s]. Segments that would exceed the robot's ``max_velocity`` or
        ``max_acceleration`` are lengthened as little as needed (``result.stretch`` says
        by how much) unless ``fit_limits=False``. Default: the fastest motion along the
        path within the limits (:func:`~armkit.trajectory.topp.time_optimal`).
    poses : bool
        Waypoints are tool poses, solved by IK, each nearest the previous solution.
    convention : str
        Angle convention of the poses (default ``"xyz-fixed"``, roll pitch yaw).
    q_start : (n,) array, optional
        Configuration the first pose's IK solution should be nearest (default zeros).

    tol : float
        Relative accuracy of stretched durations (with ``durations``).

    Raises
    ------
    InputError, JointLimitError, UnreachableError
        Bad waypoints or durations, a waypoint outside the joint limits, an unreachable pose;
        without ``durations``, a path leaving the position limits between waypoints
        (:class:`JointLimitError` naming the joint and its range).

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
    q = (joint_waypoints_from_poses(robot, waypoints, convention, q_start) if poses else waypoints)
    q = joint_waypoints(robot, q)
    limited = bool(np.any(np.isfinite(robot.max_velocity)) or np.any(np.isfinite(robot.max_acceleration)))
    if durations is None:
        trajectory = time_optimal(q, robot.max_velocity, robot.max_acceleration)
        if violations := trajectory.position_limit_violations(robot):
            raise JointLimitError("; ".join(violations) + " (the path through these waypoints overshoots: "
                                  "add a waypoint where it turns, or give durations)")
        return trajectory
    if fit_limits and limited:
        return stretch_to_limits(q, durations, robot.max_velocity, robot.max_acceleration, tol=tol)
    return min_jerk(q, durations)
