"""Every closed-form IK solution of a Pieper arm, a SCARA or a planar arm, compiled.

:class:`ClosedFormSolver` prepares, once per chain, what the case solvers of
:mod:`armkit.ik.cases` need (axes, points, the constant part of the case's equations);
then one compiled loop handles each pose: the case solver's candidates are mapped to the
user's joints, polished by two Newton steps on the full pose where they come from a
quartic, wrapped into ``[-pi, pi]``, checked by forward kinematics where the chain is
over-determined (SCARA, planar) or a quartic was solved (``VERIFY_TOLERANCE``), and
duplicates are merged. Nothing is allocated per pose beyond a few small work arrays, so
one pose costs a few microseconds and a batch scales linearly.

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

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numba import njit
from numpy.typing import ArrayLike, NDArray

from armkit._jit import entry_point
from armkit.chain import Chain
from armkit.errors import InputError, NoClosedFormError
from armkit.ik.cases import (
    PARALLEL_BASE,
    PLANAR,
    POSITION_CASES,
    SPHERICAL,
    THREE_PARALLEL,
    TWO_PI,
    CaseGeometry,
    solve_pose,
)
from armkit.ik.numeric import _damped_step
from armkit.ik.structure import ArmStructure, SolverPlan, plan_closed_form
from armkit.ik.subproblems import sp4, trig_coeffs
from armkit.kinematics import chain_frames, chain_jacobian, chain_pose, pose_error_into
from armkit.spatial.transforms import check_transform

__all__ = ["ClosedFormSolutions", "ClosedFormSolver", "closed_form_ik", "closed_form_solver",
           "solver_or_reason", "VERIFY_TOLERANCE", "DUPLICATE_TOLERANCE"]

#: A candidate counts only if its FK matches the target to this, times ``1 + arm size``
#: (entries of the 4x4 matrix, metres / dimensionless). It only rejects non-solutions:
#: the solutions themselves reproduce reachable poses to about 1e-13.
VERIFY_TOLERANCE = 1e-8
#: Candidates closer than this in every joint [rad or m, modulo 2 pi] are one solution.
DUPLICATE_TOLERANCE = 1e-9

Array = NDArray[np.float64]
Mask = NDArray[np.bool_]


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


class ChainData(NamedTuple):
    """What the compiled loop needs of the user's chain (see :class:`ClosedFormSolver`)."""

    T_between: Array  # (n + 1, 4, 4) fixed transforms, for FK
    prismatic: Mask  # (n,) user's joint order
    index: NDArray[np.int64]  # user's joint of internal joint j
    sign: Array  # q_user[index[j]] = sign[j] q_int[j]
    M_inv: Array  # (4, 4) inverse tool pose at q = 0 of the (possibly reversed) chain
    inverted: bool  # the solver's chain describes T^-1
    k: int  # candidates per pose
    verify: bool  # check candidates by FK
    polish: bool  # Newton steps on the full pose (quartic paths)
    verify_tolerance: float


# ------------------------------------------------------------ compiled loop
@njit(cache=True)
def _joint_motion(d, T):
    """``G = T M^-1`` (or ``T^-1 M^-1`` for an inverted chain): rotation rows and translation."""
    R = np.empty((3, 3))
    t = np.empty(3)
    for a in range(3):
        if d.inverted:  # T^-1 = [R^T, -R^T p]
            t[a] = -(T[0, a] * T[0, 3] + T[1, a] * T[1, 3] + T[2, a] * T[2, 3])
            for b in range(3):
                R[a, b] = T[b, a]
        else:
            t[a] = T[a, 3]
            for b in range(3):
                R[a, b] = T[a, b]
    G = np.empty((3, 4))
    M = d.M_inv
    for a in range(3):
        for b in range(4):
            G[a, b] = R[a, 0] * M[0, b] + R[a, 1] * M[1, b] + R[a, 2] * M[2, b]
    return ((G[0, 0], G[0, 1], G[0, 2]), (G[1, 0], G[1, 1], G[1, 2]), (G[2, 0], G[2, 1], G[2, 2])), \
        (G[0, 3] + t[0], G[1, 3] + t[1], G[2, 3] + t[2])


