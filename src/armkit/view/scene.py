"""The arm in viser's scene: one instanced mesh of link and joint cylinders per drawn configuration, or
a URDF arm's own meshes, each fixed in a scene frame that follows its chain frame."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from armkit.errors import ArmkitError
from armkit.robot import Robot
from armkit.spatial.rotations import quaternion_wxyz_from_matrix
from armkit.view.geometry import arm_placement, unit_cylinder
from armkit.view.meshes import LinkVisual

__all__ = ["ArmDrawing", "Colours", "MeshDrawing"]


class Colours:
    """RGB colours of the scene (0-255)."""

    LINK = (150, 160, 175)
    JOINT = (240, 150, 40)
    AT_LIMIT = (220, 30, 30)
    GHOST_IN = (40, 170, 70)
    GHOST_OUT = (220, 50, 50)
    GHOST_FAMILY = (230, 190, 0)
    AXIS = (30, 90, 220)
    PATH = (120, 60, 200)
    WAYPOINT = (20, 120, 220)


class ArmDrawing:
    """One configuration of the arm drawn as cylinders (a single instanced mesh).

    Parameters
    ----------
    scene : viser.SceneApi
    name : str
        Scene node name, e.g. ``"/arm"``.
    robot : Robot
    radius : float
        Link radius [m].
    opacity : float, optional
        ``None`` draws opaque; ghosts use about 0.3.
    """

    def __init__(self, scene: Any, name: str, robot: Robot, radius: float, q: NDArray[np.float64],
                 opacity: float | None = None) -> None:
        self.robot, self.radius = robot, radius
        self.placement = arm_placement(robot, q, radius)
        self._scheme: tuple = (Colours.LINK, Colours.JOINT, None)
        vertices, faces = unit_cylinder()
        self.handle = scene.add_batched_meshes_simple(
            name, vertices, faces, batched_wxyzs=self.placement.wxyzs,
            batched_positions=self.placement.positions, batched_scales=self.placement.scales,
            batched_colors=self._colours(*self._scheme), opacity=opacity, lod="off",
            cast_shadow=False, receive_shadow=False)

    def _colours(self, link: tuple[int, int, int], joint: tuple[int, int, int],
                 highlight: NDArray[np.bool_] | None = None) -> NDArray[np.uint8]:
        colours = np.array([link] * self.placement.link_count + [joint] * self.robot.n, dtype=np.uint8)
        if highlight is not None:
            colours[self.placement.link_count:][highlight] = Colours.AT_LIMIT
        return colours

    def update(self, q: NDArray[np.float64]) -> None:
        """Draw the arm at ``q`` [rad or m]."""
        placement = arm_placement(self.robot, q, self.radius)
        recolour = placement.link_count != self.placement.link_count  # a segment appeared or vanished
        self.placement = placement
        if recolour:
            self.handle.batched_colors = self._colours(*self._scheme)
        self.handle.batched_positions = placement.positions
        self.handle.batched_wxyzs = placement.wxyzs
        self.handle.batched_scales = placement.scales

    def colour(self, link: tuple[int, int, int], joint: tuple[int, int, int],
               highlight: NDArray[np.bool_] | None = None) -> None:
        """Colour links and joints; joints flagged in ``highlight`` ``(n,)`` in the at-limit red."""
        self._scheme = (link, joint, highlight)
        self.handle.batched_colors = self._colours(*self._scheme)

    @property
    def visible(self) -> bool:
        return bool(self.handle.visible)

    @visible.setter
    def visible(self, value: bool) -> None:
        self.handle.visible = value


class MeshDrawing:
    """A URDF arm drawn with its own visuals (:func:`armkit.view.meshes.link_visuals`).

    Each chain frame that carries a visual is a scene frame (``{name}/{frame}``) whose pose
    :meth:`update` sets; the visuals sit in it at their fixed ``T_frame_visual``. With a
    ``highlight`` colour, :meth:`highlight` shows a copy of a visual in that colour in its place (a
    mesh's own colours and textures cannot be changed); the copy is made the first time that visual
    is highlighted, so a visual never in contact is sent to the browser once.
    """

    def __init__(self, scene: Any, name: str, visuals: tuple[LinkVisual, ...],
                 link_frames: NDArray[np.float64], highlight: tuple[int, int, int] | None = None) -> None:
        self._nodes = {i: scene.add_frame(f"{name}/{i}", show_axes=False)
                       for i in sorted({v.frame for v in visuals})}
        self.frames = np.array([v.frame for v in visuals], dtype=int)
        poses = [{"position": v.T_frame_visual[:3, 3],
                  "wxyz": quaternion_wxyz_from_matrix(v.T_frame_visual[:3, :3])} for v in visuals]
        self.meshes = [scene.add_mesh_trimesh(f"{name}/{v.frame}/{k}", v.mesh, **pose)
                       for k, (v, pose) in enumerate(zip(visuals, poses, strict=True))]
        self._scene, self._name, self._visuals, self._poses = scene, name, visuals, poses
        self._highlight_colour = highlight
        #: Each visual's copy in the highlight colour (``None`` until it is first highlighted).
        self.highlights: list[Any | None] = [None] * len(visuals)
        self._highlighted = np.zeros(len(visuals), dtype=bool)
        self.update(link_frames)

    def update(self, link_frames: NDArray[np.float64]) -> None:
        """Place the visuals for the chain frames ``(n + 2, 4, 4)`` (:meth:`Robot.link_frames`)."""
        for i, node in self._nodes.items():
            node.position = link_frames[i, :3, 3]
            node.wxyz = quaternion_wxyz_from_matrix(link_frames[i, :3, :3])

    def highlight(self, flagged: NDArray[np.bool_]) -> None:
        """Draw the visuals flagged ``(len(meshes),)`` in the highlight colour, the others in their own."""
        flagged = np.asarray(flagged, dtype=bool)
        if flagged.shape != self._highlighted.shape:
            raise ArmkitError(f"highlight: expected {len(self.meshes)} flags (one per visual), got shape "
                              f"{flagged.shape}")
        if self._highlight_colour is None and flagged.any():
            raise ArmkitError("highlight: this drawing was made without a highlight colour")
        for k in np.flatnonzero(flagged != self._highlighted):  # only the changed ones: one message each
            if self.highlights[k] is None:
                visual = self._visuals[k]
                self.highlights[k] = self._scene.add_mesh_simple(
                    f"{self._name}/{visual.frame}/{k}_highlight", np.asarray(visual.mesh.vertices),
                    np.asarray(visual.mesh.faces), color=self._highlight_colour, visible=False,
                    **self._poses[k])
            self.meshes[k].visible = not flagged[k]
            self.highlights[k].visible = bool(flagged[k])
        self._highlighted = flagged.copy()

    @property
    def visible(self) -> bool:
        return all(node.visible for node in self._nodes.values())

    @visible.setter
    def visible(self, value: bool) -> None:
        for node in self._nodes.values():
            node.visible = value
