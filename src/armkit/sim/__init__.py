"""Simulation in MuJoCo: load an exported robot, drive it, compare with armkit's kinematics."""

from armkit.sim.runner import SimResult, Simulation
from armkit.sim.verify import PoseComparison, compare_poses

__all__ = ["PoseComparison", "SimResult", "Simulation", "compare_poses"]
