"""Rigid-body dynamics of a robot: joint torques, mass matrices, accelerations, payloads.

Conventions (``docs/dynamics.md``):

- Each joint's :class:`~armkit.inertial.Inertial` is its link with every body fixed to it, in
  the joint's link frame (after ``T_after``, see :mod:`armkit.chain`). The core works in the
  joint frames (after each motion) and is given the bodies there once per chain.
- ``gravity`` ``(3,)`` [m/s^2] is a vector in the robot's world frame (the frame ``robot.fk``
  poses are in, before ``T_base``); default :data:`GRAVITY`, ``(0, 0, -9.81)``.
- Torques are [N m] for revolute joints and forces [N] for prismatic ones; ``q`` [rad or m],
  ``qd`` [rad/s or m/s], ``qdd`` [rad/s^2 or m/s^2].
- Every function takes states of shape ``(..., n)`` (broadcast against each other) and
  splits a batch over ``threads`` (default: every core); the result does not depend on it.

The algorithms (recursive Newton-Euler, composite rigid bodies, Cholesky) live in armkit's
compiled core (``cpp/src/dynamics.cpp``); this module checks inputs and prepares the bodies.
"""

from __future__ import annotations

import copy
from collections.abc import Sequence
from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit import _core
from armkit._params import float_in_range, thread_count
from armkit.chain import Chain, as_chain
from armkit.errors import InputError, RobotDefinitionError
from armkit.inertial import Inertial
from armkit.kinematics import non_finite_error
from armkit.spatial.transforms import invert_transform, rot_z, trans_z

if TYPE_CHECKING:  # armkit.robot imports this module lazily
    from armkit.robot import Robot

__all__ = ["GRAVITY", "MAX_DENSITY", "MIN_DENSITY", "coriolis_torques", "forward_dynamics", "gravity_torques",
           "inverse_dynamics", "locked_inertials", "mass_matrix", "with_estimated_inertia", "with_payload"]


def _read_only(values: list[float]) -> NDArray[np.float64]:
    array = np.array(values, dtype=float)
    array.setflags(write=False)
    return array


#: Default gravity [m/s^2] in the robot's world frame: 9.81 along -z.
GRAVITY: NDArray[np.float64] = _read_only([0.0, 0.0, -9.81])
#: Largest density ``with_estimated_inertia`` takes [kg/m^3]: about four times osmium's (22,600), so
#: that a density in the wrong unit (g/m^3, 1e308) is an error, not a link of 1e305 kg.
MAX_DENSITY = 1e5
#: Smallest density it takes [kg/m^3]: a foam's is about 10; links of 1e-300 kg/m^3 would weigh
#: nothing and forward dynamics would answer 1e306 rad/s^2.
MIN_DENSITY = 1.0


def missing_inertia(chain: Chain) -> str | None:
    """The name of the first joint without inertial parameters, or None if every joint has them."""
    return next((joint.name for joint in chain.joints if joint.inertial is None), None)


def dynamics_model(chain: Chain) -> _core.Dynamics:
    """The chain's bodies in their joint frames, as the core takes them (made once per chain)."""
    return chain.derived(_make_model)


def _make_model(chain: Chain) -> _core.Dynamics:
    missing = missing_inertia(chain)
    if missing is not None:
        raise RobotDefinitionError(
            f"joint {missing} has no inertial parameters (mass, com, inertia), so no dynamics can be "
            f"computed; give them (robot file keys mass, com, inertia; URDF <inertial>) or ask for an "
            f"estimate: robot.with_estimated_inertia(density=...), --estimate-inertia DENSITY on the "
            f"command line")
    bodies = [joint.inertial.moved(joint.T_after) for joint in chain.joints]
    mass = np.array([b.mass for b in bodies])
    moment = np.array([b.mass * b.com for b in bodies])
    inertia = np.array([b.about_origin() for b in bodies])
    return _core.Dynamics(chain._core, mass, moment, inertia, GRAVITY)  # GRAVITY: for one-state calls


