"""The closed-form solvers of each geometric case, one pose at a time, compiled by numba.

The chain is taken as screw axes at ``q = 0`` (see :mod:`armkit.ik.structure`):
``T(q) = exp(xi_1 q_1) ... exp(xi_n q_n) M``, so the target gives ``G = T M^-1``, the
motion of the joints alone. One solver per geometric case splits ``G`` (rotation ``R``
as a tuple of rows, translation ``t``) into Paden-Kahan subproblems
(:mod:`armkit.ik.subproblems`) and writes every candidate into the rows of ``q``
``(k, n)`` (internal joint order), with ``valid`` and ``family`` flags ``(k,)``:

* spherical wrist (axes 4-6 meet at ``c``): joints 1-3 place ``c`` at ``G c`` (SP3 / SP4
  / SP2 / planar 2R, by which pair of axes 1-3 meets or is parallel; a prismatic third
  joint gives a quadratic; general axes give two equations in ``q1, q3`` solved like the
  three-parallel case), then the wrist turns ``h6`` (SP2) and a normal of it (SP1) into
  place. A spherical base is the same on the reversed chain (the chain of ``T^-1``).
* three parallel axes 2-4 with direction ``h``: rotations about them keep ``h``-components,
  which leaves two equations in ``q1, q5`` alone (:func:`two_angle_system`). If axes 5
  and 6 meet, a combination of them holds ``q1`` only (SP4), else they give a quartic.
  Then ``q6`` (SP1), ``q2 + q3 + q4`` (SP1), and a planar 2R. Axes 1-3 parallel give two
  equations in ``q4, q6`` the same way; axes 3-5 and 4-6 are these cases on the reversed
  chain.
* SCARA and planar 2R/3R: the orientation gives the sum of the angles, a prismatic joint
  along the axes the height, and a planar 2R the rest.

Every subproblem says whether its branch exists, so for the closed paths the flags are
exact (an unreachable pose gives no valid candidate); :mod:`armkit.ik.closed_form`
verifies the over-determined and quartic paths by forward kinematics.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit
from numpy.typing import NDArray

from armkit.ik.subproblems import (
    add,
    cross,
    dot,
    planar_2r,
    rotate,
    scale,
    solve_trig_linear,
    sp1,
    sp2,
    sp3,
    sp4,
    sub,
    vec3,
)

__all__ = ["CaseGeometry", "solve_pose", "SPHERICAL", "THREE_PARALLEL", "PARALLEL_BASE", "PLANAR",
           "POSITION_CASES", "TWO_PI", "trig_coeffs", "two_angle_system", "wrap_angle"]

#: Solver kinds (``CaseGeometry.kind``).
SPHERICAL, THREE_PARALLEL, PARALLEL_BASE, PLANAR = range(4)
#: How joints 1-3 of a spherical-wrist arm place the wrist centre (``CaseGeometry.position_case``).
POSITION_CASES = ("parallel-23", "parallel-12", "intersect-23", "intersect-12-revolute",
                  "intersect-12-prismatic", "general-123")
TWO_PI = 2.0 * math.pi

Vector = tuple[float, float, float]


class CaseGeometry(NamedTuple):
    """Everything a case solver needs from the chain, computed once per chain.

    ``h``, ``p``: internal axes and points ``(n, 3)`` [-, m]; ``c``, ``o``, ``u``, ``hp``
    and ``a1 .. a3`` points and directions whose meaning depends on the case (see
    :mod:`armkit.ik.closed_form`, which builds them); ``Q``, ``Q_inv``, ``f``, ``lam``,
    ``mu``: the constant part of the case's two-angle system.
    """

    kind: int
    position_case: int
    h: NDArray[np.float64]
    p: NDArray[np.float64]
    prismatic: NDArray[np.bool_]
    c: Vector
    o: Vector
    u: Vector
    hp: Vector
    a1: Vector
    a2: Vector
    a3: Vector
    Q: NDArray[np.float64]
    Q_inv: NDArray[np.float64]
    f: tuple[float, float]
    rank1: bool
    lam: tuple[float, float]
    mu: tuple[float, float]
    snap_t2: bool
    q5_aligned: NDArray[np.float64]
    b_aligned: float
    revolute_joints: NDArray[np.int64]
    prismatic_joint: int


# ------------------------------------------------------------------ helpers
@njit(cache=True)
def _mul(R, v):
    """``R v`` for ``R`` a tuple of rows."""
    return (dot(R[0], v), dot(R[1], v), dot(R[2], v))


@njit(cache=True)
def _mul_transposed(R, v):
    """``R^T v`` for ``R`` a tuple of rows."""
    return add(add(scale(v[0], R[0]), scale(v[1], R[1])), scale(v[2], R[2]))


@njit(cache=True)
def _neg(v):
    return (-v[0], -v[1], -v[2])


@njit(cache=True)
def trig_coeffs(h, k, v):
    """``h . R(k, t) v = const + cos_coeff cos t + sin_coeff sin t``."""
    hk = dot(h, k)
    kv = dot(k, v)
    return hk * kv, dot(h, v) - hk * kv, dot(h, cross(k, v))


@njit(cache=True)
def wrap_angle(angle):
    """``angle`` shifted by whole turns into ``[-pi, pi]``."""
    return angle - TWO_PI * np.rint(angle / TWO_PI)


# --------------------------------------------------------- two-angle system
@njit(cache=True)
def _family_representative(m0, m1, mr):
    """``t1`` with ``m . x(t1) = mr`` (or as close as it gets).

    When the first equation leaves ``t1`` free, the second, ``mP . x(t1) - mQ . x(t2) =
    mr``, still ties ``t2`` to it; this ``t1`` puts its right-hand side at 0, the middle
    of the range ``t2`` can reach.
    """
    m = math.sqrt(m0 * m0 + m1 * m1)
    if m == 0.0:
        return 0.0
    return math.atan2(m1, m0) + math.acos(min(max(mr / m, -1.0), 1.0))


@njit(cache=True)
def _rank1(g, P, r, size, t1, t2, valid, free):
    """The system when ``Q`` has rank 1: ``lam`` holds ``t1`` alone, ``mu`` then ``t2``."""
    l0, l1 = g.lam
    m0, m1 = g.mu
    lP0, lP1 = l0 * P[0][0] + l1 * P[1][0], l0 * P[0][1] + l1 * P[1][1]
    first, first_valid, first_free = solve_trig_linear(lP0, lP1, r[0] * l0 + r[1] * l1, size, True)
    mP0, mP1 = m0 * P[0][0] + m1 * P[1][0], m0 * P[0][1] + m1 * P[1][1]
    mr = r[0] * m0 + r[1] * m1
    if first_free:  # t1 free: the member whose t2 equation is easiest (middle of its range)
        rep = _family_representative(mP0, mP1, mr)
        first = (rep, rep)
    Q = g.Q
    mQ0, mQ1 = m0 * Q[0, 0] + m1 * Q[1, 0], m0 * Q[0, 1] + m1 * Q[1, 1]
    for i in range(2):
        rhs = mP0 * math.cos(first[i]) + mP1 * math.sin(first[i]) - mr
        second, second_valid, second_free = solve_trig_linear(mQ0, mQ1, rhs, size, g.snap_t2)
        for j in range(2):
            t1[2 * i + j] = first[i]
            t2[2 * i + j] = second[j]
            valid[2 * i + j] = first_valid[i] and second_valid[j]
            free[2 * i + j] = first_free or second_free


@njit(cache=True)
def _quartic_equation(A0, A1, B1, A2, B2, t):
    """``F(t) = A0 + A1 cos t + B1 sin t + A2 cos 2t + B2 sin 2t`` and ``F'(t)``."""
    c, s, c2, s2 = math.cos(t), math.sin(t), math.cos(2.0 * t), math.sin(2.0 * t)
    return (A0 + A1 * c + B1 * s + A2 * c2 + B2 * s2,
            -A1 * s + B1 * c - 2.0 * A2 * s2 + 2.0 * B2 * c2)


