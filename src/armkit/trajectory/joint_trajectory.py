"""The trajectory result: piecewise polynomials in joint space that know their timing.

>>> from armkit.trajectory import min_jerk
>>> traj = min_jerk([[0.0, 0.0], [1.0, -1.0]], [2.0])
>>> traj.duration, traj.waypoint_times
(2.0, array([0., 2.]))
>>> samples = traj.sample(10.0)          # 10 Hz: t, q, qd, qdd, qddd
>>> samples.q.shape
(21, 2)
"""

from __future__ import annotations

from pathlib import Path
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit._deprecation import deprecated_property
from armkit._time import rate_time_grid
from armkit.errors import InputError
from armkit.robot import Robot
from armkit.trajectory import export
from armkit.trajectory._checks import check_finite
from armkit.trajectory.peaks import segment_peaks, segment_ranges
from armkit.trajectory.polynomial import TIME_TOLERANCE

__all__ = ["MAX_SAMPLE_BYTES", "JointTrajectory", "TrajectorySamples", "TrajectoryTorques"]

#: Most memory [bytes] that :meth:`JointTrajectory.sample` may ask for (1 GiB): a rate that needs
#: more is refused with the sample count, rather than exhausting the machine.
MAX_SAMPLE_BYTES = 2**30


class TrajectorySamples(NamedTuple):
    """Samples of a trajectory: ``t`` ``(K,)`` [s] and ``q``, ``qd``, ``qdd``, ``qddd`` ``(K, n)`` (SI)."""

    t: NDArray[np.float64]
    q: NDArray[np.float64]
    qd: NDArray[np.float64]
    qdd: NDArray[np.float64]
    qddd: NDArray[np.float64]


class TrajectoryTorques(NamedTuple):
    """Joint torques along a trajectory: ``t`` ``(K,)`` [s], ``tau`` ``(K, n)`` [N m or N] and
    ``peak`` ``(n,)``, the largest ``|tau|`` per joint over the samples."""

    t: NDArray[np.float64]
    tau: NDArray[np.float64]
    peak: NDArray[np.float64]


