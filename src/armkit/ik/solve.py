"""The IK dispatcher behind :meth:`armkit.Robot.ik`: closed form where the geometry has one.

For a chain with a closed-form solution (see :mod:`armkit.ik.structure`) every candidate
of :func:`armkit.ik.closed_form.closed_form_ik` is

1. wrapped into the joint limits: a revolute angle is shifted by a multiple of ``2 pi``
   when that makes it fit (among several fitting shifts, the one closest to ``near``);
2. verified by forward kinematics: it must reproduce the target within
   :data:`VERIFY_TOLERANCE` (candidates above ``1e-10`` are first refined by a few
   Newton steps of the numeric solver, without leaving the solution's branch);
3. at a singular pose, moved from the closed form's representative of its family of
   solutions to the member nearest to ``near`` (:func:`_nearest_family_members`);
4. flagged inside or outside the limits and sorted by distance to ``near``
   (``closed_form_ik`` has already merged duplicates, modulo ``2 pi``).

When only the solution nearest to ``near`` is asked for, the candidates go through FK
nearest first and the first that reproduces the target is the answer. Steps 1, 2 and 4
run in one compiled loop over the poses (numba), which also calls the case solver
(:func:`armkit.ik.closed_form.pose_candidates`): a few microseconds per pose, one pose
or a million; only the rare refinement and singular poses go through Python.

Chains without a closed form, and targets with a task ``mask``, go to the numeric
solver (:func:`armkit.ik.numeric.numeric_ik`) seeded from ``near``.

Distance used for ``near``: the weighted Euclidean norm ``|w * (q - near)|`` of the joint
differences in radians and metres (weights ``w`` default 1), after the ``2 pi`` wrap.
"""

from __future__ import annotations

import math
import threading
from collections.abc import Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numba import njit
from numpy.typing import ArrayLike, NDArray

from armkit._jit import entry_point
from armkit.chain import LIMIT_TOLERANCE, Chain
from armkit.errors import InputError, JointLimitError, NoClosedFormError, UnreachableError
from armkit.ik.closed_form import ClosedFormSolver, pose_candidates, solver_or_reason
from armkit.ik.numeric import numeric_ik, wrap_angle_into_limits, wrap_into_limits
from armkit.kinematics import chain_pose, fk, geometric_jacobian
from armkit.spatial.transforms import check_transform

__all__ = ["VERIFY_TOLERANCE", "IKSolutions", "IKSolutionsBatch", "ik", "ik_solutions"]

#: Position [m] and angle [rad] within which every returned solution reproduces the target.
VERIFY_TOLERANCE = 1e-9
#: Candidates with a larger FK residual [m or rad] are refined by Newton steps.
_REFINE_ABOVE = 1e-10
#: A refinement may move a candidate by at most this [rad or m] (it must stay on its branch).
_REFINE_MAX_MOVE = 1e-6
#: Budget of the search for the closest pose when a target is out of reach.
_CLOSEST_POSE_RESTARTS = 20
#: Steps along a singular family towards ``near`` (one where the family is a line in joint space).
_FAMILY_STEPS = 10
#: Singular values below this fraction of the largest span a family's directions.
_NULL_SPACE = 1e-8
#: Points sampled along a family's line (two whole turns of its fastest joint).
_FAMILY_SAMPLES = 257


@dataclass(frozen=True)
class IKSolutions:
    """Every closed-form solution of one target pose, with a flag per solution.

    Attributes
    ----------
    q : ndarray, shape (k, n)
        Solutions [rad or m], wrapped into the limits where a ``2 pi`` shift makes them fit,
        sorted by distance to ``near``.
    within_limits : ndarray, shape (k,), bool
        Whether each solution lies inside every joint limit.
    family : ndarray, shape (k,), bool
        Whether the solution is a representative of a one-parameter family (a wrist,
        shoulder or elbow singularity, where only a sum of joint angles is defined).
    position_error : ndarray, shape (k,)
        FK residual [m] of each solution: distance from the target position.
    orientation_error : ndarray, shape (k,)
        FK residual [rad] of each solution: angle from the target orientation.
    """

    q: NDArray[np.float64]
    within_limits: NDArray[np.bool_]
    family: NDArray[np.bool_]
    position_error: NDArray[np.float64]
    orientation_error: NDArray[np.float64]


