"""``armkit.view.Viewer``: the arm in a browser (viser), with joint sliders, IK ghosts and a timeline.

The viewer runs a local web server (viser's, in a background thread) and keeps the state here in
Python: the configuration ``q``, the IK target and its solutions, the taught waypoints and the
motion on the timeline. The page and the Python API change the same state; every change redraws
the scene and the read-outs for every connected browser.
"""

from __future__ import annotations

import contextlib
import html
import io
import logging
import threading
import time
import warnings
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit.errors import ArmkitError, InputError, JointLimitError, UnreachableError
from armkit.ik.solve import IKSolutions, ik_solutions
from armkit.ik.structure import analyze_structure
from armkit.kinematics import pose_error
from armkit.robot import Robot
from armkit.robot_file import load
from armkit.spatial.rotations import matrix_from_quaternion_wxyz, quaternion_wxyz_from_matrix
from armkit.spatial.transforms import check_transform, transform_from
from armkit.trajectory.joint_trajectory import JointTrajectory
from armkit.trajectory.plan import plan_trajectory
from armkit.trajectory.waypoints import joint_waypoints, write_waypoints
from armkit.view import readout
from armkit.view.geometry import arm_size, ellipsoid_axes, label_positions, unit_sphere
from armkit.view.meshes import link_visuals
from armkit.view.obstacles import colour_contacts, draw_obstacles
from armkit.view.playback import Playback
from armkit.view.scene import ArmDrawing, Colours, MeshDrawing
from armkit.view.server_log import SERVER_LOGGERS, OneLineMessageErrors

if TYPE_CHECKING:  # armkit.collision needs MuJoCo only when a scene is given
    from armkit.collision.scene import Scene

__all__ = ["Viewer"]

#: Ghost arms kept in the scene: the most IK solutions armkit lists for one pose (a general 6R arm).
MAX_GHOSTS = 16
#: Least distance between two ghosts' labels, in link radii.
LABEL_SPACING = 3.0
#: Height of the page inside a notebook cell [px] (:meth:`Viewer._repr_html_`).
NOTEBOOK_HEIGHT_PX = 600
#: Frames per second of the timeline while playing.
PLAY_RATE_HZ = 30.0
#: Seconds of motion the velocity ellipsoid is drawn for (semi-axes [m] = rate [m/s] times this).
ELLIPSOID_SECONDS = 0.3


# A value of the wrong type in a client's message: viser warns, then its handler fails (said in one line
# by OneLineMessageErrors). Set once, here: a filter set by a viewer inside warnings.catch_warnings()
# would be gone when that block ends.
warnings.filterwarnings("ignore", r"\[viser\] .* does not match annotation", UserWarning)


def _import_viser() -> Any:
    try:
        import viser
    except ImportError as exc:
        raise ArmkitError("the 3-D viewer needs viser: pip install 'armkit[view]'") from exc
    return viser


def _nice_step(length: float) -> float:
    """A round grid step [m] (0.05, 0.1, 0.2, 0.5, ...) giving about five cells over ``length``."""
    raw = length / 5
    power = 10 ** np.floor(np.log10(raw))
    return float(min((s * power for s in (1, 2, 5, 10) if s * power >= raw), default=raw))