def _gravity(gravity: ArrayLike) -> NDArray[np.float64]:
    if gravity is GRAVITY:
        return GRAVITY
    try:
        g = np.array(gravity, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InputError(f"gravity: expected 3 numbers [m/s^2], got {gravity!r}") from exc
    if g.shape != (3,) or not np.isfinite(g).all():
        raise InputError(f"gravity: expected 3 finite numbers [m/s^2] (default (0, 0, -9.81)), "
                         f"got {gravity!r}")
    return g


def _states(chain: Chain, optional: tuple[str, ...] = (),
            **arrays: ArrayLike | None) -> list[NDArray[np.float64] | None]:
    """The named arrays as C-ordered float64 ``(..., n)``, broadcast against each other; None stays
    None for the ``optional`` ones (zero) and is refused for the others."""
    n = chain.n
    out = {}
    for name, values in arrays.items():
        if values is None and name in optional:
            out[name] = None
            continue
        if values is None:
            raise InputError(f"{name}: expected {n} numbers per state (shape (..., {n})), got None")
        try:
            a = np.asarray(values, dtype=float)
        except (TypeError, ValueError) as exc:
            raise InputError(f"{name}: expected {n} numbers per state (shape (..., {n})), "
                             f"got {values!r}") from exc
        if a.shape[-1:] != (n,):
            got = "a scalar" if a.ndim == 0 else f"shape {a.shape}"
            raise InputError(f"{name}: the robot has {n} joints, so expected shape (..., {n}), got {got}")
        if not np.isfinite(a).all():
            raise non_finite_error(a, name)
        out[name] = a
    given = [name for name, a in out.items() if a is not None]
    try:
        shape = np.broadcast_shapes(*(out[name].shape for name in given))
    except ValueError as exc:
        shapes = ", ".join(f"{name} {out[name].shape}" for name in given)
        raise InputError(f"{shapes}: expected shapes that broadcast together, (..., {n}) each") from exc
    return [None if a is None else np.ascontiguousarray(np.broadcast_to(a, shape)) for a in out.values()]


def inverse_dynamics(robot: Robot | Chain, q: ArrayLike, qd: ArrayLike | None = None,
                     qdd: ArrayLike | None = None, *, gravity: ArrayLike = GRAVITY,
                     threads: int | None = None) -> NDArray[np.float64]:
    """Joint torques that produce accelerations ``qdd`` at ``(q, qd)``: ``M qdd + C qd + g``.

    Recursive Newton-Euler in the compiled core.

    Parameters
    ----------
    robot : Robot or Chain
        With inertial parameters on every joint.
    q : array_like, shape (..., n)
        Joint positions [rad or m].
    qd, qdd : array_like, shape (..., n), optional
        Joint velocities [rad/s or m/s] and accelerations [rad/s^2 or m/s^2]; default zero.
    gravity : array_like, shape (3,)
        [m/s^2] in the world frame; default (0, 0, -9.81).
    threads : int, optional
        Threads for a batch (default: every core).

    Returns
    -------
    ndarray, shape (..., n)
        [N m] (revolute) or [N] (prismatic).

    Raises
    ------
    RobotDefinitionError
        If a joint has no inertial parameters (the message names it).
    InputError
        If a state is not ``(..., n)`` finite numbers or the shapes do not broadcast.

    Examples
    --------
    A 1 kg point 1 m along x of a 1R arm turning about z, with gravity along -y:

    >>> import armkit
    >>> from armkit.inertial import Inertial
    >>> arm = armkit.Robot.from_dh([armkit.DHRow(0, 1.0, 0, 0)], "standard",
    ...                            inertials=[Inertial.from_values(1.0, [0, 0, 0], [0, 0, 0])])
    >>> inverse_dynamics(arm, [0.0], [0.0], [2.0], gravity=[0, -9.81, 0]).round(6).tolist()
    [11.81]
    """
    chain = as_chain(robot)
    model = dynamics_model(chain)
    q, qd, qdd = _states(chain, ("qd", "qdd"), q=q, qd=qd, qdd=qdd)  # broadcast to one shape
    tau = np.empty(q.shape)
    _core.inverse_dynamics(model, q, qd, qdd, _gravity(gravity), tau, thread_count(threads))
    return tau


def gravity_torques(robot: Robot | Chain, q: ArrayLike, *, gravity: ArrayLike = GRAVITY,
                    threads: int | None = None) -> NDArray[np.float64]:
    """Torques that hold the arm still against gravity at ``q`` ``(..., n)``: ``(..., n)`` [N m or N].

    >>> import armkit
    >>> from armkit.inertial import Inertial
    >>> arm = armkit.Robot.from_dh([armkit.DHRow(np.pi / 2, 0.5, 0, 0)], "standard",
    ...                            inertials=[Inertial.from_values(2.0, [0, 0, 0], [0, 0, 0])])
    >>> gravity_torques(arm, [0.0], gravity=[0, -9.81, 0]).round(6).tolist()
    [9.81]
    """
    return inverse_dynamics(robot, q, gravity=gravity, threads=threads)


def coriolis_torques(robot: Robot | Chain, q: ArrayLike, qd: ArrayLike, *,
                     threads: int | None = None) -> NDArray[np.float64]:
    """Coriolis and centrifugal torques ``C(q, qd) qd`` ``(..., n)`` [N m or N] (no gravity)."""
    return inverse_dynamics(robot, q, qd, gravity=np.zeros(3), threads=threads)


def mass_matrix(robot: Robot | Chain, q: ArrayLike, *, threads: int | None = None) -> NDArray[np.float64]:
    """Joint-space mass matrices ``M(q)`` ``(..., n, n)`` [kg m^2, kg m or kg], symmetric positive
    (semi-)definite; composite rigid bodies in the compiled core.

    >>> import armkit
    >>> from armkit.inertial import Inertial
    >>> arm = armkit.Robot.from_dh([armkit.DHRow(0, 1.0, 0, 0)], "standard",
    ...                            inertials=[Inertial.from_values(3.0, [0, 0, 0], [0, 0, 0.5])])
    >>> mass_matrix(arm, [0.3]).tolist()
    [[3.5]]
    """
    chain = as_chain(robot)
    model = dynamics_model(chain)
    (q,) = _states(chain, q=q)
    M = np.empty((*q.shape, chain.n))
    _core.mass_matrix(model, q, M, thread_count(threads))
    return M


def forward_dynamics(robot: Robot | Chain, q: ArrayLike, qd: ArrayLike, tau: ArrayLike, *,
                     gravity: ArrayLike = GRAVITY, threads: int | None = None) -> NDArray[np.float64]:
    """Joint accelerations ``(..., n)`` [rad/s^2 or m/s^2] under torques ``tau`` [N m or N]:
    ``M(q) qdd = tau - C(q, qd) qd - g(q)``, solved with a Cholesky factorisation.

    Raises
    ------
    InputError
        If a state is not ``(..., n)`` finite numbers or the shapes do not broadcast.
    RobotDefinitionError
        If a joint has no inertial parameters, or the mass matrix of a state is singular
        (a joint moves no mass, e.g. a massless last link turning about its own axis).

    Examples
    --------
    >>> import armkit
    >>> from armkit.inertial import Inertial
    >>> arm = armkit.Robot.from_dh([armkit.DHRow(0, 1.0, 0, 0)], "standard",
    ...                            inertials=[Inertial.from_values(2.0, [0, 0, 0], [0, 0, 0])])
    >>> forward_dynamics(arm, [0.0], [0.0], [4.0]).round(12).tolist()
    [2.0]
    """
    chain = as_chain(robot)
    model = dynamics_model(chain)
    q, qd, tau = _states(chain, q=q, qd=qd, tau=tau)
    qdd = np.empty(q.shape)
    bad = _core.forward_dynamics(model, q, qd, tau, _gravity(gravity), qdd, thread_count(threads))
    if bad >= 0:
        where = np.unravel_index(bad, q.shape[:-1]) if q.ndim > 1 else ()
        state = f" at state {tuple(int(i) for i in where)}" if where else ""
        raise RobotDefinitionError(
            f"the mass matrix{state} (q = {np.round(q.reshape(-1, chain.n)[bad], 6).tolist()}) is not "
            f"positive definite: some joint moves no mass or inertia; check the links' mass and inertia")
    return qdd


# ------------------------------------------------------------------ building robots with inertia
def locked_inertials(chain: Chain, locked: dict[int, float]) -> list[Inertial | None]:
    """Per free joint of ``chain`` with the joints ``locked`` (index -> value [rad or m]) fixed,
    its link with the locked links after it folded in (in its link frame). Locked links before
    the first free joint are fixed to the base and carry no load.
    """
    out: list[Inertial | None] = []
    T_link = np.eye(4)  # locked link frame in the last free joint's link frame
    for i, joint in enumerate(chain.joints):
        if i not in locked:
            out.append(joint.inertial)
            T_link = np.eye(4)
            continue
        motion = (trans_z if joint.kind == "prismatic" else rot_z)(locked[i])
        T_link = T_link @ joint.T_before @ motion @ joint.T_after
        if out and out[-1] is not None:
            out[-1] = None if joint.inertial is None else out[-1] + joint.inertial.moved(T_link)
    return out


def _with_inertials(robot: Robot, inertials: list[Inertial | None]) -> Robot:
    """A copy of ``robot`` (same class and description) whose joints carry ``inertials``."""
    chain = robot.chain
    joints = tuple(replace(joint, inertial=inertial) for joint, inertial in zip(chain.joints, inertials,
                                                                               strict=True))
    new = copy.copy(robot)
    new.chain = Chain(joints, chain.T_base, chain.T_tool)
    return new


def with_payload(robot: Robot, mass: float, com: ArrayLike = (0.0, 0.0, 0.0),
                 inertia: ArrayLike = ((0.0,) * 3,) * 3) -> Robot:
    """``robot`` carrying a payload fixed to its tool frame, added to the last link's own.

    Parameters
    ----------
    mass : float
        [kg], at least 0.
    com : array_like, shape (3,)
        The payload's centre of mass in the tool frame [m].
    inertia : array_like, shape (3, 3) or (3,)
        About its centre of mass, tool-frame axes [kg m^2]; ``(3,)`` the diagonal.

    Raises
    ------
    InputError
        If a value is not finite, the mass negative or the inertia not symmetric.
    RobotDefinitionError
        If the robot has no inertial parameters (the payload never replaces the link's own).

    Examples
    --------
    >>> import armkit
    >>> arm = armkit.load("puma560")
    >>> heavier = arm.with_payload(2.0, [0, 0, 0.1])
    >>> round(heavier.chain.joints[-1].inertial.mass - arm.chain.joints[-1].inertial.mass, 12)
    2.0
    """
    try:
        payload = Inertial.from_values(mass, com, inertia)
    except (RobotDefinitionError, ValueError, TypeError) as exc:
        raise InputError(f"payload: {exc}") from exc
    missing = missing_inertia(robot.chain)
    if missing is not None:
        raise RobotDefinitionError(
            f"joint {missing} has no inertial parameters; a payload adds to the links' own, so give "
            f"them first (or robot.with_estimated_inertia(density=...))")
    inertials = [joint.inertial for joint in robot.chain.joints]
    inertials[-1] = inertials[-1] + payload.moved(robot.chain.T_tool)  # T_tool: tool in the last link frame
    return _with_inertials(robot, inertials)


def with_estimated_inertia(robot: Robot, density: float = 1000.0) -> Robot:
    """``robot`` with every link's inertia estimated from the capsules MJCF export draws.

    Each link is the solid cylinders (and the joint housing sphere) of
    :mod:`armkit.export.physical` of the given density: a rough but explicit model for an arm
    whose file has no masses. Links that already have inertial parameters are replaced.

    Parameters
    ----------
    density : float
        [kg/m^3], from :data:`MIN_DENSITY` to :data:`MAX_DENSITY` (1000: a light, partly hollow arm).

    Examples
    --------
    >>> import armkit
    >>> arm = armkit.load("probot-anno").with_estimated_inertia(density=1000.0)
    >>> round(sum(j.inertial.mass for j in arm.chain.joints), 3)
    1.639
    """
    from armkit.export.physical import DENSITY, capsule_bodies

    scale = float_in_range(density, "density [kg/m^3]", MIN_DENSITY, MAX_DENSITY, "a density") / DENSITY
    return with_body_inertials(robot, capsule_bodies(robot)[2], scale)


def with_body_inertials(robot: Robot, bodies: Sequence, scale: float = 1.0) -> Robot:
    """A copy of ``robot`` whose links carry ``bodies``' masses and inertias (each body with
    ``mass``, ``com`` and ``inertia`` in its joint's frame, as the MuJoCo export writes them),
    scaled by ``scale`` and moved back into the link frames."""
    inertials = [Inertial(body.mass * scale, body.com, body.inertia * scale)
                 .moved(invert_transform(joint.T_after))
                 for joint, body in zip(robot.chain.joints, bodies, strict=True)]
    return _with_inertials(robot, inertials)
