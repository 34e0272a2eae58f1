"""URDF import: the serial chain between two links of a URDF file, mapped exactly onto the chain.

A URDF joint moves its child link by ``O · M_a(q)``: the fixed ``<origin>`` ``O``, then a
rotation about (or a translation along) its ``<axis>`` ``a``. With ``R`` a rotation taking
z onto ``a`` (:func:`armkit.poe.rotation_z_to`), ``M_a(q) = R · M_z(q) · R^T``, so the
joint fills the chain (:mod:`armkit.chain`) as ``T_before = F · O · R`` and
``T_after = R^T``, ``F`` being the fixed joints met since the previous moving joint. Link
frame ``i`` of the chain is then the URDF frame of joint ``i``'s child link, and the fixed
joints after the last moving one become the tool transform.

What is read
    ``revolute``, ``continuous`` (limits ``[-inf, inf]``: IK wraps it to the whole turn
    nearest the seed, ``random_q`` draws it from ``[-pi, pi]``), ``prismatic`` and
    ``fixed`` joints on the path from ``base`` (default: the root link) to ``tip``
    (default: the only leaf below ``base``); ``<limit>`` ``lower``/``upper``/``velocity``
    (a velocity of 0, written by some files for "none", is no limit; so is a position limit
    beyond :data:`armkit.chain.MAX_VALUE`, such as Gazebo's ``1e16``) and ``effort`` (kept
    in :class:`UrdfDescription` and as the joint's ``max_torque``; 0 is no limit); the
    ``<visual>`` meshes of every link that moves with the chain (file name as written:
    ``package://`` or relative, origin and scale); every ``<inertial>`` (mass, origin,
    inertia) of the links that move with a chain link, merged into that link as pinocchio's
    reduced model does: links fixed to it, and side branches and links beyond the tip held
    at zero (a hand and its fingers), in its link frame. Links fixed to the base carry no
    load and are left out; a file without any ``<inertial>`` on the moving links gives a
    robot without inertia (:mod:`armkit.dynamics` then asks for it); the ``<collision>``
    geometry (box, cylinder, sphere, mesh) of the same links, placed like the visual meshes,
    for :mod:`armkit.collision`, and their ``<visual>`` boxes, cylinders and spheres for the
    viewer. Everything else (transmissions, ``<gazebo>``) is ignored.
Refused, with one :class:`~armkit.errors.RobotDefinitionError` naming the joint or line
    Malformed XML, a document type declaration (``<!DOCTYPE``/``<!ENTITY``: entities can
    expand without bound, so no DTD is accepted at all; the standard library's parser then
    has nothing to expand), a root other than ``<robot>``, missing or repeated link and joint
    names, links with two parents or no single root, ``mimic``/``floating``/``planar``
    joints on the chosen path, a revolute or prismatic joint without ``<limit>``, a zero
    axis, numbers that are not plain decimals as the spec writes them (``1_0``, ``inf``,
    ``nan`` and non-ASCII digits are refused) or not finite, origins beyond
    :data:`armkit.chain.MAX_VALUE`. A UTF-8 byte order mark is skipped.
Read with the spec's defaults, explicitly
    A ``<limit>`` without ``lower`` or ``upper`` takes 0 for the missing one, as the URDF spec
    and urdfdom do; one with neither holds a revolute or prismatic joint at ``[0, 0]`` and is
    loaded so (real files write it: example-robot-data's Centauro wheels, the quadruped's
    knees) with a ``UserWarning`` naming the joint, since it is rarely what was meant.
"""

from __future__ import annotations

import os
import re
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from armkit.chain import MAX_VALUE, chain_from_frames
from armkit.errors import RobotDefinitionError, warn_at_caller
from armkit.inertial import Inertial
from armkit.poe import rotation_z_to, unit_axis
from armkit.robot import Robot
from armkit.spatial.rotations import matrix_from_euler
from armkit.spatial.transforms import transform_from

__all__ = ["UrdfDescription", "UrdfGeometry", "UrdfMesh", "find_mesh_file", "load_urdf",
           "mesh_search_folders", "robot_from_urdf"]

_MOVING = {"revolute", "continuous", "prismatic"}
_UNSUPPORTED = {"floating", "planar"}


