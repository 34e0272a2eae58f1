"""A 7-joint arm's self-motion in the viewer: ghosts along one branch, a slider moving the arm along it.

With one joint free, a 7-joint arm reaches a pose along curves of configurations, the branches
of its self-motion (:func:`armkit.self_motion`, every branch sampled along the free joint). The
"Self-motion" folder picks the free joint, samples the self-motion of the IK target, draws ghost
arms along the branch the arm is on (or the one picked in the list), and its slider over the free
joint's value moves the arm along that branch, the tool staying on the target. The ghosts go
when the arm's tool leaves the target; while it stays on the target (the arm set to another of its
configurations), the slider and the text follow the arm.
"""

from __future__ import annotations

import html
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from armkit.errors import InputError
from armkit.ik.self_motion import SelfMotion, largest_joint_gap
from armkit.kinematics import pose_error
from armkit.view.scene import ArmDrawing, Colours

if TYPE_CHECKING:
    from armkit.view.viewer import Viewer

__all__ = ["ON_TARGET", "PANEL_MAX_SAMPLES", "SAMPLES", "SELF_MOTION_GHOSTS", "SelfMotionGhosts"]

#: Ghost arms drawn along the shown branch, spread evenly over its samples.
SELF_MOTION_GHOSTS = 8
#: Values of the free joint sampled by default (as ``armkit ik --self-motion`` does).
SAMPLES = 64
#: Most values the panel's ``samples`` box takes: each value is a closed-form IK of the locked arm
#: (about 17 ms for the Panda, so 256 take about 4 s, run outside the viewer's lock);
#: :meth:`Viewer.show_self_motion` takes more.
PANEL_MAX_SAMPLES = 256
#: The arm's tool counts as on the self-motion's target within this [m and rad]: well above the
#: closed-form solutions' residuals (1e-9 and below), well below any move a user makes.
ON_TARGET = 1e-6


