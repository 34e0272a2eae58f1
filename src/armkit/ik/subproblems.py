"""Paden-Kahan subproblems: the geometric building blocks of closed-form IK.

Every function here is compiled by numba (``@njit``) and works on one instance: vectors
are 3-tuples of floats (the kernels keep them in registers, nothing is allocated), axes
``k`` are unit vectors, angles are floats. Rotations are active, right-handed, about an
axis through the origin: ``R(k, theta)``. From Python, pass tuples (``(0.0, 0.0, 1.0)``).

The subproblems that can have two solutions return both as a pair together with a pair
of ``valid`` flags; a tangent (double) solution is returned once (second branch
invalid), a slightly impossible instance (within ``OUT_TOLERANCE``, from rounding) is
treated as tangent, and an instance whose solution set is a whole circle returns the
representative ``theta = 0`` with ``free = True``.

=====  ================================================  ==================
name   equation                                          solutions
=====  ================================================  ==================
SP1    ``R(k, t) p = q``                                 1 (least squares)
SP2    ``R(k1, t1) p1 = R(k2, t2) p2``                   0, 1 or 2 pairs
SP3    ``|R(k, t) p1 - p2| = d``                         0, 1 or 2
SP4    ``h . R(k, t) p = d``                             0, 1 or 2
2R     ``R(h, ta) (a + R(h, tb) b) = v`` (planar)        0, 1 or 2 pairs
=====  ================================================  ==================

Example
-------
>>> sp1((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))  # a quarter turn, not free
(1.5707963267948966, False)
"""

from __future__ import annotations

import math

from numba import njit

__all__ = [
    "FREE_TOLERANCE",
    "OUT_TOLERANCE",
    "TANGENT_TOLERANCE",
    "add",
    "cross",
    "dot",
    "planar_2r",
    "rotate",
    "scale",
    "solve_trig_linear",
    "sp1",
    "sp2",
    "sp3",
    "sp4",
    "sub",
    "vec3",
]

#: Relative amount by which an instance may be impossible and still count as tangent.
OUT_TOLERANCE = 1e-9
#: Relative distance to tangency below which a double solution is returned once. Only the
#: subproblems whose error is second order in the angle (SP3, SP4) snap to tangency.
TANGENT_TOLERANCE = 1e-14
#: Relative size below which a vector counts as lying on the rotation axis (any angle).
FREE_TOLERANCE = 1e-12

_FREE2 = FREE_TOLERANCE * FREE_TOLERANCE


# ------------------------------------------------------------------ 3-vectors
@njit(cache=True)
def vec3(a):
    """The first three entries of an array as a 3-tuple."""
    return (a[0], a[1], a[2])


@njit(cache=True)
def add(a, b):
    """``a + b``."""
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


@njit(cache=True)
def sub(a, b):
    """``a - b``."""
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


@njit(cache=True)
def scale(s, a):
    """``s a`` for a number ``s``."""
    return (s * a[0], s * a[1], s * a[2])


@njit(cache=True)
def dot(a, b):
    """``a . b``."""
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@njit(cache=True)
def cross(a, b):
    """``a x b``."""
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


@njit(cache=True)
def rotate(k, theta, v):
    """``R(k, theta) v`` by Rodrigues' formula (``k`` a unit vector).

    >>> [round(x, 12) for x in rotate((0.0, 0.0, 1.0), 0.5 * math.pi, (1.0, 0.0, 0.0))]
    [0.0, 1.0, 0.0]
    """
    along = scale(dot(k, v), k)  # the part of v on the axis stays; the rest turns
    c, s = math.cos(theta), math.sin(theta)
    return add(add(along, scale(c, sub(v, along))), scale(s, cross(k, v)))


# ---------------------------------------------------------------- subproblems
@njit(cache=True)
def sp1(p, q, k):
    """SP1: the angle ``t`` with ``R(k, t) p = q`` (least squares if ``|p| != |q|``).

    Returns
    -------
    theta : float
        Angle [rad] in ``(-pi, pi]``; 0 where ``p`` lies on the axis.
    free : bool
        ``p`` (or ``q``) lies on the axis: every angle is a solution.
    """
    kxp = cross(k, p)  # its length: the distance of p from the axis
    kxq = cross(k, q)
    free = dot(kxp, kxp) <= _FREE2 * dot(p, p) or dot(kxq, kxq) <= _FREE2 * dot(q, q)
    if free:
        return 0.0, True
    p_perp = sub(p, scale(dot(k, p), k))
    return math.atan2(dot(kxp, q), dot(p_perp, q)), False


