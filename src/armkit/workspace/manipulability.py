"""Manipulability (Yoshikawa) and conditioning per voxel, and the singular voxels.

For every sampled configuration the base-frame Jacobian's singular values
``s_1 >= ... >= s_m`` give the manipulability ``w = s_1 ... s_m`` (Yoshikawa 1985,
``sqrt(det(J J^T))``) and the inverse condition number ``s_m / s_1`` in ``[0, 1]`` (1:
isotropic, 0: singular; its inverse, the condition number, is infinite at a singularity,
so statistics are kept of the inverse). Per voxel the map keeps the count, the sum, minimum
and maximum of both, and the minimum of ``s_m``; *singular voxels* are those where some
sample came within ``threshold`` of a singularity (``min s_m < threshold``). Linear and
angular rows are mixed as they are (m and rad), as in :meth:`armkit.Robot.manipulability`.
For an arm with a wrist, the wrist singularity can occur anywhere in the workspace, so
the singular voxels of a 6R arm mark where samples came near any singularity.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial
from typing import Any

import numpy as np
from numpy.typing import NDArray

from armkit._params import positive_float
from armkit.robot import Robot
from armkit.robot_file import robot_to_toml
from armkit.workspace.grid import Grid, grid_for
from armkit.workspace.reachability import CHUNK_SIZE
from armkit.workspace.sampling import (
    SamplePlan,
    configurations,
    robot_from_toml,
    singular_values,
    tool_positions,
)
from armkit.workspace.store import run_resumable

__all__ = ["ManipulabilityMap", "manipulability"]

#: Default singular-value threshold [m or rad per unit joint rate] of a singular voxel.
SINGULAR_THRESHOLD = 1e-3
_SUMS = ("manipulability_sum", "inverse_condition_sum")
_MINIMA = ("manipulability_min", "inverse_condition_min", "sigma_min_min")
_MAXIMA = ("manipulability_max", "inverse_condition_max")


@dataclass(frozen=True)
class ManipulabilityMap:
    """Per-voxel statistics of the Jacobian's singular values over the samples in each voxel.

    Attributes
    ----------
    grid : Grid
    arrays : dict of ndarray, each of shape grid.shape
        ``count`` (int64), ``manipulability_sum/min/max``, ``inverse_condition_sum/min/max``,
        ``sigma_min_min`` (NaN where no sample fell).
    plan : SamplePlan
    chunks_done : int
    threshold : float
        ``sigma_min_min`` below this marks a singular voxel.
    """

    grid: Grid
    arrays: dict[str, NDArray]
    plan: SamplePlan
    chunks_done: int
    threshold: float = SINGULAR_THRESHOLD

    @classmethod
    def from_section(cls, grid: Grid, arrays: dict[str, NDArray], attrs: dict) -> ManipulabilityMap:
        """The map a store's ``manipulability`` group holds."""
        stats = _Stats(grid)
        stats.restore(arrays)
        plan = SamplePlan(**{key: attrs[key] for key in ("samples", "chunk_size", "seed", "method")})
        return cls(grid, stats.published(grid.shape), plan, int(attrs["chunks_done"]),
                   float(attrs["threshold"]))

    @property
    def complete(self) -> bool:
        """Whether every chunk of the plan is counted (not an interrupted run's part)."""
        return self.chunks_done == self.plan.n_chunks

    @property
    def samples(self) -> int:
        """Configurations counted [-]."""
        return int(self.arrays["count"].sum())

    def _mean(self, key: str) -> NDArray[np.float64]:
        count = self.arrays["count"]
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(count > 0, self.arrays[f"{key}_sum"] / count, np.nan)

    @property
    def mean_manipulability(self) -> NDArray[np.float64]:
        """Mean Yoshikawa manipulability per voxel (NaN where no sample fell)."""
        return self._mean("manipulability")

    @property
    def mean_inverse_condition(self) -> NDArray[np.float64]:
        """Mean ``s_min / s_max`` per voxel in ``[0, 1]`` (NaN where no sample fell)."""
        return self._mean("inverse_condition")

    @property
    def singular(self) -> NDArray[np.bool_]:
        """Voxels where some sample had its smallest singular value below ``threshold``."""
        return np.nan_to_num(self.arrays["sigma_min_min"], nan=np.inf) < self.threshold


@dataclass(frozen=True)
class _Task:
    robot_toml: str
    grid: Grid
    plan: SamplePlan