@njit(cache=True)
def _quartic(g, P, r, t1, t2, valid):
    """Roots of the quartic in ``exp(i t1)`` with ``t2`` from ``Q^-1`` (companion matrix)."""
    Qi = g.Q_inv
    W00 = Qi[0, 0] * P[0][0] + Qi[0, 1] * P[1][0]
    W01 = Qi[0, 0] * P[0][1] + Qi[0, 1] * P[1][1]
    W10 = Qi[1, 0] * P[0][0] + Qi[1, 1] * P[1][0]
    W11 = Qi[1, 0] * P[0][1] + Qi[1, 1] * P[1][1]
    w0 = (Qi[0, 0] * r[0] + Qi[0, 1] * r[1], Qi[1, 0] * r[0] + Qi[1, 1] * r[1])
    S00, S11, S01 = W00 * W00 + W10 * W10, W01 * W01 + W11 * W11, W00 * W01 + W10 * W11
    m0, m1 = W00 * w0[0] + W10 * w0[1], W01 * w0[0] + W11 * w0[1]
    # F(t) = |W x(t) - w0|^2 - 1 = A0 + A1 cos t + B1 sin t + A2 cos 2t + B2 sin 2t
    A0 = 0.5 * (S00 + S11) + w0[0] * w0[0] + w0[1] * w0[1] - 1.0
    A1, B1 = -2.0 * m0, -2.0 * m1
    A2, B2 = 0.5 * (S00 - S11), S01
    # z^2 F in z = exp(i t): coefficients of z^4 ... z^0
    coeffs = np.array([complex(A2, -B2) / 2, complex(A1, -B1) / 2, complex(A0, 0.0),
                       complex(A1, B1) / 2, complex(A2, B2) / 2])
    size = np.abs(coeffs).max()
    if abs(coeffs[0]) > 1e-12 * size:
        companion = np.zeros((4, 4), dtype=np.complex128)
        for i in range(3):
            companion[i + 1, i] = 1.0
        for i in range(4):
            companion[0, i] = -coeffs[i + 1] / coeffs[0]
        roots = np.linalg.eigvals(companion)
        for i in range(4):
            t = math.atan2(roots[i].imag, roots[i].real)
            for _ in range(3):  # Newton on F(t), the real equation
                F, dF = _quartic_equation(A0, A1, B1, A2, B2, t)
                if abs(dF) > 1e-300:
                    t -= min(max(F / dF, -0.1), 0.1)
            t1[i] = t
            valid[i] = abs(abs(roots[i]) - 1.0) <= 1e-6
    else:  # degenerate: F is of degree 1, a cos t + b sin t = -A0
        lin, lin_valid, _ = solve_trig_linear(A1, B1, -A0, size, True)
        for i in range(4):
            t1[i] = lin[i % 2]
            valid[i] = lin_valid[i] if i < 2 else False
    for i in range(4):
        c, s = math.cos(t1[i]), math.sin(t1[i])
        t2[i] = math.atan2(W10 * c + W11 * s - w0[1], W00 * c + W01 * s - w0[0])


