"""Numeric inverse kinematics for any chain: Levenberg-Marquardt with random restarts.

The solver minimises ``E = 1/2 e^T W e`` where ``e = [p_target - p; log(R_target R^T)]``
is the pose error in the base frame (metres over radians, the rotation part a rotation
vector) and ``W`` a diagonal 0/1 task mask. Each step solves the damped normal equations
of Sugihara's Levenberg-Marquardt method (T. Sugihara, "Solvability-unconcerned inverse
kinematics by the Levenberg-Marquardt method", IEEE T-RO 27(5), 2011)::

    (J^T W J + (g E + damping) I) dq = J^T W e

whose damping grows with the error far from the target and nearly vanishes near it, so
the last steps converge quadratically (Sugihara uses ``g = 1``; ``g = 0.1`` and
``damping = 1e-6`` needed the fewest iterations on random Panda poses here).

Several seeds (the caller's ``q0`` and random configurations inside the limits) iterate
together, one vectorised step for all, because in NumPy a step for eight configurations
costs little more than a step for one. The steps ignore the joint limits; a solution
outside them is shifted into them by whole turns and, if still outside, moved along its
self-motion into them by null-space steps (for a redundant arm or a masked task). A seed
that has not converged after ``max_iterations`` steps is replaced by a new random one
until the restart or time budget runs out.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit.chain import Chain
from armkit.errors import InputError
from armkit.robot import LIMIT_TOLERANCE

__all__ = ["IKResult", "numeric_ik", "pose_error", "wrap_into_limits"]

#: Range [m] used for random seeds of prismatic joints without limits.
_UNBOUNDED_SEED_RANGE = 1.0
#: A move into the limits that shrinks the violation by less than 10 % in this many
#: steps is given up, and so is one that takes more than _REPAIR_STEPS steps.
_STALL_STEPS = 3
_REPAIR_STEPS = 8


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


class _Kernel:
    """FK and Jacobian of a chain for a few configurations ``(B, n)`` at once: the solver's hot loop.

    ``kinematics.fk`` and ``kinematics.geometric_jacobian`` loop over joints with several
    array operations each; for a handful of configurations that overhead dominates, so
    the kernel builds every joint's motion-times-next-link transform in one product and
    multiplies them in order.
    """

    def __init__(self, chain: Chain) -> None:
        self.n = chain.n
        self.first = np.array(chain.T_between[0])
        self.prismatic = chain.prismatic
        self.any_prismatic = bool(self.prismatic.any())
        # Rz(q) B = (I - C) B + cos(q) C B + sin(q) S B and Tz(q) B = B + q D B, with
        # C = diag(1, 1, 0, 0), S the 90-degree rotation block and D the z-translation unit:
        # every joint's motion times the next fixed link is linear in [1, cos q, sin q, q].
        C, S, D = np.zeros((4, 4)), np.zeros((4, 4)), np.zeros((4, 4))
        C[0, 0] = C[1, 1] = 1.0
        S[0, 1], S[1, 0] = -1.0, 1.0
        D[2, 3] = 1.0
        basis = np.zeros((self.n, 4, 4, 4))
        for i, B in enumerate(chain.T_between[1:]):
            if self.prismatic[i]:
                basis[i, 0], basis[i, 3] = B, D @ B
            else:
                basis[i, 0], basis[i, 1], basis[i, 2] = B - C @ B, C @ B, S @ B
        self.basis = basis.reshape(self.n, 4, 16)

    def frames(self, q: NDArray[np.float64]) -> tuple[NDArray[np.float64], ...]:
        """Joint axes and origins ``(B, n, 3)`` in the base frame and tool poses ``(B, 4, 4)``."""
        batch = len(q)
        k = np.empty((batch, self.n, 1, 4))
        k[..., 0, 0] = 1.0
        k[..., 0, 1] = np.cos(q)
        k[..., 0, 2] = np.sin(q)
        k[..., 0, 3] = q
        A = (k @ self.basis).reshape(batch, self.n, 4, 4)
        P = np.empty((self.n + 1, batch, 4, 4))
        P[0] = self.first
        for i in range(self.n):
            np.matmul(P[i], A[:, i], out=P[i + 1])
        axes_origins = P[:-1, :, :3, 2:].transpose(1, 0, 3, 2)  # (B, n, 2, 3)
        return axes_origins[:, :, 0], axes_origins[:, :, 1], P[-1]

    def jacobian(self, axes: NDArray[np.float64], origins: NDArray[np.float64],
                 T: NDArray[np.float64]) -> NDArray[np.float64]:
        """Geometric Jacobians ``(B, 6, n)``, rows ``[v; w]``, from :meth:`frames`."""
        r = T[:, None, :3, 3] - origins
        J = np.empty((len(T), 6, self.n))
        J[:, 0] = axes[..., 1] * r[..., 2] - axes[..., 2] * r[..., 1]
        J[:, 1] = axes[..., 2] * r[..., 0] - axes[..., 0] * r[..., 2]
        J[:, 2] = axes[..., 0] * r[..., 1] - axes[..., 1] * r[..., 0]
        J[:, 3:] = axes.transpose(0, 2, 1)
        if self.any_prismatic:
            J[:, :3, self.prismatic] = axes[:, self.prismatic].transpose(0, 2, 1)
            J[:, 3:, self.prismatic] = 0.0
        return J


def pose_error(T_target: ArrayLike, T: ArrayLike) -> NDArray[np.float64]:
    """Pose errors ``(..., 6)``: ``p_target - p`` [m] and the rotation vector of ``R_target R^T`` [rad].

    Both parts are in the base frame; the rotation vector's norm is the angle between
    the two orientations, exact up to ``pi``. Inputs ``(..., 4, 4)`` broadcast.

    Examples
    --------
    >>> from armkit.spatial import matrix_from_axis_angle, transform_from
    >>> T = transform_from(np.eye(3), [0.1, 0.0, 0.0])
    >>> T_target = transform_from(matrix_from_axis_angle([0.0, 0.0, 0.3]), [0.1, 0.2, 0.0])
    >>> pose_error(T_target, T).round(12) + 0.0
    array([0. , 0.2, 0. , 0. , 0. , 0.3])
    """
    T_target, T = np.asarray(T_target, dtype=float), np.asarray(T, dtype=float)
    R = T_target[..., :3, :3] @ np.swapaxes(T[..., :3, :3], -1, -2)
    flat = R.reshape(*R.shape[:-2], 9)
    e = np.empty((*R.shape[:-2], 6))
    e[..., :3] = T_target[..., :3, 3] - T[..., :3, 3]
    v = flat[..., [7, 2, 3]] - flat[..., [5, 6, 1]]  # 2 sin(angle) * axis
    norm = np.sqrt(np.einsum("...i,...i->...", v, v))
    trace = flat[..., 0] + flat[..., 4] + flat[..., 8]
    angle = np.arctan2(norm, trace - 1.0)
    # angle / (2 sin angle) -> 1/2 for small angles
    scale = np.divide(angle, norm, out=np.full_like(angle, 0.5), where=norm > 1e-300)
    e[..., 3:] = v * scale[..., None]
    half_turn = (norm <= 1e-7) & (trace <= 0.0)
    if np.any(half_turn):  # angle near pi: axis from the diagonal, signs from off-diagonals
        Rh = R[half_turn]
        axis = np.sqrt(np.clip((np.diagonal(Rh, axis1=-2, axis2=-1) + 1.0) / 2.0, 0.0, None))
        k = np.argmax(axis, axis=-1)
        rows = np.take_along_axis(Rh, k[:, None, None], axis=-2)[:, 0]
        columns = np.take_along_axis(Rh, k[:, None, None], axis=-1)[..., 0]
        sign = np.where(rows + columns < 0, -1.0, 1.0)
        np.put_along_axis(sign, k[:, None], 1.0, axis=-1)
        e[half_turn, 3:] = np.pi * axis * sign
    return e


def _check_mask(mask: ArrayLike | None) -> NDArray[np.bool_]:
    if mask is None:
        return np.ones(6, dtype=bool)
    m = np.asarray(mask, dtype=float)
    if m.shape != (6,) or not np.all((m == 0) | (m == 1)) or not m.any():
        raise InputError(f"mask: expected 6 values of 0 or 1 (x y z rx ry rz, at least one 1), "
                         f"got {np.asarray(mask).tolist()}")
    return m == 1


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
    lower, upper = _limits(chain)
    turns_low = np.ceil((lower - LIMIT_TOLERANCE - q) / (2 * np.pi))
    turns_high = np.floor((upper + LIMIT_TOLERANCE - q) / (2 * np.pi))
    turns = np.round((np.asarray(reference, dtype=float) - q) / (2 * np.pi))
    turns = np.where(turns_low <= turns_high, np.clip(turns, turns_low, turns_high), turns)
    return np.where(chain.prismatic, q, q + 2 * np.pi * turns)


def _limits(chain: Chain) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    return (np.array([j.lower for j in chain.joints]), np.array([j.upper for j in chain.joints]))


class _Problem:
    """One target: masked pose errors and Jacobian rows, tolerances, limits, best pose seen."""

    def __init__(self, chain: Chain, T_target: NDArray[np.float64], rows: NDArray[np.bool_],
                 tolerances: tuple[float, float], respect_limits: bool) -> None:
        self.kernel, self.T_target, self.rows, self.tolerances = _Kernel(chain), T_target, rows, tolerances
        self.lower, self.upper = _limits(chain)
        self.respect_limits = respect_limits
        self.all_rows = bool(rows.all())
        self.squared_tolerances = np.square(tolerances)
        self.best: tuple[float, NDArray[np.float64], float, float] | None = None

    def inside(self, q: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Whether configurations ``(..., n)`` are admissible (inside the limits if respected)."""
        if not self.respect_limits:
            return np.ones(q.shape[:-1], dtype=bool)
        return np.all((q >= self.lower) & (q <= self.upper), axis=-1)

    def evaluate(self, q: NDArray[np.float64]) -> tuple[NDArray, tuple, NDArray, NDArray]:
        """For configurations ``(B, n)``: masked errors ``(B, m)``, frames, solved ``(B,)``,
        and ``(B, 2)`` position [m] and orientation [rad] errors.

        Remembers the admissible configuration with the smallest error as :attr:`best`.
        """
        frames = self.kernel.frames(q)
        e = pose_error(self.T_target, frames[2])
        if not self.all_rows:
            e[:, ~self.rows] = 0.0
        squared = np.einsum("bij,bij->bi", e.reshape(-1, 2, 3), e.reshape(-1, 2, 3))  # (B, 2)
        solved = np.all(squared <= self.squared_tolerances, axis=-1)
        cost = np.where(self.inside(q), 0.5 * squared.sum(axis=-1), np.inf)
        i = int(np.argmin(cost))
        if cost[i] < (np.inf if self.best is None else self.best[0]):
            self.best = (float(cost[i]), q[i].copy(), *np.sqrt(squared[i]).tolist())
        return (e if self.all_rows else e[:, self.rows]), frames, solved, np.sqrt(squared)

    def jacobian(self, frames: tuple) -> NDArray[np.float64]:
        J = self.kernel.jacobian(*frames)
        return J if self.all_rows else J[:, self.rows]


