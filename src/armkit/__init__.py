"""armkit: from a robot arm's DH table or URDF to a verified motion.

>>> import armkit
>>> robot = armkit.load("probot-anno")
>>> robot.fk([0, 0, 0, 0, 0, 0]).shape
(4, 4)
"""

from __future__ import annotations

import importlib
from typing import Any

# Public names and the module each lives in. They are imported on first use (PEP 562), so
# ``import armkit`` stays light: a command that only needs FK never loads the trajectory,
# control, export or simulation code, nor scipy and matplotlib.
_MODULES = {
    "armkit.chain": ["Chain", "DHRow", "Joint", "chain_from_dh"],
    "armkit.control": ["MotionResult", "ResolvedRate", "cartesian_line", "move_linear",
                       "rotate_about_tool_point"],
    "armkit.errors": ["ArmkitError", "ConvergenceError", "InputError", "JointLimitError", "NoClosedFormError",
                      "RobotDefinitionError", "UnreachableError"],
    "armkit.export": ["mjcf_from_robot", "urdf_from_robot", "write_mjcf", "write_urdf"],
    "armkit.ik": ["IKResult", "IKSolutions", "NumericIK", "analyze_structure", "ik_solutions", "numeric_ik"],
    "armkit.kinematics": ["ChainKernel"],
    "armkit.robot": ["LockedRobot", "Robot"],
    "armkit.robot_file": ["builtin_robots", "load", "robot_from_dict", "robot_to_toml"],
    "armkit.trajectory": ["JointTrajectory", "auto_time", "min_jerk", "plan_trajectory", "quintic"],
}
_EXPORTS = {name: module for module, names in _MODULES.items() for name in names}


def __getattr__(name: str) -> Any:
    """Import a public name's module on first use (``armkit.load``, ``from armkit import Robot``)."""
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'armkit' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted([*globals(), *_EXPORTS])


__version__ = "0.1.0"

__all__ = sorted(_EXPORTS)
