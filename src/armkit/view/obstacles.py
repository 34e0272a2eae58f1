"""A collision scene in the viewer: the floor and obstacles drawn, the links in contact coloured."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from armkit import kinematics
from armkit.spatial.rotations import quaternion_wxyz_from_matrix
from armkit.view.geometry import SHORTEST_SEGMENT, centre_line

if TYPE_CHECKING:
    from armkit.collision.scene import Scene
    from armkit.view.scene import ArmDrawing, MeshDrawing

__all__ = ["COLLIDING", "OBSTACLE", "colour_contacts", "draw_obstacles"]

OBSTACLE = (150, 150, 165)
COLLIDING = (235, 40, 150)
_OPACITY = 0.55


def draw_obstacles(server_scene: Any, scene: Scene, size: float) -> list[Any]:
    """Draw ``scene``'s floor (a translucent slab ``2 size`` wide) and obstacles; their handles."""
    handles = []
    for k, shape in enumerate(scene.world_shapes()):
        name = f"/obstacles/{k}_{shape.part}"
        pose = {"wxyz": quaternion_wxyz_from_matrix(shape.T_base_geom[:3, :3]),
                "position": shape.T_base_geom[:3, 3]}
        common = {"color": OBSTACLE, "opacity": _OPACITY}
        if shape.kind == "plane":
            thickness = 0.002 * size
            pose["position"] = shape.T_base_geom[:3, 3] - [0.0, 0.0, thickness / 2]
            handles.append(server_scene.add_box(name, dimensions=(2 * size, 2 * size, thickness),
                                                **common, **pose))
        elif shape.kind == "box":
            handles.append(server_scene.add_box(name, dimensions=2 * shape.size, **common, **pose))
        elif shape.kind == "sphere":
            handles.append(server_scene.add_icosphere(name, radius=float(shape.size[0]), **common, **pose))
        elif shape.kind == "cylinder":
            handles.append(server_scene.add_cylinder(name, radius=float(shape.size[0]),
                                                     height=float(2 * shape.size[1]), **common, **pose))
        else:
            handles.append(server_scene.add_mesh_simple(name, shape.vertices, shape.faces, **common, **pose))
    return handles


def colour_contacts(arm: ArmDrawing, meshes: MeshDrawing | None, scene: Scene, q: NDArray[np.float64],
                    link: tuple[int, int, int], joint: tuple[int, int, int]) -> list[tuple[str, str]]:
    """Colour the arm parts in contact at ``q`` in :data:`COLLIDING`: their drawn links and joints
    (the others ``link`` and ``joint``) and, if the arm is drawn with its meshes, their visuals
    (``meshes`` built with ``highlight=COLLIDING``); the contacts."""
    contacts = scene.contacts(q)
    touching = {part for pair in contacts for part in pair}
    n = scene.robot.n
    colliding = np.array([part in touching for part in scene.parts[:n + 1]])  # base, links
    T_joints, T_tool = kinematics.joint_frames(scene.robot, q)
    path = centre_line(T_joints, T_tool)
    keep = np.linalg.norm(path[1:] - path[:-1], axis=-1) > SHORTEST_SEGMENT
    owner = np.repeat(np.arange(n + 1), 2)[keep]  # frame k to k + 1 belongs to part k
    colours = np.array([link] * int(keep.sum()) + [joint] * n, dtype=np.uint8)
    colours[:int(keep.sum())][colliding[owner]] = COLLIDING
    colours[int(keep.sum()):][colliding[1:]] = COLLIDING  # joint i's cylinder moves with link i
    arm.handle.batched_colors = colours
    if meshes is not None:  # a visual in chain frame i is part i's (the tool frame n + 1 is link n's)
        meshes.highlight(colliding[np.minimum(meshes.frames, n)])
    return contacts
