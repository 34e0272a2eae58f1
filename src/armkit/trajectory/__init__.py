"""Joint-space trajectories: polynomial segments, multi-waypoint minimum jerk, timing, export.

Modules: :mod:`~armkit.trajectory.polynomial` (quintic, cubic),
:mod:`~armkit.trajectory.trapezoid` (LSPB), :mod:`~armkit.trajectory.min_jerk`
(multi-waypoint minimum jerk), :mod:`~armkit.trajectory.joint_trajectory` (the result
object), :mod:`~armkit.trajectory.timing` (fitting durations to limits),
:mod:`~armkit.trajectory.export` (CSV, NPZ: writing and reading back), :mod:`~armkit.trajectory.peaks`,
:mod:`~armkit.trajectory.waypoints` (files, poses through IK), :mod:`~armkit.trajectory.plan`
(a robot's trajectory within its limits).
"""

from armkit._lazy import lazy_exports

# ``min_jerk`` is also a submodule's name: importing the submodule would put the module in
# the package's namespace, so the function is imported now (the module itself is light).
from armkit.trajectory.min_jerk import min_jerk  # noqa: E402, F401

__getattr__, __dir__, _lazy_names = lazy_exports(__name__, {
    "armkit.trajectory._checks": ["durations_from_times"],
    "armkit.trajectory.export": ["read_trajectory"],
    "armkit.trajectory.joint_trajectory": ["JointTrajectory", "TrajectorySamples", "TrajectoryTorques"],
    "armkit.trajectory.plan": ["plan_trajectory", "planning_limits"],
    "armkit.trajectory.polynomial": ["PolynomialSegment", "cubic", "quintic"],
    "armkit.trajectory.timing": ["auto_time", "limit_ratio", "limit_ratios", "stretch_to_limits"],
    "armkit.trajectory.trapezoid": ["TrapezoidSegment", "lspb"],
    "armkit.trajectory.waypoints": ["joint_waypoints", "joint_waypoints_from_poses", "read_waypoints",
                                   "write_waypoints"],
})
__all__ = sorted([*_lazy_names, "min_jerk"])
