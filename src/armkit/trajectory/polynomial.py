"""Point-to-point polynomial segments: the quintic and the cubic.

A :class:`PolynomialSegment` holds one polynomial per joint on ``[0, duration]``;
``at_time(t)`` returns position, velocity, acceleration and jerk together (as every
armkit trajectory, ``at_time`` takes times [s]; ``sample`` takes a rate [Hz]).

>>> seg = quintic(0.0, 1.0, 2.0)
>>> q, qd, qdd, qddd = seg.at_time([0.0, 1.0, 2.0])
>>> q[:, 0], qd[:, 0]
(array([0. , 0.5, 1. ]), array([0.    , 0.9375, 0.    ]))
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit._deprecation import deprecated_property, warn_deprecated
from armkit.errors import InputError
from armkit.trajectory._checks import check_durations, check_finite

__all__ = ["PolynomialSegment", "cubic", "quintic", "quintic_coefficients"]

#: Relative slack on ``t`` beyond ``[0, duration]`` accepted by ``at_time`` (rounding of ``t``).
TIME_TOLERANCE = 1e-9


@dataclass(frozen=True)
class PolynomialSegment:
    """One polynomial per joint on ``t`` in ``[0, duration]``.

    Attributes
    ----------
    coefficients : (degree + 1, n) array
        Ascending powers of ``t`` [s]: ``q_j(t) = sum_k coefficients[k, j] * t**k``.
    duration : float
        Length of the segment [s].
    """

    coefficients: NDArray[np.float64]
    duration: float

    @property
    def n(self) -> int:
        """Number of joints (as :attr:`armkit.Robot.n`)."""
        return self.coefficients.shape[1]

    dof = deprecated_property("dof", "n")

    @property
    def degree(self) -> int:
        return self.coefficients.shape[0] - 1

    def at_time(self, t: ArrayLike) -> tuple[NDArray[np.float64], ...]:
        """Position, velocity, acceleration and jerk at times ``t`` [s].

        Parameters
        ----------
        t : float or (N,) array
            Times in ``[0, duration]`` [s].

        Returns
        -------
        q, qd, qdd, qddd : (N, n) arrays
            In the joints' SI units (rad or m) per second to the power 0, 1, 2, 3.
        """
        t = np.atleast_1d(check_finite(t, "t"))
        slack = TIME_TOLERANCE * max(1.0, self.duration)
        if t.ndim != 1 or np.any(t < -slack) or np.any(t > self.duration + slack):
            raise InputError(f"t: expected times in [0, {self.duration:g}] s, got "
                             f"{t.min():g} .. {t.max():g}")
        powers = t[:, None] ** np.arange(self.degree + 1)                  # (N, degree + 1)
        out = []
        for order in range(4):
            scaled = self.coefficients[order:] * _falling_factorial(self.degree, order)[:, None]
            out.append(powers[:, :scaled.shape[0]] @ scaled if scaled.size else np.zeros((t.size, self.n)))
        return tuple(out)

    def sample(self, t: ArrayLike) -> tuple[NDArray[np.float64], ...]:
        """Deprecated name of :meth:`at_time` (``sample`` takes a rate [Hz] elsewhere); warns."""
        warn_deprecated("PolynomialSegment.sample(t)", ".at_time(t)")
        return self.at_time(t)


def _falling_factorial(degree: int, order: int) -> NDArray[np.float64]:
    """``k! / (k - order)!`` for ``k = order .. degree``: the factors of the ``order``-th derivative."""
    k = np.arange(order, degree + 1)
    return np.prod(k[:, None] - np.arange(order), axis=1).astype(float)


def _boundary(q0: ArrayLike, q1: ArrayLike, duration: float, **derivatives: ArrayLike):
    arrays = [check_finite(q0, "q0"), check_finite(q1, "q1")]
    arrays += [check_finite(value, name) for name, value in derivatives.items()]
    try:
        shape = np.broadcast_shapes((1,), *(a.shape for a in arrays))
    except ValueError as exc:
        shapes = ", ".join(str(np.shape(a)) for a in arrays)
        raise InputError(f"boundary values have incompatible shapes: {shapes}") from exc
    if len(shape) != 1:
        raise InputError(f"q0, q1: expected scalars or (n,) arrays, got shape {shape}")
    return float(check_durations(duration, name="duration")[0]), shape, [np.atleast_1d(a) for a in arrays]


def quintic_coefficients(q0: ArrayLike, q1: ArrayLike, T: ArrayLike, v0: ArrayLike = 0.0,
                         v1: ArrayLike = 0.0, a0: ArrayLike = 0.0,
                         a1: ArrayLike = 0.0) -> NDArray[np.float64]:
    """Coefficients ``(6, ...)`` (ascending powers of ``t``) of the quintic meeting the boundary values.

    Every argument broadcasts; ``T`` [s] is the duration. No checks (see :func:`quintic`).
    """
    h = np.subtract(q1, q0)
    c3 = (20 * h - (8 * v1 + 12 * v0) * T - (3 * a0 - a1) * T**2) / (2 * T**3)
    c4 = (-30 * h + (14 * v1 + 16 * v0) * T + (3 * a0 - 2 * a1) * T**2) / (2 * T**4)
    c5 = (12 * h - 6 * (v1 + v0) * T + (a1 - a0) * T**2) / (2 * T**5)
    return np.stack(np.broadcast_arrays(q0, v0, np.multiply(a0, 0.5), c3, c4, c5)).astype(float)


def quintic(q0: ArrayLike, q1: ArrayLike, duration: float, v0: ArrayLike = 0.0, v1: ArrayLike = 0.0,
            a0: ArrayLike = 0.0, a1: ArrayLike = 0.0) -> PolynomialSegment:
    """The quintic from ``q0`` to ``q1`` in ``duration`` with the given end velocities and accelerations.

    Parameters
    ----------
    q0, q1 : float or (n,) array
        Start and end positions [rad or m].
    duration : float
        [s], positive.
    v0, v1 : float or (n,) array
        Start and end velocities [rad/s or m/s], zero by default.
    a0, a1 : float or (n,) array
        Start and end accelerations [rad/s^2 or m/s^2], zero by default.

    Examples
    --------
    >>> seg = quintic([0.0, 1.0], [1.0, 1.0], 1.0)
    >>> seg.at_time(0.5)[0]
    array([[0.5, 1. ]])
    """
    duration, shape, (q0, q1, v0, v1, a0, a1) = _boundary(q0, q1, duration, v0=v0, v1=v1, a0=a0, a1=a1)
    coefficients = quintic_coefficients(q0, q1, duration, v0, v1, a0, a1)
    return PolynomialSegment(np.broadcast_to(coefficients, (6, *shape)).copy(), duration)


def cubic(q0: ArrayLike, q1: ArrayLike, duration: float, v0: ArrayLike = 0.0,
          v1: ArrayLike = 0.0) -> PolynomialSegment:
    """The cubic from ``q0`` to ``q1`` in ``duration`` [s] with end velocities ``v0``, ``v1``.

    Its acceleration jumps at both ends (``6 (q1 - q0) / T^2`` for zero end velocities):
    the comparison case for :func:`quintic`.

    Examples
    --------
    >>> cubic(0.0, 1.0, 1.0).at_time(0.5)[1]
    array([[1.5]])
    """
    duration, shape, (q0, q1, v0, v1) = _boundary(q0, q1, duration, v0=v0, v1=v1)
    T = duration
    h = q1 - q0
    c2 = (3 * h - (2 * v0 + v1) * T) / T**2
    c3 = (-2 * h + (v0 + v1) * T) / T**3
    return PolynomialSegment(np.stack([np.broadcast_to(c, shape) for c in (q0, v0, c2, c3)]), duration)
