"""The memory a workspace run needs, estimated from its arguments before it starts.

A run holds its maps' per-voxel arrays for the whole run, and per worker thread the arrays of
the task it is working on (a reachability task counts hits on a whole grid; a manipulability
task holds its configurations and Jacobians; a dexterity task its voxels' target poses and IK
solutions). Nothing grows with the number of samples beyond one entry per chunk, so the peak
is bounded by the grid and the chunk size. :func:`check_memory` adds these up (the bytes per
item were measured with ``tracemalloc`` on 6-joint arms and rounded up) and refuses a run that
would not fit in the memory the machine has free, naming the option to change, instead of
letting the kernel's OOM killer end it without a word.

Runs on a Dask cluster are counted for this machine only (the maps; the tasks run on the
workers).
"""

from __future__ import annotations

import math
import os
import resource
from dataclasses import dataclass
from typing import Any

from armkit.errors import InputError
from armkit.workspace.grid import Grid

__all__ = ["MemoryEstimate", "available_memory", "check_memory", "estimate_memory", "local_threads"]

#: Bytes per voxel of the maps kept for the run: reachability (hits, hits of the even chunks,
#: masks), manipulability (eight statistics and their published means), dexterity (three
#: statistics, the candidate voxels, a dilation mask).
REACHABILITY_VOXEL_BYTES = 24
MANIPULABILITY_VOXEL_BYTES = 88
DEXTERITY_VOXEL_BYTES = 27
#: Bytes per voxel of one running reachability task (hits of its even and odd chunks, their sum).
REACHABILITY_TASK_VOXEL_BYTES = 24
#: Bytes per configuration of a running task: Sobol reachability (uniform samples are counted in
#: one compiled pass with no array per configuration), manipulability (FK, Jacobian, SVD; 521 measured).
SOBOL_SAMPLE_BYTES = 256
MANIPULABILITY_SAMPLE_BYTES = 768
#: Bytes per target pose of a running dexterity task (715 measured) and per orientation of its set.
DEXTERITY_POSE_BYTES = 1024
ORIENTATION_BYTES = 256
#: Bytes per chunk of the run's list of chunks.
CHUNK_BYTES = 128


@dataclass(frozen=True)
class MemoryEstimate:
    """Peak bytes of a run, by what they grow with.

    Attributes
    ----------
    maps : int
        The maps' per-voxel arrays and the running reachability tasks' grids (``resolution``).
    samples : int
        The running manipulability or Sobol tasks' configurations, the list of chunks (``chunk_size``).
    orientations : int
        The running dexterity tasks' poses and IK solutions (``orientations``).
    """

    maps: int
    samples: int
    orientations: int

    @property
    def total(self) -> int:
        return self.maps + self.samples + self.orientations