@dataclass(frozen=True)
class UrdfMesh:
    """A ``<visual>`` mesh of a link that moves with the chain.

    Attributes
    ----------
    link : str
    filename : str
        As written in the file (``package://...`` or a relative path); not opened by armkit.
    frame : int
        The chain frame the mesh is fixed in: 0 the base frame, ``i`` link frame ``i``
        (after joint ``i``), as :meth:`armkit.Robot.link_frames` numbers them.
    T_frame_mesh : ndarray (4, 4)
        The mesh's pose in that frame [m].
    scale : tuple of 3 floats
    """

    link: str
    filename: str
    frame: int
    T_frame_mesh: NDArray[np.float64]
    scale: tuple[float, float, float]


@dataclass(frozen=True)
class UrdfGeometry:
    """A ``<collision>`` geometry, or a ``<visual>`` box, cylinder or sphere, of a link that moves
    with the chain (or is fixed to the base).

    Attributes
    ----------
    link : str
    kind : str
        ``"box"``, ``"cylinder"``, ``"sphere"`` or ``"mesh"``.
    size : tuple of float
        Box: full edge lengths ``(x, y, z)``; cylinder: ``(radius, length)``; sphere:
        ``(radius,)``; mesh: the ``scale`` ``(sx, sy, sz)``. Metres.
    filename : str or None
        A mesh's file as written (``package://...``, relative to the URDF, or absolute).
    frame : int
        The chain frame it is fixed in (0 the base frame, ``i`` link frame ``i``).
    T_frame_geom : ndarray (4, 4)
        Its pose in that frame [m].
    """

    link: str
    kind: str
    size: tuple[float, ...]
    filename: str | None
    frame: int
    T_frame_geom: NDArray[np.float64]


@dataclass(frozen=True)
class UrdfDescription:
    """Where a robot loaded from URDF came from.

    Attributes
    ----------
    path : str
        The file (or ``"URDF text"``).
    robot_name : str
        The ``<robot name>``.
    base, tip : str
        The links the chain runs between.
    links : tuple of str
        Per joint, its child link: the URDF link at each chain link frame.
    effort : tuple of float or None
        Per joint, the ``<limit effort>`` [N m or N].
    meshes : tuple of UrdfMesh
    collisions : tuple of UrdfGeometry
        The ``<collision>`` geometry (box, cylinder, sphere, mesh).
    shapes : tuple of UrdfGeometry
        The ``<visual>`` boxes, cylinders and spheres (the visual meshes are in ``meshes``).
    """

    path: str
    robot_name: str
    base: str
    tip: str
    links: tuple[str, ...]
    effort: tuple[float | None, ...]
    meshes: tuple[UrdfMesh, ...]
    collisions: tuple[UrdfGeometry, ...] = ()
    shapes: tuple[UrdfGeometry, ...] = ()


@dataclass(frozen=True)
class _UrdfJoint:
    name: str
    kind: str
    parent: str
    child: str
    element: ET.Element


def load_urdf(path: str | Path, base: str | None = None, tip: str | None = None) -> Robot:
    """Load the serial chain from ``base`` to ``tip`` of a URDF file (see the module notes).

    Parameters
    ----------
    path : str or Path
    base : str, optional
        Link whose frame is the robot's base frame; default the URDF's root link.
    tip : str, optional
        Link whose frame is the tool frame; default the only leaf link below ``base``.

    Raises
    ------
    RobotDefinitionError
        If the file cannot be read or is not a URDF armkit can use (the message names the
        file and the joint, link or line).
    """
    path = Path(path)
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise RobotDefinitionError(f"{path}: cannot be read ({exc.strerror or exc})") from exc
    return robot_from_urdf(data, str(path), base=base, tip=tip)


