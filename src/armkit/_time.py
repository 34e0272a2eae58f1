"""Time grids [s] shared by control, trajectory sampling and simulation."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from armkit.errors import InputError

__all__ = ["MAX_TIME_STEPS", "even_time_grid", "rate_time_grid"]

#: Slack [in steps] when counting how many steps fit, so that 3.0 / 0.1 counts as 30 steps.
_COUNT_SLACK = 1e-9

#: Most steps a time grid may have (33 minutes at 1 kHz): a longer grid is refused with the
#: count asked for, rather than filling the machine's memory or running for days.
MAX_TIME_STEPS = 2_000_000


def _check_count(count: float, duration: float, step: float) -> None:
    if not count <= MAX_TIME_STEPS:  # also NaN
        raise InputError(f"{duration:.6g} s in steps of {step:.3g} s asks for {count:.4g} time steps, "
                         f"more than the {MAX_TIME_STEPS:,} allowed: shorten the duration or lengthen the "
                         f"step (lower the rate)")


def even_time_grid(duration: float, max_step: float) -> NDArray[np.float64]:
    """Evenly spaced times ``0 .. duration`` [s], steps of at most ``max_step`` [s].

    The first time is 0 and the last exactly ``duration``; at least one step.

    >>> even_time_grid(1.0, 0.3)
    array([0.  , 0.25, 0.5 , 0.75, 1.  ])
    """
    count = np.ceil(duration / max_step - _COUNT_SLACK)
    _check_count(count, duration, max_step)
    steps = max(1, int(count))
    return np.linspace(0.0, duration, steps + 1)


def rate_time_grid(duration: float, rate_hz: float, end_tolerance: float) -> NDArray[np.float64]:
    """Times ``0, 1/rate, 2/rate, ...`` [s] up to ``duration``, plus ``duration`` if the grid misses it.

    ``duration`` is appended when the last grid time falls short of it by more than
    ``end_tolerance`` [s], so the grid always ends at ``duration`` (its last step may be shorter).
    Both grids raise :class:`~armkit.errors.InputError` beyond :data:`MAX_TIME_STEPS` steps.

    >>> rate_time_grid(1.0, 4.0, 1e-9)
    array([0.  , 0.25, 0.5 , 0.75, 1.  ])
    >>> rate_time_grid(0.6, 4.0, 1e-9)
    array([0.  , 0.25, 0.5 , 0.6 ])
    """
    count = np.floor(duration * rate_hz + _COUNT_SLACK)
    _check_count(count, duration, 1.0 / rate_hz)
    t = np.arange(int(count) + 1) / rate_hz
    return np.append(t, duration) if duration - t[-1] > end_tolerance else t