@njit(cache=True)
def _newton(d, T, q, steps):
    """Damped Newton steps on ``fk(q) = T`` for one candidate ``q`` (quartic paths only).

    Where a quartic root meets another singularity (a double root near an aligned
    wrist), a candidate may carry errors of ~1e-7; two steps bring it to rounding level,
    and the FK check then decides.
    """
    n = q.shape[0]
    F, axes, points = np.empty((4, 4)), np.empty((n, 3)), np.empty((n, 3))
    J, e, dq = np.empty((6, n)), np.empty(6), np.empty(n)
    rows, free = np.arange(6), np.zeros(n)  # every task row; no joint held at a bound
    for _ in range(steps):
        chain_frames(d.T_between, d.prismatic, q, F, axes, points)
        chain_jacobian(F, axes, points, d.prismatic, J)
        pose_error_into(T, F, e)
        _damped_step(J, e, rows, free, 1e-14, dq)
        for j in range(n):
            q[j] += dq[j]


@njit(cache=True)
def _fk_difference(d, T, q):
    """``max |fk(q) - T|`` over the top three rows."""
    F = np.empty((4, 4))
    chain_pose(d.T_between, d.prismatic, q, F)
    worst = 0.0
    for a in range(3):
        for b in range(4):
            worst = max(worst, abs(F[a, b] - T[a, b]))
    return worst


@njit(cache=True)
def _duplicates(q, valid, prismatic, duplicate):
    """Mark in ``duplicate`` ``(k,)`` the candidates equal (modulo 2 pi) to an earlier valid one."""
    k, n = q.shape
    for a in range(k):
        duplicate[a] = False
    for a in range(k):
        if not valid[a]:
            continue
        for b in range(a + 1, k):
            same = True
            for j in range(n):
                diff = abs(q[a, j] - q[b, j])
                if not prismatic[j]:
                    diff = min(diff, TWO_PI - diff)
                if not diff <= DUPLICATE_TOLERANCE:
                    same = False
                    break
            if same:
                duplicate[b] = True


@njit(cache=True)
def pose_candidates(g, d, T, q, valid, family):
    """Every candidate of one target ``T`` ``(4, 4)`` into ``q`` ``(k, n)`` (user's joints),
    ``valid`` and ``family`` ``(k,)``; duplicates are invalid."""
    k, n = q.shape
    q_int = np.empty((k, n))
    R, t = _joint_motion(d, T)
    solve_pose(g, R, t, q_int, valid, family)
    for s in range(k):
        for j in range(n):
            q[s, d.index[j]] = d.sign[j] * q_int[s, j]
        finite = True
        for j in range(n):
            finite = finite and math.isfinite(q[s, j])
        valid[s] = valid[s] and finite
        if d.polish and valid[s]:
            _newton(d, T, q[s], 2)
        for j in range(n):
            if not d.prismatic[j]:
                q[s, j] -= TWO_PI * np.rint(q[s, j] / TWO_PI)
        if d.verify and valid[s]:
            valid[s] = _fk_difference(d, T, q[s]) <= d.verify_tolerance
    duplicate = np.empty(k, dtype=np.bool_)
    _duplicates(q, valid, d.prismatic, duplicate)
    for s in range(k):
        valid[s] = valid[s] and not duplicate[s]
    for s in range(k):
        family[s] = family[s] and valid[s]


@njit(cache=True)
def _candidates_batch(g, d, T, q, valid, family):
    for i in range(T.shape[0]):
        pose_candidates(g, d, T[i], q[i], valid[i], family[i])


