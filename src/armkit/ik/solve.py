"""The IK dispatcher behind :meth:`armkit.Robot.ik`: closed form where the geometry has one.

For a chain with a closed-form solution (see :mod:`armkit.ik.structure`) every candidate
of :func:`armkit.ik.closed_form.closed_form_ik` is

1. wrapped into the joint limits: a revolute angle is shifted by a multiple of ``2 pi``
   when that makes it fit (among several fitting shifts, the one closest to ``near``);
2. verified by forward kinematics: it must reproduce the target within
   :data:`VERIFY_TOLERANCE` (candidates above ``1e-10`` are first refined by a few
   Newton steps of the numeric solver, without leaving the solution's branch);
3. flagged inside or outside the limits and sorted by distance to ``near``
   (``closed_form_ik`` has already merged duplicates, modulo ``2 pi``).

When only the solution nearest to ``near`` is asked for, the nearest candidate is
verified alone (and the pose gets the full treatment above if it is not accurate to
``1e-10``). Batches are solved ``CHUNK`` poses at a time, all in array operations.

Chains without a closed form, and targets with a task ``mask``, go to the numeric
solver (:func:`armkit.ik.numeric.numeric_ik`) seeded from ``near``.

Distance used for ``near``: the weighted Euclidean norm ``|w * (q - near)|`` of the joint
differences in radians and metres (weights ``w`` default 1), after the ``2 pi`` wrap.
"""

from __future__ import annotations

import weakref
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit.chain import LIMIT_TOLERANCE, Chain
from armkit.errors import InputError, JointLimitError, NoClosedFormError, UnreachableError
from armkit.ik.closed_form import CHUNK, ClosedFormSolver, closed_form_solver
from armkit.ik.numeric import numeric_ik, wrap_into_limits
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


_solvers: dict[int, tuple[weakref.ref, ClosedFormSolver | NoClosedFormError]] = {}


def _solver(chain: Chain) -> ClosedFormSolver | NoClosedFormError:
    """The chain's closed-form solver, or the error saying why it has none (memoised)."""
    entry = _solvers.get(id(chain))
    if entry is not None and entry[0]() is chain:
        return entry[1]
    try:
        solver = closed_form_solver(chain)
    except NoClosedFormError as exc:
        solver = exc
    key = id(chain)
    _solvers[key] = (weakref.ref(chain, lambda _ref, key=key: _solvers.pop(key, None)), solver)
    return solver


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


