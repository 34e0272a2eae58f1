"""The verified closed-form solutions of many poses: the core's loop, then the rare repairs.

Per pose, the compiled core (``_core.solve_batch``, ``cpp/include/armkit/ik_solve.hpp``)
takes every candidate of the closed form (:mod:`armkit.ik.closed_form`) and

1. wraps it into the joint limits: a revolute angle is shifted by a multiple of ``2 pi``
   when that makes it fit (among several fitting shifts, the one closest to ``near``);
2. verifies it by forward kinematics: it must reproduce the target within
   :data:`~armkit.ik.results.SOLUTION_TOLERANCE`;
3. flags it inside or outside the limits and sorts the usable ones first, by distance to
   ``near`` (``|w * (q - near)|``, weights ``w``);
4. at a singular pose, moves each family representative to the member of its family
   nearest to ``near`` (``cpp/include/armkit/ik_family.hpp``): first the point of the
   family's line (a whole turn either way) nearest to ``near`` after the ``2 pi`` wrap,
   then steps along the Jacobian's null space, each put back exactly on the solution set
   by Levenberg-Marquardt steps, while the distance falls; a move that would leave the
   limits a representative was inside is not taken.

Every solution is listed once per whole-turn copy inside the limits
(:func:`with_turn_copies`): a revolute joint whose finite limits span more than a whole turn
(a UR5's +-360 degrees) holds an angle ``q`` and ``q + 2 pi t`` for every ``t`` that stays
inside, distinct configurations with the same tool pose (a UR5 solution has ``2^6``). A
joint spanning at most a whole turn holds one, and so does an unbounded (continuous) one:
its copies are endless, and the wrap above picks the nearest to ``near``. Solutions outside
the limits are listed once.

When only the solution nearest to ``near`` is asked for, the candidates go through FK
nearest first and the first that reproduces the target is the answer. Then, in Python
and only where needed: candidates above ``1e-10`` are refined by a few Newton steps of
the numeric solver without leaving their branch (:func:`refine`), and the poses touched
are ranked again.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from armkit import _core
from armkit.chain import Chain
from armkit.errors import SolutionsLeftOffWarning, warn_at_caller
from armkit.ik.closed_form import ClosedFormSolver
from armkit.ik.numeric import numeric_ik

__all__ = ["MAX_SOLUTIONS", "Found", "rank", "refine", "verified_solutions", "with_turn_copies"]

#: At most this many solutions of one pose are listed (whole-turn copies multiply: joints
#: spanning two turns each give 2^n per solution); beyond it, the nearest to ``near``, with a
#: :class:`~armkit.errors.SolutionsLeftOffWarning`.
MAX_SOLUTIONS = 4096

#: Candidates with a larger FK residual [m or rad] are refined by Newton steps (as the core's kRefineAbove).
_REFINE_ABOVE = 1e-10
#: A refinement may move a candidate by at most this [rad or m] (it must stay on its branch).
_REFINE_MAX_MOVE = 1e-6


class Found(NamedTuple):
    """Per pose ``(N, k)`` candidates, ranked by the core: ``q`` ``(N, k, n)``, ``errors``
    ``(N, k, 2)`` (FK residual: position [m], angle [rad]; NaN where not verified),
    ``flags`` ``(N, k, 4)`` (see the properties) and ``count`` ``(N,)``: how many are
    usable (kept, and inside the limits if asked), sorted first. Report ``family & keep``."""

    q: NDArray[np.float64]
    errors: NDArray[np.float64]
    flags: NDArray[np.bool_]
    count: NDArray[np.int64]

    @classmethod
    def empty(cls, N: int, k: int, n: int) -> Found:
        return cls(np.empty((N, k, n)), np.empty((N, k, 2)), np.empty((N, k, 4), dtype=bool),
                   np.empty(N, dtype=np.int64))

    @property
    def valid(self) -> NDArray[np.bool_]:
        """A solution of the closed form."""
        return self.flags[..., 0]

    @property
    def keep(self) -> NDArray[np.bool_]:
        """Also reproduces the pose to ``SOLUTION_TOLERANCE``."""
        return self.flags[..., 1]

    @property
    def inside(self) -> NDArray[np.bool_]:
        """Inside the joint limits."""
        return self.flags[..., 2]

    @property
    def family(self) -> NDArray[np.bool_]:
        """A representative of a one-parameter family, as the closed form flags it."""
        return self.flags[..., 3]

    @property
    def position_error(self) -> NDArray[np.float64]:
        return self.errors[..., 0]

    @property
    def orientation_error(self) -> NDArray[np.float64]:
        return self.errors[..., 1]


def refine(chain: Chain, found: Found, T_target: NDArray[np.float64]) -> NDArray[np.int_]:
    """Newton-refine (in place) the candidates whose residual is above ``_REFINE_ABOVE``;
    the poses touched (to be ranked again)."""
    rough = found.valid & ((found.position_error > _REFINE_ABOVE) | (found.orientation_error > _REFINE_ABOVE))
    for index in zip(*np.nonzero(rough), strict=True):
        q = found.q[index]
        result = numeric_ik(chain, T_target[index[0]], q0=q, max_iterations=8, max_restarts=0,
                            position_tolerance=1e-13, orientation_tolerance=1e-13,
                            within_limits=False)
        better = (result.position_error + result.orientation_error
                  < found.position_error[index] + found.orientation_error[index])
        if better and np.abs(result.q - q).max() < _REFINE_MAX_MOVE:
            found.q[index] = result.q
            found.errors[index] = result.position_error, result.orientation_error
    return np.flatnonzero(rough.any(axis=1))


def rank(solver: ClosedFormSolver, found: Found, poses: NDArray[np.int_], near: NDArray[np.float64] | None,
         weights: NDArray[np.float64] | None, within_limits: bool) -> None:
    """Flag, count and sort again (in place) the candidates of ``poses``."""
    _core.rank(solver.core, np.ascontiguousarray(poses, dtype=np.int64), near, weights, within_limits, *found)


def verified_solutions(solver: ClosedFormSolver, T: NDArray[np.float64], near: NDArray[np.float64] | None,
                       weights: NDArray[np.float64] | None, within_limits: bool = False,
                       nearest: bool = False, threads: int = 0,
                       rigid_tolerance: float = -1.0) -> tuple[Found, int] | None:
    """The verified closed-form solutions of the targets ``T`` ``(N, 4, 4)``, nearest first.

    ``near`` ``(N, n)`` or ``(n,)`` (None: zeros) and ``weights`` ``(n,)`` (None: ones),
    C-ordered float64. Per pose, the usable candidates come first, nearest to ``near``
    first (see :class:`Found`); ``count`` is zero for a pose without any; the second value
    is the number of such poses. ``nearest``: only the first is wanted. With
    ``rigid_tolerance >= 0`` the core first checks that every target is exactly rigid (as
    :func:`armkit.spatial.check_transform` would return it unchanged) and returns None if
    one is not, having solved nothing.
    """
    chain = solver.chain
    found = Found.empty(len(T), solver.k, chain.n)
    rough, empty = _core.solve_batch(solver.core, T, near, weights, within_limits, nearest, rigid_tolerance,
                                     *found, threads)
    if rough < 0:
        return None
    if rough:
        rank(solver, found, refine(chain, found, T), near, weights, within_limits)
        empty = int((found.count == 0).sum())
    return found, empty


def with_turn_copies(chain: Chain, T: NDArray[np.float64], q: NDArray[np.float64], inside: NDArray[np.bool_],
                     near: NDArray[np.float64] | None, weights: NDArray[np.float64] | None,
                     joints: NDArray[np.bool_] | None = None, left_off: list[float] | None = None,
                     ) -> tuple[NDArray[np.int64], NDArray[np.float64], NDArray[np.float64]]:
    """The solutions ``q`` ``(k, n)`` of pose ``T`` ``(4, 4)`` with every whole-turn copy
    inside the limits of those ``inside`` (see the module's docstring), nearest to ``near``
    first (None: zeros; ``weights`` None: ones), at most :data:`MAX_SOLUTIONS`. ``joints``
    ``(n,)``: the joints whose copies count (None: all; held joints keep their value).
    More than :data:`MAX_SOLUTIONS` copies: a :class:`~armkit.errors.SolutionsLeftOffWarning`,
    or with ``left_off`` (a list) their number appended to it instead (a batch warns once).

    Returns the row of ``q`` each listed solution is a copy of ``(m,)``, the solutions
    ``(m, n)`` and their FK residuals ``(m, 2)`` [m, rad] (each copy's own FK, which
    differs from its original's by rounding only; no copy is dropped for it).
    """
    n = chain.n
    source, copies, errors, total = _core.turn_copies(
        chain._core, np.ascontiguousarray(T, dtype=np.float64), np.ascontiguousarray(q, dtype=np.float64),
        np.ascontiguousarray(inside, dtype=bool),
        np.ones(n, dtype=bool) if joints is None else np.ascontiguousarray(joints, dtype=bool),
        np.zeros(n) if near is None else near,
        np.ones(n) if weights is None else weights, MAX_SOLUTIONS)
    if total > len(source) and left_off is not None:
        left_off.append(total)
    elif total > len(source):
        copied = ", ".join(f"q{j + 1}" for j in chain.spans_turns if joints is None or joints[j])
        warn_at_caller(SolutionsLeftOffWarning(
            f"{total:.0f} solutions inside the limits (whole-turn copies of joints {copied}): "
            f"the {len(source)} nearest to near are listed"))
    return source, copies, errors
