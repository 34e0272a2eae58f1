"""Fitting segment durations to velocity and acceleration limits.

Time scaling
------------
Running a trajectory ``k`` times slower, ``q_k(t) = q(t / k)``, divides velocities by
``k`` and accelerations by ``k^2``. The minimum-jerk spline of rest-to-rest waypoints
with all durations multiplied by ``k`` is exactly that slowed trajectory, so the smallest
*uniform* factor meeting the limits is exact:

    k = max( max_j peak|qd_j| / vmax_j , sqrt( max_j peak|qdd_j| / amax_j ) )

(peaks computed exactly from the polynomials, see :mod:`armkit.trajectory.peaks`).

Per segment
-----------
A uniform stretch slows every segment for the sake of the worst one. The minimum-jerk
solve couples the segments (changing one duration changes its neighbours' velocities),
so per-segment durations are found iteratively, by coordinate descent: starting from
the uniformly scaled (feasible) durations, each segment in turn is shortened to the
shortest duration that keeps the whole trajectory within the limits (bisection, to a
relative tolerance ``tol``), and rounds repeat until no segment shortens by more than
``tol``. Every iterate is feasible, so the result never exceeds a limit, and no single
segment can be shortened (by more than ``tol``) without violating one.

A coordinate-wise minimum need not be the shortest total: when one joint's limit binds
across a waypoint, shortening one segment requires lengthening its neighbour. So the
descent's result is then refined (``refine=True``) by sequential quadratic programming
(:func:`scipy.optimize.minimize`, SLSQP): minimise ``sum_i T_i`` subject to every
segment's and joint's ``peak|qd| / vmax <= 1`` and ``peak|qdd| / amax <= 1`` and
``T_i >= lower_i``, with finite-difference gradients (``N + 1`` minimum-jerk solves per
iteration). Its answer is made exactly feasible by the uniform factor above and polished
by the descent again; the shorter of the two results is kept. On report 000's waypoints
this takes the total from 9.356 s (descent alone) to 8.969 s. Neither step certifies a
global minimum.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import minimize

from armkit._params import whole_number
from armkit.errors import ConvergenceError, InputError
from armkit.trajectory._checks import (
    LIMIT_MARGIN,
    check_durations,
    check_tol,
    check_waypoints,
    checked_limits,
    per_joint_limits,
)
from armkit.trajectory.joint_trajectory import JointTrajectory
from armkit.trajectory.min_jerk import min_jerk, rest_points

__all__ = ["auto_time", "limit_ratio", "limit_ratios", "stretch_to_limits"]

#: Fits repeated with the rest points a fit's durations add (position limits), before the
#: result is slowed uniformly instead (see ``_inside``).
_REFITS = 1


def limit_ratios(trajectory: JointTrajectory, max_velocity: ArrayLike,
                 max_acceleration: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Peak ``|qd| / vmax`` and ``|qdd| / amax`` per segment and joint, two ``(N, n)`` arrays.

    A ratio above 1 is a violated limit; joints with an infinite limit give 0.
    """
    n = trajectory.n
    vmax = per_joint_limits(max_velocity, n, "max_velocity")
    amax = per_joint_limits(max_acceleration, n, "max_acceleration")
    return trajectory.segment_peaks(1) / vmax, trajectory.segment_peaks(2) / amax


def limit_ratio(trajectory: JointTrajectory, max_velocity: ArrayLike, max_acceleration: ArrayLike) -> float:
    """The uniform slow-down factor ``k`` that meets the limits exactly (below 1: room to spare)."""
    velocity, acceleration = limit_ratios(trajectory, max_velocity, max_acceleration)
    return float(max(velocity.max(), np.sqrt(acceleration.max())))


def _shorten(spline, durations, lower, vmax, amax, tol, max_rounds):
    """Coordinate descent: shorten each segment in turn to its feasible minimum (all feasible).

    ``spline(durations)`` is the trajectory through the waypoints with those durations."""
    def feasible(candidate):
        return limit_ratio(spline(candidate), vmax, amax) <= 1.0

    durations = durations.copy()
    for _ in range(max_rounds):
        before = durations.copy()
        for i in range(durations.size):
            trial = durations.copy()
            trial[i] = lower[i]
            if feasible(trial):
                durations[i] = lower[i]
                continue
            lo, hi = lower[i], durations[i]       # lo infeasible, hi feasible
            while hi - lo > tol * hi:
                trial[i] = 0.5 * (lo + hi)
                lo, hi = (lo, trial[i]) if feasible(trial) else (trial[i], hi)
            durations[i] = hi
        if np.all(before - durations <= tol * before):
            return durations
    change = float(np.max((before - durations) / before))
    raise ConvergenceError(f"segment durations still shortening after {max_rounds} rounds "
                           f"(last change {change:.2g} relative)", rounds=max_rounds, last_change=change)