class SelfMotionGhosts:
    """The self-motion of the target along a free joint: ghosts along a branch, a slider along it.

    Attributes
    ----------
    motion : SelfMotion or None
        The self-motion shown (``None`` before one is sampled, and once the arm left its target).
    target : ndarray (4, 4) or None
        Its tool pose [m].
    branch : int or None
        The branch shown (0-based).
    sample : int or None
        The sample of ``branch`` the arm is at (``None`` when the arm is on the target elsewhere).
    ghosts : list of ArmDrawing
        The ghost arms; the first ``len(shown)`` are drawn, at the samples ``shown`` of ``branch``.
    """

    def __init__(self, viewer: Viewer) -> None:
        self._viewer = viewer
        self._robot = robot = viewer.robot
        self._syncing = False
        self.motion: SelfMotion | None = None
        self.target: NDArray[np.float64] | None = None
        self.branch: int | None = None
        self.sample: int | None = None
        self.shown = np.zeros(0, dtype=int)
        scene, radius = viewer._server.scene, viewer._radius
        self.ghosts = [ArmDrawing(scene, f"/self_motion/{k}", robot, 0.8 * radius, viewer.q, opacity=0.3)
                       for k in range(SELF_MOTION_GHOSTS)]
        for ghost in self.ghosts:
            ghost.visible = False
        gui = viewer._server.gui
        with gui.add_folder("Self-motion"):
            self.free_joint = gui.add_dropdown("free joint", tuple(robot.joint_names),
                                               initial_value=robot.joint_names[min(2, robot.n - 1)])
            self.samples = gui.add_number("samples", SAMPLES, min=2, max=PANEL_MAX_SAMPLES, step=1,
                                          hint=f"values of the free joint, 2 to {PANEL_MAX_SAMPLES} "
                                               f"(more from Python: Viewer.show_self_motion)")
            self.sample_button = gui.add_button("sample the target's self-motion")
            # not under the viewer's lock: sampling takes a while, the page and the player go on meanwhile
            self.sample_button.on_click(lambda _: viewer._guarded(self._sample, locked=False))
            self.branch_pick = gui.add_dropdown("branch", ("-",), initial_value="-", disabled=True)
            self.branch_pick.on_update(lambda _: viewer._guarded(self._on_branch))
            self.slider = gui.add_slider(f"free joint [{self._unit}]", min=-180.0, max=180.0, step=1.0,
                                         initial_value=0.0, disabled=True)
            self.slider.on_update(lambda _: viewer._guarded(self._on_slider))
            self.status = gui.add_html("")
        self.clear()

    # ------------------------------------------------------------------ what the viewer calls
    def show(self, motion: SelfMotion, T: NDArray[np.float64]) -> None:
        """Show ``motion``, the self-motion at ``T`` ``(4, 4)`` [m]: ghosts along the branch nearest the
        arm, and the arm moved onto that branch (its sample nearest the arm)."""
        index = motion.free_joint
        self.clear()
        found = np.isfinite(motion.q).all(axis=-1)
        if not found.any():
            self.status.content = ("<div style='font-size:0.8em;color:#d33' data-armkit='self-motion'>"
                                   "the target is out of reach at every sampled value of "
                                   f"{html.escape(self._robot.joint_names[index])}</div>")
            return
        self.motion, self.target = motion, T.copy()
        distance = np.full(found.shape, np.inf)
        distance[found] = largest_joint_gap(motion.q[found], self._viewer.q, ~self._robot.chain.prismatic)
        branch, k = np.unravel_index(int(np.argmin(distance)), distance.shape)
        self._syncing = True
        try:
            self.free_joint.value = self._robot.joint_names[index]
            options = self._branch_options()
            self.branch_pick.options = options
            self.branch_pick.value = options[branch]
            self.branch_pick.disabled = False
            self._relabel()
            self.slider.disabled = False
        finally:
            self._syncing = False
        self._show_branch(int(branch), int(k))

    def refresh_units(self) -> None:
        """The angle unit changed: the slider's label, range and value, and the text, in the new one."""
        self._syncing = True
        try:
            self._relabel()
        finally:
            self._syncing = False
        if self.motion is not None:
            self._follow_arm(self._viewer.q)

    def _relabel(self) -> None:
        """The slider's label, and its range around the samples, in the current unit (while syncing)."""
        if self.motion is None:
            self.slider.label = f"free joint [{self._unit}]"
            return
        values = self._to_slider(self.motion.values)
        self.slider.label = f"{self._robot.joint_names[self.motion.free_joint]} [{self._unit}]"
        # ends rounded (-166.1, not -166.003062) just outside the samples: a value takes its nearest one
        scale = 10.0 ** self._decimals
        self.slider.min = float(np.floor(values[0] * scale) / scale)
        self.slider.max = float(np.ceil(values[-1] * scale) / scale)
        self.slider.step, self.slider.precision = 1 / scale, self._decimals

    def move_to(self, value: float, branch: int | None = None) -> NDArray[np.float64]:
        """Move the arm to the sample of ``branch`` (0-based, checked by the viewer; default: the one
        shown) whose free-joint value is nearest ``value`` [rad or m] (a finite number, checked by the
        viewer; a revolute joint's modulo a turn); the configuration ``(n,)``."""
        motion = self.require_motion()
        branch = self.branch if branch is None else branch
        k = self._nearest(np.arange(len(motion.values)), value)
        if not np.isfinite(motion.q[branch, k]).all():
            name = self._robot.joint_names[motion.free_joint]  # plain text: the status line escapes it
            where = self._to_slider(motion.values[np.isfinite(motion.q[branch]).all(axis=-1)])
            raise InputError(f"branch {branch + 1} has no solution at {name} = "
                             f"{self._to_slider(motion.values[k]):.4g} {self._unit}; it has from "
                             f"{where.min():.4g} to {where.max():.4g} {self._unit}")
        if branch != self.branch:
            self._show_branch(branch, k)
        else:
            self._place_arm(k)
        return motion.q[branch, k].copy()

    def arm_moved(self, q: NDArray[np.float64]) -> None:
        """The arm moved to ``q``: off the target, the self-motion goes (as :attr:`Viewer.self_motion`
        says); on it but off the sample shown, the slider and the text follow the arm."""
        if self.target is None:
            return
        if np.abs(pose_error(self.target, self._robot.fk(q))).max() > ON_TARGET:
            self.clear()
        elif self.sample is None or not np.array_equal(q, self.motion.q[self.branch, self.sample]):
            self.sample = None
            self._follow_arm(q)

    def clear(self) -> None:
        """Hide the ghosts and forget the self-motion."""
        self.motion, self.target, self.branch, self.sample = None, None, None, None
        self.shown = np.zeros(0, dtype=int)
        for ghost in self.ghosts:
            ghost.visible = False
        self._syncing = True
        try:
            self.branch_pick.options = ("-",)
            self.branch_pick.value = "-"
            self.branch_pick.disabled = True
            self.slider.disabled = True
            self._relabel()
        finally:
            self._syncing = False
        self.status.content = ("<div style='font-size:0.8em' data-armkit='self-motion'>sample the "
                               "self-motion of the IK target along the free joint</div>")

    # ------------------------------------------------------------------ drawing
    @property
    def _unit(self) -> str:
        """The slider's unit: m for a prismatic free joint, else the panel's angle unit."""
        prismatic = self.motion is not None and self._robot.chain.prismatic[self.motion.free_joint]
        return "m" if prismatic else "deg" if self._viewer._degrees else "rad"

    @property
    def _decimals(self) -> int:
        """Decimals of the slider: 0.1 mm, 0.1 deg, 0.001 rad (as the joint sliders)."""
        return {"m": 4, "deg": 1, "rad": 3}[self._unit]

    def _to_slider(self, values: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.degrees(values) if self._unit == "deg" else np.asarray(values, dtype=float)

    def from_slider(self, value: float) -> float:
        """A value of the slider [deg, rad or m] in SI units [rad or m] (NaN stays NaN: the viewer
        says it is not a value)."""
        if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
            raise InputError(f"self-motion slider: expected a number [{self._unit}], got {value!r}")
        return float(np.radians(value)) if self._unit == "deg" else float(value)

    def _nearest(self, samples: NDArray[np.int_], value: float) -> int:
        """Of ``samples`` (indices), the one whose free-joint value is nearest ``value`` [rad or m]:
        for a revolute joint modulo a turn (as the branch nearest the arm is found)."""
        motion = self.motion
        revolute = ~self._robot.chain.prismatic[[motion.free_joint]]
        gap = largest_joint_gap(motion.values[samples, None], value, revolute)
        return int(samples[int(np.argmin(gap))])

    def _branch_options(self) -> tuple[str, ...]:
        motion = self.motion
        found = np.isfinite(motion.q).all(axis=-1)
        return tuple(f"{b + 1}: {int(found[b].sum())} samples, {int(motion.within_limits[b].sum())} in limits"
                     for b in range(len(motion.q)))

    def _show_branch(self, branch: int, k: int) -> None:
        """Draw ghosts along ``branch`` and put the arm at its sample ``k``."""
        motion = self.motion
        self.branch = branch
        existing = np.flatnonzero(np.isfinite(motion.q[branch]).all(axis=-1))
        spread = np.round(np.linspace(0, len(existing) - 1, min(SELF_MOTION_GHOSTS, len(existing))))
        self.shown = existing[np.unique(spread.astype(int))]
        with self._viewer._server.atomic():
            for g, ghost in enumerate(self.ghosts):
                if g < len(self.shown):
                    s = self.shown[g]
                    colour = Colours.GHOST_IN if motion.within_limits[branch, s] else Colours.GHOST_OUT
                    ghost.update(motion.q[branch, s])
                    ghost.colour(colour, colour)
                ghost.visible = g < len(self.shown)
        self._syncing = True
        try:
            self.branch_pick.value = self._branch_options()[branch]
        finally:
            self._syncing = False
        self._place_arm(k)

    def _place_arm(self, k: int) -> None:
        self.sample = k
        q = self.motion.q[self.branch, k]
        self._viewer._set_q(q, from_ik=True)
        self._follow_arm(q)

    def _follow_arm(self, q: NDArray[np.float64]) -> None:
        """The slider at the arm's ``q`` ``(n,)``, and the text saying where it is."""
        motion, branch, k = self.motion, self.branch, self.sample
        value = float(self._to_slider(q[motion.free_joint]))
        self._syncing = True
        try:
            self.slider.value = float(np.clip(round(value, self._decimals), self.slider.min, self.slider.max))
        finally:
            self._syncing = False
        name = html.escape(self._robot.joint_names[motion.free_joint])
        values = self._to_slider(motion.values[self.shown])
        if k is None:
            where = f"on the target, at no sample of branch {branch + 1}"
        else:
            where = f"{'inside' if motion.within_limits[branch, k] else 'OUTSIDE'} the limits"
        self.status.content = (
            f"<div style='font-size:0.8em' data-armkit='self-motion' data-branches='{len(motion.q)}'>"
            f"{len(motion.q)} branch{'es' * (len(motion.q) != 1)} along {name}; branch {branch + 1}: "
            f"ghosts at {name} = {', '.join(f'{v:.4g}' for v in values)} {self._unit}; "
            f"the arm at {name} = <span data-armkit='free-value'>{value:.4g}</span> {self._unit}, "
            f"{where}</div>")

    # ------------------------------------------------------------------ the panel's controls
    def require_motion(self) -> SelfMotion:
        """The self-motion shown; raises InputError if there is none."""
        if self.motion is None:
            raise InputError("no self-motion shown: sample one first (Viewer.show_self_motion, or the "
                             "panel's 'sample the target's self-motion')")
        return self.motion

    def _sample(self) -> None:
        samples = self.samples.value
        whole = isinstance(samples, int | float) and float(samples).is_integer()
        if not whole or not 2 <= samples <= PANEL_MAX_SAMPLES:  # the page's box allows no other
            raise InputError(f"samples: expected a whole number from 2 to {PANEL_MAX_SAMPLES}, "
                             f"got {samples!r}")
        self._viewer.show_self_motion(self.free_joint.value, samples=int(samples))

    def _on_branch(self) -> None:
        if self._syncing or self.motion is None or self.branch_pick.value == "-":
            return
        branch = int(self.branch_pick.value.split(":")[0]) - 1
        existing = np.flatnonzero(np.isfinite(self.motion.q[branch]).all(axis=-1))
        self._show_branch(branch, self._nearest(existing, self._viewer.q[self.motion.free_joint]))

    def _on_slider(self) -> None:
        if self._syncing or self.motion is None:
            return
        self._viewer.move_along_self_motion(self.from_slider(self.slider.value))
