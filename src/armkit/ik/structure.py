"""Which closed-form IK applies to a chain, decided from the geometry of its joint axes.

At ``q = 0`` every joint ``i`` moves about (or along) a line: direction ``h_i``, through
a point ``p_i``, both in the base frame, with base and tool transforms folded in. The
chain is then the product of exponentials ``T(q) = exp(xi_1 q_1) ... exp(xi_n q_n) M``
with ``M = T(0)``. From these lines alone (never from a robot's name or DH convention):

==================  =========================================================  ========
kind                geometry                                                   max sol.
==================  =========================================================  ========
spherical-wrist     6 joints, revolute axes 4-6 meet at one point; joints 1-3  8
                    revolute, or joint 3 prismatic with axes 1, 2 meeting
                    (PROBOT Anno, PUMA 560, Stanford arm)
spherical-base      the same with axes 1-3 meeting at one point                8
three-parallel      6 revolute joints, three consecutive axes parallel (UR5,   8
                    ZJU-I: axes 2-4)
scara               3 parallel revolute axes and a prismatic joint along them  2
planar-2r/3r        2 or 3 parallel revolute axes (optionally one prismatic)   2
rank-deficient      the Jacobian has rank < min(6, n) everywhere (collinear    0
                    axes, or axes that only ever span 5 directions)
none                anything else (redundant arms, general 6R, ...)            0
==================  =========================================================  ========

Example
-------
>>> import armkit
>>> analyze_structure(armkit.load("ur5")).kind
'three-parallel'
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from armkit.chain import Chain, as_chain
from armkit.kinematics import geometric_jacobian, joint_frames
from armkit.spatial.lines import closest_points

if TYPE_CHECKING:
    from armkit.robot import Robot

__all__ = ["ArmStructure", "PoeChain", "SolverPlan", "analyze_structure", "generic_rank", "plan_closed_form",
           "poe_from_chain", "position_joints_case"]


@dataclass(frozen=True)
class ArmStructure:
    """The kind of arm a chain is, as far as closed-form IK is concerned.

    Attributes
    ----------
    kind : str
        ``"spherical-wrist"``, ``"spherical-base"``, ``"three-parallel"``, ``"scara"``,
        ``"planar-2r"``, ``"planar-3r"``, ``"general-6r"`` (any other 6R arm: every
        solution by elimination), ``"rank-deficient"`` (fewer independent
        directions of motion than joints, up to 6) or ``"none"``.
    closed_form : bool
        Whether :func:`armkit.ik.closed_form_ik` solves this chain.
    max_solutions : int
        Upper bound on the number of isolated solutions (0 without closed form).
    description : str
        One sentence saying which axes meet or are parallel, or why no closed form applies.
    """

    kind: str
    closed_form: bool
    max_solutions: int
    description: str


@dataclass(frozen=True)
class PoeChain:
    """A chain as screw axes at ``q = 0``, possibly reordered for a solver.

    Internal joint ``j`` turns about (or slides along) the line through ``points[j]`` with
    direction ``axes[j]``; the user's joint values are ``q[index[j]] = sign[j] * q_int[j]``
    (a solver may reverse the chain or flip axes to make parallel ones point alike).
    ``inverted``: the chain describes ``T^-1`` (a reversed chain), so solve for the inverse.
    """

    axes: NDArray[np.float64]
    points: NDArray[np.float64]
    prismatic: NDArray[np.bool_]
    M: NDArray[np.float64]
    index: NDArray[np.int_]
    sign: NDArray[np.float64]
    inverted: bool = False

    @property
    def n(self) -> int:
        """Number of joints."""
        return len(self.axes)

    def reversed(self) -> PoeChain:
        """The chain of ``T^-1``: joints in reverse order, ``M -> M^-1``, angles negated."""
        R_t = self.M[:3, :3].T
        M_inv = np.eye(4)
        M_inv[:3, :3] = R_t
        M_inv[:3, 3] = -R_t @ self.M[:3, 3]
        return PoeChain(self.axes[::-1] @ R_t.T, (self.points[::-1] - self.M[:3, 3]) @ R_t.T,
                        self.prismatic[::-1], M_inv, self.index[::-1], -self.sign[::-1],
                        not self.inverted)

    def aligned(self, joints: list[int], h: NDArray[np.float64]) -> PoeChain:
        """Flip the axes of ``joints`` that point against ``h`` (negating their variable)."""
        flip = np.ones(self.n)
        flip[joints] = np.where(self.axes[joints] @ h < 0, -1.0, 1.0)
        return replace(self, axes=self.axes * flip[:, None], sign=self.sign * flip)


@dataclass(frozen=True)
class SolverPlan:
    """What :mod:`armkit.ik.closed_form` needs: the case, the prepared chain and a point.

    ``case`` names the sub-case of the position problem (e.g. ``"parallel-23"``),
    ``point`` is the wrist centre or an intersection point where the case has one.
    """

    structure: ArmStructure
    poe: PoeChain
    case: str = ""
    point: NDArray[np.float64] | None = None
    point2: NDArray[np.float64] | None = None


def poe_from_chain(chain: Chain) -> PoeChain:
    """Screw axes ``(n, 3)``, points ``(n, 3)`` and ``M = T(0)`` of a chain, base frame."""
    frames, M = joint_frames(chain, np.zeros(chain.n))
    return PoeChain(frames[:, :3, 2].copy(), frames[:, :3, 3].copy(), chain.prismatic.copy(),
                    M, np.arange(chain.n), np.ones(chain.n))


class _Geometry:
    """Tests on the joint lines of one (possibly reversed) chain, with a length tolerance."""

    def __init__(self, poe: PoeChain, tol: float) -> None:
        self.poe = poe
        scale = 1.0 + max(np.abs(poe.points).max(), np.abs(poe.M[:3, 3]).max())
        self.tol = tol * scale
        self.angle_tol = tol

    def parallel(self, i: int, j: int) -> bool:
        return bool(np.linalg.norm(np.cross(self.poe.axes[i], self.poe.axes[j])) <= self.angle_tol)

    def distance_to_line(self, point: NDArray[np.float64], i: int) -> float:
        d = point - self.poe.points[i]
        h = self.poe.axes[i]
        return float(np.linalg.norm(d - (d @ h) * h))

    def intersection(self, i: int, j: int) -> NDArray[np.float64] | None:
        """The point where revolute axes ``i`` and ``j`` meet, or None."""
        if self.poe.prismatic[i] or self.poe.prismatic[j] or self.parallel(i, j):
            return None
        a, b = closest_points(self.poe.points[i], self.poe.axes[i], self.poe.points[j], self.poe.axes[j])
        return 0.5 * (a + b) if np.linalg.norm(a - b) <= self.tol else None

    def meet(self, i: int, j: int, k: int) -> NDArray[np.float64] | None:
        """The point where revolute axes ``i, j, k`` meet (middle one not parallel), or None."""
        point = self.intersection(i, j) if not self.parallel(i, j) else None
        if point is None or self.parallel(j, k):
            return None
        return point if self.distance_to_line(point, k) <= self.tol else None


def _axes(joints: list[int] | tuple[int, ...], poe: PoeChain) -> str:
    """User's 1-based numbers of internal joints, e.g. ``"axes 4, 5, 6"``."""
    numbers = sorted(int(poe.index[j]) + 1 for j in joints)
    return ", ".join(str(n) for n in numbers)


