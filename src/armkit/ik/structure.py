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
general-6r          any other 6R arm (the general solver, the registry's last) 16
general-5r1p        any other 6-joint arm with one prismatic joint (the same   16
                    elimination, the slide as one of the two joints it
                    eliminates linearly)
none                anything else (redundant arms, 6 joints with two           0
                    prismatic ones outside every class...)
==================  =========================================================  ========

The detection is the compiled core's (``cpp/include/armkit/ik_detect.hpp``): each case of the
registry (:data:`armkit.ik.cases.CASE_NAMES`) has a detect function that returns its geometry
or the reason it does not apply, and ``_core.classify`` runs them in the registry's order. Axes
count as parallel or meeting only to the rounding of a robot file's numbers
(:data:`CLASS_TOLERANCE`): an arm near a class (a calibrated one) is the general 6R (or 5R1P) arm it is,
and its listing holds the real arm's exact solutions, not the idealised class's.

Example
-------
>>> import armkit
>>> analyze_structure(armkit.load("ur5")).kind
'three-parallel'
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from armkit import _core
from armkit._params import whole_number
from armkit.chain import Chain, as_chain

if TYPE_CHECKING:
    from armkit.robot import Robot

__all__ = ["CLASS_TOLERANCE", "ArmStructure", "PoeChain", "SolverPlan", "analyze_structure", "arm_case",
           "generic_rank", "plan_closed_form"]

#: Axes count as parallel where the sine of their angle is at most this, and as meeting where
#: they pass within this times ``1 +`` the arm's size [m] (the core's ``kClassTolerance``, with
#: the reason for its value in ``cpp/include/armkit/tolerances.hpp``).
CLASS_TOLERANCE: float = _core.CLASS_TOLERANCE


@dataclass(frozen=True)
class ArmStructure:
    """The kind of arm a chain is, as far as closed-form IK is concerned.

    Attributes
    ----------
    kind : str
        ``"spherical-wrist"``, ``"spherical-base"``, ``"three-parallel"``, ``"scara"``,
        ``"planar-2r"``, ``"planar-3r"``, ``"general-6r"`` (any other 6R arm: every
        solution by elimination), ``"general-5r1p"`` (the same for a 6-joint arm with one
        prismatic joint), ``"rank-deficient"`` (fewer independent
        directions of motion than joints, up to 6) or ``"none"``.
    closed_form : bool
        Whether :func:`armkit.ik.closed_form_ik` solves this chain.
    max_solutions : int
        Upper bound on the number of isolated solutions (0 without closed form).
    description : str
        One sentence saying which axes meet or are parallel, or why no closed form applies.
    case : str or None
        The registry's case that solves it (:data:`armkit.ik.cases.CASE_NAMES`), or None.
    why_not : tuple of (str, str, str)
        For every registered case, ``(case, fit, reason)``: ``fit`` is ``"applies"`` for the
        chosen case, else a code (:data:`armkit._core.CASE_FITS`: ``"joints"``,
        ``"prismatic"``, ``"axes"``, ``"position"``, ``"position-only"``, ``"degenerate"``,
        ``"earlier"``) with a short reason.
    """

    kind: str
    closed_form: bool
    max_solutions: int
    description: str
    case: str | None = None
    why_not: tuple[tuple[str, str, str], ...] = ()


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

    @classmethod
    def from_lines(cls, lines: dict) -> PoeChain:
        """The lines a core case works on (``_core.ArmCase.lines``)."""
        return cls(lines["axes"], lines["points"], np.array(lines["prismatic"], dtype=bool), lines["M"],
                   lines["index"], lines["sign"], bool(lines["inverted"]))


@dataclass(frozen=True)
class SolverPlan:
    """The chain as the chosen case sees it: its structure, its lines and its point.

    ``case`` names the registry's case (e.g. ``"spherical"``), ``point`` is the wrist centre
    where the case has one.
    """

    structure: ArmStructure
    poe: PoeChain
    case: str = ""
    point: NDArray[np.float64] | None = None


def generic_rank(chain: Chain, tol: float = _core.RANK_TOLERANCE, *, joints: int | None = None,
                 position_only: bool = False) -> int:
    """The rank of the chain's Jacobian at a generic configuration: the number of
    independent directions [v; w] its joints can move the tool in, at most ``min(6, n)``.

    The largest rank over a few seeded random configurations inside the limits (a rank
    reached anywhere is reached almost everywhere); singular values below ``tol`` times
    the largest count as zero (computed in the core). ``joints``: only the first ``joints``
    joints move (the others stay at 0) and only their columns count; ``position_only``: the
    directions the tool point can move in (rows ``v`` only).

    >>> import armkit
    >>> generic_rank(armkit.load("ur5").chain), generic_rank(armkit.load("grb400-scara").chain)
    (6, 4)
    """
    moving = -1 if joints is None else whole_number(joints, "joints", minimum=1, maximum=chain.n)
    return int(_core.generic_rank(chain._core, float(tol), moving, bool(position_only)))


def arm_case(chain: Chain) -> _core.ArmCase:
    """The core's classification of ``chain`` (``_core.classify``), made once per chain."""
    return chain.derived(_classify)


def _classify(chain: Chain) -> _core.ArmCase:
    return _core.classify(chain._core)


def _structure(arm: _core.ArmCase) -> ArmStructure:
    return ArmStructure(arm.kind, arm.chosen >= 0, arm.max_solutions, arm.description, arm.case,
                        tuple(tuple(reason) for reason in arm.why_not))


def plan_closed_form(chain: Chain) -> SolverPlan:
    """The case the core chose for ``chain``, with the lines it works on (possibly reversed,
    axes flipped) and its point (a spherical wrist's centre)."""
    arm = arm_case(chain)
    geometry = arm.geometry
    point = np.array(geometry.c) if arm.case == "spherical" else None
    return SolverPlan(_structure(arm), PoeChain.from_lines(arm.lines), arm.case or "", point)


def analyze_structure(robot: Robot | Chain) -> ArmStructure:
    """Which closed-form IK case applies to ``robot``, decided from its joint axes.

    Parameters
    ----------
    robot : Robot or Chain
        The arm (its :class:`~armkit.chain.Chain` is accepted too).

    Returns
    -------
    ArmStructure
        With, for every registered case, why it does not apply (``why_not``).

    Examples
    --------
    >>> import armkit
    >>> s = analyze_structure(armkit.load("probot-anno"))
    >>> s.kind, s.closed_form, s.max_solutions, s.case
    ('spherical-wrist', True, 8, 'spherical')
    >>> analyze_structure(armkit.load("panda")).closed_form
    False
    >>> dict((case, fit) for case, fit, _ in analyze_structure(armkit.load("ur5")).why_not)["spherical"]
    'axes'
    """
    return _structure(arm_case(as_chain(robot)))
