"""An IK data set for learned solvers: sampled configurations, their poses, and every IK solution.

``ik_dataset(robot, N, out=...)`` draws ``N`` configurations inside the limits (seeded per
chunk like the maps), computes their tool poses and solves each pose for all closed-form
solutions (inside the limits or not). The Zarr store holds, row ``i`` for sample ``i``::

    q              (N, n)        the sampled configuration [rad or m]
    pose           (N, 4, 4)     T_base_tool(q) [m]
    solutions      (N, k, n)     every IK solution of pose i, nearest to q first; NaN padding
                                 (each once: the whole-turn copy nearest to q)
    counts         (N,)          solutions of pose i (k = the arm's most)
    within_limits  (N, k)        whether each solution is inside the joint limits
    chunk_done     (n_chunks,)   which chunks are written (a resume writes only the others)

Chunks are independent rows, so they are written as they finish, in any order, and a chunk
is marked done only after its rows are written.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from armkit.errors import InputError, NoClosedFormError
from armkit.ik import analyze_structure, ik_solutions
from armkit.robot import Robot
from armkit.robot_file import robot_to_toml
from armkit.workspace.engine import run_chunks
from armkit.workspace.sampling import SamplePlan, configurations, robot_from_toml
from armkit.workspace.store import create_store, store_lock

__all__ = ["IKDataset", "ik_dataset"]

#: Samples per chunk (and per Zarr chunk of every array).
DATASET_CHUNK = 2**14


@dataclass(frozen=True)
class IKDataset:
    """A data set store opened for reading; its arrays are Zarr arrays (read slices, not all of it).

    Attributes
    ----------
    group : zarr.Group
    path : str
    """

    group: Any
    path: str

    def __getitem__(self, name: str) -> Any:
        return self.group[name]

    @property
    def complete(self) -> bool:
        return bool(np.asarray(self.group["chunk_done"][...]).all())

    def summary(self) -> dict[str, Any]:
        meta = self.group.attrs["armkit"]
        counts = np.asarray(self.group["counts"][...])
        return {"robot": meta["robot"], "samples": int(len(counts)), "complete": self.complete,
                "max_solutions": int(self.group["solutions"].shape[1]),
                "mean_solutions": float(counts.mean()), "store": self.path,
                "seconds": self.group.attrs.get("summary", {}).get("seconds")}


@dataclass(frozen=True)
class _Task:
    robot_toml: str
    plan: SamplePlan
    k: int


def _rows_of_chunk(task: _Task, chunk: int) -> dict[str, NDArray]:
    robot = robot_from_toml(task.robot_toml)
    q = configurations(robot, task.plan, chunk)
    pose = robot.fk(q)
    found = ik_solutions(robot, pose, near=q, turn_copies=False)
    kept = np.arange(found.q.shape[1]) < found.counts[:, None]
    solutions = np.full((len(q), task.k, robot.n), np.nan)
    within = np.zeros((len(q), task.k), dtype=bool)
    width = min(task.k, found.q.shape[1])
    solutions[:, :width] = np.where(kept[..., None], found.q, np.nan)[:, :width]
    within[:, :width] = (found.within_limits & kept)[:, :width]
    return {"q": q, "pose": pose, "solutions": solutions, "counts": found.counts.astype(np.int16),
            "within_limits": within}


def ik_dataset(robot: Robot, samples: int, out: str | Path, *, seed: int = 0, method: str = "uniform",
               chunk_size: int = DATASET_CHUNK, engine: Any = None, resume: bool = False,
               overwrite: bool = False, progress: bool = False) -> IKDataset:
    """Write ``samples`` (q, pose, all IK solutions) rows to the Zarr store ``out`` (see the module notes).

    Raises
    ------
    NoClosedFormError
        If the arm has no closed-form IK (all solutions are only known in closed form).

    Examples
    --------
    >>> import armkit, tempfile, pathlib
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> data = ik_dataset(armkit.load("ur5"), 100, folder / "ik.zarr", chunk_size=64)
    >>> data["solutions"].shape, data.complete
    ((100, 8, 6), True)
    """
    structure = analyze_structure(robot)
    if not structure.closed_form:
        raise NoClosedFormError(f"{robot.name}: an IK data set lists every solution, which needs a closed "
                                f"form; {structure.description}")
    from armkit.workspace.maps import json_safe, store_meta

    plan = SamplePlan(int(samples), int(chunk_size), int(seed), method)
    k, n = structure.max_solutions, robot.n
    with store_lock(out):
        store = create_store(out, store_meta("ik-dataset", robot, None) | {"plan": plan.to_attrs()},
                             overwrite=overwrite, resume=resume)
        if store.attrs["armkit"].get("plan") != plan.to_attrs():
            raise InputError(f"cannot resume {str(out)!r}: it holds another sample plan "
                             f"({store.attrs['armkit'].get('plan')}); rerun with --force to replace it")
        shapes = {"q": ((n,), "float64"), "pose": ((4, 4), "float64"), "solutions": ((k, n), "float64"),
                  "counts": ((), "int16"), "within_limits": ((k,), "bool")}
        units = {"q": "rad or m", "pose": "m", "solutions": "rad or m"}
        if "chunk_done" not in store:
            for name, (tail, dtype) in shapes.items():
                store.create_array(name, shape=(plan.samples, *tail), chunks=(plan.chunk_size, *tail),
                                   dtype=dtype, fill_value=np.nan if dtype == "float64" else 0,
                                   attributes={"unit": units.get(name, "")})
            store.create_array("chunk_done", shape=(plan.n_chunks,), chunks=(1,), dtype="bool",
                               fill_value=False)
        done = np.asarray(store["chunk_done"][...])
        start = time.perf_counter()

        def write(chunk: int, rows: dict[str, NDArray]) -> None:
            rows_of = slice(chunk * plan.chunk_size, chunk * plan.chunk_size + len(rows["q"]))
            for name, values in rows.items():
                store[name][rows_of] = values
            store["chunk_done"][chunk] = True

        todo = [c for c in range(plan.n_chunks) if not done[c]]
        run_chunks(partial(_rows_of_chunk, _Task(robot_to_toml(robot), plan, k)), todo, write, engine=engine,
                   progress=progress, description="IK data set")
        data = IKDataset(store, str(out))
        store.attrs["summary"] = json_safe({**data.summary(), "seconds": time.perf_counter() - start})
    return data
