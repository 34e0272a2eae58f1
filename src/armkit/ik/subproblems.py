"""Paden-Kahan subproblems: the geometric building blocks of closed-form IK.

Every function is vectorised: vectors have shape ``(..., 3)`` and broadcast against each
other, angles have shape ``(...)``. Axes ``k`` are unit vectors. Rotations are active,
right-handed, about an axis through the origin: ``R(k, theta)``.

The subproblems that can have two solutions return both in a trailing axis of length 2
together with a ``valid`` mask; a tangent (double) solution is returned once (second
branch invalid), a slightly impossible instance (within ``OUT_TOLERANCE``, from rounding)
is treated as tangent, and an instance whose solution set is a whole circle returns the
representative ``theta = 0`` with ``free = True``.

=====  ================================================  ==================
name   equation                                          solutions
=====  ================================================  ==================
SP1    ``R(k, t) p = q``                                 1 (least squares)
SP2    ``R(k1, t1) p1 = R(k2, t2) p2``                   0, 1 or 2 pairs
SP3    ``|R(k, t) p1 - p2| = d``                         0, 1 or 2
SP4    ``h . R(k, t) p = d``                             0, 1 or 2
=====  ================================================  ==================

Example
-------
>>> import numpy as np
>>> z = np.array([0.0, 0.0, 1.0])
>>> float(sp1(np.array([1.0, 0, 0]), np.array([0.0, 1, 0]), z)[0])  # quarter turn
1.5707963267948966
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "FREE_TOLERANCE",
    "OUT_TOLERANCE",
    "TANGENT_TOLERANCE",
    "cos_sin",
    "cross",
    "dot",
    "rotate",
    "rotation_matrix",
    "solve_trig_linear",
    "sp1",
    "sp2",
    "sp3",
    "sp4",
]

#: Relative amount by which an instance may be impossible and still count as tangent.
OUT_TOLERANCE = 1e-9
#: Relative distance to tangency below which a double solution is returned once. Only the
#: subproblems whose error is second order in the angle (SP3, SP4) snap to tangency.
TANGENT_TOLERANCE = 1e-14
#: Relative size below which a vector counts as lying on the rotation axis (any angle).
FREE_TOLERANCE = 1e-12

Array = NDArray[np.float64]


def dot(a: Array, b: Array) -> Array:
    """Row-wise dot product of ``(..., 3)`` vectors, shape ``(...)``."""
    if a.ndim == 1:  # one constant vector: a single 2-D matrix product
        a, b = b, a
    if b.ndim == 1:
        return a @ b if a.ndim <= 2 else (a.reshape(-1, 3) @ b).reshape(a.shape[:-1])
    return np.einsum("...i,...i->...", a, b)


@lru_cache(maxsize=256)
def _skew_transposed(key: bytes) -> Array:
    """``[k]_x^T`` (read-only) for the float64 vector ``k`` given by its bytes (memoised:
    the solvers cross with a few constant axes, thousands of times)."""
    k = np.frombuffer(key)
    S = np.array([[0.0, k[2], -k[1]], [-k[2], 0.0, k[0]], [k[1], -k[0], 0.0]])
    S.setflags(write=False)
    return S


def cross(a: Array, b: Array) -> Array:
    """Row-wise cross product of ``(..., 3)`` vectors (broadcasting), shape ``(..., 3)``."""
    if a.ndim == 1:  # a x b = [a]_x b, one 2-D matrix product for a constant a
        return (b.reshape(-1, 3) @ _skew_transposed(a.astype(float, copy=False).tobytes())).reshape(b.shape)
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    return np.stack([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0], axis=-1)


def cos_sin(theta: Array) -> tuple[Array, Array]:
    """``(cos theta, sin theta)``; for many angles from ``t = tan(theta / 2)``.

    NumPy's float64 ``tan`` is several times faster than its ``sin`` and ``cos`` on large
    arrays; ``cos = (1 - t^2) / (1 + t^2)``, ``sin = 2 t / (1 + t^2)`` are accurate to a few
    units in the last place (absolute), also where ``t`` is huge (``theta`` near ``pi``).
    """
    if np.size(theta) < 256:
        return np.cos(theta), np.sin(theta)
    t = np.tan(0.5 * theta)
    scale = 1.0 / (1.0 + t * t)
    return (1.0 - t * t) * scale, 2.0 * t * scale


def rotate(k: Array, theta: Array, v: Array) -> Array:
    """``R(k, theta) v`` by Rodrigues' formula, shape ``(..., 3)``."""
    along = dot(k, v)[..., None] * k  # the part of v on the axis stays; the rest turns
    cos, sin = cos_sin(theta)
    return along + cos[..., None] * (v - along) + sin[..., None] * cross(k, v)


