"""A 7-joint arm's self-motion in the viewer: ghosts along one branch, a slider moving the arm along it.

With one joint free, a 7-joint arm reaches a pose along curves of configurations, the branches
of its self-motion (:func:`armkit.self_motion`, every branch sampled along the free joint). The
"Self-motion" folder picks the free joint, samples the self-motion of the IK target, draws ghost
arms along the branch the arm is on (or the one picked in the list), and its slider over the free
joint's value moves the arm along that branch, the tool staying on the target. The ghosts go
when the arm's tool leaves the target.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from armkit.errors import InputError
from armkit.ik.self_motion import SelfMotion
from armkit.kinematics import pose_error
from armkit.view.scene import ArmDrawing, Colours

if TYPE_CHECKING:
    from armkit.view.viewer import Viewer

__all__ = ["ON_TARGET", "SAMPLES", "SELF_MOTION_GHOSTS", "SelfMotionGhosts"]

#: Ghost arms drawn along the shown branch, spread evenly over its samples.
SELF_MOTION_GHOSTS = 8
#: Values of the free joint sampled by default (as ``armkit ik --self-motion`` does).
SAMPLES = 64
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
            self.samples = gui.add_number("samples", SAMPLES, min=2, max=1000, step=1)
            sample = gui.add_button("sample the target's self-motion")
            sample.on_click(lambda _: viewer._guarded(self._sample))
            self.branch_pick = gui.add_dropdown("branch", ("-",), initial_value="-", disabled=True)
            self.branch_pick.on_update(lambda _: viewer._guarded(self._on_branch))
            self.slider = gui.add_slider("free joint [deg]", min=-180.0, max=180.0, step=1.0,
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
                                   f"{self._robot.joint_names[index]}</div>")
            return
        self.motion, self.target = motion, T.copy()
        distance = np.full(found.shape, np.inf)
        distance[found] = self._distance(motion.q[found], self._viewer.q)
        branch, k = np.unravel_index(int(np.argmin(distance)), distance.shape)
        self._syncing = True
        try:
            self.free_joint.value = self._robot.joint_names[index]
            options = self._branch_options()
            self.branch_pick.options = options
            self.branch_pick.value = options[branch]
            self.branch_pick.disabled = False
            values = self._to_slider(motion.values)
            self.slider.label = f"{self._robot.joint_names[index]} [{self._unit}]"
            # ends rounded (-166.1, not -166.003062) just outside the samples: a value takes its nearest one
            scale = 10.0 ** self._decimals
            self.slider.min = float(np.floor(values[0] * scale) / scale)
            self.slider.max = float(np.ceil(values[-1] * scale) / scale)
            self.slider.step, self.slider.precision = 1 / scale, self._decimals
            self.slider.disabled = False
        finally:
            self._syncing = False
        self._show_branch(int(branch), int(k))

    def move_to(self, value: float, branch: int | None = None) -> NDArray[np.float64]:
        """Move the arm to the sample of ``branch`` (0-based; default: the one shown) whose free-joint
        value is nearest ``value`` [rad or m]; the configuration ``(n,)``."""
        motion = self._require_motion()
        branch = self.branch if branch is None else branch
        if not 0 <= branch < len(motion.q):
            raise InputError(f"branch {branch + 1}: the self-motion has {len(motion.q)} branches "
                             f"(1..{len(motion.q)})")
        k = int(np.argmin(np.abs(motion.values - value)))
        if not np.isfinite(motion.q[branch, k]).all():
            name = self._robot.joint_names[motion.free_joint]
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
        """The arm moved to ``q``: off the target, the self-motion goes."""
        if self.target is not None and np.abs(pose_error(self.target, self._robot.fk(q))).max() > ON_TARGET:
            self.clear()

    def clear(self) -> None:
        """Hide the ghosts and forget the self-motion."""
        self.motion, self.target, self.branch = None, None, None
        self.shown = np.zeros(0, dtype=int)
        for ghost in self.ghosts:
            ghost.visible = False
        self._syncing = True
        try:
            self.branch_pick.options = ("-",)
            self.branch_pick.value = "-"
            self.branch_pick.disabled = True
            self.slider.disabled = True
        finally:
            self._syncing = False
        self.status.content = ("<div style='font-size:0.8em' data-armkit='self-motion'>sample the "
                               "self-motion of the IK target along the free joint</div>")

    # ------------------------------------------------------------------ drawing
    @property
    def _unit(self) -> str:
        prismatic = self.motion is not None and self._robot.chain.prismatic[self.motion.free_joint]
        return "m" if prismatic else "deg"

    @property
    def _decimals(self) -> int:
        """Decimals of the slider: 0.1 deg, 0.1 mm."""
        return 4 if self._unit == "m" else 1

    def _to_slider(self, values: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.asarray(values, dtype=float) if self._unit == "m" else np.degrees(values)

    def _distance(self, q: NDArray[np.float64], reference: NDArray[np.float64]) -> NDArray[np.float64]:
        """The largest joint difference of each ``q`` ``(..., n)`` from ``reference``, revolute joints
        modulo a turn."""
        d = q - reference
        revolute = ~self._robot.chain.prismatic
        d[..., revolute] = np.angle(np.exp(1j * d[..., revolute]))
        return np.abs(d).max(axis=-1)

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
        motion, branch = self.motion, self.branch
        self._syncing = True
        try:
            self.slider.value = round(float(self._to_slider(motion.values[k])), self._decimals)
        finally:
            self._syncing = False
        self._viewer._set_q(motion.q[branch, k], from_ik=True)
        name = self._robot.joint_names[motion.free_joint]
        values = self._to_slider(motion.values[self.shown])
        inside = "inside" if motion.within_limits[branch, k] else "OUTSIDE"
        self.status.content = (
            f"<div style='font-size:0.8em' data-armkit='self-motion' data-branches='{len(motion.q)}'>"
            f"{len(motion.q)} branch{'es' * (len(motion.q) != 1)} along {name}; branch {branch + 1}: "
            f"ghosts at {name} = {', '.join(f'{v:.4g}' for v in values)} {self._unit}; "
            f"the arm at {name} = "
            f"<span data-armkit='free-value'>{self._to_slider(motion.values[k]):.4g}</span> "
            f"{self._unit}, {inside} the limits</div>")

    # ------------------------------------------------------------------ the panel's controls
    def _require_motion(self) -> SelfMotion:
        if self.motion is None:
            raise InputError("no self-motion shown: sample one first (Viewer.show_self_motion, or the "
                             "panel's 'sample the target's self-motion')")
        return self.motion

    def _sample(self) -> None:
        self._viewer.show_self_motion(self.free_joint.value, samples=int(self.samples.value))

    def _on_branch(self) -> None:
        if self._syncing or self.motion is None or self.branch_pick.value == "-":
            return
        branch = int(self.branch_pick.value.split(":")[0]) - 1
        existing = np.flatnonzero(np.isfinite(self.motion.q[branch]).all(axis=-1))
        k = int(np.argmin(np.abs(self.motion.values[existing] - self._viewer.q[self.motion.free_joint])))
        self._show_branch(branch, int(existing[k]))

    def _on_slider(self) -> None:
        if self._syncing or self.motion is None:
            return
        value = self.slider.value if self._unit == "m" else np.radians(self.slider.value)
        self.move_to(float(value))