@njit(cache=True)
def _system_residual(Q, P, r, t1, t2):
    """``P x(t1) - Q x(t2) - r`` and its derivatives by ``t1`` and ``t2``."""
    c1, s1, c2, s2 = math.cos(t1), math.sin(t1), math.cos(t2), math.sin(t2)
    F0 = P[0][0] * c1 + P[0][1] * s1 - Q[0, 0] * c2 - Q[0, 1] * s2 - r[0]
    F1 = P[1][0] * c1 + P[1][1] * s1 - Q[1, 0] * c2 - Q[1, 1] * s2 - r[1]
    d1 = (-P[0][0] * s1 + P[0][1] * c1, -P[1][0] * s1 + P[1][1] * c1)
    d2 = (Q[0, 0] * s2 - Q[0, 1] * c2, Q[1, 0] * s2 - Q[1, 1] * c2)
    return F0, F1, d1, d2


@njit(cache=True)
def _polish(Q, P, r, t1, t2):
    """Newton steps on ``P x(t1) - Q x(t2) = r`` itself (``Q^-1`` may be ill-conditioned).

    Returns the polished angles and the remaining residual ``max |P x(t1) - Q x(t2) - r|``.
    """
    for _ in range(6):  # quadratic convergence; linear near a double root
        F0, F1, d1, d2 = _system_residual(Q, P, r, t1, t2)
        det = d1[0] * d2[1] - d1[1] * d2[0]
        if abs(det) > 1e-12 * (1.0 + max(abs(d1[0]), abs(d1[1])) * max(abs(d2[0]), abs(d2[1]))):
            t1 -= min(max((d2[1] * F0 - d2[0] * F1) / det, -0.1), 0.1)
            t2 -= min(max((d1[0] * F1 - d1[1] * F0) / det, -0.1), 0.1)
    F0, F1, _, _ = _system_residual(Q, P, r, t1, t2)
    return t1, t2, max(abs(F0), abs(F1))


