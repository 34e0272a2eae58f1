"""The viewer's taught waypoints: ``teach waypoint``, their list, their markers in the scene, ``plan``."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit.errors import InputError, JointLimitError
from armkit.trajectory.joint_trajectory import JointTrajectory
from armkit.trajectory.plan import plan_trajectory
from armkit.trajectory.waypoints import joint_waypoints
from armkit.view import readout
from armkit.view.geometry import unit_sphere
from armkit.view.scene import Colours

if TYPE_CHECKING:
    from armkit.view.viewer import Viewer

__all__ = ["TeachPanel"]


class TeachPanel:
    """Waypoints taught from the arm's configurations: listed in the panel, marked ``W1``, ``W2``, ...
    at their tool positions, and planned through (``armkit traj --auto-time``)."""

    def __init__(self, viewer: Viewer) -> None:
        self._viewer = viewer
        self._robot = viewer.robot
        self.waypoints: list[NDArray[np.float64]] = []
        vertices, faces = unit_sphere()
        scene = viewer._server.scene
        self._markers = scene.add_batched_meshes_simple(
            "/waypoints", vertices, faces, batched_wxyzs=np.zeros((0, 4)), batched_positions=np.zeros((0, 3)),
            batched_scales=np.zeros((0,)), batched_colors=Colours.WAYPOINT, lod="off")
        self._labels: list[Any] = []
        gui = viewer._server.gui
        self.teach_button = gui.add_button("teach waypoint")
        self.teach_button.on_click(lambda _: viewer._guarded(viewer.teach))
        gui.add_button("clear waypoints").on_click(lambda _: viewer._guarded(viewer.clear_waypoints))
        self._list = gui.add_html(readout.waypoints_html(self._robot, [], True))
        self.plan_button = gui.add_button("plan through waypoints (auto time)", disabled=True)
        self.plan_button.on_click(lambda _: viewer._guarded(viewer.plan))

    def teach(self, q: NDArray[np.float64]) -> int:
        """Append ``q`` ``(n,)`` [rad or m], inside the limits; the number of waypoints."""
        violations = self._robot.limit_violations(q)
        if violations:
            raise JointLimitError(f"cannot teach this configuration: {'; '.join(violations)}")
        self.waypoints.append(q.copy())
        self.draw()
        return len(self.waypoints)

    def replace(self, values: ArrayLike) -> None:
        """Make ``values`` ``(M, n)`` [rad or m] the waypoints (checked as ``armkit traj`` checks them)."""
        self.waypoints = list(joint_waypoints(self._robot, np.reshape(values, (-1, self._robot.n))))
        self.draw()

    def clear(self) -> None:
        """Forget the waypoints."""
        self.waypoints = []
        self.draw()

    def as_array(self) -> NDArray[np.float64]:
        """The waypoints ``(M, n)`` [rad or m]."""
        return np.array(self.waypoints).reshape(len(self.waypoints), self._robot.n)

    def plan(self) -> JointTrajectory:
        """The shortest minimum-jerk trajectory within the limits through the waypoints."""
        if len(self.waypoints) < 2:
            raise InputError(f"a trajectory needs at least two waypoints, {len(self.waypoints)} taught")
        return plan_trajectory(self._robot, self.as_array())

    def draw(self) -> None:
        """Mark the waypoints in the scene and list them (in the panel's current angle unit)."""
        viewer, radius = self._viewer, self._viewer._radius
        positions = self._robot.fk(self.as_array())[:, :3, 3] if self.waypoints else np.zeros((0, 3))
        with viewer._server.atomic():
            self._markers.batched_positions = positions
            self._markers.batched_wxyzs = np.tile([1.0, 0, 0, 0], (len(positions), 1))
            self._markers.batched_scales = np.full(len(positions), 0.8 * radius)
        for label in self._labels:
            label.remove()
        self._labels = [viewer._server.scene.add_label(f"/waypoint_labels/{k}", f"W{k + 1}",
                                                       position=p + [0, 0, 3 * radius])
                        for k, p in enumerate(positions)]
        self.refresh_list()
        self.plan_button.disabled = len(self.waypoints) < 2

    def refresh_list(self) -> None:
        """Write the list again in the panel's current angle unit."""
        self._list.content = readout.waypoints_html(self._robot, self.waypoints, self._viewer._degrees)
