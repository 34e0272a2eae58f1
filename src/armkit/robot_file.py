"""Robot files: a hand-written TOML description of an arm (DH table or joint lines), the
built-in robots, and :func:`load`, which also reads URDF files (:mod:`armkit.urdf`).

DH format (every length in ``length_unit``, every angle in ``angle_unit``)::

    name = "PROBOT Anno"
    convention = "modified"        # or "standard"
    length_unit = "mm"             # "m" or "mm"
    angle_unit = "deg"             # "deg" or "rad"
    [[joints]]                     # one per joint, in order
    type = "revolute"              # or "prismatic"; default "revolute"
    alpha = 0
    a = 0
    d = 284
    theta = 0                      # revolute: zero offset added to q; prismatic: fixed angle
    limits = [-180, 180]           # optional; prismatic limits in length_unit
    max_velocity = 45              # optional, unit/s
    max_acceleration = 20          # optional, unit/s^2
    name = "shoulder"              # optional
    [[tool]]                       # optional fixed DH rows after the last joint
    alpha = 0
    a = 0
    d = 55
    theta = 0

Dynamics (optional, per joint; every joint or none)::

    mass = 4.8                     # kg, the link the joint moves
    com = [-20.3, -14.1, 70]       # centre of mass, length_unit, in the joint's link frame
    inertia = [0.066e6, 0.086e6, 0.0125e6]  # kg length_unit^2 about the centre of mass, link
                                   # frame axes: 3 numbers (the diagonal) or a 3x3 matrix
    max_torque = 89.4              # N m (revolute) or N (prismatic), optional on its own

Collision geometry (optional, per joint; :mod:`armkit.collision`)::

    radius = 40                    # length_unit: the capsules standing for the link this joint moves

``com`` (default the frame origin) and ``inertia`` (default zero) need ``mass``. The link
frame is DH link frame ``i`` of a DH file; in a POE file ``com`` and ``inertia`` are in the
base frame with every joint at zero, like ``axis`` and ``point``. See ``docs/dynamics.md``.

``[[base]]`` rows work like ``[[tool]]`` rows, before the first joint. Instead of rows,
``[base]`` and ``[tool]`` may be single tables holding a plain transform: ``xyz`` (lengths)
and ``rpy`` (angles, fixed axes: ``R = Rz(yaw) Ry(pitch) Rx(roll)``), or ``matrix`` (4x4,
translation in ``length_unit``). In a DH file the tool transform is relative to the last
joint's link frame and the base transform places the DH base frame in the world.

Product-of-exponentials format (``convention = "poe"``, EAIK's and IK-Geo's ``H``/``P``)::

    convention = "poe"
    length_unit = "mm"
    angle_unit = "deg"
    [[joints]]
    axis = [0, 0, 1]               # direction of the joint, base frame, q = 0
    point = [0, 0, 89.2]           # a point on its line, base frame, q = 0
    type = "revolute"              # limits, max_velocity, ... and name as above
    [tool]                         # the tool pose in the base frame at q = 0 (M); default identity
    xyz = [0, 191.5, 1001.3]
    rpy = [-90, 0, 0]
    [base]                         # optional: the base frame's pose in the world
    xyz = [0, 0, 0]

``convention``, ``length_unit`` and ``angle_unit`` are required in a file: a table written
in degrees must never be read as radians. Values are converted to SI units once, here;
lengths and angles larger in magnitude than :data:`armkit.chain.MAX_VALUE` (m or rad) are
refused, ``limits`` too (``limits = [-1e300, 1e300]`` in degrees is no way to say "unlimited":
leave the key out). Joint names must be unique and not empty (default ``q1 ... qn``).
"""

from __future__ import annotations

import json
import math
import re
from dataclasses import replace
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from armkit._tables import (
    ANGLE_UNITS,
    LENGTH_UNITS,
    check_table_keys,
    shown_value,
    table_choice,
    table_number,
    table_quantity,
    table_transform,
    table_vector,
    toml_table,
)
from armkit.chain import MAX_VALUE, Chain, DHRow
from armkit.errors import RobotDefinitionError
from armkit.inertial import Inertial
from armkit.poe import poe_from_chain
from armkit.robot import Robot
from armkit.spatial.rotations import euler_from_matrix
from armkit.urdf import robot_from_urdf

__all__ = ["builtin_robots", "load", "robot_from_dict", "robot_to_toml"]