def robot_from_urdf(text: str | bytes, source: str = "URDF text", *, base: str | None = None,
                    tip: str | None = None) -> Robot:
    """A :class:`~armkit.Robot` from URDF text (see :func:`load_urdf`).

    Examples
    --------
    >>> text = '''<robot name="r">
    ...   <link name="a"/><link name="b"/><link name="c"/>
    ...   <joint name="j1" type="continuous"><parent link="a"/><child link="b"/>
    ...     <axis xyz="0 1 0"/></joint>
    ...   <joint name="flange" type="fixed"><parent link="b"/><child link="c"/>
    ...     <origin xyz="0 0 0.5"/></joint>
    ... </robot>'''
    >>> robot = robot_from_urdf(text)
    >>> robot.joint_names, robot.limits.tolist()
    (['j1'], [[-inf, inf]])
    >>> robot.fk([np.pi / 2])[:3, 3].round(12) + 0.0
    array([0.5, 0. , 0. ])
    """
    root = _parse(text, source)
    links, joints = _tree(root, source)
    base = _root_link(links, joints, source) if base is None else _known_link(base, links, "base", source)
    tip = _only_leaf(base, links, joints, source) if tip is None else _known_link(tip, links, "tip", source)
    path = _path(base, tip, joints, source)
    kinds, before, after, limits, velocity, effort, names, frames = [], [], [], [], [], [], [], []
    pending = np.eye(4)
    for joint in path:
        where = f"{source}, joint {joint.name!r}"
        origin = _origin(joint.element, where)
        if joint.kind == "fixed":
            pending = pending @ origin
            continue
        if joint.kind in _UNSUPPORTED:
            raise RobotDefinitionError(f"{where}: type {joint.kind!r} is not a joint of a serial arm; "
                                       f"armkit reads revolute, continuous, prismatic and fixed joints")
        if joint.element.find("mimic") is not None:
            raise RobotDefinitionError(f"{where}: a mimic joint (it follows another joint) on the path "
                                       f"from {base!r} to {tip!r}; armkit's joints are independent")
        axis_element = joint.element.find("axis")
        axis = (np.array([1.0, 0.0, 0.0]) if axis_element is None  # the URDF default
                else _floats(axis_element, "xyz", 3, where, default=None))
        R = transform_from(rotation_z_to(unit_axis(axis, where)), np.zeros(3))
        kinds.append("prismatic" if joint.kind == "prismatic" else "revolute")
        before.append(pending @ origin @ R)
        after.append(R.T)
        lower_upper, vmax, force = _limit(joint, where)
        limits.append(lower_upper)
        velocity.append(vmax)
        effort.append(force)
        names.append(joint.name)
        frames.append(joint.child)
        pending = np.eye(4)
    if not kinds:
        raise RobotDefinitionError(f"{source}: no moving joint between links {base!r} and {tip!r}")
    chain = chain_from_frames(kinds, before, after, limits=limits, max_velocity=velocity,
                              T_tool=pending, names=names,
                              max_torque=[force if force and force > 0 else None for force in effort],
                              inertials=_inertials(base, path, joints, links, source))
    name = root.get("name") or Path(source).stem
    placed = _placed_links(base, path, joints, source)
    description = UrdfDescription(source, name, base, tip, tuple(frames), tuple(effort),
                                  _meshes(placed, links, source),
                                  _geometries(placed, links, "collision", source),
                                  _geometries(placed, links, "visual", source))
    return Robot(chain, name=name, source=source, urdf=description,
                 description=f"URDF {Path(source).name}, {base} to {tip}")


# ------------------------------------------------------------------ XML and the link tree
def _parse(text: str | bytes, source: str) -> ET.Element:
    if isinstance(text, bytes):
        try:
            text = text.decode("utf-8-sig")
        except UnicodeDecodeError as exc:
            raise RobotDefinitionError(f"{source}: not UTF-8 text (byte {exc.start}); save the URDF "
                                       f"as UTF-8") from exc
    text = text.removeprefix("\ufeff")  # a byte order mark, as utf-8-sig skips it in bytes
    for declaration in ("<!DOCTYPE", "<!ENTITY"):
        if declaration in text:
            line = text[:text.index(declaration)].count("\n") + 1
            raise RobotDefinitionError(f"{source}, line {line}: {declaration} declarations are refused "
                                       f"(entities can expand without bound); remove the DTD")
    try:
        root = ET.fromstring(text)
    except ET.ParseError as exc:
        raise RobotDefinitionError(f"{source}: not valid XML: {exc}") from exc
    if root.tag != "robot":
        raise RobotDefinitionError(f"{source}: the root element is <{root.tag}>; a URDF file has <robot> "
                                   f"(armkit.load reads an MJCF file, root <mujoco>, too)")
    return root


def _name(element: ET.Element, what: str, source: str, index: int) -> str:
    name = element.get("name")
    if not name or not name.strip():
        raise RobotDefinitionError(f"{source}: {what} number {index + 1} has no name")
    return name


