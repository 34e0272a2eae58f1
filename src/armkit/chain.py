"""The one internal representation of a serial arm: fixed transforms and joint motions.

A chain with ``n`` joints is the product::

    T_base_tool(q) = T_base · Π_i [ T_before_i · M_i(q_i) · T_after_i ] · T_tool

where ``M_i`` is ``Rz(q_i)`` for a revolute joint and ``Tz(q_i)`` for a prismatic one, so
every joint moves about or along the z axis of its *joint frame*
``T_base · ... · T_before_i``. The frame after ``T_after_i`` is link frame ``i`` of the
DH table. Standard and modified DH tables, products of exponentials (:mod:`armkit.poe`) and
URDF joints (:mod:`armkit.urdf`) are only ways to fill ``T_before`` and ``T_after``
(:func:`chain_from_frames`): FK, Jacobians, IK, export and simulation read this chain and
never ask which convention it came from.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, Literal, TypeVar

import numpy as np
from numpy.typing import NDArray

from armkit import _core
from armkit.errors import InputError, RobotDefinitionError
from armkit.inertial import Inertial
from armkit.spatial.transforms import rot_x, rot_z, trans_x, trans_z

if TYPE_CHECKING:  # armkit.robot imports this module
    from armkit.robot import Robot

__all__ = ["Chain", "DHRow", "Joint", "JointKind", "DHConvention", "LIMIT_TOLERANCE", "MAX_JOINTS",
           "MAX_VALUE", "as_chain", "chain_from_dh", "chain_from_frames"]

#: Slack [rad or m] allowed beyond a joint limit before a value counts as outside it (the
#: compiled core's ``kLimitTolerance``, so Python and C++ test limits alike).
LIMIT_TOLERANCE: float = _core.LIMIT_TOLERANCE
#: The most joints a chain can have: the compiled core's fixed capacity (``kMaxJoints``, its
#: per-configuration scratch arrays live on the stack).
MAX_JOINTS: int = _core.MAX_JOINTS
#: Largest magnitude of a length [m] or angle [rad] a robot description may hold: larger ones
#: are typos (1000 km) and let FK overflow. Robot files and URDF import refuse them.
MAX_VALUE = 1e6
_Derived = TypeVar("_Derived")

JointKind = Literal["revolute", "prismatic"]
DHConvention = Literal["standard", "modified"]


def _frozen(T: NDArray[np.float64]) -> NDArray[np.float64]:
    T = np.array(T, dtype=float)
    T.setflags(write=False)
    return T


@dataclass(frozen=True)
class DHRow:
    """One row of a DH table, SI units (metres, radians).

    For a joint row, the joint variable is added to ``theta`` (revolute; ``theta`` is the
    zero offset) or to ``d`` (prismatic). A row with ``joint=None`` is fixed (base or tool).
    """

    alpha: float
    a: float
    d: float
    theta: float
    joint: JointKind | None = "revolute"

    def transform(self, convention: DHConvention) -> NDArray[np.float64]:
        """The row's transform at joint value 0, shape ``(4, 4)``."""
        before, after = self.split(convention)
        return before @ after

    def split(self, convention: DHConvention) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """``(T_before, T_after)`` around the joint motion, for this row and convention."""
        if convention == "modified":  # Rx(alpha) Tx(a) Rz(theta) Tz(d)
            if self.joint == "prismatic":
                return rot_x(self.alpha) @ trans_x(self.a) @ rot_z(self.theta), trans_z(self.d)
            return rot_x(self.alpha) @ trans_x(self.a), rot_z(self.theta) @ trans_z(self.d)
        if convention == "standard":  # Rz(theta) Tz(d) Tx(a) Rx(alpha)
            if self.joint == "prismatic":
                return rot_z(self.theta) @ trans_z(self.d), trans_x(self.a) @ rot_x(self.alpha)
            return np.eye(4), rot_z(self.theta) @ trans_z(self.d) @ trans_x(self.a) @ rot_x(self.alpha)
        raise RobotDefinitionError(
            f"unknown DH convention {convention!r}; expected 'standard' or 'modified'")


