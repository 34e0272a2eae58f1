"""Numeric inverse kinematics for any chain: Levenberg-Marquardt with random restarts.

The solver minimises ``E = 1/2 e^T W e`` where ``e = [p_target - p; log(R_target R^T)]``
is the pose error in the base frame (metres over radians, the rotation part a rotation
vector, :func:`armkit.kinematics.pose_error`) and ``W`` a diagonal 0/1 task mask. Each
step solves the damped normal equations of Sugihara's Levenberg-Marquardt method
(T. Sugihara, "Solvability-unconcerned inverse kinematics by the Levenberg-Marquardt
method", IEEE T-RO 27(5), 2011)::

    (J^T W J + (g E + damping) I) dq = J^T W e

whose damping grows with the error far from the target and nearly vanishes near it, so
the last steps converge quadratically (Sugihara uses ``g = 1``; ``g = 0.1`` needed the
fewest iterations on random Panda poses here). The floor ``damping = 1e-9`` is small on
purpose: with ``1e-6``, configurations whose Jacobian has a singular value near ``1e-3``
converged only linearly below ``1e-8`` and 0.3-1.7 % of random poses of the 6-joint built-ins
failed the ``1e-9`` tolerance; with ``1e-9`` none did. For ``m`` task rows and ``n >= m``
joints the same step is ``dq = J^T y`` with the ``m x m`` system ``(J J^T + lambda I) y = e``,
else the ``n x n`` one; either is solved by a Cholesky factorisation written out in the
compiled kernel.

Joint limits are kept during the iterations, as bounds: after each step a revolute angle
outside its range is moved into it by whole turns if that fits, else to the bound nearer
in angle (a prismatic value to the nearer bound), and a joint held at a bound by the
gradient (``J^T e`` pointing outwards) is left out of the next step (its Jacobian column
is zeroed), so the other joints take over instead of the step stalling against the
bound: an active set, so every answer is inside the limits. One seed iterates at a time, first
the caller's ``q0``: an attempt that has not halved its error in ``3`` steps, or has
used ``max_iterations`` steps, is abandoned for a new uniform random seed inside the
limits, until the restart or time budget runs out.

Each attempt runs as one call of compiled code (numba, :func:`_attempt`): the tool pose
and Jacobian from :func:`armkit.kinematics.chain_frames` / :func:`~armkit.kinematics.chain_jacobian`
(the kernels behind :class:`armkit.kinematics.ChainKernel`), the pose error from
:func:`armkit.kinematics.pose_error_into`, the projection, the active set and the solve,
about 1 us per step on a 7-joint arm (a Panda solve from a random seed: 20-30 us median).
Restarts, their random seeds (drawn from ``rng`` in Python, so results are reproducible)
and the time budget stay in Python between attempts. The first :class:`NumericIK` of a
process compiles the kernels, or loads them from numba's on-disk cache, before any time
budget starts (about 5 s the first time after installing, 0.2 s afterwards).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
from numba import njit, vectorize
from numpy.typing import ArrayLike, NDArray

from armkit.chain import LIMIT_TOLERANCE, Chain
from armkit.errors import InputError
from armkit.kinematics import chain_frames, chain_jacobian, pose_error_into

__all__ = ["IKResult", "NumericIK", "numeric_ik", "wrap_angle_into_limits", "wrap_into_limits"]

#: Range [m] used for random seeds of prismatic joints without limits.
_UNBOUNDED_SEED_RANGE = 1.0
_TWO_PI = 2.0 * math.pi
#: An attempt whose error has not fallen below _STALL_FACTOR times its best in
#: _STALL_STEPS steps is abandoned for a new seed.
_STALL_STEPS = 3
_STALL_FACTOR = 0.5
#: Damping, relative to trace(J^T J), of a step whose damped normal equations were not
#: positive definite (a singular Jacobian and ``damping = 0``). 1e-10 came closest to the
#: minimum-norm least-squares step on rank-deficient random Jacobians (about 1e-7 from it;
#: 1e-12 and 1e-8 were 1e-5 and 1e-6 away).
_SINGULAR_DAMPING = 1e-10


@dataclass(frozen=True)
class IKResult:
    """The outcome of a numeric IK solve.

    Attributes
    ----------
    q : ndarray, shape (n,)
        The best configuration found [rad or m]; inside the joint limits unless the solver
        was called with ``respect_limits=False``.
    success : bool
        Whether the masked position and orientation errors are within the tolerances.
    iterations : int
        Levenberg-Marquardt iterations over all attempts.
    restarts : int
        Attempts started from a random configuration after the first one.
    position_error : float
        Distance [m] between the target and the tool position at ``q`` (masked axes only).
    orientation_error : float
        Angle [rad] of the orientation error at ``q`` (masked axes only).
    """

    q: NDArray[np.float64]
    success: bool
    iterations: int
    restarts: int
    position_error: float
    orientation_error: float


def _check_mask(mask: ArrayLike | None) -> NDArray[np.bool_]:
    if mask is None:
        return np.ones(6, dtype=bool)
    m = np.asarray(mask, dtype=float)
    if m.shape != (6,) or not np.all((m == 0) | (m == 1)) or not m.any():
        raise InputError(f"mask: expected 6 values of 0 or 1 (x y z rx ry rz, at least one 1), "
                         f"got {np.asarray(mask).tolist()}")
    return m == 1


def _check_target(T_base_tool: ArrayLike) -> NDArray[np.float64]:
    try:
        T = np.array(T_base_tool, dtype=np.float64, order="C")  # writable: the compiled type
    except (TypeError, ValueError) as exc:
        raise InputError(f"T_base_tool: expected a 4x4 transform, got {T_base_tool!r}") from exc
    if T.shape != (4, 4) or not math.isfinite(T.sum()):
        raise InputError(f"T_base_tool: expected a finite 4x4 transform, got {T.tolist()}")
    return T


def wrap_into_limits(chain: Chain, q: ArrayLike, reference: ArrayLike) -> NDArray[np.float64]:
    """Shift revolute angles ``(..., n)`` by multiples of ``2 pi`` into the joint limits.

    Among several shifts that fit (limits wider than ``2 pi``) the one closest to
    ``reference`` ``(..., n)`` is taken; an angle that fits no shift is moved as close to
    ``reference`` as whole turns allow. Prismatic values are left alone.

    Examples
    --------
    >>> import armkit
    >>> panda = armkit.load("panda")   # joint 6 in [-0.0175, 3.7525]
    >>> float(wrap_into_limits(panda.chain, [0, 0, 0, -1, 0, -3.0, 0], 0.0)[5].round(4))
    3.2832
    """
    q = np.asarray(q, dtype=float)
    return np.where(chain.prismatic, q, wrap_angle_into_limits(q, chain.lower, chain.upper, reference))


@vectorize(["float64(float64, float64, float64, float64)"], cache=True)
def wrap_angle_into_limits(q: float, lower: float, upper: float, reference: float) -> float:
    """A revolute angle shifted by whole turns into ``[lower, upper]`` (a NumPy ufunc).

    Among several fitting shifts (limits wider than ``2 pi``) the one closest to
    ``reference``; an angle that fits no shift is moved as close to ``reference`` as
    whole turns allow. Every argument broadcasts; all in radians.

    >>> float(wrap_angle_into_limits(-3.0, -0.0175, 3.7525, 0.0).round(4))
    3.2832
    """
    low, high = lower - LIMIT_TOLERANCE, upper + LIMIT_TOLERANCE
    if low <= q <= high and high - low < _TWO_PI:  # fits, and no other shift can: the usual case
        return q
    turns_low = np.ceil((low - q) / _TWO_PI)
    turns_high = np.floor((high - q) / _TWO_PI)
    turns = np.rint((reference - q) / _TWO_PI)
    if turns_low <= turns_high:
        turns = min(max(turns, turns_low), turns_high)
    return q + _TWO_PI * turns


# ------------------------------------------------------------------ compiled kernels (numba)
@njit(cache=True)
def _project(q: NDArray[np.float64], lower: NDArray[np.float64], upper: NDArray[np.float64],
             revolute: NDArray[np.bool_], sides: NDArray[np.float64]) -> None:
    """Move ``q`` ``(n,)`` into the limits in place and mark the joints left at a bound.

    A revolute angle outside its range moves by whole turns if that fits, else to the
    bound nearer in angle; a prismatic value to the nearer bound. ``sides[i]`` becomes
    ``-1`` at the lower bound, ``+1`` at the upper one, ``0`` inside. The same whole-turn
    rule as :func:`wrap_into_limits` with the reference at the middle of the limits, then
    clamped.
    """
    for i in range(q.shape[0]):
        value, low, high = q[i], lower[i], upper[i]
        sides[i] = 0.0
        if low < value < high:
            continue
        if revolute[i] and not low <= value <= high:
            turned = low + (value - low) % (2 * math.pi)  # in [low, low + 2 pi)
            # inside, or else at the bound nearer in angle
            value = turned if turned <= high or turned - high < low + 2 * math.pi - turned else low
        if value <= low:
            value, sides[i] = low, -1.0
        elif value >= high:
            value, sides[i] = high, 1.0
        q[i] = value


@njit(cache=True)
def _cholesky_solve(A: NDArray[np.float64], b: NDArray[np.float64]) -> bool:
    """Solve ``A x = b`` for a symmetric positive definite ``A`` ``(k, k)`` in place.

    Reads the lower triangle of ``A`` and overwrites it with the Cholesky factor, ``b``
    ``(k,)`` with ``x``. ``False`` (and ``b`` unusable) if ``A`` is not positive definite.
    Written out because for ``k <= 7`` a LAPACK call costs more than the arithmetic.
    """
    k = b.shape[0]
    for j in range(k):
        d = A[j, j]
        for p in range(j):
            d -= A[j, p] * A[j, p]
        if not d > 0.0:
            return False
        d = math.sqrt(d)
        A[j, j] = d
        for i in range(j + 1, k):
            s = A[i, j]
            for p in range(j):
                s -= A[i, p] * A[j, p]
            A[i, j] = s / d
    for i in range(k):  # L y = b
        s = b[i]
        for p in range(i):
            s -= A[i, p] * b[p]
        b[i] = s / A[i, i]
    for i in range(k - 1, -1, -1):  # L^T x = y
        s = b[i]
        for p in range(i + 1, k):
            s -= A[p, i] * b[p]
        b[i] = s / A[i, i]
    return True


@njit(cache=True)
def _solve_normal_equations(Jm: NDArray[np.float64], em: NDArray[np.float64], damping: float,
                            x: NDArray[np.float64]) -> bool:
    """``x`` ``(k,)`` from ``(Jm Jm^T + damping I) x = em`` if ``Jm`` ``(m, n)`` has ``m <= n``
    rows (``k = m``), else from ``(Jm^T Jm + damping I) x = Jm^T em`` (``k = n``), by Cholesky;
    ``False`` if the matrix is not positive definite."""
    m, n = Jm.shape
    wide = m <= n
    size = x.shape[0]
    A = np.empty((size, size))
    for a in range(size):
        for b in range(a + 1):
            s = 0.0
            if wide:
                for i in range(n):
                    s += Jm[a, i] * Jm[b, i]
            else:
                for k in range(m):
                    s += Jm[k, a] * Jm[k, b]
            A[a, b] = s
        A[a, a] += damping
        if wide:
            x[a] = em[a]
        else:
            s = 0.0
            for k in range(m):
                s += Jm[k, a] * em[k]
            x[a] = s
    return _cholesky_solve(A, x)


@njit(cache=True)
def _damped_step(J: NDArray[np.float64], e: NDArray[np.float64], rows: NDArray[np.int64],
                 sides: NDArray[np.float64], damping: float, dq: NDArray[np.float64]) -> None:
    """The Levenberg-Marquardt step ``dq`` ``(n,)`` for the masked ``rows`` of ``J`` and ``e``.

    Joints held at a bound (``sides``) by the gradient ``J^T e`` get a zero column.
    Solves ``(J J^T + damping I) y = e``, ``dq = J^T y`` when ``m <= n`` rows, else
    ``(J^T J + damping I) dq = J^T e``. If that matrix is not positive definite (a singular
    ``J`` and no damping asked), the damping becomes ``_SINGULAR_DAMPING`` times the trace
    of ``J^T J``: within about 1e-7 of the minimum-norm least-squares step
    (``np.linalg.lstsq`` would cost seconds of compile time for a case the default damping
    never reaches).
    """
    m, n = rows.shape[0], J.shape[1]
    Jm, em = np.empty((m, n)), np.empty(m)
    for k in range(m):
        em[k] = e[rows[k]]
    trace = 0.0
    for i in range(n):
        frozen = False
        if sides[i] != 0.0:
            gradient = 0.0
            for k in range(m):
                gradient += em[k] * J[rows[k], i]
            frozen = gradient * sides[i] > 0.0
        for k in range(m):
            Jm[k, i] = 0.0 if frozen else J[rows[k], i]
            trace += Jm[k, i] * Jm[k, i]
    wide = m <= n
    x = np.empty(m if wide else n)
    if not _solve_normal_equations(Jm, em, damping, x) and not _solve_normal_equations(
            Jm, em, damping + _SINGULAR_DAMPING * trace, x):
        for k in range(x.shape[0]):  # J is all zeros: no direction lowers the error
            x[k] = 0.0
    for i in range(n):
        if wide:
            s = 0.0
            for k in range(m):
                s += Jm[k, i] * x[k]
            dq[i] = s
        else:
            dq[i] = x[i]


@njit(cache=True)
def _attempt(T_between: NDArray[np.float64], prismatic: NDArray[np.bool_], lower: NDArray[np.float64],
             upper: NDArray[np.float64], respect_limits: bool, T_target: NDArray[np.float64],
             rows: NDArray[np.int64], settings: NDArray[np.float64], max_iterations: int,
             q: NDArray[np.float64], best_q: NDArray[np.float64],
             best: NDArray[np.float64]) -> tuple[bool, int, float, float]:
    """One Levenberg-Marquardt attempt from ``q`` ``(n,)`` (updated in place to the last
    configuration evaluated): ``(solved, steps, position error, orientation error)``.

    ``settings`` is ``(position_tolerance**2, orientation_tolerance**2, damping_gain,
    damping)``; ``best`` ``(cost, position error, orientation error)`` and ``best_q`` keep
    the lowest-cost configuration over all attempts.
    """
    n = q.shape[0]
    T, J, e = np.empty((4, 4)), np.empty((6, n)), np.empty(6)
    axes, points, sides, dq = np.empty((n, 3)), np.empty((n, 3)), np.zeros(n), np.empty(n)
    revolute = ~prismatic
    if respect_limits:
        _project(q, lower, upper, revolute, sides)
    reference, since, steps = math.inf, 0, 0
    position = orientation = math.inf
    while steps < max_iterations:
        steps += 1
        chain_frames(T_between, prismatic, q, T, axes, points)
        pose_error_into(T_target, T, e)
        position = orientation = 0.0
        for r in rows:
            if r < 3:
                position += e[r] * e[r]
            else:
                orientation += e[r] * e[r]
        cost = 0.5 * (position + orientation)
        if cost < best[0]:
            best[0], best[1], best[2] = cost, math.sqrt(position), math.sqrt(orientation)
            for i in range(n):
                best_q[i] = q[i]
        if position <= settings[0] and orientation <= settings[1]:
            return True, steps, math.sqrt(position), math.sqrt(orientation)
        if cost < _STALL_FACTOR * reference:
            reference, since = cost, 0
        else:
            since += 1
            if since >= _STALL_STEPS or not math.isfinite(cost):
                break
        if steps == max_iterations:  # the step would never be evaluated
            break
        chain_jacobian(T, axes, points, prismatic, J)
        _damped_step(J, e, rows, sides, settings[2] * cost + settings[3], dq)
        q += dq
        if respect_limits:
            _project(q, lower, upper, revolute, sides)
    return False, steps, math.sqrt(position), math.sqrt(orientation)


class _TargetError:
    """The pose error (:func:`armkit.kinematics.pose_error`) to one target, one compiled call
    (:func:`armkit.kinematics.pose_error_into`, the one :func:`_attempt` uses) per pose."""

    def __init__(self, T_target: NDArray[np.float64]) -> None:
        self.T_target = np.ascontiguousarray(T_target, dtype=np.float64)

    def __call__(self, T: NDArray[np.float64]) -> NDArray[np.float64]:
        """The pose error ``(6,)`` [m, rad] of the tool pose ``T`` ``(4, 4)``."""
        e = np.empty(6)
        pose_error_into(self.T_target, np.ascontiguousarray(T, dtype=np.float64), e)
        return e


class NumericIK:
    """Numeric IK of one chain, reusable for many targets (see :func:`numeric_ik`).

    Holds the chain's arrays in the form the compiled attempt takes, so that a loop over
    targets pays for them once. Parameters are those of :func:`numeric_ik`.

    Examples
    --------
    >>> import armkit
    >>> panda = armkit.load("panda")
    >>> solver = NumericIK(panda.chain, position_tolerance=1e-10)
    >>> T = panda.fk([0.1, -0.3, 0.2, -2.0, 0.1, 1.8, 0.5])
    >>> result = solver.solve(T, rng=0)
    >>> result.success, bool(result.position_error < 1e-10), bool(panda.within_limits(result.q))
    (True, True, True)
    """

    def __init__(self, chain: Chain, *, position_tolerance: float = 1e-9,
                 orientation_tolerance: float = 1e-9, mask: ArrayLike | None = None,
                 damping_gain: float = 0.1, damping: float = 1e-9, max_iterations: int = 30,
                 max_restarts: int = 100, time_budget: float = 0.5, respect_limits: bool = True) -> None:
        if max_iterations < 1:
            raise InputError(f"max_iterations: expected at least 1 step per attempt, got {max_iterations}")
        self.chain = chain
        self.rows = np.flatnonzero(_check_mask(mask)).astype(np.int64)
        self.settings = np.array([position_tolerance**2, orientation_tolerance**2, damping_gain, damping],
                                 dtype=np.float64)
        self.max_iterations, self.max_restarts = int(max_iterations), int(max_restarts)
        self.time_budget, self.respect_limits = float(time_budget), bool(respect_limits)
        # writable copies, like every array _attempt gets: a read-only array is another numba
        # type, which would compile another specialisation inside a solve's time budget
        self.lower = np.array(chain.lower, dtype=np.float64)
        self.upper = np.array(chain.upper, dtype=np.float64)
        self.seed_low = np.where(np.isfinite(self.lower), self.lower, -_UNBOUNDED_SEED_RANGE)
        self.seed_high = np.where(np.isfinite(self.upper), self.upper, _UNBOUNDED_SEED_RANGE)
        if not _attempt.signatures:  # compile (or load from numba's cache) outside any time budget
            self._run_attempt(np.eye(4), (self.seed_low + self.seed_high) / 2.0, self.seed_low.copy(),
                              np.full(3, math.inf), max_iterations=1)

    def _run_attempt(self, T_target: NDArray[np.float64], q: NDArray[np.float64], best_q: NDArray[np.float64],
                     best: NDArray[np.float64], max_iterations: int) -> tuple[bool, int, float, float]:
        """The compiled :func:`_attempt` on this solver's chain and settings."""
        return _attempt(*self.chain._kernel_arrays, self.lower, self.upper,
                        self.respect_limits, T_target, self.rows, self.settings, max_iterations,
                        q, best_q, best)

    def solve(self, T_base_tool: NDArray[np.float64], q0: ArrayLike | None = None,
              rng: np.random.Generator | int | None = None) -> IKResult:
        """Solve ``fk(q) = T_base_tool`` ``(4, 4)`` from ``q0`` ``(n,)``; see :func:`numeric_ik`.

        Raises
        ------
        InputError
            If ``T_base_tool`` is not a finite 4x4 array or ``q0`` not ``n`` finite values.
        """
        n = self.chain.n
        T_target = _check_target(T_base_tool)
        if q0 is None:
            q = (self.seed_low + self.seed_high) / 2.0
        else:
            q = np.array(q0, dtype=np.float64)  # a copy: the attempt moves it in place
            if q.shape != (n,) or not math.isfinite(q.sum()):
                raise InputError(f"q0: expected {n} finite joint values, got {q.tolist()}")
        best_q, best = q.copy(), np.array([math.inf, math.inf, math.inf])
        deadline = time.perf_counter() + self.time_budget
        iterations = restarts = 0
        while True:
            solved, steps, position, orientation = self._run_attempt(T_target, q, best_q, best,
                                                                     self.max_iterations)
            iterations += steps
            if solved:
                return IKResult(q, True, iterations, restarts, position, orientation)
            if restarts >= self.max_restarts or time.perf_counter() > deadline:
                break
            if restarts == 0:
                rng = np.random.default_rng(rng)
            q = rng.uniform(self.seed_low, self.seed_high)
            restarts += 1
        return IKResult(best_q, False, iterations, restarts, float(best[1]), float(best[2]))

    def _project(self, q: NDArray[np.float64]) -> tuple[NDArray[np.float64], list[tuple[int, float]]]:
        """``q`` moved into the limits (a copy, see the compiled ``_project``) and the joints at
        a bound as ``(index, -1.0 at the lower / +1.0 at the upper)``: the projection of
        every step, callable from Python."""
        if not self.respect_limits:
            return q, []
        q, sides = np.array(q, dtype=np.float64), np.zeros(self.chain.n)
        _project(q, self.lower, self.upper, ~self.chain._kernel_arrays[1], sides)
        return q, [(i, float(sides[i])) for i in np.flatnonzero(sides).tolist()]


