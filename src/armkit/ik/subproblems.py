"""Paden-Kahan subproblems: the geometric building blocks of closed-form IK.

The subproblems are compiled in the core (``cpp/include/armkit/subproblems.hpp``, used by
the case solvers there); this module gives them to Python for the chain preparation of
:mod:`armkit.ik.closed_form` and for tests. Each call solves one instance: vectors are
3-sequences of floats, axes ``k`` unit vectors, angles floats [rad]. Rotations are
active, right-handed, about an axis through the origin: ``R(k, theta)``.

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

``sp1(p, q, k) -> (theta, free)``; ``sp2(p1, p2, k1, k2) -> (theta1, theta2, valid,
free1, free2)`` (pairs, then flags); ``sp3(p1, p2, k, d)``, ``sp4(h, p, k, d)`` and
``solve_trig_linear(a, b, c, size, snap=True)`` (all ``t`` with ``a cos t + b sin t = c``,
``size`` the size of the terms; ``snap``: a double root within ``TANGENT_TOLERANCE`` of
tangency is returned once) ``-> (theta, valid, free)``; ``planar_2r(h, a, b, v) -> (ta,
tb, valid, free)``; ``rotate(k, theta, v)``: ``R(k, theta) v``; ``trig_coeffs(h, k, v)``:
``(constant, cos_coeff, sin_coeff)`` of ``h . R(k, t) v`` as a function of ``t``.

Example
-------
>>> sp1((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))  # a quarter turn, not free
(1.5707963267948966, False)
>>> solve_trig_linear(1.0, 0.0, 0.5, 1.0)[0]  # cos t = 1/2
(1.0471975511965979, -1.0471975511965979)
"""

from __future__ import annotations

from armkit._core import (
    FREE_TOLERANCE,
    OUT_TOLERANCE,
    TANGENT_TOLERANCE,
    planar_2r,
    rotate,
    solve_trig_linear,
    sp1,
    sp2,
    sp3,
    sp4,
    trig_coeffs,
)

__all__ = [
    "FREE_TOLERANCE",
    "OUT_TOLERANCE",
    "TANGENT_TOLERANCE",
    "planar_2r",
    "rotate",
    "solve_trig_linear",
    "sp1",
    "sp2",
    "sp3",
    "sp4",
    "trig_coeffs",
]
