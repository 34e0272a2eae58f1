"""Time-optimal timing along a geometric path (TOPP-RA), and the automatic timing built on it.

The path
--------
Through the waypoints, the minimum-jerk spline (:func:`~armkit.trajectory.min_jerk.min_jerk`)
whose segment durations are each segment's rest-to-rest time at the limits, the largest over
the joints of ``|dq| / vmax + vmax / amax`` (cruising) or ``2 sqrt(|dq| / amax)`` (too short to
cruise). Its time is the path parameter ``s`` [s]; ``q(s)`` passes through every waypoint and
``q'``, ``q''`` are continuous.

The timing
----------
Along ``q(s)`` the trajectory is ``q(s(t))``: ``qd = q' sd`` and ``qdd = q' sdd + q'' sd^2``.
With ``x = sd^2`` and ``u = sdd``, every limit is linear in ``(u, x)`` at a point of the path,

    lo <= a(s) u + b(s) x + c(s) <= hi

(joint acceleration: ``a = q'``, ``b = q''``, ``c = 0``; joint velocity: ``x <= (vmax / |q'|)^2``).
The core (``cpp/src/topp.cpp``) finds the fastest ``s(t)`` on a grid by reachability analysis
(Pham & Pham 2018): backward, the set of ``x`` from which the end is still reachable at every
grid point, in closed form; forward, the largest admissible ``u`` at every interval.
Torque limits join as more rows: ``tau = M q' u + (M q'' + C(q, q') q') x + g(q)``, so
``a = ID(q, 0, q') - g``, ``b = ID(q, q', q'') - g``, ``c = g`` with ``ID`` the inverse dynamics
(see :class:`LinearConstraint`).

The trajectory
--------------
TOPP's ``sdd`` is bang-bang (acceleration jumps). ``s(t)`` is averaged over a sliding window of
``tau`` seconds (``smoothing`` times the median time between waypoints), which makes ``sdd``
continuous and piecewise linear, bounds the jerk, starts and ends at rest with zero
acceleration, and adds ``tau`` to the duration. At every knot of that profile (the grid times,
the grid times plus ``tau``, and the waypoints' times) ``q = q(s)``, ``qd = q' sd`` and
``qdd = q' sdd + q'' sd^2``; one quintic per knot interval meets them, so ``q``, ``qd`` and ``qdd``
are continuous. Finally the whole trajectory is scaled in time by the exact factor that puts
its largest velocity or acceleration ratio (exact polynomial peaks, not samples) on 1: it
never exceeds a limit and touches one. Without any acceleration limit, the rest-to-rest
minimum-jerk spline is scaled onto the velocity limits instead (see :func:`time_optimal`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from enum import IntEnum
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit.errors import InputError
from armkit.trajectory._checks import (
    LIMIT_MARGIN,
    MAX_DURATION,
    MIN_DURATION,
    check_finite,
    check_waypoints,
    checked_limits,
)
from armkit.trajectory.joint_trajectory import JointTrajectory
from armkit.trajectory.min_jerk import min_jerk
from armkit.trajectory.polynomial import quintic_coefficients
from armkit.trajectory.timing import limit_ratio

if TYPE_CHECKING:
    from armkit.robot import Robot

__all__ = ["LinearConstraint", "ToppResult", "ToppStatus", "geometric_path", "parameterize", "time_optimal",
           "torque_constraint", "slowed_to_torque_limits"]

#: Rounds of the 1 kHz torque check, and the margin each slowing adds (the samples of a slower
#: trajectory fall between the last round's; the margin makes the next round's sure).
_TORQUE_ROUNDS = 5
_TORQUE_MARGIN = 1e-6

#: Grid intervals per waypoint segment, at least; and over the whole path, at least.
GRID_PER_SEGMENT = 16
GRID_TOTAL = 200
#: Most constraint rows per grid point the core takes (``kToppMaxRows``).
MAX_ROWS = 64
#: Default smoothing window, as a fraction of the median time between two waypoints.
SMOOTHING = 0.03
_NEWTON_STEPS = 6
#: Knots closer than this fraction of the duration are merged (a piece that short would be ill-conditioned).
_KNOT_GAP = 1e-9


class ToppStatus(IntEnum):
    """Outcome of :func:`parameterize` (the core's codes)."""

    SUCCESS = 0
    INFEASIBLE = 1         # no admissible motion passes some grid point (e.g. gravity beyond a torque limit)
    START_UNREACHABLE = 2  # the end cannot be reached from the given start speed


@dataclass(frozen=True)
class LinearConstraint:
    """Rows ``lo <= a * sdd + b * sd^2 + c <= hi`` at every grid point.

    Attributes
    ----------
    a, b, c : (K, m) arrays
        Coefficients at the ``K`` grid points of ``m`` rows (a torque row: ``a = M(q) q'``,
        ``b = M(q) q'' + C(q, q') q'``, ``c = g(q)``, in N m or N).
    lo, hi : (m,) or (K, m) arrays
        Bounds of each row (``-inf`` / ``inf`` for none).
    """

    a: NDArray[np.float64]
    b: NDArray[np.float64]
    c: NDArray[np.float64]
    lo: NDArray[np.float64]
    hi: NDArray[np.float64]


#: A user constraint: from the grid's ``s`` (K,) [s], ``q``, ``q'``, ``q''`` (K, n) to its rows.
ConstraintFunction = Callable[[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64],
                               NDArray[np.float64]], LinearConstraint]


