"""Velocity control: resolved-rate steps, closed-loop tool motions, Cartesian straight lines."""

from armkit.control.cartesian import CartesianTrajectory, cartesian_line, line_poses
from armkit.control.motions import MotionResult, move_linear, rotate_about_tool_point, track_poses
from armkit.control.resolved_rate import (
    RateStep,
    ResolvedRate,
    damping,
    joint_velocity,
    scale_to_limits,
)

__all__ = [
    "CartesianTrajectory",
    "MotionResult",
    "RateStep",
    "ResolvedRate",
    "cartesian_line",
    "damping",
    "joint_velocity",
    "line_poses",
    "move_linear",
    "rotate_about_tool_point",
    "scale_to_limits",
    "track_poses",
]
