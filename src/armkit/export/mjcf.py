"""MJCF (MuJoCo XML) export of an armkit robot.

The model is written from the one internal chain (see :mod:`armkit.export.physical`):
nested bodies at the joint frames, hinge or slide joints along each body's z axis, the
robot's base frame at the world origin and a site named ``tool`` at the tool frame (in a
fixed, massless body also named ``tool``).
Angles are in radians (``<compiler angle="radian"/>``), numbers are written with full
precision so MuJoCo's forward kinematics match armkit's to rounding error.

Every joint ``qN`` has two actuators: ``qN_position`` (position servo, ``ctrl`` = target
position) and ``qN_velocity`` (velocity servo, ``ctrl`` = target velocity); together
``kp (q* - q) + kv (qd* - qd)``. Geoms do not collide (the model checks kinematics and
servo tracking, not contacts).

MJCF has no velocity, acceleration or (without changing the simulation) torque limits: a
joint's ``max_velocity``, ``max_acceleration`` and ``max_torque`` are written as custom
numerics named ``armkit:<joint>:<limit>`` (:data:`LIMIT_NUMERIC`), which MuJoCo keeps and
ignores and :mod:`armkit.mjcf` reads back.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from armkit.dynamics import missing_inertia
from armkit.export.physical import DENSITY, TIMESTEP, BodyShape, PhysicalModel, physical_model
from armkit.export.writing import write_text
from armkit.robot import Robot
from armkit.spatial.rotations import quaternion_wxyz_from_matrix

__all__ = ["LIMIT_NUMERIC", "mjcf_element", "mjcf_from_robot", "write_mjcf"]

#: Name of the custom numeric holding joint ``joint``'s ``limit`` (a :class:`~armkit.chain.Joint` field).
LIMIT_NUMERIC = "armkit:{joint}:{limit}"

#: The joint limits MJCF has no element for, written as custom numerics.
_NUMERIC_LIMITS = ("max_velocity", "max_acceleration", "max_torque")

_COLORS = ("0.85 0.45 0.12 1", "0.20 0.40 0.75 1")  # alternate link colours
_HOUSING_COLOR = "0.25 0.25 0.28 1"


def mjcf_numbers(values: NDArray[np.float64]) -> str:
    """Numbers as an MJCF attribute: space-separated, each to its full precision (``repr``)."""
    return " ".join(repr(float(v)) for v in np.ravel(values))


def mjcf_pose(T: NDArray[np.float64]) -> dict[str, str]:
    """A 4x4 pose as MJCF ``pos`` and ``quat`` (w, x, y, z) attributes."""
    return {"pos": mjcf_numbers(T[:3, 3]), "quat": mjcf_numbers(quaternion_wxyz_from_matrix(T[:3, :3]))}


def _add_inertial(body: ET.Element, shape: BodyShape) -> None:
    eigenvalues, axes = np.linalg.eigh(shape.inertia)
    if np.linalg.det(axes) < 0:
        axes[:, 0] = -axes[:, 0]
    ET.SubElement(body, "inertial", pos=mjcf_numbers(shape.com),
                  quat=mjcf_numbers(quaternion_wxyz_from_matrix(axes)), mass=repr(shape.mass),
                  diaginertia=mjcf_numbers(np.maximum(eigenvalues, 1e-12)))


def add_capsule_geoms(body: ET.Element, shape: BodyShape, radius: float, color: str,
                      housing: bool) -> None:
    """The capsules of ``shape`` (radius ``radius`` [m]) and, with ``housing``, a joint housing
    sphere of radius ``1.5 radius`` at the body origin, as ``<geom>`` children of ``body``."""
    if housing:
        ET.SubElement(body, "geom", type="sphere", size=repr(1.5 * radius), rgba=_HOUSING_COLOR)
    for start, end in shape.segments:
        ET.SubElement(body, "geom", type="capsule", size=repr(radius),
                      fromto=mjcf_numbers(np.concatenate([start, end])), rgba=color)


def mjcf_from_robot(robot: Robot, *, gravity: bool = True,
                    model: PhysicalModel | None = None) -> str:
    """MJCF text for ``robot``: bodies, joints, limits, servos and a ``tool`` site.

    Parameters
    ----------
    robot : Robot
    gravity : bool
        Whether the world has gravity (``-9.81 m/s^2`` along base z) or none.
    model : PhysicalModel, optional
        Precomputed :func:`~armkit.export.physical.physical_model` of ``robot``.

    Returns
    -------
    str
        The XML document.

    Raises
    ------
    RobotDefinitionError
        If the arm cannot be simulated (every link length zero).

    Examples
    --------
    >>> import armkit, mujoco
    >>> xml = mjcf_from_robot(armkit.load("probot-anno"))
    >>> mujoco.MjModel.from_xml_string(xml).nu  # a position and a velocity servo per joint
    12
    """
    root = mjcf_element(robot, gravity=gravity, model=model)
    ET.indent(root)
    return ET.tostring(root, encoding="unicode") + "\n"


def mjcf_element(robot: Robot, *, gravity: bool = True, model: PhysicalModel | None = None) -> ET.Element:
    """The ``<mujoco>`` element :func:`mjcf_from_robot` writes, for callers that add to it
    (:mod:`armkit.collision` adds obstacles and makes the geoms collide). The bodies are named
    ``link1`` ... ``linkn`` (body ``i`` at joint frame ``i``), the base's geoms sit in the world body.
    """
    model = physical_model(robot) if model is None else model
    root = ET.Element("mujoco", model=robot.name)
    if missing_inertia(robot.chain) is not None:  # said in the file: read back, they pass for the arm's own
        root.append(ET.Comment(f" armkit: {robot.name} gives no masses; the inertials below are estimated "
                               f"from the capsules (density {DENSITY:g} kg/m^3, "
                               f"robot.with_estimated_inertia): give the arm's own for dynamics. "))
    ET.SubElement(root, "compiler", angle="radian", autolimits="true")
    ET.SubElement(root, "option", timestep=repr(TIMESTEP), integrator="implicitfast",
                  gravity="0 0 -9.81" if gravity else "0 0 0")
    default = ET.SubElement(root, "default")
    ET.SubElement(default, "geom", contype="0", conaffinity="0", group="1")
    world = ET.SubElement(root, "worldbody")
    ET.SubElement(world, "light", pos="0 0 3", dir="0 0 -1", directional="true")
    add_capsule_geoms(world, model.base, model.radius, _HOUSING_COLOR, housing=False)
    parent = world
    actuators = ET.Element("actuator")
    for i, joint in enumerate(robot.chain.joints):
        body = ET.SubElement(parent, "body", name=f"link{i + 1}", **mjcf_pose(model.T_parent_body[i]))
        attributes = {"name": joint.name, "type": "slide" if joint.kind == "prismatic" else "hinge",
                      "axis": "0 0 1", "armature": repr(float(model.armature[i]))}
        if np.isfinite(joint.lower) and np.isfinite(joint.upper):
            attributes["range"] = mjcf_numbers(np.array([joint.lower, joint.upper]))
        ET.SubElement(body, "joint", **attributes)
        _add_inertial(body, model.bodies[i])
        add_capsule_geoms(body, model.bodies[i], model.radius, _COLORS[i % 2], housing=True)
        ET.SubElement(actuators, "position", name=f"{joint.name}_position", joint=joint.name,
                      kp=repr(float(model.kp[i])))
        ET.SubElement(actuators, "velocity", name=f"{joint.name}_velocity", joint=joint.name,
                      kv=repr(float(model.kv[i])))
        parent = body
    # A fixed child body carries the tool frame: MuJoCo would treat a site offset within about
    # 1e-6 of the identity as no offset at all ("same frame"), a body offset it never drops.
    tool = ET.SubElement(parent, "body", name="tool", **mjcf_pose(model.T_last_tool))
    ET.SubElement(tool, "site", name="tool", size=repr(model.radius), rgba="0.1 0.7 0.2 1")
    root.append(actuators)
    _add_limit_numerics(root, robot)
    return root


def _add_limit_numerics(root: ET.Element, robot: Robot) -> None:
    """The joints' velocity, acceleration and torque limits as ``<custom><numeric>`` elements."""
    numerics = [(LIMIT_NUMERIC.format(joint=joint.name, limit=limit), getattr(joint, limit))
                for joint in robot.chain.joints for limit in _NUMERIC_LIMITS]
    numerics = [(name, value) for name, value in numerics if value is not None]
    if numerics:
        custom = ET.SubElement(root, "custom")
        for name, value in numerics:
            ET.SubElement(custom, "numeric", name=name, data=repr(float(value)))


def write_mjcf(robot: Robot, path: str | Path, *, overwrite: bool = False, gravity: bool = True) -> Path:
    """Write :func:`mjcf_from_robot` to ``path``; refuses to overwrite unless ``overwrite``.

    Raises
    ------
    InputError
        If ``path`` exists and ``overwrite`` is false, or its folder does not exist.
    """
    return write_text(path, mjcf_from_robot(robot, gravity=gravity), overwrite=overwrite)