_TOP_KEYS = {"name", "convention", "length_unit", "angle_unit", "description", "joints",
             "tool", "base"}
_ROW_KEYS = {"alpha", "a", "d", "theta"}
_COMMON_JOINT_KEYS = {"type", "limits", "max_velocity", "max_acceleration", "name", "mass", "com", "inertia",
                      "max_torque", "radius"}
_JOINT_KEYS = _ROW_KEYS | _COMMON_JOINT_KEYS
_POE_KEYS = {"axis", "point"}


def builtin_robots() -> list[str]:
    """Names of the robots shipped with armkit, sorted."""
    folder = resources.files("armkit") / "robots"
    return sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".toml"))


def load(name_or_path: str | Path, base: str | None = None, tip: str | None = None) -> Robot:
    """Load a built-in robot by name (``"probot-anno"``), a robot file, a URDF or an MJCF file by path.

    Parameters
    ----------
    name_or_path : str or Path
        A built-in name, a ``.toml`` robot file, an MJCF file (XML whose root is ``<mujoco>``,
        read by MuJoCo: ``pip install 'armkit[sim]'``) or a URDF file (``.urdf``, or any other
        file whose text starts with ``<``).
    base, tip : str, optional
        URDF: the links the serial chain runs between (default the root link and the only
        leaf; see :func:`armkit.urdf.load_urdf`). MJCF: the base body (default the world)
        and the tip body or site (default the only leaf body; see :func:`armkit.mjcf.load_mjcf`).

    Raises
    ------
    RobotDefinitionError
        If the name is neither a built-in nor an existing file, or the file is invalid
        (the message names the file, the joint and the key).

    Examples
    --------
    >>> load("puma560").n
    6
    """
    text = str(name_or_path)
    if text in builtin_robots():
        _no_links(base, tip, f"built-in robot {text!r}")
        resource = resources.files("armkit") / "robots" / f"{text}.toml"
        return _load_text(resource.read_bytes(), f"built-in robot {text!r}")
    path = Path(text)
    if path.is_dir():
        raise RobotDefinitionError(f"{text}: a folder, not a robot file (TOML), a URDF or an MJCF file")
    if not path.is_file():
        raise RobotDefinitionError(
            f"unknown robot {text!r}: not a built-in ({', '.join(builtin_robots())}) "
            f"and no such file")
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise RobotDefinitionError(f"{path}: cannot be read ({exc.strerror or exc})") from exc
    if not data.strip(b"\xef\xbb\xbf \t\r\n"):
        raise RobotDefinitionError(f"{path}: the file is empty; expected a robot file (TOML), "
                                   f"a URDF or an MJCF file")
    xml_file = path.suffix.lower() in _XML_SUFFIXES
    if xml_file and _xml_root(data) is None and _is_utf8(data):  # not UTF-8: the URDF reader says so
        raise RobotDefinitionError(f"{path}: not XML (a {path.suffix} file should hold a URDF <robot> "
                                   f"or an MJCF <mujoco> element)")
    if path.suffix.lower() != ".urdf" and _xml_root(data) == b"mujoco":
        from armkit.mjcf import load_mjcf

        return load_mjcf(path, base=base, tip=tip)
    if xml_file or data.lstrip(b"\xef\xbb\xbf \t\r\n").startswith(b"<"):
        return robot_from_urdf(data, str(path), base=base, tip=tip)
    _no_links(base, tip, str(path))
    return _load_text(data, str(path))


def _is_utf8(data: bytes) -> bool:
    try:
        data.decode("utf-8")
    except UnicodeDecodeError:
        return False
    return True


#: File suffixes that promise XML (a URDF or an MJCF file).
_XML_SUFFIXES = (".urdf", ".xml", ".mjcf", ".xacro")

#: The first element's name in XML text, after any declaration, comments and processing instructions.
_XML_ROOT = re.compile(rb"\s*(?:<\?.*?\?>\s*|<!--.*?-->\s*)*<([A-Za-z_][\w.:-]*)", re.DOTALL)


def _xml_root(data: bytes) -> bytes | None:
    """The root element's name of XML ``data`` (``b"robot"``, ``b"mujoco"``), or None if not XML."""
    match = _XML_ROOT.match(data.removeprefix(b"\xef\xbb\xbf"))
    return None if match is None else match.group(1)