def estimate_memory(grid: Grid, *, samples: int, chunk_size: int, method: str = "uniform",
                    manipulability_samples: int = 0, orientations: int = 0, voxels_per_chunk: int = 250,
                    threads: int = 1, maps: int = 1) -> MemoryEstimate:
    """Peak memory [bytes] of a run with these arguments (see the module notes).

    Parameters
    ----------
    grid : Grid
    samples, chunk_size, method
        The reachability map's sample plan.
    manipulability_samples : int
        0: no manipulability map (its chunks are ``chunk_size // 4``).
    orientations : int
        0: no dexterity map.
    voxels_per_chunk : int
        Voxels per dexterity task.
    threads : int
        Tasks running at once on this machine (0 on a remote cluster).
    maps : int
        Sets of maps held at once (a design sweep holds one per value).

    Examples
    --------
    >>> from armkit.workspace.grid import Grid
    >>> grid = Grid((-0.5, -0.5, -0.5), 0.001, (1000, 1000, 1000))
    >>> f"{estimate_memory(grid, samples=10**6, chunk_size=2**18, threads=2).total:.3g}"
    '7.2e+10'
    """
    voxels = grid.size
    per_voxel = REACHABILITY_VOXEL_BYTES + (MANIPULABILITY_VOXEL_BYTES if manipulability_samples else 0)
    per_voxel += DEXTERITY_VOXEL_BYTES if orientations else 0
    map_bytes = maps * voxels * per_voxel + threads * voxels * REACHABILITY_TASK_VOXEL_BYTES
    task_samples = max(chunk_size * (SOBOL_SAMPLE_BYTES if method == "sobol" else 0),
                       max(1, chunk_size // 4) * MANIPULABILITY_SAMPLE_BYTES if manipulability_samples else 0)
    chunks = -(-samples // chunk_size) + (-(-manipulability_samples // max(1, chunk_size // 4)))
    dexterity_task = orientations * (voxels_per_chunk * DEXTERITY_POSE_BYTES + ORIENTATION_BYTES)
    return MemoryEstimate(map_bytes, threads * task_samples + chunks * CHUNK_BYTES, threads * dexterity_task)


def available_memory() -> int:
    """Bytes this process may still allocate: the memory the system has free (``MemAvailable``),
    or less under an address-space limit (``ulimit -v``, ``RLIMIT_AS``)."""
    free = _meminfo_available()
    limit, _ = resource.getrlimit(resource.RLIMIT_AS)
    if limit != resource.RLIM_INFINITY:
        free = min(free, max(0, limit - _virtual_size()))
    return free


def _meminfo_available() -> int:
    try:
        with open("/proc/meminfo", encoding="ascii") as meminfo:
            for line in meminfo:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")


def _virtual_size() -> int:
    try:
        with open("/proc/self/status", encoding="ascii") as status:
            for line in status:
                if line.startswith("VmSize:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


def _gib(size: float) -> str:
    return f"{size / 2**30:.3g} GiB"


def check_memory(grid: Grid, *, samples: int, chunk_size: int, method: str = "uniform",
                 manipulability_samples: int = 0, orientations: int = 0, engine: Any = None, maps: int = 1,
                 available: int | None = None) -> None:
    """Refuse a run whose :func:`estimate_memory` exceeds the memory available (default
    :func:`available_memory`), naming the option whose part is largest and a value that would fit.

    Raises
    ------
    InputError
        E.g. ``resolution 0.001 m (--resolution): the run needs about 184 GiB (1.06e+09 voxels),
        more than the 22.4 GiB of memory free; choose 0.0021 m or coarser``.
    """
    estimate = estimate_memory(grid, samples=samples, chunk_size=chunk_size, method=method,
                               manipulability_samples=manipulability_samples, orientations=orientations,
                               threads=local_threads(engine), maps=maps)
    available = available_memory() if available is None else available
    resolution = grid.resolution
    if estimate.total <= available:
        return
    need = f"the run needs about {_gib(estimate.total)}"
    have = f"more than the {_gib(available)} of memory free"
    part = max(("maps", "samples", "orientations"), key=lambda name: getattr(estimate, name))
    spare = max(available - (estimate.total - getattr(estimate, part)), 0)  # what that part may use
    share = spare / getattr(estimate, part)
    if part == "maps":
        coarser = resolution / max(share, 1e-12) ** (1 / grid.dimensions)
        raise InputError(f"resolution {resolution:g} m (--resolution): {need} ({grid.size:.3g} voxels), "
                         f"{have}; choose {_round_up(coarser):g} m or coarser")
    if part == "orientations":
        raise InputError(f"orientations {orientations} (--orientations): {need} for the dexterity map's "
                         f"tasks, {have}; choose {max(1, math.floor(orientations * share))} or fewer")
    raise InputError(f"chunk_size {chunk_size} (--chunk-size): {need} for the chunks, {have}; choose "
                     f"{max(1, math.floor(chunk_size * share))} or smaller, or fewer samples")


def _round_up(value: float) -> float:
    """``value`` rounded up to two significant digits."""
    scale = 10 ** (math.floor(math.log10(value)) - 1)
    return math.ceil(value / scale) * scale


def local_threads(engine: Any) -> int:
    """Tasks that run at once on this machine: the engine's threads, 0 for a Dask client."""
    from armkit.workspace.engine import engine_threads

    return 0 if hasattr(engine, "submit") else engine_threads(engine)