def _residuals(solver: ClosedFormSolver, q: NDArray[np.float64],
               T_target: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """FK residuals of candidates ``q`` ``(N, k, n)`` of targets ``(N, 4, 4)``: [m], [rad].

    The angle is ``atan2(|v|, trace(X) - 1)`` of ``X = R_target^T R`` (``v`` the vector of
    its skew part, ``2 sin(angle) axis``), as in
    :func:`~armkit.spatial.rotations.rotation_angle_between`: accurate to rounding from 0
    to ``pi``. ``X - I = R_target^T (R - R_target)`` comes from the FK differences, so
    small angles keep their digits; it is one batched product per target.
    """
    D = solver.pose_difference(q, T_target)  # (3, 4, k, N)
    position = np.sqrt(D[0, 3] ** 2 + D[1, 3] ** 2 + D[2, 3] ** 2)
    N = len(T_target)
    E = np.moveaxis(D[:, :3], -1, 0).reshape(N, 3, -1)  # (N, 3, 3 k): R - R_target per target
    X = np.matmul(np.swapaxes(T_target[:, :3, :3], -1, -2), E).reshape(N, 3, 3, -1)  # X - I
    trace_minus_1 = 2.0 + (X[:, 0, 0] + X[:, 1, 1] + X[:, 2, 2])
    v0, v1, v2 = X[:, 2, 1] - X[:, 1, 2], X[:, 0, 2] - X[:, 2, 0], X[:, 1, 0] - X[:, 0, 1]
    return position.T, np.arctan2(np.sqrt(v0 * v0 + v1 * v1 + v2 * v2), trace_minus_1)


def _refine(chain: Chain, q: NDArray[np.float64], T_target: NDArray[np.float64],
            position_error: NDArray[np.float64], orientation_error: NDArray[np.float64],
            candidates: NDArray[np.bool_]) -> None:
    """Newton-refine (in place) the candidates whose residual is above ``_REFINE_ABOVE``.

    ``q`` ``(N, k, n)`` and the residuals and ``candidates`` ``(N, k)`` belong to the
    targets ``T_target`` ``(N, 4, 4)``.
    """
    rough = candidates & ((position_error > _REFINE_ABOVE) | (orientation_error > _REFINE_ABOVE))
    for index in zip(*np.nonzero(rough), strict=True):
        result = numeric_ik(chain, T_target[index[0]], q0=q[index], max_iterations=8, max_restarts=0,
                            position_tolerance=1e-13, orientation_tolerance=1e-13,
                            respect_limits=False)
        moved = np.abs(result.q - q[index]).max()
        better = (result.position_error + result.orientation_error
                  < position_error[index] + orientation_error[index])
        if better and moved < _REFINE_MAX_MOVE:
            q[index] = result.q
            position_error[index] = result.position_error
            orientation_error[index] = result.orientation_error


def _candidates(solver: ClosedFormSolver, T: NDArray[np.float64], near: NDArray[np.float64],
                weights: NDArray[np.float64], within_limits: bool = False) -> dict[str, NDArray]:
    """The verified closed-form solutions of the targets ``T`` ``(N, 4, 4)``, nearest first.

    Returns arrays over ``(N, k)`` candidates, sorted per pose so that the verified ones
    (``keep``; with ``within_limits`` only those also ``inside``) come first, nearest to
    ``near`` first: ``q`` ``(N, k, n)``, ``keep``, ``inside``, ``family``,
    ``position_error``, ``orientation_error``. The poses are solved ``CHUNK`` at a time
    (the temporaries stay in the CPU cache).
    """
    parts = [_candidates_chunk(solver, T[i:i + CHUNK], near[i:i + CHUNK], weights, within_limits)
             for i in range(0, len(T), CHUNK)]
    if len(parts) == 1:
        return parts[0]
    return {key: np.concatenate([part[key] for part in parts]) for key in parts[0]}


def _candidates_chunk(solver: ClosedFormSolver, T: NDArray[np.float64], near: NDArray[np.float64],
                      weights: NDArray[np.float64], within_limits: bool) -> dict[str, NDArray]:
    chain = solver.chain
    q, valid, family = solver.candidates(T)
    q = wrap_into_limits(chain, q, near[:, None, :])
    valid &= np.isfinite(q).all(axis=-1)
    q[~valid] = 0.0
    position_error, orientation_error = _residuals(solver, q, T)
    _refine(chain, q, T, position_error, orientation_error, valid)
    keep = valid & (position_error <= VERIFY_TOLERANCE) & (orientation_error <= VERIFY_TOLERANCE)
    inside = chain.within_limits(q)
    first = keep & inside if within_limits else keep
    order = np.argsort(np.where(first, _distance(q, near, weights), np.inf), axis=1, kind="stable")
    out = {"q": q, "keep": keep, "inside": inside, "family": family & keep,
           "position_error": position_error, "orientation_error": orientation_error}
    rows = np.arange(len(order))[:, None]
    return {key: value[rows, order] for key, value in out.items()}


def _distance(q: NDArray[np.float64], near: NDArray[np.float64],
              weights: NDArray[np.float64]) -> NDArray[np.float64]:
    """``|w * (q - near)|`` for candidates ``(N, k, n)`` and references ``(N, n)``: ``(N, k)``."""
    d = weights * (q - near[:, None, :])
    return np.sqrt(np.einsum("...i,...i->...", d, d))


def _nearest(solver: ClosedFormSolver, T: NDArray[np.float64], near: NDArray[np.float64],
             weights: NDArray[np.float64], within_limits: bool
             ) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """For each target, the candidate nearest to ``near``, verified by FK: ``(N, n)``, ``ok``.

    Only the chosen candidate is put through FK. ``ok`` is False where no candidate is
    usable or the chosen one is not accurate to ``_REFINE_ABOVE``; the caller hands those
    poses to the full treatment (:func:`_candidates`: refinement, errors).
    """
    if len(T) > CHUNK:
        parts = [_nearest(solver, T[i:i + CHUNK], near[i:i + CHUNK], weights, within_limits)
                 for i in range(0, len(T), CHUNK)]
        return np.concatenate([q for q, _ in parts]), np.concatenate([ok for _, ok in parts])
    q, valid, _ = solver.candidates(T, merge=False)
    q = wrap_into_limits(solver.chain, q, near[:, None, :])
    usable = valid & np.isfinite(q).all(axis=-1)
    if within_limits:
        usable &= solver.chain.within_limits(q)
    distance = np.where(usable, _distance(q, near, weights), np.inf)
    best = np.argmin(distance, axis=1)
    q = np.take_along_axis(q, best[:, None, None], axis=1)
    found = usable.any(axis=1)
    q[~found] = 0.0
    position_error, orientation_error = _residuals(solver, q, T)
    ok = found & (position_error[:, 0] <= _REFINE_ABOVE) & (orientation_error[:, 0] <= _REFINE_ABOVE)
    return q[:, 0], ok


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


def _check_inputs(chain: Chain, T_base_tool: ArrayLike, near: ArrayLike | None,
                  weights: ArrayLike | None) -> tuple[NDArray, NDArray, NDArray, tuple[int, ...]]:
    T = check_transform(T_base_tool, "target pose")
    batch = T.shape[:-2]
    T = T.reshape(-1, 4, 4)
    if near is None:
        near = np.zeros(chain.n)
    near = np.asarray(near, dtype=float)
    if near.ndim == 0 or near.shape[-1] != chain.n or not np.all(np.isfinite(near)):
        raise InputError(f"near: expected {chain.n} finite joint values (shape (..., {chain.n})), "
                         f"got {near.tolist()}")
    try:
        near = np.broadcast_to(near, (*batch, chain.n)).reshape(-1, chain.n)
    except ValueError as exc:
        raise InputError(f"near: shape {near.shape} does not match {len(T)} target poses") from exc
    weights = np.ones(chain.n) if weights is None else np.asarray(weights, dtype=float)
    if weights.shape != (chain.n,) or not np.all(np.isfinite(weights) & (weights > 0)):
        raise InputError(f"weights: expected {chain.n} positive numbers, got {weights.tolist()}")
    return T, near, weights, batch


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
    solver = _solver(chain)
    if isinstance(solver, NoClosedFormError):
        raise solver
    c = _candidates(solver, T, near, weights)
    found = IKSolutionsBatch(c["q"], c["keep"].sum(axis=1), c["inside"], c["family"],
                             c["position_error"], c["orientation_error"])
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
    solver = _solver(chain)
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
    if not all:
        q, ok = _nearest(solver, T, near, weights, within_limits)
        if ok.all():
            return q.reshape(*batch, chain.n)
        rest = np.flatnonzero(~ok)
        c = _candidates(solver, T[rest], near[rest], weights, within_limits)
        _raise_if_unusable(chain, c, T[rest], near[rest], labels.of(rest), within_limits)
        q[rest] = c["q"][:, 0]
        return q.reshape(*batch, chain.n)
    c = _candidates(solver, T, near, weights, within_limits)
    count = _raise_if_unusable(chain, c, T, near, labels, within_limits)
    found = [q[:k] for q, k in zip(c["q"], count.tolist(), strict=True)]
    return found if batch else found[0]


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


def _raise_if_unusable(chain: Chain, c: dict[str, NDArray], T: NDArray[np.float64],
                       near: NDArray[np.float64], labels: _Labels, within_limits: bool
                       ) -> NDArray[np.int_]:
    """Number of usable (sorted-first) candidates per pose; raise for a pose without any."""
    usable = c["keep"] & c["inside"] if within_limits else c["keep"]
    count = usable.sum(axis=1)
    for i in np.flatnonzero(count == 0):
        if c["keep"][i].any():
            first = np.flatnonzero(c["keep"][i])[0]
            raise _outside_limits(chain, c["q"][i, first], labels[i])
        raise _unreachable(chain, T[i], near[i], labels[i])
    return count
