"""Closed-loop tool motions: follow sampled poses, straight moves, turns about the tool point.

:func:`track_poses` is the closed loop every motion here uses. At each control step
``k`` it reads the tool pose from forward kinematics and asks resolved-rate control
(:class:`~armkit.control.resolved_rate.ResolvedRate`) for the reference's own twist
(feedforward) plus a correction of the current pose error::

    twist_k = error(T_ref(t_k+1), T_ref(t_k)) / dt + gain * error(T_ref(t_k), T(q_k))
    q_k+1   = q_k + qd_k dt

where ``error(A, B) = [p_A - p_B; log(R_A R_B^T)]`` (base frame). The error left by each
Euler step (second order in the step) is corrected rather than accumulated, so long
motions do not drift; integrating the nominal twist open loop does (see
``tests/test_control_motions.py``). The gain (default 20 1/s, a 50 ms time constant) is
a compromise: a higher gain tracks tighter, but after the velocity limits held the tool
back it brakes harder (the joint velocities change more per step).

Joint limits: a step that would carry a joint past a position limit is shortened so the
joint stops exactly on the limit, and the motion ends there with ``success = False``
and a message naming the joint (``stop_at_limits=False`` raises
:class:`~armkit.errors.JointLimitError` instead). A motion that runs to its end but
finishes farther from the target than the tolerances (for example because the velocity
limits held the tool back) also has ``success = False`` and a message saying why.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit._deprecation import deprecated_property, renamed_argument
from armkit._time import even_time_grid
from armkit.chain import Chain
from armkit.control._checks import check_positive, check_start, refuse_beyond_reach
from armkit.control.resolved_rate import ResolvedRate
from armkit.errors import InputError, JointLimitError, UnreachableError
from armkit.ik.messages import outside_limits
from armkit.kinematics import pose_error
from armkit.poe import MIN_AXIS_LENGTH, direction
from armkit.robot import Robot
from armkit.spatial.rotations import matrix_from_axis_angle, rotation_angle_between
from armkit.spatial.transforms import check_transform
from armkit.trajectory._checks import MAX_DURATION, MIN_DURATION
from armkit.trajectory.joint_trajectory import TrajectoryTorques
from armkit.trajectory.polynomial import quintic

__all__ = ["DEFAULT_DT", "MotionResult", "move_linear", "rotate_about_tool_point", "track_poses"]

#: Default control period [s] of the closed loop.
DEFAULT_DT = 0.002
#: Default feedback gain [1/s] on the pose error (time constant 1 / gain).
DEFAULT_GAIN = 20.0
#: Default final position error [m] within which a motion counts as completed.
POSITION_TOLERANCE = 1e-5
#: Default final orientation error [rad] within which a motion counts as completed.
ORIENTATION_TOLERANCE = 1e-5


@dataclass(frozen=True)
class MotionResult:
    """A closed-loop motion, sampled at the control period.

    Attributes
    ----------
    t : (N,) array
        Times [s] from 0.
    q : (N, n) array
        Joint values [rad or m].
    qd : (N, n) array
        Joint velocities [rad/s or m/s]; row ``k`` is held from ``t[k]`` to ``t[k + 1]``,
        the last row is zero (the motion ends at rest).
    poses : (N, 4, 4) array
        Tool poses ``T_base_tool`` from forward kinematics of ``q``.
    reference : (N, 4, 4) array
        The poses asked for at the same times.
    target : (4, 4) array
        The last pose asked for (at the planned end, even if the motion stopped early).
    position_error, orientation_error : float
        Final distance [m] and angle [rad] between the tool and ``target``.
    max_position_error, max_orientation_error : float
        Largest distance [m] and angle [rad] to the reference over the motion.
    sigma_min : (N,) array
        Smallest Jacobian singular value at each sample (how close to a singularity).
    scale : (N,) array
        Factor in ``(0, 1]`` the joint velocities were scaled by to respect their limits.
    success : bool
        True if the motion ran to its end and finished within the tolerances
        (``POSITION_TOLERANCE``, ``ORIENTATION_TOLERANCE``) of the target (``completed``
        is its deprecated old name).
    message : str
        ``"completed"``, or why not: which joint limit stopped the motion (joint, value,
        time), or how far from the target it ended and what held it back (joint values and
        angles in rad, or in degrees with ``message_degrees``).
    """

    t: NDArray[np.float64]
    q: NDArray[np.float64]
    qd: NDArray[np.float64]
    poses: NDArray[np.float64]
    reference: NDArray[np.float64]
    target: NDArray[np.float64]
    position_error: float
    orientation_error: float
    max_position_error: float
    max_orientation_error: float
    sigma_min: NDArray[np.float64]
    scale: NDArray[np.float64]
    success: bool
    message: str

    completed = deprecated_property("completed", "success")

    @property
    def q_final(self) -> NDArray[np.float64]:
        """Last joint values ``(n,)``."""
        return self.q[-1]

    @property
    def pose_final(self) -> NDArray[np.float64]:
        """Last tool pose ``(4, 4)``."""
        return self.poses[-1]

    def torques(self, robot: Robot, *, gravity: ArrayLike | None = None) -> TrajectoryTorques:
        """The joint torques [N m or N] that drive ``robot`` along this motion, at its samples.

        The velocity ``qd[k]`` held over period ``k`` changes to ``qd[k + 1]`` over the next, so
        the acceleration at sample ``k`` is ``(qd[k + 1] - qd[k]) / dt`` (zero at the last);
        ``tau = ID(q, qd, qdd)`` by :meth:`armkit.Robot.inverse_dynamics`. ``robot`` needs
        inertial parameters (see :mod:`armkit.dynamics`).

        Examples
        --------
        >>> import armkit
        >>> robot = armkit.load("puma560")
        >>> q0 = [0.0, 0.6, -0.8, 0.0, 0.5, 0.0]
        >>> motion = armkit.move_linear(robot, q0, [0.05, 0.0, 0.0], duration=1.0)
        >>> torques = motion.torques(robot)
        >>> torques.tau.shape == motion.q.shape, bool(torques.peak[1] > 10)
        (True, True)
        """
        dt = np.diff(self.t)
        qdd = np.zeros_like(self.qd)
        qdd[:-1] = np.diff(self.qd, axis=0) / dt[:, None]
        tau = robot.inverse_dynamics(self.q, self.qd, qdd, gravity=gravity)
        return TrajectoryTorques(self.t, tau, np.abs(tau).max(axis=0))


def _check_vector(value: ArrayLike, name: str, unit: str) -> NDArray[np.float64]:
    try:
        v = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{name}: expected 3 numbers [{unit}], got {value!r}") from exc
    if v.shape != (3,):
        raise InputError(f"{name}: expected 3 numbers [{unit}], got shape {v.shape}")
    if not np.all(np.isfinite(v)):
        raise InputError(f"{name}: contains NaN or infinite values: {v.tolist()}")
    return v


def _limit_stop(chain: Chain, q: NDArray[np.float64], step: NDArray[np.float64]) -> tuple[float, int]:
    """Fraction of ``step`` that keeps ``q`` inside the limits, and the joint that bounds it (-1: none)."""
    outside = chain.outside_limits(q + step)
    if not outside.any():
        return 1.0, -1
    bound = np.where(step < 0, chain.lower, chain.upper)
    with np.errstate(divide="ignore", invalid="ignore"):
        fraction = np.where(outside, (bound - q) / step, np.inf)
    joint = int(np.argmin(fraction))
    return float(np.clip(fraction[joint], 0.0, 1.0)), joint


def _joint_text(robot: Robot, q: NDArray[np.float64], degrees: bool, joint: int | None = None) -> str:
    """``q`` ``(n,)`` [rad or m] as text with its units: ``[v1, v2, ...] deg`` (a unit per value where
    they differ), or joint ``joint``'s ``v unit`` alone; revolute values in degrees with ``degrees``,
    else in rad, prismatic ones in m (``Chain.display_units``); 4 significant digits (6 for one joint),
    rounding noise below 1e-9 of the shown unit shown as 0, as ``Chain.limit_violations`` does."""
    scales, units = robot.chain.display_units(degrees)
    shown = q * scales
    shown = np.where(np.abs(shown) < 1e-9, 0.0, shown)
    if joint is not None:
        return f"{shown[joint]:.6g} {units[joint]}"
    if len(set(units)) == 1:
        return f"[{', '.join(f'{v:.4g}' for v in shown)}] {units[0]}"
    return f"[{', '.join(f'{v:.4g} {unit}' for v, unit in zip(shown, units, strict=True))}]"


def _target_check(robot: Robot, target: NDArray[np.float64], q_final: NDArray[np.float64],
                  degrees: bool) -> str:
    """Whether IK (closed form, or numeric from ``q_final``) reaches ``target`` inside the limits, said
    as the end of a sentence on a motion that stopped short of it near a singularity (joint values
    in degrees with ``degrees``)."""
    try:
        q = robot.ik(target, near=q_final)
    except JointLimitError as exc:  # only outside the limits: said again in the message's units
        if degrees and exc.q is not None:
            exc = outside_limits(robot.chain, exc.q, "", degrees=True)
        return f"IK of the target says: {exc}"
    except UnreachableError as exc:  # out of reach (distances in m, angles in rad and deg)
        return f"IK of the target says: {exc}"
    return (f"the target is reachable (IK finds q = {_joint_text(robot, q, degrees)}, inside the limits), so "
            f"the damping held the arm back near the singularity: move slower (a longer duration or, for a "
            f"turn, a lower angular velocity)")


def _shortfall(result_errors: tuple[float, float], scale: NDArray[np.float64],
               sigma: NDArray[np.float64], control: ResolvedRate, target: NDArray[np.float64],
               q_final: NDArray[np.float64], degrees: bool) -> str:
    """Why a motion that ran to its end (at ``q_final``) did not reach its ``target`` pose (angles in
    degrees with ``degrees``)."""
    position, angle = result_errors
    angle_shown = f"{np.degrees(angle):.3g} deg" if degrees else f"{angle:.3g} rad"
    text = f"the tool ended {position:.3g} m and {angle_shown} from the target"
    n = control.robot.n
    if n < 6:
        return (f"{text}: an arm with {n} joints cannot follow every pose path (the motion holds or "
                f"turns the tool's orientation as well as moving its point)")
    if sigma[-1] < control.threshold:
        return (f"{text}: the arm ended near a singularity (smallest singular value {sigma[-1]:.3g}, below "
                f"the damping threshold {control.threshold:g}), and "
                f"{_target_check(control.robot, target, q_final, degrees)}")
    if scale.min() < 1.0:
        return (f"{text}: the joint velocity limits held it back (velocities scaled down to "
                f"{scale.min():.0%} at the worst step); allow a longer duration")
    if sigma.min() < control.threshold:
        return (f"{text}: near a singularity (smallest singular value {sigma.min():.3g}) the "
                f"damping held it back")
    return f"{text}: the closed loop did not settle (raise the gain or shorten dt)"


def track_poses(robot: Robot, q0: ArrayLike, t: ArrayLike, reference: ArrayLike, *,
                control: ResolvedRate | None = None, gain: float = DEFAULT_GAIN,
                stop_at_limits: bool = True, position_tolerance: float = POSITION_TOLERANCE,
                orientation_tolerance: float = ORIENTATION_TOLERANCE,
                message_degrees: bool = False) -> MotionResult:
    """Follow sampled tool poses in closed loop from ``q0`` (see the module docstring).

    Parameters
    ----------
    robot : Robot
    q0 : (n,) array
        Start joint values [rad or m], inside the limits.
    t : (N,) array
        Increasing times [s]; each interval is one control step.
    reference : (N, 4, 4) array
        Tool poses to follow at ``t``; ``reference[0]`` is normally ``robot.fk(q0)``.
    control : ResolvedRate, optional
        Controller (damping and velocity limits); default ``ResolvedRate(robot)``.
    gain : float
        Feedback gain [1/s] on the pose error; ``gain * dt <= 1``.
    stop_at_limits : bool
        At a joint limit, stop and report (True) or raise :class:`JointLimitError` (False).
    position_tolerance, orientation_tolerance : float
        Final errors [m, rad] within which the motion counts as completed.
    message_degrees : bool
        Say revolute joint values and angles in the result's ``message`` in degrees (as
        ``armkit move --deg`` prints them); every input and array stays in rad.

    Returns
    -------
    MotionResult
    """
    q = check_start(robot, q0)
    t = np.asarray(t, dtype=float)
    if t.ndim != 1 or t.size < 2 or not np.all(np.isfinite(t)) or np.any(np.diff(t) <= 0):
        raise InputError(f"t: expected at least 2 finite increasing times, got {t!r}")
    reference = check_transform(reference, "reference")  # rigid, as the final IK check takes it
    if reference.shape != (t.size, 4, 4):
        raise InputError(f"reference: expected {t.size} finite 4x4 poses, got shape {reference.shape}")
    gain = check_positive(gain, "gain", "1/s")
    _check_period(float(np.diff(t).max()), gain, "the longest step of t", "t")
    control = ResolvedRate(robot) if control is None else control
    N, n = t.size, robot.n
    qs, qds = np.zeros((N, n)), np.zeros((N, n))
    poses, sigma, scale = np.zeros((N, 4, 4)), np.zeros(N), np.ones(N)
    qs[0] = q
    lower, upper = robot.limits.T
    message, last = "", N - 1
    for k in range(N - 1):
        T, J = control.kernel.fk_jacobian(q)
        poses[k] = T
        dt = t[k + 1] - t[k]
        feedforward = pose_error(reference[k + 1], reference[k]) / dt
        rate = control.solve(J, feedforward + gain * pose_error(reference[k], T))
        sigma[k], scale[k] = rate.sigma_min, rate.scale
        fraction, joint = _limit_stop(robot.chain, q, rate.qd * dt)
        qds[k] = rate.qd * fraction
        q = q + qds[k] * dt
        if joint >= 0:
            side = "lower" if rate.qd[joint] < 0 else "upper"
            q[joint] = lower[joint] if side == "lower" else upper[joint]
            value = _joint_text(robot, q, message_degrees, joint)
            message = (f"joint {robot.joint_names[joint]} reached its {side} limit {value} at "
                       f"t = {t[k] + fraction * dt:.4g} s of {t[-1]:.4g} s; the motion stopped there")
            if not stop_at_limits:
                raise JointLimitError(message, q.copy(), joint=robot.joint_names[joint],
                                      value=float(q[joint]), limits=(lower[joint], upper[joint]))
            last = k + 1
        qs[k + 1] = q
        if message:
            break
    T, J = control.kernel.fk_jacobian(q)
    poses[last] = T
    sigma[last] = control.solve(J, np.zeros(6)).sigma_min
    sl = slice(0, last + 1)
    # hypot, not norm: a target 1e160 m or farther is that far away, not inf
    errors = (float(np.hypot.reduce(T[:3, 3] - reference[-1, :3, 3])),
              float(rotation_angle_between(T, reference[-1])))
    if not message and (errors[0] > position_tolerance or errors[1] > orientation_tolerance):
        message = _shortfall(errors, scale[sl], sigma[sl], control, reference[-1], q, message_degrees)
    return MotionResult(
        t=t[sl].copy(), q=qs[sl], qd=qds[sl], poses=poses[sl], reference=reference[sl].copy(),
        target=reference[-1].copy(), position_error=errors[0], orientation_error=errors[1],
        max_position_error=float(np.hypot.reduce(poses[sl, :3, 3] - reference[sl, :3, 3], axis=-1).max()),
        max_orientation_error=float(rotation_angle_between(poses[sl], reference[sl]).max()),
        sigma_min=sigma[sl], scale=scale[sl], success=not message, message=message or "completed")


def move_linear(robot: Robot, q0: ArrayLike, displacement: ArrayLike, duration: float, *,
                frame: str = "base", dt: float = DEFAULT_DT, control: ResolvedRate | None = None,
                gain: float = DEFAULT_GAIN, stop_at_limits: bool = True,
                message_degrees: bool = False) -> MotionResult:
    """Move the tool along a straight line by ``displacement``, orientation unchanged.

    The path is ``p(t) = p0 + s(t) * displacement`` with the quintic time law ``s(t)``
    (0 to 1, zero velocity and acceleration at both ends), followed in closed loop.

    Parameters
    ----------
    robot : Robot
    q0 : (n,) array
        Start joint values [rad or m].
    displacement : (3,) array
        Tool displacement [m], in the base frame or the start tool frame (``frame``).
    duration : float
        [s], positive.
    frame : {"base", "tool"}
    dt : float
        Control period [s].
    control : ResolvedRate, optional
        Damping and velocity-limit settings.
    gain : float
        Feedback gain [1/s] on the pose error (see :func:`track_poses`).
    stop_at_limits, message_degrees : bool
        See :func:`track_poses`.

    Returns
    -------
    MotionResult

    Raises
    ------
    UnreachableError
        Before any step, if the target lies beyond the arm's reach (:attr:`armkit.chain.Chain.reach`).

    Examples
    --------
    >>> import armkit
    >>> robot = armkit.load("probot-anno")
    >>> result = move_linear(robot, [0, 0, 0, 0, 0, 0], [0.15, 0, -0.15], duration=3.0)
    >>> result.pose_final[:3, 3].round(4) + 0.0  # + 0.0: no "-0." for a coordinate at rounding level
    array([0.3789, 0.    , 0.304 ])
    >>> bool(result.position_error < 1e-6)
    True
    """
    q0 = check_start(robot, q0)
    given = _check_vector(displacement, "displacement", "m")
    duration = _motion_duration(check_positive(duration, "duration", "s"), "the move")
    dt = check_positive(dt, "dt", "s")
    _check_period(dt, check_positive(gain, "gain", "1/s"), "dt", "dt")
    T0 = robot.fk(q0)
    if frame == "tool":
        displacement = T0[:3, :3] @ given
    elif frame == "base":
        displacement = given
    else:
        raise InputError(f"frame {frame!r}: expected 'base' or 'tool'")
    shown = f"[{', '.join(f'{v:.6g}' for v in given)}] m ({frame} frame)"
    refuse_beyond_reach(robot, T0[:3, 3], displacement, f"displacement {shown}")
    t = even_time_grid(duration, dt)
    s = quintic(0.0, 1.0, duration).at_time(t)[0][:, 0]
    reference = np.broadcast_to(T0, (t.size, 4, 4)).copy()
    reference[:, :3, 3] += s[:, None] * displacement
    return track_poses(robot, q0, t, reference, control=control, gain=gain, stop_at_limits=stop_at_limits,
                       message_degrees=message_degrees)


def _check_period(period: float, gain: float, name: str, parameter: str) -> None:
    """An :class:`InputError` naming ``name`` (the argument ``parameter``) unless the control period
    ``period`` [s] and the feedback ``gain`` [1/s] make a stable loop (``gain * period <= 1``)."""
    if gain * period > 1.0:
        raise InputError(f"{name} = {period:g} s with the feedback gain {gain:g} 1/s: expected "
                         f"gain * dt <= 1 (a stable loop), a control period of at most {1.0 / gain:g} s "
                         f"(or a lower gain)", parameter=parameter, value=period)


def _check_axis(axis: ArrayLike) -> NDArray[np.float64]:
    """``axis`` as a unit vector, or an :class:`InputError` if it is no direction (too short)."""
    axis = _check_vector(axis, "axis", "unitless direction")
    unit, length = direction(axis)
    if unit is None:
        raise InputError(f"axis: expected a non-zero direction, got {axis.tolist()}: its length "
                         f"{length:.3g} is too small to be a direction (at least {MIN_AXIS_LENGTH:g})",
                         parameter="axis", value=axis)
    return unit


def _turn(angle: float | None, speed: float | None,
          duration: float | None) -> tuple[float, float, bool]:
    """Signed angle [rad], duration [s] and whether the angular velocity ``speed`` [rad/s] is
    constant, from the arguments."""
    given = {k for k, v in (("angle", angle), ("angular_velocity", speed), ("duration", duration))
             if v is not None}
    if given not in ({"angle", "angular_velocity"}, {"angular_velocity", "duration"}, {"angle", "duration"}):
        raise InputError(f"give two of angle, angular_velocity and duration (angle and angular_velocity, "
                         f"angular_velocity and duration, or angle and duration), got "
                         f"{sorted(given) or 'none'}")
    for name, value in (("angle", angle), ("angular_velocity", speed)):
        if value is not None and not (np.isfinite(value) and value != 0):
            raise InputError(f"{name} = {value}: expected a non-zero finite number")
    if duration is not None:
        duration = check_positive(duration, "duration", "s")
    if angle is not None and speed is not None:
        if np.sign(angle) != np.sign(speed) and speed < 0:
            raise InputError(f"angle {angle:g} rad and angular_velocity {speed:g} rad/s have opposite signs; "
                             f"give the direction once (the sign of angle, or of angular_velocity)")
        turn = f"a turn of {angle:g} rad at {speed:g} rad/s"
        return float(angle), _motion_duration(abs(angle / speed), turn), True
    if speed is not None:
        return float(speed) * _motion_duration(duration, "the turn"), duration, True
    return float(angle), _motion_duration(duration, "the turn"), False


def _motion_duration(duration: float, what: str) -> float:
    """``duration`` [s] if a time law takes it (:data:`~armkit.trajectory._checks.MIN_DURATION` to
    ``MAX_DURATION``: a quintic's powers of it stay finite), else an :class:`InputError` saying how
    long ``what`` takes."""
    if not MIN_DURATION <= duration <= MAX_DURATION:
        raise InputError(f"{what} takes {duration:g} s; expected a duration from {MIN_DURATION:g} s to "
                         f"{MAX_DURATION:g} s", parameter="duration", value=duration)
    return duration


def rotate_about_tool_point(robot: Robot, q0: ArrayLike, axis: ArrayLike, angle: float | None = None,
                            *, angular_velocity: float | None = None, duration: float | None = None,
                            frame: str = "base", dt: float = DEFAULT_DT,
                            control: ResolvedRate | None = None, gain: float = DEFAULT_GAIN,
                            stop_at_limits: bool = True, rate: float | None = None,
                            message_degrees: bool = False) -> MotionResult:
    """Turn the tool about an axis through its own origin, keeping its position.

    Give two of ``angle``, ``angular_velocity`` and ``duration``. With an
    ``angular_velocity`` the tool turns at that constant rate (the twist
    ``[0, 0, 0, angular_velocity * axis]``); with ``angle`` and ``duration`` only, it
    follows the quintic time law (starts and ends at rest).

    Parameters
    ----------
    robot : Robot
    q0 : (n,) array
        Start joint values [rad or m].
    axis : (3,) array
        Rotation axis (any non-zero length), in the base frame or the start tool frame.
    angle : float, optional
        Signed angle [rad] about ``axis`` (right-hand rule).
    angular_velocity : float, optional
        Angular velocity [rad/s] about ``axis``. Its sign gives the direction when ``angle``
        is not given; a negative one with a positive angle is an error.
    duration : float, optional
        [s].
    frame : {"base", "tool"}
    dt : float
        Control period [s].
    control : ResolvedRate, optional
        Damping and velocity-limit settings.
    gain : float
        Feedback gain [1/s] on the pose error (see :func:`track_poses`).
    stop_at_limits : bool
        At a joint limit stop there, ``success = False`` and a message naming the joint
        (True), or raise :class:`JointLimitError` (False).
    rate : float, optional
        Deprecated name of ``angular_velocity`` (``rate`` means a frequency in Hz,
        ``rate_hz``, elsewhere in armkit); warns.
    message_degrees : bool
        See :func:`track_poses`.

    Returns
    -------
    MotionResult

    Examples
    --------
    The seed experiment: PROBOT Anno turns about the base x axis at -0.2 rad/s.

    >>> import armkit
    >>> robot = armkit.load("probot-anno")
    >>> result = rotate_about_tool_point(robot, [0] * 6, [1, 0, 0], angular_velocity=-0.2,
    ...                                  duration=np.pi / 2 / 0.2)
    >>> bool(result.max_position_error < 1e-4), result.success
    (True, True)
    """
    q0 = check_start(robot, q0)
    axis = _check_axis(axis)
    angular_velocity = renamed_argument("rotate_about_tool_point", "rate", "angular_velocity", rate,
                                        angular_velocity, None)
    signed_angle, total_time, constant_rate = _turn(angle, angular_velocity, duration)
    dt = check_positive(dt, "dt", "s")
    _check_period(dt, check_positive(gain, "gain", "1/s"), "dt", "dt")
    T0 = robot.fk(q0)
    if frame == "tool":
        axis = T0[:3, :3] @ axis
    elif frame != "base":
        raise InputError(f"frame {frame!r}: expected 'base' or 'tool'")
    try:
        t = even_time_grid(total_time, dt)
    except InputError as exc:
        if duration is not None:
            raise
        raise InputError(f"a turn of {signed_angle:g} rad at {angular_velocity:g} rad/s takes "
                         f"{total_time:g} s: {exc}", parameter="angle", value=angle) from exc
    s = t / total_time if constant_rate else quintic(0.0, 1.0, total_time).at_time(t)[0][:, 0]
    reference = np.broadcast_to(T0, (t.size, 4, 4)).copy()
    turns = matrix_from_axis_angle(np.outer(s * signed_angle, axis))
    reference[:, :3, :3] = turns @ T0[:3, :3]
    return track_poses(robot, q0, t, reference, control=control, gain=gain, stop_at_limits=stop_at_limits,
                       message_degrees=message_degrees)
