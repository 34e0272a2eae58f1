"""The IK dispatcher behind :meth:`armkit.Robot.ik`: closed form where the geometry has one.

For a chain with a closed-form solution (see :mod:`armkit.ik.structure`) the targets go
through :func:`armkit.ik.pipeline.verified_solutions`: every candidate of the closed form
wrapped into the joint limits, verified by forward kinematics, at a singular pose moved
to the member of its family nearest to ``near``, flagged and sorted by distance to
``near``; one compiled call for any number of poses, split over threads. Chains without
a closed form, and targets with a task ``mask``, go to the numeric solver
(:func:`armkit.ik.numeric.numeric_ik`) seeded from ``near``. The errors raised for
targets without a usable solution are in :mod:`armkit.ik.messages`.

Distance used for ``near``: the weighted Euclidean norm ``|w * (q - near)|`` of the joint
differences in radians and metres (weights ``w`` default 1), after the ``2 pi`` wrap.
"""

from __future__ import annotations

import difflib
import inspect
import math
from functools import cache
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit import _core
from armkit._deprecation import renamed_argument
from armkit._params import float_array, thread_count
from armkit.chain import Chain, as_chain
from armkit.errors import InputError, NoClosedFormError, SolutionsLeftOffWarning, warn_at_caller
from armkit.ik.closed_form import solver_or_reason
from armkit.ik.messages import Labels, numeric_failure, outside_limits
from armkit.ik.numeric import numeric_ik, wrap_into_limits
from armkit.ik.pipeline import (
    MAX_SOLUTIONS,
    Found,
    left_off_warning,
    numeric_fallback,
    verified_solutions,
    with_turn_copies,
)
from armkit.ik.results import SOLUTION_TOLERANCE, IKSolutions, IKSolutionsBatch
from armkit.spatial.transforms import RIGID_TOLERANCE, check_transform

if TYPE_CHECKING:
    from armkit.robot import Robot

__all__ = ["MAX_BATCH_ROWS", "SOLUTION_TOLERANCE", "IKSolutions", "IKSolutionsBatch", "ik", "ik_solutions"]

#: Most solution rows a batch of poses lists with whole-turn copies (poses x the most rows of any
#: pose, as :class:`IKSolutionsBatch` pads them): 1e7 rows of a 6-joint arm are about 0.7 GB. A
#: UR5 at +-360 deg lists up to 512 per pose, so about 20,000 poses at a time.
MAX_BATCH_ROWS = 10_000_000


#: ``numeric_ik`` keywords that :func:`ik` sets itself (``q0`` is ``near``).
_SET_BY_IK = frozenset({"robot", "T_base_tool", "q0", "within_limits", "respect_limits"})


@cache
def _keywords() -> tuple[frozenset[str], frozenset[str]]:
    """The keywords :func:`ik` takes: its own, and the numeric options it passes on."""
    own = frozenset(name for name, p in inspect.signature(ik).parameters.items()
                    if p.kind is p.KEYWORD_ONLY)
    numeric = frozenset(inspect.signature(numeric_ik).parameters) - _SET_BY_IK
    return own, numeric


def _check_keywords(options: dict[str, object]) -> None:
    """Refuse a keyword neither :func:`ik` nor the numeric solver takes: a misspelled option
    (``nearr=``, ``positon_tolerance=``) would otherwise be ignored by the closed form."""
    own, numeric = _keywords()
    unknown = [name for name in options if name not in numeric]
    if not unknown:
        return
    valid = sorted(own | numeric)
    named = []
    for name in unknown:
        close = difflib.get_close_matches(name, valid, n=1)
        named.append(f"{name!r}" + (f" (did you mean {close[0]!r}?)" if close else ""))
    raise InputError(f"ik: unknown keyword argument{'s' if len(unknown) > 1 else ''} {', '.join(named)}; "
                     f"expected one of {', '.join(valid)}")


