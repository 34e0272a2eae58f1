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
failed the ``1e-9`` tolerance; with ``1e-9`` none did. For a
6-row task and ``n >= 6`` joints the same step is ``dq = J^T y`` with the 6x6 system
``(J J^T + lambda I) y = e``, solved by Cholesky (LAPACK ``dposv``).

Joint limits are kept during the iterations, as bounds: after each step a revolute angle
outside its range is moved into it by whole turns if that fits, else to the bound nearer
in angle (a prismatic value to the nearer bound), and a joint held at a bound by the
gradient (``J^T e`` pointing outwards) is left out of the next step (its Jacobian column
is zeroed), so the other joints take over instead of the step stalling against the
bound: an active set, so every answer is inside the limits. One seed iterates at a time, first
the caller's ``q0``: an attempt that has not halved its error in ``3`` steps, or has
used ``max_iterations`` steps, is abandoned for a new uniform random seed inside the
limits, until the restart or time budget runs out. One step costs about 20 us (the
tool pose and Jacobian come from :class:`armkit.kinematics.ChainKernel`, the pose error
from one product with a matrix built once per target).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.linalg import lapack

from armkit.chain import LIMIT_TOLERANCE, Chain
from armkit.errors import InputError
from armkit.kinematics import HALF_TURN_NORM, ChainKernel, pose_error

__all__ = ["IKResult", "NumericIK", "numeric_ik", "wrap_into_limits"]

#: Range [m] used for random seeds of prismatic joints without limits.
_UNBOUNDED_SEED_RANGE = 1.0
#: An attempt whose error has not fallen below _STALL_FACTOR times its best in
#: _STALL_STEPS steps is abandoned for a new seed.
_STALL_STEPS = 3
_STALL_FACTOR = 0.5


def _error_coefficients() -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Constants of :class:`_TargetError`: ``C[b, c, a]``, the coefficient of ``X[a, b]`` in
    output ``c`` of ``(X[2,1] - X[1,2], X[0,2] - X[2,0], X[1,0] - X[0,1], trace X)``, and the
    map's fixed part (``-1`` from each tool position entry to its error)."""
    C = np.zeros((4, 3, 3))  # [c, a, b]
    for c, (a, b) in enumerate(((2, 1), (0, 2), (1, 0))):
        C[c, a, b], C[c, b, a] = 1.0, -1.0
    C[3] = np.eye(3)
    base = np.zeros((16, 7))
    base[[3, 7, 11], [0, 1, 2]] = -1.0
    C = np.ascontiguousarray(C.transpose(2, 0, 1))
    C.setflags(write=False)
    base.setflags(write=False)
    return C, base


_ROTATION_COEFFICIENTS, _ERROR_MAP_BASE = _error_coefficients()


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
    lower, upper = chain.lower, chain.upper
    turns_low = np.ceil((lower - LIMIT_TOLERANCE - q) / (2 * np.pi))
    turns_high = np.floor((upper + LIMIT_TOLERANCE - q) / (2 * np.pi))
    turns = np.round((np.asarray(reference, dtype=float) - q) / (2 * np.pi))
    turns = np.where(turns_low <= turns_high, np.clip(turns, turns_low, turns_high), turns)
    return np.where(chain.prismatic, q, q + 2 * np.pi * turns)


