"""Reachability: how often sampled configurations put the tool in each voxel, and the reachable volume.

The volume estimator, and what its error covers
-----------------------------------------------
A voxel is *occupied* when at least one sample fell in it. ``V_occ = occupied * h^3``
(``h`` the resolution) overstates the volume of the reachable set ``W`` by the part of the
voxels on its boundary that lies outside ``W``, and understates it by the voxels of ``W``
no sample has hit yet. Both are estimated from the map itself:

* voxelisation: *boundary* voxels are occupied ones with an unoccupied neighbour (26 in
  3-D, 8 in 2-D; the grid's outside counts as unoccupied). Each holds between none and all
  of its volume inside ``W``, so the estimate is ``V = V_occ - V_bdry / 2`` with error
  ``V_bdry / 2`` (``V_bdry = boundary * h^3``). It assumes ``W`` has no holes or spikes thinner
  than a voxel, which do not show in any map of that resolution.
* sampling: reachable voxels not hit yet. Two estimates, the larger is taken: the
  bias-corrected Chao1 estimator ``f1 (f1 - 1) / (2 (f2 + 1))`` from the voxels hit exactly
  once (``f1``) and twice (``f2``) (Chao 1984; rarely hit voxels predict unseen ones), and
  the voxels the second half of the samples added to the first (even-numbered chunks
  against all), i.e. what the last doubling of the sample count found. Chao1 is a lower
  bound and was seen to fall short by 2.5x on a 6R arm; the doubling gain says what one
  more doubling would roughly add, not everything still missing. Its volume is added to
  the error, not to the estimate.

The stated error is their sum. It is a bound-like half-width, not one standard deviation:
the Monte Carlo scatter of ``V_occ`` between seeds is far smaller than either term once
the boundary is sampled (the tests check both the analytic volumes and this).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial
from typing import Any

import numpy as np
from numpy.typing import NDArray

from armkit.robot import Robot
from armkit.robot_file import robot_to_toml
from armkit.workspace.engine import engine_threads
from armkit.workspace.grid import Grid, grid_for
from armkit.workspace.sampling import SamplePlan, robot_from_toml, voxel_hits
from armkit.workspace.store import run_resumable

__all__ = ["ReachabilityMap", "VolumeEstimate", "boundary_mask", "reachability"]

#: Configurations per chunk by default (memory per chunk in flight: a few hundred bytes each).
CHUNK_SIZE = 2**18
#: Most chunks one task covers (see :func:`chunks_per_task`).
MAX_CHUNKS_PER_TASK = 8


@dataclass(frozen=True)
class VolumeEstimate:
    """The reachable volume [m^3] (area [m^2] for a planar arm) and what its error is made of.

    Attributes
    ----------
    value : float
        ``V_occ - V_bdry / 2`` (see :mod:`armkit.workspace.reachability`).
    error : float
        ``voxelisation_error + sampling_error``.
    voxelisation_error : float
        ``V_bdry / 2``.
    sampling_error : float
        Volume of the reachable voxels expected to be still unhit: the larger of Chao1 and the
        doubling gain.
    doubling_gain : float
        Volume of the voxels first reached by the second half of the samples.
    occupied, boundary : int
        Voxels hit, and those of them on the boundary.
    unit : str
        ``"m^3"`` or ``"m^2"``.
    """

    value: float
    error: float
    voxelisation_error: float
    sampling_error: float
    doubling_gain: float
    occupied: int
    boundary: int
    unit: str

    def as_dict(self) -> dict:
        return {"value": self.value, "error": self.error, "voxelisation_error": self.voxelisation_error,
                "sampling_error": self.sampling_error, "doubling_gain": self.doubling_gain,
                "occupied_voxels": self.occupied,
                "boundary_voxels": self.boundary, "unit": self.unit}


def boundary_mask(occupied: NDArray[np.bool_], grid: Grid) -> NDArray[np.bool_]:
    """Occupied voxels with an unoccupied neighbour (26 in 3-D, 8 in 2-D; outside the grid is unoccupied)."""
    from scipy.ndimage import binary_erosion

    structure = np.ones([1 if f else 3 for f in grid.flat], dtype=bool)
    return occupied & ~binary_erosion(occupied, structure=structure, border_value=0)


@dataclass(frozen=True)
class ReachabilityMap:
    """Hit counts per voxel of sampled configurations.

    Attributes
    ----------
    grid : Grid
    hits : ndarray, shape grid.shape, int64
        Samples whose tool position fell in each voxel.
    plan : SamplePlan
        The configurations asked for.
    chunks_done : int
        Chunks of ``plan`` counted (all of them unless the run was interrupted).
    outside : int
        Samples that fell outside the grid (0 for a grid from :func:`grid_for`).
    hits_even : ndarray, shape grid.shape, int64, optional
        The hits of the even-numbered chunks only (about half the samples).
    """

    grid: Grid
    hits: NDArray[np.int64]
    plan: SamplePlan
    chunks_done: int
    outside: int = 0
    hits_even: NDArray[np.int64] | None = None

    @classmethod
    def from_section(cls, grid: Grid, arrays: dict[str, NDArray], attrs: dict) -> ReachabilityMap:
        """The map a store's ``reachability`` group holds (see :mod:`armkit.workspace.store`)."""
        plan = SamplePlan(**{key: attrs[key] for key in ("samples", "chunk_size", "seed", "method")})
        return cls(grid, arrays["hits"].reshape(grid.shape), plan, int(attrs["chunks_done"]),
                   int(arrays["outside"][0]), arrays["hits_even"].reshape(grid.shape))

    @property
    def samples(self) -> int:
        """Configurations counted [-]."""
        return int(min(self.chunks_done * self.plan.chunk_size, self.plan.samples))

    @property
    def colliding(self) -> int:
        """Samples left out because they collided with the run's scene (0 without one) [-]."""
        return self.samples - int(self.hits.sum()) - self.outside

    @property
    def complete(self) -> bool:
        """Whether every chunk of the plan is counted (not an interrupted run's part)."""
        return self.chunks_done == self.plan.n_chunks

    @property
    def occupied(self) -> NDArray[np.bool_]:
        return self.hits > 0

    @property
    def boundary(self) -> NDArray[np.bool_]:
        """The outer and inner boundaries of the reachable region: occupied voxels next to empty ones."""
        return boundary_mask(self.occupied, self.grid)

    @property
    def outer_boundary(self) -> NDArray[np.bool_]:
        """The outer boundary only: the boundary of the reached region with its holes filled."""
        from scipy.ndimage import binary_fill_holes

        kept = tuple(slice(None) if not f else 0 for f in self.grid.flat)  # holes within the arm's plane
        filled = binary_fill_holes(self.occupied[kept]).reshape(self.grid.shape)
        return boundary_mask(filled, self.grid)

    def volume(self) -> VolumeEstimate:
        """The reachable volume with its error (see the module notes).

        Examples
        --------
        >>> import armkit
        >>> arm = armkit.Robot.from_dh([armkit.DHRow(0, 0.3, 0, 0), armkit.DHRow(0, 0.2, 0, 0)],
        ...                            "standard")
        >>> area = reachability(arm, resolution=0.01, samples=200_000).volume()
        >>> exact = np.pi * (0.5**2 - 0.1**2)
        >>> area.unit, bool(abs(area.value - exact) < area.error)
        ('m^2', True)
        """
        occupied = int(self.occupied.sum())
        boundary = int(self.boundary.sum())
        f1, f2 = int((self.hits == 1).sum()), int((self.hits == 2).sum())
        cell = self.grid.cell_measure
        voxelisation = boundary * cell / 2
        gain = 0.0
        if self.hits_even is not None and self.chunks_done > 1:
            gain = int((self.occupied & (self.hits_even == 0)).sum()) * cell
        sampling = max(f1 * (f1 - 1) / (2 * (f2 + 1)) * cell, gain)
        return VolumeEstimate(occupied * cell - voxelisation, voxelisation + sampling, voxelisation, sampling,
                              gain, occupied, boundary, self.grid.unit)


