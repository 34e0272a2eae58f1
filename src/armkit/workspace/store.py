"""The Zarr store behind ``--out DIR.zarr``: one group per map, checkpoints, resume.

Layout (Zarr format 3)::

    DIR.zarr/                 attrs: armkit = {format, version, kind, units, robot, robot_toml, grid}
      x, y, z                 voxel-centre coordinates [m]
      reachability/hits       (nx, ny, nz) int64; attrs: samples, seed, method, chunk_size,
                              chunks_done, n_chunks, writing, volume summary
      manipulability/...      per-voxel sums, minima, maxima and means
      dexterity/...           reachable fraction, mean and max IK solutions per voxel
      sweep/<k>/...           the same groups for each value of a design sweep

A map group is a checkpoint: its arrays hold the reduction of chunks ``0 .. chunks_done - 1``
(chunks are reduced in order, see :mod:`armkit.workspace.engine`). A checkpoint first sets
the group's ``writing`` attribute, then writes the arrays, then the attributes with the new
``chunks_done`` and ``writing = false``; a group found with ``writing = true`` was cut off
mid-write (killed, not Ctrl-C, which waits for the write) and is not resumed from.

A run holds an exclusive lock on its store for its whole length (:func:`store_lock`: ``flock``
on a file ``.NAME.lock`` beside the store, released when the run ends or its process dies), so a
second run on the same store, with ``--force`` or ``--resume``, is refused instead of removing
or mixing the first one's results.
"""

from __future__ import annotations

import fcntl
import os
import shutil
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any, Protocol

import numpy as np
from numpy.typing import NDArray

from armkit.errors import InputError
from armkit.workspace.engine import InterruptedRun, run_chunks

__all__ = ["FORMAT", "Accumulator", "create_store", "load_section", "open_store", "run_resumable",
           "save_section", "store_lock"]

FORMAT = "armkit-workspace"
VERSION = 1


def _zarr() -> Any:
    try:
        import zarr
    except ImportError as exc:
        raise InputError("writing a Zarr store needs zarr >= 3: pip install 'armkit[workspace]'") from exc
    return zarr


def _is_store(path: Path) -> bool:
    return (path / "zarr.json").is_file()


@contextmanager
def store_lock(path: str | Path | None) -> Iterator[None]:
    """Hold the store at ``path`` for one run (see the module notes); nothing if ``path`` is None.

    Raises
    ------
    InputError
        If another run holds it, or the lock file cannot be created beside it.
    """
    if path is None:
        yield
        return
    path = Path(path)
    lock = path.with_name(f".{path.name}.lock")
    try:
        handle = os.open(lock, os.O_RDWR | os.O_CREAT, 0o666)
    except OSError as exc:
        raise InputError(f"cannot lock {str(path)!r}: {exc.strerror or exc} ({str(lock)!r})") from exc
    try:
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise InputError(f"{str(path)!r} is being written by another run; wait for it to end or "
                             f"choose another --out (out=)") from None
        yield
    finally:
        os.close(handle)  # releases the lock


def create_store(path: str | Path, meta: dict, *, overwrite: bool = False, resume: bool = False) -> Any:
    """Open a store to write into: a new one, or (``resume``) the one at ``path`` made for the same ``meta``.

    Raises
    ------
    InputError
        If ``path`` exists and neither ``overwrite`` nor ``resume`` is given; if ``overwrite`` would
        remove a folder that is not a Zarr store; if ``resume`` finds no store, or one made for
        another robot, grid or kind of run.
    """
    zarr, path = _zarr(), Path(path)
    if resume and not path.exists():
        raise InputError(f"cannot resume {str(path)!r}: there is no store there; run without --resume "
                         f"(resume=False) to start one")
    if resume and _is_store(path):
        group = zarr.open_group(path, mode="r+")
        saved = dict(group.attrs.get("armkit", {}))
        for key in ("kind", "robot_toml", "grid"):
            if saved.get(key) != meta.get(key):
                what = key.replace("_", " ")
                raise InputError(f"cannot resume {str(path)!r}: it was made for another {what} "
                                 f"(rerun without --resume, with --force to replace it)")
        return group
    if path.exists():
        if not overwrite and not resume:
            raise InputError(f"{str(path)!r} exists; pass --force (overwrite=True) to replace it or "
                             f"--resume to continue the run stored in it")
        if not _is_store(path) and not (path.is_dir() and not any(path.iterdir())):
            raise InputError(f"{str(path)!r} is not a Zarr store; refusing to replace it")
        shutil.rmtree(path)
    group = zarr.open_group(path, mode="w", zarr_format=3)
    group.attrs["armkit"] = {"format": FORMAT, "version": VERSION, **meta}
    return group