class _TargetError:
    """Pose errors (see :func:`armkit.kinematics.pose_error`) to one target, one product each.

    ``[p_target - p, 2 sin(angle) axis, trace(R_target R^T)]`` is affine in the entries of
    ``T`` (whose last entry is 1): with ``X = R_target R^T``, ``X[a, b] = sum_k
    R_target[a, k] T[b, k]``. So a ``(16, 7)`` matrix built once per target maps
    ``T.reshape(16)`` to it, and the rotation vector then needs only its angle.
    """

    def __init__(self, T_target: NDArray[np.float64]) -> None:
        self.T_target = T_target
        M = _ERROR_MAP_BASE.copy()
        M[15, :3] = T_target[:3, 3]
        # rows 4 b + k, columns 3..6: sum_a C[b, c, a] R_target[a, k]
        M.reshape(4, 4, 7)[:3, :3, 3:] = (_ROTATION_COEFFICIENTS @ T_target[:3, :3]).transpose(0, 2, 1)
        self._map = M

    def __call__(self, T: NDArray[np.float64]) -> NDArray[np.float64]:
        """The pose error ``(6,)`` [m, rad] of the tool pose ``T`` ``(4, 4)``."""
        x, y, z, u, v, w, trace = T.reshape(16).dot(self._map).tolist()
        norm = math.sqrt(u * u + v * v + w * w)  # 2 sin(angle)
        if norm <= HALF_TURN_NORM and trace <= 0.0:  # near a half turn: the axis needs R + R^T
            return pose_error(self.T_target, T)
        scale = math.atan2(norm, trace - 1.0) / norm if norm > 1e-300 else 0.5
        return np.array((x, y, z, scale * u, scale * v, scale * w))


