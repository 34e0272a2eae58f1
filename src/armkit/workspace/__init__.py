"""Workspace, dexterity and manipulability maps of an arm on a voxel grid, at scale.

>>> import armkit
>>> from armkit import workspace
>>> maps = workspace.compute(armkit.load("puma560"), resolution=0.2, samples=20_000,
...                          manipulability_samples=0, orientations=0)
>>> maps.summary()["volume_unit"]
'm^3'

Chunks run on a thread per local core, or on a Dask cluster (``engine=Client(...)``); see
``docs/workspace.md``. zarr, dask and matplotlib are imported only where they are used.
"""

from armkit.workspace.dataset import IKDataset, ik_dataset
from armkit.workspace.dexterity import DexterityMap, dexterity
from armkit.workspace.engine import InterruptedRun
from armkit.workspace.grid import Grid, grid_for
from armkit.workspace.manipulability import ManipulabilityMap, manipulability
from armkit.workspace.maps import Workspace, compute, open
from armkit.workspace.orientations import super_fibonacci
from armkit.workspace.reachability import ReachabilityMap, VolumeEstimate, reachability
from armkit.workspace.sweep import Sweep, sweep

__all__ = ["DexterityMap", "Grid", "IKDataset", "InterruptedRun", "ManipulabilityMap", "ReachabilityMap",
           "Sweep", "VolumeEstimate", "Workspace", "compute", "dexterity", "grid_for", "ik_dataset",
           "manipulability", "open", "reachability", "super_fibonacci", "sweep"]