@dataclass(frozen=True)
class IKSolutionsBatch(Sequence[IKSolutions]):
    """The solutions of ``N`` target poses as padded arrays; ``batch[i]`` is pose ``i``'s.

    Attributes
    ----------
    q : ndarray, shape (N, k_max, n)
        Per pose, its ``counts[i]`` solutions first (nearest to ``near`` first), then padding.
    counts : ndarray, shape (N,), int
        Number of solutions of each pose (0: out of reach).
    within_limits, family : ndarray, shape (N, k_max), bool
    position_error, orientation_error : ndarray, shape (N, k_max)
        As in :class:`IKSolutions`; padding entries are meaningless.

    Examples
    --------
    >>> import armkit
    >>> robot = armkit.load("ur5")
    >>> found = ik_solutions(robot.chain, robot.fk(robot.random_q(3, rng=0)))
    >>> len(found), found.q.shape, found[0].q.shape == (found.counts[0], 6)
    (3, (3, 8, 6), True)
    """

    q: NDArray[np.float64]
    counts: NDArray[np.int_]
    within_limits: NDArray[np.bool_]
    family: NDArray[np.bool_]
    position_error: NDArray[np.float64]
    orientation_error: NDArray[np.float64]

    def __len__(self) -> int:
        return len(self.q)

    def __getitem__(self, i):  # type: ignore[override]  # int -> IKSolutions, slice -> list
        if isinstance(i, slice):
            return [self[j] for j in range(*i.indices(len(self)))]
        k = self.counts[i]
        return IKSolutions(self.q[i, :k], self.within_limits[i, :k], self.family[i, :k],
                           self.position_error[i, :k], self.orientation_error[i, :k])


@njit(cache=True)
def _residual(T_target, F):
    """FK residual of a candidate's pose ``F`` to ``T_target``: position [m], angle [rad].

    The angle is ``atan2(|v|, trace(X) - 1)`` of ``X = R_target^T R`` (``v`` the vector of
    its skew part, ``2 sin(angle) axis``), as in
    :func:`~armkit.spatial.rotations.rotation_angle_between`: accurate to rounding from 0
    to ``pi``. ``X - I = R_target^T (R - R_target)`` keeps the digits of small angles.
    """
    position = math.sqrt((F[0, 3] - T_target[0, 3]) ** 2 + (F[1, 3] - T_target[1, 3]) ** 2
                         + (F[2, 3] - T_target[2, 3]) ** 2)
    trace = v0 = v1 = v2 = 0.0  # of X - I, and the vector of its skew part
    for c in range(3):
        D0, D1, D2 = F[c, 0] - T_target[c, 0], F[c, 1] - T_target[c, 1], F[c, 2] - T_target[c, 2]
        R0, R1, R2 = T_target[c, 0], T_target[c, 1], T_target[c, 2]
        trace += R0 * D0 + R1 * D1 + R2 * D2
        v0 += R2 * D1 - R1 * D2
        v1 += R0 * D2 - R2 * D0
        v2 += R1 * D0 - R0 * D1
    return position, math.atan2(math.sqrt(v0 * v0 + v1 * v1 + v2 * v2), 2.0 + trace)