class NumericIK:
    """Numeric IK of one chain, reusable for many targets (see :func:`numeric_ik`).

    Holds the chain's :class:`~armkit.kinematics.ChainKernel`, its limits and work buffers,
    so that a loop over targets pays for them once (about 30 us per construction).
    Parameters are those of :func:`numeric_ik`. Use one solver per thread.

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
        self.kernel = ChainKernel(chain)
        self.rows = _check_mask(mask)
        self.all_rows, self.weights = bool(self.rows.all()), self.rows.astype(float)
        self.squared_tolerances = (position_tolerance**2, orientation_tolerance**2)
        self.damping_gain, self.damping = damping_gain, damping
        self.max_iterations, self.max_restarts, self.time_budget = max_iterations, max_restarts, time_budget
        self.respect_limits = respect_limits
        lower, upper = chain.lower, chain.upper
        self.seed_low = np.where(np.isfinite(lower), lower, -_UNBOUNDED_SEED_RANGE)
        self.seed_high = np.where(np.isfinite(upper), upper, _UNBOUNDED_SEED_RANGE)
        self.bounds = list(zip(lower.tolist(), upper.tolist(), (~chain.prismatic).tolist(), strict=True))
        m = int(self.rows.sum())
        self.wide = m <= chain.n  # solve the m x m system (J J^T) rather than the n x n one
        size = m if self.wide else chain.n
        self.normal = np.empty((size, size))  # work buffer of the damped normal equations
        self.diagonal = self.normal.reshape(-1)[::size + 1]  # a view of its diagonal

    def solve(self, T_base_tool: NDArray[np.float64], q0: ArrayLike | None = None,
              rng: np.random.Generator | int | None = None) -> IKResult:
        """Solve ``fk(q) = T_base_tool`` ``(4, 4)`` from ``q0`` ``(n,)``; see :func:`numeric_ik`."""
        n = self.chain.n
        q = (self.seed_low + self.seed_high) / 2.0 if q0 is None else np.asarray(q0, dtype=float)
        if q.shape != (n,) or not math.isfinite(q.sum()):
            raise InputError(f"q0: expected {n} finite joint values, got {q.tolist()}")
        error = _TargetError(np.asarray(T_base_tool, dtype=float))
        best: list = [math.inf, q, math.inf, math.inf]  # cost, q, position and orientation error
        deadline = time.perf_counter() + self.time_budget
        iterations = restarts = 0
        while True:
            q, solved, steps, errors = self._descend(error, q, best)
            iterations += steps
            if solved:
                return IKResult(q.copy(), True, iterations, restarts, *errors)
            if restarts >= self.max_restarts or time.perf_counter() > deadline:
                break
            if restarts == 0:
                rng = np.random.default_rng(rng)
            q = rng.uniform(self.seed_low, self.seed_high)
            restarts += 1
        return IKResult(best[1].copy(), False, iterations, restarts, best[2], best[3])

    def _project(self, q: NDArray[np.float64]) -> tuple[NDArray[np.float64], list[tuple[int, float]]]:
        """``q`` moved into the limits (by whole turns if that fits, else to the bound nearest
        in angle), and the joints at a bound as ``(index, -1.0 at the lower / +1.0 at the upper)``.

        The same whole-turn rule as :func:`wrap_into_limits` (with the reference at the middle
        of the limits, then clamped: equal to rounding on the built-ins), written in plain
        Python because it runs on every step: about 1 us per call against 15 us for the
        NumPy function on a 7-joint arm, which made Panda numeric IK 40-80 % slower.
        """
        if not self.respect_limits:
            return q, []
        values, held, moved = q.tolist(), [], False
        for i, (lower, upper, revolute) in enumerate(self.bounds):
            value = values[i]
            if lower < value < upper:
                continue
            if revolute and not lower <= value <= upper:
                turned = lower + (value - lower) % (2 * math.pi)  # in [lower, lower + 2 pi)
                # inside, or else at the bound nearer in angle
                value = turned if turned <= upper or turned - upper < lower + 2 * math.pi - turned else lower
            if value <= lower:
                value, side = lower, -1.0
            elif value >= upper:
                value, side = upper, 1.0
            else:
                side = 0.0
            if side:
                held.append((i, side))
            if value != values[i]:
                values[i], moved = value, True
        return (np.array(values) if moved else q), held

    def _descend(self, error: _TargetError, q: NDArray[np.float64],
                 best: list) -> tuple[NDArray[np.float64], bool, int, tuple[float, float]]:
        """One attempt from ``q``: ``(q, solved, steps, (position, orientation error))``;
        updates ``best`` with the lowest-cost configuration seen."""
        q, held = self._project(q)
        reference, since = math.inf, 0
        position_tolerance, orientation_tolerance = self.squared_tolerances
        for step in range(1, self.max_iterations + 1):
            T, J = self.kernel.pose_jacobian(q)
            e = error(T)
            if not self.all_rows:
                e *= self.weights
            e0, e1, e2, e3, e4, e5 = e.tolist()
            position, orientation = e0 * e0 + e1 * e1 + e2 * e2, e3 * e3 + e4 * e4 + e5 * e5
            cost = 0.5 * (position + orientation)
            errors = (math.sqrt(position), math.sqrt(orientation))
            if cost < best[0]:
                best[:] = cost, q, *errors
            if position <= position_tolerance and orientation <= orientation_tolerance:
                return q, True, step, errors
            if cost < _STALL_FACTOR * reference:
                reference, since = cost, 0
            else:
                since += 1
                if since >= _STALL_STEPS or not math.isfinite(cost):
                    break
            q, held = self._project(q + self._step(J, e, cost, held))
        return q, False, step, errors

    def _step(self, J: NDArray[np.float64], e: NDArray[np.float64], cost: float,
              held: list[tuple[int, float]]) -> NDArray[np.float64]:
        """The damped step ``dq`` ``(n,)``; joints held at a bound by the gradient stay put."""
        if held:
            gradient = e.dot(J).tolist()  # J^T e: the direction that lowers the error
            frozen = [i for i, side in held if gradient[i] * side > 0.0]
            if frozen:
                J = J.copy()
                J[:, frozen] = 0.0
        if not self.all_rows:
            J, e = J[self.rows], e[self.rows]
        if self.wide:
            np.dot(J, J.T, out=self.normal)
            rhs = e
        else:
            np.dot(J.T, J, out=self.normal)
            rhs = e.dot(J)
        self.diagonal += self.damping_gain * cost + self.damping
        # symmetric, so its transpose is the Fortran-ordered matrix LAPACK solves in place
        x, info = lapack.dposv(self.normal.T, rhs, overwrite_a=1)[1:]
        if info != 0:  # singular and no damping asked: the minimum-norm least-squares step
            return np.linalg.lstsq(J, e, rcond=None)[0]
        return J.T.dot(x) if self.wide else x


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