@njit(cache=True)
def two_angle_system(g, P, r, t1, t2, valid, free):
    """All ``(t1, t2)`` with ``P x(t1) - Q x(t2) = r``, ``x(t) = [cos t, sin t]``.

    Two equations, each first order in both angles, with ``Q = g.Q`` fixed by the chain
    and ``P`` (2x2, tuple of rows), ``r`` by the pose. If ``Q`` has rank 1, a combination
    of the equations holds ``t1`` alone (SP4-like, then ``t2`` the same way): up to 2 x 2
    pairs. Otherwise ``x(t2) = Q^-1 (P x(t1) - r)`` on the unit circle is a quartic in
    ``exp(i t1)`` (companion matrix, then Newton steps on the equations themselves).
    Writes the four candidates into ``t1, t2, valid, free`` ``(4,)``; ``free``: ``t1``
    (or ``t2``) is arbitrary.
    """
    size = 1.0 + max(max(abs(P[0][0]), abs(P[0][1])), max(abs(P[1][0]), abs(P[1][1]))) \
        + max(abs(r[0]), abs(r[1]))
    if g.rank1:
        _rank1(g, P, r, size, t1, t2, valid, free)
        return
    _quartic(g, P, r, t1, t2, valid)
    for i in range(4):
        t1[i], t2[i], residual = _polish(g.Q, P, r, t1[i], t2[i])
        valid[i] = valid[i] and residual <= 1e-10 * size
        free[i] = False


# -------------------------------------------------------- spherical wrist
@njit(cache=True)
def _slide_to_sphere(v, h, d):
    """Both ``s`` with ``|v + s h| = d`` and whether each is a real root."""
    b = dot(v, h)
    disc = b * b - dot(v, v) + d * d
    exists = disc >= -1e-9 * (dot(v, v) + d * d)
    root = math.sqrt(max(disc, 0.0))
    return (-b + root, -b - root), (exists, exists and disc > 0)


@njit(cache=True)
def _general_position(g, w, q, valid, free):
    """Joints 1-3 for general axes: a two-angle system in ``q1, q3`` (``g.a1, g.a2`` are the
    closest points ``o2, o3`` of axes 2 and 3), then ``q2`` by SP1."""
    h0, h1, h2 = vec3(g.h[0]), vec3(g.h[1]), vec3(g.h[2])
    p0 = vec3(g.p[0])
    o2, o3, c = g.a1, g.a2, g.c
    u = sub(w, p0)
    e_h, a_h, b_h = trig_coeffs(h1, _neg(h0), u)
    e_d, a_d, b_d = trig_coeffs(scale(2.0, sub(p0, o2)), _neg(h0), u)
    e_h += dot(h1, sub(p0, o2))
    e_d += dot(sub(p0, o2), sub(p0, o2)) + dot(u, u)
    t1, t3, pair_valid, pair_free = np.empty(4), np.empty(4), np.empty(4, np.bool_), np.empty(4, np.bool_)
    two_angle_system(g, ((a_h, b_h), (a_d, b_d)), (g.f[0] - e_h, g.f[1] - e_d), t1, t3, pair_valid,
                     pair_free)
    for i in range(4):
        y = add(p0, rotate(_neg(h0), t1[i], u))
        x = add(o3, rotate(h2, t3[i], sub(c, o3)))
        q2, free2 = sp1(sub(x, o2), sub(y, o2), h1)
        q[i, 0], q[i, 1], q[i, 2] = t1[i], q2, t3[i]
        valid[i] = pair_valid[i]
        free[i] = pair_free[i] or free2


