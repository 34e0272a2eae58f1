"""Resolved-rate control: the joint velocities that give a desired tool twist.

One control step maps a twist ``[v; w]`` (linear velocity of the tool origin [m/s] over
angular velocity [rad/s], the row order of :meth:`armkit.Robot.jacobian`) to joint
velocities with damped least squares (DLS)::

    qd = J^T (J J^T + lambda^2 I)^-1 twist          (n >= 6)
    qd = (J^T J + lambda^2 I)^-1 J^T twist          (n < 6, the same solution)

The damping grows as the smallest singular value ``sigma_min`` of ``J`` falls below a
threshold ``eps`` (Nakamura and Hanafusa 1986; Maciejewski and Klein 1988)::

    lambda^2 = (1 - (sigma_min / eps)^2) * lambda_max^2   if sigma_min < eps, else 0

so away from singularities the step is the exact inverse and near them the joint
velocities stay bounded (``|qd| <= |twist| / (2 lambda)``). Finally, if a joint velocity
would exceed its limit (:attr:`armkit.Robot.max_velocity`), all of them are scaled down
by the same factor, which keeps the direction of motion.

The step is computed in the core (``rate_step`` beside the numeric IK's damped least-squares
step, which it calls): ``sigma_min`` comes from the eigenvalues of the small Gram matrix,
which is cheaper than an SVD of ``J`` and accurate to about ``1e-8`` near zero, more than
the damping needs. With no damping asked (``threshold = 0``) at an exact singularity (the
smallest Gram eigenvalue within rounding of zero, ``1e-13 trace(J^T J)``) the step is the
least-squares one: a damping of ``1e-10 trace(J^T J)``, within about 1e-7 of ``pinv(J) @ twist``.
The core solves for ``J`` scaled by the power of two that brings its largest entry into [0.5, 1)
(and scales ``sigma_min``, the damping and ``qd`` back): exact, so a Jacobian of ordinary size gets
the same bits, and one of 1e-300 (or 1e300) entries, whose ``J J^T`` would underflow to zero
(overflow), its true step: before, ``qd = 0`` without damping.
:class:`ResolvedRate` evaluates the Jacobian with the shared single-configuration
:class:`armkit.kinematics.ChainKernel` (``benchmarks/bench_control.py`` times one step).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit import _core
from armkit._params import float_array, float_in_range
from armkit.chain import MAX_VALUE
from armkit.errors import InputError
from armkit.kinematics import ChainKernel
from armkit.robot import Robot

__all__ = [
    "DEFAULT_MAX_DAMPING",
    "DEFAULT_THRESHOLD",
    "RateStep",
    "ResolvedRate",
    "damping",
    "joint_velocity",
    "scale_to_limits",
]

#: Default ``eps``: the smallest singular value of ``J`` below which damping starts.
DEFAULT_THRESHOLD = 0.04
#: Default ``lambda_max``: the damping at a singularity (``sigma_min = 0``).
DEFAULT_MAX_DAMPING = 0.04

def damping(sigma_min: ArrayLike, threshold: float = DEFAULT_THRESHOLD,
            max_damping: float = DEFAULT_MAX_DAMPING) -> NDArray[np.float64]:
    """The squared damping ``lambda^2`` for a smallest singular value ``sigma_min``.

    Parameters
    ----------
    sigma_min : float or array
        Smallest singular value of the Jacobian (>= 0).
    threshold : float
        ``eps``: no damping for ``sigma_min >= eps``.
    max_damping : float
        ``lambda_max``: the damping at ``sigma_min = 0``.

    Returns
    -------
    ndarray
        ``(1 - (sigma_min / eps)^2) * lambda_max^2`` below ``eps``, else 0; same shape as
        ``sigma_min``. It rises continuously from 0 at ``eps`` to ``lambda_max^2`` at 0.

    Examples
    --------
    >>> damping([0.0, 0.02, 0.04, 0.1], threshold=0.04, max_damping=0.04)
    array([0.0016, 0.0012, 0.    , 0.    ])
    """
    threshold, max_damping = _checked_law(threshold, max_damping)
    sigma = float_array(sigma_min, "sigma_min", "singular values >= 0")
    if not (sigma >= 0).all() or not np.isfinite(sigma).all():
        raise InputError(f"sigma_min: expected finite singular values >= 0, got {sigma.tolist()}",
                         parameter="sigma_min", value=sigma_min)
    rate_damping = np.vectorize(_core.rate_damping, otypes=[float])
    return rate_damping(sigma, threshold, max_damping)


#: Largest threshold and max_damping the damping law takes: a singular value or a damping of a
#: million (m or rad per joint unit) is no arm's; larger ones overflow lambda^2.
_LARGEST_LAW = 1e6


def _checked_law(threshold: object, max_damping: object) -> tuple[float, float]:
    """The damping law's ``threshold`` and ``max_damping``, each a real number from 0 to 1e6."""
    return (float_in_range(threshold, "threshold", 0.0, _LARGEST_LAW, "a smallest singular value"),
            float_in_range(max_damping, "max_damping", 0.0, _LARGEST_LAW, "a damping"))