# ------------------------------------------------------------- preparation
def _unit_normal(h: Array) -> Array:
    """A unit vector perpendicular to ``h``."""
    e = np.eye(3)[np.argmin(np.abs(h))]
    u = np.cross(h, e)
    return u / np.linalg.norm(u)


def _closest_points(p_a: Array, h_a: Array, p_b: Array, h_b: Array) -> tuple[Array, Array]:
    """The points of lines ``(p_a, h_a)`` and ``(p_b, h_b)`` closest to each other."""
    s, t = np.linalg.lstsq(np.stack([h_a, -h_b], axis=1), p_b - p_a, rcond=None)[0]
    return p_a + s * h_a, p_b + t * h_b


def _vector(v: ArrayLike | None) -> tuple[float, float, float]:
    return (0.0, 0.0, 0.0) if v is None else tuple(float(x) for x in np.asarray(v, dtype=float))


def _two_angle_constants(Q: Array, snap_t2: bool = True) -> dict:
    """The constant part of a two-angle system ``P x(t1) - Q x(t2) = r`` (see
    :func:`armkit.ik.cases.two_angle_system`): rank, the combinations ``lam``, ``mu``."""
    U, S, _ = np.linalg.svd(Q)
    rank1 = bool(S[1] <= 1e-9 * S[0])
    return {"Q": Q, "Q_inv": np.zeros((2, 2)) if rank1 else np.linalg.inv(Q), "rank1": rank1,
            "lam": (float(U[0, 1]), float(U[1, 1])), "mu": (float(U[0, 0]), float(U[1, 0])),
            "snap_t2": snap_t2}


