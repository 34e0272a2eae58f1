"""Inverse kinematics: closed form where the geometry allows it, numeric for every chain."""

from armkit.ik.closed_form import ClosedFormSolutions, closed_form_ik, closed_form_solver
from armkit.ik.numeric import IKResult, IKResultBatch, NumericIK, numeric_ik, wrap_into_limits
from armkit.ik.position import ik_position, ik_position_solutions, position_solutions
from armkit.ik.self_motion import SelfMotion, self_motion
from armkit.ik.solve import IKSolutions, IKSolutionsBatch, ik, ik_solutions
from armkit.ik.structure import ArmStructure, analyze_structure

__all__ = ["ArmStructure", "ClosedFormSolutions", "IKResult", "IKResultBatch", "IKSolutions",
           "IKSolutionsBatch", "NumericIK", "SelfMotion", "analyze_structure",
           "closed_form_ik", "closed_form_solver", "ik", "ik_position", "ik_position_solutions",
           "ik_solutions", "numeric_ik", "position_solutions", "self_motion", "wrap_into_limits"]
