"""armkit: from a robot arm's DH table to a verified motion.

>>> import armkit
>>> robot = armkit.load("probot-anno")
>>> robot.fk([0, 0, 0, 0, 0, 0]).shape
(4, 4)
"""

from armkit.chain import Chain, DHRow, Joint, chain_from_dh
from armkit.control import (
    MotionResult,
    ResolvedRate,
    cartesian_line,
    move_linear,
    rotate_about_tool_point,
)
from armkit.errors import (
    ArmkitError,
    ConvergenceError,
    InputError,
    JointLimitError,
    NoClosedFormError,
    RobotDefinitionError,
    UnreachableError,
)
from armkit.export import mjcf_from_robot, urdf_from_robot, write_mjcf, write_urdf
from armkit.ik import (
    IKResult,
    IKResultBatch,
    IKSolutions,
    NumericIK,
    analyze_structure,
    ik_solutions,
    numeric_ik,
)
from armkit.kinematics import ChainKernel
from armkit.robot import Robot
from armkit.robot_file import builtin_robots, load, robot_from_dict, robot_to_toml
from armkit.trajectory import JointTrajectory, auto_time, min_jerk, plan_trajectory, quintic

__version__ = "0.1.0"

__all__ = [
    "ArmkitError",
    "Chain",
    "ChainKernel",
    "ConvergenceError",
    "DHRow",
    "IKResult",
    "IKResultBatch",
    "IKSolutions",
    "InputError",
    "Joint",
    "JointLimitError",
    "JointTrajectory",
    "MotionResult",
    "NoClosedFormError",
    "NumericIK",
    "ResolvedRate",
    "Robot",
    "RobotDefinitionError",
    "UnreachableError",
    "analyze_structure",
    "auto_time",
    "builtin_robots",
    "cartesian_line",
    "chain_from_dh",
    "ik_solutions",
    "load",
    "min_jerk",
    "mjcf_from_robot",
    "move_linear",
    "numeric_ik",
    "plan_trajectory",
    "quintic",
    "robot_from_dict",
    "robot_to_toml",
    "rotate_about_tool_point",
    "urdf_from_robot",
    "write_mjcf",
    "write_urdf",
]