def _reduce_by_voxel(flat: NDArray[np.int64], values: dict[str, NDArray]) -> tuple[NDArray, dict]:
    """Per-voxel count, sums, minima and maxima of ``values`` over samples sorted by voxel."""
    order = np.argsort(flat, kind="stable")
    flat = flat[order]
    voxels, starts, counts = np.unique(flat, return_index=True, return_counts=True)
    out = {"count": counts.astype(np.int64)}
    for name, v in values.items():
        v = v[order]
        out[f"{name}_sum"] = np.add.reduceat(v, starts)
        out[f"{name}_min"] = np.minimum.reduceat(v, starts)
        out[f"{name}_max"] = np.maximum.reduceat(v, starts)
    return voxels, out


def _stats_of_chunk(task: _Task, chunk: int) -> tuple[NDArray[np.int64], dict[str, NDArray]]:
    robot = robot_from_toml(task.robot_toml)
    q = configurations(robot, task.plan, chunk)
    flat = task.grid.flat_index(tool_positions(robot, q))
    inside = flat >= 0
    s = singular_values(robot, q[inside])
    voxels, stats = _reduce_by_voxel(flat[inside], {"manipulability": np.prod(s, axis=-1),
                                                    "inverse_condition": s[:, -1] / s[:, 0],
                                                    "sigma_min": s[:, -1]})
    keep = ("count", *_SUMS, *_MINIMA, *_MAXIMA)
    return voxels, {k: stats[k] for k in keep}


class _Stats:
    def __init__(self, grid: Grid) -> None:
        size = grid.size
        self.values = {"count": np.zeros(size, dtype=np.int64)}
        self.values |= {k: np.zeros(size) for k in _SUMS}
        self.values |= {k: np.full(size, np.inf) for k in _MINIMA}
        self.values |= {k: np.full(size, -np.inf) for k in _MAXIMA}

    def add(self, result: tuple[NDArray[np.int64], dict[str, NDArray]]) -> None:
        voxels, stats = result
        for key in ("count", *_SUMS):
            self.values[key][voxels] += stats[key]
        for key in _MINIMA:
            self.values[key][voxels] = np.minimum(self.values[key][voxels], stats[key])
        for key in _MAXIMA:
            self.values[key][voxels] = np.maximum(self.values[key][voxels], stats[key])

    def arrays(self) -> dict[str, NDArray]:
        return self.values

    def restore(self, arrays: dict[str, NDArray]) -> None:
        for key, values in self.values.items():
            values[:] = arrays[key].ravel()

    def published(self, shape: tuple[int, ...]) -> dict[str, NDArray]:
        """The arrays in grid shape, minima and maxima NaN where no sample fell."""
        empty = self.values["count"] == 0
        return {k: (np.where(empty, np.nan, v) if k in _MINIMA + _MAXIMA else v).reshape(shape)
                for k, v in self.values.items()}


def manipulability(robot: Robot, *, resolution: float = 0.02, grid: Grid | None = None,
                   samples: int = 200_000, seed: int = 0, method: str = "uniform",
                   chunk_size: int = CHUNK_SIZE // 4, threshold: float = SINGULAR_THRESHOLD,
                   engine: Any = None, store: Any = None, section: str = "manipulability",
                   resume: bool = False, progress: bool = False) -> ManipulabilityMap:
    """Manipulability and conditioning statistics per voxel from sampled configurations.

    The parameters are those of :func:`armkit.workspace.reachability` (a Jacobian and its
    SVD cost several FKs, hence the smaller defaults), and ``threshold`` [m or rad] of a
    singular voxel.

    Examples
    --------
    >>> import armkit
    >>> stats = manipulability(armkit.load("puma560"), resolution=0.1, samples=2000)
    >>> bool(np.nanmax(stats.mean_inverse_condition) <= 1.0), int(stats.arrays["count"].sum())
    (True, 2000)
    """
    threshold = positive_float(threshold, "threshold")
    grid = grid_for(robot, resolution) if grid is None else grid
    plan = SamplePlan(int(samples), int(chunk_size), int(seed), method)
    accumulator = _Stats(grid)
    done = run_resumable(partial(_stats_of_chunk, _Task(robot_to_toml(robot), grid, plan)), plan.n_chunks,
                         accumulator, store=store, name=section,
                         attrs={**plan.to_attrs(), "threshold": float(threshold)}, resume=resume,
                         engine=engine, progress=progress, description="manipulability")
    return ManipulabilityMap(grid, accumulator.published(grid.shape), plan, done, float(threshold))