def _descent_settings(tol: object, max_rounds: object) -> tuple[float, int]:
    """The coordinate descent's ``tol`` and ``max_rounds`` (at least one), checked."""
    return check_tol(tol), whole_number(max_rounds, "max_rounds", minimum=1)


def _feasible_start(spline, start, lower, vmax, amax):
    """``start`` scaled uniformly onto the limits, then raised to ``lower`` (re-scaled if that broke them).

    The factor carries ``1 + LIMIT_MARGIN`` so that rounding never leaves a ratio a hair above 1.
    """
    k = limit_ratio(spline(start), vmax, amax) * (1 + LIMIT_MARGIN)
    durations = np.maximum(start * k, lower)
    k = limit_ratio(spline(durations), vmax, amax) * (1 + LIMIT_MARGIN)
    return durations * max(1.0, k)


def _refine(spline, durations, lower, vmax, amax):
    """SLSQP on ``min sum(T)`` under the limits, from feasible ``durations``; the input if it fails."""
    def margins(candidate):
        velocity, acceleration = limit_ratios(spline(candidate), vmax, amax)
        return np.concatenate([1.0 - velocity.ravel(), 1.0 - acceleration.ravel()])

    result = minimize(np.sum, durations, jac=lambda T: np.ones_like(T), method="SLSQP",
                      bounds=[(low, None) for low in lower],
                      constraints=[{"type": "ineq", "fun": margins}], options={"ftol": 1e-10, "maxiter": 200})
    return result.x if result.success and np.all(np.isfinite(result.x)) else durations


def _fit(spline, starts, lower, requested, vmax, amax, tol, max_rounds, refine):
    """The shortest of the coordinate-wise minima from each start, refined by SLSQP if asked."""
    best = None
    for start in starts:
        durations = _shorten(spline, _feasible_start(spline, start, lower, vmax, amax), lower,
                             vmax, amax, tol, max_rounds)
        if best is None or durations.sum() < best.sum():
            best = durations
    if refine and best.size > 1:
        refined = _refine(spline, best, lower, vmax, amax)
        polished = _shorten(spline, _feasible_start(spline, refined, lower, vmax, amax), lower,
                            vmax, amax, tol, max_rounds)
        if polished.sum() < best.sum():
            best = polished
    final = spline(best)
    return JointTrajectory(final.durations, final.coefficients, final.waypoints, requested)


def _inside(fit, waypoints: NDArray[np.float64], durations: NDArray[np.float64],
            position_limits: ArrayLike | None, vmax: NDArray[np.float64],
            amax: NDArray[np.float64]) -> JointTrajectory:
    """``fit(spline)`` with ``spline(durations)`` the minimum-jerk trajectory through ``waypoints``
    with the rest points that keep it inside ``position_limits`` at ``durations``
    (:func:`~armkit.trajectory.min_jerk.rest_points`), held fixed during the fit (the splines
    then change smoothly with the durations). If the fitted durations need more rest points,
    the fit is repeated with them (at most :data:`_REFITS` times; the rest points only grow);
    after that they are added and the result is slowed uniformly back onto the limits (exact:
    a uniform slow-down keeps the path, and so its rest points)."""
    rest = None if position_limits is None else rest_points(waypoints, durations, position_limits)
    for _ in range(_REFITS + 1):
        def spline(candidate: NDArray[np.float64], rest=rest) -> JointTrajectory:
            return min_jerk(waypoints, candidate, rest=rest)

        fitted = fit(spline)
        if position_limits is None:
            return fitted
        more = rest_points(waypoints, fitted.durations, position_limits, rest)
        if (more == rest).all():
            return fitted
        rest = more
    held = min_jerk(waypoints, fitted.durations, rest=more)
    k = max(1.0, limit_ratio(held, vmax, amax) * (1 + LIMIT_MARGIN))
    final = min_jerk(waypoints, fitted.durations * k, rest=more)
    return JointTrajectory(final.durations, final.coefficients, final.waypoints, fitted.requested_durations)