class JointTrajectory:
    """A piecewise-polynomial joint trajectory starting at ``t = 0``.

    Parameters
    ----------
    durations : (N,) array
        Segment durations [s]; with ``segment_pieces``, the ``(P,)`` durations of the pieces.
    coefficients : (k + 1, P, n) array
        Per polynomial piece and joint, ascending powers of the local time ``t - t_p`` [s];
        one piece per segment (``P = N``) unless ``segment_pieces`` says otherwise.
    waypoints : (N + 1, n) array
        Positions at the segment boundaries [rad or m].
    requested_durations : (N,) array, optional
        The durations asked for before fitting to limits; defaults to the segment durations.
    segment_pieces : (N,) int array, optional
        How many consecutive pieces make up each segment (a time-optimal trajectory has
        many pieces between two waypoints); default one each.

    Attributes
    ----------
    durations, requested_durations, waypoints : read-only arrays, per segment
    coefficients, piece_durations : read-only arrays, per piece
    """

    def __init__(self, durations: ArrayLike, coefficients: ArrayLike, waypoints: ArrayLike,
                 requested_durations: ArrayLike | None = None, *,
                 segment_pieces: ArrayLike | None = None) -> None:
        self.piece_durations = np.array(durations, dtype=float)
        self.coefficients = np.array(coefficients, dtype=float)
        self.waypoints = np.array(waypoints, dtype=float)
        pieces = (np.ones(self.piece_durations.size, dtype=int) if segment_pieces is None
                  else np.asarray(segment_pieces, dtype=int))
        if pieces.sum() != self.piece_durations.size or pieces.size != self.waypoints.shape[0] - 1:
            raise InputError(f"segment_pieces: expected {self.waypoints.shape[0] - 1} counts adding up to "
                             f"{self.piece_durations.size} pieces, got {pieces.tolist()}")
        self._piece_breaks = np.concatenate([[0.0], np.cumsum(self.piece_durations)])
        self._segment_starts = np.concatenate([[0], np.cumsum(pieces)])
        self._breaks = self._piece_breaks[self._segment_starts]
        self.durations = np.add.reduceat(self.piece_durations, self._segment_starts[:-1])
        self.requested_durations = np.array(self.durations if requested_durations is None
                                            else requested_durations, dtype=float)
        for array in (self.durations, self.piece_durations, self.coefficients, self.waypoints,
                      self.requested_durations):
            array.setflags(write=False)
        from scipy.interpolate import PPoly  # here: scipy.interpolate costs ~0.5 s at start-up

        self._ppoly = PPoly(self.coefficients[::-1], self._piece_breaks, extrapolate=False)

    def __repr__(self) -> str:
        return (f"JointTrajectory({self.n} joints, {self.durations.size} segments, "
                f"duration {self.duration:.6g} s)")

    # ----------------------------------------------------------------- timing
    @property
    def n(self) -> int:
        """Number of joints (as :attr:`armkit.Robot.n`)."""
        return self.coefficients.shape[2]

    dof = deprecated_property("dof", "n")

    @property
    def duration(self) -> float:
        """Total duration [s]."""
        return float(self._breaks[-1])

    @property
    def waypoint_times(self) -> NDArray[np.float64]:
        """Times [s] at which the trajectory passes the waypoints, ``(N + 1,)``."""
        return self._breaks.copy()

    @property
    def segment_pieces(self) -> NDArray[np.int64]:
        """Number of polynomial pieces in each segment, ``(N,)``."""
        return np.diff(self._segment_starts)

    @property
    def stretch(self) -> NDArray[np.float64]:
        """Per segment, final over requested duration (1 where nothing was stretched), ``(N,)``."""
        return self.durations / self.requested_durations

    # ----------------------------------------------------------------- evaluation
    def _evaluate(self, t: ArrayLike, orders: int) -> tuple[NDArray[np.float64], ...]:
        t = check_finite(t, "t")
        slack = TIME_TOLERANCE * max(1.0, self.duration)
        if np.any(t < -slack) or np.any(t > self.duration + slack):
            raise InputError(f"t: expected times in [0, {self.duration:g}] s, got "
                             f"{np.min(t):g} .. {np.max(t):g}")
        t = np.clip(t, 0.0, self.duration)
        return tuple(self._ppoly(t, nu) for nu in range(orders))

    def at_time(self, t: ArrayLike) -> tuple[NDArray[np.float64], ...]:
        """Position, velocity and acceleration at ``t`` [s] (``at_time`` takes times, :meth:`sample`
        a rate, in every armkit trajectory; a single segment's ``at_time`` adds the jerk).

        Returns ``q, qd, qdd``, each ``(n,)`` for a scalar ``t`` and ``(K, n)`` for ``(K,)`` times.
        """
        return self._evaluate(t, 3)

    def sample(self, rate_hz: float) -> TrajectorySamples:
        """Samples every ``1 / rate_hz`` seconds from 0, plus the end time if the grid misses it.

        Parameters
        ----------
        rate_hz : float
            Sampling rate [Hz], positive.

        Raises
        ------
        InputError
            If ``rate_hz`` is not positive, or the samples would need more than
            :data:`MAX_SAMPLE_BYTES` of memory (the message says how many were asked for).
        """
        rate = float(check_finite(rate_hz, "rate_hz"))
        if rate <= 0:
            raise InputError(f"rate_hz: expected a positive sampling rate (Hz), got {rate:g}")
        count = self.duration * rate + 2
        per_sample = (1 + 4 * self.n) * 8  # bytes: t, q, qd, qdd, qddd
        if count * per_sample > MAX_SAMPLE_BYTES:
            fits = (MAX_SAMPLE_BYTES / per_sample - 2) / max(self.duration, TIME_TOLERANCE)
            raise InputError(f"rate_hz {rate:g} Hz over {self.duration:.4g} s asks for {count:.4g} samples "
                             f"({count * per_sample / 2**30:.3g} GiB), more than the "
                             f"{MAX_SAMPLE_BYTES / 2**30:g} GiB allowed: lower the rate to at most "
                             f"{fits:.4g} Hz")
        t = rate_time_grid(self.duration, rate, TIME_TOLERANCE * max(1.0, self.duration))
        return TrajectorySamples(t, *self._evaluate(t, 4))

    def torques(self, robot: Robot, rate_hz: float = 1000.0, *,
                gravity: ArrayLike | None = None) -> TrajectoryTorques:
        """The joint torques that drive ``robot`` along this trajectory, sampled at ``rate_hz``
        (inverse dynamics of :meth:`sample`'s positions, velocities and accelerations).

        Parameters
        ----------
        robot : Robot
            With inertial parameters (see :mod:`armkit.dynamics`).
        rate_hz : float
            Sampling rate [Hz]; default 1 kHz.
        gravity : array_like, shape (3,), optional
            [m/s^2] in the robot's world frame; default (0, 0, -9.81).

        Examples
        --------
        >>> import armkit
        >>> from armkit.trajectory import min_jerk
        >>> robot = armkit.load("puma560")
        >>> torques = min_jerk([robot.home, [0.5, 0.3, -0.2, 0, 0.4, 0]], [2.0]).torques(robot)
        >>> torques.tau.shape, bool(torques.peak[1] > 30)
        ((2001, 6), True)
        """
        samples = self.sample(rate_hz)
        tau = robot.inverse_dynamics(samples.q, samples.qd, samples.qdd, gravity=gravity)
        return TrajectoryTorques(samples.t, tau, np.abs(tau).max(axis=0))

    # ----------------------------------------------------------------- peaks
    def segment_peaks(self, order: int) -> NDArray[np.float64]:
        """Exact largest ``|d^order q / dt^order|`` per segment and joint, ``(N, n)`` (order 1, 2 or 3)."""
        peaks = segment_peaks(self.coefficients, self.piece_durations, order)
        return np.maximum.reduceat(peaks, self._segment_starts[:-1], axis=0)

    @property
    def position_range(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Exact lowest and highest ``q`` per joint over the whole trajectory, two ``(n,)`` arrays.

        A quintic or min-jerk spline can overshoot its waypoints; these are its true extremes
        (turning points between waypoints included), not samples.
        """
        low, high = segment_ranges(self.coefficients, self.piece_durations)
        return low.min(axis=0), high.max(axis=0)

    def position_limit_violations(self, robot: Robot, degrees: bool = False) -> list[str]:
        """One message per joint whose exact range leaves ``robot``'s position limits.

        The test and the message are :meth:`armkit.chain.Chain.limit_violations`' (as for
        one configuration, :meth:`Robot.limit_violations`).

        Parameters
        ----------
        robot : Robot
            The arm the trajectory is for (``robot.n`` joints).
        degrees : bool
            Show revolute values and limits in degrees.

        Examples
        --------
        >>> import armkit
        >>> from armkit.trajectory import min_jerk
        >>> robot = armkit.load("probot-anno")        # q2 within +-115 deg
        >>> traj = min_jerk([[0, 0, 0, 0, 0, 0], [0, 1.9, 0, 0, 0, 0], [0] * 6], [1.0, 0.3])
        >>> round(float(traj.position_range[1][1]), 4)   # overshoots the 1.9 rad waypoint
        3.6585
        >>> len(traj.position_limit_violations(robot))
        1
        """
        if robot.n != self.n:
            raise InputError(f"robot: {robot.name} has {robot.n} joints, the trajectory {self.n}")
        low, high = self.position_range
        return robot.chain.limit_violations(low, degrees, q_max=high, where=" between waypoints")

    @property
    def peak_velocity(self) -> NDArray[np.float64]:
        """Largest ``|qd|`` per joint over the whole trajectory [rad/s or m/s], ``(n,)``."""
        return self.segment_peaks(1).max(axis=0)

    @property
    def peak_acceleration(self) -> NDArray[np.float64]:
        """Largest ``|qdd|`` per joint [rad/s^2 or m/s^2], ``(n,)``."""
        return self.segment_peaks(2).max(axis=0)

    @property
    def peak_jerk(self) -> NDArray[np.float64]:
        """Largest ``|qddd|`` per joint [rad/s^3 or m/s^3], ``(n,)``."""
        return self.segment_peaks(3).max(axis=0)

    def jerk_cost(self) -> NDArray[np.float64]:
        """Integral of the squared jerk per joint [rad^2/s^5 or m^2/s^5], ``(n,)``, exact."""
        k1 = self.coefficients.shape[0]
        if k1 < 4:
            return np.zeros(self.n)
        powers = np.arange(3, k1)
        factor = (powers * (powers - 1) * (powers - 2)).astype(float)
        jerk = self.coefficients[3:] * factor[:, None, None]          # powers t^0 .. t^(k-3)
        exponents = np.arange(k1 - 3)
        e = exponents[:, None] + exponents[None, :] + 1
        integral = self.piece_durations[None, None, :] ** e[..., None] / e[..., None]   # (m, m, P)
        return np.einsum("iNn,jNn,ijN->n", jerk, jerk, integral)

    # ----------------------------------------------------------------- export
    def to_csv(self, path: str | Path, rate_hz: float = 100.0, overwrite: bool = False) -> Path:
        """Write samples at ``rate_hz`` to CSV, header ``t,q1..qn,qd1..qdn,qdd1..qddn`` (SI units)."""
        return export.write_csv(self.sample(rate_hz), path, overwrite)

    def to_npz(self, path: str | Path, rate_hz: float = 100.0, overwrite: bool = False) -> Path:
        """Write samples at ``rate_hz`` to NPZ, one array per CSV column name (``t``, ``q1``, ...)."""
        return export.write_npz(self.sample(rate_hz), path, overwrite)
