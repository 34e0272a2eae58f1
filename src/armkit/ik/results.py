"""What :func:`armkit.ik.ik_solutions` returns: every solution of a pose, with flags.

Every returned solution reproduces its target to :data:`SOLUTION_TOLERANCE` (checked by
forward kinematics in the compiled core, ``cpp/include/armkit/ik_solve.hpp``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from armkit import _core
from armkit._deprecation import deprecated_constants

__all__ = ["SOLUTION_TOLERANCE", "IKSolutions", "IKSolutionsBatch", "residuals"]

#: Position [m] and angle [rad] within which every returned solution reproduces the target
#: (the compiled core's ``kSolutionTolerance``). ``armkit.ik.results.VERIFY_TOLERANCE`` is its
#: deprecated old name, the one place that name still answers (``armkit.ik.solve`` and
#: ``armkit.ik.closed_form`` no longer do: the closed form's meant the candidate test,
#: :data:`armkit.ik.closed_form.CANDIDATE_TOLERANCE`).
SOLUTION_TOLERANCE: float = _core.SOLUTION_TOLERANCE
__getattr__ = deprecated_constants(__name__, {"VERIFY_TOLERANCE": "SOLUTION_TOLERANCE"},
                                   {"SOLUTION_TOLERANCE": SOLUTION_TOLERANCE})


@dataclass(frozen=True)
class IKSolutions:
    """Every closed-form solution of one target pose, with a flag per solution.

    Attributes
    ----------
    q : ndarray, shape (k, n)
        Solutions [rad or m], wrapped into the limits where a ``2 pi`` shift makes them fit,
        sorted by distance to ``near``.
    within_limits : ndarray, shape (k,), bool
        Whether each solution lies inside every joint limit.
    family : ndarray, shape (k,), bool
        Whether the solution is a representative of a one-parameter family (a wrist,
        shoulder or elbow singularity, where only a sum of joint angles is defined).
    position_error : ndarray, shape (k,)
        FK residual [m] of each solution: distance from the target position.
    orientation_error : ndarray, shape (k,)
        FK residual [rad] of each solution: angle from the target orientation.
    """

    q: NDArray[np.float64]
    within_limits: NDArray[np.bool_]
    family: NDArray[np.bool_]
    position_error: NDArray[np.float64]
    orientation_error: NDArray[np.float64]

    @property
    def success(self) -> bool:
        """Whether the pose has a solution (``k > 0``), inside the limits or not."""
        return len(self.q) > 0


@dataclass(frozen=True)
class IKSolutionsBatch(Sequence[IKSolutions]):
    """The solutions of ``N`` target poses as padded arrays; ``batch[i]`` is pose ``i``'s.

    Attributes
    ----------
    q : ndarray, shape (N, k_max, n)
        Per pose, its ``counts[i]`` solutions first (nearest to ``near`` first), then padding.
    counts : ndarray, shape (N,), int
        Number of solutions of each pose (0: out of reach).
    within_limits, family : ndarray, shape (N, k_max), bool
    position_error, orientation_error : ndarray, shape (N, k_max)
        As in :class:`IKSolutions`; padding entries are meaningless.

    Examples
    --------
    >>> import armkit
    >>> robot = armkit.load("ur5")
    >>> from armkit.ik import ik_solutions
    >>> T = robot.fk(robot.random_q(3, rng=0))
    >>> found = ik_solutions(robot, T)             # each solution once
    >>> len(found), found.q.shape, found.counts, found[1].q.shape
    (3, (3, 8, 6), array([8, 4, 8]), (4, 6))
    >>> ik_solutions(robot, T, turn_copies=True).counts  # with the whole-turn copies in its +-360 deg limits
    array([512, 256, 512])
    """

    q: NDArray[np.float64]
    counts: NDArray[np.int_]
    within_limits: NDArray[np.bool_]
    family: NDArray[np.bool_]
    position_error: NDArray[np.float64]
    orientation_error: NDArray[np.float64]

    @classmethod
    def stack(cls, solutions: Sequence[IKSolutions], n: int) -> IKSolutionsBatch:
        """The solutions of several poses, padded to the largest count (``n`` joints)."""
        counts = np.array([len(s.q) for s in solutions], dtype=np.int64)
        k = int(counts.max(initial=0))
        q, errors = np.full((len(solutions), k, n), np.nan), np.full((len(solutions), k, 2), np.nan)
        inside, family = np.zeros((len(solutions), k), dtype=bool), np.zeros((len(solutions), k), dtype=bool)
        for i, s in enumerate(solutions):
            m = counts[i]
            q[i, :m], inside[i, :m], family[i, :m] = s.q, s.within_limits, s.family
            errors[i, :m, 0], errors[i, :m, 1] = s.position_error, s.orientation_error
        return cls(q, counts, inside, family, errors[..., 0], errors[..., 1])

    @property
    def success(self) -> NDArray[np.bool_]:
        """Per pose, whether it has a solution (``counts > 0``), ``(N,)``."""
        return self.counts > 0

    def __len__(self) -> int:
        return len(self.q)

    def __getitem__(self, i):  # type: ignore[override]  # int -> IKSolutions, slice -> list
        if isinstance(i, slice):
            return [self[j] for j in range(*i.indices(len(self)))]
        k = self.counts[i]
        return IKSolutions(self.q[i, :k], self.within_limits[i, :k], self.family[i, :k],
                           self.position_error[i, :k], self.orientation_error[i, :k])


def residuals(T_target: NDArray[np.float64], F: NDArray[np.float64]) -> NDArray[np.float64]:
    """FK residuals ``(..., 2)`` of poses ``F`` to ``T_target`` ``(..., 4, 4)``: the position
    distance [m] and the rotation angle [rad], accurate to rounding from 0 to ``pi``."""
    T_target, F = np.broadcast_arrays(np.asarray(T_target, dtype=np.float64), np.asarray(F, dtype=np.float64))
    out = np.empty((*F.shape[:-2], 2))
    _core.residuals(np.ascontiguousarray(T_target), np.ascontiguousarray(F), out)
    return out