class _Found(NamedTuple):
    """Per pose ``(N, k)`` candidates, sorted by :func:`_rank_pose`: ``q`` ``(N, k, n)``,
    ``valid`` (a solution of the closed form), ``keep`` (also reproduces the pose to
    ``VERIFY_TOLERANCE``), ``inside`` (the limits), ``family`` (as the closed form flags
    it: report ``family & keep``), the FK residuals, and ``count`` ``(N,)``: how many are
    usable (kept, and inside if asked), sorted first."""

    q: NDArray[np.float64]
    valid: NDArray[np.bool_]
    keep: NDArray[np.bool_]
    inside: NDArray[np.bool_]
    family: NDArray[np.bool_]
    position_error: NDArray[np.float64]
    orientation_error: NDArray[np.float64]
    count: NDArray[np.int64]

    @classmethod
    def empty(cls, N: int, k: int, n: int) -> _Found:
        return cls(np.empty((N, k, n)), *(np.empty((N, k), dtype=bool) for _ in range(4)),
                   np.empty((N, k)), np.empty((N, k)), np.empty(N, dtype=np.int64))


@njit(cache=True)
def _inside_and_distance(q, near, weights, lower, upper):
    """Whether ``q`` is inside the limits (to ``LIMIT_TOLERANCE``), and ``|w * (q - near)|``."""
    inside, total = True, 0.0
    for j in range(q.shape[0]):
        inside = inside and lower[j] - LIMIT_TOLERANCE <= q[j] <= upper[j] + LIMIT_TOLERANCE
        total += (weights[j] * (q[j] - near[j])) ** 2
    return inside, math.sqrt(total)


@njit(cache=True)
def _rank_pose(found, i, near, weights, lower, upper, within_limits):
    """Flag pose ``i``'s candidates (``keep``, ``inside``), count the usable ones (``keep``,
    and ``inside`` if ``within_limits``) and sort them first, nearest to ``near`` first."""
    k, n = found.q.shape[1:]
    distance = np.empty(k)
    count = 0
    for s in range(k):
        found.keep[i, s] = found.valid[i, s] and found.position_error[i, s] <= VERIFY_TOLERANCE \
            and found.orientation_error[i, s] <= VERIFY_TOLERANCE
        inside, distance[s] = _inside_and_distance(found.q[i, s], near, weights, lower, upper)
        found.inside[i, s] = inside
        usable = found.keep[i, s] and (inside or not within_limits)
        if not usable:
            distance[s] = np.inf
        count += usable
    found.count[i] = count
    order = _stable_order(distance)
    # the rows in that order, through copies (loops: slice assignments cost seconds of compile time)
    errors, flags, q = np.empty((2, k)), np.empty((4, k), dtype=np.bool_), np.empty((k, n))
    for s in range(k):
        r = order[s]
        errors[0, s], errors[1, s] = found.position_error[i, r], found.orientation_error[i, r]
        flags[0, s], flags[1, s] = found.valid[i, r], found.keep[i, r]
        flags[2, s], flags[3, s] = found.inside[i, r], found.family[i, r]
        for j in range(n):
            q[s, j] = found.q[i, r, j]
    for s in range(k):
        found.position_error[i, s], found.orientation_error[i, s] = errors[0, s], errors[1, s]
        found.valid[i, s], found.keep[i, s] = flags[0, s], flags[1, s]
        found.inside[i, s], found.family[i, s] = flags[2, s], flags[3, s]
        for j in range(n):
            found.q[i, s, j] = q[s, j]


@njit(cache=True)
def _stable_order(values):
    """Indices that sort ``values`` (a few entries), equal ones in their original order.

    An insertion sort: for at most 8 candidates it is as fast as ``np.argsort`` and saves
    numba about 2 s of compile time.
    """
    order = np.arange(values.size)
    for a in range(1, values.size):
        current = order[a]
        b = a
        while b > 0 and values[order[b - 1]] > values[current]:
            order[b] = order[b - 1]
            b -= 1
        order[b] = current
    return order


