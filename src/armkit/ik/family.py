"""Singular poses: the member of a family of solutions nearest to a reference configuration.

At a singular pose the closed form returns one member of a one-parameter family (e.g.
``q4 = 0`` for an aligned wrist, where only ``q4 + q6`` is defined); :func:`walk_family`
moves it along the family to the member nearest to ``near``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from armkit.chain import Chain
from armkit.ik.numeric import numeric_ik, wrap_into_limits
from armkit.ik.results import residuals
from armkit.kinematics import fk, geometric_jacobian

if TYPE_CHECKING:
    from armkit.ik.pipeline import Found

__all__ = ["nearest_family_members", "walk_family"]

#: Steps along a singular family towards ``near`` (one where the family is a line in joint space).
_FAMILY_STEPS = 10
#: Singular values below this fraction of the largest span a family's directions.
_NULL_SPACE = 1e-8
#: Points sampled along a family's line (two whole turns of its fastest joint).
_FAMILY_SAMPLES = 257


def nearest_family_members(chain: Chain, found: Found, T: NDArray[np.float64], near: NDArray[np.float64],
                            weights: NDArray[np.float64]) -> set[int]:
    """Move each kept family representative (in place) to the member of its family nearest
    to ``near``; the poses touched (to be ranked again).

    At a singular pose the closed form returns one member of a one-parameter family (e.g.
    ``q4 = 0`` for an aligned wrist, where only ``q4 + q6`` is defined). The family runs
    along the null space of the Jacobian: first the point of that line (a whole turn
    either way) nearest to ``near`` after the ``2 pi`` wrap into the limits, then steps
    along the null space (weighted by ``weights``), each put back exactly on the solution
    set by Newton steps, while the distance falls. A move that would leave the limits a
    representative was inside is not taken.
    """
    poses = set()
    for i, s in zip(*np.nonzero(found.family & found.keep), strict=True):
        q = walk_family(chain, T[i], found.q[i, s], near[i], weights)
        if not np.array_equal(q, found.q[i, s]):
            found.q[i, s] = q
            found.errors[i, s] = residuals(T[i], fk(chain, q))
            poses.add(int(i))
    return poses


def walk_family(chain: Chain, T: NDArray[np.float64], q: NDArray[np.float64], near: NDArray[np.float64],
                weights: NDArray[np.float64]) -> NDArray[np.float64]:
    """The member of ``q``'s family of solutions nearest to ``near`` (see above)."""
    w2 = weights**2
    inside = bool(chain.within_limits(q))

    def distance(candidates: NDArray[np.float64]) -> NDArray[np.float64]:
        """Weighted squared distance to near after the wrap, infinite where the limits are left."""
        moved = wrap_into_limits(chain, candidates, near)
        far = np.sum(w2 * (moved - near) ** 2, axis=-1)
        return np.where(chain.within_limits(moved) | (not inside), far, np.inf)

    for step in range(_FAMILY_STEPS):
        _, S, Vt = np.linalg.svd(geometric_jacobian(chain, q))
        N = Vt[len(S) - np.count_nonzero(S <= _NULL_SPACE * S[0]):].T  # (n, k) null-space basis
        if N.shape[1] == 0:
            break
        if step == 0 and N.shape[1] == 1:  # the line through q, up to a whole turn of any joint
            v = N[:, 0] / np.abs(N[:, 0]).max()
            line = q + np.linspace(-2 * np.pi, 2 * np.pi, _FAMILY_SAMPLES)[:, None] * v
            target = line[np.argmin(distance(line))]
        else:
            step_to_near = N @ np.linalg.solve(N.T @ (w2[:, None] * N), N.T @ (w2 * (near - q)))
            target = q + step_to_near
        result = numeric_ik(chain, T, q0=target, respect_limits=False, max_restarts=0,
                            max_iterations=10, position_tolerance=1e-13, orientation_tolerance=1e-13)
        if not (result.success and distance(result.q) < distance(q) - 1e-24):
            if step == 0 and N.shape[1] == 1:
                continue  # the sampled point did not help: go on with local steps
            break
        q = wrap_into_limits(chain, result.q, near)
    return q
