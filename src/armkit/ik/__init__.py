"""Inverse kinematics: closed form where the geometry allows it, numeric for every chain."""

from armkit.ik.numeric import IKResult, numeric_ik

__all__ = ["IKResult", "numeric_ik"]