@njit(cache=True)
def _verify(d, T, q, found, i, s):
    """FK residuals of candidate ``s`` of pose ``i`` into ``found``; whether it is rough
    (above ``_REFINE_ABOVE``, to be refined) and whether it is kept."""
    F = np.empty((4, 4))
    chain_pose(d.T_between, d.prismatic, q, F)
    position, angle = _residual(T, F)
    found.position_error[i, s], found.orientation_error[i, s] = position, angle
    rough = position > _REFINE_ABOVE or angle > _REFINE_ABOVE
    return rough, position <= VERIFY_TOLERANCE and angle <= VERIFY_TOLERANCE


@njit(cache=True)
def _solve_batch(g, d, T, near, weights, lower, upper, within_limits, nearest, found):
    """Candidates of every pose, wrapped into the limits (reference ``near``), with their
    FK residuals, ranked: into ``found`` (see :class:`_Found`). Returns the number of
    valid candidates whose residual is above ``_REFINE_ABOVE``, the number of kept
    family representatives and the number of poses without a usable candidate.

    ``nearest``: only the nearest candidate that reproduces the pose is wanted, so the
    candidates are put through FK nearest first until one does (the others' residuals
    are NaN: not kept); family representatives always are (the caller moves them along
    their family towards ``near``), and if none does, all are (the caller's error message
    needs them).
    """
    k, n = found.q.shape[1:]
    rough = families = empty = 0
    distance = np.empty(k)
    for i in range(T.shape[0]):
        pose_candidates(g, d, T[i], found.q[i], found.valid[i], found.family[i])
        for s in range(k):
            q = found.q[i, s]
            found.position_error[i, s] = found.orientation_error[i, s] = np.nan
            distance[s] = np.inf
            if not found.valid[i, s]:
                for j in range(n):
                    q[j] = 0.0
                continue
            for j in range(n):
                if not d.prismatic[j]:
                    q[j] = wrap_angle_into_limits(q[j], lower[j], upper[j], near[i, j])
            if nearest:
                inside, gap = _inside_and_distance(q, near[i], weights, lower, upper)
                distance[s] = gap if inside or not within_limits else np.inf
            else:
                rough += _verify(d, T[i], q, found, i, s)[0]
        if nearest:
            kept = False
            for s in _stable_order(distance):
                if kept or distance[s] == np.inf:
                    break
                is_rough, kept = _verify(d, T[i], found.q[i, s], found, i, s)
                rough += is_rough
            for s in range(k):
                # a family's representative may be far from near while a member of it is not,
                # and none usable: verify the rest, to tell out of reach from out of limits
                if (found.family[i, s] or not kept) and found.valid[i, s] \
                        and np.isnan(found.position_error[i, s]):
                    rough += _verify(d, T[i], found.q[i, s], found, i, s)[0]
        _rank_pose(found, i, near[i], weights, lower, upper, within_limits)
        empty += found.count[i] == 0
        for s in range(k):
            families += found.family[i, s] and found.keep[i, s]
    return rough, families, empty


def _refine(chain: Chain, found: _Found, T_target: NDArray[np.float64]) -> NDArray[np.int_]:
    """Newton-refine (in place) the candidates whose residual is above ``_REFINE_ABOVE``;
    the poses touched (to be ranked again)."""
    rough = found.valid & ((found.position_error > _REFINE_ABOVE) | (found.orientation_error > _REFINE_ABOVE))
    for index in zip(*np.nonzero(rough), strict=True):
        q = found.q[index]
        result = numeric_ik(chain, T_target[index[0]], q0=q, max_iterations=8, max_restarts=0,
                            position_tolerance=1e-13, orientation_tolerance=1e-13,
                            respect_limits=False)
        better = (result.position_error + result.orientation_error
                  < found.position_error[index] + found.orientation_error[index])
        if better and np.abs(result.q - q).max() < _REFINE_MAX_MOVE:
            found.q[index] = result.q
            found.position_error[index] = result.position_error
            found.orientation_error[index] = result.orientation_error
    return np.flatnonzero(rough.any(axis=1))


_one_pose = threading.local()  # per thread: _Found buffers for one pose, constant inputs