@dataclass(frozen=True)
class Joint:
    """A joint of the chain: its motion, the fixed transforms around it and its limits.

    Attributes
    ----------
    kind : {"revolute", "prismatic"}
    T_before : ndarray (4, 4)
        From the previous link frame to the joint frame (motion about/along its z).
    T_after : ndarray (4, 4)
        From the joint frame (after the motion) to this joint's link frame.
    lower, upper : float
        Position limits [rad or m]: increasing, each at most :data:`MAX_VALUE` in magnitude or
        infinite (no limit).
    max_velocity, max_acceleration : float or None
        Optional limits [rad/s or m/s, rad/s^2 or m/s^2].
    name : str
    inertial : Inertial or None
        The link this joint moves (with every body fixed to it), in this joint's link frame
        (after ``T_after``); None if not given (:mod:`armkit.dynamics` then refuses the arm).
    max_torque : float or None
        Optional torque limit [N m] (revolute) or force limit [N] (prismatic).
    radius : float or None
        Optional radius [m] of the capsules that stand for the link this joint moves in collision
        checks (:mod:`armkit.collision`); None: the default.
    """

    kind: JointKind
    T_before: NDArray[np.float64]
    T_after: NDArray[np.float64]
    lower: float
    upper: float
    max_velocity: float | None = None
    max_acceleration: float | None = None
    name: str = ""
    inertial: Inertial | None = None
    max_torque: float | None = None
    radius: float | None = None

    def __post_init__(self) -> None:
        if self.kind not in ("revolute", "prismatic"):
            raise RobotDefinitionError(
                f"joint {self.name!r}: type {self.kind!r}; expected 'revolute' or 'prismatic'")
        if not self.lower <= self.upper:
            raise RobotDefinitionError(
                f"joint {self.name!r}: limits [{self.lower}, {self.upper}] are not increasing")
        if any(np.isfinite(limit) and abs(limit) > MAX_VALUE for limit in (self.lower, self.upper)):
            raise RobotDefinitionError(
                f"joint {self.name!r}: limits [{self.lower:g}, {self.upper:g}] reach beyond {MAX_VALUE:g} "
                f"rad or m (a typo, or a 'no limit' sentinel: for no limit write -inf, inf)")
        for label, value in (("max_velocity", self.max_velocity),
                             ("max_acceleration", self.max_acceleration), ("max_torque", self.max_torque),
                             ("radius", self.radius)):
            if value is not None and not (np.isfinite(value) and value > 0):
                raise RobotDefinitionError(
                    f"joint {self.name!r}: {label} = {value}; expected a positive number")
        object.__setattr__(self, "T_before", _frozen(self.T_before))
        object.__setattr__(self, "T_after", _frozen(self.T_after))