@dataclass(frozen=True)
class ToppResult:
    """The fastest ``s(t)`` on a grid.

    Attributes
    ----------
    status : ToppStatus
    point : int
        The grid point where it failed (0 on success).
    s : (K,) array
        Grid [path units].
    x : (K,) array
        ``sd^2`` at the grid points [path units^2 / s^2].
    u : (K - 1,) array
        ``sdd`` on each interval [path units / s^2].
    t : (K,) array
        Time [s] at each grid point (``sd`` linear in ``t`` between them); ``nan`` unless success.
    """

    status: ToppStatus
    point: int
    s: NDArray[np.float64]
    x: NDArray[np.float64]
    u: NDArray[np.float64]
    t: NDArray[np.float64]

    @property
    def success(self) -> bool:
        """Whether a parameterisation was found."""
        return self.status == ToppStatus.SUCCESS


def parameterize(s: ArrayLike, constraint: LinearConstraint, x_max: ArrayLike, *, x_start: float = 0.0,
                 x_end: float = 0.0, interpolation: bool = True) -> ToppResult:
    """The time-optimal ``s(t)`` on the grid ``s`` under ``constraint`` and ``sd^2 <= x_max``.

    Parameters
    ----------
    s : (K,) array
        Increasing grid of the path parameter.
    constraint : LinearConstraint
        Rows at every grid point (at most :data:`MAX_ROWS`; half that with ``interpolation``).
    x_max : (K,) array
        Largest ``sd^2`` at each grid point (``inf``: none).
    x_start, x_end : float
        ``sd^2`` at both ends (0: at rest).
    interpolation : bool
        Also hold each interval's ``sdd`` to the rows of the interval's far end (reached with
        ``x + 2 ds sdd``), as toppra's ``Interpolation`` discretisation: without it, where a
        joint's ``q'`` changes sign between grid points (a singular arc) ``sdd`` chatters.

    Returns
    -------
    ToppResult
        With ``status`` saying whether (and where not) a parameterisation exists.

    Examples
    --------
    >>> s = np.linspace(0.0, 1.0, 101)          # a straight path q = s, |qdd| <= 1
    >>> ones = np.ones((101, 1))
    >>> result = parameterize(s, LinearConstraint(ones, 0 * ones, 0 * ones, -1.0, 1.0), np.full(101, np.inf))
    >>> round(float(result.t[-1]), 6)           # bang-bang: 2 sqrt(1 / 1)
    2.0
    """
    from armkit import _core

    s = check_finite(s, "s")
    if s.ndim != 1 or s.size < 2 or np.any(np.diff(s) <= 0):
        raise InputError(f"s: expected an increasing grid of at least two points, got shape {s.shape}")
    K = s.size
    a, b, c = (np.ascontiguousarray(check_finite(getattr(constraint, name), name)) for name in "abc")
    if a.ndim != 2 or a.shape[0] != K or b.shape != a.shape or c.shape != a.shape:
        raise InputError(f"a, b, c: expected ({K}, m) arrays, got {a.shape}, {b.shape}, {c.shape}")
    most = MAX_ROWS // 2 if interpolation else MAX_ROWS
    if a.shape[1] > most:
        raise InputError(f"a, b, c: at most {most} rows per grid point, got {a.shape[1]}")
    lo, hi = (np.ascontiguousarray(np.broadcast_to(np.asarray(bound, dtype=float), a.shape))
              for bound in (constraint.lo, constraint.hi))
    if np.any(np.isnan(lo)) or np.any(np.isnan(hi)) or np.any(lo > hi):
        raise InputError(f"lo, hi: expected lo <= hi (inf for none), got lo {constraint.lo}, "
                         f"hi {constraint.hi}")
    if interpolation:
        step = 2.0 * np.diff(s)[:, None]
        far = {name: np.vstack([row[1:], row[-1:]]) for name, row in zip("abclh", (a, b, c, lo, hi),
                                                                           strict=True)}
        far["a"][:-1] += step * far["b"][:-1]
        a, b, c, lo, hi = (np.ascontiguousarray(np.hstack([row, far[name]]))
                           for name, row in zip("abclh", (a, b, c, lo, hi), strict=True))
    x_max = np.ascontiguousarray(np.broadcast_to(np.asarray(x_max, dtype=float), (K,)))
    x, u, k_lo, k_hi = np.empty(K), np.empty(K - 1), np.empty(K), np.empty(K)
    status, point = _core.topp_ra(s, a, b, c, lo, hi, x_max, float(x_start), float(x_end), x, u, k_lo, k_hi)
    status = ToppStatus(status)
    if status != ToppStatus.SUCCESS:
        return ToppResult(status, point, s, np.full(K, np.nan), np.full(K - 1, np.nan), np.full(K, np.nan))
    speed = np.sqrt(x)
    t = np.concatenate([[0.0], np.cumsum(2.0 * np.diff(s) / (speed[:-1] + speed[1:]))])
    return ToppResult(status, point, s, x, u, t)


