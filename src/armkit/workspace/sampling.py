"""The workspace maps' only contact with the kinematics: configurations in, positions, IK counts out.

Every map computes through the batch functions here (:func:`voxel_hits`,
:func:`tool_positions`, :func:`singular_values`, :func:`ik_solution_counts`), so a faster
kernel replaces them in one place. They run one thread each (:data:`KERNEL_THREADS`): the
engine runs a chunk per core. Configurations come in chunks, each drawn from its own seed
(``SeedSequence(seed, spawn_key=(chunk,))``, the ``chunk``-th child of ``SeedSequence(seed)``),
so a chunk's samples do not depend on which worker draws it, or when.

``method="uniform"``: independent uniform configurations in the joint box, drawn in the
compiled core by a counter-based generator (configuration ``i`` of a chunk from splitmix64
started at ``item_seed(chunk_seed, i)``, ``cpp/include/armkit/reach.hpp``), so
:func:`voxel_hits` samples, computes positions and counts in one pass without arrays per
configuration, and the samples do not depend on the thread count.
``method="sobol"``: each chunk is a scrambled Sobol point set of the chunk's size, scrambled
by the chunk's own seed (independent randomised quasi-Monte Carlo replicates; a chunk size
that is a power of two keeps Sobol's balance). One long sequence split by ``fast_forward``
would cost time proportional to the chunk's position in scipy.
"""

from __future__ import annotations

import tomllib
import warnings
from dataclasses import dataclass
from functools import lru_cache
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from armkit import _core
from armkit._params import whole_number
from armkit.errors import InputError
from armkit.ik import analyze_structure, ik_solutions, numeric_ik
from armkit.kinematics import fk
from armkit.robot import Robot
from armkit.robot_file import robot_from_dict

if TYPE_CHECKING:
    from armkit.workspace.grid import Grid

__all__ = ["MAX_SAMPLES", "METHODS", "SamplePlan", "configurations", "has_closed_form", "ik_solution_counts",
           "joint_box",
           "robot_from_toml", "singular_values", "tool_positions", "voxel_hits"]

METHODS = ("uniform", "sobol")
#: Most samples (and configurations per chunk) of a plan: the largest count a float (JSON, ``1e15``
#: on the command line) holds exactly.
MAX_SAMPLES = 2**53
#: Wall-clock budget [s] of one numeric IK solve (restarts from random seeds until then).
NUMERIC_BUDGET = 0.05
#: Travel [m] sampled for a prismatic joint without limits (as :meth:`armkit.Robot.random_q`).
UNBOUNDED_TRAVEL = 1.0
#: Threads of one kernel call inside a chunk (the engine already runs a chunk per core).
KERNEL_THREADS = 1