@njit(cache=True)
def _wrist_centre_joints(g, w, q, valid, free):
    """Joints 1-3 that put the wrist centre ``g.c`` at ``w``: four triples into ``q[:4, :3]``."""
    case, c, o = g.position_case, g.c, g.o
    h0, h1, h2 = vec3(g.h[0]), vec3(g.h[1]), vec3(g.h[2])
    p0, p1, p2 = vec3(g.p[0]), vec3(g.p[1]), vec3(g.p[2])
    if case == 5:  # general-123
        _general_position(g, w, q, valid, free)
        return
    if case == 0:  # parallel-23
        q1, v1, f1 = sp4(h1, sub(w, p0), _neg(h0), dot(h1, sub(c, p0)))
        for i in range(2):
            y = add(p0, rotate(_neg(h0), q1[i], sub(w, p0)))
            q2, q3, v23, f23 = planar_2r(h1, sub(p2, p1), sub(c, p2), sub(y, p1))
            for j in range(2):
                s = 2 * i + j
                q[s, 0], q[s, 1], q[s, 2] = q1[i], q2[j], q3[j]
                valid[s], free[s] = v1[i] and v23[j], f1 or f23
    elif case == 1:  # parallel-12
        q3, v3, f3 = sp4(h0, sub(c, p2), h2, dot(sub(w, p2), h0))
        for i in range(2):
            x = add(p2, rotate(h2, q3[i], sub(c, p2)))
            q1, q2, v12, f12 = planar_2r(h0, sub(p1, p0), sub(x, p1), sub(w, p0))
            for j in range(2):
                s = 2 * i + j
                q[s, 0], q[s, 1], q[s, 2] = q1[j], q2[j], q3[i]
                valid[s], free[s] = v3[i] and v12[j], f3 or f12
    elif case == 2:  # intersect-23
        q1, v1, f1 = sp3(sub(w, p0), sub(o, p0), _neg(h0), math.sqrt(dot(sub(c, o), sub(c, o))))
        for i in range(2):
            y = add(p0, rotate(_neg(h0), q1[i], sub(w, p0)))
            q2, q3, v23, f2, f3 = sp2(sub(y, o), sub(c, o), _neg(h1), h2)
            for j in range(2):
                s = 2 * i + j
                q[s, 0], q[s, 1], q[s, 2] = q1[i], q2[j], q3[j]
                valid[s], free[s] = v1[i] and v23[j], f1 or f2 or f3
    else:  # intersect-12-revolute (3) / intersect-12-prismatic (4)
        d = math.sqrt(dot(sub(w, o), sub(w, o)))
        if case == 4:
            q3, v3 = _slide_to_sphere(sub(c, o), h2, d)
            f3 = False
        else:
            q3, v3, f3 = sp3(sub(c, p2), sub(o, p2), h2, d)
        for i in range(2):
            if case == 4:
                x = add(c, scale(q3[i], h2))
            else:
                x = add(p2, rotate(h2, q3[i], sub(c, p2)))
            q1, q2, v12, f1, f2 = sp2(sub(w, o), sub(x, o), _neg(h0), h1)
            for j in range(2):
                s = 2 * i + j
                q[s, 0], q[s, 1], q[s, 2] = q1[j], q2[j], q3[i]
                valid[s], free[s] = v3[i] and v12[j], f3 or f1 or f2


@njit(cache=True)
def _spherical(g, R, t, q, valid, family):
    """Spherical wrist: joints 1-3 for the wrist centre, then the wrist: 8 candidates."""
    h3, h4, h5 = vec3(g.h[3]), vec3(g.h[4]), vec3(g.h[5])
    u = g.u
    w = add(_mul(R, g.c), t)
    arm_q, arm_valid, arm_free = np.empty((4, 3)), np.empty(4, np.bool_), np.empty(4, np.bool_)
    _wrist_centre_joints(g, w, arm_q, arm_valid, arm_free)
    # the wrist's rotation R_w = R123^T R_G, applied to h6 and a normal u of it
    for i in range(4):
        a, b = _mul(R, h5), _mul(R, u)
        for j in range(3):
            if not g.prismatic[j]:
                k = _neg(vec3(g.h[j]))
                a, b = rotate(k, arm_q[i, j], a), rotate(k, arm_q[i, j], b)
        q4, q5, v45, f4, f5 = sp2(a, h5, _neg(h3), h4)
        for m in range(2):
            # R6 u = R5^T R4^T R_w u
            target = rotate(_neg(h4), q5[m], rotate(_neg(h3), q4[m], b))
            q6, f6 = sp1(u, target, h5)
            s = 2 * i + m
            q[s, 0], q[s, 1], q[s, 2] = arm_q[i, 0], arm_q[i, 1], arm_q[i, 2]
            q[s, 3], q[s, 4], q[s, 5] = q4[m], q5[m], q6
            valid[s] = arm_valid[i] and v45[m]
            family[s] = arm_free[i] or f4 or f5 or f6


