"""Closed-form position IK: joints 1-3 carry the tool point to a target position.

The tool point of a 3-joint arm (or of any arm with joints 4..n held at given values) goes
where joints 1-3 put it. Which pair of axes 1-3 meets or is parallel decides the
subproblems, exactly as for a spherical wrist's centre (:mod:`armkit.ik.structure`,
``wrist_centre_joints`` in ``cpp/src/ik_case_point.cpp``): an elbow arm (axes 2 and 3 parallel)
by SP4 for q1 and a planar 2R, intersecting axes by SP3 and SP2, general axes by a quartic.
Up to 4 solutions; where the target is on a line that leaves a joint free (e.g. on axis 1
of an elbow arm) a family, whose member is flagged ``family``. Every solution is checked
by forward kinematics (position within :data:`~armkit.ik.results.SOLUTION_TOLERANCE`),
wrapped into the limits and sorted by distance to ``near``, as :func:`armkit.ik.ik` does.

Decision (issue 10 item 4): the orientation is free, so this is its own call,
:func:`ik_position` (``Robot.ik_position``), with ``ik``'s ``all_solutions``, ``near``,
``within_limits`` and ``turn_copies`` and its result shapes, for one target position per call
(no ``weights``: the solutions are sorted by the plain joint distance to ``near``). Joints 4..n
keep their values from ``near`` (default zeros) exactly, not wrapped into their limits: a held
value outside them makes every solution out of limits.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit import _core
from armkit._deprecation import deprecated_function
from armkit._params import float_array
from armkit.chain import Chain, as_chain
from armkit.errors import InputError, JointLimitError, NoClosedFormError, UnreachableError, warn_at_caller
from armkit.ik.cases import PointGeometry, solve_pose
from armkit.ik.numeric import wrap_into_limits
from armkit.ik.pipeline import Found, left_off_warning, with_turn_copies
from armkit.ik.results import SOLUTION_TOLERANCE, IKSolutions
from armkit.ik.structure import generic_rank
from armkit.kinematics import fk, geometric_jacobian

if TYPE_CHECKING:
    from armkit.robot import Robot

__all__ = ["ik_position", "ik_position_solutions", "position_case", "position_solutions"]

#: Newton steps on joints 1-3 for a candidate whose position is off by more than 1e-12 m
#: (quartic roots).
_POLISH_STEPS = 4


def position_case(robot: Robot | Chain) -> str:
    """How joints 1-3 carry the tool point (e.g. ``"axes 2, 3 are parallel"``).

    Raises
    ------
    NoClosedFormError
        If the chain has fewer than 3 joints, or joints 1-3 have no closed form here.
    """
    return _plan(as_chain(robot))


def _plan(chain: Chain) -> str:
    """How joints 1-3 carry the tool point (the core's point case, its clause); decided once
    per chain (a refusal too)."""
    plan = chain.derived(_make_plan)
    if isinstance(plan, NoClosedFormError):
        raise NoClosedFormError(str(plan))
    return plan


_NO_POSITION_CASE = ("joints 1-3 have no closed-form position solution here (two prismatic joints, or "
                     "parallel axes that leave the position problem degenerate); use numeric IK with "
                     "mask=[1, 1, 1, 0, 0, 0]")


def _make_plan(chain: Chain) -> str | NoClosedFormError:
    if chain.n < 3:
        return NoClosedFormError(f"position IK in closed form needs 3 joints; this arm has {chain.n}")
    rank = generic_rank(chain, joints=3, position_only=True)
    if rank < 3:
        return NoClosedFormError(f"joints 1-3 move the tool point in only {rank} independent directions at "
                                 f"every configuration tried (e.g. axes 1-3 meet at one point, or two are "
                                 f"one line): its positions form a surface, not a volume, so there is no "
                                 f"closed form here; use numeric IK with mask=[1, 1, 1, 0, 0, 0]")
    geometry, _, clause = _core.detect_point(chain._core, (0.0, 0.0, 0.0))  # the case is the lines'
    return NoClosedFormError(_NO_POSITION_CASE) if geometry is None else clause


def _geometry(chain: Chain, tail: NDArray[np.float64]) -> tuple[PointGeometry, NDArray[np.float64]]:
    """The point case for joints 1-3 with joints 4..n at ``tail`` (its tool point at q1-3 = 0),
    and the signs of joints 1-3."""
    _plan(chain)
    c = fk(chain, np.concatenate([np.zeros(3), tail])[None])[0, :3, 3]
    geometry, lines, _ = _core.detect_point(chain._core, tuple(float(x) for x in c))
    if geometry is None:
        raise NoClosedFormError(_NO_POSITION_CASE)
    return geometry, lines["sign"]


def _polish(chain: Chain, q: NDArray[np.float64], p: NDArray[np.float64]) -> NDArray[np.float64]:
    """Newton steps on joints 1-3 of ``q`` for the tool position ``p`` (least squares)."""
    for _ in range(_POLISH_STEPS):
        error = p - fk(chain, q[None])[0, :3, 3]
        if np.linalg.norm(error) <= 1e-13:
            break
        J = geometric_jacobian(chain, q[None])[0, :3, :3]
        q = q.copy()
        q[:3] += np.linalg.lstsq(J, error, rcond=None)[0]
    return q


def ik_position_solutions(robot: Robot | Chain, position: ArrayLike, *, near: ArrayLike | None = None,
                          turn_copies: bool = False) -> IKSolutions:
    """Every closed-form solution for a tool position, inside the limits or not, with flags.

    Parameters
    ----------
    robot : Robot or Chain
    position : array_like, shape (3,)
        Target tool position [m], base frame.
    near : array_like, shape (n,), optional
        Reference configuration [rad or m] for the ``2 pi`` wrap and the order; joints 4..n
        keep its values (default zeros).
    turn_copies : bool
        Also list the whole-turn copies inside the limits (as :func:`armkit.ik.ik_solutions`);
        default each solution once.

    Returns
    -------
    IKSolutions
        ``orientation_error`` is NaN (the orientation is free); empty if out of reach.
    """
    return _solve(as_chain(robot), position, near, turn_copies)[0]


def _wrap_first_three(chain: Chain, q: NDArray[np.float64], near: NDArray[np.float64]) -> NDArray[np.float64]:
    """Joints 1-3 of ``q`` wrapped into the limits (near ``near``); joints 4..n as held."""
    wrapped = wrap_into_limits(chain, q, near)
    wrapped[:, 3:] = near[3:]
    return wrapped


#: A position farther from the base than this many times the arm's whole length is out of reach
#: without solving; its distance from the base is then the distance to the closest reachable
#: point to 1e-6 relative.
_FAR = 1e6
#: Largest distance [m] from the base the subproblems can take: their squares overflow near 1e154.
_LARGEST_DISTANCE = 1e150


def _refuse_far(chain: Chain, p: NDArray[np.float64]) -> None:
    """:class:`UnreachableError` for a position beyond :data:`_FAR` whole arm lengths (prismatic
    joints' travel included) from the base; :class:`InputError` beyond :data:`_LARGEST_DISTANCE`
    for an arm whose unlimited prismatic joints might reach it."""
    travel = np.abs(chain.lower[chain.prismatic]).sum() + np.abs(chain.upper[chain.prismatic]).sum()
    whole = chain.link_length + travel
    scale = max(float(np.abs(p).max()), 1.0)  # |p| without overflow
    distance = float(np.linalg.norm(p / scale)) * scale
    shown = ", ".join(f"{v:.6g}" for v in p)
    if np.isfinite(whole) and distance > _FAR * (1.0 + whole):
        raise UnreachableError(f"tool position [{shown}] m is out of reach: {distance:.3g} m from the base, "
                               f"over a million times the arm's whole length ({whole:.3g} m)", distance)
    if distance > _LARGEST_DISTANCE:
        raise InputError(f"position [{shown}] m: {distance:.3g} m from the base; position IK takes targets "
                         f"up to {_LARGEST_DISTANCE:g} m away (the subproblems' squares overflow beyond)",
                         parameter="position", value=p)


def _solve(chain: Chain, position: ArrayLike, near: ArrayLike | None, turn_copies: bool
           ) -> tuple[IKSolutions, float]:
    """:func:`ik_position_solutions`, and the distance [m] of the closest candidate (valid or not:
    an invalid one is as close as the subproblems get)."""
    p = float_array(position, "position", "3 finite numbers [m]")
    if p.shape != (3,) or not np.isfinite(p).all():
        raise InputError(f"position: expected 3 finite numbers [m], got {p.tolist()}")
    near = np.zeros(chain.n) if near is None else float_array(near, "near", f"{chain.n} finite joint values")
    if near.shape != (chain.n,) or not np.isfinite(near).all():
        raise InputError(f"near: expected {chain.n} finite joint values, got {near.tolist()}")
    _plan(chain)  # an arm without a position closed form says so first
    _refuse_far(chain, p)
    geometry, sign = _geometry(chain, near[3:])
    q3, valid, family = solve_pose(geometry, np.eye(3), p)
    q = np.tile(near, (len(q3), 1))
    q[:, :3] = np.asarray(q3) * sign
    q = _wrap_first_three(chain, q, near)
    q = np.stack([_polish(chain, row, p) if ok else row for row, ok in zip(q, valid, strict=True)])
    error = np.linalg.norm(fk(chain, q)[:, :3, 3] - p, axis=1)
    closest = float(error.min())
    keep = np.asarray(valid) & (error <= SOLUTION_TOLERANCE)
    duplicate = np.zeros(len(q), dtype=bool)
    _core.duplicates(np.ascontiguousarray(q), keep, np.ascontiguousarray(chain.prismatic), duplicate)
    keep &= ~duplicate
    q, family, error = _wrap_first_three(chain, q[keep], near), np.asarray(family)[keep], error[keep]
    order = np.argsort(np.linalg.norm(q - near, axis=1), kind="stable")
    q, family, error = q[order], family[order], error[order]
    inside = chain.within_limits(q)
    if turn_copies and chain.spans_turns and len(q):
        k = len(q)
        flags = np.zeros((1, k, 4), dtype=bool)
        flags[0, :, 2], flags[0, :, 3] = inside, family
        errors = np.stack([error, np.full(k, np.nan)], axis=-1)[None]
        joints = np.arange(chain.n) < 3
        found = Found(np.ascontiguousarray(q[None]), errors, flags, np.array([k]))
        listed, total = with_turn_copies(chain, found, near, None, joints)
        m = int(listed.count[0])
        if total[0] > m:
            warn_at_caller(left_off_warning(chain, m, float(total[0]), joints))
        q, inside, family, error = listed.q[0, :m], listed.inside[0, :m], listed.family[0, :m], \
            listed.position_error[0, :m]  # each copy with its solution's residual
    return IKSolutions(q, inside, family, error, np.full(len(q), np.nan)), closest


def ik_position(robot: Robot | Chain, position: ArrayLike, *, all_solutions: bool = False,
                near: ArrayLike | None = None, within_limits: bool = True,
                turn_copies: bool = False) -> NDArray[np.float64]:
    """Position IK in closed form: joints 1-3 put the tool point at ``position`` [m].

    Parameters
    ----------
    robot : Robot or Chain
    position : array_like, shape (3,)
        Target tool position [m], base frame; the orientation is free.
    all_solutions : bool
        Every solution (up to 4, and whole-turn copies: see :func:`armkit.ik.ik_solutions`),
        nearest to ``near`` first, instead of the nearest one.
    near : array_like, shape (n,), optional
        Reference configuration; joints 4..n keep its values (default zeros).
    within_limits : bool
        Only solutions inside the joint limits (default).
    turn_copies : bool
        As in :func:`armkit.ik.ik`.

    Returns
    -------
    ndarray
        ``(n,)``, or ``(k, n)`` with ``all_solutions``.

    Raises
    ------
    NoClosedFormError
        If joints 1-3 have no closed-form position solution (then use numeric IK with
        ``mask=[1, 1, 1, 0, 0, 0]``).
    UnreachableError
        If the position is out of reach (with joints 4..n as held).
    JointLimitError
        If it is reachable only outside the limits (and ``within_limits``).

    Examples
    --------
    >>> import armkit
    >>> robot = armkit.load("examples/data/my_arm.toml")
    >>> ik_position(robot, [0.3, 0.1, 0.3], all_solutions=True).round(4)  # elbow up / down, facing / turned
    array([[ 0.3218, -0.2925, -1.6293],
           [ 0.3218, -1.9633,  1.6293],
           [-2.8198,  0.2925,  1.6293],
           [-2.8198,  1.9633, -1.6293]])
    """
    chain = as_chain(robot)
    found, closest = _solve(chain, position, near, turn_copies)
    usable = found.within_limits if within_limits else np.ones(len(found.q), dtype=bool)
    if not usable.any():
        p = np.round(np.asarray(position, dtype=float), 6).tolist()
        if len(found.q):
            raise JointLimitError(
                f"tool position {p} m is reachable, but only outside the joint limits (e.g. "
                f"{', '.join(chain.limit_violations(found.q[0]))}): ask for solutions outside the "
                f"limits with within_limits=False or 'armkit ik --outside'", found.q[0].copy(),
                **chain.limit_fields(found.q[0]))
        held = f" with joints 4..{chain.n} held at near's values" if chain.n > 3 else ""
        raise UnreachableError(f"tool position {p} m is out of reach{held}: the closest tool position "
                               f"found is {closest:.3g} m away", closest)
    q = found.q[usable]
    return q if all_solutions else q[0]


#: The old name of :func:`ik_position_solutions` (``ik`` pairs with ``ik_solutions``, so
#: ``ik_position`` with ``ik_position_solutions``).
position_solutions = deprecated_function("position_solutions", ik_position_solutions)