def rotation_matrix(k: Array, theta: Array) -> Array:
    """``R(k, theta)`` as matrices ``(..., 3, 3)`` for unit axes ``(..., 3)``, angles ``(...)``."""
    k = np.asarray(k, dtype=float)
    theta = np.asarray(theta, dtype=float)
    c, s = np.cos(theta)[..., None, None], np.sin(theta)[..., None, None]
    K = np.zeros((*k.shape[:-1], 3, 3))
    K[..., 0, 1], K[..., 0, 2], K[..., 1, 2] = -k[..., 2], k[..., 1], -k[..., 0]
    K[..., 1, 0], K[..., 2, 0], K[..., 2, 1] = k[..., 2], -k[..., 1], k[..., 0]
    return np.eye(3) + s * K + (1.0 - c) * (K @ K)


def sp1(p: Array, q: Array, k: Array) -> tuple[Array, NDArray[np.bool_]]:
    """SP1: the angle ``t`` with ``R(k, t) p = q`` (least squares if ``|p| != |q|``).

    Returns
    -------
    theta : ndarray (...)
        Angle [rad] in ``(-pi, pi]``; 0 where ``p`` lies on the axis.
    free : ndarray of bool (...)
        ``p`` (or ``q``) lies on the axis: every angle is a solution.
    """
    p_perp = p - dot(k, p)[..., None] * k
    kxp, kxq = cross(k, p), cross(k, q)  # their lengths: distances from the axis
    sin_part = dot(kxp, q)  # k . (p_perp x q)
    cos_part = dot(p_perp, q)
    tol2 = FREE_TOLERANCE ** 2
    free = (dot(kxp, kxp) <= tol2 * dot(p, p)) | (dot(kxq, kxq) <= tol2 * dot(q, q))
    theta = np.where(free, 0.0, np.arctan2(sin_part, cos_part))
    return theta, free


def solve_trig_linear(a: Array, b: Array, c: Array, scale: Array, snap: bool = True
                      ) -> tuple[Array, NDArray[np.bool_], NDArray[np.bool_]]:
    """All ``t`` with ``a cos t + b sin t = c``; ``scale`` is the size of the terms.

    ``snap``: within ``TANGENT_TOLERANCE`` of tangency return the double root once (its
    error is second order where the caller only needs the equation to hold); without it
    both branches are returned, which a caller refining the angle itself needs.

    Returns
    -------
    theta : ndarray (..., 2)
        The two branches ``atan2(b, a) +- acos(c / hypot(a, b))`` [rad].
    valid : ndarray of bool (..., 2)
        Branch exists; at tangency only the first one.
    free : ndarray of bool (...)
        ``a = b = c = 0``: every angle is a solution (``theta = 0`` returned).
    """
    r = np.sqrt(a * a + b * b)  # not np.hypot: several times slower on large arrays
    degenerate = r <= FREE_TOLERANCE * scale
    free = degenerate & (np.abs(c) <= OUT_TOLERANCE * scale)
    x = c / np.where(degenerate, 1.0, r)
    exists = ~degenerate & (np.abs(x) <= 1.0 + OUT_TOLERANCE)
    tangent = np.abs(x) >= 1.0 - TANGENT_TOLERANCE if snap else np.zeros(np.shape(x), dtype=bool)
    delta = np.where(tangent, np.where(x > 0, 0.0, np.pi), np.arccos(np.clip(x, -1.0, 1.0)))
    phi = np.arctan2(b, a)
    theta = np.stack([phi + delta, phi - delta], axis=-1)
    valid = np.stack([exists | free, exists & ~tangent], axis=-1)
    theta = np.where(free[..., None], 0.0, theta)
    return theta, valid, free


def sp4(h: Array, p: Array, k: Array, d: Array) -> tuple[Array, NDArray[np.bool_], NDArray[np.bool_]]:
    """SP4: all ``t`` with ``h . R(k, t) p = d`` (``h`` any vector), see :func:`solve_trig_linear`.

    Example: the heights ``z . R(x, t) [0, 1, 0] = 0.5`` give ``t = pi/6`` and ``5 pi/6``.
    """
    kp = dot(k, p)
    hk = dot(h, k)
    a = dot(h, p) - hk * kp
    b = dot(h, cross(k, p))
    scale = np.sqrt(dot(h, h) * dot(p, p)) + np.abs(d)
    return solve_trig_linear(a, b, d - hk * kp, scale)


