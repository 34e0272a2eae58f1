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
numeric IK one pose at a time, about a millisecond each and only "solved or not".

The work follows what was asked (``ik_solves``), not the grid: when ``orientations`` times
the voxels to test exceeds it, the voxels are grouped into cubic blocks of ``block`` x
``block`` voxels per side (the smallest edge that fits), each block's IK is solved at one
position, one of its sampled voxels picked pseudo-randomly by index (a neighbour added only to
catch an unsampled border voxel is taken only in a block without sampled ones), and the
block's voxels to test take that position's values. Picking the block's centre instead was
seen to bias the mean index low by 0.12 (boundary blocks are represented by their border).
Statistics over voxels (:meth:`DexterityMap.mean_index`) then weigh each position by the
voxels it stands for, so a small run estimates what a large one measures.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial
from typing import Any

import numpy as np
from numpy.typing import NDArray

from armkit._params import whole_number
from armkit.errors import InputError
from armkit.robot import Robot
from armkit.robot_file import robot_to_toml
from armkit.workspace.grid import Grid, grid_for, reach_bound
from armkit.workspace.orientations import super_fibonacci
from armkit.workspace.reachability import ReachabilityMap
from armkit.workspace.sampling import MAX_SAMPLES, ik_solution_counts, robot_from_toml
from armkit.workspace.store import run_resumable

__all__ = ["MIN_JOINTS", "MIN_POSITIONS", "DexterityMap", "applies", "blocks", "candidate_voxels",
           "dexterity"]

#: Voxels per task: with 100 orientations, 2.5e4 IK poses.
VOXELS_PER_CHUNK = 250
#: Joints an arm needs for a dexterity map: with fewer, the orientations reachable at a point
#: are a set of measure zero, and every voxel's index is 0 (see :func:`applies`).
MIN_JOINTS = 6
#: Fewest positions worth a map: a budget of IK solves that allows fewer (``ik_solves //
#: orientations``) skips it (a handful of blocks the size of the workspace says nothing per voxel).
MIN_POSITIONS = 50


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
        Positions tested (all candidates unless the run was interrupted).
    candidates : int
        Positions to test: voxels, or with ``block > 1`` one voxel per block (module notes).
    block : int
        Edge of the blocks, in voxels, each solved at one position (1: every voxel).
    """

    grid: Grid
    reachable_fraction: NDArray[np.float64]
    mean_solutions: NDArray[np.float64]
    max_solutions: NDArray[np.int16]
    orientations: int
    tested: int
    candidates: int
    block: int = 1

    @classmethod
    def from_section(cls, grid: Grid, arrays: dict[str, NDArray], attrs: dict) -> DexterityMap:
        """The map a store's ``dexterity`` group holds."""
        candidates = int(attrs["candidate_voxels"])
        tested = min(int(attrs["chunks_done"]) * attrs["voxels_per_chunk"], candidates)
        values = (arrays[key].reshape(grid.shape) for key in _Counts.KEYS)
        return cls(grid, *values, int(attrs["orientations"]), tested, candidates, int(attrs.get("block", 1)))

    @property
    def ik_solves(self) -> int:
        """IK solves made: positions tested times orientations."""
        return self.tested * self.orientations

    @property
    def complete(self) -> bool:
        """Whether every candidate voxel is tested (not an interrupted run's part)."""
        return self.tested == self.candidates

    @property
    def reachable(self) -> NDArray[np.bool_]:
        """Voxels reached in at least one tested orientation."""
        return np.nan_to_num(self.reachable_fraction) > 0

    def mean_index(self, voxels: NDArray[np.bool_] | None = None) -> float:
        """The mean reachability index over ``voxels`` (grid-shaped mask; default: those reached in
        some orientation) that were tested; NaN if none."""
        mask = self.reachable if voxels is None else voxels & np.isfinite(self.reachable_fraction)
        return float(self.reachable_fraction[mask].mean()) if mask.any() else float("nan")


def applies(robot: Robot, orientations: int, ik_solves: int | None = None) -> str | None:
    """Why a dexterity map does not apply: ``robot`` has fewer than :data:`MIN_JOINTS` joints, or
    ``ik_solves`` allow fewer than :data:`MIN_POSITIONS` positions; None if it does."""
    if robot.n < MIN_JOINTS:
        return (f"a {robot.n}-joint arm reaches each point in a set of orientations of measure zero, so "
                f"every voxel's reachability index would be 0 (a dexterity map needs {MIN_JOINTS} or more "
                f"joints)")
    if ik_solves is not None and ik_solves // orientations < MIN_POSITIONS:
        return (f"{ik_solves:,} IK solves (--ik-solves) at {orientations} orientations allow "
                f"{ik_solves // orientations} positions, fewer than {MIN_POSITIONS}: give more --samples or "
                f"--ik-solves, or fewer --orientations")
    return None


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
class _Blocks:
    """Positions to solve and the voxels each stands for (module notes).

    ``targets`` ``(B,)`` ascending raveled voxel indices; ``members`` the voxels to test grouped
    by target, ``starts`` ``(B + 1,)`` where each target's group begins."""

    edge: int
    targets: NDArray[np.int64]
    members: NDArray[np.int64]
    starts: NDArray[np.int64]


