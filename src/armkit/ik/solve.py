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
from functools import cache
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit import _core
from armkit._deprecation import renamed_argument
from armkit._params import core_ready, float_array, thread_count
from armkit.chain import Chain, as_chain
from armkit.errors import InputError, NoClosedFormError, SolutionsLeftOffWarning, warn_at_caller
from armkit.ik.closed_form import ClosedFormSolver, solver_or_reason
from armkit.ik.messages import Labels, numeric_failure, outside_limits
from armkit.ik.numeric import numeric_ik, wrap_into_limits
from armkit.ik.pipeline import MAX_SOLUTIONS, Found, numeric_fallback, verified_solutions, with_turn_copies
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
    """Targets ``(N, 4, 4)``, references ``(N, n)`` / ``(n,)`` or None (zeros) and weights
    ``(n,)`` or None (ones), C-ordered float64 as the core takes them, and the batch shape.

    ``T_base_tool`` that already is a float64 C-ordered ``(..., 4, 4)`` array is checked by
    the core itself, in the same call that solves it (``unchecked``); anything else goes
    through :func:`armkit.spatial.check_transform` first.
    """

    __slots__ = ("T", "batch", "near", "weights", "unchecked", "given")

    def __init__(self, chain: Chain, T_base_tool: ArrayLike, near: ArrayLike | None,
                 weights: ArrayLike | None) -> None:
        T = T_base_tool
        self.given = T
        self.unchecked = core_ready(T, (4, 4))
        if not self.unchecked:
            T = np.ascontiguousarray(check_transform(T, "target pose"))
        self.batch = T.shape[:-2]
        self.T = T.reshape(-1, 4, 4)
        n = chain.n
        if near is not None:
            near = float_array(near, "near", f"{n} finite joint values (shape (..., {n}))")
            if near.ndim == 0 or near.shape[-1] != n or not np.isfinite(near).all():
                raise InputError(f"near: expected {n} finite joint values (shape (..., {n})), "
                                 f"got {near.tolist()}")
            if near.shape != (n,):
                try:
                    near = np.broadcast_to(near, (*self.batch, n)).reshape(-1, n)
                except ValueError as exc:
                    raise InputError(f"near: shape {near.shape} does not match {len(self.T)} target poses") \
                        from exc
            near = np.ascontiguousarray(near)
        self.near = near
        if weights is not None:
            weights = float_array(weights, "weights", f"{n} positive numbers")
            if weights.shape != (n,) or not np.all(np.isfinite(weights) & (weights > 0)):
                raise InputError(f"weights: expected {n} positive numbers, got {weights.tolist()}")
            weights = np.ascontiguousarray(weights)
        self.weights = weights

    def near_of(self, i: int) -> NDArray[np.float64] | None:
        """Pose ``i``'s reference configuration ``(n,)``, or None (zeros)."""
        return self.near if self.near is None or self.near.ndim == 1 else self.near[i]

    def near_rows(self, n: int) -> NDArray[np.float64]:
        """The reference configuration of every pose, ``(N, n)`` (a read-only view)."""
        return np.broadcast_to(np.zeros(n) if self.near is None else self.near, (len(self.T), n))

    def check(self) -> None:
        """Put the targets through :func:`armkit.spatial.check_transform` if not done yet: it
        raises for a non-rigid one, or replaces a nearly rigid one by the nearest rigid transform."""
        if self.unchecked:
            self.T = np.ascontiguousarray(check_transform(self.given, "target pose")).reshape(-1, 4, 4)
            self.unchecked = False

    def solve(self, solver: ClosedFormSolver, within_limits: bool = False, nearest: bool = False,
              threads: int = 0) -> tuple[Found, int]:
        """:func:`~armkit.ik.pipeline.verified_solutions` of these targets."""
        args = (self.near, self.weights, within_limits, nearest, threads)
        if self.unchecked:
            result = verified_solutions(solver, self.T, *args, rigid_tolerance=RIGID_TOLERANCE)
            if result is not None:
                return result
            self.check()  # not exactly rigid
        return verified_solutions(solver, self.T, *args)


