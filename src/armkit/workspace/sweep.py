"""A design sweep: the same maps over a range of one DH parameter, e.g. a link length.

``"a2=0.2:0.4:5"`` means: parameter ``a`` of joint row 2 (1-based, as ``armkit show`` numbers
the rows), five values evenly from 0.2 to 0.4 in SI units (metres for ``a`` and ``d``,
radians for ``alpha`` and ``theta``). Each value rebuilds the arm with
:meth:`armkit.Robot.from_dh` from its DH table with that one entry changed (limits, tool
and base rows kept). All values share one grid (the union of their grids), so their maps
can be compared voxel by voxel; every value uses the same seed.
"""

from __future__ import annotations

import dataclasses
import re
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from armkit.chain import MAX_VALUE
from armkit.errors import InputError
from armkit.robot import Robot
from armkit.workspace.budget import check_memory
from armkit.workspace.dexterity import applies, dexterity
from armkit.workspace.grid import Grid, grid_for
from armkit.workspace.maps import (
    Workspace,
    default_sizes,
    json_safe,
    store_meta,
    workspace_from_group,
    write_axes,
)
from armkit.workspace.reachability import CHUNK_SIZE, reachability
from armkit.workspace.sampling import SamplePlan
from armkit.workspace.store import create_store, store_lock

__all__ = ["Sweep", "parse_sweep", "robot_with", "sweep"]

PARAMETERS = ("alpha", "a", "d", "theta")
#: Most values a sweep takes: each is a whole workspace run (and a map in the report).
MAX_SWEEP_VALUES = 1000
_SPEC = re.compile(r"^\s*(alpha|theta|a|d)(\d+)\s*=\s*([^:]+):([^:]+):(\d+)\s*$")


def parse_sweep(text: str) -> tuple[str, int, NDArray[np.float64]]:
    """``"a2=0.2:0.4:5"`` -> ``("a", 2, array([0.2, 0.25, 0.3, 0.35, 0.4]))``.

    >>> name, row, values = parse_sweep("a2=0.2:0.4:5")
    >>> name, row, values.round(3).tolist()
    ('a', 2, [0.2, 0.25, 0.3, 0.35, 0.4])
    """
    match = _SPEC.match(text)
    if match is None:
        raise InputError(f"sweep {text!r}: expected PARAMETER ROW=START:STOP:COUNT with PARAMETER one of "
                         f"{', '.join(PARAMETERS)}, e.g. 'a2=0.2:0.4:5' (SI units)")
    name, row, start, stop, count = match.groups()
    try:
        ends = float(start), float(stop)
    except ValueError as exc:
        raise InputError(f"sweep {text!r}: {start!r} or {stop!r} is not a number") from exc
    if not (np.abs(ends) <= MAX_VALUE).all():
        raise InputError(f"sweep {text!r}: expected finite START and STOP from {-MAX_VALUE:g} to "
                         f"{MAX_VALUE:g} (m or rad), got {start.strip()} and {stop.strip()}")
    if not 1 <= int(count) <= MAX_SWEEP_VALUES:
        raise InputError(f"sweep {text!r}: expected COUNT from 1 to {MAX_SWEEP_VALUES} (each value is a "
                         f"whole workspace run), got {count}")
    values = np.linspace(*ends, int(count))
    return name, int(row), values


def robot_with(robot: Robot, parameter: str, row: int, value: float) -> Robot:
    """``robot`` rebuilt from its DH table with ``parameter`` of joint row ``row`` (1-based) = ``value``."""
    if robot.dh is None:
        raise InputError(f"{robot.name}: has no DH table to sweep")
    if parameter not in PARAMETERS:
        raise InputError(f"sweep parameter {parameter!r}; expected one of {', '.join(PARAMETERS)}")
    if not 1 <= row <= robot.n:
        raise InputError(f"sweep row {row}: {robot.name} has joint rows 1 to {robot.n}")
    rows = list(robot.dh.rows)
    rows[row - 1] = dataclasses.replace(rows[row - 1], **{parameter: float(value)})
    chain = robot.chain
    return Robot.from_dh(rows, robot.dh.convention, name=f"{robot.name} ({parameter}{row}={value:g})",
                         limits=[(j.lower, j.upper) for j in chain.joints],
                         max_velocity=[j.max_velocity for j in chain.joints],
                         max_acceleration=[j.max_acceleration for j in chain.joints],
                         base_rows=robot.dh.base_rows, tool_rows=robot.dh.tool_rows,
                         names=robot.joint_names)


