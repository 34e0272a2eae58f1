"""armkit: from a robot arm's DH table or URDF to a verified motion.

>>> import armkit
>>> robot = armkit.load("probot-anno")
>>> robot.fk([0, 0, 0, 0, 0, 0]).shape
(4, 4)
"""

from armkit._lazy import lazy_exports

# Public names and the module each lives in, imported on first use (see armkit._lazy).
_MODULES = {
    "armkit.chain": ["Chain", "DHRow", "Joint", "chain_from_dh"],
    "armkit.collision": ["Box", "Cylinder", "Mesh", "Scene", "Sphere", "load_scene"],
    "armkit.control": ["MotionResult", "ResolvedRate", "cartesian_line", "move_linear",
                       "rotate_about_tool_point"],
    "armkit.errors": ["ArmkitError", "CollisionError", "ConvergenceError", "InputError", "JointLimitError",
                      "NoClosedFormError", "PlanningError", "RobotDefinitionError", "UnreachableError"],
    "armkit.export": ["mjcf_from_robot", "urdf_from_robot", "write_mjcf", "write_urdf"],
    "armkit.ik": ["IKResult", "IKResultBatch", "IKSolutions", "IKSolutionsBatch", "NumericIK",
                  "analyze_structure",
                  "ik_position", "ik_position_solutions", "ik_solutions", "numeric_ik", "position_solutions",
                  "SelfMotion",
                  "self_motion"],
    "armkit.inertial": ["Inertial"],
    "armkit.kinematics": ["ChainKernel"],
    "armkit.plan": ["plan_path"],
    "armkit.robot": ["LockedRobot", "Robot"],
    "armkit.robot_file": ["builtin_robots", "load", "robot_from_dict", "robot_to_toml"],
    "armkit.trajectory": ["JointTrajectory", "auto_time", "min_jerk", "plan_trajectory", "quintic"],
}
__getattr__, __dir__, __all__ = lazy_exports(__name__, _MODULES)

__version__ = "0.1.0"
