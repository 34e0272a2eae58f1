"""Every closed-form IK solution of a Pieper arm, a SCARA or a planar arm, vectorised.

The chain is taken as screw axes at ``q = 0`` (see :mod:`armkit.ik.structure`):
``T(q) = exp(xi_1 q_1) ... exp(xi_n q_n) M``, so the target gives ``G = T M^-1``, the
motion of the joints alone. One solver per geometric case splits ``G`` into
Paden-Kahan subproblems (:mod:`armkit.ik.subproblems`):

* spherical wrist (axes 4-6 meet at ``c``): joints 1-3 place ``c`` at ``G c`` (SP3 / SP4
  / SP2 / planar 2R, by which pair of axes 1-3 meets or is parallel; a prismatic third
  joint gives a quadratic; general axes give two equations in ``q1, q3`` solved like the
  three-parallel case), then the wrist turns ``h6`` (SP2) and a normal of it (SP1) into
  place. A spherical base is the same on the reversed chain (the chain of ``T^-1``).
* three parallel axes 2-4 with direction ``h``: rotations about them keep ``h``-components,
  which leaves two equations in ``q1, q5`` alone. If axes 5 and 6 meet, a combination of
  them holds ``q1`` only (SP4), else they give a quartic (roots of a companion matrix,
  polished by Newton steps). Then ``q6`` (SP1), ``q2 + q3 + q4`` (SP1), and a planar 2R.
  Axes 1-3 parallel give two equations in ``q4, q6`` the same way; axes 3-5 and 4-6 are
  these cases on the reversed chain.
* SCARA and planar 2R/3R: the orientation gives the sum of the angles, a prismatic joint
  along the axes the height, and a planar 2R the rest.

Candidates are computed for all poses at once in fixed-size arrays with masks. Every
subproblem says whether its branch exists, so for the closed paths the masks are exact
(an unreachable pose gives no valid candidate). Over-determined chains (SCARA, planar)
and the quartic paths are also checked by forward kinematics (``VERIFY_TOLERANCE``), the
quartic paths after two Newton steps on the full pose. Duplicates are merged.

Example
-------
>>> import numpy as np, armkit
>>> chain = armkit.load("probot-anno").chain
>>> from armkit.kinematics import fk
>>> sol = closed_form_ik(chain, fk(chain, np.array([0.3, -0.5, 0.4, 0.2, 0.6, -0.1])))
>>> int(sol.valid.sum())
8
"""

from __future__ import annotations

import weakref
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit.chain import Chain
from armkit.errors import NoClosedFormError
from armkit.ik.structure import ArmStructure, SolverPlan, plan_closed_form
from armkit.ik.subproblems import (
    FREE_TOLERANCE,
    cos_sin,
    cross,
    dot,
    rotate,
    solve_trig_linear,
    sp1,
    sp2,
    sp3,
    sp4,
)
from armkit.kinematics import fk, geometric_jacobian, pose_error
from armkit.spatial.transforms import check_transform

__all__ = ["ClosedFormSolutions", "ClosedFormSolver", "closed_form_ik", "closed_form_solver",
           "VERIFY_TOLERANCE", "DUPLICATE_TOLERANCE"]

#: A candidate counts only if its FK matches the target to this, times ``1 + arm size``
#: (entries of the 4x4 matrix, metres / dimensionless). It only rejects non-solutions:
#: the solutions themselves reproduce reachable poses to about 1e-13.
VERIFY_TOLERANCE = 1e-8
#: Poses solved together: enough to amortise NumPy's cost per call, few enough that the
#: temporaries (``CHUNK x 8 x 6`` candidates) stay in the CPU cache.
CHUNK = 1024
#: Candidates closer than this in every joint [rad or m, modulo 2 pi] are one solution.
DUPLICATE_TOLERANCE = 1e-9

Array = NDArray[np.float64]
Mask = NDArray[np.bool_]
Snap = Callable[[Array, Array, Array, Array], tuple[Array, Array]]


@dataclass(frozen=True)
class ClosedFormSolutions:
    """Candidate solutions of closed-form IK for a batch of poses.

    Attributes
    ----------
    q : ndarray (..., k_max, n)
        Candidate joint values [rad or m]; revolute ones in ``[-pi, pi]``, not fitted to
        the joint limits and not filtered by them.
    valid : ndarray of bool (..., k_max)
        The candidate is a solution (reproduces the pose; duplicates are invalid).
    family : ndarray of bool (..., k_max)
        The candidate is a representative of a one-parameter family of solutions (wrist
        singularity: only ``q4 + q6`` defined; shoulder singularity: ``q1`` free, ...).
    """

    q: Array
    valid: Mask
    family: Mask


def _planar_2r(h: Array, a: Array, b: Array, v: Array) -> tuple[Array, Array, Mask, Mask]:
    """All ``(ta, tb)`` with ``R(h, ta) (a + R(h, tb) b) = v`` in the plane normal to ``h``.

    Components along ``h`` are ignored (the caller makes them consistent). Shapes
    broadcast; results ``(..., 2)``; ``free``: the middle point lies on the first axis.
    """
    a = a - dot(a, h)[..., None] * h
    b = b - dot(b, h)[..., None] * h
    v = v - dot(v, h)[..., None] * h
    tb, valid, free_b = sp3(b, -a, h, np.sqrt(dot(v, v)))
    # ta: SP1 turning u = a + R(h, tb) b onto v. With b normal to h, R(h, tb) b = cos b +
    # sin (h x b), so (h x u) . v and u . v are linear in cos tb, sin tb.
    hbv, bv = dot(cross(h, b), v)[..., None], dot(b, v)[..., None]
    cos, sin = cos_sin(tb)
    ta = np.arctan2(dot(cross(h, a), v)[..., None] + cos * hbv - sin * bv,
                    dot(a, v)[..., None] + cos * bv + sin * hbv)
    hxv = cross(h, v)
    free_a = np.broadcast_to((dot(hxv, hxv) <= FREE_TOLERANCE ** 2 * dot(v, v))[..., None], ta.shape)
    return np.where(free_a, 0.0, ta), tb, valid, free_a | free_b[..., None]


def _matvec(R: Array, v: Array) -> Array:
    """``R v`` for one matrix per pose ``(N, 3, 3)`` and vectors ``(N, ..., 3)``."""
    return (v.reshape(len(v), -1, 3) @ np.swapaxes(R, -1, -2)).reshape(v.shape)