def geometric_path(waypoints: ArrayLike, max_velocity: ArrayLike, max_acceleration: ArrayLike, *,
                   position_limits: ArrayLike | None = None) -> JointTrajectory:
    """The path through ``waypoints`` that :func:`time_optimal` times: its time is the path parameter.

    The minimum-jerk spline with each segment as long as its slowest joint's rest-to-rest time
    at the limits (module notes), kept inside ``position_limits`` if given
    (:func:`~armkit.trajectory.min_jerk.min_jerk`). Parameters as in :func:`time_optimal`.
    """
    waypoints = check_waypoints(waypoints)
    vmax, amax = checked_limits(waypoints, max_velocity, max_acceleration)
    step = np.abs(np.diff(waypoints, axis=0))
    if (repeated := np.flatnonzero(step.max(axis=1) == 0)).size:
        k = int(repeated[0]) + 1
        raise InputError(f"waypoints {k} and {k + 1} are the same ({waypoints[k].tolist()}): a path through "
                         f"waypoints needs each to differ from the previous one; drop the repeat")
    with np.errstate(invalid="ignore", over="ignore"):  # inf / inf: a joint with neither limit; overflow:
        cruising = step / vmax + vmax / amax            # limits too small (refused below)
        rest_to_rest = np.where(step * amax >= vmax**2, cruising, 2.0 * np.sqrt(step / amax))
        rest_to_rest = np.where(np.isnan(rest_to_rest), step / vmax, rest_to_rest)  # no acceleration limit
    nominal = np.nan_to_num(rest_to_rest, nan=0.0, posinf=np.inf).max(axis=1)
    if (free := np.flatnonzero(nominal == 0)).size:
        k = int(free[0]) + 1
        raise InputError(f"waypoints {k} to {k + 1}: only joints without a finite max_velocity or "
                         f"max_acceleration move, so no timing is fastest; give them limits")
    if (slow := np.flatnonzero(~(nominal <= MAX_DURATION))).size:
        k = int(slow[0])
        joint = int(np.argmax(np.nan_to_num(rest_to_rest[k], nan=0.0, posinf=np.inf)))
        takes = (f"at least {nominal[k]:.3g} s" if np.isfinite(nominal[k])
                 else "more seconds than a float holds")
        raise InputError(f"waypoints {k + 1} to {k + 2}: at joint {joint + 1}'s limits (max_velocity "
                         f"{vmax[joint]:.3g}, max_acceleration {amax[joint]:.3g}) the move takes "
                         f"{takes}, longer than a trajectory's longest segment "
                         f"({MAX_DURATION:g} s): are the limits in SI units (rad/s, rad/s^2)?")
    if (quick := np.flatnonzero(nominal < MIN_DURATION)).size:
        k = int(quick[0])
        raise InputError(f"waypoints {k + 1} to {k + 2}: at the limits (max_velocity {vmax.max():.3g}, "
                         f"max_acceleration {amax.max():.3g} at most) the move takes {nominal[k]:.3g} s, "
                         f"shorter than a trajectory's shortest segment ({MIN_DURATION:g} s): are the limits "
                         f"in SI units (rad/s, rad/s^2), and the waypoints apart?")
    if np.all(np.isinf(amax)):   # timed uniformly by time_optimal, at rest at both ends; durations
        # as the square root of the time at the velocity limit ("centripetal"): a long segment next to
        # a short one would otherwise make the spline overshoot (as time at an acceleration limit does)
        return min_jerk(waypoints, np.sqrt(nominal * nominal.mean()), position_limits=position_limits)
    # Leaving the first waypoint and reaching the last at the chord's speed, not at rest: a path
    # with q' = 0 at an end would let s run arbitrarily fast there (nothing bounds sd where q' = q'' = 0).
    # (A first or last segment leaving along its chord towards a waypoint held at rest moves
    # monotonically, so position_limits can always be kept.)
    return min_jerk(waypoints, nominal, start_velocity=(waypoints[1] - waypoints[0]) / nominal[0],
                    end_velocity=(waypoints[-1] - waypoints[-2]) / nominal[-1],
                    position_limits=position_limits)


