"""Input checks shared by the trajectory modules (one place for their error messages)."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit._params import float_in_range
from armkit.errors import InputError

__all__ = ["FINEST_TOL", "LIMIT_MARGIN", "MAX_DURATION", "MIN_DURATION", "check_durations", "check_finite",
           "check_tol", "check_waypoints", "checked_limits", "durations_from_times", "per_joint_limits"]

#: Shortest and longest segment duration [s] a trajectory takes: a microsecond (a thousandth of
#: a 1 kHz servo period) to about 11.6 days. The polynomials hold powers of the duration up to
#: the fifth and their inverses, so durations such as 1e-300 s or 1e200 s overflow float64
#: (NaN coefficients); these bounds keep every power within about 1e30 of 1.
MIN_DURATION = 1e-6
MAX_DURATION = 1e6
#: Finest relative accuracy ``tol`` of the timing's durations: its bisection stops at
#: ``hi - lo <= tol * hi``, and a finer bound than ~1e4 ulp could ask it to split two adjacent
#: floats forever.
FINEST_TOL = 1e-12
#: Relative margin added to the exact uniform factor that fits a trajectory to its limits, against
#: rounding.
LIMIT_MARGIN = 1e-12


def check_tol(tol: object) -> float:
    """The timing's ``tol`` (relative accuracy of each duration) as a float in
    ``[FINEST_TOL, 0.5]``, or :class:`InputError` naming it."""
    return float_in_range(tol, "tol", FINEST_TOL, 0.5, "a relative accuracy of each duration")


def check_finite(values: ArrayLike, name: str) -> NDArray[np.float64]:
    """``values`` as float64, or :class:`InputError` naming ``name`` if not numeric and finite."""
    try:
        array = np.asarray(values, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{name}: expected numbers, got {values!r}") from exc
    if not np.all(np.isfinite(array)):
        raise InputError(f"{name}: contains NaN or infinite values: {array.tolist()}")
    return array


def check_durations(durations: ArrayLike, count: int | None = None,
                    name: str = "durations") -> NDArray[np.float64]:
    """Segment durations [s] as ``(N,)``, each in ``[MIN_DURATION, MAX_DURATION]``; ``count`` is
    the expected ``N``."""
    durations = np.atleast_1d(check_finite(durations, name))
    if durations.ndim != 1:
        raise InputError(f"{name}: expected a list of segment durations, got shape {durations.shape}")
    if count is not None and durations.size != count:
        raise InputError(f"{name}: {count + 1} waypoints need {count} segment durations, "
                         f"got {durations.size}")
    bad = np.flatnonzero((durations < MIN_DURATION) | (durations > MAX_DURATION))
    if bad.size:
        raise InputError(f"{name}: every segment duration must be from {MIN_DURATION:g} s to "
                         f"{MAX_DURATION:g} s, got {durations[bad[0]]:g} s for segment {bad[0] + 1}")
    return durations


def check_waypoints(waypoints: ArrayLike, name: str = "waypoints") -> NDArray[np.float64]:
    """Waypoints as ``(M, n)`` with ``M >= 2`` (a 1-D input is ``M`` waypoints of one joint)."""
    waypoints = check_finite(waypoints, name)
    if waypoints.ndim == 1:
        waypoints = waypoints[:, None]
    if waypoints.ndim != 2:
        raise InputError(f"{name}: expected shape (M, n), got {waypoints.shape}")
    if waypoints.shape[0] < 2:
        raise InputError(f"{name}: a trajectory needs at least two waypoints, got {waypoints.shape[0]}")
    return waypoints


def durations_from_times(times: ArrayLike) -> NDArray[np.float64]:
    """Segment durations ``(M - 1,)`` [s] from strictly increasing waypoint times ``(M,)`` [s].

    >>> durations_from_times([0.0, 10.0, 20.0, 30.0])
    array([10., 10., 10.])
    """
    times = np.atleast_1d(check_finite(times, "times"))
    if times.ndim != 1 or times.size < 2:
        raise InputError(f"times: expected one time per waypoint (at least two), got {times.tolist()}")
    bad = np.flatnonzero(np.diff(times) <= 0)
    if bad.size:
        k = int(bad[0])
        raise InputError(f"times: must increase, but waypoint {k + 2} is at {times[k + 1]:g} s after "
                         f"waypoint {k + 1} at {times[k]:g} s")
    return np.diff(times)


def _as_float(value: ArrayLike, name: str) -> NDArray[np.float64]:
    """``value`` as float64 (``inf`` allowed, meaning no limit), or :class:`InputError`."""
    try:
        return np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{name}: expected numbers, got {value!r}") from exc


def per_joint_limits(value: ArrayLike, n: int, name: str) -> NDArray[np.float64]:
    """One limit or ``n`` limits as ``(n,)`` positive values (``inf`` for none), or :class:`InputError`."""
    limits = np.asarray(_as_float(value, name), dtype=float)
    if limits.ndim > 1 or limits.size not in (1, n):
        raise InputError(f"{name}: expected one limit or {n} limits (one per joint), got {limits.tolist()}")
    limits = np.broadcast_to(limits, (n,))
    if np.any(np.isnan(limits)) or np.any(limits <= 0):
        raise InputError(f"{name}: expected positive limits (inf for none), got {limits.tolist()}")
    return limits


def checked_limits(waypoints: NDArray[np.float64], max_velocity: ArrayLike,
                   max_acceleration: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``(vmax, amax)`` per joint of ``waypoints`` ``(M, n)``, at least one of them finite somewhere."""
    n = waypoints.shape[1]
    vmax = per_joint_limits(max_velocity, n, "max_velocity")
    amax = per_joint_limits(max_acceleration, n, "max_acceleration")
    if np.all(np.isinf(vmax)) and np.all(np.isinf(amax)):
        raise InputError("max_velocity, max_acceleration: no finite limit to fit the durations to; give "
                         "limits (robot file keys max_velocity / max_acceleration, plan_trajectory's "
                         "max_velocity= / max_acceleration=, armkit traj --max-velocity / "
                         "--max-acceleration) or durations")
    return vmax, amax
