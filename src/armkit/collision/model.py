"""The MuJoCo model a :class:`~armkit.collision.Scene` checks: the arm's bodies, their collision
geometry, the floor and the obstacles, with the pairs that are never checked left out.

Bodies and frames come from the MJCF export (:func:`armkit.export.mjcf.mjcf_element`): body ``i`` at
joint frame ``i``, the world at the frame :meth:`armkit.Robot.fk` reports poses in. The arm's geometry
is either

* the capsules of :func:`armkit.export.physical.capsule_bodies` (the MJCF export's shapes: a housing
  sphere at each joint and capsules along the links; the radius per link from ``link_radius``), or
* a URDF's ``<collision>`` elements (:class:`armkit.urdf.UrdfGeometry`), box, cylinder, sphere and
  mesh; a mesh collides as its convex hull (MuJoCo's rule).

Every part (the base, each link, the floor, each obstacle) is a MuJoCo body of its own, so pairs can be
excluded part by part (``<exclude>``). The arm's geoms have ``contype = conaffinity = 1``; the floor's
and obstacles' ``contype = 2, conaffinity = 1``: arm against arm and arm against world collide, world
against world never does (nor does the fixed base against the world: both are welded to it).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from armkit.collision.shapes import Box, Cylinder, Mesh, Obstacle, Sphere
from armkit.errors import ArmkitError, InputError
from armkit.export.mjcf import add_capsule_geoms, mjcf_element, mjcf_numbers, mjcf_pose
from armkit.export.physical import capsule_bodies
from armkit.robot import Robot
from armkit.urdf import find_mesh_file, mesh_search_folders

__all__ = ["FLOOR", "Parts", "body_names", "build_xml", "compile_model", "part_names", "require_mujoco",
           "resolve_mesh"]

FLOOR = "floor"
_ROBOT_TYPES = {"contype": "1", "conaffinity": "1"}
_WORLD_TYPES = {"contype": "2", "conaffinity": "1"}
_OBSTACLE_COLOR = "0.55 0.55 0.6 0.6"
_MESH_SUFFIXES = {".stl", ".obj", ".msh"}


@dataclass(frozen=True)
class Parts:
    """The named parts of a scene, in MuJoCo body order after the world body.

    Attributes
    ----------
    names : tuple of str
        ``base``, the links, then ``floor`` (if any) and the obstacles.
    robot : int
        How many of them belong to the arm (the base and the links come first).
    """

    names: tuple[str, ...]
    robot: int


def part_names(robot: Robot, obstacles: Sequence[Obstacle], floor: bool) -> Parts:
    """The parts' names: the URDF's link names for a URDF robot, else ``base``, ``link1`` ...
    ``linkn``; obstacles by their ``name`` or ``box1``, ``sphere1``, ... in order of kind."""
    if robot.urdf is not None:
        arm = (robot.urdf.base, *robot.urdf.links)
    else:
        arm = ("base", *(f"link{i + 1}" for i in range(robot.n)))
    world = [FLOOR] if floor else []
    counts: dict[str, int] = {}
    for obstacle in obstacles:
        kind = type(obstacle).__name__.lower()
        counts[kind] = counts.get(kind, 0) + 1
        world.append(obstacle.name or f"{kind}{counts[kind]}")
    names = (*arm, *world)
    seen: set[str] = set()
    for name in names:
        if name in seen:
            raise InputError(f"scene: two parts are named {name!r} (link, floor and obstacle names must "
                             f"differ); give the obstacle another name")
        seen.add(name)
    return Parts(names, len(arm))


def resolve_mesh(filename: str, relative_to: Path | None, package_paths: Sequence[str | Path]) -> Path:
    """The file a mesh reference names (:func:`armkit.urdf.find_mesh_file`: ``package://`` through
    ``package_paths``, ``ROS_PACKAGE_PATH`` and ``relative_to`` and the folders above it; other
    paths relative to ``relative_to``), in a format MuJoCo reads.

    Raises
    ------
    InputError
        If no such file exists (the message lists where it looked), or MuJoCo cannot read its format.
    """
    found = find_mesh_file(filename, relative_to, package_paths)
    if found is None:
        where = ", ".join(str(p) for p in mesh_search_folders(relative_to, package_paths)) \
            if filename.startswith("package://") else str(relative_to or Path.cwd())
        remedy = " (give the folder holding the package with --package-path DIR or package_paths=[DIR])" \
            if filename.startswith("package://") else ""
        raise InputError(f"mesh {filename!r}: file not found (looked in {where}){remedy}")
    if found.suffix.lower() not in _MESH_SUFFIXES:
        raise InputError(f"mesh {found}: MuJoCo reads STL, OBJ and MSH meshes, not {found.suffix!r}; "
                         f"convert it (or give the link primitive <collision> shapes)")
    return found.resolve()


def _geom(parent: ET.Element, kind: str, size: Sequence[float], T: NDArray[np.float64], types: dict,
          **extra: str) -> None:
    ET.SubElement(parent, "geom", type=kind, size=mjcf_numbers(np.asarray(size, dtype=float)), **mjcf_pose(T),
                  **types, **extra)


#: Name prefix of the mesh geoms that stand for boxes (see _add_box).
BOX_MESH = "armkit_box"


def _add_box(root: ET.Element, body: ET.Element, size: Sequence[float], T: NDArray[np.float64],
             types: dict) -> None:
    """A box of full edge lengths ``size`` [m], as the convex mesh of its eight corners: MuJoCo's own
    capsule-box test misses a capsule that crosses a thin box with both ends outside it (MuJoCo 3.x and
    4.0.1: no contact, a positive distance; tests/test_collision.py), its convex-mesh test does not."""
    assets = _assets(root)
    name = f"{BOX_MESH}{len(assets)}"
    half = np.asarray(size, dtype=float) / 2
    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]) * half
    ET.SubElement(assets, "mesh", name=name, vertex=mjcf_numbers(corners.ravel()))
    ET.SubElement(body, "geom", name=name, type="mesh", mesh=name, **mjcf_pose(T), **types)


def _assets(root: ET.Element) -> ET.Element:
    assets = root.find("asset")
    if assets is None:
        assets = ET.Element("asset")
        root.insert(list(root).index(root.find("worldbody")), assets)
    return assets


def _add_mesh(root: ET.Element, body: ET.Element, path: Path, scale: Sequence[float],
              T: NDArray[np.float64], types: dict) -> None:
    assets = _assets(root)
    name = f"mesh{len(assets)}"
    ET.SubElement(assets, "mesh", name=name, file=str(path),
                  scale=mjcf_numbers(np.asarray(scale, dtype=float)))
    ET.SubElement(body, "geom", type="mesh", mesh=name, **mjcf_pose(T), **types)


def _add_obstacle(root: ET.Element, body: ET.Element, obstacle: Obstacle, relative_to: Path | None) -> None:
    types = {**_WORLD_TYPES, "rgba": _OBSTACLE_COLOR}
    if isinstance(obstacle, Box):
        _add_box(root, body, obstacle.size, np.eye(4), types)
    elif isinstance(obstacle, Sphere):
        _geom(body, "sphere", [obstacle.radius], np.eye(4), types)
    elif isinstance(obstacle, Cylinder):
        _geom(body, "cylinder", [obstacle.radius, obstacle.length / 2], np.eye(4), types)
    elif isinstance(obstacle, Mesh):
        path = resolve_mesh(str(obstacle.path), relative_to, ())
        _add_mesh(root, body, path, obstacle.scale, np.eye(4), types)
    else:
        raise InputError(f"obstacle: expected armkit.Box, Sphere, Cylinder or Mesh, got {obstacle!r}")


def _link_radii(robot: Robot, link_radius: float | Sequence[float] | None,
                default: float) -> NDArray[np.float64]:
    """Capsule radius per body (the base first) [m]: ``link_radius``, else the joints' ``radius`` (a
    robot file's key) where set, else ``default``."""
    if link_radius is None:
        joints = [default if joint.radius is None else joint.radius for joint in robot.chain.joints]
        return np.array([default, *joints])
    radii = np.asarray(link_radius, dtype=float)
    if radii.ndim == 0:
        radii = np.full(robot.n + 1, float(radii))
    if radii.shape != (robot.n + 1,) or not (np.isfinite(radii) & (radii > 0)).all():
        raise InputError(f"link_radius: expected one radius > 0 m, or {robot.n + 1} (the base, then each of "
                         f"the {robot.n} links), got {link_radius!r}")
    return radii