def time_optimal(waypoints: ArrayLike, max_velocity: ArrayLike, max_acceleration: ArrayLike, *,
                 constraints: Sequence[ConstraintFunction] = (),
                 smoothing: float = SMOOTHING, position_limits: ArrayLike | None = None) -> JointTrajectory:
    """The fastest trajectory along :func:`geometric_path` within the limits, at rest at both ends.

    Parameters
    ----------
    waypoints : (M, n) array
        Joint positions [rad or m]; the trajectory passes through each.
    max_velocity, max_acceleration : float or (n,) array
        Limits [rad/s, rad/s^2 or m/s, m/s^2]; ``inf`` for none.
    constraints : sequence of callables
        More limits: each maps the grid's ``s`` (K,), ``q``, ``q'``, ``q''`` (K, n) to a
        :class:`LinearConstraint` (torque limits, say; module notes).
    smoothing : float
        Width of the moving average over ``s(t)``, as a fraction of the median time between
        waypoints: the trajectory is about that much longer than the bang-bang optimum, and
        its jerk is about ``2 amax / (smoothing * that time)``.
    position_limits : (n, 2) array, optional
        Lower and upper limit per joint [rad or m]: the path stays inside them
        (:func:`geometric_path`); timing along it does not change where it goes.

    Without any acceleration limit (and no ``constraints``) the fastest motion would jump in
    speed; the rest-to-rest minimum-jerk spline through the waypoints (segment durations
    proportional to ``sqrt(max_j |dq_j| / vmax_j)``) is then scaled uniformly onto the velocity
    limits instead.

    Returns
    -------
    JointTrajectory
        One segment per pair of waypoints, each made of one quintic per knot interval of the
        smoothed profile (module notes).

    Raises
    ------
    InputError
        Bad waypoints, limits or ``smoothing``, or no motion meeting the constraints (naming
        the grid point).

    Examples
    --------
    >>> traj = time_optimal([[0.0], [1.0]], 10.0, 1.0)
    >>> round(traj.duration, 2), float(traj.peak_acceleration[0].round(9))   # bang-bang 2 s + smoothing
    (2.06, 1.0)
    """
    smoothing = float(check_finite(smoothing, "smoothing"))
    if not 0.0 < smoothing <= 1.0:
        raise InputError(f"smoothing: expected a fraction in (0, 1] of the time between waypoints, got "
                         f"{smoothing:g}")
    path = geometric_path(waypoints, max_velocity, max_acceleration, position_limits=position_limits)
    vmax, amax = checked_limits(path.waypoints, max_velocity, max_acceleration)
    if np.all(np.isinf(amax)) and not constraints:
        return _scaled(path, limit_ratio(path, vmax, amax) * (1 + LIMIT_MARGIN))
    per_segment = max(GRID_PER_SEGMENT, -(-GRID_TOTAL // path.durations.size))
    fractions = np.arange(per_segment) / per_segment
    s = np.append(path.waypoint_times[:-1, None] + path.durations[:, None] * fractions, path.duration)
    q, dq, ddq = path.at_time(s)
    q[::per_segment] = path.waypoints                       # the waypoints exactly
    rows = [LinearConstraint(dq, ddq, np.zeros_like(dq), -amax, amax),
            *(function(s, q, dq, ddq) for function in constraints)]
    constraint = LinearConstraint(*(
        np.concatenate([np.broadcast_to(getattr(row, name), np.shape(row.a)) for row in rows], axis=1)
        for name in ("a", "b", "c", "lo", "hi")))
    with np.errstate(divide="ignore", over="ignore"):  # inf: no bound from the velocity limits there
        x_max = np.min((vmax / np.abs(dq)) ** 2, axis=1)
    result = parameterize(s, constraint, x_max)
    if not result.success:
        raise InputError(f"no motion along the path meets the limits: {result.status.name.lower()} at "
                         f"s = {s[result.point]:.6g} s of {path.duration:.6g} s "
                         f"(q = {q[result.point].tolist()})")
    if not np.all(np.isfinite(result.t)):
        raise InputError("max_velocity, max_acceleration: the path can be run infinitely fast somewhere; "
                         "give every moving joint a finite limit")
    tau = smoothing * float(np.median(np.diff(result.t[::per_segment])))
    knots, s_t, sd_t, sdd_t, at_waypoint = _smoothed_profile(result, tau, path.waypoint_times)
    q, dq, ddq = path.at_time(np.clip(s_t, 0.0, path.duration))
    q[at_waypoint] = path.waypoints                          # the waypoints exactly
    qd = dq * sd_t[:, None]
    qdd = dq * sdd_t[:, None] + ddq * (sd_t**2)[:, None]
    pieces = np.diff(at_waypoint)
    h = np.diff(knots)
    coefficients = quintic_coefficients(q[:-1], q[1:], h[:, None], qd[:-1], qd[1:], qdd[:-1], qdd[1:])
    fitted = JointTrajectory(h, coefficients, path.waypoints, segment_pieces=pieces)
    k = limit_ratio(fitted, vmax, amax) * (1 + LIMIT_MARGIN)
    if constraints:       # never faster than the profile that met them: slower keeps a torque between
        k = max(k, 1.0)   # its value at rest and along the profile
    return _scaled(fitted, k)


def _scaled(trajectory: JointTrajectory, k: float) -> JointTrajectory:
    """``trajectory`` run ``k`` times slower, ``q(t / k)`` (velocities over ``k``, accelerations ``k^2``)."""
    powers = np.arange(trajectory.coefficients.shape[0])[:, None, None]
    return JointTrajectory(trajectory.piece_durations * k, trajectory.coefficients / k**powers,
                           trajectory.waypoints, segment_pieces=trajectory.segment_pieces)


def _profile(result: ToppResult, t: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """TOPP's ``s`` and ``sd`` at times ``t`` [s] (``sdd`` constant on each interval; at rest outside)."""
    i = np.clip(np.searchsorted(result.t, t, side="right") - 1, 0, result.u.size - 1)
    local = np.clip(t, 0.0, result.t[-1]) - result.t[i]
    sd0 = np.sqrt(result.x[i])
    return result.s[i] + sd0 * local + 0.5 * result.u[i] * local**2, sd0 + result.u[i] * local


def _smoothed_profile(result: ToppResult, tau: float, s_waypoints: NDArray[np.float64]):
    """TOPP's ``s(t)`` averaged over the last ``tau`` seconds: ``sdd`` continuous, its jerk bounded.

    ``s_tau(t) = (1 / tau) integral_{t - tau}^{t} s``, so ``sd_tau(t) = (s(t) - s(t - tau)) / tau`` and
    ``sdd_tau(t) = (sd(t) - sd(t - tau)) / tau``: continuous, piecewise linear between the knots
    ``t_k`` and ``t_k + tau``, at rest at ``0`` and at ``T + tau``. Returns the knots (those and the
    times the smoothed profile passes each waypoint's ``s``), ``s``, ``sd``, ``sdd`` there, and the
    index of each waypoint's knot.
    """
    def rates(t):
        s_now, sd_now = _profile(result, t)
        s_before, sd_before = _profile(result, t - tau)
        return (s_now - s_before) / tau, (sd_now - sd_before) / tau

    end = result.t[-1] + tau
    knots = np.unique(np.concatenate([result.t, result.t + tau]))
    knots = knots[np.concatenate([[True], np.diff(knots) > _KNOT_GAP * end])]
    knots[-1] = end
    sd, sdd = rates(knots)
    h = np.diff(knots)
    # sd_tau is quadratic between knots: Simpson's rule integrates it exactly.
    s_knots = np.concatenate([[0.0], np.cumsum(h / 6.0 * (sd[:-1] + 4.0 * rates(knots[:-1] + 0.5 * h)[0]
                                                           + sd[1:]))])
    # Each interior waypoint's time: s_tau is the cubic Hermite of (s, sd) at its knot interval's ends;
    # Newton from the linear guess, kept inside the interval (s_tau increases there).
    inner = s_waypoints[1:-1]
    j = np.clip(np.searchsorted(s_knots, inner, side="right") - 1, 0, knots.size - 2)
    span, s0, s1 = h[j], s_knots[j], s_knots[j + 1]
    v0, v1 = sd[j] * span, sd[j + 1] * span                 # derivatives in the unit variable
    cubic = np.stack([s0, v0, 3 * (s1 - s0) - 2 * v0 - v1, 2 * (s0 - s1) + v0 + v1])
    x = (inner - s0) / (s1 - s0)
    for _ in range(_NEWTON_STEPS):
        value = cubic[0] + x * (cubic[1] + x * (cubic[2] + x * cubic[3])) - inner
        slope = cubic[1] + x * (2 * cubic[2] + x * 3 * cubic[3])
        x = np.clip(x - value / slope, 0.0, 1.0)
    t_w = knots[j] + x * span
    near = np.zeros(knots.size, dtype=bool)                 # knots a waypoint's time replaces
    for neighbour in (j, j + 1):
        near[neighbour[np.abs(knots[neighbour] - t_w) <= _KNOT_GAP * end]] = True
    keep = ~near
    keep[[0, -1]] = True
    all_knots = np.concatenate([knots[keep], t_w])
    order = np.argsort(all_knots, kind="stable")
    all_knots = all_knots[order]
    s_all = np.concatenate([s_knots[keep], inner])[order]
    sd, sdd = rates(all_knots)
    sd[[0, -1]] = sdd[[0, -1]] = 0.0
    s_all[[0, -1]] = s_waypoints[[0, -1]]
    at_waypoint = np.concatenate([[0], np.flatnonzero(order >= keep.sum()), [all_knots.size - 1]])
    return all_knots, s_all, sd, sdd, at_waypoint


def torque_constraint(robot: Robot, gravity: ArrayLike | None = None) -> ConstraintFunction:
    """The rows that keep ``robot``'s joint torques within ``robot.max_torque`` along a path.

    ``tau = a sdd + b sd^2 + c`` with ``a = ID(q, 0, q') - g``, ``b = ID(q, q', q'') - g``,
    ``c = g`` (``ID`` :meth:`armkit.Robot.inverse_dynamics`, ``g`` the gravity torques), for
    :func:`time_optimal`'s ``constraints``. Joints without a limit get ``+-inf``.
    """
    limits = np.asarray(robot.max_torque, dtype=float)

    def rows(s: NDArray[np.float64], q: NDArray[np.float64], dq: NDArray[np.float64],
             ddq: NDArray[np.float64]) -> LinearConstraint:
        g = robot.gravity_torques(q, gravity=gravity)
        a = robot.inverse_dynamics(q, np.zeros_like(dq), dq, gravity=gravity) - g
        b = robot.inverse_dynamics(q, dq, ddq, gravity=gravity) - g
        return LinearConstraint(a, b, g, -limits, limits)

    return rows


def slowed_to_torque_limits(trajectory: JointTrajectory, robot: Robot, *, rate_hz: float = 1000.0,
                            gravity: ArrayLike | None = None) -> JointTrajectory:
    """``trajectory`` run as much slower as needed for its torques, sampled at ``rate_hz``, to stay
    within ``robot.max_torque`` (unchanged where they do).

    Run ``k`` times slower, the torques are ``g(q) + d / k^2`` at the same points of the path
    (``d`` the part that moves: inertia, Coriolis), so the smallest ``k`` that keeps every
    sample within its limit is exact for those points; the slower trajectory's own samples
    fall elsewhere on the path, so it is checked again (at most a few rounds, each slower).

    Raises
    ------
    InputError
        Where gravity alone needs more than a joint's limit (no timing can help).
    """
    limits = np.asarray(robot.max_torque, dtype=float)
    if not np.any(np.isfinite(limits)):
        return trajectory
    for _ in range(_TORQUE_ROUNDS):
        samples = trajectory.sample(rate_hz)
        g = robot.gravity_torques(samples.q, gravity=gravity)
        d = robot.inverse_dynamics(samples.q, samples.qd, samples.qdd, gravity=gravity) - g
        held = np.abs(g) >= limits
        if held.any():
            k, j = np.argwhere(held)[0]
            raise InputError(f"max_torque: joint {robot.joint_names[j]} needs {abs(g[k, j]):.6g} to hold the "
                             f"arm against gravity at t = {samples.t[k]:.6g} s, at or above its limit "
                             f"{limits[j]:.6g}; no timing keeps it within")
        with np.errstate(divide="ignore", invalid="ignore"):
            room = np.where(d > 0, (limits - g) / d, np.where(d < 0, (-limits - g) / d, np.inf))
        u = float(np.min(np.where(np.isfinite(limits), room, np.inf), initial=np.inf))
        if u >= 1.0:
            return trajectory
        trajectory = _scaled(trajectory, (1.0 + _TORQUE_MARGIN) / np.sqrt(u))
    return trajectory