def sp3(p1: Array, p2: Array, k: Array, d: Array) -> tuple[Array, NDArray[np.bool_], NDArray[np.bool_]]:
    """SP3: all ``t`` with ``|R(k, t) p1 - p2| = d`` (``d >= 0``), see :func:`solve_trig_linear`.

    Expanding the square turns it into SP4: ``p2 . R(k, t) p1 = (|p1|^2 + |p2|^2 - d^2) / 2``.
    """
    rhs = 0.5 * (dot(p1, p1) + dot(p2, p2) - d * d)
    return sp4(p2, p1, k, rhs)


def _angles_to_branches(kxp: Array, p_perp: Array, base: Array, n: Array, gamma: Array) -> Array:
    """SP1 onto both points ``x = base +- gamma n``: the angles ``(..., 2)`` [rad].

    For ``R(k, t) p = x`` the angle is ``atan2((k x p) . x, p_perp . x)``, linear in
    ``gamma``: four dot products instead of building both points.
    """
    sign = np.array([1.0, -1.0])
    g = gamma[..., None] * sign
    sin = dot(kxp, base)[..., None] + g * dot(kxp, n)[..., None]
    cos = dot(p_perp, base)[..., None] + g * dot(p_perp, n)[..., None]
    return np.arctan2(sin, cos)


def sp2(p1: Array, p2: Array, k1: Array, k2: Array
        ) -> tuple[Array, Array, NDArray[np.bool_], NDArray[np.bool_], NDArray[np.bool_]]:
    """SP2: all ``(t1, t2)`` with ``R(k1, t1) p1 = R(k2, t2) p2`` for non-parallel ``k1, k2``.

    The common point ``x`` satisfies ``k1 . x = k1 . p1``, ``k2 . x = k2 . p2`` and
    ``|x| = |p1|``: ``x = alpha k1 + beta k2 +- gamma (k1 x k2)``.

    Returns
    -------
    theta1, theta2 : ndarray (..., 2)
        Angles [rad] of the two branches.
    valid : ndarray of bool (..., 2)
        Branch exists (one branch when the circles touch).
    free1, free2 : ndarray of bool (...)
        ``p1`` lies on ``k1`` (``t1`` arbitrary, 0 returned) or ``p2`` on ``k2``.
    """
    c12 = dot(k1, k2)
    a1, a2 = dot(k1, p1), dot(k2, p2)
    det = 1.0 - c12 * c12
    alpha = ((a1 - c12 * a2) / det)[..., None]
    beta = ((a2 - c12 * a1) / det)[..., None]
    base = alpha * k1 + beta * k2
    n = cross(k1, k2)
    n1, n2 = dot(p1, p1), dot(p2, p2)
    norm2 = 0.5 * (n1 + n2)
    # gamma^2 det^2 = r1^2 det - (a2 - c12 a1)^2 with r1 = |k1 x p1| the radius of p1's
    # circle (or the same with 1 <-> 2): no cancellation against |p|^2, so a tiny circle
    # (a wrist near its singularity) keeps its relative accuracy. Use the smaller circle.
    c1, c2 = cross(k1, p1), cross(k2, p2)
    r1, r2 = dot(c1, c1), dot(c2, c2)
    gamma2 = np.where(r1 <= r2, r1 * det - (a2 - c12 * a1) ** 2,
                      r2 * det - (a1 - c12 * a2) ** 2) / (det * det)
    exists = (gamma2 >= -OUT_TOLERANCE * norm2) & (np.abs(n1 - n2) <= OUT_TOLERANCE * norm2)
    free1 = r1 <= (FREE_TOLERANCE ** 2) * n1
    free2 = r2 <= (FREE_TOLERANCE ** 2) * n2
    gamma = np.sqrt(np.maximum(gamma2, 0.0))
    on_axis = free1 | free2
    if np.any(on_axis):  # a point on its axis stays put: the common point is that point itself
        base = np.where(free1[..., None], p1, np.where(free2[..., None], p2, base))
        gamma = np.where(on_axis, 0.0, gamma)
    theta1 = _angles_to_branches(c1, p1 - a1[..., None] * k1, base, n, gamma)
    theta2 = _angles_to_branches(c2, p2 - a2[..., None] * k2, base, n, gamma)
    theta1 = np.where(free1[..., None], 0.0, theta1)
    theta2 = np.where(free2[..., None], 0.0, theta2)
    single = (gamma2 <= 0.0) | free1 | free2
    valid = np.stack([exists, exists & ~single], axis=-1)
    return theta1, theta2, valid, free1, free2
