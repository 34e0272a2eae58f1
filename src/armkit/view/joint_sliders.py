"""The viewer's "Joints" folder: the angle unit, one slider per joint within its limits, ``home``."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from armkit.view import readout

if TYPE_CHECKING:
    from armkit.view.viewer import Viewer

__all__ = ["JointSliders"]


class JointSliders:
    """A slider per joint: revolute joints in degrees or radians (the ``angles`` list), prismatic in m.

    A slider shows its value with as many decimals as fit its number box; joint names too long for
    the label column get a row of their own above their slider. Moving a slider moves the arm
    (``viewer.q``); :meth:`sync` moves the sliders to the arm.
    """

    def __init__(self, viewer: Viewer) -> None:
        self._viewer = viewer
        self._robot = viewer.robot
        self._syncing = False
        self.sliders: list[Any] = []
        self.name_rows: list[Any] = []
        self._decimals: list[int] = []
        gui = viewer._server.gui
        with gui.add_folder("Joints"):
            self.units = gui.add_dropdown("angles", ("deg", "rad"), initial_value="deg")
            self.units.on_update(lambda _: viewer._units_changed())
            self._folder = gui.add_folder("q", expand_by_default=True)
            self.rebuild(viewer.q)
            gui.add_button("home").on_click(lambda _: viewer._guarded(self._home))

    @property
    def degrees(self) -> bool:
        """Revolute joints are shown in degrees (else radians)."""
        return self.units.value == "deg"

    def _in_degrees(self, j: int) -> bool:
        return self.degrees and not self._robot.chain.prismatic[j]

    def _to_slider(self, j: int, value: float) -> float:
        return float(np.degrees(value)) if self._in_degrees(j) else float(value)

    def _from_slider(self, j: int, value: float) -> float:
        return float(np.radians(value)) if self._in_degrees(j) else float(value)

    def rebuild(self, q: NDArray[np.float64]) -> None:
        """Make the sliders again in the current unit, at ``q`` ``(n,)`` [rad or m]."""
        robot = self._robot
        gui = self._viewer._server.gui
        for element in (*self.sliders, *self.name_rows):
            element.remove()
        self.sliders, self.name_rows, self._decimals = [], [], []
        units = ["m" if prismatic else self.units.value for prismatic in robot.chain.prismatic]
        # names too long for the label column get a full-width row of their own (wrapping if need be)
        long_names = any(len(f"{name} [{unit}]") > readout.LABEL_CHARS
                         for name, unit in zip(robot.joint_names, units, strict=True))
        with self._folder:
            for j, (name, (lower, upper)) in enumerate(zip(robot.joint_names, robot.limits, strict=True)):
                prismatic = robot.chain.prismatic[j]
                span = self._viewer._size if prismatic else np.pi
                lower = lower if np.isfinite(lower) else -span
                upper = upper if np.isfinite(upper) else span
                label = f"{name} [{units[j]}]"
                if long_names:
                    self.name_rows.append(gui.add_html(readout.joint_name_html(j, label)))
                    label = f"q{j + 1} [{units[j]}]"
                low, high = self._to_slider(j, lower), self._to_slider(j, upper)
                most = 4 if prismatic else (1 if self.degrees else 3)
                decimals = readout.box_decimals(low, high, most)
                shown = readout.box_range(low, high, decimals)
                self._decimals.append(decimals)
                initial = self._slider_value(j, np.clip(q[j], lower, upper), *shown)
                slider = gui.add_slider(label, min=shown[0], max=shown[1], step=10.0 ** -decimals,
                                        initial_value=initial)
                slider.on_update(lambda _, j=j: self._viewer._guarded(lambda: self._on_slider(j)))
                self.sliders.append(slider)

    def _slider_value(self, j: int, value: float, low: float, high: float) -> float:
        """Joint ``j``'s ``value`` [rad or m] as its slider shows it: unit, box precision, range."""
        return float(np.clip(round(self._to_slider(j, value), self._decimals[j]), low, high))

    def sync(self, q: NDArray[np.float64]) -> None:
        """Move the sliders to ``q`` ``(n,)`` [rad or m] (without moving the arm again)."""
        self._syncing = True
        try:
            for j, slider in enumerate(self.sliders):
                slider.value = self._slider_value(j, q[j], slider.min, slider.max)
        finally:
            self._syncing = False

    def _on_slider(self, j: int) -> None:
        if self._syncing:
            return
        q = self._viewer.q
        q[j] = self._from_slider(j, self.sliders[j].value)
        self._viewer.q = q

    def _home(self) -> None:
        self._viewer.q = self._robot.home
