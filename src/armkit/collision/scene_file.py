"""Scene files: a floor, obstacles and self-collision settings for a robot, in TOML.

Format (lengths in ``length_unit``, angles in ``angle_unit``, both required as in robot files)::

    length_unit = "m"              # "m" or "mm"
    angle_unit = "deg"             # "deg" or "rad"
    floor = 0.0                    # height of the floor plane; false for no floor; default 0
    link_radius = 0.04             # optional: capsule radius, one or one per body (base first)
    geometry = "auto"              # optional: "auto", "capsules" or "urdf"
    package_paths = ["../ros_ws/src"]  # optional: folders holding package:// meshes

    [[box]]                        # any number of [[box]], [[sphere]], [[cylinder]], [[mesh]]
    name = "table"                 # optional; default box1, box2, ...
    size = [1.2, 0.8, 0.05]        # full edge lengths
    xyz = [0.6, 0, -0.025]         # centre; rpy = [roll, pitch, yaw] (fixed axes) or matrix = 4x4
    [[sphere]]
    radius = 0.1
    xyz = [0.5, 0.2, 0.4]
    [[cylinder]]
    radius = 0.05
    length = 1.0                   # full length, along the cylinder's own z axis
    xyz = [0.4, -0.4, 0.5]
    [[mesh]]
    path = "fixture.stl"           # relative to the scene file; collided as its convex hull
    scale = 0.001                  # optional: one factor or three
    xyz = [0.7, 0, 0]

    [self_collision]               # optional
    samples = 5000                 # random configurations for always/never-touching pairs; 0: none
    disabled = [["link1", "link3"]]  # never check these
    enabled = [["link2", "link5"]]   # always check these (overrides adjacency and sampling)

Every bad value raises one :class:`~armkit.errors.InputError` naming the file, the table and the key.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from armkit._tables import (
    ANGLE_UNITS,
    LENGTH_UNITS,
    check_table_keys,
    shown_value,
    table_choice,
    table_quantity,
    table_transform,
    table_vector,
    toml_table,
)
from armkit.collision.scene import DEFAULT_SAMPLES, MAX_SAMPLES, Scene
from armkit.collision.shapes import Box, Cylinder, Mesh, Obstacle, Sphere
from armkit.errors import InputError, RobotDefinitionError
from armkit.robot import Robot

__all__ = ["load_scene", "scene_from_dict"]

_TOP_KEYS = {"length_unit", "angle_unit", "floor", "link_radius", "geometry", "package_paths", "box",
             "sphere", "cylinder", "mesh", "self_collision"}
_PLACE_KEYS = {"name", "xyz", "rpy", "matrix"}
_SHAPE_KEYS = {"box": {"size"}, "sphere": {"radius"}, "cylinder": {"radius", "length"}, "mesh": {"path"}}
_OPTIONAL_KEYS = {"mesh": {"scale"}}
_SELF_KEYS = {"samples", "disabled", "enabled"}


def load_scene(path: str | Path, robot: Robot, *, package_paths: tuple[str | Path, ...] = (),
               threads: int | None = None) -> Scene:
    """The :class:`Scene` a TOML scene file describes for ``robot`` (see the module notes).

    Parameters
    ----------
    path : str or Path
    robot : Robot
    package_paths : tuple of path
        Folders for ``package://`` meshes, searched after the file's own ``package_paths``.
    threads : int, optional
        Threads for batch queries (``None``: every core).

    Raises
    ------
    InputError
        If the file cannot be read, is not TOML, or a key is unknown, missing or has a bad value.
    """
    path = Path(path)
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise InputError(f"{path}: cannot read the scene file ({exc.strerror or exc})") from exc
    data = toml_table(raw, str(path), "scene file", InputError)
    return scene_from_dict(data, robot, str(path), folder=path.parent, package_paths=package_paths,
                           threads=threads)


def scene_from_dict(data: dict[str, Any], robot: Robot, source: str = "scene", *, folder: Path | None = None,
                    package_paths: tuple[str | Path, ...] = (), threads: int | None = None) -> Scene:
    """A :class:`Scene` from the parsed contents of a scene file; relative paths start at ``folder``."""
    folder = Path.cwd() if folder is None else folder
    try:
        check_table_keys(data, _TOP_KEYS, {"length_unit", "angle_unit"}, source)
        length = LENGTH_UNITS[table_choice(data, "length_unit", LENGTH_UNITS, source, None)]
        angle = ANGLE_UNITS[table_choice(data, "angle_unit", ANGLE_UNITS, source, None)]
        floor = data.get("floor", 0.0)
        if floor is not False:
            floor = table_quantity(floor, f"{source}, key 'floor' (a height, or false for none)", length)
        radius = data.get("link_radius")
        if radius is not None:
            where = f"{source}, key 'link_radius'"
            radius = table_vector(radius, where, length, len(radius)) if isinstance(radius, list) \
                else table_quantity(radius, where, length)
        geometry = table_choice(data, "geometry", ("auto", "capsules", "urdf"), source, "auto")
        paths = _strings(data.get("package_paths", []), f"{source}, key 'package_paths'")
        obstacles = [obstacle for kind in ("box", "sphere", "cylinder", "mesh")
                     for obstacle in _obstacles(data.get(kind, []), kind, source, folder, length, angle)]
        self_collision = data.get("self_collision", {})
        where = f"{source}, [self_collision]"
        check_table_keys(self_collision, _SELF_KEYS, set(), where)
        samples = self_collision.get("samples", DEFAULT_SAMPLES)
        if isinstance(samples, bool) or not isinstance(samples, int) or not 0 <= samples <= MAX_SAMPLES:
            raise InputError(f"{where}, key 'samples': expected a whole number from 0 to {MAX_SAMPLES:,}, "
                             f"got {shown_value(samples)}")
        disabled = _pairs(self_collision.get("disabled", []), f"{where}, key 'disabled'")
        enabled = _pairs(self_collision.get("enabled", []), f"{where}, key 'enabled'")
    except RobotDefinitionError as exc:  # the robot-file helpers' errors: here a bad input file
        raise InputError(str(exc)) from exc
    try:
        return Scene(robot, obstacles, None if floor is False else floor, link_radius=radius,
                     geometry=geometry, package_paths=[*(folder / p for p in paths), *package_paths],
                     disabled_pairs=disabled, enabled_pairs=enabled, samples=samples, threads=threads,
                     relative_to=folder)
    except InputError as exc:
        raise InputError(f"{source}: {exc}") from exc


def _strings(value: Any, where: str) -> list[str]:
    if not isinstance(value, list) or not all(isinstance(v, str) and v for v in value):
        raise InputError(f"{where}: expected a list of non-empty strings, got {shown_value(value)}")
    return value


def _pairs(value: Any, where: str) -> list[tuple[str, str]]:
    if not isinstance(value, list) or not all(isinstance(pair, list) and len(pair) == 2 and
                                              all(isinstance(name, str) for name in pair) for pair in value):
        raise InputError(f"{where}: expected a list of [part, part] name pairs, got {shown_value(value)}")
    return [(a, b) for a, b in value]


def _obstacles(tables: Any, kind: str, source: str, folder: Path, length: float,
               angle: float) -> list[Obstacle]:
    if not isinstance(tables, list):
        raise InputError(f"{source}: {kind} must be [[{kind}]] tables, got {shown_value(tables)}")
    out: list[Obstacle] = []
    for i, table in enumerate(tables):
        where = f"{source}, [[{kind}]] number {i + 1}"
        try:
            out.append(_obstacle(table, kind, where, folder, length, angle))
        except InputError as exc:
            message = str(exc)
            raise InputError(message if message.startswith(where) else f"{where}: {message}") from exc
    return out


def _obstacle(table: Any, kind: str, where: str, folder: Path, length: float, angle: float) -> Obstacle:
    allowed = _PLACE_KEYS | _SHAPE_KEYS[kind] | _OPTIONAL_KEYS.get(kind, set())
    check_table_keys(table, allowed, _SHAPE_KEYS[kind], where)
    if "matrix" in table and ({"xyz", "rpy"} & set(table)):
        raise InputError(f"{where}: give either matrix or xyz and rpy, not both")
    T = table_transform({k: table[k] for k in ("xyz", "rpy", "matrix") if k in table}, where, length, angle)
    name = table.get("name")
    if name is not None and (not isinstance(name, str) or not name.strip()):
        raise InputError(f"{where}, key 'name': expected a non-empty string, got {shown_value(name)}")

    def size(key: str, what: str) -> float:
        value = table_quantity(table[key], f"{where}, key {key!r}", length)
        if not value > 0:
            raise InputError(f"{where}, key {key!r}: expected {what} > 0, got {shown_value(table[key])}")
        return value

    if kind == "box":
        edges = table_vector(table["size"], f"{where}, key 'size' (full edge lengths)", length)
        if not (edges > 0).all():
            raise InputError(f"{where}, key 'size': expected 3 edge lengths > 0, "
                             f"got {shown_value(table['size'])}")
        return Box(edges, T, name=name)
    elif kind == "sphere":
        return Sphere(size("radius", "a radius"), T[:3, 3], name=name)
    elif kind == "cylinder":
        return Cylinder(size("radius", "a radius"), size("length", "a full length"), T, name=name)
    else:
        path = table["path"]
        if not isinstance(path, str) or not path.strip():
            raise InputError(f"{where}, key 'path': expected a file name, got {shown_value(path)}")
        scale = table.get("scale", 1.0)
        scale = table_vector(scale, f"{where}, key 'scale'", 1.0) if isinstance(scale, list) \
            else table_quantity(scale, f"{where}, key 'scale'", 1.0)
        resolved = Path(path).expanduser()
        return Mesh(resolved if resolved.is_absolute() else folder / resolved, T, scale=scale, name=name)
