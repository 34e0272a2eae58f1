"""The errors IK raises when a target has no usable solution, and their messages.

Each message says which pose of a batch it is about, how far out of reach the target is
(the closest pose the numeric solver finds) or which joint limits the solutions leave,
and what to ask for instead. This module only words the errors; the search for the closest
pose (and the numeric answer of a pose the closed form misses) is
:func:`armkit.ik.pipeline.numeric_fallback`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from armkit.chain import Chain
from armkit.errors import JointLimitError, UnreachableError

if TYPE_CHECKING:
    from armkit.ik.numeric import IKResult

__all__ = ["Labels", "angle_text", "numeric_failure", "out_of_reach", "outside_limits"]


def angle_text(angle: float) -> str:
    return f"{angle:.3g} rad ({np.degrees(angle):.3g} deg)"


def outside_limits(chain: Chain, q: NDArray[np.float64], label: str,
                   degrees: bool = False) -> JointLimitError:
    """The error for a pose reachable only outside the limits, ``q`` ``(n,)`` a solution there
    (revolute values in degrees in the message with ``degrees``)."""
    q = np.array(q, dtype=float)
    bad = chain.limit_violations(q, degrees)
    return JointLimitError(
        f"{label}the target pose is reachable, but only outside the joint limits (e.g. "
        f"{', '.join(bad)}): ask for solutions outside the limits with within_limits=False or "
        f"'armkit ik --outside'", q, **chain.limit_fields(q))


class Labels:
    """``labels[i]``: ``"pose i of N: "`` to start an error message about pose ``i`` of a batch."""

    def __init__(self, size: int) -> None:
        self.size = size

    def __getitem__(self, i: int) -> str:
        return f"pose {i} of {self.size}: " if self.size else ""


def out_of_reach(closest: IKResult, label: str) -> UnreachableError:
    """The error for a target pose out of reach, ``closest`` the closest pose numeric IK found."""
    return UnreachableError(
        f"{label}the target pose is out of reach: the closest pose found is "
        f"{closest.position_error:.3g} m and {angle_text(closest.orientation_error)} away",
        closest.position_error, closest.orientation_error)


def numeric_failure(chain: Chain, result: IKResult, label: str, masked: bool) -> UnreachableError:
    """The error for a target the numeric solver did not reach (``result``: its best attempt)."""
    hint = ""
    if chain.n < 6 and not masked:
        hint = (f" (an arm with {chain.n} joints reaches only a {chain.n}-dimensional set of poses, so a "
                f"rounded pose misses it: ask for the position only, mask=[1, 1, 1, 0, 0, 0] or "
                f"'armkit ik --position')")
    return UnreachableError(
        f"{label}no solution found by numeric IK within its budget ({result.restarts + 1} "
        f"attempts): the closest pose found is {result.position_error:.3g} m and "
        f"{angle_text(result.orientation_error)} away; the target is probably out of reach{hint}",
        result.position_error, result.orientation_error)