# ---------------------------------------------------- three parallel axes
@njit(cache=True)
def _q5_near_aligned_wrist(g, R, q1, q5, s):
    """Near an aligned wrist, q5 from a sine (accurate) rather than a cosine (~1e-8).

    ``h6 . R5^T h`` is the cosine-like quantity the equations give; at a distance ``d``
    from the aligned value it differs from +-1 by ``b (1 - cos d)`` only, lost below
    d ~ 1e-8. The length ``S = |h6 x R5^T h| = |h6 x R_G^T R1 h|`` is computed from
    vectors, so it keeps its relative accuracy: ``b (1 - cos d) = S^2 / (1 + sqrt(1 -
    S^2))``. The two branches of candidate pair ``s`` straddle the aligned value.
    """
    if g.q5_aligned.size == 0:
        return q5
    nearest, gap = 0, math.inf
    for a in range(g.q5_aligned.size):
        d = wrap_angle(q5 - g.q5_aligned[a])
        if abs(d) < abs(gap):
            nearest, gap = a, d
    if abs(gap) > 1e-3:
        return q5
    v = _mul_transposed(R, rotate(vec3(g.h[0]), q1, g.hp))
    c = cross(vec3(g.h[5]), v)
    S2 = min(dot(c, c), 1.0)
    one_minus_cos = S2 / (1.0 + math.sqrt(1.0 - S2)) / g.b_aligned
    d = 2.0 * math.asin(min(math.sqrt(0.5 * one_minus_cos), 1.0))
    if gap > 0:
        sign = 1.0
    elif gap < 0:
        sign = -1.0
    else:
        sign = 1.0 if s % 2 == 0 else -1.0  # (+d, -d) pairs
    return g.q5_aligned[nearest] + sign * d


@njit(cache=True)
def _snap_to_aligned_wrist(g, P, r, t1, t5):
    """Put q5 exactly where axis 6 is parallel to h when a quartic root is that close to it.

    There the quartic has a double root, which Newton steps reach only to ~1e-8; the
    exact value lets the family (``q6`` against ``q2 + q3 + q4``) be recognised. ``q1``
    is then solved from ``P x1 = r + Q x5`` (a 2x2 linear system).
    """
    det = P[0][0] * P[1][1] - P[0][1] * P[1][0]
    size = 1.0 + max(max(abs(P[0][0]), abs(P[0][1])), max(abs(P[1][0]), abs(P[1][1])))
    if g.q5_aligned.size == 0 or abs(det) <= 1e-9 * size:
        return
    Q = g.Q
    for i in range(4):
        nearest, gap = 0, math.inf
        for a in range(g.q5_aligned.size):
            d = abs(wrap_angle(t5[i] - g.q5_aligned[a]))
            if d < gap:
                nearest, gap = a, d
        if gap > 1e-6:
            continue
        q5 = g.q5_aligned[nearest]
        rhs0 = r[0] + Q[0, 0] * math.cos(q5) + Q[0, 1] * math.sin(q5)
        rhs1 = r[1] + Q[1, 0] * math.cos(q5) + Q[1, 1] * math.sin(q5)
        t1[i] = math.atan2((P[0][0] * rhs1 - P[1][0] * rhs0) / det, (P[1][1] * rhs0 - P[0][1] * rhs1) / det)
        t5[i] = q5


@njit(cache=True)
def _wrist_family_representative(g, s6, q6, theta, A, B):
    """Axis 6 parallel to axes 2-4: pick the ``q6`` of the family that is best reachable.

    Along the family ``q2 + q3 + q4 = theta - s q6`` (``s = +-1``: axis 6 along or against
    ``h``) the planar target ``A - R(h, theta) B`` turns on a circle; choose the angle
    that puts its length where the planar 2R reaches best (``|v|^2 = |a|^2 + |b|^2``).
    """
    h = g.hp
    A = sub(A, scale(dot(A, h), h))
    B = sub(B, scale(dot(B, h), h))
    a, b = sub(vec3(g.p[2]), vec3(g.p[1])), sub(vec3(g.p[3]), vec3(g.p[2]))
    a, b = sub(a, scale(dot(a, h), h)), sub(b, scale(dot(b, h), h))
    wanted = 0.5 * (dot(A, A) + dot(B, B) - dot(a, a) - dot(b, b))  # A . R(h, phi) B
    cos_part, sin_part = dot(A, B), dot(A, cross(h, B))
    r = math.sqrt(cos_part * cos_part + sin_part * sin_part)
    if r == 0.0:
        return q6, theta
    phi = math.atan2(sin_part, cos_part) + math.acos(min(max(wanted / r, -1.0), 1.0))
    return q6 + s6 * (theta - phi), phi