class _Targets:
    """Targets ``(..., 4, 4)``, references ``(N, n)`` / ``(n,)`` or None (zeros) and weights
    ``(n,)`` or None (ones), C-ordered float64 as the core takes them, and the batch shape.

    The one input check of the targets: an array the core takes as it is (C-ordered native
    float64) that is exactly rigid is used as it is (the core tests that in one pass);
    anything else goes through :func:`armkit.spatial.check_transform`, which raises for a
    non-rigid target or replaces a nearly rigid one by the nearest rigid transform.
    """

    __slots__ = ("T", "batch", "near", "weights")

    def __init__(self, chain: Chain, T_base_tool: ArrayLike, near: ArrayLike | None,
                 weights: ArrayLike | None) -> None:
        T = T_base_tool
        if not _core.exactly_rigid(T, RIGID_TOLERANCE):
            T = np.ascontiguousarray(check_transform(T, "target pose"))
        self.T = T
        self.batch = T.shape[:-2] if T.ndim > 2 else ()
        if near is not None:
            n = chain.n
            near = float_array(near, "near", f"{n} finite joint values (shape (..., {n}))")
            if near.ndim == 0 or near.shape[-1] != n or not np.isfinite(near).all():
                raise InputError(f"near: expected {n} finite joint values (shape (..., {n})), "
                                 f"got {near.tolist()}")
            if near.shape != (n,):
                try:
                    near = np.broadcast_to(near, (*self.batch, n)).reshape(-1, n)
                except ValueError as exc:
                    raise InputError(f"near: shape {near.shape} does not match {self.poses} target poses") \
                        from exc
            near = np.ascontiguousarray(near)
        self.near = near
        if weights is not None:
            n = chain.n
            weights = float_array(weights, "weights", f"{n} positive numbers")
            if weights.shape != (n,) or not np.all(np.isfinite(weights) & (weights > 0)):
                raise InputError(f"weights: expected {n} positive numbers, got {weights.tolist()}")
            weights = np.ascontiguousarray(weights)
        self.weights = weights

    @property
    def poses(self) -> int:
        """How many target poses (1 for one pose)."""
        return self.T.size // 16

    def near_rows(self, n: int) -> NDArray[np.float64]:
        """The reference configuration of every pose, ``(N, n)`` (a read-only view)."""
        return np.broadcast_to(np.zeros(n) if self.near is None else self.near, (self.poses, n))

    def with_turn_copies(self, chain: Chain, found: Found, threads: int = 0) -> Found:
        """``found``'s usable solutions with their whole-turn copies inside the limits
        (:func:`~armkit.ik.pipeline.with_turn_copies`, one core call), refused as soon as a batch
        padded to its longest listing, as :class:`IKSolutionsBatch` is, would hold more than
        :data:`MAX_BATCH_ROWS` rows (before the memory is taken, not after); copies left off
        (more than :data:`~armkit.ik.pipeline.MAX_SOLUTIONS` for a pose) warn once."""
        poses = self.poses
        listed, total = with_turn_copies(chain, found, self.near, self.weights,
                                         max_rows=MAX_BATCH_ROWS if self.batch else math.inf, threads=threads)
        if listed.q is None:
            running = np.maximum.accumulate(np.maximum(listed.count, 1))
            i = int(np.argmax(poses * running > MAX_BATCH_ROWS))
            widest = int(running[i])
            rows = poses * widest
            raise InputError(f"T_base_tool: {poses:,} poses whose whole-turn copies give up to {widest} "
                             f"solutions each (pose {i + 1}) would list {rows:,} rows (about "
                             f"{rows * (chain.n + 3) * 8 / 1e9:.3g} GB), more than MAX_BATCH_ROWS = "
                             f"{MAX_BATCH_ROWS:,}; solve at most {MAX_BATCH_ROWS // widest:,} poses at a "
                             f"time, or pass turn_copies=False (each solution once, its copy nearest to "
                             f"near)")
        left_off = total > listed.count
        if not left_off.any():
            return listed
        if not self.batch:
            warn_at_caller(left_off_warning(chain, int(listed.count[0]), float(total[0])))
        else:
            warn_at_caller(SolutionsLeftOffWarning(
                f"{int(left_off.sum())} of {poses} poses have more solutions inside the limits than "
                f"MAX_SOLUTIONS = {MAX_SOLUTIONS} (up to {total.max():.0f}, whole-turn copies): the "
                f"{MAX_SOLUTIONS} nearest to near are listed for each"))
        return listed


