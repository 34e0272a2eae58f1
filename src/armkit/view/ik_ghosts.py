"""The viewer's IK: the handle at the target, every solution as a ghost arm, the "Inverse kinematics" folder.

Closed-form arms get every solution (green: inside the limits, red: outside, yellow: a singular
family's representative), numbered in the scene and listed; other arms the numeric solution
nearest the arm. The arm can follow the handle (the nearest solution inside the limits) or take
any solution from the list.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from armkit.errors import JointLimitError, UnreachableError
from armkit.ik.solve import IKSolutions, ik_solutions
from armkit.kinematics import pose_error
from armkit.spatial.rotations import matrix_from_quaternion_wxyz, quaternion_wxyz_from_matrix
from armkit.spatial.transforms import transform_from
from armkit.view import readout
from armkit.view.geometry import label_positions
from armkit.view.scene import ArmDrawing, Colours

if TYPE_CHECKING:
    from armkit.view.viewer import Viewer

__all__ = ["LABEL_SPACING", "MAX_GHOSTS", "IKGhosts"]

#: Ghost arms kept in the scene: the most IK solutions armkit lists for one pose (a general 6R arm).
MAX_GHOSTS = 16
#: Least distance between two ghosts' labels, in link radii.
LABEL_SPACING = 3.0
#: What the IK list says when the arm has moved off the target by its joints.
MOVE_THE_HANDLE = "move the handle at the tool to solve IK"


class IKGhosts:
    """The IK target (a handle in the scene), its solutions drawn as ghost arms, and their list.

    Attributes
    ----------
    target : ndarray (4, 4)
        The handle's pose [m].
    solutions : IKSolutions or None
        The solutions of ``target`` (``None`` after the arm moved by its joints).
    """

    def __init__(self, viewer: Viewer) -> None:
        self._viewer = viewer
        self._robot = viewer.robot
        self._syncing = False
        self.target = self._robot.fk(viewer.q)
        self.solutions: IKSolutions | None = None
        self._index: int | None = None
        scene, radius = viewer._server.scene, viewer._radius
        self.ghosts = [ArmDrawing(scene, f"/ghost/{k}", self._robot, 0.8 * radius, viewer.q, opacity=0.3)
                       for k in range(MAX_GHOSTS)]
        self.labels = [scene.add_label(f"/ghost/{k}/label", f"#{k + 1}", visible=False)
                       for k in range(MAX_GHOSTS)]
        for ghost in self.ghosts:
            ghost.visible = False
        self.handle = scene.add_transform_controls("/target", scale=0.22 * viewer._size, depth_test=False,
                                                   position=self.target[:3, 3],
                                                   wxyz=quaternion_wxyz_from_matrix(self.target[:3, :3]))
        self.handle.on_update(self._on_handle)
        gui = viewer._server.gui
        with gui.add_folder("Inverse kinematics"):
            self.follow = gui.add_checkbox("arm follows the handle", True,
                                           hint="the arm takes the nearest solution inside the limits")
            self.pick = gui.add_dropdown("solution", ("-",), initial_value="-", disabled=True)
            self.pick.on_update(lambda _: viewer._guarded(self._on_pick))
            self.status = gui.add_html("<div style='font-size:0.8em' data-armkit='ik-summary'>"
                                       "drag the handle at the tool to solve IK</div>")
            gui.add_button("handle to tool").on_click(lambda _: viewer._guarded(self._handle_to_tool))

    def move_handle(self, T: NDArray[np.float64]) -> None:
        """Put the target, and the handle, at ``T`` ``(4, 4)`` [m]."""
        self.target = T.copy()
        with self._viewer._server.atomic():
            self.handle.position = T[:3, 3]
            self.handle.wxyz = quaternion_wxyz_from_matrix(T[:3, :3])

    def clear(self, message: str = MOVE_THE_HANDLE) -> None:
        """Forget the solutions, hide the ghosts, say ``message`` in their place."""
        self.solutions, self._index = None, None
        for ghost, label in zip(self.ghosts, self.labels, strict=True):
            ghost.visible = False
            label.visible = False
        self.status.content = f"<div style='font-size:0.8em' data-armkit='ik-summary'>{message}</div>"
        self._set_pick_options(("-",), disabled=True)

    def solve(self, T: NDArray[np.float64], follow: bool, final: bool) -> IKSolutions:
        """Solve IK at ``T`` ``(4, 4)`` [m] and draw the solutions; with ``follow`` the arm takes the
        nearest one inside the limits. ``final``: the drag has ended (say how far an unreachable
        target is)."""
        robot, q = self._robot, self._viewer.q
        try:
            # each solution once: a whole-turn copy looks the same as its solution in the scene
            found = (ik_solutions(robot, T, near=q, turn_copies=False) if self._viewer.closed_form
                     else self._numeric_solutions(T, q))
        except UnreachableError as exc:
            found = IKSolutions(np.zeros((0, robot.n)), *(np.zeros(0, dtype=bool),) * 2, *(np.zeros(0),) * 2)
            self._unreachable(found, exc.position_error, exc.orientation_error)
            return found
        if len(found.q) == 0:
            self._unreachable(found, *self._distance(T, q, final))
            return found
        self.solutions, self._index = found, None
        if len(found.q) > MAX_GHOSTS:
            self._viewer._show_status(f"<div style='font-size:0.8em'>{len(found.q)} solutions; "
                                      f"the first {MAX_GHOSTS} are drawn</div>")
        self._draw(found)
        inside = np.flatnonzero(found.within_limits)
        if follow and len(inside):
            self.take(int(inside[0]))
        else:
            self._show_list()
        return found

    def _draw(self, found: IKSolutions) -> None:
        for k, ghost in enumerate(self.ghosts[:len(found.q)]):
            colour = (Colours.GHOST_OUT if not found.within_limits[k] else
                      Colours.GHOST_FAMILY if found.family[k] else Colours.GHOST_IN)
            with self._viewer._server.atomic():
                ghost.update(found.q[k])
                ghost.colour(colour, colour)
        drawn = self.ghosts[:len(found.q)]
        # each label at a joint of its ghost away from the others' labels: no two overlap
        first = min(1, self._robot.n - 1)  # the first joint's origin is every ghost's
        positions = label_positions([ghost.placement.joint_origins[first:] for ghost in drawn],
                                    LABEL_SPACING * self._viewer._radius)
        for k, (ghost, label) in enumerate(zip(self.ghosts, self.labels, strict=True)):
            shown = k < len(drawn)
            if shown:
                label.position = positions[k]
            ghost.visible = shown
            label.visible = shown

    def take(self, k: int) -> None:
        """Move the arm to solution ``k`` (0-based) of the target."""
        self._index = k
        self._viewer._set_q(self.solutions.q[k], from_ik=True)
        self._show_list()

    def _numeric_solutions(self, T: NDArray[np.float64], q: NDArray[np.float64]) -> IKSolutions:
        """The numeric solution nearest ``q`` (inside the limits, else outside them) as a one-row list."""
        robot = self._robot
        try:
            solution = robot.ik(T, near=q)
        except JointLimitError:
            solution = robot.ik(T, near=q, within_limits=False)
        residual = pose_error(T, robot.fk(solution))
        return IKSolutions(solution[None], robot.within_limits(solution)[None], np.zeros(1, dtype=bool),
                           np.linalg.norm(residual[:3])[None], np.linalg.norm(residual[3:])[None])

    def _distance(self, T: NDArray[np.float64], q: NDArray[np.float64], final: bool) -> tuple[float, float]:
        """How far the closest pose is (only once the drag ends: the search takes a while)."""
        if not final:
            return float("nan"), float("nan")
        try:
            self._robot.ik(T, near=q, within_limits=False)
        except UnreachableError as exc:
            return exc.position_error, exc.orientation_error
        return 0.0, 0.0

    def _unreachable(self, found: IKSolutions, position_error: float, orientation_error: float) -> None:
        self.clear("")
        self.solutions = found
        how_far = ("" if np.isnan(position_error) else
                   f": the closest pose found is {position_error * 1000:.1f} mm and "
                   f"{np.degrees(orientation_error):.1f}° away")
        self.status.content = (f"<div style='font-size:0.8em;color:#d33' data-armkit='ik-summary' "
                               f"data-unreachable='true'>target out of reach{how_far}</div>")

    def _show_list(self) -> None:
        found = self.solutions
        method = "closed form" if self._viewer.closed_form else "numeric, nearest the arm"
        self.status.content = readout.solutions_html(self._robot, found, self._index,
                                                     self._viewer._degrees, method)
        options = tuple(f"{k + 1}: {'in limits' if ok else 'OUT of limits'}"
                        f"{', singular family' if family else ''}"
                        for k, (ok, family) in enumerate(zip(found.within_limits, found.family, strict=True)))
        self._set_pick_options(options, disabled=False,
                               value=None if self._index is None else options[self._index])

    def refresh_list(self) -> None:
        """Write the list again (in the panel's current angle unit), if there is one."""
        if self.solutions is not None and len(self.solutions.q):
            self._show_list()

    def _set_pick_options(self, options: tuple[str, ...], disabled: bool, value: str | None = None) -> None:
        self._syncing = True
        try:
            self.pick.options = options
            self.pick.value = options[0] if value is None else value
            self.pick.disabled = disabled
        finally:
            self._syncing = False

    def _on_pick(self) -> None:
        if self._syncing or self.solutions is None or self.pick.value == "-":
            return
        self.take(int(self.pick.value.split(":")[0]) - 1)

    def _handle_to_tool(self) -> None:
        self.move_handle(self._robot.fk(self._viewer.q))
        self.clear()

    def _on_handle(self, event: Any) -> None:
        handle = event.target
        final = getattr(event, "phase", "end") == "end"

        def solve() -> None:  # the pose is read inside the guard: a zero quaternion is an error line
            R = matrix_from_quaternion_wxyz(np.asarray(handle.wxyz))
            T = transform_from(R, np.asarray(handle.position))
            self.target = T
            self.solve(T, follow=self.follow.value, final=final)

        self._viewer._guarded(solve)
