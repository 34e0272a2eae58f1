"""Velocity control: resolved-rate steps, closed-loop tool motions, Cartesian straight lines."""

from armkit._lazy import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(__name__, {
    "armkit.control.cartesian": ["CartesianTrajectory", "cartesian_line", "line_poses"],
    "armkit.control.motions": ["DEFAULT_DT", "MotionResult", "move_linear", "rotate_about_tool_point",
                               "track_poses"],
    "armkit.control.resolved_rate": ["RateStep", "ResolvedRate", "damping", "joint_velocity",
                                     "scale_to_limits"],
})
