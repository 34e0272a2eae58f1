"""The closed-form solvers of each geometric case, one pose at a time (compiled core).

The chain is taken as screw axes at ``q = 0`` (see :mod:`armkit.ik.structure`):
``T(q) = exp(xi_1 q_1) ... exp(xi_n q_n) M``, so the target gives ``G = T M^-1``, the
motion of the joints alone. One solver per geometric case (``cpp/src/ik_case_<name>.cpp``)
splits ``G`` (rotation ``R``, translation ``t``) into Paden-Kahan subproblems
(:mod:`armkit.ik.subproblems`) and writes every candidate into the rows of ``q``
``(k, n)`` (internal joint order), with ``valid`` and ``family`` flags ``(k,)``:

* spherical wrist (axes 4-6 meet at ``c``): joints 1-3 place ``c`` at ``G c`` (SP3 / SP4
  / SP2 / planar 2R, by which pair of axes 1-3 meets or is parallel; a prismatic third
  joint gives a quadratic; general axes give two equations in ``q1, q3`` solved like the
  three-parallel case), then the wrist turns ``h6`` (SP2) and a normal of it (SP1) into
  place. A spherical base is the same on the reversed chain (the chain of ``T^-1``).
* three parallel axes 2-4 with direction ``h``: rotations about them keep ``h``-components,
  which leaves two equations in ``q1, q5`` alone (a two-angle system ``P x(t1) - Q x(t2) =
  r``, ``x(t) = [cos t, sin t]``, with ``Q`` fixed by the chain). If axes 5 and 6 meet
  (``Q`` of rank 1), a combination of them holds ``q1`` only (SP4), else they give a
  quartic in ``exp(i q1)`` (its roots by Aberth-Ehrlich iterations, then Newton steps on
  the equations themselves). Then ``q6`` (SP1), ``q2 + q3 + q4`` (SP1), and a planar 2R.
  Axes 1-3 parallel give two equations in ``q4, q6`` the same way; axes 3-5 and 4-6 are
  these cases on the reversed chain.
* SCARA and planar 2R/3R: the orientation gives the sum of the angles, a prismatic joint
  along the axes the height, and a planar 2R the rest.

Every subproblem says whether its branch exists, so for the closed paths the flags are
exact (an unreachable pose gives no valid candidate); :mod:`armkit.ik.closed_form`
verifies the over-determined and quartic paths by forward kinematics.

The cases are registered in one place, the core's registry (``kCases`` in
``cpp/include/armkit/ik_cases.hpp``): :data:`CASE_NAMES` and :data:`CASE_CANDIDATES` are read
from it. Each case has a detect function in the core (the chain's joint lines to its geometry,
or the reason it does not apply: :func:`armkit.ik.structure.analyze_structure` shows both) and
its own geometry, a plain struct bound as a class with a typed keyword constructor
(``armkit._core``, for tests that build one by hand): :class:`SphericalGeometry`,
:class:`ThreeParallelGeometry`, :class:`ParallelBaseGeometry`, :class:`PlanarGeometry`,
:class:`PointGeometry` (joints 1-3 carry a tool point: position IK) and
:class:`GeneralGeometry` (any 6R or 5R1P arm, the last case), each over a :class:`CaseChain`
(internal axes and points ``(n, 3)`` [-, m], ``prismatic`` ``(n,)``) and, where the case has
one, a :class:`TwoAngleSystem`; built once per chain by its detect function. Each has ``n``,
``k`` (candidates per pose) and ``case`` (its registry name). :func:`solve_pose`
``(geometry, R (3, 3), t (3,)) -> (q (k, n), valid (k,), family (k,))`` solves one joint motion.
"""

from __future__ import annotations

import math

from armkit import _core
from armkit._core import (
    CaseChain,
    GeneralGeometry,
    ParallelBaseGeometry,
    PlanarGeometry,
    PointGeometry,
    SphericalGeometry,
    ThreeParallelGeometry,
    TwoAngleSystem,
    solve_pose,
)

__all__ = ["CASE_NAMES", "CASE_CANDIDATES", "MAX_CANDIDATES", "POSITION_CASES", "TWO_PI", "CaseChain",
           "CaseGeometry", "GeneralGeometry", "ParallelBaseGeometry", "PlanarGeometry", "PointGeometry",
           "SphericalGeometry", "ThreeParallelGeometry", "TwoAngleSystem", "solve_pose"]

#: The registered cases, in the core's order (the general solver last), and the candidates
#: per pose of each: one fixed-capacity buffer of :data:`MAX_CANDIDATES` holds any of them.
CASE_NAMES: tuple[str, ...] = _core.CASE_NAMES
CASE_CANDIDATES: tuple[int, ...] = _core.CASE_CANDIDATES
MAX_CANDIDATES: int = _core.MAX_CANDIDATES
#: How joints 1-3 of a spherical-wrist arm (or a point case) place the wrist centre
#: (``position_case`` of :class:`PointGeometry`, an index into this).
POSITION_CASES: tuple[str, ...] = _core.POSITION_CASES
#: Any case's geometry.
CaseGeometry = (SphericalGeometry | ThreeParallelGeometry | ParallelBaseGeometry | PlanarGeometry
                | PointGeometry | GeneralGeometry)
TWO_PI = 2.0 * math.pi