class ClosedFormSolver:
    """Closed-form IK of one chain, with everything that depends only on the chain cached.

    Build it with :func:`closed_form_solver` (memoised per chain).
    """

    def __init__(self, chain: Chain, plan: SolverPlan) -> None:
        self.chain = chain
        self.structure: ArmStructure = plan.structure
        poe = plan.poe
        kind = plan.structure.kind
        fields = {"h": np.ascontiguousarray(poe.axes), "p": np.ascontiguousarray(poe.points),
                  "prismatic": np.ascontiguousarray(poe.prismatic), "position_case": -1,
                  "c": _vector(plan.point), "o": _vector(plan.point2), "u": _vector(None),
                  "hp": _vector(None), "a1": _vector(None), "a2": _vector(None), "a3": _vector(None),
                  "f": (0.0, 0.0), "q5_aligned": np.zeros(0), "b_aligned": 0.0,
                  "revolute_joints": np.zeros(0, dtype=np.int64), "prismatic_joint": -1,
                  **_two_angle_constants(np.eye(2))}
        # Over-determined chains (fewer than 6 joints) must be checked by FK; for 6 joints
        # every subproblem checks its own existence, so the flags are exact.
        verify, polish = chain.n < 6, False
        if kind in ("spherical-wrist", "spherical-base"):
            fields.update(kind=SPHERICAL, position_case=POSITION_CASES.index(plan.case),
                          u=_vector(_unit_normal(poe.axes[5])))
            if plan.case == "general-123":
                fields.update(self._general_position(poe, plan.point))
                polish = True
        elif kind == "three-parallel" and plan.case == "parallel-123":
            fields.update(kind=PARALLEL_BASE, **self._parallel_base(poe))
            polish = not fields["rank1"]  # a quartic: polished on the full pose and checked by FK
        elif kind == "three-parallel":
            fields.update(kind=THREE_PARALLEL, **self._three_parallel(poe))
            polish = not fields["rank1"]
        else:
            fields.update(kind=PLANAR, **self._planar(poe))
        self.geometry = CaseGeometry(**fields)
        size = 1.0 + max(np.abs(poe.points).max(), np.abs(poe.M[:3, 3]).max())
        M_inv = np.eye(4)
        M_inv[:3, :3] = poe.M[:3, :3].T
        M_inv[:3, 3] = -poe.M[:3, :3].T @ poe.M[:3, 3]
        self._candidates_entry = None  # the compiled loop for this chain, set on first use
        self.data = ChainData(*chain._kernel_arrays,
                              poe.index.astype(np.int64), poe.sign.astype(float), M_inv, poe.inverted,
                              8 if fields["kind"] != PLANAR else 2, verify or polish, polish,
                              VERIFY_TOLERANCE * size)

    # ------------------------------------------------------------------ public
    def solve(self, T_base_tool: ArrayLike) -> ClosedFormSolutions:
        """All candidates for poses ``(4, 4)`` or ``(..., 4, 4)``; see :func:`closed_form_ik`."""
        T = check_transform(T_base_tool, "T_base_tool")
        batch = T.shape[:-2]
        q, valid, family = self.candidates(T.reshape(-1, 4, 4))
        k, n = q.shape[-2:]
        return ClosedFormSolutions(q.reshape(*batch, k, n), valid.reshape(*batch, k),
                                   family.reshape(*batch, k))

    def candidates(self, T: Array) -> tuple[Array, Mask, Mask]:
        """``(q, valid, family)`` ``(N, k, n)``, ``(N, k)`` for rigid poses ``T`` ``(N, 4, 4)``
        (checked by :func:`armkit.spatial.check_transform`)."""
        T = np.require(T, dtype=np.float64, requirements="CW")  # the types the compiled loop takes
        if T.ndim != 3 or T.shape[1:] != (4, 4):
            raise InputError(f"T: expected shape (N, 4, 4), got {T.shape}")
        N, k = len(T), self.data.k
        q = np.empty((N, k, self.chain.n))
        valid, family = np.empty((N, k), dtype=bool), np.empty((N, k), dtype=bool)
        args = (self.geometry, self.data, T, q, valid, family)
        if self._candidates_entry is None:  # compiled once per chain: later calls skip numba's dispatch
            self._candidates_entry = entry_point(_candidates_batch, *args)
        self._candidates_entry(*args)
        return q, valid, family

    # ------------------------------------------------------------ per case
    @staticmethod
    def _general_position(poe, c: Array) -> dict:
        """Axes 1-3 general: two equations in q1 and q3 alone.

        With ``y = e1^-1 G c`` (q1) and ``x = e3 c`` (q3), ``e2 x = y`` keeps the height along
        axis 2 and the distance to a point ``o2`` of it: ``h2 . (y - o2) = h2 . (x - o2)`` and
        ``|y - o2|^2 = |x - o2|^2``, each first order in its angle.
        """
        h, p = poe.axes, poe.points
        o2, o3 = _closest_points(p[1], h[1], p[2], h[2])
        height = trig_coeffs(_vector(h[1]), _vector(h[2]), _vector(c - o3))
        distance = trig_coeffs(_vector(2.0 * (o3 - o2)), _vector(h[2]), _vector(c - o3))
        Q = np.array([[height[1], height[2]], [distance[1], distance[2]]])
        f = (height[0] + float(h[1] @ (o3 - o2)),
             distance[0] + float((o3 - o2) @ (o3 - o2) + (c - o3) @ (c - o3)))
        return {"a1": _vector(o2), "a2": _vector(o3), "f": f, **_two_angle_constants(Q)}

    @staticmethod
    def _three_parallel(poe) -> dict:
        """Axes 2-4 parallel to ``h``: two equations in ``q1, q5``; ``a1, a2``: the closest
        points ``p5, p6`` of axes 5 and 6."""
        h_all, p = poe.axes, poe.points
        h = h_all[1]
        p5, p6 = _closest_points(p[4], h_all[4], p[5], h_all[5])
        # right-hand sides h . R(h5, q5) v = const + c cos q5 + d sin q5, for v = h6, p6 - p5
        rows = [trig_coeffs(_vector(h), _vector(h_all[4]), _vector(v)) for v in (h_all[5], p6 - p5)]
        Q = np.array([[r[1], r[2]] for r in rows])
        f = (rows[0][0], rows[1][0] + float(h @ (p5 - p[0])))
        # values of q5 that turn axis 6 parallel to h (a UR-like wrist singularity)
        q5_aligned = []
        for side in (1.0, -1.0):
            angles, ok, _ = sp4(_vector(h), _vector(h_all[5]), _vector(h_all[4]), side)
            q5_aligned += [angles[i] for i in range(2) if ok[i]]
        b_aligned = float(np.linalg.norm(np.cross(h_all[4], h))
                          * np.linalg.norm(np.cross(h_all[4], h_all[5])))
        # q5 near an aligned wrist is refined from sines, so its cosine equation must not snap
        return {"hp": _vector(h), "u": _vector(_unit_normal(h)), "a1": _vector(p5), "a2": _vector(p6),
                "f": f, "q5_aligned": np.array(q5_aligned, dtype=float), "b_aligned": b_aligned,
                **_two_angle_constants(Q, snap_t2=False)}

    @staticmethod
    def _parallel_base(poe) -> dict:
        """Axes 1-3 parallel to ``h``: two equations in ``q6, q4``; ``a1 .. a3``: points
        ``o4, o5, o6`` of axes 4-6."""
        h_all, p = poe.axes, poe.points
        h = h_all[0]
        o4, o5 = _closest_points(p[3], h_all[3], p[4], h_all[4])
        o6 = _closest_points(p[4], h_all[4], p[5], h_all[5])[1]
        rows = [trig_coeffs(_vector(h), _vector(h_all[3]), _vector(v)) for v in (h_all[4], o5 - o4)]
        Q = np.array([[r[1], r[2]] for r in rows])
        f = (rows[0][0], rows[1][0] + float(h @ o4))
        return {"hp": _vector(h), "u": _vector(_unit_normal(h)), "a1": _vector(o4), "a2": _vector(o5),
                "a3": _vector(o6), "f": f, **_two_angle_constants(Q)}

    @staticmethod
    def _planar(poe) -> dict:
        """SCARA / planar: ``a1`` a point moved by the first two revolute joints only."""
        rev = [j for j in range(poe.n) if not poe.prismatic[j]]
        pri = [j for j in range(poe.n) if poe.prismatic[j]]
        h = poe.axes[rev[0]]
        u = _unit_normal(h)
        y = poe.points[rev[2]] if len(rev) == 3 else poe.points[rev[1]] + u
        return {"hp": _vector(h), "u": _vector(u), "a1": _vector(y),
                "revolute_joints": np.array(rev, dtype=np.int64), "prismatic_joint": pri[0] if pri else -1}


def closed_form_solver(chain: Chain) -> ClosedFormSolver:
    """The closed-form solver of ``chain`` (made once per chain and kept with it).

    Raises
    ------
    NoClosedFormError
        If the chain's geometry has no closed form here (the message says why).
    """
    solver = solver_or_reason(chain)
    if isinstance(solver, NoClosedFormError):
        raise solver
    return solver


def solver_or_reason(chain: Chain) -> ClosedFormSolver | NoClosedFormError:
    """The chain's closed-form solver, or the error saying why it has none (made once)."""
    return chain.derived("closed_form_solver", lambda: _make_solver(chain))


def _make_solver(chain: Chain) -> ClosedFormSolver | NoClosedFormError:
    plan = plan_closed_form(chain)
    if not plan.structure.closed_form:
        return NoClosedFormError(f"no closed-form IK for this chain: {plan.structure.description}")
    return ClosedFormSolver(chain, plan)


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
    >>> import armkit
    >>> robot = armkit.load("ur5")
    >>> sol = closed_form_ik(robot.chain, robot.fk(np.full(6, 0.3)))
    >>> sol.q.shape, int(sol.valid.sum())
    ((8, 6), 8)
    """
    return closed_form_solver(chain).solve(T_base_tool)
