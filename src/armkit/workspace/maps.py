"""All maps of one arm in one call, with their store: :func:`compute`, :func:`open`, :class:`Workspace`."""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from armkit._params import positive_float
from armkit.errors import InputError
from armkit.robot import Robot
from armkit.robot_file import robot_to_toml
from armkit.workspace.budget import check_memory
from armkit.workspace.dexterity import DexterityMap, dexterity
from armkit.workspace.grid import Grid, grid_for
from armkit.workspace.manipulability import SINGULAR_THRESHOLD, ManipulabilityMap, manipulability
from armkit.workspace.reachability import CHUNK_SIZE, ReachabilityMap, reachability
from armkit.workspace.sampling import SamplePlan
from armkit.workspace.store import create_store, load_section, open_store, store_lock

__all__ = ["Workspace", "compute", "json_safe", "open", "store_meta", "workspace_from_group", "write_axes"]

_MAPS = {"reachability": ReachabilityMap, "manipulability": ManipulabilityMap, "dexterity": DexterityMap}


@dataclass(frozen=True)
class Workspace:
    """The maps of one arm on one grid, as computed or as reopened from a store.

    Attributes
    ----------
    robot : Robot
        Rebuilt from the robot file text the maps were made with.
    grid : Grid
    reachability, manipulability, dexterity : map or None
        The maps that were computed.
    seconds : float
        Wall-clock time of the run [s] (of the last part of a resumed run).
    path : str or None
        The store, if any.
    missing : tuple of str
        Maps the run was asked for that its store does not hold (it was interrupted before them).
    """

    robot: Robot
    grid: Grid
    reachability: ReachabilityMap | None = None
    manipulability: ManipulabilityMap | None = None
    dexterity: DexterityMap | None = None
    seconds: float = float("nan")
    path: str | None = None
    missing: tuple[str, ...] = ()

    @property
    def complete(self) -> bool:
        """Whether every map asked for is there and complete (an interrupted run's store is not)."""
        maps = (self.reachability, self.manipulability, self.dexterity)
        return not self.missing and all(m.complete for m in maps if m is not None)

    def summary(self) -> dict[str, Any]:
        """What ``--json`` prints: volume [m^3 or m^2] and its error, voxels, samples, seconds."""
        out: dict[str, Any] = {"robot": self.robot.name, "resolution_m": self.grid.resolution,
                               "grid_shape": list(self.grid.shape), "voxels": self.grid.size,
                               "seconds": self.seconds, "store": self.path, "complete": self.complete}
        if self.missing:
            out["maps_missing"] = list(self.missing)
        if self.reachability is not None:
            reach = self.reachability
            volume = reach.volume()
            out |= {"samples": reach.samples, "samples_requested": reach.plan.samples,
                    "reachability_complete": reach.complete, "method": reach.plan.method,
                    "seed": reach.plan.seed,
                    "reachable_volume": volume.value, "reachable_volume_error": volume.error,
                    "volume_unit": volume.unit, "volume": volume.as_dict(),
                    "mean_hits_per_reached_voxel": reach.samples / max(volume.occupied, 1),
                    "outer_boundary_voxels": int(reach.outer_boundary.sum())}
            if reach.colliding:
                out["colliding_samples_left_out"] = reach.colliding
        if self.manipulability is not None:
            manip = self.manipulability
            out["manipulability"] = {"samples": manip.samples, "complete": manip.complete,
                                     "mean": _nanmean(manip.mean_manipulability),
                                     "mean_inverse_condition": _nanmean(manip.mean_inverse_condition),
                                     "singular_threshold": manip.threshold,
                                     "singular_voxels": int(manip.singular.sum())}
        if self.dexterity is not None:
            dex = self.dexterity
            out["dexterity"] = {"orientations": dex.orientations, "voxels_tested": dex.tested,
                                "voxels_to_test": dex.candidates, "complete": dex.complete,
                                "ik_solves": dex.tested * dex.orientations,
                                "mean_reachability_index": dex.mean_index(),
                                "voxels_reached": int(dex.reachable.sum()),
                                "max_solutions": int(dex.max_solutions.max())}
        return out


def _nanmean(values: np.ndarray) -> float:
    return float(np.nanmean(values)) if np.isfinite(values).any() else float("nan")


def store_meta(kind: str, robot: Robot, grid: Grid | None) -> dict:
    """The root attributes of a store: kind of run, robot (name and file text), grid and units."""
    meta = {"kind": kind, "robot": robot.name, "robot_toml": robot_to_toml(robot),
            "units": {"length": "m", "angle": "rad", "x": "m", "y": "m", "z": "m"}}
    if grid is not None:
        meta |= {"grid": grid.to_attrs(), "volume_unit": grid.unit}
    return meta


def write_axes(group: Any, grid: Grid, prefix: str = "") -> None:
    for name, axis in zip("xyz", grid.axes, strict=True):
        group.create_array(f"{prefix}{name}", data=axis, overwrite=True, attributes={"unit": "m"})