@dataclass(frozen=True)
class Sweep:
    """The maps for each value of one DH parameter.

    Attributes
    ----------
    robot : Robot
        The arm as given (each map holds its variant).
    parameter : str
        E.g. ``"a2"``.
    values : ndarray (k,)
        SI units.
    maps : list of Workspace
        One per value, on one shared grid.
    seconds : float
    path : str or None
    complete : bool
        Whether every value's maps are there and complete (an interrupted run's store is not).
    """

    robot: Robot
    parameter: str
    values: NDArray[np.float64]
    maps: list[Workspace]
    seconds: float = float("nan")
    path: str | None = None
    complete: bool = True

    def table(self) -> list[dict[str, Any]]:
        """Per value: reachable volume and its error [m^3], mean reachability index."""
        rows = []
        for value, maps in zip(self.values, self.maps, strict=True):
            volume = maps.reachability.volume()
            index = maps.dexterity.mean_index(maps.reachability.occupied) if maps.dexterity else None
            rows.append({"value": float(value), "reachable_volume": volume.value,
                         "reachable_volume_error": volume.error, "volume_unit": volume.unit,
                         "mean_reachability_index": index})
        return rows

    def summary(self) -> dict[str, Any]:
        first = self.maps[0]
        return {"robot": self.robot.name, "parameter": self.parameter, "resolution_m": first.grid.resolution,
                "voxels": first.grid.size, "samples": first.reachability.samples, "seconds": self.seconds,
                "store": self.path, "complete": self.complete, "values": self.table()} | (
                    {"maps_skipped": dict(first.skipped)} if first.skipped else {})

    @classmethod
    def from_store(cls, group: Any, robot: Robot, path: str) -> Sweep:
        meta = group.attrs["armkit"]
        grid = Grid.from_attrs(meta["grid"])
        name, row = meta["sweep_parameter"], meta["sweep_row"]
        values = np.asarray(meta["sweep_values"])
        maps = [workspace_from_group(group, robot_with(robot, name, row, v), grid, f"sweep/{k}/", path)
                for k, v in enumerate(values) if f"sweep/{k}" in group]
        seconds = group.attrs.get("summary", {}).get("seconds")
        seconds = float("nan") if seconds is None else seconds
        complete = len(maps) == len(values) and all(m.complete for m in maps)
        return cls(robot, f"{name}{row}", values[:len(maps)], maps, seconds, path, complete)


def sweep(robot: Robot, spec: str, *, resolution: float = 0.02, samples: int = 1_000_000, seed: int = 0,
          method: str = "uniform", chunk_size: int = CHUNK_SIZE, orientations: int = 0,
          ik_solves: int | None = None, engine: Any = None,
          out: str | Path | None = None, resume: bool = False, overwrite: bool = False,
          progress: bool = False) -> Sweep:
    """Reachability (and with ``orientations`` dexterity) maps for each value of a DH parameter.

    ``spec`` is e.g. ``"a2=0.2:0.4:5"`` (see the module notes); the other parameters are
    those of :func:`armkit.workspace.compute`.

    Examples
    --------
    >>> import armkit
    >>> result = sweep(armkit.load("probot-anno"), "a3=0.15:0.3:2", resolution=0.05, samples=20_000)
    >>> [round(row["value"], 2) for row in result.table()]
    [0.15, 0.3]
    >>> result.table()[0]["reachable_volume"] < result.table()[1]["reachable_volume"]
    True
    """
    start = time.perf_counter()
    name, row, values = parse_sweep(spec)
    robots = [robot_with(robot, name, row, v) for v in values]
    ik_solves = default_sizes(robot, int(samples))[1] if ik_solves is None else ik_solves
    skipped = {}
    if orientations and (reason := applies(robot, orientations, ik_solves)) is not None:
        skipped["dexterity"], orientations = reason, 0
    grid = grid_for(robots[0], resolution)
    for other in robots[1:]:
        grid = grid.union(grid_for(other, resolution))
    plan = SamplePlan(int(samples), int(chunk_size), int(seed), method)  # checked before the estimate
    check_memory(grid, samples=plan.samples, chunk_size=plan.chunk_size, method=method,
                 orientations=int(orientations), engine=engine, maps=len(robots))
    with store_lock(out):
        store = None
        if out is not None:
            meta = store_meta("sweep", robot, grid) | {"sweep_parameter": name, "sweep_row": row,
                                                       "sweep_values": values.tolist()}
            store = create_store(out, meta, overwrite=overwrite, resume=resume)
            if "x" not in store:
                write_axes(store, grid)
            store.attrs["maps_requested"] = ["reachability", *(["dexterity"] if orientations else [])]
        maps = []
        for k, variant in enumerate(robots):
            common = {"engine": engine, "store": store, "resume": resume, "progress": progress}
            reach = reachability(variant, grid=grid, samples=samples, seed=seed, method=method,
                                 chunk_size=chunk_size, section=f"sweep/{k}/reachability", **common)
            dex = (dexterity(variant, reach=reach, orientations=orientations, ik_solves=ik_solves,
                             section=f"sweep/{k}/dexterity", **common) if orientations else None)
            maps.append(Workspace(variant, grid, reach, None, dex, skipped=skipped))
        path = None if out is None else str(out)
        result = Sweep(robot, f"{name}{row}", values, maps, time.perf_counter() - start, path)
        if store is not None:
            store.attrs["summary"] = json_safe(result.summary())
    return result
