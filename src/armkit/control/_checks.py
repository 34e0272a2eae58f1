"""Input checks the control modules share (the motions and the Cartesian line)."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit._params import positive_float
from armkit.errors import InputError, UnreachableError
from armkit.robot import Robot

__all__ = ["REACH_MARGIN", "check_positive", "check_start", "refuse_beyond_reach"]

#: Relative margin on :attr:`armkit.chain.Chain.reach` before a target counts as beyond it (the bound's
#: own rounding).
REACH_MARGIN = 1e-9


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


def refuse_beyond_reach(robot: Robot, start: NDArray[np.float64], displacement: NDArray[np.float64],
                        what: str) -> None:
    """:class:`UnreachableError` before any step if the target ``start + displacement`` [m] (base frame)
    lies beyond :attr:`armkit.chain.Chain.reach`, farther than any tool position can be; ``what``: the
    argument that gave the target, as given."""
    reach = robot.chain.reach
    scale = max(float(np.abs(displacement).max()), 1.0)  # |target| without overflow (1e308 components)
    distance = float(np.linalg.norm(start / scale + displacement / scale)) * scale
    if distance > reach * (1.0 + REACH_MARGIN):
        raise UnreachableError(f"{what}: the target is {distance:.6g} m from the base, beyond the arm's "
                               f"reach ({reach:.6g} m: its link lengths and slide travel added up); nothing "
                               f"was run", distance - reach)