def _candidates(solver: ClosedFormSolver, T: NDArray[np.float64], near: NDArray[np.float64],
                weights: NDArray[np.float64], within_limits: bool = False, nearest: bool = False,
                reuse: bool = False) -> tuple[_Found, int]:
    """The verified closed-form solutions of the targets ``T`` ``(N, 4, 4)``, nearest first.

    Per pose, the usable candidates (``keep``; with ``within_limits`` only those also
    ``inside``) come first, nearest to ``near`` first (see :class:`_Found`); ``count``
    is zero for a pose without any; the second value is the number of such poses.
    ``nearest``: only the first is wanted (see :func:`_solve_batch`). ``reuse``: for one
    pose, fill this thread's buffers (the caller copies what it returns) instead of
    allocating eight arrays.
    """
    chain = solver.chain
    shape = (len(T), solver.data.k, chain.n)
    if reuse and len(T) == 1:
        buffers = _one_pose.__dict__
        found = buffers.get(shape) or buffers.setdefault(shape, _Found.empty(*shape))
    else:
        found = _Found.empty(*shape)
    lower, upper = chain.lower, chain.upper
    args = (solver.geometry, solver.data, T, near, weights, lower, upper, within_limits, nearest, found)
    # compiled once per chain (kept with it): later calls skip numba's per-call dispatch
    loop = chain.derived("ik_solve_loop", lambda: entry_point(_solve_batch, *args))
    rough, families, empty = loop(*args)
    touched = set(_refine(chain, found, T).tolist()) if rough else set()
    if families or rough:  # singular poses: the members of each family nearest to near
        touched.update(_nearest_family_members(chain, found, T, near, weights))
    for i in sorted(touched):
        _rank_pose(found, i, near[i], weights, lower, upper, within_limits)
    if touched:
        empty = int((found.count == 0).sum())
    return found, empty


def _nearest_family_members(chain: Chain, found: _Found, T: NDArray[np.float64], near: NDArray[np.float64],
                            weights: NDArray[np.float64]) -> set[int]:
    """Move each kept family representative (in place) to the member of its family nearest
    to ``near``; the poses touched (to be ranked again).

    At a singular pose the closed form returns one member of a one-parameter family (e.g.
    ``q4 = 0`` for an aligned wrist, where only ``q4 + q6`` is defined). The family runs
    along the null space of the Jacobian: first the point of that line (a whole turn
    either way) nearest to ``near`` after the ``2 pi`` wrap into the limits, then steps
    along the null space (weighted by ``weights``), each put back exactly on the solution
    set by Newton steps, while the distance falls. A move that would leave the limits a
    representative was inside is not taken.
    """
    poses = set()
    for i, s in zip(*np.nonzero(found.family & found.keep), strict=True):
        q = _walk_family(chain, T[i], found.q[i, s], near[i], weights)
        if not np.array_equal(q, found.q[i, s]):
            found.q[i, s] = q
            found.position_error[i, s], found.orientation_error[i, s] = _residual(T[i], fk(chain, q))
            poses.add(int(i))
    return poses