def _matvec_transposed(R: Array, v: Array) -> Array:
    """``R^T v`` for one matrix per pose ``(N, 3, 3)`` and vectors ``(N, ..., 3)``."""
    return (v.reshape(len(v), -1, 3) @ R).reshape(v.shape)


def _transform_point(R: Array, t: Array, p: Array) -> Array:
    """``R p + t`` for rotations ``(..., 3, 3)``, translations ``(..., 3)``, a point ``(3,)``."""
    return R @ p + t


def _unit_normal(h: Array) -> Array:
    """A unit vector perpendicular to ``h``."""
    e = np.eye(3)[np.argmin(np.abs(h))]
    u = np.cross(h, e)
    return u / np.linalg.norm(u)


def _trig_coeffs(h: Array, k: Array, v: Array) -> tuple[Array, Array, Array]:
    """``h . R(k, t) v = const + cos_coeff cos t + sin_coeff sin t`` (broadcasting)."""
    hk = h @ k if h.ndim == 1 else dot(h, k)
    kv = dot(k, v)
    return hk * kv, dot(h, v) - hk * kv, dot(h, cross(k, v))


class _TwoAngleSystem:
    """All ``(t1, t2)`` with ``P x(t1) - Q x(t2) = r``, ``x(t) = [cos t, sin t]``.

    Two equations, each first order in both angles, with ``Q`` fixed by the chain and
    ``P (N, 2, 2)``, ``r (N, 2)`` by the pose. If ``Q`` has rank 1, a combination of the
    equations holds ``t1`` alone (SP4-like, then ``t2`` the same way): up to 2 x 2 pairs.
    Otherwise ``x(t2) = Q^-1 (P x(t1) - r)`` on the unit circle is a quartic in
    ``exp(i t1)`` (companion matrix, then Newton steps on the equations themselves).
    """

    def __init__(self, Q: Array, snap_t2: bool = True) -> None:
        self.Q = Q
        self._snap_t2 = snap_t2
        U, S, _ = np.linalg.svd(Q)
        self.rank1 = bool(S[1] <= 1e-9 * S[0])
        self._lam, self._mu = U[:, 1], U[:, 0]

    def solve(self, P: Array, r: Array, snap: Snap | None = None) -> tuple[Array, Array, Mask, Mask]:
        """``(t1, t2, valid, free)``, each ``(N, 4)``; ``free``: ``t1`` is arbitrary.

        ``snap(P, r, t1, t2) -> (t1, t2)`` may move quartic roots onto known exact values.
        """
        scale = 1.0 + np.abs(P).max(axis=(-1, -2)) + np.abs(r).max(axis=-1)
        N = len(r)
        if self.rank1:
            lam, mu = self._lam, self._mu
            lP, lr = lam @ P, r @ lam
            t1, v1, f1 = solve_trig_linear(lP[:, 0], lP[:, 1], lr, scale)
            mP = (mu @ P)[:, None, :]
            if f1.any():  # t1 free: the member whose t2 equation is easiest (middle of its range)
                t1 = np.where(f1[:, None], self._family_representative(mP[:, 0], r @ mu)[:, None], t1)
            cos1, sin1 = cos_sin(t1)
            rhs = mP[..., 0] * cos1 + mP[..., 1] * sin1 - (r @ mu)[:, None]
            mQ = mu @ self.Q
            t2, v2, f2 = solve_trig_linear(mQ[0], mQ[1], rhs, scale[:, None], snap=self._snap_t2)
            t1 = np.broadcast_to(t1[:, :, None], t2.shape)
            valid = v1[:, :, None] & v2
            free = np.broadcast_to(f1[:, None, None] | f2[..., None], valid.shape)
            return t1.reshape(N, 4), t2.reshape(N, 4), valid.reshape(N, 4), free.reshape(N, 4)
        t1, t2, valid = self._quartic(P, r)
        t1, t2, residual = self._polish(P, r, t1, t2)
        if snap is not None:
            t1, t2 = snap(P, r, t1, t2)
        valid = valid & (residual <= 1e-10 * scale[:, None])
        return t1, t2, valid, np.zeros_like(valid)

    @staticmethod
    def _family_representative(mP: Array, mr: Array) -> Array:
        """``t1`` with ``mP . x(t1) = mr`` (or as close as it gets), ``(N,)``.

        When the first equation leaves ``t1`` free, the second, ``mP . x(t1) - mQ . x(t2) =
        mr``, still ties ``t2`` to it; this ``t1`` puts its right-hand side at 0, the middle
        of the range ``t2`` can reach.
        """
        m = np.sqrt(mP[:, 0] ** 2 + mP[:, 1] ** 2)
        cos = np.clip(mr / np.where(m > 0, m, 1.0), -1.0, 1.0)
        return np.where(m > 0, np.arctan2(mP[:, 1], mP[:, 0]) + np.arccos(cos), 0.0)

    def _quartic(self, P: Array, r: Array) -> tuple[Array, Array, Mask]:
        """Roots of the quartic in ``exp(i t1)`` with ``t2`` from ``Q^-1``: ``(N, 4)`` each."""
        Q_inv = np.linalg.inv(self.Q)
        W = Q_inv @ P
        w0 = r @ Q_inv.T
        S = np.swapaxes(W, -1, -2) @ W
        m = (np.swapaxes(W, -1, -2) @ w0[..., None])[..., 0]
        z0 = dot2(w0, w0) - 1.0
        # F(t) = A0 + A1 cos t + B1 sin t + A2 cos 2t + B2 sin 2t
        A0 = 0.5 * (S[:, 0, 0] + S[:, 1, 1]) + z0
        A1, B1 = -2.0 * m[:, 0], -2.0 * m[:, 1]
        A2, B2 = 0.5 * (S[:, 0, 0] - S[:, 1, 1]), S[:, 0, 1]
        # z^2 F in z = exp(i t): coefficients of z^4 ... z^0
        coeffs = np.stack([(A2 - 1j * B2) / 2, (A1 - 1j * B1) / 2, A0 + 0j,
                           (A1 + 1j * B1) / 2, (A2 + 1j * B2) / 2], axis=-1)
        scale = np.abs(coeffs).max(axis=-1)
        lead = coeffs[:, 0]
        quartic = np.abs(lead) > 1e-12 * scale
        companion = np.zeros((len(r), 4, 4), dtype=complex)
        companion[:, 1:, :3] = np.eye(3)
        companion[:, 0, :] = -coeffs[:, 1:] / np.where(quartic, lead, 1.0)[:, None]
        roots = np.linalg.eigvals(companion)
        t = np.angle(roots)
        on_circle = np.abs(np.abs(roots) - 1.0) <= 1e-6
        for _ in range(3):  # Newton on F(t), the real equation
            c, s, c2, s2 = np.cos(t), np.sin(t), np.cos(2 * t), np.sin(2 * t)
            F = A0[:, None] + A1[:, None] * c + B1[:, None] * s + A2[:, None] * c2 + B2[:, None] * s2
            dF = -A1[:, None] * s + B1[:, None] * c - 2 * A2[:, None] * s2 + 2 * B2[:, None] * c2
            step = np.where(np.abs(dF) > 1e-300, F / np.where(dF == 0, 1.0, dF), 0.0)
            t = t - np.clip(step, -0.1, 0.1)
        # degenerate (|lead| ~ 0): F is of degree 1, a cos t + b sin t = -A0
        t_lin, v_lin, _ = solve_trig_linear(A1, B1, -A0, scale)
        t = np.where(quartic[:, None], t, np.concatenate([t_lin, t_lin], axis=-1))
        valid = np.where(quartic[:, None], on_circle,
                         np.concatenate([v_lin, np.zeros_like(v_lin)], axis=-1))
        x1 = np.stack([np.cos(t), np.sin(t)], axis=-1)
        x2 = (W[:, None] @ x1[..., None])[..., 0] - w0[:, None, :]
        return t, np.arctan2(x2[..., 1], x2[..., 0]), valid

    def _polish(self, P: Array, r: Array, t1: Array, t2: Array) -> tuple[Array, Array, Array]:
        """Newton steps on ``P x(t1) - Q x(t2) = r`` itself (Q^-1 may be ill-conditioned).

        Returns the polished angles and the remaining residual ``max |P x(t1) - Q x(t2) - r|``.
        """
        Q = self.Q
        for _ in range(6):  # quadratic convergence; linear near a double root
            c1, s1, c2, s2 = np.cos(t1), np.sin(t1), np.cos(t2), np.sin(t2)
            x1 = np.stack([c1, s1], axis=-1)
            x2 = np.stack([c2, s2], axis=-1)
            F = (P[:, None] @ x1[..., None])[..., 0] - x2 @ Q.T - r[:, None, :]
            d1 = (P[:, None] @ np.stack([-s1, c1], axis=-1)[..., None])[..., 0]
            d2 = -np.stack([-s2, c2], axis=-1) @ Q.T
            det = d1[..., 0] * d2[..., 1] - d1[..., 1] * d2[..., 0]
            ok = np.abs(det) > 1e-12 * (1.0 + np.abs(d1).max(-1) * np.abs(d2).max(-1))
            det = np.where(ok, det, 1.0)
            step1 = np.where(ok, (d2[..., 1] * F[..., 0] - d2[..., 0] * F[..., 1]) / det, 0.0)
            step2 = np.where(ok, (d1[..., 0] * F[..., 1] - d1[..., 1] * F[..., 0]) / det, 0.0)
            t1, t2 = t1 - np.clip(step1, -0.1, 0.1), t2 - np.clip(step2, -0.1, 0.1)
        x1 = np.stack([np.cos(t1), np.sin(t1)], axis=-1)
        x2 = np.stack([np.cos(t2), np.sin(t2)], axis=-1)
        F = (P[:, None] @ x1[..., None])[..., 0] - x2 @ Q.T - r[:, None, :]
        return t1, t2, np.abs(F).max(axis=-1)