def build_xml(robot: Robot, parts: Parts, obstacles: Sequence[Obstacle], floor: float | None, *,
              link_radius: float | Sequence[float] | None = None, package_paths: Sequence[str | Path] = (),
              relative_to: Path | None = None, geometry: str = "auto") -> ET.Element:
    """The MJCF of the scene without exclusions (see the module notes).

    ``geometry``: ``"capsules"``, ``"urdf"`` (the URDF's ``<collision>`` elements) or ``"auto"`` (the
    URDF's when it has any, else capsules). ``relative_to``: the folder obstacle meshes are relative to.
    """
    root = mjcf_element(robot, gravity=False)
    for tag in ("actuator", "default"):
        for element in root.findall(tag):
            root.remove(element)
    world = root.find("worldbody")
    bodies = [world, *(world.iter("body"))]  # world, link1 ... linkn, tool
    for body in bodies:
        for geom in body.findall("geom"):
            body.remove(geom)
    base = ET.Element("body", name="armkit_base")
    world.insert(0, base)
    urdf = robot.urdf.collisions if robot.urdf is not None else ()
    if geometry not in ("auto", "capsules", "urdf"):
        raise InputError(f"geometry: expected 'auto', 'capsules' or 'urdf', got {geometry!r}")
    if geometry == "urdf" and not urdf:
        raise InputError(f"geometry 'urdf': {robot.name} has no URDF <collision> elements; use 'capsules'")
    targets = [base, *bodies[1:robot.n + 1]]
    if urdf and geometry != "capsules":
        folder = Path(robot.urdf.path).parent
        T_body_link = [robot.chain.T_base, *(joint.T_after for joint in robot.chain.joints)]
        for item in urdf:
            T = T_body_link[item.frame] @ item.T_frame_geom
            body = targets[item.frame]
            if item.kind == "mesh":
                _add_mesh(root, body, resolve_mesh(item.filename, folder, package_paths), item.size, T,
                          _ROBOT_TYPES)
            elif item.kind == "box":
                _add_box(root, body, item.size, T, _ROBOT_TYPES)
            elif item.kind == "cylinder":
                _geom(body, "cylinder", [item.size[0], item.size[1] / 2], T, _ROBOT_TYPES)
            else:
                _geom(body, "sphere", item.size, T, _ROBOT_TYPES)
    else:
        default, base_shape, shapes = capsule_bodies(robot)
        radii = _link_radii(robot, link_radius, default)
        for i, (body, shape) in enumerate(zip(targets, (base_shape, *shapes), strict=True)):
            add_capsule_geoms(body, shape, float(radii[i]), "0.85 0.45 0.12 1", housing=i > 0)
    for geom in root.iter("geom"):
        if geom.get("contype") is None:
            geom.attrib.update(_ROBOT_TYPES)
    if floor is not None:
        floor_body = ET.SubElement(world, "body", name="armkit_floor",
                                   pos=mjcf_numbers(np.array([0, 0, floor])))
        _geom(floor_body, "plane", [0, 0, 1], np.eye(4), _WORLD_TYPES, rgba="0.8 0.8 0.8 1")
    for k, obstacle in enumerate(obstacles):
        body = ET.SubElement(world, "body", name=f"armkit_obstacle{k}",
                             **mjcf_pose(np.asarray(obstacle.pose)))
        _add_obstacle(root, body, obstacle, relative_to)
    return root