@njit(cache=True)
def solve_trig_linear(a, b, c, size, snap=True):
    """All ``t`` with ``a cos t + b sin t = c``; ``size`` is the size of the terms.

    ``snap``: within ``TANGENT_TOLERANCE`` of tangency return the double root once (its
    error is second order where the caller only needs the equation to hold); without it
    both branches are returned, which a caller refining the angle itself needs.

    Returns
    -------
    theta : (float, float)
        The two branches ``atan2(b, a) +- acos(c / hypot(a, b))`` [rad].
    valid : (bool, bool)
        Branch exists; at tangency only the first one.
    free : bool
        ``a = b = c = 0``: every angle is a solution (``theta = 0`` returned).

    >>> solve_trig_linear(1.0, 0.0, 0.5, 1.0)[0]  # cos t = 1/2
    (1.0471975511965979, -1.0471975511965979)
    """
    r = math.sqrt(a * a + b * b)
    if r <= FREE_TOLERANCE * size:
        free = abs(c) <= OUT_TOLERANCE * size
        return (0.0, 0.0), (free, False), free
    x = c / r
    if abs(x) > 1.0 + OUT_TOLERANCE:
        return (0.0, 0.0), (False, False), False
    phi = math.atan2(b, a)
    if snap and abs(x) >= 1.0 - TANGENT_TOLERANCE:
        delta = 0.0 if x > 0 else math.pi
        return (phi + delta, phi - delta), (True, False), False
    delta = math.acos(min(max(x, -1.0), 1.0))
    return (phi + delta, phi - delta), (True, True), False


@njit(cache=True)
def sp4(h, p, k, d):
    """SP4: all ``t`` with ``h . R(k, t) p = d`` (``h`` any vector), see :func:`solve_trig_linear`.

    Example: the heights ``z . R(x, t) [0, 1, 0] = 0.5`` give ``t = pi/6`` and ``5 pi/6``.
    """
    kp = dot(k, p)
    hk = dot(h, k)
    size = math.sqrt(dot(h, h) * dot(p, p)) + abs(d)
    return solve_trig_linear(dot(h, p) - hk * kp, dot(h, cross(k, p)), d - hk * kp, size)


@njit(cache=True)
def sp3(p1, p2, k, d):
    """SP3: all ``t`` with ``|R(k, t) p1 - p2| = d`` (``d >= 0``), see :func:`solve_trig_linear`.

    Expanding the square turns it into SP4: ``p2 . R(k, t) p1 = (|p1|^2 + |p2|^2 - d^2) / 2``.
    """
    return sp4(p2, p1, k, 0.5 * (dot(p1, p1) + dot(p2, p2) - d * d))


@njit(cache=True)
def _angles_to_branches(kxp, p_perp, base, n, gamma):
    """SP1 onto both points ``x = base +- gamma n``: the two angles [rad].

    For ``R(k, t) p = x`` the angle is ``atan2((k x p) . x, p_perp . x)``, linear in
    ``gamma``: four dot products instead of building both points.
    """
    sin0, sin1 = dot(kxp, base), gamma * dot(kxp, n)
    cos0, cos1 = dot(p_perp, base), gamma * dot(p_perp, n)
    return math.atan2(sin0 + sin1, cos0 + cos1), math.atan2(sin0 - sin1, cos0 - cos1)