@dataclass(frozen=True)
class Chain:
    """A serial chain: base transform, joints in order, tool transform.

    Every field is declared here; those after ``T_tool`` are computed once from the first three
    (read-only arrays) or filled on first use (``_derived``).

    Attributes
    ----------
    T_between : ndarray (n + 1, 4, 4)
        The fixed transforms between consecutive joint motions (base to the first, ..., the last
        to the tool): what FK multiplies.
    lower, upper : ndarray (n,)
        The joints' position limits [rad or m], read-only (computed once).
    """

    joints: tuple[Joint, ...]
    T_base: NDArray[np.float64] = field(default_factory=lambda: np.eye(4))
    T_tool: NDArray[np.float64] = field(default_factory=lambda: np.eye(4))
    T_between: NDArray[np.float64] = field(init=False, repr=False, compare=False)
    lower: NDArray[np.float64] = field(init=False, repr=False, compare=False)
    upper: NDArray[np.float64] = field(init=False, repr=False, compare=False)
    #: What :meth:`derived` made, by the function that made it.
    _derived: dict[Callable[[Chain], object], object] = field(
        init=False, repr=False, compare=False, default_factory=dict)

    def __post_init__(self) -> None:
        if len(self.joints) == 0:
            raise RobotDefinitionError("a chain needs at least one joint, got none")
        if len(self.joints) > MAX_JOINTS:
            raise RobotDefinitionError(
                f"a chain of {len(self.joints)} moving joints: armkit handles at most {MAX_JOINTS} (a URDF's "
                f"--base/--tip can choose a shorter chain)")
        object.__setattr__(self, "joints", tuple(self.joints))
        object.__setattr__(self, "T_base", _frozen(self.T_base))
        object.__setattr__(self, "T_tool", _frozen(self.T_tool))
        # Fixed transforms between consecutive motions, used by FK on its hot path.
        links = [self.T_base @ self.joints[0].T_before]
        links += [a.T_after @ b.T_before for a, b in zip(self.joints, self.joints[1:], strict=False)]
        links.append(self.joints[-1].T_after @ self.T_tool)
        object.__setattr__(self, "T_between", _frozen(np.stack(links)))
        object.__setattr__(self, "lower", _frozen([j.lower for j in self.joints]))
        object.__setattr__(self, "upper", _frozen([j.upper for j in self.joints]))

    @property
    def n(self) -> int:
        """Number of joints."""
        return len(self.joints)

    @property
    def prismatic(self) -> NDArray[np.bool_]:
        """``(n,)`` mask of prismatic joints."""
        return np.array([j.kind == "prismatic" for j in self.joints])

    @cached_property
    def _core(self) -> _core.Chain:
        """The chain as armkit's compiled core takes it (made once)."""
        return _core.Chain(np.ascontiguousarray(self.T_between), np.ascontiguousarray(self.prismatic),
                           np.ascontiguousarray(self.lower), np.ascontiguousarray(self.upper))

    @property
    def link_length(self) -> float:
        """The arm's length scale [m]: the sum of the distances between consecutive frame origins
        (base to the first joint, joint to joint, the last joint to the tool, at ``q = 0``), the
        one definition of "the size of the arm" outside IK's tolerances.

        Examples
        --------
        >>> round(chain_from_dh([DHRow(0, 0.5, 0.2, 0)] * 2, "standard").link_length, 6)  # 2 * sqrt(0.29)
        1.077033
        """
        return float(np.linalg.norm(self.T_between[:, :3, 3], axis=-1).sum())

    @cached_property
    def reach(self) -> float:
        """A distance [m] from the base frame's origin that no tool position exceeds, at any joint
        values within the prismatic joints' limits: :attr:`link_length` plus each prismatic joint's
        largest travel (``inf`` if one is unlimited). A bound, not the workspace's exact radius.

        Examples
        --------
        >>> chain = chain_from_dh([DHRow(0, 0.5, 0.2, 0), DHRow(0, 0, 0, 0, "prismatic")], "standard",
        ...                       limits=[(-3, 3), (-0.1, 0.3)])
        >>> round(chain.reach, 6)  # sqrt(0.29) + 0.3
        0.838516
        """
        travel = np.maximum(np.abs(self.lower), np.abs(self.upper))[self.prismatic]
        return self.link_length + float(travel.sum())

    @cached_property
    def spans_turns(self) -> tuple[int, ...]:
        """The revolute joints (0-based) whose finite limits span more than a whole turn:
        an angle of such a joint has several whole-turn copies ``q + 2 pi t`` inside the
        limits, distinct configurations with the same tool pose (IK lists them all)."""
        return tuple(self._core.spans_turns)

    def derived(self, make: Callable[[Chain], _Derived]) -> _Derived:
        """``make(self)``, computed once per chain and kept with it (solvers and the like), keyed
        by the function ``make`` itself (a module-level function, so one entry per kind).

        The value lives as long as the chain does: no global cache keeps chains alive.

        Examples
        --------
        >>> chain = chain_from_dh([DHRow(0, 1.0, 0, 0)], "standard")
        >>> chain.derived(len_of := lambda c: c.n) == 1 and chain.derived(len_of) is chain._derived[len_of]
        True
        """
        if make not in self._derived:
            self._derived[make] = make(self)
        return self._derived[make]

    def outside_limits(self, q: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Per joint, whether the values ``q`` ``(..., n)`` (float, not checked) leave its
        position limits by more than :data:`LIMIT_TOLERANCE`: ``(..., n)``.

        armkit's one joint-limit test in Python (:meth:`within_limits`,
        :meth:`limit_violations`, the motions' limit stops and IK's messages use it; the
        compiled core's is ``Chain::within_limit``, with the same tolerance).

        Examples
        --------
        >>> chain = chain_from_dh([DHRow(0, 1.0, 0, 0)] * 2, "standard", limits=[(-1.0, 1.0)] * 2)
        >>> chain.outside_limits(np.array([0.5, 1.0 + 2e-9]))
        array([False,  True])
        """
        return (q < self.lower - LIMIT_TOLERANCE) | (q > self.upper + LIMIT_TOLERANCE)

    def within_limits(self, q: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Whether each configuration ``q`` ``(..., n)`` (float, not checked) is inside all
        position limits, to :data:`LIMIT_TOLERANCE`: ``(...)``.

        Examples
        --------
        >>> chain = chain_from_dh([DHRow(0, 1.0, 0, 0)], "standard", limits=[(-1.0, 1.0)])
        >>> chain.within_limits(np.array([[0.5], [1.5]]))
        array([ True, False])
        """
        return ~np.any(self.outside_limits(q), axis=-1)

    def limit_fields(self, q: NDArray[np.float64]) -> dict[str, object]:
        """The first joint of ``q`` ``(n,)`` outside its limits (:meth:`outside_limits`), as the
        keyword arguments of :class:`~armkit.errors.JointLimitError`: ``joint`` (its name),
        ``value`` [rad or m] and ``limits``; empty if every joint is inside.

        Examples
        --------
        >>> chain = chain_from_dh([DHRow(0, 1.0, 0, 0)] * 2, "standard", limits=[(-1.0, 1.0)] * 2)
        >>> chain.limit_fields(np.array([0.5, 1.5]))
        {'joint': 'q2', 'value': 1.5, 'limits': (-1.0, 1.0)}
        """
        outside = np.flatnonzero(self.outside_limits(q))
        if not len(outside):
            return {}
        joint = self.joints[outside[0]]
        return {"joint": joint.name, "value": float(q[outside[0]]), "limits": (joint.lower, joint.upper)}

    def display_units(self, degrees: bool = False) -> tuple[NDArray[np.float64], list[str]]:
        """Per joint, the factor from its SI value to the unit it is shown in, and that unit: rad
        for revolute joints (deg with ``degrees``), m for prismatic ones (messages, not data).

        >>> chain = chain_from_dh([DHRow(0, 1.0, 0, 0)] * 2, "standard")
        >>> chain.display_units(degrees=True)[1]
        ['deg', 'deg']
        """
        revolute = ~self.prismatic
        units = ["deg" if degrees and r else "rad" if r else "m" for r in revolute]
        return np.where(revolute & degrees, 180 / np.pi, 1.0), units

    def limit_violations(self, q: NDArray[np.float64], degrees: bool = False, *,
                         q_max: NDArray[np.float64] | None = None, where: str = "") -> list[str]:
        """One message per joint outside its limits (:meth:`outside_limits`), all alike:
        ``joint q2 = 2.5 rad is outside its limits [-2.00713, 2.00713] rad``.

        Parameters
        ----------
        q : ndarray, shape (n,)
            Joint values [rad or m] (float, not checked); with ``q_max``, the smallest value
            each joint takes.
        degrees : bool
            Show revolute values and limits in degrees.
        q_max : ndarray, shape (n,), optional
            The largest value each joint takes (a trajectory's range ``q .. q_max``).
        where : str
            Said after the value, e.g. ``" between waypoints"``.

        Examples
        --------
        >>> chain = chain_from_dh([DHRow(0, 1.0, 0, 0)] * 2, "standard", limits=[(-1.0, 1.0)] * 2)
        >>> chain.limit_violations(np.array([0.5, 1.5]))
        ['joint q2 = 1.5 rad is outside its limits [-1, 1] rad']
        >>> chain.limit_violations(np.array([0.0, -0.5]), True, q_max=np.array([0.5, 1.5]),
        ...                        where=" on the way")
        ['joint q2 = -28.6479 .. 85.9437 deg on the way is outside its limits [-57.2958, 57.2958] deg']
        """
        high = q if q_max is None else q_max
        outside = self.outside_limits(q) | self.outside_limits(high)
        messages = []
        scales, units = self.display_units(degrees)
        for j in np.flatnonzero(outside):
            joint = self.joints[j]
            scale, unit = float(scales[j]), " " + units[j]
            if not math.isfinite(max(abs(float(q[j])), abs(float(high[j]))) * scale):
                scale, unit = 1.0, " rad"  # beyond 1e306 rad: in degrees it would overflow to inf
            # below 1e-9 shown as 0: no -1e-14 from a root finder beside values of 6 digits
            low_shown, high_shown = (0.0 if abs(x) < 1e-9 else x
                                     for x in (float(q[j]) * scale, float(high[j]) * scale))
            value = f"{low_shown:.6g}" if q_max is None else f"{low_shown:.6g} .. {high_shown:.6g}"
            messages.append(f"joint {joint.name} = {value}{unit}{where} is outside its limits "
                            f"[{joint.lower * scale:.6g}, {joint.upper * scale:.6g}]{unit}")
        return messages


def as_chain(robot: Robot | Chain) -> Chain:
    """The chain of ``robot``: what every public function that takes a robot computes with.

    Public functions take a :class:`~armkit.robot.Robot` (what :func:`armkit.load` returns)
    and accept its bare :class:`Chain` too; they all turn it into the chain with this one
    helper (``robot.chain``, or the chain itself).

    Raises
    ------
    InputError
        If ``robot`` is neither a Robot nor a Chain.

    Examples
    --------
    >>> import armkit
    >>> robot = armkit.load("ur5")
    >>> as_chain(robot) is robot.chain is as_chain(robot.chain)
    True
    """
    if type(robot) is Chain:
        return robot
    chain = getattr(robot, "chain", None)
    if isinstance(chain, Chain):
        return chain
    if isinstance(robot, Chain):
        return robot
    shown = repr(robot)
    raise InputError(f"robot: expected an armkit Robot (e.g. armkit.load('ur5')) or its Chain, got "
                     f"{type(robot).__name__} {shown[:60] + '...' if len(shown) > 60 else shown}")


def chain_from_dh(rows: Sequence[DHRow], convention: DHConvention, *,
                  limits: Sequence[tuple[float, float]] | None = None,
                  max_velocity: Sequence[float | None] | None = None,
                  max_acceleration: Sequence[float | None] | None = None,
                  base_rows: Sequence[DHRow] = (), tool_rows: Sequence[DHRow] = (),
                  T_base: NDArray[np.float64] | None = None,
                  T_tool: NDArray[np.float64] | None = None,
                  names: Sequence[str] | None = None,
                  inertials: Sequence[Inertial | None] | None = None,
                  max_torque: Sequence[float | None] | None = None) -> Chain:
    """Build a :class:`Chain` from DH rows in either convention.

    Parameters
    ----------
    rows : sequence of DHRow
        One per joint (``joint`` not None), SI units.
    convention : {"standard", "modified"}
    limits : sequence of (lower, upper), optional
        Per joint [rad or m]. Default ``[-pi, pi]`` for revolute joints and unbounded for
        prismatic ones.
    max_velocity, max_acceleration : sequence of float or None, optional
    base_rows, tool_rows : sequence of DHRow
        Fixed rows before the first and after the last joint (``joint=None``).
    T_base, T_tool : ndarray (4, 4), optional
        Extra fixed transforms, applied before the base rows and after the tool rows.
    names : sequence of str, optional
        Joint names, default ``q1 ... qn``.
    inertials, max_torque : sequence, optional
        Per joint, as for :func:`chain_from_frames` (inertials in the DH link frames).
    """
    if len(rows) == 0:
        raise RobotDefinitionError("a DH table needs at least one joint row, got none")
    for i, row in enumerate(rows):
        if row.joint is None:
            raise RobotDefinitionError(f"joint row {i + 1} has no joint type")
    before, after = zip(*(row.split(convention) for row in rows), strict=True)
    base = np.eye(4) if T_base is None else np.asarray(T_base, dtype=float)
    for row in base_rows:
        base = base @ row.transform(convention)
    tool = np.eye(4)
    for row in tool_rows:
        tool = tool @ row.transform(convention)
    if T_tool is not None:
        tool = tool @ np.asarray(T_tool, dtype=float)
    return chain_from_frames([row.joint for row in rows], before, after, limits=limits,
                             max_velocity=max_velocity, max_acceleration=max_acceleration,
                             T_base=base, T_tool=tool, names=names, inertials=inertials,
                             max_torque=max_torque)


def chain_from_frames(kinds: Sequence[JointKind], T_before: Sequence[NDArray[np.float64]],
                      T_after: Sequence[NDArray[np.float64]], *,
                      limits: Sequence[tuple[float, float] | None] | None = None,
                      max_velocity: Sequence[float | None] | None = None,
                      max_acceleration: Sequence[float | None] | None = None,
                      T_base: NDArray[np.float64] | None = None,
                      T_tool: NDArray[np.float64] | None = None,
                      names: Sequence[str] | None = None,
                      inertials: Sequence[Inertial | None] | None = None,
                      max_torque: Sequence[float | None] | None = None) -> Chain:
    """Build a :class:`Chain` from each joint's fixed transforms (what every description fills).

    Parameters
    ----------
    kinds : sequence of {"revolute", "prismatic"}
    T_before, T_after : sequence of ndarray (4, 4)
        Per joint, the transforms before and after its motion (lengths in m).
    limits : sequence of (lower, upper) or None, optional
        Per joint [rad or m]; ``None`` (or no sequence) means ``[-pi, pi]`` for revolute
        joints and unbounded for prismatic ones.
    max_velocity, max_acceleration : sequence of float or None, optional
    T_base, T_tool : ndarray (4, 4), optional
    names : sequence of str, optional
        Joint names, default ``q1 ... qn``.
    inertials : sequence of Inertial or None, optional
        Per joint, its link's mass properties in its link frame (see :class:`Joint`).
    max_torque : sequence of float or None, optional
        Per joint, a torque [N m] or force [N] limit.

    Examples
    --------
    >>> chain = chain_from_frames(["revolute"], [np.eye(4)], [trans_x(0.5)])
    >>> chain.T_between[-1][:3, 3].tolist(), chain.upper.tolist()
    ([0.5, 0.0, 0.0], [3.141592653589793])
    """
    n = len(kinds)
    if n == 0:
        raise RobotDefinitionError("a chain needs at least one joint, got none")
    names = list(names) if names is not None else [f"q{i + 1}" for i in range(n)]
    limits = list(limits) if limits is not None else [None] * n
    max_velocity = list(max_velocity) if max_velocity is not None else [None] * n
    max_acceleration = list(max_acceleration) if max_acceleration is not None else [None] * n
    inertials = list(inertials) if inertials is not None else [None] * n
    max_torque = list(max_torque) if max_torque is not None else [None] * n
    for label, values in (("T_before", T_before), ("T_after", T_after), ("limits", limits),
                          ("max_velocity", max_velocity), ("max_acceleration", max_acceleration),
                          ("names", names), ("inertials", inertials), ("max_torque", max_torque)):
        if len(values) != n:
            raise RobotDefinitionError(f"{label} has {len(values)} entries; expected {n}, "
                                       f"one per joint")
    joints = []
    for i, kind in enumerate(kinds):
        lower, upper = limits[i] if limits[i] is not None else (
            (-np.pi, np.pi) if kind == "revolute" else (-np.inf, np.inf))
        joints.append(Joint(kind, T_before[i], T_after[i], float(lower), float(upper),
                            max_velocity[i], max_acceleration[i], names[i], inertials[i], max_torque[i]))
    return Chain(tuple(joints), np.eye(4) if T_base is None else T_base,
                 np.eye(4) if T_tool is None else T_tool)