class Viewer:
    """An arm in the browser: sliders per joint, the tool pose live, every IK solution of a target.

    Parameters
    ----------
    robot : Robot or str
        The arm, or a built-in name / robot file for :func:`armkit.load`.
    port : int
        TCP port of the page (the next free one if taken; 0: any free port). See :attr:`url`.
    host : str
        Interface to listen on: ``"127.0.0.1"`` (this machine only, the default) or
        ``"0.0.0.0"`` to let other machines open the page.
    q : array_like, shape (n,), optional
        Starting configuration [rad or m]; default :attr:`Robot.home`.
    verbose : bool
        Let viser print its own messages.
    scene : armkit.Scene, optional
        A collision scene (built for this robot): its floor and obstacles are drawn, and the arm's
        links in contact are coloured magenta (:mod:`armkit.view.obstacles`).
    package_paths : sequence of str or Path
        Folders to look for ``package://`` meshes of a URDF arm in, before ``ROS_PACKAGE_PATH``
        and the URDF's own folders (see :mod:`armkit.view.meshes`). A URDF arm is drawn with
        its ``<visual>`` meshes and shapes (the "meshes" box switches to capsules); if one is
        missing, with capsules, and a warning and the panel say which.

    Examples
    --------
    >>> from armkit.view import Viewer
    >>> viewer = Viewer("probot-anno", port=0)                # open viewer.url in a browser
    >>> viewer.q = [0.9, -0.9, -0.35, 0.96, 2.97, -0.24]      # the arm and the read-out move
    >>> found = viewer.show_solutions(viewer.robot.fk(viewer.q))   # ghosts of all 8 solutions
    >>> len(found.q), int(found.within_limits.sum())
    (8, 4)
    >>> q = viewer.pick(1)                                    # the arm takes solution 1
    >>> viewer.teach()                                        # one waypoint taught
    1
    >>> viewer.close()
    """

    def __init__(self, robot: Robot | str, port: int = 8080, host: str = "127.0.0.1", *,
                 q: ArrayLike | None = None, verbose: bool = False,
                 package_paths: Sequence[str | Path] = (), scene: Scene | None = None) -> None:
        viser = _import_viser()
        self.robot = load(robot) if isinstance(robot, str | Path) else robot
        self.source = str(robot) if isinstance(robot, str | Path) else self.robot.name
        self.closed_form = analyze_structure(self.robot.chain).closed_form
        self._lock = threading.RLock()
        self._syncing = False
        self._q = self.robot.home if q is None else self.robot.check_q(q).copy()
        self._target = self.robot.fk(self._q)
        self._solutions: IKSolutions | None = None
        self._solution_index: int | None = None
        self._waypoints: list[NDArray[np.float64]] = []
        self._playback: Playback | None = None
        self._playing = False
        self._player: threading.Thread | None = None
        self._closed = False
        if scene is not None:
            scene.check_robot(self.robot)
        self._scene = scene
        self._size = arm_size(self.robot)
        self._radius = float(np.clip(0.025 * self._size, 0.004, 0.05))
        self._message_errors = OneLineMessageErrors()
        for name in SERVER_LOGGERS:
            logging.getLogger(name).addFilter(self._message_errors)
        with contextlib.redirect_stdout(io.StringIO()) if not verbose else contextlib.nullcontext():
            self._server = viser.ViserServer(host=host, port=port, label=f"armkit view: {self.robot.name}",
                                             verbose=verbose)
        self._verbose = verbose
        self._host = host
        self._package_paths = tuple(package_paths)
        try:
            self._build_scene()
            self._build_gui()
            self._redraw()
        except BaseException:  # nothing left listening on the port
            self.close()
            raise

    # ------------------------------------------------------------------ public API
    @property
    def url(self) -> str:
        """Address of the page, e.g. ``http://127.0.0.1:8080``."""
        host = "127.0.0.1" if self._host in ("0.0.0.0", "") else self._host
        return f"http://{host}:{self._server.get_port()}"

    @property
    def q(self) -> NDArray[np.float64]:
        """The arm's configuration ``(n,)`` [rad or m]; assign to move the arm (limits not enforced)."""
        with self._lock:
            return self._q.copy()

    @q.setter
    def q(self, value: ArrayLike) -> None:
        with self._lock:
            self._set_q(self.robot.check_q(value))
            self._clear_solutions("move the handle at the tool to solve IK")

    @property
    def target(self) -> NDArray[np.float64]:
        """The IK target (the handle's pose) ``(4, 4)`` [m]."""
        with self._lock:
            return self._target.copy()

    @property
    def solutions(self) -> IKSolutions | None:
        """The solutions of the current target (``None`` after the arm moved by its joints)."""
        with self._lock:
            return self._solutions

    @property
    def waypoints(self) -> NDArray[np.float64]:
        """The taught waypoints ``(M, n)`` [rad or m]."""
        with self._lock:
            return np.array(self._waypoints).reshape(len(self._waypoints), self.robot.n)

    @waypoints.setter
    def waypoints(self, values: ArrayLike) -> None:
        checked = joint_waypoints(self.robot, np.reshape(values, (-1, self.robot.n)))
        with self._lock:
            self._waypoints = list(checked)
            self._draw_waypoints()

    @property
    def playback(self) -> Playback | None:
        """The motion on the timeline, if any."""
        return self._playback

    @property
    def time(self) -> float:
        """Position on the timeline [s]; assign to jump there."""
        return float(self._timeline.value)

    @time.setter
    def time(self, value: float) -> None:
        if self._playback is None:
            raise InputError("no motion on the timeline: plan one or load a trajectory file first")
        self._timeline.value = float(np.clip(value, 0.0, self._playback.duration))

    def show_solutions(self, T_base_tool: ArrayLike, follow: bool | None = None) -> IKSolutions:
        """Put the IK target at ``T_base_tool`` ``(4, 4)`` [m] and show its solutions as ghost arms.

        Closed-form arms get every solution (green: inside the limits, red: outside, yellow: a
        singular family's representative); other arms the numeric solution nearest the current
        configuration. With ``follow`` (default: the page's "arm follows the handle" box) the
        arm takes the nearest solution inside the limits.

        Returns
        -------
        IKSolutions
            Empty if the target is out of reach (the panel says how far the closest pose is).
        """
        T = check_transform(T_base_tool, "target pose")
        with self._lock:
            self._move_handle(T)
            return self._solve(T, follow=self._follow.value if follow is None else follow, final=True)

    def pick(self, k: int) -> NDArray[np.float64]:
        """Move the arm to solution ``k`` (1-based, as listed in the panel) of the current target."""
        with self._lock:
            if self._solutions is None or not 1 <= k <= len(self._solutions.q):
                count = 0 if self._solutions is None else len(self._solutions.q)
                raise InputError(f"solution {k}: the current target has {count} solutions (1..{count})")
            self._take_solution(k - 1)
            return self._q.copy()

    def teach(self) -> int:
        """Append the current configuration to the waypoints; returns their number.

        Raises
        ------
        JointLimitError
            If the configuration is outside a joint limit (a trajectory could not pass it).
        """
        with self._lock:
            violations = self.robot.limit_violations(self._q)
            if violations:
                raise JointLimitError(f"cannot teach this configuration: {'; '.join(violations)}")
            self._waypoints.append(self._q.copy())
            self._draw_waypoints()
            return len(self._waypoints)

    def clear_waypoints(self) -> None:
        """Forget the taught waypoints."""
        with self._lock:
            self._waypoints.clear()
            self._draw_waypoints()

    def save_waypoints(self, path: str | Path, overwrite: bool = False) -> Path:
        """Write the taught waypoints as the CSV ``armkit traj --waypoints`` reads (rad, m).

        Raises
        ------
        InputError
            If ``path`` exists and ``overwrite`` is false, or fewer than one waypoint was taught.
        """
        with self._lock:
            if not self._waypoints:
                raise InputError("no waypoints taught yet: press 'teach waypoint' first")
            return write_waypoints(path, self.robot, self.waypoints, overwrite)

    def plan(self) -> JointTrajectory:
        """Plan the shortest minimum-jerk trajectory within the limits through the waypoints
        (``armkit traj --auto-time``) and put it on the timeline."""
        with self._lock:
            if len(self._waypoints) < 2:
                raise InputError(f"a trajectory needs at least two waypoints, {len(self._waypoints)} taught")
            trajectory = plan_trajectory(self.robot, self.waypoints)
            self.load(trajectory)
            return trajectory

    def load(self, motion: JointTrajectory | Playback | str | Path) -> Playback:
        """Put a motion on the timeline: a trajectory, samples, or a file ``armkit traj`` wrote."""
        if isinstance(motion, JointTrajectory):
            playback = Playback.from_trajectory(motion)
        elif isinstance(motion, Playback):
            playback = motion
        else:
            playback = Playback.from_file(motion, self.robot)
        if playback.q.shape[1] != self.robot.n:
            raise InputError(f"motion has {playback.q.shape[1]} joints; {self.robot.name} has {self.robot.n}")
        with self._lock:
            self.pause()
            self._playback = playback
            self._draw_path()
            self._timeline.max = playback.duration
            self._timeline.step = max(playback.duration / 1000, 1e-3)
            self._timeline.disabled = False
            self._play_button.disabled = False
            self._timeline.value = 0.0
            self._show_time(0.0)
            return playback

    def play(self, motion: JointTrajectory | Playback | str | Path | None = None) -> Playback:
        """Play ``motion`` (or the one on the timeline) from its start, in a background thread."""
        playback = self.load(motion) if motion is not None else self._playback
        if playback is None:
            raise InputError("nothing to play: plan a trajectory or load a trajectory file first")
        with self._lock:
            if self.time >= playback.duration:
                self._timeline.value = 0.0
            self._playing = True
            self._play_button.label = "pause"
            if self._player is None or not self._player.is_alive():
                self._player = threading.Thread(target=self._run_player, daemon=True)
                self._player.start()
        return playback

    def pause(self) -> None:
        """Stop the timeline where it is."""
        self._playing = False
        self._play_button.label = "play"

    def wait(self) -> None:
        """Block until the playing motion ends (or is paused)."""
        while self._playing and not self._closed:
            time.sleep(0.05)

    def serve_forever(self) -> None:
        """Block until :meth:`close` or Ctrl-C (``KeyboardInterrupt`` propagates)."""
        while not self._closed:
            time.sleep(0.2)

    def close(self) -> None:
        """Stop the web server (the page disconnects)."""
        if self._closed:
            return
        self._closed = True
        self._playing = False
        with contextlib.redirect_stdout(io.StringIO()) if not self._verbose else contextlib.nullcontext():
            self._server.stop()
        for name in SERVER_LOGGERS:
            logging.getLogger(name).removeFilter(self._message_errors)

    def __enter__(self) -> Viewer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def __repr__(self) -> str:
        return f"Viewer({self.robot.name!r}, url={self.url!r})"

    def _repr_html_(self) -> str:
        """The live page inside a Jupyter cell whose value is the viewer: an iframe on :attr:`url`.

        The browser showing the notebook loads the page, so it must reach :attr:`url` (a notebook
        on this machine does; for a remote kernel start the viewer with ``host="0.0.0.0"`` or
        forward the port).
        """
        url = html.escape(self.url, quote=True)
        return (f"<iframe src=\"{url}\" width=\"100%\" height=\"{NOTEBOOK_HEIGHT_PX}\" "
                f"style=\"border:1px solid #ddd\" data-armkit=\"viewer\"></iframe>"
                f"<div style=\"font-size:0.8em\">armkit view: {html.escape(self.robot.name)} at "
                f"<a href=\"{url}\" target=\"_blank\">{url}</a></div>")

    # ------------------------------------------------------------------ scene
    def _build_scene(self) -> None:
        scene = self._server.scene
        scene.set_up_direction("+z")
        self._server.gui.configure_theme(control_width="large", show_share_button=False)
        # looking from the front right, aimed to the right of the arm so the panel leaves it in view
        self._server.initial_camera.look_at = (0.12 * self._size, 0.16 * self._size, 0.3 * self._size)
        self._server.initial_camera.position = (0.85 * self._size, -0.7 * self._size, 0.65 * self._size)
        step = _nice_step(self._size)
        half = step * np.ceil(0.6 * self._size / step)
        scene.add_grid("/floor", width=2 * half, height=2 * half, cell_size=step / 2, section_size=step,
                       plane_opacity=0.0, shadow_opacity=0.0)
        ticks = np.arange(-half, half + step / 2, step)
        for value in ticks[np.abs(ticks) > step / 2]:
            scene.add_label(f"/floor/x{value:+.3f}", f"{value:g} m", position=(value, 0.0, 0.0),
                            font_screen_scale=0.7)
            scene.add_label(f"/floor/y{value:+.3f}", f"y {value:g} m", position=(0.0, value, 0.0),
                            font_screen_scale=0.7)
        scene.add_frame("/world", axes_length=0.6 * step, axes_radius=0.04 * step, origin_radius=0.0)
        self._arm = ArmDrawing(scene, "/arm", self.robot, self._radius, self._q)
        self._meshes: MeshDrawing | None = None
        found = link_visuals(self.robot, self._package_paths)
        self._visual_note = "" if found is None else found.summary(self.robot.name)
        if self._visual_note:  # said once: here, and in the panel
            warnings.warn(self._visual_note, UserWarning, stacklevel=3)
        elif found is not None:
            self._meshes = MeshDrawing(scene, "/visuals", found.visuals, self.robot.link_frames(self._q))
            self._arm.visible = False
        if self._scene is not None:
            draw_obstacles(scene, self._scene, self._size)
        axis = 3 * self._radius
        self._axes = scene.add_line_segments("/joint_axes", points=np.zeros((self.robot.n, 2, 3)),
                                             colors=Colours.AXIS, thickness=0.25 * self._radius)
        self._axis_length = axis
        frames = self.robot.n + 2
        self._frames = scene.add_batched_axes("/link_frames",
                                              batched_wxyzs=np.tile([1.0, 0, 0, 0], (frames, 1)),
                                              batched_positions=np.zeros((frames, 3)),
                                              axes_length=2.5 * self._radius, axes_radius=0.12 * self._radius)
        self._ghosts = [ArmDrawing(scene, f"/ghost/{k}", self.robot, 0.8 * self._radius, self._q, opacity=0.3)
                        for k in range(MAX_GHOSTS)]
        self._ghost_labels = [scene.add_label(f"/ghost/{k}/label", f"#{k + 1}", visible=False)
                              for k in range(MAX_GHOSTS)]
        for ghost in self._ghosts:
            ghost.visible = False
        vertices, faces = unit_sphere()
        self._ellipsoid = scene.add_batched_meshes_simple(
            "/ellipsoid", vertices, faces, batched_wxyzs=[[1.0, 0, 0, 0]], batched_positions=[[0.0, 0, 0]],
            batched_scales=[[1.0, 1.0, 1.0]], batched_colors=(90, 200, 255), opacity=0.35, visible=False,
            lod="off", cast_shadow=False, receive_shadow=False)
        self._waypoint_markers = scene.add_batched_meshes_simple(
            "/waypoints", vertices, faces, batched_wxyzs=np.zeros((0, 4)), batched_positions=np.zeros((0, 3)),
            batched_scales=np.zeros((0,)), batched_colors=Colours.WAYPOINT, lod="off")
        self._waypoint_labels: list[Any] = []
        self._path = None
        self._handle = scene.add_transform_controls("/target", scale=0.22 * self._size, depth_test=False,
                                                    position=self._target[:3, 3],
                                                    wxyz=quaternion_wxyz_from_matrix(self._target[:3, :3]))
        self._handle.on_update(self._on_handle)

    def _draw_arm(self) -> None:
        placement = self._arm.placement
        ends = np.stack([placement.joint_origins - self._axis_length * placement.joint_axes,
                         placement.joint_origins + self._axis_length * placement.joint_axes], axis=1)
        self._axes.points = ends
        frames = placement.link_frames
        if self._meshes is not None:
            self._meshes.update(frames)
        self._frames.batched_positions = frames[:, :3, 3]
        self._frames.batched_wxyzs = quaternion_wxyz_from_matrix(frames[:, :3, :3])
        if self._show_ellipsoid.value:
            R, semi = ellipsoid_axes(self.robot, self._q)
            self._ellipsoid.batched_positions = frames[-1:, :3, 3]
            self._ellipsoid.batched_wxyzs = quaternion_wxyz_from_matrix(R)[None]
            self._ellipsoid.batched_scales = np.maximum(semi * ELLIPSOID_SECONDS, 1e-4)[None]

    def _redraw(self) -> None:
        with self._server.atomic():
            self._arm.update(self._q)
            if self._scene is not None:
                colour_contacts(self._arm, self._scene, self._q, Colours.LINK, Colours.JOINT)
            self._draw_arm()
        self._readout.content = readout.pose_html(self.robot, self._q, self.robot.fk(self._q),
                                                  self._convention.value, self._degrees)

    def _move_handle(self, T: NDArray[np.float64]) -> None:
        self._target = T.copy()
        with self._server.atomic():
            self._handle.position = T[:3, 3]
            self._handle.wxyz = quaternion_wxyz_from_matrix(T[:3, :3])

    def _draw_waypoints(self) -> None:
        positions = (self.robot.fk(np.array(self._waypoints))[:, :3, 3] if self._waypoints
                     else np.zeros((0, 3)))
        with self._server.atomic():
            self._waypoint_markers.batched_positions = positions
            self._waypoint_markers.batched_wxyzs = np.tile([1.0, 0, 0, 0], (len(positions), 1))
            self._waypoint_markers.batched_scales = np.full(len(positions), 0.8 * self._radius)
        for label in self._waypoint_labels:
            label.remove()
        self._waypoint_labels = [self._server.scene.add_label(f"/waypoint_labels/{k}", f"W{k + 1}",
                                                              position=p + [0, 0, 3 * self._radius])
                                 for k, p in enumerate(positions)]
        self._waypoint_list.content = readout.waypoints_html(self.robot, self._waypoints, self._degrees)
        self._plan_button.disabled = len(self._waypoints) < 2

    def _draw_path(self) -> None:
        if self._path is not None:
            self._path.remove()
        stride = max(1, len(self._playback.q) // 400)
        points = self.robot.fk(self._playback.q[::stride])[:, :3, 3]
        if len(self._playback.q) % stride != 1:
            points = np.vstack([points, self.robot.fk(self._playback.q[-1])[:3, 3]])
        segments = np.stack([points[:-1], points[1:]], axis=1)
        self._path = self._server.scene.add_line_segments("/tool_path", points=segments, colors=Colours.PATH,
                                                          thickness=0.3 * self._radius)

    # ------------------------------------------------------------------ GUI
    def _build_gui(self) -> None:
        gui = self._server.gui
        gui.add_markdown(f"**{self.robot.name}**: {self.robot.n} joints, "
                         f"{'closed-form' if self.closed_form else 'numeric'} IK")
        if self._visual_note:
            gui.add_html(f"<div style='font-size:0.8em;color:#a60' data-armkit='visual-note'>"
                         f"{html.escape(self._visual_note)}</div>")
        with gui.add_folder("Joints"):
            self._units = gui.add_dropdown("angles", ("deg", "rad"), initial_value="deg")
            self._units.on_update(lambda _: self._rebuild_sliders())
            self._slider_folder = gui.add_folder("q", expand_by_default=True)
            self._sliders: list[Any] = []
            self._name_rows: list[Any] = []
            self._slider_decimals: list[int] = []
            self._rebuild_sliders()
            gui.add_button("home").on_click(lambda _: self._guarded(self._home))
        with gui.add_folder("Tool pose"):
            self._convention = gui.add_dropdown("convention", readout.angle_conventions(),
                                                initial_value="xyz-fixed")
            self._convention.on_update(lambda _: self._guarded(self._redraw))
            self._readout = gui.add_html("")
            self._show_frames = gui.add_checkbox("link frames", True)
            self._show_frames.on_update(lambda _: setattr(self._frames, "visible", self._show_frames.value))
            if self._meshes is not None:
                self._show_meshes = gui.add_checkbox(
                    "meshes", True, hint="the URDF's visual meshes; off: capsules (joints at a limit in red)")
                self._show_meshes.on_update(lambda _: self._guarded(self._toggle_meshes))
            self._show_ellipsoid = gui.add_checkbox("velocity ellipsoid", False,
                                                    hint=f"tool velocities for unit joint-rate norm, "
                                                         f"drawn for {ELLIPSOID_SECONDS} s")
            self._show_ellipsoid.on_update(lambda _: self._guarded(self._toggle_ellipsoid))
            gui.add_button("copy q").on_click(lambda _: self._guarded(self._copy_q))
            gui.add_button("copy pose").on_click(lambda _: self._guarded(self._copy_pose))
            self._copy = gui.add_text("copy this", "", hint="select and copy (Ctrl-C)")
        with gui.add_folder("Inverse kinematics"):
            self._follow = gui.add_checkbox("arm follows the handle", True,
                                            hint="the arm takes the nearest solution inside the limits")
            self._solution_pick = gui.add_dropdown("solution", ("-",), initial_value="-", disabled=True)
            self._solution_pick.on_update(lambda _: self._guarded(self._on_pick))
            self._ik_status = gui.add_html("<div style='font-size:0.8em' data-armkit='ik-summary'>"
                                           "drag the handle at the tool to solve IK</div>")
            gui.add_button("handle to tool").on_click(lambda _: self._guarded(self._handle_to_tool))
        with gui.add_folder("Waypoints and trajectory"):
            self._teach_button = gui.add_button("teach waypoint")
            self._teach_button.on_click(lambda _: self._guarded(self.teach))
            gui.add_button("clear waypoints").on_click(lambda _: self._guarded(self.clear_waypoints))
            self._waypoint_list = gui.add_html(readout.waypoints_html(self.robot, [], True))
            self._plan_button = gui.add_button("plan through waypoints (auto time)", disabled=True)
            self._plan_button.on_click(lambda _: self._guarded(self.plan))
            self._trajectory_file = gui.add_text("trajectory file", "traj.csv")
            gui.add_button("load trajectory file").on_click(
                lambda _: self._guarded(lambda: self.load(self._trajectory_file.value)))
            self._timeline = gui.add_slider("time [s]", min=0.0, max=1.0, step=0.01, initial_value=0.0,
                                            disabled=True)
            self._timeline.on_update(lambda _: self._guarded(lambda: self._show_time(self._timeline.value)))
            self._play_button = gui.add_button("play", disabled=True)
            self._play_button.on_click(lambda _: self._guarded(self._toggle_play))
            self._play_status = gui.add_html("")
            self._waypoint_file = gui.add_text("waypoints file", "waypoints.csv")
            self._save_button = gui.add_button("save waypoints")
            self._save_button.on_click(lambda event: self._guarded(lambda: self._save_clicked(event)))
        self._status = gui.add_html("")

    @property
    def _degrees(self) -> bool:
        return self._units.value == "deg"

    def _in_degrees(self, j: int) -> bool:
        return self._degrees and not self.robot.chain.prismatic[j]

    def _to_slider(self, j: int, value: float) -> float:
        return float(np.degrees(value)) if self._in_degrees(j) else float(value)

    def _from_slider(self, j: int, value: float) -> float:
        return float(np.radians(value)) if self._in_degrees(j) else float(value)

    def _rebuild_sliders(self) -> None:
        with self._lock:
            for element in (*self._sliders, *self._name_rows):
                element.remove()
            self._sliders, self._name_rows, self._slider_decimals = [], [], []
            units = ["m" if prismatic else self._units.value for prismatic in self.robot.chain.prismatic]
            # names too long for the label column get a full-width row of their own (wrapping if need be)
            long_names = any(len(f"{name} [{unit}]") > readout.LABEL_CHARS
                             for name, unit in zip(self.robot.joint_names, units, strict=True))
            with self._slider_folder:
                for j, (name, (lower, upper)) in enumerate(zip(self.robot.joint_names, self.robot.limits,
                                                              strict=True)):
                    prismatic = self.robot.chain.prismatic[j]
                    span = self._size if prismatic else np.pi
                    lower = lower if np.isfinite(lower) else -span
                    upper = upper if np.isfinite(upper) else span
                    label = f"{name} [{units[j]}]"
                    if long_names:
                        self._name_rows.append(self._server.gui.add_html(readout.joint_name_html(j, label)))
                        label = f"q{j + 1} [{units[j]}]"
                    low, high = self._to_slider(j, lower), self._to_slider(j, upper)
                    most = 4 if prismatic else (1 if self._degrees else 3)
                    decimals = readout.box_decimals(low, high, most)
                    shown = readout.box_range(low, high, decimals)
                    self._slider_decimals.append(decimals)
                    slider = self._server.gui.add_slider(
                        label, min=shown[0], max=shown[1], step=10.0 ** -decimals,
                        initial_value=self._slider_value(j, np.clip(self._q[j], lower, upper), *shown))
                    slider.on_update(lambda _, j=j: self._guarded(lambda: self._on_slider(j)))
                    self._sliders.append(slider)
            if hasattr(self, "_readout"):
                self._redraw()
                self._waypoint_list.content = readout.waypoints_html(self.robot, self._waypoints,
                                                                     self._degrees)
                if self._solutions is not None:
                    self._show_list()

    def _slider_value(self, j: int, value: float, low: float, high: float) -> float:
        """Joint ``j``'s ``value`` [rad or m] as its slider shows it: unit, box precision, range."""
        return float(np.clip(round(self._to_slider(j, value), self._slider_decimals[j]), low, high))

    def _sync_sliders(self) -> None:
        self._syncing = True
        try:
            for j, slider in enumerate(self._sliders):
                slider.value = self._slider_value(j, self._q[j], slider.min, slider.max)
        finally:
            self._syncing = False

    def _guarded(self, action) -> None:
        """Run a GUI action; an armkit error becomes the status line instead of a traceback."""
        with self._lock:
            self._status.content = ""
            try:
                action()
            except ArmkitError as exc:
                self._status.content = (f"<div style='color:#d33;font-size:0.8em' data-armkit='error'>"
                                        f"{html.escape(str(exc))}</div>")

    # ------------------------------------------------------------------ state changes
    def _set_q(self, q: NDArray[np.float64], from_ik: bool = False) -> None:
        self._q = np.array(q, dtype=float)
        self._sync_sliders()
        if not from_ik:  # before the pose read-out: a page that shows the new pose has the handle there
            self._move_handle(self.robot.fk(self._q))
        self._redraw()

    def _on_slider(self, j: int) -> None:
        if self._syncing:
            return
        q = self._q.copy()
        q[j] = self._from_slider(j, self._sliders[j].value)
        self._set_q(q)
        self._clear_solutions("move the handle at the tool to solve IK")

    def _home(self) -> None:
        self.q = self.robot.home

    def _toggle_meshes(self) -> None:
        self._meshes.visible = self._show_meshes.value
        self._arm.visible = not self._show_meshes.value

    def _toggle_ellipsoid(self) -> None:
        self._ellipsoid.visible = self._show_ellipsoid.value
        self._redraw()

    def _copy_q(self) -> None:
        self._copy.value = readout.copy_q_text(self.source, self._q)

    def _copy_pose(self) -> None:
        self._copy.value = readout.copy_pose_text(self.source, self.robot.fk(self._q), self._convention.value,
                                                  self.closed_form)

    def _handle_to_tool(self) -> None:
        self._move_handle(self.robot.fk(self._q))
        self._clear_solutions("move the handle at the tool to solve IK")

    def _on_handle(self, event: Any) -> None:
        handle = event.target
        final = getattr(event, "phase", "end") == "end"

        def solve() -> None:  # the pose is read inside the guard: a zero quaternion is an error line
            R = matrix_from_quaternion_wxyz(np.asarray(handle.wxyz))
            T = transform_from(R, np.asarray(handle.position))
            self._target = T
            self._solve(T, follow=self._follow.value, final=final)

        self._guarded(solve)

    def _clear_solutions(self, message: str) -> None:
        self._solutions, self._solution_index = None, None
        for ghost, label in zip(self._ghosts, self._ghost_labels, strict=True):
            ghost.visible = False
            label.visible = False
        self._ik_status.content = f"<div style='font-size:0.8em' data-armkit='ik-summary'>{message}</div>"
        self._set_pick_options(("-",), disabled=True)

    def _set_pick_options(self, options: tuple[str, ...], disabled: bool, value: str | None = None) -> None:
        self._syncing = True
        try:
            self._solution_pick.options = options
            self._solution_pick.value = options[0] if value is None else value
            self._solution_pick.disabled = disabled
        finally:
            self._syncing = False

    def _numeric_solutions(self, T: NDArray[np.float64]) -> IKSolutions:
        """The numeric solution nearest ``q`` (inside the limits, else outside them) as a one-row list."""
        try:
            q = self.robot.ik(T, near=self._q)
        except JointLimitError:
            q = self.robot.ik(T, near=self._q, within_limits=False)
        residual = pose_error(T, self.robot.fk(q))
        return IKSolutions(q[None], self.robot.within_limits(q)[None], np.zeros(1, dtype=bool),
                           np.linalg.norm(residual[:3])[None], np.linalg.norm(residual[3:])[None])

    def _solve(self, T: NDArray[np.float64], follow: bool, final: bool) -> IKSolutions:
        try:
            # each solution once: a whole-turn copy looks the same as its solution in the scene
            found = (ik_solutions(self.robot, T, near=self._q, turn_copies=False) if self.closed_form
                     else self._numeric_solutions(T))
        except UnreachableError as exc:
            found = IKSolutions(np.zeros((0, self.robot.n)), *(np.zeros(0, dtype=bool),) * 2,
                                *(np.zeros(0),) * 2)
            self._unreachable(found, exc.position_error, exc.orientation_error)
            return found
        if len(found.q) == 0:
            self._unreachable(found, *self._distance(T, final))
            return found
        self._solutions = found
        self._solution_index = None
        if len(found.q) > MAX_GHOSTS:
            self._status.content = (f"<div style='font-size:0.8em'>{len(found.q)} solutions; the first "
                                    f"{MAX_GHOSTS} are drawn</div>")
        for k, ghost in enumerate(self._ghosts[:len(found.q)]):
            colour = (Colours.GHOST_OUT if not found.within_limits[k] else
                      Colours.GHOST_FAMILY if found.family[k] else Colours.GHOST_IN)
            with self._server.atomic():
                ghost.update(found.q[k])
                ghost.colour(colour, colour)
        drawn = self._ghosts[:len(found.q)]
        # each label at a joint of its ghost away from the others' labels: no two overlap
        first = min(1, self.robot.n - 1)  # the first joint's origin is every ghost's
        positions = label_positions([ghost.placement.joint_origins[first:] for ghost in drawn],
                                    LABEL_SPACING * self._radius)
        for k, (ghost, label) in enumerate(zip(self._ghosts, self._ghost_labels, strict=True)):
            shown = k < len(drawn)
            if shown:
                label.position = positions[k]
            ghost.visible = shown
            label.visible = shown
        inside = np.flatnonzero(found.within_limits)
        if follow and len(inside):
            self._take_solution(int(inside[0]))
        else:
            self._show_list()
        return found

    def _distance(self, T: NDArray[np.float64], final: bool) -> tuple[float, float]:
        """How far the closest pose is (only once the drag ends: the search takes a while)."""
        if not final:
            return float("nan"), float("nan")
        try:
            self.robot.ik(T, near=self._q, within_limits=False)
        except UnreachableError as exc:
            return exc.position_error, exc.orientation_error
        return 0.0, 0.0

    def _unreachable(self, found: IKSolutions, position_error: float, orientation_error: float) -> None:
        self._clear_solutions("")
        self._solutions = found
        how_far = ("" if np.isnan(position_error) else
                   f": the closest pose found is {position_error * 1000:.1f} mm and "
                   f"{np.degrees(orientation_error):.1f}° away")
        self._ik_status.content = (f"<div style='font-size:0.8em;color:#d33' data-armkit='ik-summary' "
                                   f"data-unreachable='true'>target out of reach{how_far}</div>")

    def _show_list(self) -> None:
        found = self._solutions
        method = "closed form" if self.closed_form else "numeric, nearest the arm"
        self._ik_status.content = readout.solutions_html(self.robot, found, self._solution_index,
                                                         self._degrees, method)
        options = tuple(f"{k + 1}: {'in limits' if ok else 'OUT of limits'}"
                        f"{', singular family' if family else ''}"
                        for k, (ok, family) in enumerate(zip(found.within_limits, found.family, strict=True)))
        self._set_pick_options(options, disabled=False,
                               value=None if self._solution_index is None else options[self._solution_index])

    def _take_solution(self, k: int) -> None:
        self._solution_index = k
        self._set_q(self._solutions.q[k], from_ik=True)
        self._show_list()

    def _on_pick(self) -> None:
        if self._syncing or self._solutions is None or self._solution_pick.value == "-":
            return
        self._take_solution(int(self._solution_pick.value.split(":")[0]) - 1)

    # ------------------------------------------------------------------ timeline
    def _show_time(self, t: float) -> None:
        if self._playback is None:
            return
        q, _, _ = self._playback.at(t)
        velocity, acceleration = self._playback.at_limits(self.robot, t)
        self._set_q(q)
        self._clear_solutions("move the handle at the tool to solve IK")
        self._arm.colour(Colours.LINK, Colours.JOINT, velocity | acceleration)
        names = self.robot.joint_names
        flagged = ([f"{names[j]} at its velocity limit" for j in np.flatnonzero(velocity)]
                   + [f"{names[j]} at its acceleration limit" for j in np.flatnonzero(acceleration)])
        self._play_status.content = (
            f"<div style='font-size:0.8em' data-armkit='playback'>{self._playback.source}: "
            f"t = <span data-armkit='time'>{t:.2f}</span> of {self._playback.duration:.2f} s"
            f"<div data-armkit='at-limit' style='color:#d33'>{'; '.join(flagged)}</div></div>")

    def _toggle_play(self) -> None:
        if self._playing:
            self.pause()
        else:
            self.play()

    def _run_player(self) -> None:
        last = time.perf_counter()
        while self._playing and not self._closed:
            time.sleep(1 / PLAY_RATE_HZ)
            now = time.perf_counter()
            with self._lock:
                if not self._playing or self._playback is None:
                    break
                t = min(self.time + (now - last), self._playback.duration)
                self._timeline.value = t
                if t >= self._playback.duration:
                    self.pause()
            last = now

    # ------------------------------------------------------------------ saving
    def _save_clicked(self, event: Any) -> None:
        path = Path(self._waypoint_file.value)
        if not path.exists():
            self._saved(self.save_waypoints(path))
            return
        client = event.client
        with client.gui.add_modal("Replace the file?") as modal:
            client.gui.add_markdown(f"`{path}` exists. Replace it with {len(self._waypoints)} waypoints?")
            replace = client.gui.add_button("replace", color="red")
            cancel = client.gui.add_button("cancel")

        def do_replace(_: Any) -> None:
            self._guarded(lambda: self._saved(self.save_waypoints(path, overwrite=True)))
            modal.close()

        replace.on_click(do_replace)
        cancel.on_click(lambda _: modal.close())

    def _saved(self, path: Path) -> None:
        self._status.content = (f"<div style='font-size:0.8em' data-armkit='saved'>saved "
                                f"{len(self._waypoints)} waypoints to {html.escape(str(path))}</div>")