def scale_to_limits(qd: ArrayLike, max_velocity: ArrayLike) -> tuple[NDArray[np.float64], float]:
    """Scale joint velocities down together so that none exceeds its limit.

    Parameters
    ----------
    qd : (..., n) array
        Joint velocities [rad/s or m/s]; a batch is scaled row by row.
    max_velocity : (n,) array
        Limits [rad/s or m/s], ``inf`` for none.

    Returns
    -------
    qd_scaled : (..., n) array
        ``qd * scale``: same direction, every ``|qd_i| <= max_velocity_i``.
    scale : float or (...) array
        The factor applied, in ``(0, 1]``.

    Examples
    --------
    >>> scale_to_limits([2.0, 0.5], [1.0, 1.0])
    (array([1.  , 0.25]), 0.5)
    >>> scale_to_limits([2.0, 0.5], 1.0)  # one limit for every joint
    (array([1.  , 0.25]), 0.5)
    """
    qd = float_array(qd, "qd", "joint velocities (n,) or a batch (..., n)")
    limits = float_array(max_velocity, "max_velocity", "one limit or one per joint")
    if not np.isfinite(qd).all():
        raise InputError(f"qd: expected finite joint velocities, got {qd.tolist()}", parameter="qd", value=qd)
    if not (limits > 0).all():  # inf: no limit; NaN, 0 and negative ones refused
        raise InputError(f"max_velocity: expected limits > 0 (inf for none), got {limits.tolist()}",
                         parameter="max_velocity", value=max_velocity)
    if qd.ndim == 0 or qd.shape[-1] == 0:
        raise InputError(f"qd: expected joint velocities (n,) or a batch (..., n), got {qd!r}",
                         parameter="qd", value=qd)
    if limits.ndim > 1 or limits.size not in (1, qd.shape[-1]):
        raise InputError(f"max_velocity: expected one limit or one per joint ({qd.shape[-1]}), got shape "
                         f"{limits.shape}", parameter="max_velocity", value=max_velocity)
    with np.errstate(over="ignore"):  # a limit of 1e-320: its inverse is inf, the scale 0
        inverse_max_velocity = np.ascontiguousarray(np.broadcast_to(1.0 / limits, qd.shape[-1:]))
    rows = np.ascontiguousarray(qd.reshape(-1, qd.shape[-1]))
    scale = np.array([_core.limit_scale(row, inverse_max_velocity) for row in rows]).reshape(qd.shape[:-1])
    return qd * scale[..., None], (float(scale) if scale.ndim == 0 else scale)


class RateStep(NamedTuple):
    """One resolved-rate step.

    Attributes
    ----------
    qd : (n,) array
        Joint velocities [rad/s or m/s], after velocity scaling.
    sigma_min : float
        Smallest singular value of the base-frame Jacobian at ``q``.
    damping : float
        ``lambda^2`` used (0 away from singularities); ``inf`` or 0 where that value is beyond a
        float's range (a ``J`` of entries near 1e300 or 1e-300: the step itself is solved on ``J``
        scaled by a power of two, and is right).
    scale : float
        Factor in ``(0, 1]`` applied to keep every joint within its velocity limit.
    """

    qd: NDArray[np.float64]
    sigma_min: float
    damping: float
    scale: float