def _walk_family(chain: Chain, T: NDArray[np.float64], q: NDArray[np.float64], near: NDArray[np.float64],
                 weights: NDArray[np.float64]) -> NDArray[np.float64]:
    """The member of ``q``'s family of solutions nearest to ``near`` (see above)."""
    w2 = weights**2
    inside = bool(chain.within_limits(q))

    def distance(candidates: NDArray[np.float64]) -> NDArray[np.float64]:
        """Weighted squared distance to near after the wrap, infinite where the limits are left."""
        moved = wrap_into_limits(chain, candidates, near)
        far = np.sum(w2 * (moved - near) ** 2, axis=-1)
        return np.where(chain.within_limits(moved) | (not inside), far, np.inf)

    for step in range(_FAMILY_STEPS):
        _, S, Vt = np.linalg.svd(geometric_jacobian(chain, q))
        N = Vt[len(S) - np.count_nonzero(S <= _NULL_SPACE * S[0]):].T  # (n, k) null-space basis
        if N.shape[1] == 0:
            break
        if step == 0 and N.shape[1] == 1:  # the line through q, up to a whole turn of any joint
            v = N[:, 0] / np.abs(N[:, 0]).max()
            line = q + np.linspace(-2 * np.pi, 2 * np.pi, _FAMILY_SAMPLES)[:, None] * v
            target = line[np.argmin(distance(line))]
        else:
            step_to_near = N @ np.linalg.solve(N.T @ (w2[:, None] * N), N.T @ (w2 * (near - q)))
            target = q + step_to_near
        result = numeric_ik(chain, T, q0=target, respect_limits=False, max_restarts=0,
                            max_iterations=10, position_tolerance=1e-13, orientation_tolerance=1e-13)
        if not (result.success and distance(result.q) < distance(q) - 1e-24):
            if step == 0 and N.shape[1] == 1:
                continue  # the sampled point did not help: go on with local steps
            break
        q = wrap_into_limits(chain, result.q, near)
    return q


def _angle_text(angle: float) -> str:
    return f"{angle:.3g} rad ({np.degrees(angle):.3g} deg)"


def _unreachable(chain: Chain, T: NDArray[np.float64], seed: NDArray[np.float64],
                 label: str) -> UnreachableError:
    closest = numeric_ik(chain, T, q0=seed, respect_limits=False,
                         max_restarts=_CLOSEST_POSE_RESTARTS, rng=0)
    return UnreachableError(
        f"{label}the target pose is out of reach: the closest pose found is "
        f"{closest.position_error:.3g} m and {_angle_text(closest.orientation_error)} away",
        closest.position_error, closest.orientation_error)


def _outside_limits(chain: Chain, q: NDArray[np.float64], label: str) -> JointLimitError:
    lower, upper = chain.lower, chain.upper
    bad = [f"{j.name} = {v:.4g} not in [{lo:.4g}, {hi:.4g}]"
           for j, v, lo, hi in zip(chain.joints, q, lower, upper, strict=True)
           if not lo - LIMIT_TOLERANCE <= v <= hi + LIMIT_TOLERANCE]
    return JointLimitError(
        f"{label}the target pose is reachable, but only outside the joint limits (e.g. "
        f"{', '.join(bad)}): ask for solutions outside the limits with within_limits=False or "
        f"'armkit ik --outside'")


def _constant(make, shape):
    """``make(shape)``, made once per thread and shape (the kernels only read it)."""
    cache = _one_pose.__dict__
    key = (make, shape)
    return cache.get(key) if key in cache else cache.setdefault(key, make(shape))


def _check_inputs(chain: Chain, T_base_tool: ArrayLike, near: ArrayLike | None,
                  weights: ArrayLike | None) -> tuple[NDArray, NDArray, NDArray, tuple[int, ...]]:
    """Targets ``(N, 4, 4)``, references ``(N, n)`` and weights ``(n,)``, all writable
    C-contiguous float64 (the one set of types the compiled loop is compiled for), and the
    batch shape."""
    T = check_transform(T_base_tool, "target pose")
    batch = T.shape[:-2]
    T = np.require(T.reshape(-1, 4, 4), requirements="CW")
    n = chain.n
    if near is None:
        near = np.zeros((len(T), n)) if len(T) > 1 else _constant(np.zeros, (1, n))
    else:
        near = np.asarray(near, dtype=float)
        if near.ndim == 0 or near.shape[-1] != n or not np.isfinite(near).all():
            raise InputError(f"near: expected {n} finite joint values (shape (..., {n})), "
                             f"got {near.tolist()}")
        try:
            near = np.require(np.broadcast_to(near, (*batch, n)).reshape(-1, n), requirements="CW")
        except ValueError as exc:
            raise InputError(f"near: shape {near.shape} does not match {len(T)} target poses") from exc
    if weights is None:
        return T, near, _constant(np.ones, n), batch
    weights = np.asarray(weights, dtype=float)
    if weights.shape != (n,) or not np.all(np.isfinite(weights) & (weights > 0)):
        raise InputError(f"weights: expected {n} positive numbers, got {weights.tolist()}")
    return T, near, np.require(weights, requirements="CW"), batch


