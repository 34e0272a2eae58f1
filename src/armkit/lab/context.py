"""What every lab experiment shares: the robot, its simulation, the report folder, number formats."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit.robot import Robot
from armkit.sim.runner import Simulation

#: The floor the experiments keep clear of and are checked against: the plane z = 0 of the base frame [m].
FLOOR_HEIGHT = 0.0

__all__ = ["LabContext", "fmt", "fmt_error", "fmt_q"]


@dataclass
class LabContext:
    """The robot under test, its MuJoCo model (gravity on, compensated) and the report folder.

    ``seeds`` is true when the robot is the PROBOT Anno of report 000 and the report's
    published numbers apply; otherwise the experiments choose reachable targets themselves.
    """

    robot: Robot
    folder: Path
    quick: bool
    seeds: bool
    rng: np.random.Generator = field(default_factory=lambda: np.random.default_rng(2024))
    files: list[str] = field(default_factory=list)
    stage: str = ""
    motions: list[tuple[str, NDArray[np.float64]]] = field(default_factory=list)
    _sim: Simulation | None = None
    _scene: object = None

    def record(self, q: NDArray[np.float64]) -> None:
        """Keep a motion's commanded configurations ``(N, n)`` for the collision check (under ``stage``)."""
        self.motions.append((self.stage, np.asarray(q, dtype=float).reshape(-1, self.robot.n)))

    @property
    def sim(self) -> Simulation:
        """The robot in MuJoCo with gravity and gravity compensation (built on first use)."""
        if self._sim is None:
            self._sim = Simulation(self.robot, gravity=True, gravity_compensation=True)
        return self._sim

    @property
    def scene(self):  # -> armkit.Scene
        """The arm with a floor at :data:`FLOOR_HEIGHT` and its self-collision (built on first use)."""
        if self._scene is None:
            from armkit.collision import Scene

            self._scene = Scene(self.robot, floor=FLOOR_HEIGHT)
        return self._scene

    @property
    def home(self) -> NDArray[np.float64]:
        """Zero joint values, clipped into the limits: where simulated moves start."""
        return self.robot.home

    @property
    def gif_frames(self) -> int:
        return 8 if self.quick else 36

    @property
    def gif_dpi(self) -> int:
        """Animations are 4 inch square: 160 px in quick mode, 480 px otherwise."""
        return 40 if self.quick else 120

    def path(self, name: str) -> Path:
        """A file of the report (registered so a later run can replace it)."""
        self.files.append(name)
        return self.folder / name


def fmt(value: float, digits: int = 6) -> str:
    """A table number with fixed decimals; ``-0`` shown as ``0``."""
    text = f"{value:.{digits}f}"
    return text[1:] if text.startswith("-") and float(text) == 0 else text


def fmt_error(value: float) -> str:
    """An error in scientific notation with two digits."""
    return f"{value:.1e}"


def fmt_q(q: ArrayLike, digits: int = 4) -> str:
    """Joint values as ``[a, b, ...]``."""
    return "[" + ", ".join(fmt(v, digits) for v in np.asarray(q, dtype=float)) + "]"