def _position_case(g: _Geometry) -> tuple[str, NDArray[np.float64] | None, str] | None:
    """How joints 1-3 place the wrist centre: case name, point, human clause."""
    poe = g.poe
    revolute = ~poe.prismatic
    if revolute[:3].all() and g.parallel(1, 2) and not g.parallel(0, 1):
        return "parallel-23", None, f"axes {_axes([1, 2], poe)} are parallel"
    if revolute[:2].all():
        point = g.intersection(0, 1)
        if point is not None:
            kind = "prismatic" if poe.prismatic[2] else "revolute"
            return f"intersect-12-{kind}", point, f"axes {_axes([0, 1], poe)} meet"
    if revolute[:3].all():
        point = g.intersection(1, 2)
        if point is not None:
            return "intersect-23", point, f"axes {_axes([1, 2], poe)} meet"
        if g.parallel(0, 1) and not g.parallel(1, 2):
            return "parallel-12", None, f"axes {_axes([0, 1], poe)} are parallel"
        if not g.parallel(0, 1) and not g.parallel(1, 2):
            return "general-123", None, (f"axes {_axes([0, 1, 2], poe)} neither meet nor are "
                                         f"parallel (a quartic)")
    return None


def _spherical(poe: PoeChain, tol: float, kind: str) -> SolverPlan | None:
    g = _Geometry(poe, tol)
    if poe.prismatic[3:].any():
        return None
    centre = g.meet(3, 4, 5)
    if centre is None:
        return None
    where = "wrist" if kind == "spherical-wrist" else "base"
    meet = f"spherical {where}: axes {_axes([3, 4, 5], poe)} meet at one point"
    position = _position_case(g)
    if position is None:
        structure = ArmStructure(kind, False, 0, f"{meet}, but joints {_axes([0, 1, 2], poe)} "
                                 f"are not solved in closed form here (a prismatic joint, or "
                                 f"degenerate axes); use numeric IK")
        return SolverPlan(structure, poe)
    case, point, clause = position
    if case.startswith("parallel"):
        pair = [1, 2] if case == "parallel-23" else [0, 1]
        poe = poe.aligned(pair, poe.axes[pair[0]])
    structure = ArmStructure(kind, True, 8, f"{meet} and {clause}: closed-form IK, "
                                            f"up to 8 solutions")
    return SolverPlan(structure, poe, case, centre, point)


