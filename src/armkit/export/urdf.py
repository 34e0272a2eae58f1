"""URDF export of an armkit robot.

Written from the one internal chain (see :mod:`armkit.export.physical`): links ``base``,
``link1`` ... ``linkN`` and ``tool``. Link ``i`` is joint frame ``i`` of the chain (not
the DH link frame): joint ``i``'s ``<origin>`` is the fixed transform from the previous
joint frame (``T_between[i - 1]``), its axis is ``0 0 1``, and a fixed joint ``tool_joint``
(``tool_joint_2`` ... if the robot has a joint of that name) places the ``tool`` link at the
tool frame. FK through the URDF therefore equals
:func:`armkit.kinematics.fk` whatever DH convention the robot came in.

URDF has no capsules, so links are drawn as cylinders plus spheres at the joints. URDF
requires limits on revolute and prismatic joints: a revolute joint without finite limits
is written ``continuous``; a prismatic joint without finite limits gets
``UNBOUNDED_PRISMATIC`` metres. Velocity limits are the robot's where it has them, else
``DEFAULT_VELOCITY``.

A ``<mujoco>`` element asks MuJoCo's URDF importer to keep the ``tool`` link as its own
body (``fusestatic="false"``); other URDF readers ignore it.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from armkit.export.physical import BodyShape, PhysicalModel, physical_model
from armkit.export.writing import write_text
from armkit.robot import Robot
from armkit.spatial.rotations import euler_from_matrix

__all__ = ["urdf_from_robot", "write_urdf"]

UNBOUNDED_PRISMATIC = 1000.0  # m
DEFAULT_VELOCITY = 10.0  # rad/s or m/s
_INERTIA_KEYS = {"ixx": (0, 0), "ixy": (0, 1), "ixz": (0, 2), "iyy": (1, 1), "iyz": (1, 2), "izz": (2, 2)}


def _numbers(values: NDArray[np.float64]) -> str:
    return " ".join(repr(float(v)) for v in np.ravel(values))


def _origin(parent: ET.Element, T: NDArray[np.float64]) -> None:
    ET.SubElement(parent, "origin", xyz=_numbers(T[:3, 3]),
                  rpy=_numbers(euler_from_matrix(T[:3, :3], "xyz-fixed")))


def _frame_along(start: NDArray[np.float64], end: NDArray[np.float64]) -> NDArray[np.float64]:
    """A transform at the segment's middle whose z axis points from ``start`` to ``end``."""
    z = (end - start) / np.linalg.norm(end - start)
    helper = np.eye(3)[np.argmin(np.abs(z))]
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    T = np.eye(4)
    T[:3, :3] = np.column_stack([x, np.cross(z, x), z])
    T[:3, 3] = (start + end) / 2
    return T


def _add_link(robot_el: ET.Element, name: str, shape: BodyShape | None, radius: float,
              housing: bool) -> None:
    link = ET.SubElement(robot_el, "link", name=name)
    if shape is None:
        return
    if shape.mass > 0 or shape.inertia.any():  # a massless link with inertia (a rotor) keeps it
        inertial = ET.SubElement(link, "inertial")
        ET.SubElement(inertial, "origin", xyz=_numbers(shape.com), rpy="0 0 0")
        ET.SubElement(inertial, "mass", value=repr(shape.mass))
        ET.SubElement(inertial, "inertia",
                      **{key: repr(float(shape.inertia[ij])) for key, ij in _INERTIA_KEYS.items()})
    pieces = [(np.eye(4), ("sphere", {"radius": repr(1.5 * radius)}))] if housing else []
    for start, end in shape.segments:
        pieces.append((_frame_along(start, end),
                       ("cylinder", {"radius": repr(radius),
                                     "length": repr(float(np.linalg.norm(end - start)))})))
    for tag in ("visual", "collision"):
        for T, (kind, size) in pieces:
            element = ET.SubElement(link, tag)
            _origin(element, T)
            ET.SubElement(ET.SubElement(element, "geometry"), kind, **size)


def _limit_attributes(robot: Robot, i: int, effort: float) -> dict[str, str] | None:
    joint = robot.chain.joints[i]
    velocity = joint.max_velocity if joint.max_velocity is not None else DEFAULT_VELOCITY
    bounded = np.isfinite(joint.lower) and np.isfinite(joint.upper)
    if joint.kind == "revolute" and not bounded:
        return None
    lower, upper = (joint.lower, joint.upper) if bounded else (-UNBOUNDED_PRISMATIC, UNBOUNDED_PRISMATIC)
    return {"lower": repr(float(lower)), "upper": repr(float(upper)), "effort": repr(float(effort)),
            "velocity": repr(float(velocity))}


def _unused_name(name: str, taken: list[str]) -> str:
    """``name``, or ``name_2``, ``name_3`` ... : the first that is not in ``taken``."""
    candidate, k = name, 1
    while candidate in taken:
        k += 1
        candidate = f"{name}_{k}"
    return candidate


def urdf_from_robot(robot: Robot, *, model: PhysicalModel | None = None) -> str:
    """URDF text for ``robot``: links ``base``, ``link1..N``, ``tool``; joints named as the robot's.

    Parameters
    ----------
    robot : Robot
    model : PhysicalModel, optional
        Precomputed :func:`~armkit.export.physical.physical_model` of ``robot``.

    Raises
    ------
    RobotDefinitionError
        If the arm cannot be simulated (every link length zero).

    Examples
    --------
    >>> import armkit
    >>> text = urdf_from_robot(armkit.load("grb400-scara"))
    >>> text.count("<joint "), 'type="prismatic"' in text
    (5, True)
    """
    model = physical_model(robot) if model is None else model
    root = ET.Element("robot", name=robot.name)
    mujoco = ET.SubElement(root, "mujoco")
    ET.SubElement(mujoco, "compiler", fusestatic="false", discardvisual="true",
                  balanceinertia="true")
    _add_link(root, "base", model.base, model.radius, housing=False)
    parent = "base"
    for i, joint in enumerate(robot.chain.joints):
        child = f"link{i + 1}"
        _add_link(root, child, model.bodies[i], model.radius, housing=True)
        limits = _limit_attributes(robot, i, model.effort[i])
        kind = joint.kind if limits is not None else "continuous"
        element = ET.SubElement(root, "joint", name=joint.name, type=kind)
        _origin(element, model.T_parent_body[i])
        ET.SubElement(element, "parent", link=parent)
        ET.SubElement(element, "child", link=child)
        ET.SubElement(element, "axis", xyz="0 0 1")
        if limits is not None:
            ET.SubElement(element, "limit", **limits)
        parent = child
    _add_link(root, "tool", None, model.radius, housing=False)
    tool_joint = ET.SubElement(root, "joint", name=_unused_name("tool_joint", robot.joint_names),
                               type="fixed")
    _origin(tool_joint, model.T_last_tool)
    ET.SubElement(tool_joint, "parent", link=parent)
    ET.SubElement(tool_joint, "child", link="tool")
    ET.indent(root)
    return '<?xml version="1.0"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def write_urdf(robot: Robot, path: str | Path, *, overwrite: bool = False) -> Path:
    """Write :func:`urdf_from_robot` to ``path``; refuses to overwrite unless ``overwrite``.

    Raises
    ------
    InputError
        If ``path`` exists and ``overwrite`` is false, or its folder does not exist.
    """
    return write_text(path, urdf_from_robot(robot), overwrite=overwrite)