def compute(robot: Robot, *, resolution: float = 0.02, samples: int = 1_000_000, seed: int = 0,
            method: str = "uniform", chunk_size: int = CHUNK_SIZE, manipulability_samples: int = 200_000,
            singular_threshold: float = SINGULAR_THRESHOLD, orientations: int = 100,
            engine: Any = None, out: str | Path | None = None, resume: bool = False,
            overwrite: bool = False, progress: bool = False, scene: Any = None) -> Workspace:
    """Reachability, manipulability and dexterity maps of ``robot``, written to ``out`` if given.

    Parameters
    ----------
    robot : Robot
    resolution : float
        Voxel edge [m].
    samples : int
        Configurations for the reachability map.
    seed, method, chunk_size
        See :func:`armkit.workspace.reachability`.
    manipulability_samples : int
        Configurations for the manipulability map (0: no map).
    singular_threshold : float
        See :mod:`armkit.workspace.manipulability`.
    orientations : int
        Tool orientations per voxel for the dexterity map (0: no map).
    engine : None, int or dask.distributed.Client
        Where the chunks run (default: a thread per local core).
    out : path, optional
        A Zarr store (a folder, by convention ``NAME.zarr``).
    resume : bool
        Continue the run stored in ``out`` (same robot, grid and settings).
    overwrite : bool
        Replace ``out`` if it exists.
    progress : bool
        Progress bars on stderr.
    scene : armkit.Scene, optional
        The reachability map leaves out the samples that collide in it (the manipulability and
        dexterity maps do not check collisions).

    Examples
    --------
    >>> import armkit
    >>> maps = compute(armkit.load("puma560"), resolution=0.2, samples=20_000, manipulability_samples=2000,
    ...                orientations=10)
    >>> sorted(k for k in maps.summary() if k.startswith("reachable_volume"))
    ['reachable_volume', 'reachable_volume_error']
    """
    start = time.perf_counter()
    positive_float(singular_threshold, "singular_threshold")
    grid = grid_for(robot, resolution)
    plan = SamplePlan(int(samples), int(chunk_size), int(seed), method)  # checked before the estimate
    check_memory(grid, samples=plan.samples, chunk_size=plan.chunk_size, method=method,
                 manipulability_samples=int(manipulability_samples), orientations=int(orientations),
                 engine=engine)
    with store_lock(out):
        store = None
        if out is not None:
            store = create_store(out, store_meta("maps", robot, grid), overwrite=overwrite, resume=resume)
            if "x" not in store:
                write_axes(store, grid)
            asked = {"reachability": True, "manipulability": manipulability_samples,
                     "dexterity": orientations}
            store.attrs["maps_requested"] = [name for name, wanted in asked.items() if wanted]
        common = {"grid": grid, "seed": seed, "method": method, "engine": engine, "store": store,
                  "resume": resume, "progress": progress}
        reach = reachability(robot, samples=samples, chunk_size=chunk_size, scene=scene, **common)
        manip = (manipulability(robot, samples=manipulability_samples, threshold=singular_threshold,
                                chunk_size=max(1, chunk_size // 4), **common)
                 if manipulability_samples else None)
        dex = (dexterity(robot, reach=reach, orientations=orientations, engine=engine, store=store,
                         resume=resume, progress=progress) if orientations else None)
        result = Workspace(robot, grid, reach, manip, dex, time.perf_counter() - start,
                           None if out is None else str(out))
        if store is not None:
            store.attrs["summary"] = json_safe(result.summary())
    return result


def json_safe(value: Any) -> Any:
    """Attributes are JSON: NaN and infinity become None."""
    if isinstance(value, dict):
        return {k: json_safe(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [json_safe(v) for v in value]
    if isinstance(value, float) and not np.isfinite(value):
        return None
    return value


def open(path: str | Path) -> Any:  # noqa: A001  (armkit.workspace.open, like zarr.open)
    """Reopen a store written by :func:`compute`, :func:`armkit.workspace.sweep` or
    :func:`armkit.workspace.ik_dataset`: a :class:`Workspace`, a ``Sweep`` or an ``IKDataset``.

    Raises
    ------
    InputError
        If ``path`` is not such a store.
    """
    from armkit.workspace.sampling import robot_from_toml

    group = open_store(path)
    meta = group.attrs["armkit"]
    robot = robot_from_toml(meta["robot_toml"])
    if meta["kind"] == "maps":
        return workspace_from_group(group, robot, Grid.from_attrs(meta["grid"]), "", str(path))
    if meta["kind"] == "sweep":
        from armkit.workspace.sweep import Sweep

        return Sweep.from_store(group, robot, str(path))
    if meta["kind"] == "ik-dataset":
        from armkit.workspace.dataset import IKDataset

        return IKDataset(group, str(path))
    raise InputError(f"{str(path)!r}: unknown kind of armkit store {meta['kind']!r}")


def workspace_from_group(group: Any, robot: Robot, grid: Grid, prefix: str, path: str | None) -> Workspace:
    """The maps under ``prefix`` of a store, with the ones its run asked for and did not reach."""
    maps = {}
    for name, cls in _MAPS.items():
        loaded = load_section(group, f"{prefix}{name}")
        maps[name] = None if loaded is None else cls.from_section(grid, *loaded)
    requested = group.attrs.get("maps_requested", [name for name, m in maps.items() if m is not None])
    missing = tuple(name for name in requested if maps[name] is None)
    seconds = group.attrs.get("summary", {}).get("seconds") if not prefix else None
    return Workspace(robot, grid, **maps, seconds=float("nan") if seconds is None else seconds, path=path,
                     missing=missing)

