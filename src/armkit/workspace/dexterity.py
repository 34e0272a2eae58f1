"""Dexterity: from how many orientations, and in how many ways, the tool reaches each voxel centre.

The capability map of Zacharias, Borst and Hirzinger (IROS 2007), as ROS's Reuleaux builds it:
for each voxel centre, a fixed near-uniform set of tool orientations
(:func:`armkit.workspace.orientations.super_fibonacci`) is solved by IK. The *reachability
index* of a voxel is the fraction of them with a solution inside the joint limits; the map
also keeps the mean and the largest number of distinct solutions per orientation.

The voxels tested are those of a reachability map (occupied voxels and their neighbours,
so that an unsampled border voxel is not missed), or without one every voxel whose centre
lies within the reach bound of :func:`armkit.workspace.grid.reach_bound`. Arms with a
closed form are solved in batches (all solutions); any other arm (e.g. a 7-joint Panda) by
numeric IK one pose at a time, about a millisecond each and only "solved or not": expect
minutes for a few thousand voxels.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial
from typing import Any

import numpy as np
from numpy.typing import NDArray

from armkit.errors import InputError
from armkit.robot import Robot
from armkit.robot_file import robot_to_toml
from armkit.workspace.grid import Grid, grid_for, reach_bound
from armkit.workspace.orientations import super_fibonacci
from armkit.workspace.reachability import ReachabilityMap
from armkit.workspace.sampling import ik_solution_counts, robot_from_toml
from armkit.workspace.store import run_resumable

__all__ = ["DexterityMap", "candidate_voxels", "dexterity"]

#: Voxels per task: with 100 orientations, 2.5e4 IK poses.
VOXELS_PER_CHUNK = 250


@dataclass(frozen=True)
class DexterityMap:
    """Per-voxel IK statistics over a fixed set of tool orientations.

    Attributes
    ----------
    grid : Grid
    reachable_fraction : ndarray, grid.shape, float64
        Fraction of the orientations with an IK solution inside the limits (NaN: not tested).
    mean_solutions : ndarray, grid.shape, float64
        Distinct in-limit solutions per orientation, averaged over all orientations (NaN: not tested).
    max_solutions : ndarray, grid.shape, int16
        The most solutions of any one orientation (-1: not tested).
    orientations : int
    tested : int
        Voxels tested (all candidates unless the run was interrupted).
    candidates : int
        Voxels to test.
    """

    grid: Grid
    reachable_fraction: NDArray[np.float64]
    mean_solutions: NDArray[np.float64]
    max_solutions: NDArray[np.int16]
    orientations: int
    tested: int
    candidates: int

    @classmethod
    def from_section(cls, grid: Grid, arrays: dict[str, NDArray], attrs: dict) -> DexterityMap:
        """The map a store's ``dexterity`` group holds."""
        candidates = int(attrs["candidate_voxels"])
        tested = min(int(attrs["chunks_done"]) * attrs["voxels_per_chunk"], candidates)
        values = (arrays[key].reshape(grid.shape) for key in _Counts.KEYS)
        return cls(grid, *values, int(attrs["orientations"]), tested, candidates)

    @property
    def complete(self) -> bool:
        """Whether every candidate voxel is tested (not an interrupted run's part)."""
        return self.tested == self.candidates

    @property
    def reachable(self) -> NDArray[np.bool_]:
        """Voxels reached in at least one tested orientation."""
        return np.nan_to_num(self.reachable_fraction) > 0

    def mean_index(self) -> float:
        """The mean reachability index over the voxels reached in some orientation (NaN if none)."""
        reached = self.reachable
        return float(self.reachable_fraction[reached].mean()) if reached.any() else float("nan")


def candidate_voxels(grid: Grid, robot: Robot, reach: ReachabilityMap | None = None) -> NDArray[np.int64]:
    """Raveled indices of the voxels to test: a reachability map's occupied ones and their neighbours,
    or (without a map) those within the reach bound."""
    if reach is not None:
        from scipy.ndimage import binary_dilation

        structure = np.ones([1 if f else 3 for f in grid.flat], dtype=bool)
        return np.flatnonzero(binary_dilation(reach.occupied, structure=structure))
    centre, radius = reach_bound(robot)
    centres = grid.centres(np.arange(grid.size))
    return np.flatnonzero(np.linalg.norm(centres - centre, axis=1) <= radius + grid.resolution)