class ResolvedRate:
    """Resolved-rate controller of one robot: twist in, joint velocities out.

    Parameters
    ----------
    robot : Robot
    threshold : float
        ``eps`` of :func:`damping`: smallest singular value where damping starts.
    max_damping : float
        ``lambda_max`` of :func:`damping`.
    limit_velocity : bool
        Scale joint velocities to :attr:`Robot.max_velocity` (keeping the direction).

    Notes
    -----
    :meth:`step` is the fast path for control loops: it takes a float64 ``(n,)`` ``q``
    and a base-frame ``(6,)`` twist without checking them. :meth:`joint_velocity` checks
    its input and accepts tool-frame twists. The controller holds only the robot's constants
    (no work buffers), so one controller can serve several threads.

    Examples
    --------
    >>> import armkit
    >>> robot = armkit.load("probot-anno")
    >>> control = ResolvedRate(robot)
    >>> qd = control.joint_velocity([0, 0, 0, 0, 0, 0], [0.01, 0, 0, 0, 0, 0])
    >>> bool(np.allclose(robot.jacobian([0, 0, 0, 0, 0, 0]) @ qd, [0.01, 0, 0, 0, 0, 0]))
    True
    """

    def __init__(self, robot: Robot, *, threshold: float = DEFAULT_THRESHOLD,
                 max_damping: float = DEFAULT_MAX_DAMPING, limit_velocity: bool = True) -> None:
        threshold, max_damping = _checked_law(threshold, max_damping)
        self.robot = robot
        self.threshold = threshold
        self.max_damping = max_damping
        self.limit_velocity = bool(limit_velocity)
        self._n = robot.n
        self._inverse_max_velocity = 1.0 / robot.max_velocity
        #: Tool pose and Jacobian of one configuration (:class:`armkit.kinematics.ChainKernel`).
        self.kernel = ChainKernel(robot)

    # ------------------------------------------------------------------ fast path
    def solve(self, J: NDArray[np.float64], twist: NDArray[np.float64]) -> RateStep:
        """One control step through a given base-frame Jacobian, with only the core's checks: DLS
        joint velocities for a base-frame twist (in the core), then velocity scaling.

        Parameters
        ----------
        J : (6, n) array
            C-ordered float64 Jacobian at the current configuration (:meth:`armkit.Robot.jacobian`).
        twist : (6,) array
            C-ordered float64 ``[v; w]`` of the tool origin in the base frame [m/s, rad/s].

        Returns
        -------
        RateStep
            Joint velocities, ``sigma_min``, the damping used and the velocity scale.

        Raises
        ------
        InputError
            If ``J`` or ``twist`` is not an array of its shape, holds NaN or infinite values, or the
            step overflows (the core checks; Python looks only when it refused).

        Examples
        --------
        >>> import armkit
        >>> robot = armkit.load("ur5")
        >>> q = np.array([0.1, -1.2, 1.4, -0.3, 1.1, 0.2])
        >>> step = ResolvedRate(robot).solve(robot.jacobian(q), np.array([0.01, 0, 0, 0, 0, 0]))
        >>> bool(np.allclose(robot.jacobian(q) @ step.qd, [0.01, 0, 0, 0, 0, 0])), step.scale
        (True, 1.0)
        """
        qd = np.empty(self._n)
        limits = self._inverse_max_velocity if self.limit_velocity else None
        try:
            info = _core.rate_step(J, twist, self.threshold, self.max_damping, limits, qd)
        except (TypeError, ValueError) as exc:  # the core checks shapes and finiteness; name the culprit
            raise self._unsolvable(J, twist, exc) from exc
        return RateStep(qd, *info)

    def _unsolvable(self, J: object, twist: object, refusal: Exception) -> InputError:
        """The :class:`InputError` for the ``J`` or ``twist`` the core refused (``refusal``) in solve."""
        for name, value, shape in (("J", J, (6, self._n)), ("twist", twist, (6,))):
            if not isinstance(value, np.ndarray) or value.shape != shape or value.dtype.kind not in "fiu":
                shown = (f"shape {value.shape}, dtype {value.dtype}" if isinstance(value, np.ndarray)
                         else type(value).__name__)
                return InputError(f"{name}: expected a float64 array of shape {shape}, got {shown} (solve "
                                  f"takes arrays as they are; joint_velocity() checks and converts)",
                                  parameter=name, value=value)
            if not np.isfinite(value).all():
                return InputError(f"{name}: contains NaN or infinite values: {value.tolist()}",
                                  parameter=name, value=value)
        check_twist(twist)  # components beyond MAX_VALUE
        if "overflow" in str(refusal):
            return InputError(f"twist {twist.tolist()}: the joint velocities through J overflow; expected a "
                              f"twist the arm can follow", parameter="twist", value=twist)
        return InputError(f"J, twist: {refusal}", parameter="twist", value=twist)

    def step(self, q: NDArray[np.float64], twist: NDArray[np.float64]) -> RateStep:
        """One control step without input checks: ``q`` float64 ``(n,)``, base-frame twist ``(6,)``.

        Parameters
        ----------
        q : (n,) array
            Joint values [rad or m].
        twist : (6,) array
            ``[v; w]`` of the tool origin in the base frame [m/s, rad/s].
        """
        return self.solve(self.kernel.jacobian(q), twist)

    # ------------------------------------------------------------------ checked API
    def joint_velocity(self, q: ArrayLike, twist: ArrayLike, frame: str = "base") -> NDArray[np.float64]:
        """Joint velocities ``(n,)`` [rad/s or m/s] for a tool twist, with input checks.

        Parameters
        ----------
        q : (n,) array
            Joint values [rad or m].
        twist : (6,) array
            ``[vx, vy, vz, wx, wy, wz]`` [m/s, rad/s] of the tool origin.
        frame : {"base", "tool"}
            Frame the twist's components are written in.
        """
        q = self.robot.check_q(q)
        if q.ndim != 1:
            raise InputError(f"q: expected one configuration of {self._n} values, got shape {q.shape}")
        twist = check_twist(twist)
        T, J = self.kernel.fk_jacobian(q)
        if frame == "tool":
            twist = np.concatenate((T[:3, :3] @ twist[:3], T[:3, :3] @ twist[3:]))
        elif frame != "base":
            raise InputError(f"frame {frame!r}: expected 'base' or 'tool'")
        return self.solve(J, twist).qd