@njit(cache=True)
def _three_parallel(g, R, t, q, valid, family):
    """Axes 2-4 parallel: (q1, q5), then q6, q2 + q3 + q4 and a planar 2R: 8 candidates.

    ``g.a1, g.a2``: the closest points ``p5, p6`` of axes 5 and 6.
    """
    h = g.hp
    h0, h4, h5 = vec3(g.h[0]), vec3(g.h[4]), vec3(g.h[5])
    p0, p1, p2, p3 = vec3(g.p[0]), vec3(g.p[1]), vec3(g.p[2]), vec3(g.p[3])
    p5, p6 = g.a1, g.a2
    G_p6 = add(_mul(R, p6), t)
    e1, a1, b1 = trig_coeffs(h, _neg(h0), _mul(R, h5))
    e2, a2, b2 = trig_coeffs(h, _neg(h0), sub(G_p6, p0))
    P, r = ((a1, b1), (a2, b2)), (g.f[0] - e1, g.f[1] - e2)  # P x1 - Q x5 = r
    q1s, q5s, pair_valid, pair_free = np.empty(4), np.empty(4), np.empty(4, np.bool_), np.empty(4, np.bool_)
    two_angle_system(g, P, r, q1s, q5s, pair_valid, pair_free)
    if g.rank1:
        for i in range(4):
            q5s[i] = _q5_near_aligned_wrist(g, R, q1s[i], q5s[i], i)
    else:
        _snap_to_aligned_wrist(g, P, r, q1s, q5s)
    for i in range(4):
        q1, q5 = q1s[i], q5s[i]
        # q6: R6^T (R5^T h) = R_G^T R1 h
        v = rotate(_neg(h4), q5, h)
        q6, f6 = sp1(v, _mul_transposed(R, rotate(h0, q1, h)), _neg(h5))
        # q2 + q3 + q4: R234 = R1^T R_G R6^T R5^T, applied to a normal of h
        turned = rotate(_neg(h0), q1, _mul(R, rotate(_neg(h5), q6, rotate(_neg(h4), q5, g.u))))
        theta, _ = sp1(g.u, turned, h)
        # planar part: e2 e3 e4 y = z with y = e5 p6, z = e1^-1 G p6
        y = add(p5, rotate(h4, q5, sub(p6, p5)))
        z = add(p0, rotate(_neg(h0), q1, sub(G_p6, p0)))
        if f6:
            s6 = 1.0 if dot(v, h5) > 0 else (-1.0 if dot(v, h5) < 0 else 0.0)
            q6, theta = _wrist_family_representative(g, s6, q6, theta, sub(z, p1), sub(y, p3))
        target = sub(sub(z, p1), rotate(h, theta, sub(y, p3)))
        q2, q3, v23, f23 = planar_2r(h, sub(p2, p1), sub(p3, p2), target)
        for b in range(2):
            s = 2 * i + b
            q[s, 0], q[s, 1], q[s, 2] = q1, q2[b], q3[b]
            q[s, 3], q[s, 4], q[s, 5] = theta - q2[b] - q3[b], q5, q6
            valid[s] = pair_valid[i] and v23[b]
            family[s] = pair_free[i] or f6 or f23


