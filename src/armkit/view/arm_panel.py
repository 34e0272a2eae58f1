"""The arm as the viewer draws it at its configuration, and the "Tool pose" folder that reads it out.

The arm is drawn as capsules (:class:`~armkit.view.scene.ArmDrawing`), or with a URDF arm's own
meshes (:class:`~armkit.view.scene.MeshDrawing`), with its joint axes, its link frames, the
tool's velocity ellipsoid and, with a collision scene, its parts in contact coloured. The folder
reads out the tool pose and says what is drawn.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from armkit.spatial.rotations import quaternion_wxyz_from_matrix
from armkit.view import readout
from armkit.view.geometry import ellipsoid_axes, unit_sphere
from armkit.view.meshes import LinkVisual
from armkit.view.obstacles import COLLIDING, colour_contacts, draw_obstacles
from armkit.view.scene import ArmDrawing, Colours, MeshDrawing

if TYPE_CHECKING:
    from armkit.view.viewer import Viewer

__all__ = ["ELLIPSOID_SECONDS", "ArmPanel"]

#: Seconds of motion the velocity ellipsoid is drawn for (semi-axes [m] = rate [m/s] times this).
ELLIPSOID_SECONDS = 0.3


class ArmPanel:
    """The arm at the viewer's ``q`` in the scene, and the "Tool pose" folder.

    Parameters
    ----------
    viewer : Viewer
    visuals : tuple of LinkVisual, optional
        A URDF arm's own look, all found; ``None``: capsules.
    """

    def __init__(self, viewer: Viewer, visuals: tuple[LinkVisual, ...] | None) -> None:
        self._viewer = viewer
        robot, radius, scene = viewer.robot, viewer._radius, viewer._server.scene
        q = viewer.q
        self.arm = ArmDrawing(scene, "/arm", robot, radius, q)
        self.meshes: MeshDrawing | None = None
        #: The panel's "meshes" box (a URDF arm drawn with its meshes only).
        self.show_meshes: Any | None = None
        if visuals is not None:
            highlight = COLLIDING if viewer._scene is not None else None
            self.meshes = MeshDrawing(scene, "/visuals", visuals, robot.link_frames(q), highlight)
            self.arm.visible = False
        if viewer._scene is not None:
            draw_obstacles(scene, viewer._scene, viewer._size)
        self._axis_length = 3 * radius
        self._axes = scene.add_line_segments("/joint_axes", points=np.zeros((robot.n, 2, 3)),
                                             colors=Colours.AXIS, thickness=0.25 * radius)
        frames = robot.n + 2
        self._frames = scene.add_batched_axes("/link_frames",
                                              batched_wxyzs=np.tile([1.0, 0, 0, 0], (frames, 1)),
                                              batched_positions=np.zeros((frames, 3)),
                                              axes_length=2.5 * radius, axes_radius=0.12 * radius)
        vertices, faces = unit_sphere()
        self._ellipsoid = scene.add_batched_meshes_simple(
            "/ellipsoid", vertices, faces, batched_wxyzs=[[1.0, 0, 0, 0]], batched_positions=[[0.0, 0, 0]],
            batched_scales=[[1.0, 1.0, 1.0]], batched_colors=(90, 200, 255), opacity=0.35, visible=False,
            lod="off", cast_shadow=False, receive_shadow=False)
        self._build_folder()

    def _build_folder(self) -> None:
        viewer, gui = self._viewer, self._viewer._server.gui
        with gui.add_folder("Tool pose"):
            self.convention = gui.add_dropdown("convention", readout.angle_conventions(),
                                               initial_value="xyz-fixed")
            self.convention.on_update(lambda _: viewer._guarded(viewer._redraw))
            self._readout = gui.add_html("")
            self._show_frames = gui.add_checkbox("link frames", True)
            self._show_frames.on_update(lambda _: setattr(self._frames, "visible", self._show_frames.value))
            if self.meshes is not None:
                self.show_meshes = gui.add_checkbox(
                    "meshes", True, hint="the URDF's visual meshes; off: capsules (joints at a limit in red)")
                self.show_meshes.on_update(lambda _: viewer._guarded(self._toggle_meshes))
            self._show_ellipsoid = gui.add_checkbox("velocity ellipsoid", False,
                                                    hint=f"tool velocities for unit joint-rate norm, "
                                                         f"drawn for {ELLIPSOID_SECONDS} s")
            self._show_ellipsoid.on_update(lambda _: viewer._guarded(self._toggle_ellipsoid))
            gui.add_button("copy q").on_click(lambda _: viewer._guarded(self._copy_q))
            gui.add_button("copy pose").on_click(lambda _: viewer._guarded(self._copy_pose))
            self._copy = gui.add_text("copy this", "", hint="select and copy (Ctrl-C)")

    def draw(self, q: NDArray[np.float64], degrees: bool) -> None:
        """Draw the arm at ``q`` ``(n,)`` [rad or m] and read out its tool pose (angles in ``degrees``)."""
        viewer = self._viewer
        robot = viewer.robot
        with viewer._server.atomic():
            self.arm.update(q)
            placement = self.arm.placement
            if viewer._scene is not None:
                colour_contacts(self.arm, self.meshes, viewer._scene, q, Colours.LINK, Colours.JOINT)
            self._axes.points = np.stack([placement.joint_origins - self._axis_length * placement.joint_axes,
                                          placement.joint_origins + self._axis_length * placement.joint_axes],
                                         axis=1)
            frames = placement.link_frames
            if self.meshes is not None:
                self.meshes.update(frames)
            self._frames.batched_positions = frames[:, :3, 3]
            self._frames.batched_wxyzs = quaternion_wxyz_from_matrix(frames[:, :3, :3])
            if self._show_ellipsoid.value:
                R, semi = ellipsoid_axes(robot, q)
                self._ellipsoid.batched_positions = frames[-1:, :3, 3]
                self._ellipsoid.batched_wxyzs = quaternion_wxyz_from_matrix(R)[None]
                self._ellipsoid.batched_scales = np.maximum(semi * ELLIPSOID_SECONDS, 1e-4)[None]
        self._readout.content = readout.pose_html(robot, q, robot.fk(q), self.convention.value, degrees)

    def show_at_limit(self, flagged: NDArray[np.bool_]) -> None:
        """Draw the joints flagged ``(n,)`` in the at-limit red (the capsules)."""
        self.arm.colour(Colours.LINK, Colours.JOINT, flagged)

    def _toggle_meshes(self) -> None:
        self.meshes.visible = self.show_meshes.value
        self.arm.visible = not self.show_meshes.value

    def _toggle_ellipsoid(self) -> None:
        self._ellipsoid.visible = self._show_ellipsoid.value
        self._viewer._redraw()

    def _copy_q(self) -> None:
        self._copy.value = readout.copy_q_text(self._viewer.source, self._viewer.q)

    def _copy_pose(self) -> None:
        viewer = self._viewer
        self._copy.value = readout.copy_pose_text(viewer.source, viewer.robot.fk(viewer.q),
                                                  self.convention.value, viewer.closed_form)