def body_names(robot: Robot, floor: bool, obstacles: int) -> list[str]:
    """The MuJoCo body name of each part, in :func:`part_names` order."""
    return ["armkit_base", *(f"link{i + 1}" for i in range(robot.n)), *(["armkit_floor"] if floor else []),
            *(f"armkit_obstacle{k}" for k in range(obstacles))]


def require_mujoco():  # -> the mujoco module
    """The ``mujoco`` module, or one :class:`~armkit.errors.ArmkitError` naming the extra to install."""
    try:
        import mujoco
    except ImportError as exc:
        raise ArmkitError("collision checking needs MuJoCo: pip install 'armkit[collision]' "
                          "(or pip install mujoco)") from exc
    return mujoco


def compile_model(root: ET.Element, excluded: Sequence[tuple[str, str]]):  # -> mujoco.MjModel
    """The compiled model of ``root`` with the body pairs ``excluded`` (MuJoCo body names) never checked.

    Raises
    ------
    InputError
        If MuJoCo refuses the model (a mesh it cannot read, say), with MuJoCo's message.
    """
    mujoco = require_mujoco()
    root = ET.fromstring(ET.tostring(root))  # a copy: the caller's element is reused
    # parent and child bodies are checked too unless excluded (adjacent links are, by name): an
    # enabled adjacent pair then collides exactly when its distance is negative, as clearance says
    option = root.find("option")
    option = ET.SubElement(root, "option") if option is None else option
    ET.SubElement(option, "flag", filterparent="disable")
    if excluded:
        contact = ET.SubElement(root, "contact")
        for a, b in excluded:
            ET.SubElement(contact, "exclude", body1=a, body2=b)
    try:
        return mujoco.MjModel.from_xml_string(ET.tostring(root, encoding="unicode"))
    except ValueError as exc:
        raise InputError(f"scene: MuJoCo cannot build the collision model: {exc}") from exc