def _listed(chain: Chain, targets: _Targets, found: Found, i: int, turn_copies: bool,
            left_off: list[float] | None = None) -> IKSolutions:
    """Pose ``i``'s usable solutions in ``found``, each inside the limits with its whole-turn
    copies there if ``turn_copies`` (:func:`~armkit.ik.pipeline.with_turn_copies`)."""
    k = int(found.count[i])
    q, inside, family = found.q[i, :k], found.inside[i, :k], found.family[i, :k]
    if not (turn_copies and chain.spans_turns and k):
        return IKSolutions(q, inside, family, found.position_error[i, :k], found.orientation_error[i, :k])
    source, q, errors = with_turn_copies(chain, targets.T[i], q, inside, targets.near_of(i), targets.weights,
                                         left_off=left_off)
    return IKSolutions(q, inside[source], family[source], errors[:, 0], errors[:, 1])


def _listed_batch(chain: Chain, targets: _Targets, found: Found, turn_copies: bool,
                  left_off: list[float] | None = None) -> list[IKSolutions]:
    """:func:`_listed` for every pose, refused as soon as one pose has so many whole-turn copies
    that the batch, padded to that pose's count as :class:`IKSolutionsBatch` is, would hold more
    than :data:`MAX_BATCH_ROWS` rows (before the memory is taken, not after)."""
    listed, widest, poses = [], 1, len(found.q)
    for i in range(poses):
        listed.append(_listed(chain, targets, found, i, turn_copies, left_off))
        widest = max(widest, len(listed[-1].q))
        if poses * widest > MAX_BATCH_ROWS:
            gigabytes = poses * widest * (chain.n + 3) * 8 / 1e9
            raise InputError(f"T_base_tool: {poses:,} poses whose whole-turn copies give up to {widest} "
                             f"solutions each (pose {i + 1}) would list {poses * widest:,} rows (about "
                             f"{gigabytes:.3g} GB), more than MAX_BATCH_ROWS = {MAX_BATCH_ROWS:,}; solve at "
                             f"most {MAX_BATCH_ROWS // widest:,} poses at a time, or pass turn_copies=False "
                             f"(each solution once, its copy nearest to near)")
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
    c, _ = targets.solve(solver, threads=threads)  # outside the limits too: the kept ones are counted
    if not targets.batch:
        return _listed(chain, targets, c, 0, turn_copies)
    if turn_copies and chain.spans_turns:
        left_off: list[float] = []
        listed = _listed_batch(chain, targets, c, True, left_off)
        if left_off:
            warn_at_caller(SolutionsLeftOffWarning(
                f"{len(left_off)} of {len(c.q)} poses have more solutions inside the limits than "
                f"MAX_SOLUTIONS = {MAX_SOLUTIONS} (up to {max(left_off):.0f}, whole-turn copies): the "
                f"{MAX_SOLUTIONS} nearest to near are listed for each"))
        return IKSolutionsBatch.stack(listed, chain.n)
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
    T = T_base_tool
    if (core_ready(T, (4, 4), exact=True) and not numeric_options
            and (near is None or core_ready(near, (chain.n,), exact=True))
            and (weights is None or core_ready(weights, (chain.n,), exact=True))):
        # one pose as float64 arrays: checked and solved in one core call (None: take the general path)
        solver = solver_or_reason(chain)
        if type(solver) is ClosedFormSolver:
            q = _core.solve_one(solver.core, T, near, weights, within_limits, not all_solutions,
                                RIGID_TOLERANCE)
            if q is not None:
                if all_solutions and turn_copies and chain.spans_turns:
                    inside = np.ones(len(q), dtype=bool) if within_limits else chain.within_limits(q)
                    return with_turn_copies(chain, T, q, inside, near, weights)[1]
                return q
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
    labels = Labels(len(targets.T) if batch else 0)
    if not closed:
        targets.check()
        near_rows = targets.near_rows(chain.n)
        q = np.stack([_numeric_one(chain, targets.T[i], near_rows[i], within_limits, labels[i],
                                   numeric_options) for i in range(len(targets.T))])
        return q.reshape(*batch, chain.n)
    c, empty = targets.solve(solver, within_limits, nearest=not all_solutions, threads=threads)
    if empty:
        numeric_fallback(chain, c, targets.T, targets.near_rows(chain.n), labels, within_limits)
    if not all_solutions:
        return c.q[0, 0] if not batch else c.q[:, 0].reshape(*batch, chain.n)
    listed = [solutions.q for solutions in _listed_batch(chain, targets, c, turn_copies)]
    return listed if batch else listed[0]