# ------------------------------------------------ parallel axes 1-3 (or 4-6)
@njit(cache=True)
def _parallel_base(g, R, t, q, valid, family):
    """Axes 1-3 parallel: (q6, q4), then q5, q1 + q2 + q3 and a planar 2R: 8 candidates.

    Their motion keeps ``h``-components, which leaves two equations in ``q4`` and ``q6``:
    ``h . R4 h5 = (R_G^T h) . R6^T h5`` (orientation, since ``R5 h5 = h5``) and
    ``h . e4 o5 = h . G e6^-1 o5``. ``g.a1 .. g.a3``: points ``o4, o5, o6`` of axes 4-6
    (``o4, o5`` closest to each other).
    """
    h = g.hp
    h3, h4, h5 = vec3(g.h[3]), vec3(g.h[4]), vec3(g.h[5])
    p0, p1, p2 = vec3(g.p[0]), vec3(g.p[1]), vec3(g.p[2])
    o4, o5, o6 = g.a1, g.a2, g.a3
    gh = _mul_transposed(R, h)  # R_G^T h
    e1, a1, b1 = trig_coeffs(gh, _neg(h5), h4)
    e2, a2, b2 = trig_coeffs(gh, _neg(h5), sub(o5, o6))
    e2 += dot(add(_mul(R, o6), t), h)
    q6s, q4s, pair_valid, pair_free = np.empty(4), np.empty(4), np.empty(4, np.bool_), np.empty(4, np.bool_)
    two_angle_system(g, ((a1, b1), (a2, b2)), (g.f[0] - e1, g.f[1] - e2), q6s, q4s, pair_valid,
                     pair_free)
    z = add(_mul(R, o4), t)
    for i in range(4):
        q4, q6 = q4s[i], q6s[i]
        # q5: R5^T (R4^T h) = R6 R_G^T h
        q5, f5 = sp1(rotate(_neg(h3), q4, h), rotate(h5, q6, gh), _neg(h4))
        # q1 + q2 + q3: R123 = R_G R6^T R5^T R4^T, applied to a normal of h
        turned = rotate(_neg(h5), q6, rotate(_neg(h4), q5, rotate(_neg(h3), q4, g.u)))
        theta, _ = sp1(g.u, _mul(R, turned), h)
        # planar part: e1 e2 e3 y = z with y = e4 e5 e6 o4, z = G o4
        y = add(o6, rotate(h5, q6, sub(o4, o6)))
        y = add(o5, rotate(h4, q5, sub(y, o5)))
        y = add(o4, rotate(h3, q4, sub(y, o4)))
        target = sub(sub(z, p0), rotate(h, theta, sub(y, p2)))
        q1, q2, v12, f12 = planar_2r(h, sub(p1, p0), sub(p2, p1), target)
        for b in range(2):
            s = 2 * i + b
            q[s, 0], q[s, 1], q[s, 2] = q1[b], q2[b], theta - q1[b] - q2[b]
            q[s, 3], q[s, 4], q[s, 5] = q4, q5, q6
            valid[s] = pair_valid[i] and v12[b]
            family[s] = pair_free[i] or f5 or f12


# ----------------------------------------------------- SCARA and planar
@njit(cache=True)
def _planar(g, R, t, q, valid, family):
    """SCARA / planar arm: angle sum, height, planar 2R: 2 candidates.

    ``g.a1``: a point moved by the first two revolute joints only.
    """
    h, y = g.hp, g.a1
    rev = g.revolute_joints
    theta, _ = sp1(g.u, _mul(R, g.u), h)
    Gy = add(_mul(R, y), t)
    slide = dot(sub(Gy, y), h) if g.prismatic_joint >= 0 else 0.0
    p_a, p_b = vec3(g.p[rev[0]]), vec3(g.p[rev[1]])
    qa, qb, ok, free = planar_2r(h, sub(p_b, p_a), sub(y, p_b), sub(sub(Gy, scale(slide, h)), p_a))
    for b in range(2):
        for j in range(q.shape[1]):  # (a loop: a slice assignment costs seconds of compile time)
            q[b, j] = 0.0
        q[b, rev[0]], q[b, rev[1]] = qa[b], qb[b]
        if rev.size == 3:
            q[b, rev[2]] = theta - qa[b] - qb[b]
        if g.prismatic_joint >= 0:
            q[b, g.prismatic_joint] = slide
        valid[b], family[b] = ok[b], free


@njit(cache=True)
def solve_pose(g, R, t, q, valid, family):
    """Every candidate for the joint motion ``G = (R, t)`` (``R`` a tuple of rows): written
    into ``q`` ``(k, n)`` (internal joint order), ``valid`` and ``family`` ``(k,)``."""
    if g.kind == SPHERICAL:
        _spherical(g, R, t, q, valid, family)
    elif g.kind == THREE_PARALLEL:
        _three_parallel(g, R, t, q, valid, family)
    elif g.kind == PARALLEL_BASE:
        _parallel_base(g, R, t, q, valid, family)
    else:
        _planar(g, R, t, q, valid, family)
