"""A motion the viewer plays: joint samples over time, from a planned trajectory or a CSV file."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from armkit.errors import InputError
from armkit.robot import Robot
from armkit.trajectory.export import read_trajectory
from armkit.trajectory.joint_trajectory import JointTrajectory

__all__ = ["AT_LIMIT", "Playback"]

#: A joint rate within this fraction of its limit counts as "at the limit" (auto-timed
#: trajectories reach their limits to ``1e-4``).
AT_LIMIT = 1e-3


@dataclass(frozen=True)
class Playback:
    """Joint samples to play on the timeline.

    Attributes
    ----------
    t : (K,) times [s], increasing from 0; q, qd, qdd : (K, n) joint values [rad or m] and their
    first and second time derivatives; source : what the samples came from (shown in the panel).
    """

    t: NDArray[np.float64]
    q: NDArray[np.float64]
    qd: NDArray[np.float64]
    qdd: NDArray[np.float64]
    source: str

    @classmethod
    def from_trajectory(cls, trajectory: JointTrajectory, rate_hz: float = 100.0,
                        source: str = "planned trajectory") -> Playback:
        """Samples of a :class:`JointTrajectory` at ``rate_hz`` [Hz]."""
        samples = trajectory.sample(rate_hz)
        return cls(samples.t, samples.q, samples.qd, samples.qdd, source)

    @classmethod
    def from_file(cls, path: str | Path, robot: Robot) -> Playback:
        """Samples of a trajectory file as ``armkit traj`` writes it (CSV or NPZ).

        Rates missing from the file are taken by finite differences of ``q`` (and of ``qd``).

        Raises
        ------
        InputError
            If the file cannot be read, has the wrong joint count, or its times do not increase.
        """
        t, q, qd = read_trajectory(path, robot)
        if len(t) < 2 or np.any(np.diff(t) <= 0):
            raise InputError(f"trajectory file {str(path)!r}: expected at least two rows with "
                             f"increasing times t, got {len(t)} rows")
        qd = np.gradient(q, t, axis=0) if qd is None else qd
        return cls(t - t[0], q, qd, np.gradient(qd, t, axis=0), Path(path).name)

    @property
    def duration(self) -> float:
        """Length of the motion [s]."""
        return float(self.t[-1])

    def at(self, time: float) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """``q, qd, qdd`` ``(n,)`` at ``time`` [s], linearly interpolated between samples."""
        time = float(np.clip(time, 0.0, self.duration))
        k = int(np.clip(np.searchsorted(self.t, time, side="right") - 1, 0, len(self.t) - 2))
        w = (time - self.t[k]) / (self.t[k + 1] - self.t[k])
        return tuple((1 - w) * x[k] + w * x[k + 1] for x in (self.q, self.qd, self.qdd))

    def at_limits(self, robot: Robot, time: float) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
        """Which joints are at (or above) their velocity, and their acceleration, limit at ``time``."""
        _, qd, qdd = self.at(time)
        return (np.abs(qd) >= (1 - AT_LIMIT) * robot.max_velocity,
                np.abs(qdd) >= (1 - AT_LIMIT) * robot.max_acceleration)