class ClosedFormSolver:
    """Closed-form IK of one chain, with everything that depends only on the chain cached.

    Build it with :func:`closed_form_solver` (memoised per chain).
    """

    def __init__(self, chain: Chain, plan: SolverPlan) -> None:
        self.chain = chain
        self.structure: ArmStructure = plan.structure
        self._plan = plan
        poe = plan.poe
        self._poe = poe
        size = 1.0 + max(np.abs(poe.points).max(), np.abs(poe.M[:3, 3]).max())
        self._verify_tol = VERIFY_TOLERANCE * size
        M_inv = np.eye(4)
        M_inv[:3, :3] = poe.M[:3, :3].T
        M_inv[:3, 3] = -poe.M[:3, :3].T @ poe.M[:3, 3]
        self._M_inv = M_inv
        self._revolute_user = ~chain.prismatic
        self._prismatic_user = chain.prismatic.tolist()
        self._after_T = np.swapaxes(chain.T_between[1:], -1, -2).copy()  # rows @ C = C^T @ columns
        kind = plan.structure.kind
        # Over-determined chains (fewer than 6 joints) must be checked by FK; for 6 joints
        # every subproblem checks its own existence, so the masks are exact.
        self._verify = chain.n < 6
        self._polish_by_newton = False
        if kind in ("spherical-wrist", "spherical-base"):
            self._k = 8
            self._u6 = _unit_normal(poe.axes[5])
            self._solve = self._spherical
            if plan.case == "general-123":
                self._setup_general_position()
        elif kind == "three-parallel" and plan.case == "parallel-123":
            self._k = 8
            self._setup_parallel_base()
            self._solve = self._parallel_base
        elif kind == "three-parallel":
            self._k = 8
            self._setup_three_parallel()
            self._solve = self._three_parallel
        else:
            self._k = 2
            self._setup_planar()
            self._solve = self._planar
        self._pairs = np.triu_indices(self._k, 1)  # candidate pairs (earlier, later)
        self._identity_map = bool(np.all(poe.index == np.arange(poe.n)) and np.all(poe.sign == 1))

    # ------------------------------------------------------------------ public
    def solve(self, T_base_tool: ArrayLike) -> ClosedFormSolutions:
        """All candidates for poses ``(4, 4)`` or ``(..., 4, 4)``; see :func:`closed_form_ik`."""
        T = check_transform(T_base_tool, "T_base_tool")
        batch = T.shape[:-2]
        T = T.reshape(-1, 4, 4)
        chunks = [self.candidates(T[i:i + CHUNK]) for i in range(0, len(T), CHUNK)]
        q, valid, family = (np.concatenate(part) for part in zip(*chunks, strict=True))
        k, n = q.shape[-2:]
        return ClosedFormSolutions(q.reshape(*batch, k, n), valid.reshape(*batch, k),
                                   family.reshape(*batch, k))

    def candidates(self, T: Array, merge: bool = True) -> tuple[Array, Mask, Mask]:
        """``(q, valid, family)`` ``(N, k, n)``, ``(N, k)`` for checked poses ``T`` ``(N, 4, 4)``.

        Solves all ``N`` poses in one set of array operations; :meth:`solve` feeds it
        ``CHUNK`` poses at a time. ``merge=False`` keeps duplicate candidates valid (for a
        caller that wants only the nearest one).
        """
        T_int = T
        if self._poe.inverted:
            R_t = np.swapaxes(T[:, :3, :3], -1, -2)
            T_int = np.zeros_like(T)
            T_int[:, :3, :3] = R_t
            T_int[:, :3, 3] = -(R_t @ T[:, :3, 3, None])[..., 0]
            T_int[:, 3, 3] = 1.0
        G = T_int @ self._M_inv
        q_int, valid, family = self._solve(G[:, :3, :3], G[:, :3, 3])
        if self._identity_map:
            q = np.array(q_int, dtype=float)
        else:
            q = np.empty_like(q_int)
            q[..., self._poe.index] = q_int * self._poe.sign
        if self._polish_by_newton:
            q = self._newton(q, T, valid)
        turns = np.round(q * (0.5 / np.pi)) * (2 * np.pi)
        q -= turns if self._revolute_user.all() else turns * self._revolute_user
        if self._verify:
            valid = valid & self._reproduces(q, T)
        if merge:
            valid = valid & ~self._duplicates(q, valid)
        return q, valid, family & valid

    def pose_difference(self, q: Array, T: Array) -> Array:
        """``fk(q) - T`` in the top three rows for candidates ``q`` ``(N, k, n)``: ``(3, 4, k, N)``.

        A lean forward kinematics for verification, component-major so that every array
        operation runs over all ``k N`` candidates at once: per joint its motion on two
        columns, then the next fixed transform as one matrix product. It is kept apart from
        :func:`armkit.kinematics.fk` (batch-first ``(..., 4, 4)``, one small 4 x 4 product
        per candidate and joint) because on the verification batches it is 3 to 5 times
        faster: 0.38 ms against 2.1 ms for the UR5 at ``N = 256, k = 8``, and about equal at
        ``N = 1`` (timeit on the 2-core development machine); tests/test_ik_closed_form.py
        checks it against :func:`~armkit.kinematics.fk`.
        """
        N, k, n = q.shape
        q = np.swapaxes(q, 0, 1).reshape(k * N, n).T  # (n, k N), candidate-major
        cos, sin = cos_sin(q)
        rows = np.empty((3, 4, k * N))
        rows[...] = self.chain.T_between[0][:3, :, None]
        for j, prismatic in enumerate(self._prismatic_user):
            if prismatic:
                rows[:, 3] += q[j] * rows[:, 2]
            else:
                x, y = rows[:, 0], rows[:, 1]
                rows[:, 0], rows[:, 1] = cos[j] * x + sin[j] * y, cos[j] * y - sin[j] * x
            rows = self._after_T[j] @ rows
        return rows.reshape(3, 4, k, N) - np.moveaxis(T[:, :3, :], 0, -1)[:, :, None, :]

    # ----------------------------------------------------------- verification
    def _newton(self, q: Array, T: Array, valid: Mask, steps: int = 2) -> Array:
        """Newton steps on the full pose for the valid candidates (quartic paths only).

        Where a quartic root meets another singularity (a double root near an aligned
        wrist), the candidates may carry errors of ~1e-7; two damped Newton steps on
        ``fk(q) = T`` bring them to rounding level, and :meth:`_reproduces` then decides.
        """
        target = T[:, None]
        moving = (valid & np.isfinite(q).all(axis=-1))[..., None]  # invalid ones may be NaN
        for _ in range(steps):
            q_moving = np.where(moving, q, 0.0)
            e = pose_error(target, fk(self.chain, q_moving))
            J = geometric_jacobian(self.chain, q_moving)
            JJt = J @ np.swapaxes(J, -1, -2) + 1e-14 * np.eye(6)
            step = (np.swapaxes(J, -1, -2) @ np.linalg.solve(JJt, e[..., None]))[..., 0]
            q = np.where(moving, q + step, q)
        return q

    def _reproduces(self, q: Array, T: Array) -> Mask:
        return (np.abs(self.pose_difference(q, T)).max(axis=(0, 1)) <= self._verify_tol).T

    def _duplicates(self, q: Array, valid: Mask) -> Mask:
        """Candidates equal (modulo 2 pi) to an earlier valid one, ``(N, k)``.

        Equal candidates have sums of joint values equal modulo 2 pi: that cheap test
        picks the few pairs that are then compared joint by joint.
        """
        first, second = self._pairs
        total = q.sum(axis=-1)
        d = total[:, first] - total[:, second]
        d -= np.round(d * (0.5 / np.pi)) * (2 * np.pi)
        rows, pairs = np.nonzero((np.abs(d) <= q.shape[-1] * DUPLICATE_TOLERANCE) & valid[:, first])
        duplicate = np.zeros(valid.shape, dtype=bool)
        if rows.size:
            diff = np.abs(q[rows, first[pairs]] - q[rows, second[pairs]])
            rev = self._revolute_user
            diff[:, rev] = np.minimum(diff[:, rev], 2 * np.pi - diff[:, rev])
            same = np.all(diff <= DUPLICATE_TOLERANCE, axis=-1)
            duplicate[rows[same], second[pairs[same]]] = True
        return duplicate

    # -------------------------------------------------------- spherical wrist
    def _wrist_centre_joints(self, w: Array) -> tuple[Array, Mask, Mask]:
        """Joints 1-3 that put the wrist centre ``c`` at ``w`` (N, 3): ``(N, 4, 3)``."""
        poe, case, c, o = self._poe, self._plan.case, self._plan.point, self._plan.point2
        h, p = poe.axes, poe.points
        N = len(w)
        if case == "general-123":
            return self._general_position(w)
        if case == "parallel-23":
            q1, v1, f1 = sp4(h[1], w - p[0], -h[0], np.full(N, h[1] @ (c - p[0])))
            y = p[0] + rotate(-h[0], q1, (w - p[0])[:, None, :])
            q2, q3, v23, f23 = _planar_2r(h[1], p[2] - p[1], c - p[2], y - p[1])
            q1 = np.broadcast_to(q1[:, :, None], q2.shape)
            valid, free = v1[:, :, None] & v23, f1[:, None, None] | f23
        elif case == "parallel-12":
            q3, v3, f3 = sp4(h[0], c - p[2], h[2], (w - p[2]) @ h[0])
            x = p[2] + rotate(h[2], q3, c - p[2])
            q1, q2, v12, f12 = _planar_2r(h[0], p[1] - p[0], x - p[1], (w - p[0])[:, None, :])
            q3 = np.broadcast_to(q3[:, :, None], q1.shape)
            valid, free = v3[:, :, None] & v12, f3[:, None, None] | f12
        elif case == "intersect-23":
            q1, v1, f1 = sp3(w - p[0], o - p[0], -h[0], np.full(N, np.linalg.norm(c - o)))
            y = p[0] + rotate(-h[0], q1, (w - p[0])[:, None, :])
            q2, q3, v23, f2, f3 = sp2(y - o, c - o, -h[1], h[2])
            q1 = np.broadcast_to(q1[:, :, None], q2.shape)
            valid = v1[:, :, None] & v23
            free = (f1[:, None] | f2 | f3)[:, :, None] & np.ones(2, dtype=bool)
        else:  # intersect-12-revolute / intersect-12-prismatic
            d = np.linalg.norm(w - o, axis=-1)
            if case.endswith("prismatic"):
                q3, v3 = self._slide_to_sphere(c - o, h[2], d)
                x = c + q3[..., None] * h[2]
                f3 = np.zeros(N, dtype=bool)
            else:
                q3, v3, f3 = sp3(c - p[2], o - p[2], h[2], d)
                x = p[2] + rotate(h[2], q3, c - p[2])
            q1, q2, v12, f1, f2 = sp2((w - o)[:, None, :], x - o, -h[0], h[1])
            q3 = np.broadcast_to(q3[:, :, None], q1.shape)
            valid = v3[:, :, None] & v12
            free = f3[:, None, None] | (f1 | f2)[:, :, None]
        q = np.stack([q1, q2, q3], axis=-1).reshape(N, 4, 3)
        return q, valid.reshape(N, 4), np.broadcast_to(free, valid.shape).reshape(N, 4)

    def _setup_general_position(self) -> None:
        """Axes 1-3 general: two equations in q1 and q3 alone, a :class:`_TwoAngleSystem`.

        With ``y = e1^-1 G c`` (q1) and ``x = e3 c`` (q3), ``e2 x = y`` keeps the height along
        axis 2 and the distance to a point ``o2`` of it: ``h2 . (y - o2) = h2 . (x - o2)`` and
        ``|y - o2|^2 = |x - o2|^2``, each first order in its angle.
        """
        h, p, c = self._poe.axes, self._poe.points, self._plan.point
        A = np.stack([h[1], -h[2]], axis=1)
        s, t = np.linalg.lstsq(A, p[2] - p[1], rcond=None)[0]
        self._o2, self._o3 = p[1] + s * h[1], p[2] + t * h[2]  # closest points of axes 2, 3
        o2, o3 = self._o2, self._o3
        height = _trig_coeffs(h[1], h[2], c - o3)
        distance = _trig_coeffs(2.0 * (o3 - o2), h[2], c - o3)
        self._Q = np.array([[height[1], height[2]], [distance[1], distance[2]]])
        self._f = np.array([height[0] + h[1] @ (o3 - o2),
                            distance[0] + (o3 - o2) @ (o3 - o2) + (c - o3) @ (c - o3)])
        self._pair = _TwoAngleSystem(self._Q)
        self._verify = self._polish_by_newton = True

    def _general_position(self, w: Array) -> tuple[Array, Mask, Mask]:
        """Joints 1-3 for general axes (see :meth:`_setup_general_position`), ``(N, 4, 3)``."""
        h, p, c = self._poe.axes, self._poe.points, self._plan.point
        o2, o3 = self._o2, self._o3
        u = w - p[0]
        e_h, a_h, b_h = _trig_coeffs(h[1], -h[0], u)
        e_d, a_d, b_d = _trig_coeffs(2.0 * (p[0] - o2), -h[0], u)
        e_h = e_h + h[1] @ (p[0] - o2)
        e_d = e_d + (p[0] - o2) @ (p[0] - o2) + dot(u, u)
        P = np.stack([np.stack([a_h, b_h], -1), np.stack([a_d, b_d], -1)], -2)
        r = self._f - np.stack([e_h, e_d], axis=-1)
        q1, q3, valid, free = self._pair.solve(P, r)
        y = p[0] + rotate(-h[0], q1, u[:, None, :])
        x = o3 + rotate(h[2], q3, c - o3)
        q2, free2 = sp1(x - o2, y - o2, h[1])
        return np.stack([q1, q2, q3], axis=-1), valid, free | free2

    @staticmethod
    def _slide_to_sphere(v: Array, h: Array, d: Array) -> tuple[Array, Mask]:
        """Both ``s`` with ``|v + s h| = d``: ``(N, 2)`` and the mask of real roots."""
        b = v @ h
        disc = b * b - (v @ v) + d * d
        exists = disc >= -1e-9 * (v @ v + d * d)
        root = np.sqrt(np.maximum(disc, 0.0))
        s = np.stack([-b + root, -b - root], axis=-1)
        return s, np.stack([exists, exists & (disc > 0)], axis=-1)

    def _spherical(self, R_G: Array, t_G: Array) -> tuple[Array, Mask, Mask]:
        """Spherical wrist: joints 1-3 for the wrist centre, then the wrist: ``(N, 8, 6)``."""
        poe = self._poe
        h = poe.axes
        N = len(t_G)
        w = _transform_point(R_G, t_G, self._plan.point)
        q123, valid, free = self._wrist_centre_joints(w)
        # the wrist's rotation R_w = R123^T R_G, applied to h6 and a normal u of it
        u = self._u6
        vectors = np.stack([R_G @ h[5], R_G @ u], axis=1)[:, None]  # (N, 1, 2, 3)
        for j in range(3):
            if not poe.prismatic[j]:
                vectors = rotate(-h[j], q123[:, :, None, j], vectors)
        q4, q5, v45, f4, f5 = sp2(vectors[:, :, 0], h[5], -h[3], h[4])
        # R6 u = R5^T R4^T R_w u
        target = rotate(-h[4], q5, rotate(-h[3], q4, vectors[:, :, None, 1]))
        q6, f6 = sp1(u, target, h[5])
        q = np.concatenate([np.broadcast_to(q123[:, :, None, :], (N, 4, 2, 3)),
                            np.stack([q4, q5, q6], axis=-1)], axis=-1)
        valid = valid[:, :, None] & v45
        family = free[:, :, None] | (f4 | f5)[:, :, None] | f6
        return q.reshape(N, 8, 6), valid.reshape(N, 8), family.reshape(N, 8)

    # ---------------------------------------------------- three parallel axes
    def _setup_three_parallel(self) -> None:
        poe = self._poe
        h, p = poe.axes, poe.points
        self._h = h[1]
        # closest points of axes 5 and 6 (joint indices 4 and 5)
        A = np.stack([h[4], -h[5]], axis=1)
        s, t = np.linalg.lstsq(A, p[5] - p[4], rcond=None)[0]
        self._p5, self._p6 = p[4] + s * h[4], p[5] + t * h[5]
        # right-hand sides h . R(h5, q5) v = const + c cos q5 + d sin q5, for v = h6, p6 - p5
        rows = [_trig_coeffs(self._h, h[4], v) for v in (h[5], self._p6 - self._p5)]
        self._Q = np.array([[r[1], r[2]] for r in rows])
        self._f = np.array([r[0] for r in rows]) + np.array([0.0, self._h @ (self._p5 - p[0])])
        # q5 near an aligned wrist is refined from sines, so its cosine equation must not snap
        self._pair = _TwoAngleSystem(self._Q, snap_t2=False)
        # axes 5 and 6 skew: roots of a quartic, polished on the full pose and checked by FK
        self._polish_by_newton = self._verify = not self._pair.rank1
        # values of q5 that turn axis 6 parallel to h (a UR-like wrist singularity)
        q5, ok, _ = sp4(self._h, h[5], h[4], np.array([1.0, -1.0]))
        self._q5_aligned = q5[ok]
        self._b_aligned = np.linalg.norm(np.cross(h[4], self._h)) * np.linalg.norm(np.cross(h[4], h[5]))
        self._u_h = _unit_normal(self._h)

    def _q1_q5(self, R_G: Array, t_G: Array) -> tuple[Array, Array, Mask, Mask]:
        """The (q1, q5) pairs: ``(N, 4)`` each, validity, shoulder family."""
        poe = self._poe
        h1, p1 = poe.axes[0], poe.points[0]
        u1 = R_G @ poe.axes[5]
        u2 = _transform_point(R_G, t_G, self._p6) - p1
        e1, a1, b1 = _trig_coeffs(self._h, -h1, u1)
        e2, a2, b2 = _trig_coeffs(self._h, -h1, u2)
        P = np.stack([np.stack([a1, b1], -1), np.stack([a2, b2], -1)], -2)  # (N, 2, 2)
        r = self._f - np.stack([e1, e2], axis=-1)  # P x1 - Q x5 = r
        if self._pair.rank1:
            q1, q5, valid, free = self._pair.solve(P, r)
            return q1, self._q5_near_aligned_wrist(R_G, q1, q5), valid, free
        return self._pair.solve(P, r, self._snap_to_aligned_wrist)

    def _q5_near_aligned_wrist(self, R_G: Array, q1: Array, q5: Array) -> Array:
        """Near an aligned wrist, q5 from a sine (accurate) rather than a cosine (~1e-8).

        ``h6 . R5^T h`` is the cosine-like quantity the equations give; at a distance ``d``
        from the aligned value it differs from +-1 by ``b (1 - cos d)`` only, lost below
        d ~ 1e-8. The length ``S = |h6 x R5^T h| = |h6 x R_G^T R1 h|`` is computed from
        vectors, so it keeps its relative accuracy: ``b (1 - cos d) = S^2 / (1 + sqrt(1 -
        S^2))``. The two branches straddle the aligned value (+d and -d).
        """
        if self._q5_aligned.size == 0:
            return q5
        gap = q5[..., None] - self._q5_aligned
        gap -= np.round(gap * (0.5 / np.pi)) * (2 * np.pi)
        nearest = np.argmin(np.abs(gap), axis=-1)
        gap = np.take_along_axis(gap, nearest[..., None], axis=-1)[..., 0]
        rows, cols = np.nonzero(np.abs(gap) <= 1e-3)
        if rows.size == 0:
            return q5
        v = _matvec_transposed(R_G[rows], rotate(self._poe.axes[0], q1[rows, cols], self._h))
        c = cross(self._poe.axes[5], v)
        S2 = np.minimum(dot(c, c), 1.0)
        one_minus_cos = S2 / (1.0 + np.sqrt(1.0 - S2)) / self._b_aligned
        d = 2.0 * np.arcsin(np.minimum(np.sqrt(0.5 * one_minus_cos), 1.0))
        gap = gap[rows, cols]
        branch = np.where(cols % 2 == 0, 1.0, -1.0)  # (+d, -d) pairs
        sign = np.where(gap > 0, 1.0, np.where(gap < 0, -1.0, branch))
        q5 = q5.copy()
        q5[rows, cols] = self._q5_aligned[nearest[rows, cols]] + sign * d
        return q5

    def _snap_to_aligned_wrist(self, P: Array, r: Array, q1: Array, q5: Array
                               ) -> tuple[Array, Array]:
        """Put q5 exactly where axis 6 is parallel to h when a root is that close to it.

        There the quartic has a double root, which Newton steps reach only to ~1e-8; the
        exact value lets the family (``q6`` against ``q2 + q3 + q4``) be recognised. ``q1``
        is then solved from ``P x1 = r + Q x5`` (a 2x2 linear system).
        """
        if self._q5_aligned.size == 0:
            return q1, q5
        gap = q5[..., None] - self._q5_aligned
        gap = np.abs(gap - np.round(gap * (0.5 / np.pi)) * (2 * np.pi))
        near = gap.min(axis=-1) <= 1e-6
        if not near.any():
            return q1, q5
        q5_snap = self._q5_aligned[np.argmin(gap, axis=-1)]
        rhs = r[:, None, :] + np.stack([np.cos(q5_snap), np.sin(q5_snap)], axis=-1) @ self._pair.Q.T
        det = P[:, 0, 0] * P[:, 1, 1] - P[:, 0, 1] * P[:, 1, 0]
        ok = near & (np.abs(det) > 1e-9 * (1.0 + np.abs(P).max(axis=(-1, -2))))[:, None]
        det = np.where(np.abs(det) > 0, det, 1.0)[:, None]
        c1 = (P[:, None, 1, 1] * rhs[..., 0] - P[:, None, 0, 1] * rhs[..., 1]) / det
        s1 = (P[:, None, 0, 0] * rhs[..., 1] - P[:, None, 1, 0] * rhs[..., 0]) / det
        return np.where(ok, np.arctan2(s1, c1), q1), np.where(ok, q5_snap, q5)

    def _three_parallel(self, R_G: Array, t_G: Array) -> tuple[Array, Mask, Mask]:
        """Axes 2-4 parallel: (q1, q5), then q6, q2 + q3 + q4 and a planar 2R: ``(N, 8, 6)``."""
        poe = self._poe
        h_all, p = poe.axes, poe.points
        h, N = self._h, len(t_G)
        q1, q5, valid, free = self._q1_q5(R_G, t_G)
        # q6: R6^T (R5^T h) = R_G^T R1 h
        v = rotate(-h_all[4], q5, h)
        w = _matvec_transposed(R_G, rotate(h_all[0], q1, h))
        q6, f6 = sp1(v, w, -h_all[5])
        # q2 + q3 + q4: R234 = R1^T R_G R6^T R5^T, applied to a normal of h
        turned = rotate(-h_all[5], q6, rotate(-h_all[4], q5, self._u_h))
        turned = rotate(-h_all[0], q1, _matvec(R_G, turned))
        theta, _ = sp1(self._u_h, turned, h)
        # planar part: e2 e3 e4 y = z with y = e5 p6, z = e1^-1 G p6
        y = self._p5 + rotate(h_all[4], q5, self._p6 - self._p5)
        z = p[0] + rotate(-h_all[0], q1, (_transform_point(R_G, t_G, self._p6) - p[0])[:, None, :])
        if f6.any():
            s6 = np.sign(dot(v, h_all[5]))  # axis 6 along (+1) or against (-1) h at this q5
            q6, theta = self._wrist_family_representative(f6, s6, q6, theta, z - p[1], y - p[3])
        target = z - p[1] - rotate(h, theta, y - p[3])
        q2, q3, v23, f23 = _planar_2r(h, p[2] - p[1], p[3] - p[2], target)
        q4 = theta[..., None] - q2 - q3

        q = np.empty((*q2.shape, 6))
        q[..., 0], q[..., 1], q[..., 2] = q1[..., None], q2, q3
        q[..., 3], q[..., 4], q[..., 5] = q4, q5[..., None], q6[..., None]
        valid = valid[..., None] & v23
        family = (free | f6)[..., None] | f23
        return q.reshape(N, 8, 6), valid.reshape(N, 8), family.reshape(N, 8)

    def _wrist_family_representative(self, free: Mask, s6: Array, q6: Array, theta: Array,
                                     A: Array, B: Array) -> tuple[Array, Array]:
        """Axis 6 parallel to axes 2-4: pick the ``q6`` of the family that is best reachable.

        Along the family ``q2 + q3 + q4 = theta - s q6`` (``s = +-1``: axis 6 along or against
        ``h``) the planar target ``A - R(h, theta) B`` turns on a circle; choose the angle
        that puts its length where the planar 2R reaches best (``|v|^2 = |a|^2 + |b|^2``).
        """
        h, p = self._h, self._poe.points
        A = A - dot(A, h)[..., None] * h
        B = B - dot(B, h)[..., None] * h
        a, b = p[2] - p[1], p[3] - p[2]
        a, b = a - (a @ h) * h, b - (b @ h) * h
        wanted = 0.5 * (dot(A, A) + dot(B, B) - (a @ a) - (b @ b))  # A . R(h, phi) B
        cos_part, sin_part = dot(A, B), dot(A, cross(h, B))
        r = np.sqrt(cos_part * cos_part + sin_part * sin_part)
        phi = np.arctan2(sin_part, cos_part) + np.arccos(np.clip(wanted / np.where(r > 0, r, 1.0),
                                                                 -1.0, 1.0))
        phi = np.where(r > 0, phi, theta)
        return np.where(free, q6 + s6 * (theta - phi), q6), np.where(free, phi, theta)

    # ------------------------------------------------ parallel axes 1-3 (or 4-6)
    def _setup_parallel_base(self) -> None:
        """Axes 1-3 parallel to ``h``: their motion keeps ``h``-components, which leaves two
        equations in ``q4`` and ``q6`` alone (a :class:`_TwoAngleSystem`):

        ``h . R4 h5 = (R_G^T h) . R6^T h5`` (orientation, since ``R5 h5 = h5``) and
        ``h . e4 o5 = h . G e6^-1 o5`` (a point ``o5`` of axis 5, fixed by ``e5``).
        """
        h_all, p = self._poe.axes, self._poe.points
        self._h = h_all[0]
        A = np.stack([h_all[3], -h_all[4]], axis=1)
        s, t = np.linalg.lstsq(A, p[4] - p[3], rcond=None)[0]
        self._o4, self._o5 = p[3] + s * h_all[3], p[4] + t * h_all[4]
        A = np.stack([h_all[4], -h_all[5]], axis=1)
        t6 = np.linalg.lstsq(A, p[5] - p[4], rcond=None)[0][1]
        self._o6 = p[5] + t6 * h_all[5]
        rows = [_trig_coeffs(self._h, h_all[3], v) for v in (h_all[4], self._o5 - self._o4)]
        self._Q = np.array([[r[1], r[2]] for r in rows])
        self._f = np.array([rows[0][0], rows[1][0] + self._h @ self._o4])
        self._pair = _TwoAngleSystem(self._Q)
        self._polish_by_newton = self._verify = not self._pair.rank1
        self._u_h = _unit_normal(self._h)

    def _parallel_base(self, R_G: Array, t_G: Array) -> tuple[Array, Mask, Mask]:
        """Axes 1-3 parallel: (q6, q4), then q5, q1 + q2 + q3 and a planar 2R: ``(N, 8, 6)``."""
        h_all, p = self._poe.axes, self._poe.points
        h, N = self._h, len(t_G)
        g = np.swapaxes(R_G, -1, -2) @ h  # R_G^T h
        e1, a1, b1 = _trig_coeffs(g, -h_all[5], h_all[4])
        e2, a2, b2 = _trig_coeffs(g, -h_all[5], self._o5 - self._o6)
        e2 = e2 + _transform_point(R_G, t_G, self._o6) @ h
        P = np.stack([np.stack([a1, b1], -1), np.stack([a2, b2], -1)], -2)
        r = self._f - np.stack([e1, e2], axis=-1)  # P x6 - Q x4 = r
        q6, q4, valid, free = self._pair.solve(P, r)
        # q5: R5^T (R4^T h) = R6 R_G^T h
        q5, f5 = sp1(rotate(-h_all[3], q4, h), rotate(h_all[5], q6, g[:, None, :]), -h_all[4])
        # q1 + q2 + q3: R123 = R_G R6^T R5^T R4^T, applied to a normal of h
        turned = rotate(-h_all[5], q6, rotate(-h_all[4], q5, rotate(-h_all[3], q4, self._u_h)))
        theta, _ = sp1(self._u_h, _matvec(R_G, turned), h)
        # planar part: e1 e2 e3 y = z with y = e4 e5 e6 o4, z = G o4
        o4, o5, o6 = self._o4, self._o5, self._o6
        y = o6 + rotate(h_all[5], q6, o4 - o6)
        y = o5 + rotate(h_all[4], q5, y - o5)
        y = o4 + rotate(h_all[3], q4, y - o4)
        z = _transform_point(R_G, t_G, o4)[:, None, :]
        target = z - p[0] - rotate(h, theta, y - p[2])
        q1, q2, v12, f12 = _planar_2r(h, p[1] - p[0], p[2] - p[1], target)
        q3 = theta[..., None] - q1 - q2

        q = np.empty((*q1.shape, 6))
        q[..., 0], q[..., 1], q[..., 2] = q1, q2, q3
        q[..., 3], q[..., 4], q[..., 5] = q4[..., None], q5[..., None], q6[..., None]
        valid = valid[..., None] & v12
        family = (free | f5)[..., None] | f12
        return q.reshape(N, 8, 6), valid.reshape(N, 8), family.reshape(N, 8)

    # ----------------------------------------------------- SCARA and planar
    def _setup_planar(self) -> None:
        poe = self._poe
        self._rev = [j for j in range(poe.n) if not poe.prismatic[j]]
        self._pri = [j for j in range(poe.n) if poe.prismatic[j]]
        self._h = poe.axes[self._rev[0]]
        self._u_h = _unit_normal(self._h)
        r = self._rev
        # a point moved by the first two revolute joints only (on the third axis if any)
        self._y = poe.points[r[2]] if len(r) == 3 else poe.points[r[1]] + self._u_h

    def _planar(self, R_G: Array, t_G: Array) -> tuple[Array, Mask, Mask]:
        """SCARA / planar arm: angle sum, height, planar 2R: ``(N, 2, n)``."""
        poe, h, r = self._poe, self._h, self._rev
        N = len(t_G)
        theta, _ = sp1(self._u_h, R_G @ self._u_h, h)
        Gy = _transform_point(R_G, t_G, self._y)
        slide = (Gy - self._y) @ h if self._pri else np.zeros(N)
        p_a, p_b = poe.points[r[0]], poe.points[r[1]]
        qa, qb, valid, free = _planar_2r(h, p_b - p_a, self._y - p_b, Gy - slide[:, None] * h - p_a)
        q = np.zeros((N, 2, poe.n))
        q[..., r[0]], q[..., r[1]] = qa, qb
        if len(r) == 3:
            q[..., r[2]] = theta[:, None] - qa - qb
        if self._pri:
            q[..., self._pri[0]] = slide[:, None]
        return q, valid, free