def _tree(root: ET.Element, source: str) -> tuple[dict[str, ET.Element], dict[str, _UrdfJoint]]:
    """Links by name, and the joints by their child link; checked to form one tree."""
    links: dict[str, ET.Element] = {}
    for i, element in enumerate(root.findall("link")):
        name = _name(element, "<link>", source, i)
        if name in links:
            raise RobotDefinitionError(f"{source}: two links are named {name!r}")
        links[name] = element
    if not links:
        raise RobotDefinitionError(f"{source}: no <link> elements; nothing to load")
    by_child: dict[str, _UrdfJoint] = {}
    names: set[str] = set()
    for i, element in enumerate(root.findall("joint")):
        name = _name(element, "<joint>", source, i)
        where = f"{source}, joint {name!r}"
        if name in names:
            raise RobotDefinitionError(f"{source}: two joints are named {name!r}")
        names.add(name)
        kind = element.get("type")
        if kind not in _MOVING | _UNSUPPORTED | {"fixed"}:
            raise RobotDefinitionError(f"{where}: type {kind!r}; expected one of revolute, continuous, "
                                       f"prismatic, fixed (floating, planar)")
        parent, child = (_link_reference(element, tag, links, where) for tag in ("parent", "child"))
        if child in by_child:
            raise RobotDefinitionError(f"{where}: link {child!r} already has parent joint "
                                       f"{by_child[child].name!r}; a URDF is a tree")
        by_child[child] = _UrdfJoint(name, kind, parent, child, element)
    _refuse_cycles(links, by_child, source)
    return links, by_child


def _refuse_cycles(links: dict, joints: dict[str, _UrdfJoint], source: str) -> None:
    """Every link must lead up to a root (with one parent each, else the parents loop)."""
    rooted: set[str] = set()
    for start in links:
        walk: dict[str, None] = {}  # the links met, in order; a dict so membership is O(1) at any depth
        link = start
        while link in joints and link not in rooted:
            if link in walk:
                met = list(walk)
                loop = met[met.index(link):]
                raise RobotDefinitionError(f"{source}: links {', '.join(sorted(loop))} form a cycle; "
                                           f"a URDF is a tree")
            walk[link] = None
            link = joints[link].parent
        rooted.update(walk)


def _link_reference(element: ET.Element, tag: str, links: dict, where: str) -> str:
    ref = element.find(tag)
    link = None if ref is None else ref.get("link")
    if link is None:
        raise RobotDefinitionError(f"{where}: missing <{tag} link=\"...\"/>")
    if link not in links:
        raise RobotDefinitionError(f"{where}: {tag} link {link!r} is not a <link> of the file")
    return link


def _root_link(links: dict, joints: dict[str, _UrdfJoint], source: str) -> str:
    roots = [name for name in links if name not in joints]
    if len(roots) != 1:
        raise RobotDefinitionError(f"{source}: {len(roots)} root links ({', '.join(roots) or 'a cycle'}); "
                                   f"a URDF is a tree with one root")
    return roots[0]


def _known_link(name: str, links: dict, what: str, source: str) -> str:
    if name not in links:
        shown = ", ".join(list(links)[:20]) + (", ..." if len(links) > 20 else "")
        raise RobotDefinitionError(f"{source}: {what} link {name!r} is not in the file; its links: {shown}")
    return name


def _path(base: str, tip: str, joints: dict[str, _UrdfJoint], source: str) -> list[_UrdfJoint]:
    """The joints from ``base`` down to ``tip``, in order."""
    path, link = [], tip
    while link != base:
        joint = joints.get(link)
        if joint is None or len(path) > len(joints):
            raise RobotDefinitionError(f"{source}: tip link {tip!r} is not below base link {base!r}")
        path.append(joint)
        link = joint.parent
    return path[::-1]


def _only_leaf(base: str, links: dict, joints: dict[str, _UrdfJoint], source: str) -> str:
    parents = {joint.parent for joint in joints.values()}
    leaves = []
    for link in links:
        if link in parents:
            continue
        try:
            moving = sum(j.kind != "fixed" for j in _path(base, link, joints, source))
        except RobotDefinitionError:  # a leaf of another branch, not below base
            continue
        leaves.append((link, moving))
    if len(leaves) == 1:
        return leaves[0][0]
    leaves.sort(key=lambda leaf: -leaf[1])  # the arms' ends first
    listed = ", ".join(f"{link} ({moving} moving joint{'s' * (moving != 1)})" for link, moving in leaves[:8])
    more = f" and {len(leaves) - 8} more" if len(leaves) > 8 else ""
    raise RobotDefinitionError(f"{source}: {len(leaves)} leaf links below {base!r}: {listed}{more}; choose "
                               f"one as the tip (tip=... in Python, --tip LINK on the command line)")


