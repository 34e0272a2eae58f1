"""Input checks the control modules share (the motions and the Cartesian line)."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit._params import positive_float
from armkit.errors import InputError
from armkit.robot import Robot

__all__ = ["check_positive", "check_start"]


def check_start(robot: Robot, q0: ArrayLike) -> NDArray[np.float64]:
    """``q0`` as one configuration of ``robot`` inside its limits, or an armkit error naming it."""
    q0 = robot.check_q(q0, "q0")
    if q0.ndim != 1:
        raise InputError(f"q0: expected one configuration of {robot.n} values, got shape {q0.shape}")
    robot.check_limits(q0)
    return q0


def check_positive(value: object, name: str, unit: str) -> float:
    """``value`` as a finite float > 0, or :class:`InputError` naming ``name`` and its ``unit``."""
    return positive_float(value, f"{name} [{unit}]")