def _step(problem: _Problem, e: NDArray[np.float64], frames: tuple, damping_gain: float,
          damping: float) -> NDArray[np.float64]:
    """Levenberg-Marquardt steps ``(B, n)`` for errors ``(B, m)``."""
    J = problem.jacobian(frames)
    Jt = J.transpose(0, 2, 1)
    lam = damping_gain * 0.5 * np.sum(e * e, axis=-1) + damping
    H = Jt @ J + lam[:, None, None] * np.eye(J.shape[-1])
    return np.linalg.solve(H, (Jt @ e[..., None]))[..., 0]


def _repair_limits(problem: _Problem, q: NDArray[np.float64],
                   iterations: int) -> tuple[NDArray[np.float64], bool, int]:
    """Move a solution ``(n,)`` outside the limits along its self-motion into them.

    Each step keeps the task error going to zero (``J^+ e``) and, in the null space of the
    task Jacobian, pushes every joint beyond a limit to a small margin inside it (this
    needs a redundant arm or a masked task). Gives up when the violation stops shrinking.
    """
    lower, upper = problem.lower, problem.upper
    margin = np.minimum(0.05, 0.25 * (upper - lower))
    eye = np.eye(len(q))
    violations = []
    for i in range(iterations):
        e, frames, solved, _ = problem.evaluate(q[None])
        if solved[0] and problem.inside(q):
            return q, True, i
        violations.append(np.sum(np.maximum(lower - q, 0.0) + np.maximum(q - upper, 0.0)))
        if i >= _STALL_STEPS and violations[-1] > 0.9 * violations[-1 - _STALL_STEPS]:
            return q, False, i
        J = problem.jacobian(frames)[0]
        J_pinv = J.T @ np.linalg.inv(J @ J.T + 1e-12 * np.eye(len(J)))
        push = np.where(q < lower, lower + margin - q, np.where(q > upper, upper - margin - q, 0.0))
        q = q + J_pinv @ e[0] + (eye - J_pinv @ J) @ push
    return q, bool(problem.evaluate(q[None])[2][0] and problem.inside(q)), iterations