def ik_solutions(robot: Robot | Chain, T_base_tool: ArrayLike, *, near: ArrayLike | None = None,
                 weights: ArrayLike | None = None, turn_copies: bool = False,
                 threads: int | None = None) -> IKSolutions | IKSolutionsBatch:
    """Every closed-form solution of a target pose, inside the limits or not, with flags.

    Each solution is listed once (by default), the whole-turn copy nearest to ``near``; with
    ``turn_copies=True`` a solution inside the limits is listed with each of its whole-turn
    copies there (joints whose limits span more than a whole turn, e.g. a UR5's +-360 degrees:
    2^6 per solution; at most :data:`~armkit.ik.pipeline.MAX_SOLUTIONS`, see
    :mod:`armkit.ik.pipeline`), one outside the limits once. :func:`~armkit.ik.pipeline.count_turn_copies`
    counts the copies without listing them.

    Parameters
    ----------
    robot : Robot or Chain
        The arm (its :class:`~armkit.chain.Chain` is accepted too, see :func:`armkit.chain.as_chain`).
    T_base_tool : array_like, shape (4, 4) or (N, 4, 4)
        Target tool pose(s) [m].
    near : array_like, shape (n,) or (N, n), optional
        Reference configuration [rad or m] for the ``2 pi`` wrap and the sort order;
        default zeros.
    weights : array_like, shape (n,), optional
        Per-joint weights of the distance to ``near``; default ones.
    turn_copies : bool
        ``False`` (default): each solution once, the copy nearest to ``near``. ``True``: also
        list its whole-turn copies inside the limits (distinct configurations, same pose).
    threads : int, optional
        Threads a batch of poses is split over: ``None`` (default) all cores, else 1 to
        1024 (:func:`armkit._params.thread_count`); the answers do not depend on it.

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
    >>> found = ik_solutions(robot, robot.fk([0.927, -0.687, -0.396, 0, 1.083, 0.927]))
    >>> len(found.q), int(found.within_limits.sum()), bool(found.position_error.max() < 1e-12)
    (8, 4, True)
    """
    chain = as_chain(robot)
    threads = thread_count(threads)
    targets = _Targets(chain, T_base_tool, near, weights)
    solver = solver_or_reason(chain)
    if isinstance(solver, NoClosedFormError):
        raise solver
    # outside the limits too: the kept ones are counted
    q, errors, flags, count, _ = verified_solutions(solver, targets.T, targets.near, targets.weights, False,
                                                    False, threads)
    c = Found(q, errors, flags, count)
    if turn_copies and chain.spans_turns:
        c = targets.with_turn_copies(chain, c, threads)
    if not targets.batch:
        k = c.count[0]
        return IKSolutions(c.q[0, :k], c.inside[0, :k], c.family[0, :k] & c.keep[0, :k],
                           c.position_error[0, :k], c.orientation_error[0, :k])
    return IKSolutionsBatch(c.q, c.count, c.inside, c.family & c.keep, c.position_error, c.orientation_error)


def _numeric_one(chain: Chain, T: NDArray[np.float64], seed: NDArray[np.float64],
                 within_limits: bool, label: str, options: dict) -> NDArray[np.float64]:
    result = numeric_ik(chain, T, q0=seed, within_limits=within_limits, **options)
    if result.success:
        return wrap_into_limits(chain, result.q, seed)
    if within_limits:
        outside = numeric_ik(chain, T, q0=seed, within_limits=False, **options)
        if outside.success:
            raise outside_limits(chain, wrap_into_limits(chain, outside.q, seed), label)
    raise numeric_failure(chain, result, label, "mask" in options)