def _no_links(base: str | None, tip: str | None, source: str) -> None:
    if base is not None or tip is not None:
        raise RobotDefinitionError(f"{source}: base and tip links choose a chain in a URDF file (bodies "
                                   f"in an MJCF file); this is a robot file (its base and tool are [base] "
                                   f"and [tool])")


def _load_text(data: bytes, source: str) -> Robot:
    parsed = toml_table(data, source)
    return robot_from_dict(parsed, source, require_units=True)


def _text(value: Any, where: str) -> str:
    if not isinstance(value, str):
        raise RobotDefinitionError(f"{where}: expected a string, got {shown_value(value)}")
    return value


# ------------------------------------------------------------------ tables
def _row(table: dict, where: str, joint: str | None, length: float, angle: float) -> DHRow:
    return DHRow(alpha=table_quantity(table["alpha"], f"{where}, key 'alpha'", angle),
                 a=table_quantity(table["a"], f"{where}, key 'a'", length),
                 d=table_quantity(table["d"], f"{where}, key 'd'", length),
                 theta=table_quantity(table["theta"], f"{where}, key 'theta'", angle),
                 joint=joint)


def _fixed_rows(rows: list, key: str, source: str, length: float, angle: float) -> list[DHRow]:
    out = []
    for i, table in enumerate(rows):
        where = f"{source}, {key} row {i + 1}"
        check_table_keys(table, _ROW_KEYS, _ROW_KEYS, where)
        out.append(_row(table, where, None, length, angle))
    return out


def _end(data: dict, key: str, source: str, length: float, angle: float,
         poe: bool) -> tuple[list[DHRow], NDArray[np.float64] | None]:
    """``[[key]]`` DH rows or a ``[key]`` transform table (``None`` if neither)."""
    value = data.get(key)
    if value is None:
        return [], None
    if isinstance(value, dict):
        return [], table_transform(value, f"{source}, [{key}]", length, angle)
    if isinstance(value, list) and not poe:
        return _fixed_rows(value, key, source, length, angle), None
    expected = f"a [{key}] table (xyz and rpy, or matrix)" + ("" if poe else f" or [[{key}]] DH rows")
    raise RobotDefinitionError(f"{source}: {key} must be {expected}, got {shown_value(value)}")


def _joint_name(table: dict, where: str, index: int, seen: set[str]) -> str:
    name = _text(table.get("name", f"q{index + 1}"), f"{where}, key 'name'")
    if not name.strip():
        raise RobotDefinitionError(f"{where}, key 'name': empty; give the joint a name or leave the key out")
    if name in seen:
        raise RobotDefinitionError(f"{where}, key 'name': {name!r} is already the name of another joint")
    seen.add(name)
    return name


