"""Robot files: a hand-written TOML description of a DH arm, and the built-in robots.

Format (every length in ``length_unit``, every angle in ``angle_unit``)::

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

``[[base]]`` rows work like ``[[tool]]`` rows, before the first joint. For a prismatic
joint the joint variable is added to ``d``. In a file ``convention``, ``length_unit`` and
``angle_unit`` are required: a table written in degrees must never be read as radians.
Values are converted to SI units once, here.
"""

from __future__ import annotations

import math
import tomllib
from importlib import resources
from pathlib import Path
from typing import Any

from armkit.chain import DHRow
from armkit.errors import RobotDefinitionError
from armkit.robot import Robot

__all__ = ["builtin_robots", "load", "robot_from_dict", "robot_to_toml"]

_LENGTH_UNITS = {"m": 1.0, "mm": 1e-3}
_ANGLE_UNITS = {"rad": 1.0, "deg": math.pi / 180.0}
_TOP_KEYS = {"name", "convention", "length_unit", "angle_unit", "description", "joints",
             "tool", "base"}
_ROW_KEYS = {"alpha", "a", "d", "theta"}
_JOINT_KEYS = _ROW_KEYS | {"type", "limits", "max_velocity", "max_acceleration", "name"}


def builtin_robots() -> list[str]:
    """Names of the robots shipped with armkit, sorted."""
    folder = resources.files("armkit") / "robots"
    return sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".toml"))


