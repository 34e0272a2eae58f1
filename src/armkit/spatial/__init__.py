"""Rotations and homogeneous transforms, batch-first, conventions always named."""

from armkit.spatial.rotations import (
    CONVENTIONS,
    AngleConvention,
    angular_velocity_matrix,
    axis_angle_from_matrix,
    euler_from_matrix,
    matrix_from_axis_angle,
    matrix_from_euler,
    matrix_from_quaternion_wxyz,
    parse_convention,
    quaternion_wxyz_from_matrix,
    rotation_angle_between,
)
from armkit.spatial.transforms import (
    check_transform,
    invert_transform,
    pose_from_transform,
    rot_x,
    rot_z,
    trans_x,
    trans_z,
    transform_from,
    transform_from_pose,
)

__all__ = [
    "CONVENTIONS",
    "AngleConvention",
    "angular_velocity_matrix",
    "axis_angle_from_matrix",
    "check_transform",
    "euler_from_matrix",
    "invert_transform",
    "matrix_from_axis_angle",
    "matrix_from_euler",
    "matrix_from_quaternion_wxyz",
    "parse_convention",
    "pose_from_transform",
    "quaternion_wxyz_from_matrix",
    "rot_x",
    "rot_z",
    "rotation_angle_between",
    "trans_x",
    "trans_z",
    "transform_from",
    "transform_from_pose",
]