def _block_ids(grid: Grid, voxels: NDArray[np.int64], edge: int) -> NDArray[np.int64]:
    """Raveled block index of each voxel."""
    block = np.stack(np.unravel_index(voxels, grid.shape), axis=1) // edge
    return np.ravel_multi_index(tuple(block.T), tuple(-(-np.asarray(grid.shape) // edge)))


def _scrambled(voxels: NDArray[np.int64]) -> NDArray[np.uint64]:
    """A fixed pseudo-random key per voxel index (Fibonacci hashing): which voxel of a block stands for it."""
    return (voxels.astype(np.uint64) + np.uint64(1)) * np.uint64(0x9E3779B97F4A7C15)


def blocks(grid: Grid, voxels: NDArray[np.int64], orientations: int, ik_solves: int | None,
           preferred: NDArray[np.bool_] | None = None) -> _Blocks:
    """The smallest block edge whose positions times ``orientations`` fit in ``ik_solves`` (None: no
    limit), and the positions: per block, one of its ``preferred`` voxels (grid-shaped mask, e.g.
    the voxels sampled; of all if it has none of those), picked pseudo-randomly by its index so
    that the block's value is, on average over blocks, the mean of its voxels' values."""
    voxels = np.asarray(voxels, dtype=np.int64)
    other = (np.zeros(voxels.size, dtype=bool) if preferred is None
             else ~np.asarray(preferred).ravel()[voxels])
    edge = 1
    if ik_solves is not None and voxels.size * orientations > ik_solves:
        dimensions = sum(not f for f in grid.flat)
        edge = max(1, int((voxels.size * orientations / max(ik_solves, 1)) ** (1 / dimensions)))
        while (np.unique(_block_ids(grid, voxels, edge)).size * orientations > ik_solves
               and edge < max(grid.shape)):
            edge += 1
    block = _block_ids(grid, voxels, edge)
    order = np.lexsort((voxels, _scrambled(voxels), other, block))   # by block, preferred first
    first = np.flatnonzero(np.r_[True, np.diff(block[order]) != 0])
    targets = voxels[order[first]]
    target_of = np.repeat(targets, np.diff(np.r_[first, order.size]))   # each sorted voxel's target
    by_target = np.lexsort((voxels[order], target_of))
    members = voxels[order][by_target]
    sorted_targets = np.sort(targets)
    sizes = np.bincount(np.searchsorted(sorted_targets, target_of), minlength=targets.size)
    return _Blocks(edge, sorted_targets, members, np.r_[0, np.cumsum(sizes)])


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

    def __init__(self, grid: Grid, orientations: int, positions: _Blocks) -> None:
        self.orientations = orientations
        self.positions = positions
        self.values = {"reachable_fraction": np.full(grid.size, np.nan),
                       "mean_solutions": np.full(grid.size, np.nan),
                       "max_solutions": np.full(grid.size, -1, dtype=np.int16)}

    def add(self, result: tuple[NDArray[np.int64], NDArray[np.int64]]) -> None:
        targets, counts = result
        at = np.searchsorted(self.positions.targets, targets)
        starts, ends = self.positions.starts[at], self.positions.starts[at + 1]
        voxels = np.concatenate([self.positions.members[a:b] for a, b in zip(starts, ends, strict=True)])
        sizes = ends - starts
        self.values["reachable_fraction"][voxels] = np.repeat((counts > 0).sum(axis=1) / self.orientations,
                                                              sizes)
        self.values["mean_solutions"][voxels] = np.repeat(counts.sum(axis=1) / self.orientations, sizes)
        self.values["max_solutions"][voxels] = np.repeat(counts.max(axis=1), sizes)

    def arrays(self) -> dict[str, NDArray]:
        return self.values

    def restore(self, arrays: dict[str, NDArray]) -> None:
        for key, values in self.values.items():
            values[:] = arrays[key].ravel()


def dexterity(robot: Robot, *, resolution: float = 0.02, grid: Grid | None = None,
              reach: ReachabilityMap | None = None, orientations: int = 100,
              voxels_per_chunk: int = VOXELS_PER_CHUNK, ik_solves: int | None = None, engine: Any = None,
              store: Any = None, section: str = "dexterity", resume: bool = False,
              progress: bool = False) -> DexterityMap:
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
        Positions per task.
    ik_solves : int, optional
        At most this many IK solves: blocks of voxels share one position when the voxels to
        test times ``orientations`` exceed it (module notes). Default: every voxel.
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
    if ik_solves is not None:
        whole_number(ik_solves, "ik_solves", minimum=1, maximum=MAX_SAMPLES)
    positions = blocks(grid, candidate_voxels(grid, robot, reach), int(orientations), ik_solves,
                       None if reach is None else reach.occupied)
    voxels = positions.targets
    n_chunks = -(-len(voxels) // voxels_per_chunk)
    accumulator = _Counts(grid, orientations, positions)
    task = _Task(robot_to_toml(robot), grid, voxels, int(orientations), voxels_per_chunk)
    attrs = {"orientations": int(orientations), "voxels_per_chunk": voxels_per_chunk,
             "candidate_voxels": len(voxels), "block": positions.edge}
    done = run_resumable(partial(_dexterity_of_chunk, task), n_chunks, accumulator, store=store,
                         name=section, attrs=attrs, resume=resume, engine=engine, progress=progress,
                         description="dexterity")
    return DexterityMap.from_section(grid, accumulator.values, {**attrs, "chunks_done": done})