def dot2(a: Array, b: Array) -> Array:
    """Row-wise dot product of ``(..., 2)`` vectors."""
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1]


_solvers: dict[int, tuple[weakref.ref, ClosedFormSolver]] = {}


def closed_form_solver(chain: Chain) -> ClosedFormSolver:
    """The (memoised) closed-form solver of ``chain``.

    Raises
    ------
    NoClosedFormError
        If the chain's geometry has no closed form here (the message says why).
    """
    entry = _solvers.get(id(chain))
    if entry is not None and entry[0]() is chain:
        return entry[1]
    plan = plan_closed_form(chain)
    if not plan.structure.closed_form:
        raise NoClosedFormError(f"no closed-form IK for this chain: {plan.structure.description}")
    solver = ClosedFormSolver(chain, plan)
    key = id(chain)
    _solvers[key] = (weakref.ref(chain, lambda _ref, key=key: _solvers.pop(key, None)), solver)
    return solver


def closed_form_ik(chain: Chain, T_base_tool: ArrayLike) -> ClosedFormSolutions:
    """Every closed-form IK solution of ``chain`` for one pose or a batch of poses.

    Parameters
    ----------
    chain : Chain
        A chain with a closed form (see :func:`armkit.ik.analyze_structure`).
    T_base_tool : array_like (4, 4) or (N, 4, 4)
        Target tool pose(s) in the base frame [m].

    Returns
    -------
    ClosedFormSolutions
        ``q`` of shape ``(k_max, n)`` (or ``(N, k_max, n)``), ``valid`` and ``family``
        masks ``(k_max,)`` (or ``(N, k_max)``). ``k_max`` is 8 for 6-joint arms and 2
        for SCARA and planar arms. An unreachable pose has no valid candidate.

    Raises
    ------
    NoClosedFormError
        For chains without closed form (e.g. the 7-joint Panda).
    InputError
        If a pose is not a rigid transform.

    Examples
    --------
    >>> import numpy as np, armkit
    >>> robot = armkit.load("ur5")
    >>> sol = closed_form_ik(robot.chain, robot.fk(np.full(6, 0.3)))
    >>> sol.q.shape, int(sol.valid.sum())
    ((8, 6), 8)
    """
    return closed_form_solver(chain).solve(T_base_tool)