@dataclass(frozen=True)
class SamplePlan:
    """How many configurations, in chunks of what size, from which seed and sequence.

    Examples
    --------
    >>> plan = SamplePlan(samples=10, chunk_size=4)
    >>> plan.n_chunks, [plan.chunk_count(i) for i in range(plan.n_chunks)]
    (3, [4, 4, 2])
    """

    samples: int
    chunk_size: int = 2**18
    seed: int = 0
    method: str = "uniform"

    def __post_init__(self) -> None:
        for name in ("samples", "chunk_size"):
            whole_number(getattr(self, name), name, minimum=1, maximum=MAX_SAMPLES)
        if self.method not in METHODS:
            raise InputError(f"sampling method {self.method!r}; expected one of {', '.join(METHODS)}")
        if not (isinstance(self.seed, int | np.integer) and self.seed >= 0):
            raise InputError(f"seed: expected a whole number >= 0, got {self.seed!r}")

    @property
    def n_chunks(self) -> int:
        return -(-self.samples // self.chunk_size)

    def chunk_count(self, chunk: int) -> int:
        """Configurations in chunk ``chunk`` (the last one may be short)."""
        return min(self.chunk_size, self.samples - chunk * self.chunk_size)

    def to_attrs(self) -> dict:
        return {"samples": int(self.samples), "chunk_size": int(self.chunk_size), "seed": int(self.seed),
                "method": self.method}


@lru_cache(maxsize=8)
def robot_from_toml(text: str) -> Robot:
    """The robot a robot file's text describes, built once per process (tasks carry the text, not the
    robot, so that they pickle for a Dask worker)."""
    return robot_from_dict(tomllib.loads(text), "robot description in the task")


def joint_box(robot: Robot) -> NDArray[np.float64]:
    """``(n, 2)`` the joint ranges sampled [rad or m]: the limits, ±1 m for an unbounded prismatic joint."""
    limits = robot.limits
    return np.where(np.isfinite(limits), limits, [[-UNBOUNDED_TRAVEL, UNBOUNDED_TRAVEL]])


def configurations(robot: Robot, plan: SamplePlan, chunk: int) -> NDArray[np.float64]:
    """Chunk ``chunk``'s configurations ``(plan.chunk_count(chunk), n)`` [rad or m], inside the limits.

    >>> import armkit
    >>> robot = armkit.load("ur5")
    >>> plan = SamplePlan(100, chunk_size=50, seed=7)
    >>> bool((configurations(robot, plan, 1) == configurations(robot, plan, 1)).all())
    True
    """
    count, box = plan.chunk_count(chunk), joint_box(robot)
    if plan.method == "uniform":
        q = np.empty((count, robot.n))
        seed = chunk_seed(plan, chunk)
        _core.sample_uniform(robot.chain._core, *_box_edges(box), seed, 0, q, KERNEL_THREADS)
        return q
    from scipy.stats import qmc

    rng = np.random.default_rng(np.random.SeedSequence(int(plan.seed), spawn_key=(int(chunk),)))
    with warnings.catch_warnings():  # a short last chunk is not a power of two: known, see above
        warnings.filterwarnings("ignore", "The balance properties", UserWarning)
        unit = qmc.Sobol(robot.n, scramble=True, rng=rng).random(count)
    return box[:, 0] + unit * (box[:, 1] - box[:, 0])


def chunk_seed(plan: SamplePlan, chunk: int) -> int:
    """The 64-bit seed of chunk ``chunk``'s uniform samples, from the chunk-th child of the seed
    (``SeedSequence(seed, spawn_key=(chunk,))``)."""
    state = np.random.SeedSequence(int(plan.seed), spawn_key=(int(chunk),)).generate_state(1, np.uint64)
    return int(state[0])


def _box_edges(box: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    return np.ascontiguousarray(box[:, 0]), np.ascontiguousarray(box[:, 1])


def voxel_hits(robot: Robot, grid: Grid, plan: SamplePlan, chunk: int,
               hits: NDArray[np.int64] | None = None, scene: Any = None) -> tuple[NDArray[np.int64], int]:
    """Chunk ``chunk``'s tool positions counted per voxel: hits ``(grid.size,)`` and the samples outside.

    ``uniform``: sampled, moved through FK (position only) and counted in one compiled pass,
    with no array per configuration; ``sobol``: the configurations of :func:`configurations`
    counted by the same kernel. Given ``hits`` (contiguous int64, ``(grid.size,)``), the counts
    are added to it and it is returned. Given an :class:`armkit.Scene`, the configurations of
    :func:`configurations` that collide in it are left out (counted nowhere).
    """
    hits = np.zeros(grid.size, dtype=np.int64) if hits is None else hits
    lower = np.ascontiguousarray(grid.lower, dtype=np.float64)
    where = (lower, float(grid.resolution), *map(int, grid.shape))
    if scene is not None:
        q = configurations(robot, plan, chunk)
        outside = _core.reach_given(robot.chain._core, np.ascontiguousarray(q[~scene.collides(q)]), *where,
                                    hits, KERNEL_THREADS)
    elif plan.method == "uniform":
        seed, box = chunk_seed(plan, chunk), _box_edges(joint_box(robot))
        outside = _core.reach_uniform(robot.chain._core, *box, seed, 0, plan.chunk_count(chunk), *where, hits,
                                      KERNEL_THREADS)
    else:
        outside = _core.reach_given(robot.chain._core, configurations(robot, plan, chunk), *where, hits,
                                    KERNEL_THREADS)
    return hits, int(outside)


def tool_positions(robot: Robot, q: NDArray[np.float64]) -> NDArray[np.float64]:
    """Tool positions ``(N, 3)`` [m] in the base frame of configurations ``(N, n)``."""
    return fk(robot, q, threads=KERNEL_THREADS)[..., :3, 3]


def singular_values(robot: Robot, q: NDArray[np.float64]) -> NDArray[np.float64]:
    """Singular values ``(N, min(6, n))`` of the base-frame Jacobian, descending (m and rad mixed)."""
    return robot.singular_values(q)


def has_closed_form(robot: Robot) -> bool:
    """Whether armkit solves this arm's IK in closed form (else :func:`ik_solution_counts` is numeric)."""
    return analyze_structure(robot).closed_form


def ik_solution_counts(robot: Robot, T_base_tool: NDArray[np.float64]) -> NDArray[np.int64]:
    """Distinct IK solutions inside the joint limits of each target pose ``(N, 4, 4)``: ``(N,)``.

    Closed form: every solution (a singular family counts once; whole-turn copies of a joint
    whose limits span more than a turn count once, see :mod:`armkit.ik.pipeline`). Without a closed form, a
    numeric solve per pose (slow: ~1 ms for a reachable pose, up to :data:`NUMERIC_BUDGET` for
    one out of reach) that can only say 1 (solved) or 0.
    """
    if not has_closed_form(robot):
        return np.array([int(numeric_ik(robot, T, rng=0, time_budget=NUMERIC_BUDGET).success)
                         for T in T_base_tool], dtype=np.int64)
    found = ik_solutions(robot, T_base_tool, turn_copies=False, threads=KERNEL_THREADS)
    kept = np.arange(found.within_limits.shape[1]) < found.counts[:, None]
    return (found.within_limits & kept).sum(axis=1).astype(np.int64)
