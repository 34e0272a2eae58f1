"""A URDF arm's own look: its ``<visual>`` meshes and boxes, cylinders and spheres, found and loaded.

Mesh files are named as the URDF writes them: a path relative to the URDF file, an absolute
path, ``file://...`` or ``package://PACKAGE/path``, found by :func:`armkit.urdf.find_mesh_file`
(``package_paths``, then ``ROS_PACKAGE_PATH``, then the URDF's folder and those above it, as in
example-robot-data's ``share/example-robot-data/robots/...``). Meshes (STL, DAE, OBJ and what
else trimesh reads) are loaded with trimesh (``pip install 'armkit[view]'``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from armkit.robot import Robot
from armkit.urdf import find_mesh_file

__all__ = ["LinkVisual", "VisualSet", "link_visuals"]


@dataclass(frozen=True)
class LinkVisual:
    """One shape to draw, fixed in a chain frame.

    Attributes
    ----------
    frame : int
        0 the base frame, ``i`` link frame ``i`` (:meth:`armkit.Robot.link_frames` numbering).
    T_frame_visual : ndarray (4, 4)
        The shape's pose in that frame [m] (the mesh's own scale already applied to ``mesh``).
    mesh : trimesh.Trimesh
        The shape, in its own frame [m].
    name : str
        What it is: the link and the file or primitive.
    """

    frame: int
    T_frame_visual: NDArray[np.float64]
    mesh: Any
    name: str


@dataclass(frozen=True)
class VisualSet:
    """The visuals found for a robot, and the meshes that could not be drawn (with the reason)."""

    visuals: tuple[LinkVisual, ...]
    missing: tuple[str, ...]

    def summary(self, robot_name: str) -> str:
        """One sentence on what is missing, for the status line (empty if nothing is)."""
        if not self.missing:
            return ""
        more = f" (and {len(self.missing) - 1} more)" if len(self.missing) > 1 else ""
        return f"{robot_name}: drawn as capsules: {self.missing[0]}{more}"


def _primitive(trimesh: Any, kind: str, size: tuple[float, ...]) -> Any:
    if kind == "box":
        return trimesh.creation.box(extents=size)
    if kind == "cylinder":
        return trimesh.creation.cylinder(radius=size[0], height=size[1], sections=32)
    return trimesh.creation.icosphere(subdivisions=3, radius=size[0])


def link_visuals(robot: Robot, package_paths: Sequence[str | Path] = ()) -> VisualSet | None:
    """Every ``<visual>`` of a URDF robot, loaded; None for a robot that has none (or no URDF).

    A mesh that cannot be found or read is listed in :attr:`VisualSet.missing` instead; so is
    every mesh when trimesh is not installed.
    """
    urdf = robot.urdf
    if urdf is None or not (urdf.meshes or urdf.shapes):
        return None
    try:
        import trimesh
    except ImportError:
        return VisualSet((), (f"{len(urdf.meshes) + len(urdf.shapes)} visuals need trimesh "
                              f"(pip install 'armkit[view]')",))
    visuals, missing = [], []
    for shape in urdf.shapes:
        visuals.append(LinkVisual(shape.frame, np.array(shape.T_frame_geom),
                                  _primitive(trimesh, shape.kind, shape.size), f"{shape.link} {shape.kind}"))
    for mesh in urdf.meshes:
        path = find_mesh_file(mesh.filename, Path(urdf.path).parent, package_paths)
        if path is None:
            missing.append(f"mesh {mesh.filename} of link {mesh.link} not found")
            continue
        try:
            loaded = trimesh.load(str(path), force="mesh")
        except Exception as exc:  # trimesh raises what its readers raise: any of them means unreadable
            missing.append(f"mesh {path} of link {mesh.link} cannot be read ({type(exc).__name__}: {exc})")
            continue
        if not len(getattr(loaded, "faces", ())):
            missing.append(f"mesh {path} of link {mesh.link} has no triangles")
            continue
        loaded.apply_scale(mesh.scale)
        visuals.append(LinkVisual(mesh.frame, np.array(mesh.T_frame_mesh), loaded,
                                  f"{mesh.link} {path.name}"))
    return VisualSet(tuple(visuals), tuple(missing))