# ------------------------------------------------------------------ numbers and elements
#: A number as the URDF spec writes one: a plain decimal float in ASCII digits (Python's
#: ``float`` also reads ``1_0``, ``inf``, ``nan`` and other scripts' digits; URDF has none of them).
_DECIMAL = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")


def _floats(element: ET.Element, key: str, count: int, where: str,
            default: list[float] | None, bound: float = MAX_VALUE) -> NDArray[np.float64]:
    text = element.get(key)
    if text is None:
        if default is None:
            raise RobotDefinitionError(f"{where}: <{element.tag}> has no {key}=\"...\"")
        return np.array(default, dtype=float)
    words = text.split()
    values = np.array([float(word) for word in words] if all(map(_DECIMAL.fullmatch, words)) else [])
    if values.shape != (count,) or not np.isfinite(values).all() or np.abs(values).max() > bound:
        limit = "" if bound == np.inf else f" of magnitude at most {bound:g}"
        raise RobotDefinitionError(f"{where}: <{element.tag} {key}=\"{text}\">: expected {count} finite "
                                   f"number{'s' * (count != 1)}{limit}")
    return values


def _origin(element: ET.Element, where: str) -> NDArray[np.float64]:
    origin = element.find("origin")
    if origin is None:
        return np.eye(4)
    xyz = _floats(origin, "xyz", 3, where, default=[0.0, 0.0, 0.0])
    rpy = _floats(origin, "rpy", 3, where, default=[0.0, 0.0, 0.0])
    return transform_from(matrix_from_euler(rpy, "xyz-fixed"), xyz)  # URDF rpy: Rz(y) Ry(p) Rx(r)


def _limit(joint: _UrdfJoint, where: str) -> tuple[tuple[float, float], float | None, float | None]:
    """``((lower, upper), velocity or None, effort or None)`` of a moving joint."""
    element = joint.element.find("limit")
    if element is None:
        if joint.kind == "continuous":
            return (-np.inf, np.inf), None, None
        raise RobotDefinitionError(f"{where}: a {joint.kind} joint needs <limit lower=... upper=... "
                                   f"velocity=... effort=...> (or type continuous, unbounded)")
    if joint.kind != "continuous" and "lower" not in element.attrib and "upper" not in element.attrib:
        warn_at_caller(UserWarning(f"{where}: <limit> has neither lower nor upper, so the URDF spec's "
                                   f"defaults hold the {joint.kind} joint at [0, 0] (as urdfdom and "
                                   f"pinocchio read it); write both, or type continuous for no limits"))
    lower, upper, velocity, effort = (
        float(_floats(element, key, 1, where, default=[0.0], bound=np.inf)[0])
        for key in ("lower", "upper", "velocity", "effort"))
    if joint.kind == "continuous":
        lower, upper = -np.inf, np.inf
    lower, upper = (-np.inf if lower < -MAX_VALUE else lower), (np.inf if upper > MAX_VALUE else upper)
    if lower > upper:
        raise RobotDefinitionError(f"{where}: <limit lower=\"{lower}\" upper=\"{upper}\">: lower is "
                                   f"above upper")
    for key, value in (("velocity", velocity), ("effort", effort)):
        if value < 0:
            raise RobotDefinitionError(f"{where}: <limit {key}=\"{value:g}\">: expected a number >= 0 "
                                       f"(0: no limit)")
    return (lower, upper), velocity if velocity > 0 else None, effort if "effort" in element.attrib else None


def _placed_links(base: str, path: list[_UrdfJoint], joints: dict[str, _UrdfJoint],
                  source: str) -> list[tuple[str, int, NDArray[np.float64]]]:
    """``(link, chain frame, T_frame_link)`` of every link rigidly attached to a chain frame: the
    links on the path and the fixed side branches hanging from them."""
    children: dict[str, list[_UrdfJoint]] = {}
    for joint in joints.values():
        children.setdefault(joint.parent, []).append(joint)
    on_path = {joint.child for joint in path}
    placed: list[tuple[str, int, NDArray[np.float64]]] = [(base, 0, np.eye(4))]
    frame = 0
    for joint in path:
        if joint.kind == "fixed":
            origin = _origin(joint.element, f"{source}, joint {joint.name!r}")
            placed.append((joint.child, frame, placed[-1][2] @ origin))
        else:
            frame += 1
            placed.append((joint.child, frame, np.eye(4)))
    out, stack = [], list(placed)
    while stack:
        link, frame, T_frame_link = stack.pop()
        out.append((link, frame, T_frame_link))
        for joint in children.get(link, []):  # fixed side branches move with this frame
            if joint.kind == "fixed" and joint.child not in on_path:
                where = f"{source}, joint {joint.name!r}"
                stack.append((joint.child, frame, T_frame_link @ _origin(joint.element, where)))
    return out