def ik(robot: Robot | Chain, T_base_tool: ArrayLike, *, all_solutions: bool = False,
       near: ArrayLike | None = None, within_limits: bool = True,
       weights: ArrayLike | None = None, turn_copies: bool = False, threads: int | None = None,
       **numeric_options) -> NDArray[np.float64] | list[NDArray[np.float64]]:
    """Inverse kinematics: every solution, or the one closest to ``near``.

    Parameters
    ----------
    robot : Robot or Chain
        The arm (its :class:`~armkit.chain.Chain` is accepted too).
    T_base_tool : array_like, shape (4, 4) or (N, 4, 4)
        Target tool pose(s) [m].
    all_solutions : bool
        Return every closed-form solution (sorted by distance to ``near``) instead of one,
        each once (``turn_copies=True`` adds the whole-turn copies, see :func:`ik_solutions`).
        (``all=`` is its deprecated old name, which shadowed the builtin; it warns.)
    near : array_like, shape (n,) or (N, n), optional
        Reference configuration [rad or m], default zeros: the solution closest to it is
        returned (closed form), or the numeric solver starts from it.
    within_limits : bool
        Only solutions inside the joint limits (default). ``False``: any solution.
    weights : array_like, shape (n,), optional
        Per-joint weights of the distance to ``near`` (default ones).
    turn_copies : bool
        With ``all_solutions``: also list the whole-turn copies inside the limits of joints
        whose limits span more than a whole turn; default ``False``, each solution once. The
        one nearest solution (``all_solutions=False``) is chosen among all copies either way.
    threads : int, optional
        Threads a batch of poses is split over: ``None`` (default) all cores, else 1 to
        1024 (:func:`armkit._params.thread_count`); the answers do not depend on it.
    **numeric_options
        Passed to :func:`armkit.ik.numeric.numeric_ik` (``position_tolerance``, ``mask``,
        ``max_restarts``, ``time_budget``, ``rng``, ...). A ``mask`` selects the numeric
        solver even for chains with a closed form.

    Returns
    -------
    ndarray
        ``all_solutions=False``: shape ``(n,)`` for one pose, ``(N, n)`` for ``N`` poses.
        ``all_solutions=True``: shape ``(k, n)`` for one pose; a list of them for ``N`` poses.

    Raises
    ------
    InputError
        If a target is not a rigid transform, contains NaN, ``near`` has a wrong shape, or a
        keyword is neither one of these nor a numeric option (a misspelling is not ignored).
    UnreachableError
        If a target is out of reach; the message says how far the closest pose found is.
    JointLimitError
        If a target is reachable only outside the joint limits (and ``within_limits``).
    NoClosedFormError
        If ``all_solutions=True`` is asked of a chain without a closed-form solution.

    Examples
    --------
    >>> import armkit
    >>> robot = armkit.load("puma560")
    >>> q = [0.1, -0.4, 0.3, 0.2, 0.5, -0.1]
    >>> bool(np.allclose(ik(robot, robot.fk(q), near=q), q))
    True
    """
    chain = as_chain(robot)
    threads = thread_count(threads)
    if numeric_options:
        if "all" in numeric_options:
            all_solutions = renamed_argument("ik", "all", "all_solutions", numeric_options.pop("all"),
                                             all_solutions, False)
        _check_keywords(numeric_options)
    targets = _Targets(chain, T_base_tool, near, weights)
    solver = solver_or_reason(chain)
    closed = "mask" not in numeric_options and not isinstance(solver, NoClosedFormError)
    if all_solutions and not closed:
        reason = ("a task mask needs the numeric solver" if "mask" in numeric_options
                  else str(solver))
        raise NoClosedFormError(
            f"all_solutions=True asks for every solution, but {reason}; numeric IK returns one "
            f"solution per seed: solve once per seed configuration, near=q_seed or "
            f"'armkit ik --near Q...'")
    batch = targets.batch
    if not closed:
        T, near_rows = targets.T.reshape(-1, 4, 4), targets.near_rows(chain.n)
        labels = Labels(targets.poses if batch else 0)
        q = np.stack([_numeric_one(chain, T[i], near_rows[i], within_limits, labels[i], numeric_options)
                      for i in range(len(T))])
        return q.reshape(*batch, chain.n)
    q, errors, flags, count, empty = verified_solutions(solver, targets.T, targets.near, targets.weights,
                                                        within_limits, not all_solutions, threads)
    if empty:  # in place: a pose the closed form misses but numeric IK reaches gets that solution
        numeric_fallback(chain, Found(q, errors, flags, count), targets.T.reshape(-1, 4, 4),
                         targets.near_rows(chain.n), Labels(targets.poses if batch else 0), within_limits)
    if not all_solutions:
        return q[:, 0].reshape(*batch, chain.n)
    if turn_copies and chain.spans_turns:
        q, _, _, count = targets.with_turn_copies(chain, Found(q, errors, flags, count), threads)
    if not batch:
        return q[0, :count[0]]
    return [rows[:k] for rows, k in zip(q, count.tolist(), strict=True)]