def robot_from_dict(data: dict, source: str = "robot description", require_units: bool = False) -> Robot:
    """Build a :class:`Robot` from the parsed contents of a robot file (see module docstring).

    In code the units default to SI (``"m"``, ``"rad"``) like the rest of the Python API;
    ``require_units=True`` (how files are read) makes ``length_unit`` and ``angle_unit``
    required keys.
    """
    required = {"convention", "joints"} | ({"length_unit", "angle_unit"} if require_units else set())
    check_table_keys(data, _TOP_KEYS, required, source)
    convention = table_choice(data, "convention", ("standard", "modified", "poe"), source, None)
    length_unit = table_choice(data, "length_unit", LENGTH_UNITS, source, "m")
    angle_unit = table_choice(data, "angle_unit", ANGLE_UNITS, source, "rad")
    length, angle = LENGTH_UNITS[length_unit], ANGLE_UNITS[angle_unit]
    poe = convention == "poe"
    joints = data["joints"]
    if not isinstance(joints, list) or not joints:
        raise RobotDefinitionError(f"{source}: 'joints' must be a non-empty array of tables "
                                   f"([[joints]]), got {shown_value(joints)}")
    rows, axes, points, kinds, limits, vmax, amax, names = [], [], [], [], [], [], [], []
    inertials, max_torque, radii = [], [], []
    seen: set[str] = set()
    for i, table in enumerate(joints):
        where = f"{source}, joint {i + 1}"
        keys = _POE_KEYS if poe else _ROW_KEYS
        check_table_keys(table, keys | _COMMON_JOINT_KEYS, keys, where)
        kind = table_choice(table, "type", ("revolute", "prismatic"), where, "revolute")
        unit = angle if kind == "revolute" else length
        if poe:
            axes.append(table_vector(table["axis"], f"{where}, key 'axis'", 1.0))
            points.append(table_vector(table["point"], f"{where}, key 'point'", length))
        else:
            rows.append(_row(table, where, kind, length, angle))
        kinds.append(kind)
        limits.append(_limits(table.get("limits"), f"{where}, key 'limits'", unit))
        vmax.append(_positive(table.get("max_velocity"), f"{where}, key 'max_velocity'", unit))
        amax.append(_positive(table.get("max_acceleration"), f"{where}, key 'max_acceleration'", unit))
        names.append(_joint_name(table, where, i, seen))
        inertials.append(_inertial(table, where, length))
        max_torque.append(_positive(table.get("max_torque"), f"{where}, key 'max_torque'", 1.0))
        radii.append(_positive(table.get("radius"), f"{where}, key 'radius'", length))
    given = [inertial is not None for inertial in inertials]
    if any(given) and not all(given):
        raise RobotDefinitionError(f"{source}, joint {given.index(False) + 1}: no 'mass' while joint "
                                   f"{given.index(True) + 1} has one; give mass (com, inertia) for every "
                                   f"joint or for none")
    inertials = inertials if any(given) else None
    base_rows, T_base = _end(data, "base", source, length, angle, poe)
    tool_rows, T_tool = _end(data, "tool", source, length, angle, poe)
    name = _text(data.get("name", Path(source).stem), f"{source}, key 'name'")
    if poe:
        try:
            robot = Robot.from_poe(axes, points, np.eye(4) if T_tool is None else T_tool, name=name,
                                   kinds=kinds, T_base=T_base, limits=limits, max_velocity=vmax,
                                   max_acceleration=amax, names=names, length_unit=length_unit,
                                   angle_unit=angle_unit, inertials=inertials, max_torque=max_torque)
        except RobotDefinitionError as exc:  # e.g. an axis too short to be a direction: name the file
            raise RobotDefinitionError(f"{source}, {exc}") from exc
    else:
        robot = Robot.from_dh(rows, convention, name=name, limits=limits, max_velocity=vmax,
                              max_acceleration=amax, base_rows=base_rows, tool_rows=tool_rows,
                              length_unit=length_unit, angle_unit=angle_unit, names=names,
                              T_base=T_base, T_tool=T_tool, inertials=inertials, max_torque=max_torque)
    if not np.isfinite(robot.chain.T_between).all():
        raise RobotDefinitionError(f"{source}: the fixed transforms overflow; check the lengths")
    if any(r is not None for r in radii):  # collision capsule radii (armkit.collision)
        chain = robot.chain
        joints = tuple(replace(joint, radius=r) for joint, r in zip(chain.joints, radii, strict=True))
        robot.chain = Chain(joints, chain.T_base, chain.T_tool)
    robot.source = source
    robot.description = _text(data.get("description", ""), f"{source}, key 'description'")
    return robot


def _inertial(table: dict, where: str, length: float) -> Inertial | None:
    """A joint's ``mass``, ``com`` and ``inertia`` (file units) as SI, or None without ``mass``."""
    if "mass" not in table:
        for key in ("com", "inertia"):
            if key in table:
                raise RobotDefinitionError(f"{where}, key {key!r}: needs 'mass' [kg] too")
        return None
    mass = table_number(table["mass"], f"{where}, key 'mass'")
    if not 0 <= mass <= MAX_VALUE:
        raise RobotDefinitionError(f"{where}, key 'mass': expected a mass from 0 to {MAX_VALUE:g} kg, "
                                   f"got {table['mass']!r}")
    com = table_vector(table.get("com", [0, 0, 0]), f"{where}, key 'com'", length)
    value, key = table.get("inertia", [0, 0, 0]), f"{where}, key 'inertia'"
    if isinstance(value, list) and len(value) == 3 and all(isinstance(row, list) for row in value):
        inertia = np.array([table_vector(row, key, length**2) for row in value])
    elif isinstance(value, list) and len(value) == 3:
        inertia = np.diag(table_vector(value, key, length**2))
    else:
        raise RobotDefinitionError(f"{key}: expected 3 numbers (the diagonal) or a 3x3 matrix "
                                   f"[kg length_unit^2], got {shown_value(value)}")
    try:
        return Inertial(mass, com, inertia)
    except RobotDefinitionError as exc:
        raise RobotDefinitionError(f"{where}: {exc}") from exc