@dataclass(frozen=True)
class _Task:
    robot_toml: str
    grid: Grid
    voxels: NDArray[np.int64]
    orientations: int
    voxels_per_chunk: int


def _dexterity_of_chunk(task: _Task, chunk: int) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """The chunk's voxels and their IK solution counts ``(V, orientations)``."""
    robot = robot_from_toml(task.robot_toml)
    voxels = task.voxels[chunk * task.voxels_per_chunk:(chunk + 1) * task.voxels_per_chunk]
    R = super_fibonacci(task.orientations)
    T = np.zeros((len(voxels), len(R), 4, 4))
    T[..., :3, :3] = R
    T[..., :3, 3] = task.grid.centres(voxels)[:, None, :]
    T[..., 3, 3] = 1.0
    counts = ik_solution_counts(robot, T.reshape(-1, 4, 4)).reshape(len(voxels), len(R))
    return voxels, counts


class _Counts:
    KEYS = ("reachable_fraction", "mean_solutions", "max_solutions")

    def __init__(self, grid: Grid, orientations: int) -> None:
        self.orientations = orientations
        self.values = {"reachable_fraction": np.full(grid.size, np.nan),
                       "mean_solutions": np.full(grid.size, np.nan),
                       "max_solutions": np.full(grid.size, -1, dtype=np.int16)}

    def add(self, result: tuple[NDArray[np.int64], NDArray[np.int64]]) -> None:
        voxels, counts = result
        self.values["reachable_fraction"][voxels] = (counts > 0).sum(axis=1) / self.orientations
        self.values["mean_solutions"][voxels] = counts.sum(axis=1) / self.orientations
        self.values["max_solutions"][voxels] = counts.max(axis=1)

    def arrays(self) -> dict[str, NDArray]:
        return self.values

    def restore(self, arrays: dict[str, NDArray]) -> None:
        for key, values in self.values.items():
            values[:] = arrays[key].ravel()


def dexterity(robot: Robot, *, resolution: float = 0.02, grid: Grid | None = None,
              reach: ReachabilityMap | None = None, orientations: int = 100,
              voxels_per_chunk: int = VOXELS_PER_CHUNK, engine: Any = None, store: Any = None,
              section: str = "dexterity", resume: bool = False, progress: bool = False) -> DexterityMap:
    """The reachability index and IK solution counts per voxel (see the module notes).

    Parameters
    ----------
    robot : Robot
    resolution : float
        Voxel edge [m], when neither ``grid`` nor ``reach`` is given.
    grid : Grid, optional
    reach : ReachabilityMap, optional
        Test only its occupied voxels and their neighbours (and use its grid).
    orientations : int
        Tool orientations per voxel.
    voxels_per_chunk : int
        Voxels per task.
    engine, store, section, resume, progress
        As in :func:`armkit.workspace.reachability`.

    Examples
    --------
    >>> import armkit
    >>> robot = armkit.load("puma560")
    >>> dex = dexterity(robot, resolution=0.25, orientations=20)
    >>> bool(dex.max_solutions.max() <= 8), 0 < dex.mean_index() <= 1
    (True, True)
    """
    if not (isinstance(voxels_per_chunk, int) and voxels_per_chunk > 0):
        raise InputError(f"voxels_per_chunk: expected a positive whole number, got {voxels_per_chunk!r}")
    super_fibonacci(orientations)  # checks the number
    grid = reach.grid if reach is not None else (grid_for(robot, resolution) if grid is None else grid)
    voxels = candidate_voxels(grid, robot, reach)
    n_chunks = -(-len(voxels) // voxels_per_chunk)
    accumulator = _Counts(grid, orientations)
    task = _Task(robot_to_toml(robot), grid, voxels, int(orientations), voxels_per_chunk)
    attrs = {"orientations": int(orientations), "voxels_per_chunk": voxels_per_chunk,
             "candidate_voxels": len(voxels)}
    done = run_resumable(partial(_dexterity_of_chunk, task), n_chunks, accumulator, store=store,
                         name=section, attrs=attrs, resume=resume, engine=engine, progress=progress,
                         description="dexterity")
    return DexterityMap.from_section(grid, accumulator.values, {**attrs, "chunks_done": done})
