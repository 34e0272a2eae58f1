"""Joint-space trajectories: polynomial segments, multi-waypoint minimum jerk, timing, export.

Modules: :mod:`~armkit.trajectory.polynomial` (quintic, cubic),
:mod:`~armkit.trajectory.trapezoid` (LSPB), :mod:`~armkit.trajectory.min_jerk`
(multi-waypoint minimum jerk), :mod:`~armkit.trajectory.joint_trajectory` (the result
object), :mod:`~armkit.trajectory.timing` (fitting durations to limits),
:mod:`~armkit.trajectory.export` (CSV, NPZ: writing and reading back), :mod:`~armkit.trajectory.peaks`,
:mod:`~armkit.trajectory.waypoints` (files, poses through IK), :mod:`~armkit.trajectory.plan`
(a robot's trajectory within its limits).
"""

from armkit.trajectory._checks import durations_from_times
from armkit.trajectory.export import read_trajectory
from armkit.trajectory.joint_trajectory import JointTrajectory, TrajectorySamples
from armkit.trajectory.min_jerk import min_jerk
from armkit.trajectory.plan import plan_trajectory
from armkit.trajectory.polynomial import PolynomialSegment, cubic, quintic
from armkit.trajectory.timing import auto_time, limit_ratio, limit_ratios, stretch_to_limits
from armkit.trajectory.trapezoid import TrapezoidSegment, lspb
from armkit.trajectory.waypoints import joint_waypoints, joint_waypoints_from_poses, read_waypoints

__all__ = [
    "JointTrajectory",
    "PolynomialSegment",
    "TrajectorySamples",
    "TrapezoidSegment",
    "auto_time",
    "cubic",
    "durations_from_times",
    "joint_waypoints",
    "joint_waypoints_from_poses",
    "limit_ratio",
    "limit_ratios",
    "lspb",
    "min_jerk",
    "plan_trajectory",
    "quintic",
    "read_trajectory",
    "read_waypoints",
    "stretch_to_limits",
]