def _limits(value: Any, where: str, unit: float) -> tuple[float, float] | None:
    if value is None:
        return None
    if not isinstance(value, list) or len(value) != 2:
        raise RobotDefinitionError(f"{where}: expected [lower, upper], got {shown_value(value)}")
    lower, upper = (table_quantity(v, where, unit) for v in value)
    if not lower < upper:
        raise RobotDefinitionError(f"{where}: lower {value[0]} must be below upper {value[1]}")
    return lower, upper


def _positive(value: Any, where: str, unit: float) -> float | None:
    if value is None:
        return None
    number = table_number(value, where)
    if number <= 0:
        raise RobotDefinitionError(f"{where}: expected a positive number, got {value!r}")
    return number * unit


# ------------------------------------------------------------------ writing
def robot_to_toml(robot: Robot) -> str:
    """A robot file (TOML text, SI units) in the form the robot came in.

    A robot built from a DH table is written as that table (with its base and tool rows or
    transforms); any other robot (product of exponentials, URDF, locked joints) as
    ``convention = "poe"``: its joint lines at ``q = 0`` and the tool pose. Loading the
    text gives the same FK (to rounding) and the same joint names and limits.

    >>> import tomllib
    >>> text = robot_to_toml(load("ur5").lock({"q1": 0.0}))
    >>> robot_from_dict(tomllib.loads(text)).n, 'convention = "poe"' in text
    (5, True)
    """
    poe = None if robot.dh is not None else robot.poe or poe_from_chain(robot.chain)
    convention = robot.dh.convention if robot.dh is not None else "poe"
    lines = [f"name = {_toml_string(robot.name)}",
             *([f"description = {_toml_string(robot.description)}"] if robot.description else []),
             f'convention = "{convention}"', 'length_unit = "m"', 'angle_unit = "rad"']
    T_base_link, frame = [], np.eye(4)  # POE: each link frame in the base frame at q = 0
    for joint in robot.chain.joints:
        frame = frame @ joint.T_before @ joint.T_after
        T_base_link.append(frame)
    for i, joint in enumerate(robot.chain.joints):
        lines += ["", "[[joints]]", f"name = {_toml_string(joint.name)}", f'type = "{joint.kind}"']
        if poe is None:
            lines += _row_lines(robot.dh.rows[i])
        else:
            lines += [f"axis = {_array(poe.axes[i])}", f"point = {_array(poe.points[i])}"]
        if math.isfinite(joint.lower) and math.isfinite(joint.upper):
            lines.append(f"limits = [{joint.lower!r}, {joint.upper!r}]")
        for key in ("max_velocity", "max_acceleration", "max_torque", "radius"):
            if getattr(joint, key) is not None:
                lines.append(f"{key} = {getattr(joint, key)!r}")
        if joint.inertial is not None:
            inertial = joint.inertial if poe is None else joint.inertial.moved(T_base_link[i])
            lines += [f"mass = {inertial.mass!r}", f"com = {_array(inertial.com)}",
                      f"inertia = [{', '.join(_array(row) for row in inertial.inertia)}]"]
    if poe is None:
        for key, rows, T in (("base", robot.dh.base_rows, robot.dh.T_base),
                             ("tool", robot.dh.tool_rows, robot.dh.T_tool)):
            for row in rows:
                lines += ["", f"[[{key}]]", *_row_lines(row)]
            if T is not None:
                lines += ["", f"[{key}]", *_transform_lines(T)]
    else:
        lines += ["", "[tool]", *_transform_lines(poe.M)]
        if not np.array_equal(poe.T_base, np.eye(4)):
            lines += ["", "[base]", *_transform_lines(poe.T_base)]
    return "\n".join(lines) + "\n"


def _row_lines(row: DHRow) -> list[str]:
    return [f"{key} = {getattr(row, key)!r}" for key in ("alpha", "a", "d", "theta")]


def _toml_string(text: str) -> str:
    """A TOML basic string (JSON's escapes, plus DEL, which TOML wants escaped too)."""
    return json.dumps(text, ensure_ascii=False).replace("\x7f", "\\u007f")


def _array(values: NDArray[np.float64]) -> str:
    return "[" + ", ".join(repr(float(v)) for v in values) + "]"


def _transform_lines(T: NDArray[np.float64]) -> list[str]:
    return [f"xyz = {_array(T[:3, 3])}", f"rpy = {_array(euler_from_matrix(T[:3, :3], 'xyz-fixed'))}"]