def _admit(problem: _Problem, chain: Chain, q: NDArray[np.float64],
           middle: NDArray[np.float64]) -> tuple[NDArray[np.float64] | None, int]:
    """A solution moved into the limits (whole turns, then self-motion), or None."""
    if problem.inside(q):
        return q, 0
    q = wrap_into_limits(chain, q, middle)
    if problem.inside(q) and problem.evaluate(q[None])[2][0]:
        return q, 0
    q, ok, used = _repair_limits(problem, q, _REPAIR_STEPS)
    return (q if ok else None), used


def numeric_ik(chain: Chain, T_base_tool: NDArray[np.float64], *, q0: ArrayLike | None = None,
               position_tolerance: float = 1e-9, orientation_tolerance: float = 1e-9,
               mask: ArrayLike | None = None, damping_gain: float = 0.1, damping: float = 1e-6,
               seeds: int = 8, max_iterations: int = 20, max_restarts: int = 100,
               time_budget: float = 0.5, respect_limits: bool = True,
               rng: np.random.Generator | int | None = None) -> IKResult:
    """Solve ``fk(q) = T_base_tool`` numerically inside the joint limits.

    ``seeds`` configurations iterate together (one vectorised LM step for all): ``q0`` and
    uniform random ones inside the limits. The first that converges (``q0``'s on a tie)
    and is inside the limits, or can be moved into them (whole turns, then null-space
    steps along its self-motion), is the answer. A seed that has not converged after
    ``max_iterations`` steps is replaced by a new random one (a restart).

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
    seeds : int
        Configurations iterated together (``1``: one seed at a time).
    max_iterations : int
        Steps per seed before it is replaced.
    max_restarts : int
        Random seeds drawn after the first ``seeds`` (the budget of replacements).
    time_budget : float
        Wall-clock budget [s].
    respect_limits : bool
        Return only configurations inside the joint limits (default). ``False`` accepts
        any solution, e.g. to refine a known one.
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
    rows = _check_mask(mask)
    lower, upper = _limits(chain)
    seed_low = np.where(np.isfinite(lower), lower, -_UNBOUNDED_SEED_RANGE)
    seed_high = np.where(np.isfinite(upper), upper, _UNBOUNDED_SEED_RANGE)
    middle = (seed_low + seed_high) / 2.0
    first = middle if q0 is None else np.asarray(q0, dtype=float)
    if first.shape != (chain.n,) or not np.all(np.isfinite(first)):
        raise InputError(f"q0: expected {chain.n} finite joint values, got {first.tolist()}")
    if seeds < 1:
        raise InputError(f"seeds: expected a positive number of seeds, got {seeds}")
    problem = _Problem(chain, np.asarray(T_base_tool, dtype=float), rows,
                       (position_tolerance, orientation_tolerance), respect_limits)
    rng = np.random.default_rng(rng)
    deadline = time.perf_counter() + time_budget
    q = np.vstack([first, rng.uniform(seed_low, seed_high, (seeds - 1, chain.n))])
    age = np.zeros(seeds, dtype=int)
    iterations = restarts = 0
    while len(q):
        e, frames, solved, errors = problem.evaluate(q)
        age[~np.isfinite(errors[:, 0])] = max_iterations  # a step blew up: replace the seed
        for i in np.flatnonzero(solved):
            found, used = _admit(problem, chain, q[i], middle)
            iterations += used
            if found is not None:
                position_error, orientation_error = problem.evaluate(found[None])[3][0]
                return IKResult(found.copy(), True, iterations, restarts, float(position_error),
                                float(orientation_error))
            age[i] = max_iterations  # solved outside the limits: replace it
        stale = age >= max_iterations
        if not stale.any():  # the common case: every seed takes a step
            q += _step(problem, e, frames, damping_gain, damping)
            age += 1
            iterations += len(q)
            continue
        if not stale.all():
            q[~stale] += _step(problem, e[~stale], tuple(f[~stale] for f in frames), damping_gain,
                               damping)
            age[~stale] += 1
            iterations += int(np.sum(~stale))
        if time.perf_counter() > deadline:
            break
        replaced = np.flatnonzero(stale)[:max_restarts - restarts]
        q[replaced] = rng.uniform(seed_low, seed_high, (len(replaced), chain.n))
        age[replaced] = 0
        restarts += len(replaced)
        stale[replaced] = False
        q, age = q[~stale], age[~stale]  # seeds not replaced (budget spent) are dropped
    if problem.best is None:  # no configuration was inside the limits: report the first seed
        problem.respect_limits = False
        problem.evaluate(np.clip(first, lower, upper)[None])
    _, q_best, position_error, orientation_error = problem.best
    return IKResult(q_best, False, iterations, restarts, position_error, orientation_error)