def _three_parallel(poe: PoeChain, tol: float, first: int) -> SolverPlan | None:
    """Revolute axes ``first .. first + 2`` parallel (internal 0 or 1), the others not."""
    g = _Geometry(poe, tol)
    block = [first, first + 1, first + 2]
    if poe.prismatic.any() or not (g.parallel(block[0], block[1]) and g.parallel(block[0], block[2])):
        return None
    # the axes next to the block must leave it, and the ones after must not be parallel
    before, after = (0, 4) if first == 1 else (None, 3)
    if (before is not None and g.parallel(before, first)) or g.parallel(after, first) \
            or g.parallel(after, after + 1) or g.parallel(4, 5):
        return None
    poe = poe.aligned(block, poe.axes[first])
    structure = ArmStructure("three-parallel", True, 8,
                             f"three parallel axes: axes {_axes(block, poe)} are parallel: "
                             f"closed-form IK, up to 8 solutions")
    return SolverPlan(structure, poe, "parallel-234" if first == 1 else "parallel-123")


def _planar(poe: PoeChain, tol: float) -> SolverPlan | None:
    g = _Geometry(poe, tol)
    revolute = [j for j in range(poe.n) if not poe.prismatic[j]]
    prismatic = [j for j in range(poe.n) if poe.prismatic[j]]
    if len(revolute) not in (2, 3) or len(prismatic) > 1:
        return None
    if not all(g.parallel(revolute[0], j) for j in revolute[1:] + prismatic):
        return None
    poe = poe.aligned(list(range(poe.n)), poe.axes[revolute[0]])
    axes = _axes(revolute, poe)
    if prismatic:
        kind = "scara"
        what = (f"SCARA: revolute axes {axes} are parallel and prismatic joint "
                f"{_axes(prismatic, poe)} moves along them")
    else:
        kind = f"planar-{len(revolute)}r"
        what = f"planar {len(revolute)}R arm: axes {axes} are parallel"
    return SolverPlan(ArmStructure(kind, True, 2, f"{what}: closed-form IK, up to 2 solutions"),
                      poe, kind)


def _general(poe: PoeChain) -> SolverPlan:
    """Any other 6R arm: the general solver (Raghavan-Roth elimination, up to 16 solutions)."""
    why = ("general 6R arm: no three consecutive axes meet at one point or are parallel; every "
           "solution by Raghavan-Roth elimination (a 24 x 24 eigenproblem), up to 16 solutions")
    return SolverPlan(ArmStructure("general-6r", True, 16, why), poe, "general")


def _no_closed_form(chain: Chain, poe: PoeChain, tol: float) -> ArmStructure:
    n = chain.n
    if n > 6:
        why = (f"{n} joints: a redundant arm has infinitely many solutions per pose, so no "
               f"closed form; use numeric IK")
    elif n == 6:
        why = ("6 joints with a prismatic one, and no three consecutive axes meet at one point or "
               "are parallel (Pieper's conditions): the general solver takes revolute joints only; "
               "use numeric IK")
    else:
        why = (f"{n} joints that are not a planar 2R/3R arm or a SCARA (parallel revolute axes, "
               f"prismatic along them): no closed form; use numeric IK")
    return ArmStructure("none", False, 0, why)


#: Random configurations at which :func:`generic_rank` evaluates the Jacobian.
_RANK_SAMPLES = 8


