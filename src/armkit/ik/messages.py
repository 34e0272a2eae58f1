"""The errors IK raises when a target has no usable solution, and their messages.

Each message says which pose of a batch it is about, how far out of reach the target is
(the closest pose the numeric solver finds) or which joint limits the solutions leave,
and what to ask for instead. A pose every closed-form candidate misses (degenerate
geometry at a doubly singular pose, where a root of the closed form's equations is
multiple) but numeric IK from ``near`` reaches exactly is answered by that solution, not
called out of reach.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from armkit.chain import Chain
from armkit.errors import JointLimitError, UnreachableError
from armkit.ik.numeric import IKResult, numeric_ik, wrap_into_limits
from armkit.kinematics import singular_values

if TYPE_CHECKING:
    from armkit.ik.pipeline import Found

__all__ = ["Labels", "angle_text", "numeric_failure", "outside_limits", "answer_or_raise"]

#: Budget of the search for the closest pose when a target is out of reach.
_CLOSEST_POSE_RESTARTS = 20
#: Smallest singular value below this fraction of the largest: a singular configuration.
_SINGULAR = 1e-8


def angle_text(angle: float) -> str:
    return f"{angle:.3g} rad ({np.degrees(angle):.3g} deg)"


def outside_limits(chain: Chain, q: NDArray[np.float64], label: str,
                   degrees: bool = False) -> JointLimitError:
    """The error for a pose reachable only outside the limits, ``q`` ``(n,)`` a solution there
    (revolute values in degrees in the message with ``degrees``)."""
    bad = chain.limit_violations(q, degrees)
    return JointLimitError(
        f"{label}the target pose is reachable, but only outside the joint limits (e.g. "
        f"{', '.join(bad)}): ask for solutions outside the limits with within_limits=False or "
        f"'armkit ik --outside'", q=np.array(q, dtype=float))


class Labels:
    """``labels[i]``: ``"pose i of N: "`` to start an error message about pose ``i`` of a batch."""

    def __init__(self, size: int) -> None:
        self.size = size

    def __getitem__(self, i: int) -> str:
        return f"pose {i} of {self.size}: " if self.size else ""


def answer_or_raise(chain: Chain, c: Found, T: NDArray[np.float64], near: NDArray[np.float64],
                      labels: Labels, within_limits: bool = True) -> None:
    """For each pose without a usable candidate: raise, or where the closed form's
    candidates all miss the pose but numeric IK from ``near`` reaches it exactly, put that
    solution in ``c`` (in place), so a reachable pose is never called out of reach."""
    for i in np.flatnonzero(c.count == 0):
        if c.keep[i].any():
            first = np.flatnonzero(c.keep[i])[0]
            raise outside_limits(chain, c.q[i, first], labels[i])
        closest = numeric_ik(chain, T[i], q0=near[i], within_limits=False,
                             max_restarts=_CLOSEST_POSE_RESTARTS, rng=0)
        if not closest.success:
            raise UnreachableError(
                f"{labels[i]}the target pose is out of reach: the closest pose found is "
                f"{closest.position_error:.3g} m and {angle_text(closest.orientation_error)} away",
                closest.position_error, closest.orientation_error)
        if within_limits and not chain.within_limits(wrap_into_limits(chain, closest.q, near[i])):
            inside = numeric_ik(chain, T[i], q0=near[i], max_restarts=_CLOSEST_POSE_RESTARTS, rng=0)
            if not inside.success:
                raise outside_limits(chain, wrap_into_limits(chain, closest.q, near[i]), labels[i])
            closest = inside
        _take_numeric_solution(chain, c, i, closest, near[i])
        c.count[i] = 1


def _take_numeric_solution(chain: Chain, c: Found, i: int, result: IKResult,
                           near: NDArray[np.float64]) -> None:
    """Put numeric IK's solution of pose ``i`` first among its (all unusable) candidates:
    wrapped towards ``near``, flagged ``family`` if the Jacobian there is singular (the
    degenerate poses where closed-form candidates fail lie on families)."""
    q = wrap_into_limits(chain, result.q, near)
    S = singular_values(chain, q)
    c.q[i, 0] = q
    c.errors[i, 0] = result.position_error, result.orientation_error
    c.flags[i, 0] = True, True, bool(chain.within_limits(q)), bool(S[-1] <= _SINGULAR * S[0] or len(S) < 6)


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
