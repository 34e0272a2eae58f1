"""The viewer's timeline: a motion (:class:`~armkit.view.playback.Playback`) played on the arm.

A slider over the motion's time, ``play``/``pause`` (a background thread moves the time on at
:data:`PLAY_RATE_HZ`), the tool path traced in the scene, and the joints at their velocity or
acceleration limit named and drawn red.
"""

from __future__ import annotations

import threading
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from armkit.errors import InputError
from armkit.trajectory.joint_trajectory import JointTrajectory
from armkit.view.playback import Playback
from armkit.view.scene import Colours

if TYPE_CHECKING:
    from armkit.view.viewer import Viewer

__all__ = ["PLAY_RATE_HZ", "Timeline"]

#: Frames per second of the timeline while playing.
PLAY_RATE_HZ = 30.0


class Timeline:
    """The motion on the timeline, its slider, ``play``/``pause`` and the thread that plays it.

    Attributes
    ----------
    playback : Playback or None
        The motion on the timeline.
    player : threading.Thread or None
        The thread moving the time on while playing (it ends at a pause).
    """

    def __init__(self, viewer: Viewer) -> None:
        self._viewer = viewer
        self._robot = viewer.robot
        self.playback: Playback | None = None
        self.player: threading.Thread | None = None
        self._playing = False
        self._path: Any = None
        gui = viewer._server.gui
        self._file = gui.add_text("trajectory file", "traj.csv")
        gui.add_button("load trajectory file").on_click(
            lambda _: viewer._guarded(lambda: viewer.load(self._file.value)))
        self.slider = gui.add_slider("time [s]", min=0.0, max=1.0, step=0.01, initial_value=0.0,
                                     disabled=True)
        self.slider.on_update(lambda _: viewer._guarded(lambda: self._show_time(self.slider.value)))
        self.play_button = gui.add_button("play", disabled=True)
        self.play_button.on_click(lambda _: viewer._guarded(self._toggle_play))
        self._status = gui.add_html("")

    @property
    def playing(self) -> bool:
        """The motion is playing."""
        return self._playing

    def load(self, motion: JointTrajectory | Playback | str | Path) -> Playback:
        """Put ``motion`` on the timeline at its start: a trajectory, samples, or a file ``armkit traj``
        wrote."""
        if isinstance(motion, JointTrajectory):
            playback = Playback.from_trajectory(motion)
        elif isinstance(motion, Playback):
            playback = motion
        else:
            playback = Playback.from_file(motion, self._robot)
        if playback.q.shape[1] != self._robot.n:
            raise InputError(f"motion has {playback.q.shape[1]} joints; {self._robot.name} has "
                             f"{self._robot.n}")
        with self._viewer._lock:
            self.pause()
            self.playback = playback
            self._draw_path()
            self.slider.max = playback.duration
            self.slider.step = max(playback.duration / 1000, 1e-3)
            self.slider.disabled = False
            self.play_button.disabled = False
            self.slider.value = 0.0
            self._show_time(0.0)
            return playback

    def play(self) -> None:
        """Play the motion on the timeline from where it is (from its start once it has ended)."""
        if self.playback is None:
            raise InputError("nothing to play: plan a trajectory or load a trajectory file first")
        with self._viewer._lock:
            if self.slider.value >= self.playback.duration:
                self.slider.value = 0.0
            self._playing = True
            self.play_button.label = "pause"
            if self.player is None or not self.player.is_alive():
                self.player = threading.Thread(target=self._run_player, daemon=True)
                self.player.start()

    def pause(self) -> None:
        """Stop the timeline where it is."""
        self._playing = False
        self.play_button.label = "play"

    def _draw_path(self) -> None:
        if self._path is not None:
            self._path.remove()
        q = self.playback.q
        stride = max(1, len(q) // 400)
        points = self._robot.fk(q[::stride])[:, :3, 3]
        if len(q) % stride != 1:
            points = np.vstack([points, self._robot.fk(q[-1])[:3, 3]])
        segments = np.stack([points[:-1], points[1:]], axis=1)
        self._path = self._viewer._server.scene.add_line_segments(
            "/tool_path", points=segments, colors=Colours.PATH, thickness=0.3 * self._viewer._radius)

    def _show_time(self, t: float) -> None:
        viewer, playback = self._viewer, self.playback
        if playback is None:
            return
        q, _, _ = playback.at(t)
        velocity, acceleration = playback.at_limits(self._robot, t)
        viewer._play_q(q, velocity | acceleration)
        names = self._robot.joint_names
        flagged = ([f"{names[j]} at its velocity limit" for j in np.flatnonzero(velocity)]
                   + [f"{names[j]} at its acceleration limit" for j in np.flatnonzero(acceleration)])
        self._status.content = (
            f"<div style='font-size:0.8em' data-armkit='playback'>{playback.source}: "
            f"t = <span data-armkit='time'>{t:.2f}</span> of {playback.duration:.2f} s"
            f"<div data-armkit='at-limit' style='color:#d33'>{'; '.join(flagged)}</div></div>")

    def _toggle_play(self) -> None:
        if self._playing:
            self.pause()
        else:
            self.play()

    def _run_player(self) -> None:
        last = time.perf_counter()
        while self._playing and not self._viewer._closed:
            time.sleep(1 / PLAY_RATE_HZ)
            now = time.perf_counter()
            with self._viewer._lock:
                if not self._playing or self.playback is None or self._viewer._closed:
                    break
                t = min(self.slider.value + (now - last), self.playback.duration)
                self.slider.value = t
                if t >= self.playback.duration:
                    self.pause()
            last = now