def load(name_or_path: str | Path) -> Robot:
    """Load a built-in robot by name (``"probot-anno"``) or a robot file by path.

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
        resource = resources.files("armkit") / "robots" / f"{text}.toml"
        return _load_text(resource.read_text(encoding="utf-8"), f"built-in robot {text!r}")
    path = Path(text)
    if not path.is_file():
        raise RobotDefinitionError(
            f"unknown robot {text!r}: not a built-in ({', '.join(builtin_robots())}) "
            f"and no such file")
    return _load_text(path.read_text(encoding="utf-8"), str(path))


def _load_text(text: str, source: str) -> Robot:
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise RobotDefinitionError(f"{source}: not valid TOML: {exc}") from exc
    return robot_from_dict(data, source, require_units=True)


def _number(value: Any, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise RobotDefinitionError(f"{where}: expected a finite number, got {value!r}")
    return float(value)


def _choice(data: dict, key: str, options: dict | tuple, source: str, default: str | None) -> str:
    value = data.get(key, default)
    if value is None:
        raise RobotDefinitionError(f"{source}: missing key {key!r} (one of {', '.join(options)})")
    if value not in options:
        raise RobotDefinitionError(
            f"{source}: {key} = {value!r}; expected one of {', '.join(map(repr, options))}")
    return value


def _check_keys(table: dict, allowed: set[str], required: set[str], where: str) -> None:
    if not isinstance(table, dict):
        raise RobotDefinitionError(f"{where}: expected a table, got {table!r}")
    unknown = sorted(set(table) - allowed)
    if unknown:
        raise RobotDefinitionError(f"{where}: unknown key {unknown[0]!r}; expected keys: "
                                   f"{', '.join(sorted(allowed))}")
    missing = sorted(required - set(table))
    if missing:
        raise RobotDefinitionError(f"{where}: missing key {missing[0]!r}")


def _row(table: dict, where: str, joint: str | None, length: float, angle: float) -> DHRow:
    return DHRow(alpha=_number(table["alpha"], f"{where}, key 'alpha'") * angle,
                 a=_number(table["a"], f"{where}, key 'a'") * length,
                 d=_number(table["d"], f"{where}, key 'd'") * length,
                 theta=_number(table["theta"], f"{where}, key 'theta'") * angle,
                 joint=joint)


def _fixed_rows(data: dict, key: str, source: str, length: float, angle: float) -> list[DHRow]:
    rows = data.get(key, [])
    if not isinstance(rows, list):
        raise RobotDefinitionError(f"{source}: {key} must be an array of tables ([[{key}]])")
    out = []
    for i, table in enumerate(rows):
        where = f"{source}, {key} row {i + 1}"
        _check_keys(table, _ROW_KEYS, _ROW_KEYS, where)
        out.append(_row(table, where, None, length, angle))
    return out


def robot_from_dict(data: dict, source: str = "robot description", require_units: bool = False) -> Robot:
    """Build a :class:`Robot` from the parsed contents of a robot file (see module docstring).

    In code the units default to SI (``"m"``, ``"rad"``) like the rest of the Python API;
    ``require_units=True`` (how files are read) makes ``length_unit`` and ``angle_unit``
    required keys.
    """
    required = {"convention", "joints"} | ({"length_unit", "angle_unit"} if require_units else set())
    _check_keys(data, _TOP_KEYS, required, source)
    convention = _choice(data, "convention", ("standard", "modified"), source, None)
    length_unit = _choice(data, "length_unit", _LENGTH_UNITS, source, "m")
    angle_unit = _choice(data, "angle_unit", _ANGLE_UNITS, source, "rad")
    length, angle = _LENGTH_UNITS[length_unit], _ANGLE_UNITS[angle_unit]
    joints = data["joints"]
    if not isinstance(joints, list) or not joints:
        raise RobotDefinitionError(f"{source}: 'joints' must be a non-empty array of tables "
                                   f"([[joints]]), got {joints!r}")
    rows, limits, vmax, amax, names = [], [], [], [], []
    for i, table in enumerate(joints):
        where = f"{source}, joint {i + 1}"
        _check_keys(table, _JOINT_KEYS, _ROW_KEYS, where)
        kind = _choice(table, "type", ("revolute", "prismatic"), where, "revolute")
        unit = angle if kind == "revolute" else length
        rows.append(_row(table, where, kind, length, angle))
        limits.append(_limits(table.get("limits"), f"{where}, key 'limits'", unit))
        vmax.append(_positive(table.get("max_velocity"), f"{where}, key 'max_velocity'", unit))
        amax.append(_positive(table.get("max_acceleration"), f"{where}, key 'max_acceleration'",
                              unit))
        names.append(str(table.get("name", f"q{i + 1}")))
    robot = Robot.from_dh(rows, convention, name=str(data.get("name", Path(source).stem)),
                          limits=limits, max_velocity=vmax, max_acceleration=amax,
                          base_rows=_fixed_rows(data, "base", source, length, angle),
                          tool_rows=_fixed_rows(data, "tool", source, length, angle),
                          length_unit=length_unit, angle_unit=angle_unit, names=names)
    robot.source = source
    robot.description = str(data.get("description", ""))
    return robot


def _limits(value: Any, where: str, unit: float) -> tuple[float, float] | None:
    if value is None:
        return None
    if not isinstance(value, list) or len(value) != 2:
        raise RobotDefinitionError(f"{where}: expected [lower, upper], got {value!r}")
    lower, upper = (_number(v, where) * unit for v in value)
    if not lower < upper:
        raise RobotDefinitionError(f"{where}: lower {value[0]} must be below upper {value[1]}")
    return lower, upper


def _positive(value: Any, where: str, unit: float) -> float | None:
    if value is None:
        return None
    number = _number(value, where)
    if number <= 0:
        raise RobotDefinitionError(f"{where}: expected a positive number, got {value!r}")
    return number * unit


def robot_to_toml(robot: Robot) -> str:
    """A robot file (TOML text, SI units) for a robot built from a DH table."""
    if robot.dh is None:
        raise RobotDefinitionError(f"{robot.name}: has no DH table to write")
    lines = [f"name = {robot.name!r}".replace("'", '"'), f'convention = "{robot.dh.convention}"',
             'length_unit = "m"', 'angle_unit = "rad"']
    for row, joint in zip(robot.dh.rows, robot.chain.joints, strict=True):
        lines += ["", "[[joints]]", f'name = "{joint.name}"', f'type = "{joint.kind}"',
                  *_row_lines(row)]
        if math.isfinite(joint.lower) and math.isfinite(joint.upper):
            lines.append(f"limits = [{joint.lower!r}, {joint.upper!r}]")
        for key in ("max_velocity", "max_acceleration"):
            if getattr(joint, key) is not None:
                lines.append(f"{key} = {getattr(joint, key)!r}")
    for key, rows in (("base", robot.dh.base_rows), ("tool", robot.dh.tool_rows)):
        for row in rows:
            lines += ["", f"[[{key}]]", *_row_lines(row)]
    return "\n".join(lines) + "\n"


def _row_lines(row: DHRow) -> list[str]:
    return [f"{key} = {getattr(row, key)!r}" for key in ("alpha", "a", "d", "theta")]