def _meshes(placed: list[tuple[str, int, NDArray[np.float64]]], links: dict[str, ET.Element],
            source: str) -> tuple[UrdfMesh, ...]:
    """The visual meshes of the links rigidly attached to each chain frame."""
    out = []
    for link, frame, T_frame_link in placed:
        for visual in links[link].findall("visual"):
            mesh = visual.find("geometry/mesh")
            if mesh is not None and mesh.get("filename"):
                where = f"{source}, link {link!r}"
                scale = _floats(mesh, "scale", 3, where, default=[1.0, 1.0, 1.0])
                out.append(UrdfMesh(link, mesh.get("filename"), frame, T_frame_link @ _origin(visual, where),
                                    (float(scale[0]), float(scale[1]), float(scale[2]))))
    return tuple(sorted(out, key=lambda m: (m.frame, m.link)))


def mesh_search_folders(folder: Path | None, package_paths: Sequence[str | Path] = ()) -> list[Path]:
    """Where a ``package://PACKAGE/...`` mesh is looked for: each folder of ``package_paths``, then of
    the ``ROS_PACKAGE_PATH`` environment variable, then ``folder`` (the URDF's) and every folder
    above it (a package that holds the URDF, or sits beside one of its parents)."""
    environment = [p for p in os.environ.get("ROS_PACKAGE_PATH", "").split(os.pathsep) if p]
    here = [] if folder is None else [Path(folder).resolve(), *Path(folder).resolve().parents]
    return [Path(p) for p in (*package_paths, *environment)] + here


def find_mesh_file(filename: str, folder: Path | None,
                   package_paths: Sequence[str | Path] = ()) -> Path | None:
    """The file a mesh name in a URDF (or a scene file) refers to, or None if there is none:
    ``package://PACKAGE/rest`` as ``DIR/PACKAGE/rest`` (or ``DIR/rest`` when ``DIR`` is the package)
    for each ``DIR`` of :func:`mesh_search_folders`; ``file://`` and absolute paths as they are;
    other paths relative to ``folder``.

    >>> import pathlib, tempfile
    >>> root = pathlib.Path(tempfile.mkdtemp())
    >>> (root / "arm_description" / "meshes").mkdir(parents=True)
    >>> (root / "arm_description" / "urdf").mkdir()
    >>> _ = (root / "arm_description" / "meshes" / "base.stl").write_text("solid")
    >>> urdf_folder = root / "arm_description" / "urdf"
    >>> find_mesh_file("package://arm_description/meshes/base.stl", urdf_folder).name
    'base.stl'
    >>> find_mesh_file("../meshes/base.stl", urdf_folder).name
    'base.stl'
    >>> find_mesh_file("package://other/base.stl", urdf_folder) is None
    True
    """
    if filename.startswith("package://"):
        package, _, rest = filename.removeprefix("package://").partition("/")
        for base in mesh_search_folders(folder, package_paths):
            for root in (base / package, base):
                if root.name == package and (root / rest).is_file():
                    return root / rest
        return None
    path = Path(filename.removeprefix("file://")).expanduser()
    if not path.is_absolute() and folder is not None:
        path = Path(folder) / path
    return path if path.is_file() else None