@dataclass(frozen=True)
class _Task:
    robot_toml: str
    grid: Grid
    plan: SamplePlan
    scene: Any = None  # an armkit.Scene whose colliding samples are left out (it pickles for Dask)


def _hits_of_chunks(task: _Task, chunks: tuple[int, ...]) -> tuple[NDArray[np.int64], NDArray[np.int64],
                                                                    NDArray[np.int64], int]:
    """Voxels hit by chunks ``chunks`` (raveled indices), how often in all of them and in the
    even-numbered ones, and how many samples missed the grid. The counts are added up on the
    worker, so one task ships one sparse array, whatever its number of chunks."""
    robot = robot_from_toml(task.robot_toml)
    even, odd = np.zeros(task.grid.size, dtype=np.int64), np.zeros(task.grid.size, dtype=np.int64)
    outside = 0
    for chunk in chunks:
        outside += voxel_hits(robot, task.grid, task.plan, chunk, even if chunk % 2 == 0 else odd,
                              scene=task.scene)[1]
    hits = even + odd
    voxels = np.flatnonzero(hits)
    return voxels, hits[voxels], even[voxels], outside


def chunks_per_task(n_chunks: int, threads: int) -> int:
    """Chunks one reachability task covers: up to :data:`MAX_CHUNKS_PER_TASK`, keeping about eight
    tasks per worker thread (fewer round trips and transfers; integer counts add up the same in
    any grouping)."""
    return max(1, min(MAX_CHUNKS_PER_TASK, n_chunks // (8 * threads)))


class _Hits:
    def __init__(self, grid: Grid) -> None:
        self.hits = np.zeros(grid.size, dtype=np.int64)
        self.hits_even = np.zeros(grid.size, dtype=np.int64)
        self.outside = np.zeros(1, dtype=np.int64)

    def add(self, result: tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64], int]) -> None:
        voxels, counts, counts_even, outside = result
        self.hits[voxels] += counts
        self.hits_even[voxels] += counts_even
        self.outside += outside

    def arrays(self) -> dict[str, NDArray]:
        return {"hits": self.hits, "hits_even": self.hits_even, "outside": self.outside}

    def restore(self, arrays: dict[str, NDArray]) -> None:
        self.hits[:] = arrays["hits"].ravel()
        self.hits_even[:] = arrays["hits_even"].ravel()
        self.outside[:] = arrays["outside"]


