"""A plausible physical model of an arm for simulation and export: shapes, masses, servos.

armkit robots are kinematic (a DH table). To simulate one, every moving body gets simple
geometry and the mass that goes with it, and every joint a servo. The bodies are the
*joint frames* of :mod:`armkit.chain`: body ``i`` sits at ``T_between[i]`` in the frame of
body ``i - 1`` (the world for ``i = 0``) and moves about or along its own z axis, so the
MJCF and URDF written from this model reproduce :func:`armkit.kinematics.fk` exactly,
whatever DH convention the robot came in.

Geometry
    Each body carries a sphere (the joint housing, radius ``1.5 r``) at its origin and
    solid cylinders of radius ``r`` from its origin to the next joint frame: first along
    the joint axis, then straight to the next origin (the "L" of a DH offset). ``r`` is
    ``LINK_RADIUS_RATIO`` times the arm's total link length, at least ``MIN_RADIUS``.
Mass
    The robot's own inertial parameters when it has them (robot file ``mass``/``com``/
    ``inertia``, URDF ``<inertial>``; see :mod:`armkit.dynamics`), moved into the joint
    frames; a body no simulator takes is made one that it does, without changing the
    moment about its largest principal axis: a massless link gets ``MIN_MASS``, principal
    moments ``A + B < C`` (no rigid body has them, e.g. roboticstoolbox's PUMA 560 link 1,
    which holds only its rotor's moment about the joint axis) are raised until ``A + B = C``,
    and none is below ``MIN_MOMENT``. Otherwise density ``DENSITY`` (a light, partly hollow
    arm), inertia of solid cylinders and spheres, combined with the parallel-axis theorem
    (:func:`capsule_bodies`; :meth:`armkit.Robot.with_estimated_inertia` is the same estimate).
Servos
    Per joint a position servo (gain ``kp``) and a velocity servo (gain ``kv``) with
    critical damping at ``SERVO_BANDWIDTH_HZ``, computed from the largest inertia the
    joint sees over sample configurations plus a reflected rotor inertia (``armature``,
    ``ARMATURE_RATIO`` of it). The servos track a 1 kHz command stream
    (``TIMESTEP``) stably.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from armkit import kinematics
from armkit.dynamics import missing_inertia
from armkit.errors import RobotDefinitionError
from armkit.inertial import Inertial
from armkit.robot import Robot

__all__ = ["BodyShape", "PhysicalModel", "capsule_bodies", "physical_model"]

DENSITY = 1000.0  # kg/m^3
LINK_RADIUS_RATIO = 0.025
MIN_RADIUS = 0.005  # m
SERVO_BANDWIDTH_HZ = 20.0
ARMATURE_RATIO = 0.25
TIMESTEP = 1e-3  # s, the physics and command rate
GRAVITY = 9.81  # m/s^2
#: Smallest mass [kg] and principal moment of inertia [kg m^2] an exported body gets (MuJoCo refuses
#: moving bodies without them).
MIN_MASS = 1e-9
MIN_MOMENT = 1e-12
_MIN_SEGMENT = 1e-6  # m; shorter offsets get no cylinder (MuJoCo rejects degenerate capsules)
_GAIN_SAMPLES = 32


@dataclass(frozen=True)
class BodyShape:
    """Geometry and inertia of one body, in its own frame.

    Attributes
    ----------
    segments : ndarray (k, 2, 3)
        Cylinder end points [m].
    mass : float
        [kg], cylinders and joint housing together.
    com : ndarray (3,)
        Centre of mass [m].
    inertia : ndarray (3, 3)
        Inertia tensor about the centre of mass [kg m^2].
    """

    segments: NDArray[np.float64]
    mass: float
    com: NDArray[np.float64]
    inertia: NDArray[np.float64]


@dataclass(frozen=True)
class PhysicalModel:
    """What MJCF and URDF export need: frames, shapes, limits and servo gains.

    Attributes
    ----------
    robot : Robot
    radius : float
        Link radius ``r`` [m]; joint housings have radius ``1.5 r``.
    T_parent_body : ndarray (n, 4, 4)
        Pose of body ``i`` (joint frame ``i`` at ``q_i = 0``) in body ``i - 1`` (the base
        frame for ``i = 0``).
    T_last_tool : ndarray (4, 4)
        Tool frame in the last body.
    base : BodyShape
        The fixed pedestal, from the base origin to the first joint frame.
    bodies : tuple of BodyShape
        One per joint.
    armature, kp, kv : ndarray (n,)
        Reflected rotor inertia [kg m^2 or kg], position gain [N m/rad or N/m] and
        velocity gain [N m s/rad or N s/m] per joint.
    effort : ndarray (n,)
        Per joint [N m or N], written to the URDF: the robot's ``max_torque`` where it has
        one, else a generous bound (five times the worst static gravity load).
    """

    robot: Robot
    radius: float
    T_parent_body: NDArray[np.float64]
    T_last_tool: NDArray[np.float64]
    base: BodyShape
    bodies: tuple[BodyShape, ...]
    armature: NDArray[np.float64]
    kp: NDArray[np.float64]
    kv: NDArray[np.float64]
    effort: NDArray[np.float64]


def _segments(offset: NDArray[np.float64]) -> NDArray[np.float64]:
    """Cylinders from the origin to ``offset``: along z first, then straight to it."""
    corner = np.array([0.0, 0.0, offset[2]])
    pieces = [(np.zeros(3), corner), (corner, offset)]
    kept = [p for p in pieces if np.linalg.norm(p[1] - p[0]) > _MIN_SEGMENT]
    return np.array(kept, dtype=float).reshape(-1, 2, 3)


def _cylinder_inertia(start: NDArray[np.float64], end: NDArray[np.float64], radius: float,
                      mass: float) -> NDArray[np.float64]:
    """Inertia [kg m^2] of a solid cylinder about its own centre, in the body frame."""
    axis = end - start
    length = np.linalg.norm(axis)
    u = axis / length
    along = np.outer(u, u)
    return mass * radius**2 / 2 * along + mass * (3 * radius**2 + length**2) / 12 * (np.eye(3) - along)


def _shape(offset: NDArray[np.float64], radius: float, housing: bool) -> BodyShape:
    segments = _segments(offset)
    housing_radius = 1.5 * radius
    parts = []  # (mass, centre, inertia about centre)
    if housing:
        m = DENSITY * 4 / 3 * np.pi * housing_radius**3
        parts.append((m, np.zeros(3), 0.4 * m * housing_radius**2 * np.eye(3)))
    for start, end in segments:
        m = DENSITY * np.pi * radius**2 * np.linalg.norm(end - start)
        parts.append((m, (start + end) / 2, _cylinder_inertia(start, end, radius, m)))
    if not parts:
        return BodyShape(segments, 0.0, np.zeros(3), np.zeros((3, 3)))
    mass = sum(p[0] for p in parts)
    com = sum(p[0] * p[1] for p in parts) / mass
    inertia = np.zeros((3, 3))
    for m, centre, inertia_c in parts:
        d = centre - com
        inertia += inertia_c + m * (d @ d * np.eye(3) - np.outer(d, d))
    return BodyShape(segments, float(mass), com, inertia)


def _with_inertial(body: BodyShape, inertial: Inertial) -> BodyShape:
    """``body``'s geometry with ``inertial``'s mass, made one a simulator takes (see the module notes)."""
    inertia = np.array(inertial.inertia)
    moments, axes = np.linalg.eigh(inertia)  # ascending
    shortfall = moments[2] - moments[0] - moments[1]
    if shortfall > 0 or moments[0] < MIN_MOMENT:
        moments[:2] += max(shortfall, 0.0) / 2
        inertia = axes @ np.diag(np.maximum(moments, MIN_MOMENT)) @ axes.T
    return replace(body, mass=max(inertial.mass, MIN_MASS), com=inertial.com, inertia=inertia)


def _check_simulatable(robot: Robot, total_length: float) -> None:
    if not total_length > 1e-6:
        raise RobotDefinitionError(
            f"{robot.name}: cannot be simulated: every link offset is zero (total link length "
            f"{total_length:.3g} m), so the arm has no size to give bodies and masses; expected "
            f"at least one nonzero a or d in the DH table")


def _joint_inertias(robot: Robot, bodies: tuple[BodyShape, ...],
                    q: NDArray[np.float64]) -> NDArray[np.float64]:
    """Inertia each joint drives [kg m^2 or kg], ``(m, n)`` for configurations ``(m, n)``."""
    frames, _ = kinematics.joint_frames(robot, q)
    R, p = frames[..., :3, :3], frames[..., :3, 3]
    mass = np.array([b.mass for b in bodies])
    com = p + np.einsum("...ij,...j->...i", R, np.stack([b.com for b in bodies]))
    inertia = R @ np.stack([b.inertia for b in bodies]) @ np.swapaxes(R, -1, -2)
    result = np.zeros(q.shape)
    for i, prismatic in enumerate(robot.chain.prismatic):
        downstream = slice(i, None)
        if prismatic:
            result[:, i] = mass[downstream].sum()
            continue
        z, origin = R[:, i, :, 2], p[:, i]
        r = com[:, downstream] - origin[:, None]
        r_perp = r - np.einsum("mkj,mj->mk", r, z)[..., None] * z[:, None]
        rotational = np.einsum("mi,mkij,mj->mk", z, inertia[:, downstream], z)
        result[:, i] = (rotational + mass[downstream] * np.sum(r_perp**2, axis=-1)).sum(axis=-1)
    return result


def _gravity_bound(robot: Robot, bodies: tuple[BodyShape, ...], reach: float) -> NDArray[np.float64]:
    """Five times a static gravity load bound per joint [N m or N]."""
    downstream_mass = np.cumsum([b.mass for b in bodies][::-1])[::-1]
    lever = np.where(robot.chain.prismatic, 1.0, reach)
    return 5 * GRAVITY * downstream_mass * lever


def capsule_bodies(robot: Robot) -> tuple[float, BodyShape, tuple[BodyShape, ...]]:
    """The capsule geometry and its masses (density :data:`DENSITY`): ``(radius [m], base, bodies)``,
    each body in its joint frame.

    Raises
    ------
    RobotDefinitionError
        If the arm has no size at all (every DH length zero).
    """
    offsets = robot.chain.T_between[:, :3, 3]
    total_length = float(np.linalg.norm(offsets, axis=-1).sum())
    _check_simulatable(robot, total_length)
    radius = max(LINK_RADIUS_RATIO * total_length, MIN_RADIUS)
    base = _shape(offsets[0], radius, housing=False)
    return radius, base, tuple(_shape(offsets[i + 1], radius, housing=True) for i in range(robot.n))


def physical_model(robot: Robot) -> PhysicalModel:
    """The simulation model of ``robot``: body frames, shapes, masses and servo gains.

    Raises
    ------
    RobotDefinitionError
        If the arm has no size at all (every DH length zero): nothing to simulate.

    Examples
    --------
    >>> import armkit
    >>> model = physical_model(armkit.load("probot-anno"))
    >>> model.T_parent_body.shape, round(model.radius, 4)
    ((6, 4, 4), 0.0198)
    """
    chain = robot.chain
    between = chain.T_between
    radius, base, bodies = capsule_bodies(robot)
    reach = chain.link_length  # the total link length [m]
    if missing_inertia(chain) is None:  # the robot's own masses, in the joint frames
        bodies = tuple(_with_inertial(body, joint.inertial.moved(joint.T_after))
                       for body, joint in zip(bodies, chain.joints, strict=True))
    q = np.vstack([robot.home, robot.random_q(_GAIN_SAMPLES, rng=0)])
    inertia = _joint_inertias(robot, bodies, q).max(axis=0)
    armature = ARMATURE_RATIO * inertia
    omega = 2 * np.pi * SERVO_BANDWIDTH_HZ
    driven = inertia + armature
    return PhysicalModel(robot=robot, radius=radius, T_parent_body=between[:-1].copy(),
                         T_last_tool=between[-1].copy(), base=base, bodies=bodies,
                         armature=armature, kp=driven * omega**2, kv=2 * driven * omega,
                         effort=np.where(np.isfinite(robot.max_torque), robot.max_torque,
                                         _gravity_bound(robot, bodies, reach)))