def stretch_to_limits(waypoints: ArrayLike, durations: ArrayLike, max_velocity: ArrayLike,
                      max_acceleration: ArrayLike, *, tol: float = 1e-4, max_rounds: int = 200,
                      refine: bool = True, position_limits: ArrayLike | None = None) -> JointTrajectory:
    """The rest-to-rest minimum-jerk trajectory, segments lengthened only as far as the limits need.

    Each final duration is at least the requested one; a trajectory already within the
    limits is returned unchanged. ``result.stretch`` says by how much each segment grew.
    The descent (module notes) runs from two starts, the requested durations scaled
    uniformly and the elementwise larger of the requested and the :func:`auto_time`
    durations, and keeps the shorter result.

    Parameters
    ----------
    waypoints : (M, n) array
        Joint positions [rad or m].
    durations : (M - 1,) array
        Requested segment durations [s].
    max_velocity, max_acceleration : float or (n,) array
        Limits [rad/s, rad/s^2 or m/s, m/s^2]; ``inf`` for none.
    tol : float
        Relative accuracy of each duration.
    max_rounds : int
        Rounds of the coordinate descent before :class:`ConvergenceError`.
    refine : bool
        Refine the descent's result by SLSQP (module notes); costs ``N + 1`` solves per iteration.
    position_limits : (n, 2) array, optional
        Keep the trajectory inside these [rad or m]: joints held at rest at the waypoints where
        the spline would leave them (:func:`~armkit.trajectory.min_jerk.rest_points`).

    Examples
    --------
    >>> traj = stretch_to_limits([[0.0], [1.0]], [1.0], 1.0, 1.0)
    >>> float(traj.durations[0].round(3)), float(traj.peak_acceleration[0].round(3))
    (2.403, 1.0)
    """
    waypoints = check_waypoints(waypoints)
    requested = check_durations(durations, waypoints.shape[0] - 1)
    vmax, amax = checked_limits(waypoints, max_velocity, max_acceleration)
    tol, max_rounds = _descent_settings(tol, max_rounds)
    as_requested = min_jerk(waypoints, requested, position_limits=position_limits)
    if limit_ratio(as_requested, vmax, amax) <= 1.0:
        return as_requested
    fastest = auto_time(waypoints, vmax, amax, tol=tol, max_rounds=max_rounds, refine=refine,
                        position_limits=position_limits).durations
    return _inside(lambda spline: _fit(spline, [requested, np.maximum(requested, fastest)], requested,
                                       requested, vmax, amax, tol, max_rounds, refine),
                   waypoints, requested, position_limits, vmax, amax)


def auto_time(waypoints: ArrayLike, max_velocity: ArrayLike, max_acceleration: ArrayLike, *,
              tol: float = 1e-4, max_rounds: int = 200, refine: bool = True,
              position_limits: ArrayLike | None = None) -> JointTrajectory:
    """The rest-to-rest minimum-jerk trajectory with the shortest durations meeting the limits.

    Starts from durations proportional to each segment's largest ``|dq| / vmax +
    sqrt(|dq| / amax)``, scales them uniformly onto the limits, then shortens segment by
    segment and refines by SLSQP (see the module notes; parameters as in
    :func:`stretch_to_limits`, ``position_limits`` too). A segment cannot be shorter than
    ``max_j |dq_j| / vmax_j``
    (nor than ``1e-6`` of the total, for repeated waypoints).

    Examples
    --------
    >>> traj = auto_time([[0.0], [1.0]], 1.0, 1.0)
    >>> round(traj.duration, 3)                 # rest to rest, 1 rad at 1 rad/s^2 (sqrt(10 / sqrt(3)))
    2.403
    """
    waypoints = check_waypoints(waypoints)
    vmax, amax = checked_limits(waypoints, max_velocity, max_acceleration)
    step = np.abs(np.diff(waypoints, axis=0))
    guess = (step / vmax + np.sqrt(step / amax)).max(axis=1)
    if not np.all(np.isfinite(guess)) or guess.max() == 0:
        raise InputError("auto_time: needs finite limits and waypoints that move")
    guess = np.maximum(guess, 1e-6 * guess.sum())
    lower = np.maximum((step / vmax).max(axis=1), 1e-6 * guess.sum())
    tol, max_rounds = _descent_settings(tol, max_rounds)
    return _inside(lambda spline: _fit(spline, [guess], lower, guess, vmax, amax, tol, max_rounds, refine),
                   waypoints, guess, position_limits, vmax, amax)
