"""LSPB (linear segment with parabolic blends): the trapezoidal velocity profile.

>>> seg = lspb(0.0, 1.0, 2.0)          # cruise velocity 1.5 * 1 / 2 = 0.75
>>> q, qd, qdd, qddd = seg.at_time([0.0, 1.0, 2.0])
>>> q[:, 0], qd[:, 0]
(array([0. , 0.5, 1. ]), array([0.  , 0.75, 0.  ]))
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit._deprecation import deprecated_property, warn_deprecated
from armkit.errors import InputError
from armkit.trajectory._checks import check_durations, check_finite
from armkit.trajectory.polynomial import TIME_TOLERANCE

__all__ = ["TrapezoidSegment", "lspb"]


@dataclass(frozen=True)
class TrapezoidSegment:
    """Per joint: constant acceleration for ``blend_time``, cruise, constant deceleration.

    Attributes
    ----------
    q0, q1 : (n,) arrays
        Start and end positions [rad or m].
    velocity : (n,) array
        Cruise velocity [rad/s or m/s] (sign of ``q1 - q0``).
    blend_time : (n,) array
        Duration of each parabolic blend [s]; zero for joints that do not move.
    duration : float
        [s].
    """

    q0: NDArray[np.float64]
    q1: NDArray[np.float64]
    velocity: NDArray[np.float64]
    blend_time: NDArray[np.float64]
    duration: float

    @property
    def n(self) -> int:
        """Number of joints (as :attr:`armkit.Robot.n`)."""
        return self.q0.size

    dof = deprecated_property("dof", "n")

    @property
    def acceleration(self) -> NDArray[np.float64]:
        """Blend acceleration magnitude with sign [rad/s^2 or m/s^2], ``(n,)``."""
        moving = self.blend_time > 0
        return np.divide(self.velocity, self.blend_time, out=np.zeros(self.n), where=moving)

    def sample(self, t: ArrayLike) -> tuple[NDArray[np.float64], ...]:
        """Deprecated name of :meth:`at_time` (``sample`` takes a rate [Hz] elsewhere); warns."""
        warn_deprecated("TrapezoidSegment.sample(t)", ".at_time(t)")
        return self.at_time(t)

    def at_time(self, t: ArrayLike) -> tuple[NDArray[np.float64], ...]:
        """Position, velocity, acceleration and jerk ``(N, n)`` at times ``t`` [s].

        The jerk is zero between the four switching instants, where it is unbounded.
        """
        t = np.atleast_1d(check_finite(t, "t"))[:, None]
        T = self.duration
        if np.any(t < -TIME_TOLERANCE * max(1.0, T)) or np.any(t > T + TIME_TOLERANCE * max(1.0, T)):
            raise InputError(f"t: expected times in [0, {T:g}] s, got {t.min():g} .. {t.max():g}")
        t = np.clip(t, 0.0, T)
        tb, V, a = self.blend_time, self.velocity, self.acceleration
        rest = T - t
        start, end = t < tb, t > T - tb
        q = np.where(start, self.q0 + a / 2 * t**2,
                     np.where(end, self.q1 - a / 2 * rest**2, (self.q0 + self.q1 - V * T) / 2 + V * t))
        qd = np.where(start, a * t, np.where(end, a * rest, V))
        qdd = np.where(start, a, np.where(end, -a, 0.0))
        return q, qd, qdd, np.zeros_like(q)


def lspb(q0: ArrayLike, q1: ArrayLike, duration: float,
         velocity: ArrayLike | None = None) -> TrapezoidSegment:
    """Trapezoidal-velocity segment from ``q0`` to ``q1`` in ``duration`` [s].

    Parameters
    ----------
    q0, q1 : float or (n,) array
        Start and end positions [rad or m]; start and end at rest.
    duration : float
        [s], positive.
    velocity : float or (n,) array, optional
        Cruise speed magnitude per joint [rad/s or m/s]. It must lie in
        ``(|q1 - q0| / T, 2 |q1 - q0| / T]`` (the upper end is a triangle profile);
        default ``1.5 |q1 - q0| / T``.

    Examples
    --------
    >>> lspb([0.0, 0.0], [1.0, -2.0], 2.0).blend_time
    array([0.66666667, 0.66666667])
    """
    T = float(check_durations(duration, name="duration")[0])
    q0, q1 = np.broadcast_arrays(np.atleast_1d(check_finite(q0, "q0")), np.atleast_1d(check_finite(q1, "q1")))
    h = q1 - q0
    speed = 1.5 * np.abs(h) / T if velocity is None else np.broadcast_to(
        np.abs(check_finite(velocity, "velocity")), h.shape)
    moving = h != 0
    low, high = np.abs(h) / T, 2 * np.abs(h) / T
    bad = moving & ((speed <= low) | (speed > high * (1 + 1e-12)))
    if np.any(bad):
        j = int(np.flatnonzero(bad)[0])
        raise InputError(f"velocity: joint {j + 1} needs a cruise speed in ({low[j]:.6g}, {high[j]:.6g}] "
                         f"to move {h[j]:.6g} in {T:g} s, got {speed[j]:.6g}")
    V = np.sign(h) * speed
    blend = np.divide(T * speed - np.abs(h), speed, out=np.zeros_like(h), where=moving)
    return TrapezoidSegment(q0.astype(float), q1.astype(float), V, blend, T)