def generic_rank(chain: Chain, tol: float = 1e-9) -> int:
    """The rank of the chain's Jacobian at a generic configuration: the number of
    independent directions [v; w] its joints can move the tool in, at most ``min(6, n)``.

    The largest rank over a few seeded random configurations inside the limits (a rank
    reached anywhere is reached almost everywhere); singular values below ``tol`` times
    the largest count as zero.

    >>> import armkit
    >>> generic_rank(armkit.load("ur5").chain), generic_rank(armkit.load("grb400-scara").chain)
    (6, 4)
    """
    rng = np.random.default_rng(0)
    low = np.where(np.isfinite(chain.lower), chain.lower, -1.0)
    high = np.where(np.isfinite(chain.upper), chain.upper, 1.0)
    S = np.linalg.svd(geometric_jacobian(chain, rng.uniform(low, high, (_RANK_SAMPLES, chain.n))),
                      compute_uv=False)
    return int((S > tol * S[:, :1]).sum(axis=1).max())


def plan_closed_form(chain: Chain, tol: float = 1e-9) -> SolverPlan:
    """Classify ``chain`` and prepare the chain a closed-form solver works on.

    Parameters
    ----------
    chain : Chain
    tol : float
        Angle tolerance [rad] for parallel axes; times ``1 + size of the arm`` [m] it is
        the distance below which axes count as meeting.
    """
    poe = poe_from_chain(chain)
    g = _Geometry(poe, tol)
    for i in range(chain.n - 1):
        if not poe.prismatic[i] and not poe.prismatic[i + 1] and g.parallel(i, i + 1) \
                and g.distance_to_line(poe.points[i + 1], i) <= g.tol:
            why = (f"axes {i + 1} and {i + 2} are the same line: the arm has fewer degrees of "
                   f"freedom than joints, no closed form; use numeric IK")
            return SolverPlan(ArmStructure("none", False, 0, why), poe)
    rank = generic_rank(chain)
    if rank < min(6, chain.n):
        why = (f"the Jacobian has rank {rank} at every configuration tried (not {min(6, chain.n)}): "
               f"the {chain.n} joints move the tool in only {rank} independent directions, so the "
               f"arm reaches a {rank}-dimensional set of poses and has no closed form here; use "
               f"numeric IK")
        return SolverPlan(ArmStructure("rank-deficient", False, 0, why), poe)
    if chain.n == 6:
        plan = _spherical(poe, tol, "spherical-wrist")
        if plan is None or not plan.structure.closed_form:
            base = _spherical(poe.reversed(), tol, "spherical-base")
            if base is not None and (plan is None or base.structure.closed_form):
                plan = base
        if plan is None:
            plan = (_three_parallel(poe, tol, 1) or _three_parallel(poe.reversed(), tol, 1)
                    or _three_parallel(poe, tol, 0) or _three_parallel(poe.reversed(), tol, 0))
        if plan is not None:
            return plan
        if not poe.prismatic.any():
            return _general(poe)
    elif chain.n <= 4:
        plan = _planar(poe, tol)
        if plan is not None:
            return plan
    return SolverPlan(_no_closed_form(chain, poe, tol), poe)


def analyze_structure(robot: Robot | Chain, tol: float = 1e-9) -> ArmStructure:
    """Which closed-form IK case applies to ``robot``, decided from its joint axes.

    Parameters
    ----------
    robot : Robot or Chain
        The arm (its :class:`~armkit.chain.Chain` is accepted too).
    tol : float
        Angle tolerance [rad] for parallel axes (and, scaled by the arm's size, the
        distance [m] for meeting axes).

    Returns
    -------
    ArmStructure

    Examples
    --------
    >>> import armkit
    >>> s = analyze_structure(armkit.load("probot-anno"))
    >>> s.kind, s.closed_form, s.max_solutions
    ('spherical-wrist', True, 8)
    >>> analyze_structure(armkit.load("panda")).closed_form
    False
    """
    return plan_closed_form(as_chain(robot), tol).structure


def position_joints_case(poe: PoeChain, tol: float = 1e-9
                         ) -> tuple[str, NDArray[np.float64] | None, str] | None:
    """How joints 1-3 of ``poe`` carry a point (a wrist centre, or the tool point of position IK):
    the case name (``"parallel-23"``, ``"intersect-12-revolute"``, ...), the point where two of
    the axes meet (None for the parallel and general cases) and a clause for messages; None if
    joints 1-3 have no closed form. ``tol`` as in :func:`plan_closed_form`."""
    return _position_case(_Geometry(poe, tol))