def open_store(path: str | Path) -> Any:
    """The store at ``path`` for reading; :class:`InputError` if it is not an armkit workspace store."""
    zarr, path = _zarr(), Path(path)
    if not _is_store(path):
        raise InputError(f"{str(path)!r} is not a Zarr store (no zarr.json); expected the --out of "
                         f"'armkit workspace'")
    group = zarr.open_group(path, mode="r")
    if group.attrs.get("armkit", {}).get("format") != FORMAT:
        raise InputError(f"{str(path)!r} is a Zarr store but not one written by 'armkit workspace'")
    return group


def save_section(group: Any, name: str, arrays: dict[str, NDArray], attrs: dict) -> None:
    """Write a map group's arrays and attributes as one checkpoint (see the module notes)."""
    section = group.require_group(name)
    section.attrs["writing"] = True
    for key, values in arrays.items():
        if key in section and section[key].shape == values.shape and section[key].dtype == values.dtype:
            section[key][...] = values
        else:
            section.create_array(key, data=values, overwrite=True)
    section.attrs.update({**attrs, "writing": False})


def load_section(group: Any, name: str) -> tuple[dict[str, NDArray], dict] | None:
    """A map group's arrays and attributes, or ``None`` if the store has no such group."""
    if name not in group:
        return None
    section = group[name]
    attrs = dict(section.attrs)
    if attrs.get("writing", True):
        raise InputError(f"the store's {name!r} was cut off while being written; it cannot be resumed "
                         f"(rerun with --force to start again)")
    return {key: np.asarray(section[key][...]) for key, _ in section.arrays()}, attrs


class Accumulator(Protocol):
    """What :func:`run_resumable` reduces chunk results into."""

    def add(self, result: Any) -> None: ...

    def arrays(self) -> dict[str, NDArray]: ...

    def restore(self, arrays: dict[str, NDArray]) -> None: ...


def run_resumable(task: Callable[[Any], Any], n_chunks: int, accumulator: Accumulator, *, store: Any,
                  name: str, attrs: dict, resume: bool, engine: Any, progress: bool,
                  description: str, chunks_per_task: int | None = None) -> int:
    """Run chunks ``0 .. n_chunks - 1`` into ``accumulator``, checkpointing to ``store[name]``; chunks done.

    With ``resume``, a checkpoint in ``store[name]`` made with the same ``attrs`` (sample plan,
    orientations ...) is restored and only the remaining chunks run. Given ``chunks_per_task``,
    ``task`` gets a tuple of consecutive chunks (up to that many) instead of one chunk,
    and a checkpoint records the chunks of the tasks consumed (``chunks_done`` stays a prefix
    count, so a resume with another grouping continues where it stopped).

    Raises
    ------
    InputError
        If the checkpoint was made with other settings.
    """
    start = 0
    loaded = load_section(store, name) if store is not None and resume else None
    if loaded is not None:
        arrays, saved = loaded
        changed = [key for key in attrs if saved.get(key) != attrs[key]]
        if changed:
            differences = ", ".join(f"{k} {saved.get(k)!r} there, {attrs[k]!r} now" for k in changed)
            raise InputError(f"cannot resume {name}: the store was made with other settings ({differences})")
        accumulator.restore(arrays)
        start = int(saved["chunks_done"])
    done = [start]

    def consume(unit: Any, result: Any) -> None:
        accumulator.add(result)
        done[0] = (unit[-1] if isinstance(unit, tuple) else unit) + 1

    def checkpoint() -> None:
        if store is not None:
            save_section(store, name, accumulator.arrays(),
                         {**attrs, "chunks_done": done[0], "n_chunks": n_chunks})

    try:
        units: Any = range(start, n_chunks)
        if chunks_per_task is not None:
            units = [tuple(units[i:i + chunks_per_task]) for i in range(0, len(units), chunks_per_task)]
        run_chunks(task, units, consume, engine=engine, progress=progress,
                   description=description, checkpoint=checkpoint)
    except InterruptedRun as exc:
        if store is None:
            raise
        raise InterruptedRun(f"{exc}; the store keeps them: continue with --resume (resume=True)") from None
    return done[0]

