"""Numeric inverse kinematics for any chain: Levenberg-Marquardt with random restarts.

The solver minimises ``E = 1/2 e^T W e`` where ``e = [p_target - p; log(R_target R^T)]``
is the pose error in the base frame (metres over radians, the rotation part a rotation
vector) and ``W`` a diagonal 0/1 task mask. Each step solves the damped normal equations
of Sugihara's Levenberg-Marquardt method (T. Sugihara, "Solvability-unconcerned inverse
kinematics by the Levenberg-Marquardt method", IEEE T-RO 27(5), 2011)::

    (J^T W J + (g E + damping) I) dq = J^T W e

whose damping grows with the error far from the target and nearly vanishes near it, so
the last steps converge quadratically (Sugihara uses ``g = 1``; ``g = 0.1`` and
``damping = 1e-6`` needed the fewest iterations on random Panda poses here). The steps
ignore the joint limits; a solution outside them is wrapped into them by whole turns
and, if still outside, moved along its self-motion into them by null-space steps (for a
redundant arm or a masked task). An attempt that fails within ``max_iterations`` is
restarted from a uniform random configuration inside the limits until the restart or
time budget runs out.
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
#: steps is given up.
_STALL_STEPS = 3


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
    """Single-configuration FK, pose error and Jacobian of a chain, for the solver's hot loop.

    ``kinematics.fk`` and ``kinematics.geometric_jacobian`` serve batches; for one
    configuration their per-call overhead dominates, so the solver builds every joint's
    motion-times-next-link transform in one vectorised step and multiplies them in order.
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
        self.coefficients = np.zeros((self.n, 1, 4))
        self.coefficients[:, 0, 0] = 1.0

    def frames(self, q: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Joint axes and origins ``(n, 3)`` each, in the base frame, and the tool pose."""
        k = self.coefficients
        k[:, 0, 1] = np.cos(q)
        k[:, 0, 2] = np.sin(q)
        k[:, 0, 3] = q
        A = (k @ self.basis).reshape(self.n, 4, 4)
        P = np.empty((self.n + 1, 4, 4))
        P[0] = self.first
        for i in range(self.n):
            np.matmul(P[i], A[i], out=P[i + 1])
        return P[:-1, :3, 2], P[:-1, :3, 3], P[-1]

    def jacobian(self, axes: NDArray[np.float64], origins: NDArray[np.float64],
                 T: NDArray[np.float64]) -> NDArray[np.float64]:
        """Geometric Jacobian ``(6, n)``, rows ``[v; w]``, from :meth:`frames`."""
        r = T[:3, 3] - origins
        J = np.empty((6, self.n))
        J[0] = axes[:, 1] * r[:, 2] - axes[:, 2] * r[:, 1]
        J[1] = axes[:, 2] * r[:, 0] - axes[:, 0] * r[:, 2]
        J[2] = axes[:, 0] * r[:, 1] - axes[:, 1] * r[:, 0]
        J[3:] = axes.T
        if self.any_prismatic:
            J[:3, self.prismatic] = axes[self.prismatic].T
            J[3:, self.prismatic] = 0.0
        return J


def pose_error(T_target: NDArray[np.float64], T: NDArray[np.float64]) -> NDArray[np.float64]:
    """Pose error ``(6,)``: ``p_target - p`` [m] and the rotation vector of ``R_target R^T`` [rad].

    Both parts are in the base frame; the rotation vector's norm is the angle between
    the two orientations, exact up to ``pi``.
    """
    e = np.empty(6)
    e[:3] = T_target[:3, 3] - T[:3, 3]
    R = T_target[:3, :3] @ T[:3, :3].T
    v = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    norm = np.sqrt(v @ v)
    trace = R[0, 0] + R[1, 1] + R[2, 2]
    if norm > 1e-7 or trace > 0.0:
        angle = np.arctan2(norm, trace - 1.0)
        # angle / (2 sin angle) -> 1/2 for small angles; norm = 2 sin(angle).
        e[3:] = v * (angle / norm if norm > 1e-300 else 0.5)
    else:  # angle near pi: axis from the diagonal, sign from the off-diagonal terms
        axis = np.sqrt(np.clip((np.diag(R) + 1.0) / 2.0, 0.0, None))
        k = int(np.argmax(axis))
        sign = np.sign(R[k] + R[:, k])
        sign[k] = 1.0
        e[3:] = np.pi * axis * np.where(sign == 0, 1.0, sign)
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
    """One target: masked pose error and Jacobian rows, tolerances, limits, best pose seen."""

    def __init__(self, chain: Chain, T_target: NDArray[np.float64], rows: NDArray[np.bool_],
                 tolerances: tuple[float, float], respect_limits: bool) -> None:
        self.kernel, self.T_target, self.rows, self.tolerances = _Kernel(chain), T_target, rows, tolerances
        self.lower, self.upper = _limits(chain)
        self.respect_limits = respect_limits
        self.best: tuple[float, NDArray[np.float64], float, float] | None = None
        self.last: tuple[NDArray[np.float64], float, float] | None = None

    def inside(self, q: NDArray[np.float64]) -> bool:
        return not self.respect_limits or bool(np.all((q >= self.lower) & (q <= self.upper)))

    def evaluate(self, q: NDArray[np.float64]) -> tuple[NDArray, tuple, bool]:
        """Masked error ``(m,)``, the frames for the Jacobian, and whether ``q`` is a solution.

        Remembers ``q`` as :attr:`last`, and as :attr:`best` if it is admissible (inside the
        limits when they are respected) with the smallest error so far.
        """
        axes, origins, T = self.kernel.frames(q)
        e = pose_error(self.T_target, T)
        e[~self.rows] = 0.0
        position_error, orientation_error = float(np.sqrt(e[:3] @ e[:3])), float(np.sqrt(e[3:] @ e[3:]))
        cost = 0.5 * float(e @ e)
        self.last = (q, position_error, orientation_error)
        if (self.best is None or cost < self.best[0]) and self.inside(q):
            self.best = (cost, q, position_error, orientation_error)
        solved = position_error <= self.tolerances[0] and orientation_error <= self.tolerances[1]
        return e[self.rows], (axes, origins, T), solved

    def jacobian(self, frames: tuple) -> NDArray[np.float64]:
        return self.kernel.jacobian(*frames)[self.rows]


def _levenberg_marquardt(problem: _Problem, q: NDArray[np.float64], iterations: int,
                         damping_gain: float, damping: float) -> tuple[NDArray[np.float64], bool, int]:
    """Unconstrained LM steps from ``q``: ``(q, solved, iterations used)``."""
    eye = np.eye(len(q))
    for i in range(iterations):
        e, frames, solved = problem.evaluate(q)
        if solved:
            return q, True, i
        J = problem.jacobian(frames)
        q = q + np.linalg.solve(J.T @ J + (damping_gain * 0.5 * (e @ e) + damping) * eye, J.T @ e)
    return q, problem.evaluate(q)[2], iterations


def _repair_limits(problem: _Problem, q: NDArray[np.float64],
                   iterations: int) -> tuple[NDArray[np.float64], bool, int]:
    """Move a solution outside the limits along its self-motion into them (redundant arms).

    Each step keeps the task error going to zero (``J^+ e``) and, in the null space of the
    task Jacobian, pushes every joint beyond a limit to a small margin inside it.
    """
    lower, upper = problem.lower, problem.upper
    margin = np.minimum(0.05, 0.25 * (upper - lower))
    eye = np.eye(len(q))
    violations = []
    for i in range(iterations):
        e, frames, solved = problem.evaluate(q)
        if solved and problem.inside(q):
            return q, True, i
        violations.append(np.sum(np.maximum(lower - q, 0.0) + np.maximum(q - upper, 0.0)))
        if i >= _STALL_STEPS and violations[-1] > 0.9 * violations[-1 - _STALL_STEPS]:
            return q, False, i
        J = problem.jacobian(frames)
        J_pinv = J.T @ np.linalg.inv(J @ J.T + 1e-12 * np.eye(len(e)))
        push = np.where(q < lower, lower + margin - q, np.where(q > upper, upper - margin - q, 0.0))
        q = q + J_pinv @ e + (eye - J_pinv @ J) @ push
    return q, problem.evaluate(q)[2] and problem.inside(q), iterations


def numeric_ik(chain: Chain, T_base_tool: NDArray[np.float64], *, q0: ArrayLike | None = None,
               position_tolerance: float = 1e-9, orientation_tolerance: float = 1e-9,
               mask: ArrayLike | None = None, damping_gain: float = 0.1, damping: float = 1e-6,
               max_iterations: int = 20, max_restarts: int = 100, time_budget: float = 0.5,
               respect_limits: bool = True,
               rng: np.random.Generator | int | None = None) -> IKResult:
    """Solve ``fk(q) = T_base_tool`` numerically inside the joint limits.

    Each attempt runs Levenberg-Marquardt steps without limits; a solution outside the
    limits is wrapped into them by whole turns and, if still outside, moved along its
    self-motion into them (null-space steps, for redundant arms and masked tasks). An
    attempt that fails is restarted from a uniform random configuration inside the limits.

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
        Iterations per attempt (and again for moving a solution into the limits).
    max_restarts : int
        Attempts from random seeds after the first one.
    time_budget : float
        Wall-clock budget [s] over all attempts.
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
    if q0 is None:
        q = middle
    else:
        q = np.asarray(q0, dtype=float)
        if q.shape != (chain.n,) or not np.all(np.isfinite(q)):
            raise InputError(f"q0: expected {chain.n} finite joint values, got {q.tolist()}")
    problem = _Problem(chain, np.asarray(T_base_tool, dtype=float), rows,
                       (position_tolerance, orientation_tolerance), respect_limits)
    rng = np.random.default_rng(rng)
    deadline = time.perf_counter() + time_budget
    iterations = 0
    for restarts in range(max_restarts + 1):
        if restarts:
            q = rng.uniform(seed_low, seed_high)
        q, solved, used = _levenberg_marquardt(problem, q, max_iterations, damping_gain, damping)
        iterations += used
        if solved and not problem.inside(q):
            q = wrap_into_limits(chain, q, middle)
            solved = problem.evaluate(q)[2]
            if solved and not problem.inside(q):
                q, solved, used = _repair_limits(problem, q, max_iterations)
                iterations += used
        if solved and problem.inside(q):
            q, position_error, orientation_error = problem.last
            return IKResult(q, True, iterations, restarts, position_error, orientation_error)
        if time.perf_counter() > deadline:
            break
    if problem.best is None:  # no iterate was inside the limits: report the first seed
        problem.respect_limits = False
        problem.evaluate(np.clip(q0 if q0 is not None else middle, lower, upper))
    _, q, position_error, orientation_error = problem.best
    return IKResult(q, False, iterations, restarts, position_error, orientation_error)
