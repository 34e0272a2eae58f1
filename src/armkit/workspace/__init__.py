"""Workspace, dexterity and manipulability maps of an arm, on a voxel grid, at scale."""

from armkit.workspace.grid import Grid, grid_for
from armkit.workspace.reachability import ReachabilityMap, VolumeEstimate, reachability

__all__ = ["Grid", "ReachabilityMap", "VolumeEstimate", "grid_for", "reachability"]