def ik_solutions(chain: Chain, T_base_tool: ArrayLike, *, near: ArrayLike | None = None,
                 weights: ArrayLike | None = None) -> IKSolutions | IKSolutionsBatch:
    """Every closed-form solution of a target pose, inside the limits or not, with flags.

    Parameters
    ----------
    chain : Chain
    T_base_tool : array_like, shape (4, 4) or (N, 4, 4)
        Target tool pose(s) [m].
    near : array_like, shape (n,) or (N, n), optional
        Reference configuration [rad or m] for the ``2 pi`` wrap and the sort order;
        default zeros.
    weights : array_like, shape (n,), optional
        Per-joint weights of the distance to ``near``; default ones.

    Returns
    -------
    IKSolutions, or for a batch of poses an IKSolutionsBatch (a sequence of them)
        Empty (``k = 0``) when the pose is out of reach.

    Raises
    ------
    InputError
        If a target is not a rigid transform or contains NaN.
    NoClosedFormError
        If the chain has no closed-form solution.

    Examples
    --------
    >>> import armkit
    >>> from armkit.ik import ik_solutions
    >>> robot = armkit.load("probot-anno")
    >>> found = ik_solutions(robot.chain, robot.fk([0.927, -0.687, -0.396, 0, 1.083, 0.927]))
    >>> len(found.q), int(found.within_limits.sum()), bool(found.position_error.max() < 1e-12)
    (8, 4, True)
    """
    T, near, weights, batch = _check_inputs(chain, T_base_tool, near, weights)
    solver = solver_or_reason(chain)
    if isinstance(solver, NoClosedFormError):
        raise solver
    c, _ = _candidates(solver, T, near, weights)
    found = IKSolutionsBatch(c.q, c.keep.sum(axis=1), c.inside, c.family & c.keep, c.position_error,
                             c.orientation_error)
    return found if batch else found[0]


def _numeric_one(chain: Chain, T: NDArray[np.float64], seed: NDArray[np.float64],
                 within_limits: bool, label: str, options: dict) -> NDArray[np.float64]:
    result = numeric_ik(chain, T, q0=seed, respect_limits=within_limits, **options)
    if result.success:
        return wrap_into_limits(chain, result.q, seed)
    if within_limits:
        outside = numeric_ik(chain, T, q0=seed, respect_limits=False, **options)
        if outside.success:
            raise _outside_limits(chain, wrap_into_limits(chain, outside.q, seed), label)
    hint = ""
    if chain.n < 6 and "mask" not in options:
        hint = (f" (an arm with {chain.n} joints reaches only a {chain.n}-dimensional set of poses, so a "
                f"rounded pose misses it: ask for the position only, mask=[1, 1, 1, 0, 0, 0] or "
                f"'armkit ik --position')")
    raise UnreachableError(
        f"{label}no solution found by numeric IK within its budget ({result.restarts + 1} "
        f"attempts): the closest pose found is {result.position_error:.3g} m and "
        f"{_angle_text(result.orientation_error)} away; the target is probably out of reach{hint}",
        result.position_error, result.orientation_error)


