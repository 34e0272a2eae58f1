"""``armkit.view.Viewer``: the arm in a browser (viser), with joint sliders, IK ghosts and a timeline.

The viewer runs a local web server (viser's, in a background thread) and keeps the state here in
Python: the configuration ``q``; its parts keep theirs, one module each: the joint sliders
(:mod:`~armkit.view.joint_sliders`), the arm drawn and its tool pose read out
(:mod:`~armkit.view.arm_panel`), the IK target and its solutions (:mod:`~armkit.view.ik_ghosts`), a
7-joint arm's self-motion (:mod:`~armkit.view.self_motion_ghosts`), the taught waypoints
(:mod:`~armkit.view.teach_panel`, :mod:`~armkit.view.waypoint_saving`) and the motion on the
timeline (:mod:`~armkit.view.timeline`). The page and the Python API change the same state; every
change redraws the scene and the read-outs for every connected browser.

What a part may use of the viewer, and nothing else: to build, ``robot``, ``_server`` (its scene
and panel), ``_radius``, ``_size`` and ``_scene``; to read, ``q``, ``closed_form``, ``_degrees`` (the
panel's angle unit) and ``_closed``; to act, the public API (a part's control does what the method
of the same name does), :meth:`Viewer._set_q` (move the arm), :meth:`Viewer._play_q` (the timeline
moved the arm), :meth:`Viewer._redraw`, :meth:`Viewer._units_changed`, :meth:`Viewer._show_status`
(the status line under the panel) and :meth:`Viewer._guarded` (run a page action under ``_lock``,
an armkit error becoming the status line); the timeline takes ``_lock`` for each step of its
thread. The viewer uses a part only through its public methods and attributes.
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

from armkit.errors import ArmkitError, InputError
from armkit.ik.self_motion import SelfMotion
from armkit.ik.self_motion import self_motion as sample_self_motion
from armkit.ik.solve import IKSolutions
from armkit.ik.structure import analyze_structure
from armkit.robot import Robot
from armkit.robot_file import load
from armkit.spatial.transforms import check_transform
from armkit.trajectory.joint_trajectory import JointTrajectory
from armkit.trajectory.waypoints import write_waypoints
from armkit.view.arm_panel import ArmPanel
from armkit.view.floor import add_floor
from armkit.view.geometry import arm_size
from armkit.view.ik_ghosts import IKGhosts
from armkit.view.joint_sliders import JointSliders
from armkit.view.meshes import link_visuals
from armkit.view.playback import Playback
from armkit.view.self_motion_ghosts import SAMPLES, SelfMotionGhosts
from armkit.view.server_log import SERVER_LOGGERS, OneLineMessageErrors
from armkit.view.teach_panel import TeachPanel
from armkit.view.timeline import Timeline
from armkit.view.waypoint_saving import WaypointSaving

if TYPE_CHECKING:  # armkit.collision needs MuJoCo only when a scene is given
    from armkit.collision.scene import Scene

__all__ = ["Viewer"]

#: Height of the page inside a notebook cell [px] (:meth:`Viewer._repr_html_`).
NOTEBOOK_HEIGHT_PX = 600


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
        self._q = self.robot.home if q is None else self.robot.check_q(q).copy()
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
        try:
            self._build(package_paths)
            self._redraw()
        except BaseException:  # nothing left listening on the port
            self.close()
            raise

    def _build(self, package_paths: Sequence[str | Path]) -> None:
        """The scene and the panel, part by part, in the panel's order."""
        self._server.gui.configure_theme(control_width="large", show_share_button=False)
        add_floor(self._server, self._size)
        found = link_visuals(self.robot, package_paths)
        visual_note = "" if found is None else found.summary(self.robot.name)
        if visual_note:  # said once: here, and in the panel
            warnings.warn(visual_note, UserWarning, stacklevel=3)
        gui = self._server.gui
        gui.add_markdown(f"**{self.robot.name}**: {self.robot.n} joints, "
                         f"{'closed-form' if self.closed_form else 'numeric'} IK")
        if visual_note:
            gui.add_html(f"<div style='font-size:0.8em;color:#a60' data-armkit='visual-note'>"
                         f"{html.escape(visual_note)}</div>")
        self._joints = JointSliders(self)
        self._arm_panel = ArmPanel(self, None if found is None or visual_note else found.visuals)
        self._ik = IKGhosts(self)
        self._self_motion = SelfMotionGhosts(self) if self.robot.n == 7 else None
        with gui.add_folder("Waypoints and trajectory"):
            self._teach = TeachPanel(self)
            self._timeline = Timeline(self)
            self._saving = WaypointSaving(self)
        self._status = gui.add_html("")

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
            self._ik.clear()

    @property
    def target(self) -> NDArray[np.float64]:
        """The IK target (the handle's pose) ``(4, 4)`` [m]."""
        with self._lock:
            return self._ik.target.copy()

    @property
    def solutions(self) -> IKSolutions | None:
        """The solutions of the current target (``None`` after the arm moved by its joints)."""
        with self._lock:
            return self._ik.solutions

    @property
    def self_motion(self) -> SelfMotion | None:
        """The self-motion shown (:meth:`show_self_motion`; ``None`` once the arm left its target)."""
        with self._lock:
            return None if self._self_motion is None else self._self_motion.motion

    @property
    def waypoints(self) -> NDArray[np.float64]:
        """The taught waypoints ``(M, n)`` [rad or m]."""
        with self._lock:
            return self._teach.as_array()

    @waypoints.setter
    def waypoints(self, values: ArrayLike) -> None:
        with self._lock:
            self._teach.replace(values)

    @property
    def playback(self) -> Playback | None:
        """The motion on the timeline, if any."""
        return self._timeline.playback

    @property
    def time(self) -> float:
        """Position on the timeline [s]; assign to jump there."""
        return float(self._timeline.slider.value)

    @time.setter
    def time(self, value: float) -> None:
        if self._timeline.playback is None:
            raise InputError("no motion on the timeline: plan one or load a trajectory file first")
        self._timeline.slider.value = float(np.clip(value, 0.0, self._timeline.playback.duration))

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
            self._ik.move_handle(T)
            return self._ik.solve(T, follow=self._ik.follow.value if follow is None else follow, final=True)

    def pick(self, k: int) -> NDArray[np.float64]:
        """Move the arm to solution ``k`` (1-based, as listed in the panel) of the current target."""
        with self._lock:
            solutions = self._ik.solutions
            if solutions is None or not 1 <= k <= len(solutions.q):
                count = 0 if solutions is None else len(solutions.q)
                raise InputError(f"solution {k}: the current target has {count} solutions (1..{count})")
            self._ik.take(k - 1)
            return self._q.copy()

    def show_self_motion(self, free_joint: int | str, T_base_tool: ArrayLike | None = None, *,
                         samples: int = SAMPLES) -> SelfMotion:
        """Show the self-motion of a 7-joint arm at ``T_base_tool`` (default: the IK target) along
        ``free_joint``: every branch sampled (:func:`armkit.self_motion`), ghost arms along the branch
        nearest the arm, and the arm moved onto that branch; the panel's slider then moves the arm
        along it (:meth:`move_along_self_motion`).

        Parameters
        ----------
        free_joint : int or str
            The joint swept: a 0-based index or a joint name.
        T_base_tool : array_like (4, 4), optional
            The tool pose [m]; the IK handle moves there.
        samples : int
            Values of the free joint, spread evenly over its limits (2 to 100000; sampled outside
            the viewer's lock, so the page and a playing motion go on meanwhile).

        Returns
        -------
        SelfMotion
            ``q`` ``(branches, samples, 7)``, NaN where a branch does not exist.

        Raises
        ------
        InputError
            For an arm without seven joints, an unknown joint or a bad sample count (nothing changes
            then), or if ``T_base_tool`` is not given and the IK target moved while its self-motion
            was sampled (sample again).

        Examples
        --------
        >>> import numpy as np
        >>> from armkit.view import Viewer
        >>> viewer = Viewer("panda", port=0)
        >>> motion = viewer.show_self_motion(2, samples=9)         # q3 free, at the tool's pose
        >>> motion.q.shape[1:], bool(np.allclose(viewer.robot.fk(viewer.q), viewer.target, atol=1e-9))
        ((9, 7), True)
        >>> viewer.close()
        """
        part = self._self_motion_part()
        if T_base_tool is None:
            with self._lock:
                T = asked = self._ik.target.copy()
        else:
            T, asked = check_transform(T_base_tool, "target pose"), None
        # sampled outside the lock (seconds for hundreds of values): the page and the player go on
        motion = sample_self_motion(self.robot, T, free_joint=free_joint, samples=samples)
        with self._lock:
            if asked is not None and not np.array_equal(self._ik.target, asked):
                raise InputError("self-motion: the IK target moved while its self-motion was sampled; "
                                 "sample again")
            self._ik.move_handle(T)
            self._ik.clear()
            part.show(motion, T)
            return motion

    def move_along_self_motion(self, value: float, branch: int | None = None) -> NDArray[np.float64]:
        """Move the arm along the self-motion shown to its sample whose free-joint value is nearest
        ``value`` (a revolute joint's modulo a turn): the samples are the values
        :attr:`self_motion` lists, so the arm lands on ``value`` only if it is one of them.

        Parameters
        ----------
        value : float
            The free joint's value [rad, or m for a prismatic joint]; a finite number.
        branch : int, optional
            The branch (1-based, as listed in the panel); default: the branch shown.

        Returns
        -------
        ndarray (7,)
            The arm's configuration [rad or m]; its tool stays on the target.

        Raises
        ------
        InputError
            If no self-motion is shown, ``value`` is not a finite number, ``branch`` is not a whole
            number from 1 to the number of branches, or the branch has no solution at that value.

        Examples
        --------
        >>> from armkit.view import Viewer
        >>> viewer = Viewer("panda", port=0)
        >>> motion = viewer.show_self_motion(2, samples=9)         # q3 at -2.8973, ..., 2.8973 rad
        >>> q = viewer.move_along_self_motion(0.8)                  # the sample at 0.7243 rad
        >>> round(float(q[2]), 4), bool(q[2] == motion.values[5])
        (0.7243, True)
        >>> viewer.close()
        """
        part = self._self_motion_part()
        with self._lock:
            motion = part.require_motion()
            name = self.robot.joint_names[motion.free_joint]
            unit = "m" if self.robot.chain.prismatic[motion.free_joint] else "rad"
            number = isinstance(value, int | float | np.integer | np.floating) and not isinstance(value, bool)
            if not number or not np.isfinite(value):
                raise InputError(f"value: expected a finite value of {name} [{unit}], got {value!r}")
            count = len(motion.q)
            whole = isinstance(branch, int | np.integer) and not isinstance(branch, bool)
            if branch is not None and not (whole and 1 <= branch <= count):
                raise InputError(f"branch {branch!r}: the self-motion has {count} branches; expected a whole "
                                 f"number from 1 to {count}")
            return part.move_to(float(value), None if branch is None else int(branch) - 1)

    def _self_motion_part(self) -> SelfMotionGhosts:
        if self._self_motion is None:
            raise InputError(f"self-motion: needs a 7-joint arm (one joint free, six solved in closed form); "
                             f"{self.robot.name} has {self.robot.n}")
        return self._self_motion

    def teach(self) -> int:
        """Append the current configuration to the waypoints; returns their number.

        Raises
        ------
        JointLimitError
            If the configuration is outside a joint limit (a trajectory could not pass it).
        """
        with self._lock:
            return self._teach.teach(self._q)

    def clear_waypoints(self) -> None:
        """Forget the taught waypoints."""
        with self._lock:
            self._teach.clear()

    def save_waypoints(self, path: str | Path, overwrite: bool = False) -> Path:
        """Write the taught waypoints as the CSV ``armkit traj --waypoints`` reads (rad, m).

        Raises
        ------
        InputError
            If ``path`` exists and ``overwrite`` is false, or fewer than one waypoint was taught.
        """
        with self._lock:
            if not self._teach.waypoints:
                raise InputError("no waypoints taught yet: press 'teach waypoint' first")
            return write_waypoints(path, self.robot, self.waypoints, overwrite)

    def plan(self) -> JointTrajectory:
        """Plan the shortest minimum-jerk trajectory within the limits through the waypoints
        (``armkit traj --auto-time``) and put it on the timeline."""
        with self._lock:
            trajectory = self._teach.plan()
            self.load(trajectory)
            return trajectory

    def load(self, motion: JointTrajectory | Playback | str | Path) -> Playback:
        """Put a motion on the timeline: a trajectory, samples, or a file ``armkit traj`` wrote."""
        return self._timeline.load(motion)

    def play(self, motion: JointTrajectory | Playback | str | Path | None = None) -> Playback:
        """Play ``motion`` (or the one on the timeline) from its start, in a background thread."""
        if motion is not None:
            self.load(motion)
        self._timeline.play()
        return self._timeline.playback

    def pause(self) -> None:
        """Stop the timeline where it is."""
        self._timeline.pause()

    def wait(self) -> None:
        """Block until the playing motion ends (or is paused)."""
        while self._timeline.playing and not self._closed:
            time.sleep(0.05)

    def serve_forever(self) -> None:
        """Block until :meth:`close` or Ctrl-C (``KeyboardInterrupt`` propagates)."""
        while not self._closed:
            time.sleep(0.2)

    def close(self) -> None:
        """Stop the playing motion and the web server (the page disconnects)."""
        with self._lock:  # the player checks _closed under the lock: no step after this one
            if self._closed:
                return
            self._closed = True
            if hasattr(self, "_timeline"):  # absent if building the panel failed
                self._timeline.pause()
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

    # ------------------------------------------------------------------ what the parts call
    def _set_q(self, q: NDArray[np.float64], from_ik: bool = False) -> None:
        """Move the arm to ``q``; unless it comes from IK, the handle goes to the tool."""
        self._q = np.array(q, dtype=float)
        self._joints.sync(self._q)
        if not from_ik:  # before the pose read-out: a page that shows the new pose has the handle there
            self._ik.move_handle(self.robot.fk(self._q))
        if self._self_motion is not None:
            self._self_motion.arm_moved(self._q)
        self._redraw()

    def _play_q(self, q: NDArray[np.float64], at_limit: NDArray[np.bool_]) -> None:
        """The timeline moved the arm to ``q``: the joints flagged ``at_limit`` ``(n,)`` drawn red, the
        IK solutions forgotten."""
        self._set_q(q)
        self._ik.clear()
        self._arm_panel.show_at_limit(at_limit)

    def _redraw(self) -> None:
        self._arm_panel.draw(self._q, self._degrees)

    @property
    def _degrees(self) -> bool:
        """The panel shows revolute joints in degrees (else radians)."""
        return self._joints.degrees

    def _show_status(self, content: str) -> None:
        """Put ``content`` (HTML; anything a user wrote in it escaped) in the status line."""
        self._status.content = content

    def _units_changed(self) -> None:
        """The angle unit changed: the sliders and every list of joint values again."""
        with self._lock:
            self._joints.rebuild(self._q)
            self._redraw()
            self._teach.refresh_list()
            self._ik.refresh_list()
            if self._self_motion is not None:
                self._self_motion.refresh_units()

    def _guarded(self, action, locked: bool = True) -> None:
        """Run a GUI action; an armkit error becomes the status line instead of a traceback. Under the
        viewer's lock, unless ``locked`` is false (an action that takes the lock itself, for a while)."""
        with self._lock:
            self._show_status("")
        try:
            with self._lock if locked else contextlib.nullcontext():
                action()
        except ArmkitError as exc:
            with self._lock:
                self._show_status(f"<div style='color:#d33;font-size:0.8em' data-armkit='error'>"
                                  f"{html.escape(str(exc))}</div>")
