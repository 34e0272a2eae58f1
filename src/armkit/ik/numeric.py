"""Numeric inverse kinematics for any chain: Levenberg-Marquardt with random restarts.

The solver minimises ``E = 1/2 e^T W e`` where ``e = [p_target - p; log(R_target R^T)]``
is the pose error in the base frame (metres over radians, the rotation part a rotation
vector) and ``W`` a diagonal 0/1 task mask. Each step solves the damped normal equations
of Sugihara's Levenberg-Marquardt method (T. Sugihara, "Solvability-unconcerned inverse
kinematics by the Levenberg-Marquardt method", IEEE T-RO 27(5), 2011)::

    (J^T W J + (g E + damping) I) dq = J^T W e

whose damping grows with the error far from the target and nearly vanishes near it, so
the last steps converge quadratically (Sugihara uses ``g = 1``; ``g = 0.1`` and
``damping = 1e-6`` needed the fewest iterations on random Panda poses here). Joint
values are projected onto the limits after each step. An attempt that has not converged
after ``max_iterations`` is restarted from a uniform random configuration inside the
limits until the restart or time budget runs out.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit.chain import Chain
from armkit.errors import InputError

__all__ = ["IKResult", "numeric_ik", "pose_error"]

#: Range [m] used for random seeds of prismatic joints without limits.
_UNBOUNDED_SEED_RANGE = 1.0


@dataclass(frozen=True)
class IKResult:
    """The outcome of a numeric IK solve.

    Attributes
    ----------
    q : ndarray, shape (n,)
        The best configuration found [rad or m], inside the joint limits.
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


def _check_mask(mask: ArrayLike | None) -> NDArray[np.float64]:
    if mask is None:
        return np.ones(6)
    m = np.asarray(mask, dtype=float)
    if m.shape != (6,) or not np.all((m == 0) | (m == 1)) or not m.any():
        raise InputError(f"mask: expected 6 values of 0 or 1 (x y z rx ry rz, at least one 1), "
                         f"got {np.asarray(mask).tolist()}")
    return m


def _errors(e: NDArray[np.float64], mask: NDArray[np.float64]) -> tuple[float, float]:
    ep, eo = e[:3] * mask[:3], e[3:] * mask[3:]
    return float(np.sqrt(ep @ ep)), float(np.sqrt(eo @ eo))


def numeric_ik(chain: Chain, T_base_tool: NDArray[np.float64], *, q0: ArrayLike | None = None,
               position_tolerance: float = 1e-9, orientation_tolerance: float = 1e-9,
               mask: ArrayLike | None = None, damping_gain: float = 0.1, damping: float = 1e-6,
               max_iterations: int = 30, max_restarts: int = 100, time_budget: float = 0.5,
               rng: np.random.Generator | int | None = None) -> IKResult:
    """Solve ``fk(q) = T_base_tool`` numerically inside the joint limits.

    Parameters
    ----------
    chain : Chain
    T_base_tool : ndarray, shape (4, 4)
        Target tool pose [m], assumed rigid (see :func:`armkit.spatial.check_transform`).
    q0 : array_like, shape (n,), optional
        First seed [rad or m], projected onto the limits; default the middle of the limits.
    position_tolerance, orientation_tolerance : float
        Success when the masked position error [m] and orientation error [rad] are below.
    mask : array_like, shape (6,), optional
        0/1 weights of the error components ``x y z rx ry rz`` (base frame), e.g.
        ``[1, 1, 1, 0, 0, 0]`` for a position-only target. Default all ones.
    damping_gain, damping : float
        The Levenberg-Marquardt damping is ``damping_gain * E + damping``.
    max_iterations : int
        Iterations per attempt.
    max_restarts : int
        Attempts from random seeds after the first one.
    time_budget : float
        Wall-clock budget [s] over all attempts.
    rng : numpy Generator or int, optional
        Source of the random seeds (reproducible when given).

    Returns
    -------
    IKResult
        The best configuration found; check ``success``.

    Examples
    --------
    >>> import armkit
    >>> panda = armkit.load("panda")
    >>> T = panda.fk([0.1, -0.3, 0.2, -2.0, 0.1, 1.8, 0.5])
    >>> result = numeric_ik(panda.chain, T, rng=0)
    >>> result.success, bool(result.position_error < 1e-9)
    (True, True)
    """
    kernel = _Kernel(chain)
    mask = _check_mask(mask)
    lower = np.array([j.lower for j in chain.joints])
    upper = np.array([j.upper for j in chain.joints])
    seed_low = np.where(np.isfinite(lower), lower, -_UNBOUNDED_SEED_RANGE)
    seed_high = np.where(np.isfinite(upper), upper, _UNBOUNDED_SEED_RANGE)
    if q0 is None:
        q = (seed_low + seed_high) / 2.0
    else:
        q = np.asarray(q0, dtype=float)
        if q.shape != (chain.n,) or not np.all(np.isfinite(q)):
            raise InputError(f"q0: expected {chain.n} finite joint values, got {q.tolist()}")
    q = np.clip(q, lower, upper)
    rng = np.random.default_rng(rng)
    deadline = time.perf_counter() + time_budget
    eye = np.eye(chain.n)
    best = (np.inf, q, np.inf, np.inf)
    iterations = 0
    restarts = 0
    while True:
        axes, origins, T = kernel.frames(q)
        e = pose_error(T_base_tool, T)
        for _ in range(max_iterations):
            pos_err, ori_err = _errors(e, mask)
            cost = 0.5 * float(e @ (mask * e))
            if cost < best[0]:
                best = (cost, q, pos_err, ori_err)
            if pos_err <= position_tolerance and ori_err <= orientation_tolerance:
                return IKResult(q, True, iterations, restarts, pos_err, ori_err)
            J = kernel.jacobian(axes, origins, T) * mask[:, None]
            g = J.T @ e
            H = J.T @ J + (damping_gain * cost + damping) * eye
            q = np.clip(q + np.linalg.solve(H, g), lower, upper)
            iterations += 1
            axes, origins, T = kernel.frames(q)
            e = pose_error(T_base_tool, T)
        pos_err, ori_err = _errors(e, mask)
        if pos_err <= position_tolerance and ori_err <= orientation_tolerance:
            return IKResult(q, True, iterations, restarts, pos_err, ori_err)
        if restarts >= max_restarts or time.perf_counter() > deadline:
            _, q, pos_err, ori_err = best
            return IKResult(q, False, iterations, restarts, pos_err, ori_err)
        restarts += 1
        q = rng.uniform(seed_low, seed_high)