def _geometries(placed: list[tuple[str, int, NDArray[np.float64]]], links: dict[str, ET.Element], tag: str,
                source: str) -> tuple[UrdfGeometry, ...]:
    """The ``<collision>`` geometry (``tag`` "collision"), or the ``<visual>`` boxes, cylinders and
    spheres (``tag`` "visual": its meshes are :func:`_meshes`'), of the links rigidly attached to
    each chain frame."""
    out = []
    for link, frame, T_frame_link in placed:
        for i, element in enumerate(links[link].findall(tag)):
            where = f"{source}, link {link!r}, <{tag}> number {i + 1}"
            geometry = element.find("geometry")
            shape = None if geometry is None or len(geometry) == 0 else geometry[0]
            if shape is None:
                if tag == "visual":
                    continue
                raise RobotDefinitionError(f"{where}: no <geometry> shape; expected <box>, <cylinder>, "
                                           f"<sphere> or <mesh>")
            if tag == "visual" and shape.tag not in ("box", "cylinder", "sphere"):
                continue
            filename = None
            if shape.tag == "box":
                size = _floats(shape, "size", 3, where, default=None)
            elif shape.tag == "cylinder":
                size = np.concatenate([_floats(shape, key, 1, where, default=None)
                                       for key in ("radius", "length")])
            elif shape.tag == "sphere":
                size = _floats(shape, "radius", 1, where, default=None)
            elif shape.tag == "mesh":
                filename = shape.get("filename")
                if not filename:
                    raise RobotDefinitionError(f"{where}: <mesh> has no filename=\"...\"")
                size = _floats(shape, "scale", 3, where, default=[1.0, 1.0, 1.0])
            else:
                raise RobotDefinitionError(f"{where}: <{shape.tag}>; expected <box>, <cylinder>, <sphere> "
                                           f"or <mesh>")
            if shape.tag != "mesh" and not (size > 0).all():
                if tag == "visual":  # nothing to draw: no reason to refuse the file
                    continue
                raise RobotDefinitionError(f"{where}: <{shape.tag}> sizes must be > 0 m, got {size.tolist()}")
            out.append(UrdfGeometry(link, shape.tag, tuple(float(v) for v in size), filename, frame,
                                    T_frame_link @ _origin(element, where)))
    return tuple(sorted(out, key=lambda c: (c.frame, c.link)))


def _inertials(base: str, path: list[_UrdfJoint], joints: dict[str, _UrdfJoint], links: dict[str, ET.Element],
               source: str) -> list[Inertial] | None:
    """Per moving joint of ``path``, the ``<inertial>`` of every link moving with its child link,
    in the child's frame: links fixed to it, side branches and links beyond the tip at joint
    values zero. None if none of them has an ``<inertial>``."""
    children: dict[str, list[_UrdfJoint]] = {}
    for joint in joints.values():
        children.setdefault(joint.parent, []).append(joint)
    on_path = {joint.child for joint in path}
    frame, T_frame_link, stack = 0, np.eye(4), []
    for joint in path:
        if joint.kind == "fixed":
            T_frame_link = T_frame_link @ _origin(joint.element, f"{source}, joint {joint.name!r}")
        else:
            frame, T_frame_link = frame + 1, np.eye(4)
        stack.append((joint.child, frame, T_frame_link))
    bodies = [Inertial.zero() for _ in range(frame)]
    found = False
    while stack:
        link, frame, T_frame_link = stack.pop()
        element = links[link].find("inertial")
        if element is not None and frame > 0:
            body = _inertial(element, f"{source}, link {link!r}").moved(T_frame_link)
            bodies[frame - 1] = bodies[frame - 1] + body
            found = True
        for joint in children.get(link, []):  # everything below, held at zero, except the chain itself
            if joint.child not in on_path:
                stack.append((joint.child, frame, T_frame_link @ _origin(joint.element,
                                                                         f"{source}, joint {joint.name!r}")))
    return bodies if found else None


def _inertial(element: ET.Element, where: str) -> Inertial:
    """An ``<inertial>`` in its link's frame: mass, centre-of-mass frame (``<origin>``), inertia in it."""
    mass_element = element.find("mass")
    if mass_element is None:
        raise RobotDefinitionError(f"{where}: <inertial> has no <mass value=\"...\"/>")
    mass = float(_floats(mass_element, "value", 1, where, default=None)[0])
    if mass < 0:
        raise RobotDefinitionError(f"{where}: <mass value=\"{mass_element.get('value')}\">: "
                                   f"expected a mass >= 0 kg")
    inertia_element = element.find("inertia")
    inertia = np.zeros((3, 3))
    if inertia_element is not None:
        xx, xy, xz, yy, yz, zz = (
            float(_floats(inertia_element, key, 1, where, default=[0.0])[0])
            for key in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"))
        inertia = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
    T_link_com = _origin(element, where)
    try:
        return Inertial(mass, np.zeros(3), inertia).moved(T_link_com)
    except RobotDefinitionError as exc:
        raise RobotDefinitionError(f"{where}: <inertial>: {exc}") from exc