def check_twist(twist: ArrayLike, name: str = "twist") -> NDArray[np.float64]:
    """Return ``twist`` as a finite float64 ``(6,)`` array or raise :class:`InputError`."""
    try:
        twist = np.asarray(twist, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{name}: expected 6 numbers [vx vy vz wx wy wz], got {twist!r}") from exc
    if twist.shape != (6,):
        raise InputError(f"{name}: expected 6 numbers [vx vy vz wx wy wz] (m/s, rad/s), "
                         f"got shape {twist.shape}")
    if not np.all(np.isfinite(twist)):
        raise InputError(f"{name}: contains NaN or infinite values: {twist.tolist()}")
    if not np.all(np.abs(twist) <= MAX_VALUE):
        raise InputError(f"{name}: expected components from {-MAX_VALUE:g} to {MAX_VALUE:g} (m/s, rad/s), "
                         f"got {twist.tolist()}", parameter=name, value=twist)
    return twist


def joint_velocity(robot: Robot, q: ArrayLike, twist: ArrayLike, frame: str = "base", *,
                   threshold: float = DEFAULT_THRESHOLD, max_damping: float = DEFAULT_MAX_DAMPING,
                   limit_velocity: bool = True) -> NDArray[np.float64]:
    """Joint velocities ``(n,)`` for a desired tool twist (one-off; loops use :class:`ResolvedRate`).

    Parameters
    ----------
    robot : Robot
    q : (n,) array
        Joint values [rad or m].
    twist : (6,) array
        ``[vx, vy, vz, wx, wy, wz]`` of the tool origin [m/s, rad/s].
    frame : {"base", "tool"}
        Frame the twist is written in.
    threshold, max_damping, limit_velocity
        See :class:`ResolvedRate`.

    Examples
    --------
    >>> import armkit
    >>> robot = armkit.load("probot-anno")
    >>> joint_velocity(robot, [0, 0, 0, 0, 0, 0], [0, 0, -0.01, 0, 0, 0]).round(4)
    array([ 0.    ,  0.    , -0.0437,  0.    ,  0.0437,  0.    ])
    """
    control = ResolvedRate(robot, threshold=threshold, max_damping=max_damping,
                           limit_velocity=limit_velocity)
    return control.joint_velocity(q, twist, frame)