def ik(chain: Chain, T_base_tool: ArrayLike, *, all: bool = False,
       near: ArrayLike | None = None, within_limits: bool = True,
       weights: ArrayLike | None = None,
       **numeric_options) -> NDArray[np.float64] | list[NDArray[np.float64]]:
    """Inverse kinematics: every solution, or the one closest to ``near``.

    Parameters
    ----------
    chain : Chain
    T_base_tool : array_like, shape (4, 4) or (N, 4, 4)
        Target tool pose(s) [m].
    all : bool
        Return every closed-form solution (sorted by distance to ``near``) instead of one.
    near : array_like, shape (n,) or (N, n), optional
        Reference configuration [rad or m], default zeros: the solution closest to it is
        returned (closed form), or the numeric solver starts from it.
    within_limits : bool
        Only solutions inside the joint limits (default). ``False``: any solution.
    weights : array_like, shape (n,), optional
        Per-joint weights of the distance to ``near`` (default ones).
    **numeric_options
        Passed to :func:`armkit.ik.numeric.numeric_ik` (``position_tolerance``, ``mask``,
        ``max_restarts``, ``time_budget``, ``rng``, ...). A ``mask`` selects the numeric
        solver even for chains with a closed form.

    Returns
    -------
    ndarray
        ``all=False``: shape ``(n,)`` for one pose, ``(N, n)`` for ``N`` poses.
        ``all=True``: shape ``(k, n)`` for one pose; a list of them for ``N`` poses.

    Raises
    ------
    InputError
        If a target is not a rigid transform, contains NaN, or ``near`` has a wrong shape.
    UnreachableError
        If a target is out of reach; the message says how far the closest pose found is.
    JointLimitError
        If a target is reachable only outside the joint limits (and ``within_limits``).
    NoClosedFormError
        If ``all=True`` is asked of a chain without a closed-form solution.

    Examples
    --------
    >>> import armkit
    >>> robot = armkit.load("puma560")
    >>> q = [0.1, -0.4, 0.3, 0.2, 0.5, -0.1]
    >>> bool(np.allclose(ik(robot.chain, robot.fk(q), near=q), q))
    True
    """
    T, near, weights, batch = _check_inputs(chain, T_base_tool, near, weights)
    solver = solver_or_reason(chain)
    closed = "mask" not in numeric_options and not isinstance(solver, NoClosedFormError)
    if all and not closed:
        reason = ("a task mask needs the numeric solver" if "mask" in numeric_options
                  else str(solver))
        raise NoClosedFormError(
            f"all=True asks for every solution, but {reason}; numeric IK returns one "
            f"solution per seed: solve once per seed configuration, near=q_seed or "
            f"'armkit ik --near Q...'")
    labels = _Labels(len(T) if batch else 0)
    if not closed:
        q = np.stack([_numeric_one(chain, T[i], near[i], within_limits, labels[i], numeric_options)
                      for i in range(len(T))])
        return q.reshape(*batch, chain.n)
    c, empty = _candidates(solver, T, near, weights, within_limits, nearest=not all, reuse=not batch)
    if empty:
        _raise_if_unusable(chain, c, T, near, labels)
    if not batch:  # c holds this thread's buffers: copy
        return c.q[0, :c.count[0]].copy() if all else c.q[0, 0].copy()
    if not all:
        return c.q[:, 0].reshape(*batch, chain.n)
    return [q[:k] for q, k in zip(c.q, c.count.tolist(), strict=True)]


class _Labels:
    """``labels[i]``: ``"pose i of N: "`` to start an error message about pose ``i`` of a batch."""

    def __init__(self, size: int, index: NDArray[np.int_] | None = None) -> None:
        self.size, self.index = size, index

    def __getitem__(self, i: int) -> str:
        i = i if self.index is None else int(self.index[i])
        return f"pose {i} of {self.size}: " if self.size else ""

    def of(self, index: NDArray[np.int_]) -> _Labels:
        """The labels of the poses ``index`` of this batch."""
        return _Labels(self.size, index)


def _raise_if_unusable(chain: Chain, c: _Found, T: NDArray[np.float64],
                       near: NDArray[np.float64], labels: _Labels) -> None:
    """Raise for the first pose without a usable candidate."""
    for i in np.flatnonzero(c.count == 0):
        if c.keep[i].any():
            first = np.flatnonzero(c.keep[i])[0]
            raise _outside_limits(chain, c.q[i, first], labels[i])
        raise _unreachable(chain, T[i], near[i], labels[i])