def _scene_digest(scene: Any) -> str:
    """A fingerprint of a scene for a store's checkpoint: a resume must check against the same one."""
    import hashlib
    import pickle

    return hashlib.sha256(pickle.dumps(scene)).hexdigest()[:16]


def reachability(robot: Robot, *, resolution: float = 0.02, grid: Grid | None = None,
                 samples: int = 1_000_000, seed: int = 0, method: str = "uniform",
                 chunk_size: int = CHUNK_SIZE, engine: Any = None, store: Any = None,
                 section: str = "reachability", resume: bool = False,
                 progress: bool = False, scene: Any = None) -> ReachabilityMap:
    """Sample configurations inside the joint limits and count the tool positions per voxel.

    Parameters
    ----------
    robot : Robot
    resolution : float
        Voxel edge [m] (ignored when ``grid`` is given).
    grid : Grid, optional
        Default :func:`grid_for` ``(robot, resolution)``.
    samples : int
        Configurations to draw.
    seed : int
        The same seed gives the same counts on any engine and after a resume.
    method : {"uniform", "sobol"}
        See :mod:`armkit.workspace.sampling`.
    chunk_size : int
        Configurations per task; memory grows with it (and the engine's threads), not with ``samples``.
    engine : None, int or dask.distributed.Client
        See :func:`armkit.workspace.engine.run_chunks`.
    store : zarr.Group, optional
        Checkpoint into ``store[section]`` (see :mod:`armkit.workspace.store`).
    resume : bool
        Continue from the checkpoint in ``store[section]``.
    progress : bool
        A progress bar on stderr.
    scene : armkit.Scene, optional
        Leave out the samples that collide in this scene (floor, obstacles, self-collision); they
        count in :attr:`ReachabilityMap.colliding`, not in any voxel.

    Returns
    -------
    ReachabilityMap
    """
    grid = grid_for(robot, resolution) if grid is None else grid
    plan = SamplePlan(int(samples), int(chunk_size), int(seed), method)
    accumulator = _Hits(grid)
    attrs = (plan.to_attrs() if scene is None or store is None  # the digest guards a store's resume
             else {**plan.to_attrs(), "scene": _scene_digest(scene)})
    task = _Task(robot_to_toml(robot), grid, plan, scene)
    done = run_resumable(partial(_hits_of_chunks, task), plan.n_chunks, accumulator, store=store,
                         name=section, attrs=attrs, resume=resume,
                         engine=engine, progress=progress, description="reachability",
                         chunks_per_task=chunks_per_task(plan.n_chunks, engine_threads(engine)))
    hits, hits_even = accumulator.hits.reshape(grid.shape), accumulator.hits_even.reshape(grid.shape)
    return ReachabilityMap(grid, hits, plan, done, int(accumulator.outside[0]), hits_even)
