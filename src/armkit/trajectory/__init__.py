"""Joint-space trajectories: polynomial segments, multi-waypoint minimum jerk, timing, export.

Modules: :mod:`~armkit.trajectory.polynomial` (quintic, cubic),
:mod:`~armkit.trajectory.trapezoid` (LSPB), :mod:`~armkit.trajectory.min_jerk`
(multi-waypoint minimum jerk), :mod:`~armkit.trajectory.joint_trajectory` (the result
object), :mod:`~armkit.trajectory.timing` (fitting durations to limits),
:mod:`~armkit.trajectory.export` (CSV, NPZ), :mod:`~armkit.trajectory.peaks`.
"""

from armkit.trajectory.joint_trajectory import JointTrajectory, TrajectorySamples
from armkit.trajectory.min_jerk import min_jerk
from armkit.trajectory.polynomial import PolynomialSegment, cubic, quintic
from armkit.trajectory.timing import auto_time, limit_ratio, limit_ratios, stretch_to_limits
from armkit.trajectory.trapezoid import TrapezoidSegment, lspb

__all__ = [
    "JointTrajectory",
    "PolynomialSegment",
    "TrajectorySamples",
    "TrapezoidSegment",
    "auto_time",
    "cubic",
    "limit_ratio",
    "limit_ratios",
    "lspb",
    "min_jerk",
    "quintic",
    "stretch_to_limits",
]