@njit(cache=True)
def sp2(p1, p2, k1, k2):
    """SP2: all ``(t1, t2)`` with ``R(k1, t1) p1 = R(k2, t2) p2`` for non-parallel ``k1, k2``.

    The common point ``x`` satisfies ``k1 . x = k1 . p1``, ``k2 . x = k2 . p2`` and
    ``|x| = |p1|``: ``x = alpha k1 + beta k2 +- gamma (k1 x k2)``.

    Returns
    -------
    theta1, theta2 : (float, float)
        Angles [rad] of the two branches.
    valid : (bool, bool)
        Branch exists (one branch when the circles touch).
    free1, free2 : bool
        ``p1`` lies on ``k1`` (``t1`` arbitrary, 0 returned) or ``p2`` on ``k2``.
    """
    c12 = dot(k1, k2)
    a1, a2 = dot(k1, p1), dot(k2, p2)
    det = 1.0 - c12 * c12
    base = add(scale((a1 - c12 * a2) / det, k1), scale((a2 - c12 * a1) / det, k2))
    n = cross(k1, k2)
    n1, n2 = dot(p1, p1), dot(p2, p2)
    norm2 = 0.5 * (n1 + n2)
    # gamma^2 det^2 = r1^2 det - (a2 - c12 a1)^2 with r1 = |k1 x p1| the radius of p1's
    # circle (or the same with 1 <-> 2): no cancellation against |p|^2, so a tiny circle
    # (a wrist near its singularity) keeps its relative accuracy. Use the smaller circle.
    c1, c2 = cross(k1, p1), cross(k2, p2)
    r1, r2 = dot(c1, c1), dot(c2, c2)
    if r1 <= r2:
        gamma2 = (r1 * det - (a2 - c12 * a1) ** 2) / (det * det)
    else:
        gamma2 = (r2 * det - (a1 - c12 * a2) ** 2) / (det * det)
    exists = gamma2 >= -OUT_TOLERANCE * norm2 and abs(n1 - n2) <= OUT_TOLERANCE * norm2
    free1 = r1 <= _FREE2 * n1
    free2 = r2 <= _FREE2 * n2
    gamma = math.sqrt(max(gamma2, 0.0))
    if free1 or free2:  # a point on its axis stays put: the common point is that point itself
        base = p1 if free1 else p2
        gamma = 0.0
    theta1 = (0.0, 0.0) if free1 else _angles_to_branches(c1, sub(p1, scale(a1, k1)), base, n, gamma)
    theta2 = (0.0, 0.0) if free2 else _angles_to_branches(c2, sub(p2, scale(a2, k2)), base, n, gamma)
    single = gamma2 <= 0.0 or free1 or free2
    return theta1, theta2, (exists, exists and not single), free1, free2


@njit(cache=True)
def _in_plane(v, h):
    """``v`` minus its component along the unit vector ``h``."""
    return sub(v, scale(dot(v, h), h))


@njit(cache=True)
def planar_2r(h, a, b, v):
    """All ``(ta, tb)`` with ``R(h, ta) (a + R(h, tb) b) = v`` in the plane normal to ``h``.

    Components along ``h`` are ignored (the caller makes them consistent).

    Returns
    -------
    ta, tb : (float, float)
        Angles [rad] of the two branches (elbow one way and the other).
    valid : (bool, bool)
        Branch exists (one at a stretched or folded elbow).
    free : bool
        The middle point lies on the first axis (``ta`` arbitrary) or ``b`` on the second.
    """
    a, b, v = _in_plane(a, h), _in_plane(b, h), _in_plane(v, h)
    tb, valid, free_b = sp3(b, scale(-1.0, a), h, math.sqrt(dot(v, v)))
    # ta: SP1 turning u = a + R(h, tb) b onto v. With b normal to h, R(h, tb) b = cos b +
    # sin (h x b), so (h x u) . v and u . v are linear in cos tb, sin tb.
    hbv, bv = dot(cross(h, b), v), dot(b, v)
    hav, av = dot(cross(h, a), v), dot(a, v)
    # v on the first axis (to rounding, relative to the links' size): ta is arbitrary
    if math.sqrt(dot(v, v)) <= FREE_TOLERANCE * (math.sqrt(dot(a, a)) + math.sqrt(dot(b, b))):
        return (0.0, 0.0), tb, valid, True
    c0, s0 = math.cos(tb[0]), math.sin(tb[0])
    c1, s1 = math.cos(tb[1]), math.sin(tb[1])
    ta = (math.atan2(hav + c0 * hbv - s0 * bv, av + c0 * bv + s0 * hbv),
          math.atan2(hav + c1 * hbv - s1 * bv, av + c1 * bv + s1 * hbv))
    return ta, tb, valid, free_b