def numeric_ik(chain: Chain, T_base_tool: NDArray[np.float64], *, q0: ArrayLike | None = None,
               position_tolerance: float = 1e-9, orientation_tolerance: float = 1e-9,
               mask: ArrayLike | None = None, damping_gain: float = 0.1, damping: float = 1e-9,
               max_iterations: int = 30, max_restarts: int = 100, time_budget: float = 0.5,
               respect_limits: bool = True, rng: np.random.Generator | int | None = None) -> IKResult:
    """Solve ``fk(q) = T_base_tool`` numerically inside the joint limits.

    Levenberg-Marquardt from ``q0`` (moved into the limits); an attempt that stops
    improving (error not halved in 3 steps) or reaches ``max_iterations`` steps is
    restarted from a uniform random configuration inside the limits. The joint limits
    are bounds of every step (see the module notes), so every answer is inside them.
    For many targets of one chain, build a :class:`NumericIK` once and call its
    ``solve``.

    Parameters
    ----------
    chain : Chain
    T_base_tool : ndarray, shape (4, 4)
        Target tool pose [m], assumed rigid (see :func:`armkit.spatial.check_transform`).
    q0 : array_like, shape (n,), optional
        First seed [rad or m]; default the middle of the limits.
    position_tolerance, orientation_tolerance : float
        Success when the masked position error [m] and orientation error [rad] are below.
    mask : array_like, shape (6,), optional
        0/1 weights of the error components ``x y z rx ry rz`` (base frame), e.g.
        ``[1, 1, 1, 0, 0, 0]`` for a position-only target. Default all ones.
    damping_gain, damping : float
        The Levenberg-Marquardt damping is ``damping_gain * E + damping``.
    max_iterations : int
        Steps per attempt at most.
    max_restarts : int
        Random seeds drawn after the first attempt at most.
    time_budget : float
        Wall-clock budget [s], checked between attempts.
    respect_limits : bool
        Keep every step inside the joint limits (default). ``False`` accepts any solution,
        e.g. to refine a known one.
    rng : numpy Generator or int, optional
        Source of the random seeds (reproducible when given).

    Returns
    -------
    IKResult
        The solution, or (``success=False``) the configuration with the smallest error
        seen (inside the limits when ``respect_limits``).

    Examples
    --------
    >>> import armkit
    >>> panda = armkit.load("panda")
    >>> T = panda.fk([0.1, -0.3, 0.2, -2.0, 0.1, 1.8, 0.5])
    >>> result = numeric_ik(panda.chain, T, rng=0)
    >>> result.success, bool(result.position_error < 1e-9)
    (True, True)
    """
    solver = NumericIK(chain, position_tolerance=position_tolerance,
                       orientation_tolerance=orientation_tolerance, mask=mask,
                       damping_gain=damping_gain, damping=damping, max_iterations=max_iterations,
                       max_restarts=max_restarts, time_budget=time_budget, respect_limits=respect_limits)
    return solver.solve(T_base_tool, q0, rng)
