"""The verified closed-form solutions of many poses: the core's loop, then the whole-turn copies.

Per pose, the compiled core (``_core.solve_batch``, ``cpp/include/armkit/ik_solve.hpp``)
takes every candidate of the closed form (:mod:`armkit.ik.closed_form`) and

1. wraps it into the joint limits: a revolute angle is shifted by a multiple of ``2 pi``
   when that makes it fit (among several fitting shifts, the one closest to ``near``);
2. verifies it by forward kinematics: it must reproduce the target within
   :data:`~armkit.ik.results.SOLUTION_TOLERANCE`; a candidate with an FK residual above
   ``1e-13`` is first refined by a few Levenberg-Marquardt steps that may move a joint by
   at most 1e-6 (a family's representative by 1e-3: its exact neighbours are members of
   the family), so that it stays on its branch, and wrapped towards ``near`` again; one the
   case did not flag is flagged a family member where, refined, it lies on a family;
3. flags it inside or outside the limits and sorts the usable ones first, by distance to
   ``near`` (``|w * (q - near)|``, weights ``w``);
4. at a singular pose, moves each family representative to the member of its family
   nearest to ``near`` (``cpp/include/armkit/ik_family.hpp``): first the point of the
   family's line (a whole turn either way) nearest to ``near`` after the ``2 pi`` wrap,
   then steps along the Jacobian's null space, each put back exactly on the solution set
   by Levenberg-Marquardt steps, while the distance falls; a move that would leave the
   limits a representative was inside is not taken; candidates that refinement or a walk
   brought onto the same solution are merged.

Asked for them (``turn_copies=True``), every solution is listed once per whole-turn copy
inside the limits (:func:`with_turn_copies`; :func:`count_turn_copies` counts them): a revolute
joint whose finite limits span more than a whole turn (a UR5's +-360 degrees) holds an angle
``q`` and ``q + 2 pi t`` for every ``t`` that stays inside, distinct configurations with the same
tool pose (a UR5 solution has ``2^6``). A joint spanning at most a whole turn holds one, and so
does an unbounded (continuous) one: its copies are endless, and the wrap above picks the nearest
to ``near``. Solutions outside the limits are listed once; by default each solution is listed
once, the copy nearest to ``near``. A copy has its solution's tool pose, so it is listed with
that solution's FK residuals (not put through FK again), and the copies of a whole batch are
listed in one core call (``cpp/include/armkit/turn_copies.hpp``).

When only the solution nearest to ``near`` is asked for, the candidates go through FK
nearest first and the first that reproduces the target (inside the limits, if asked) is
the answer.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from armkit import _core
from armkit.chain import Chain
from armkit.errors import SolutionsLeftOffWarning
from armkit.ik.closed_form import ClosedFormSolver
from armkit.ik.messages import Labels, out_of_reach, outside_limits
from armkit.ik.numeric import IKResult, numeric_ik, wrap_into_limits
from armkit.kinematics import singular_values

__all__ = ["MAX_SOLUTIONS", "Found", "count_turn_copies", "left_off_warning", "numeric_fallback",
           "verified_solutions", "with_turn_copies"]

#: At most this many solutions of one pose are listed (whole-turn copies multiply: joints
#: spanning two turns each give 2^n per solution); beyond it, the nearest to ``near``, with a
#: :class:`~armkit.errors.SolutionsLeftOffWarning`.
MAX_SOLUTIONS = 4096
#: Budget of the search for the closest pose when no candidate of a pose is usable.
CLOSEST_POSE_RESTARTS = 20
#: Smallest singular value below this fraction of the largest: a singular configuration.
SINGULAR = 1e-8

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


#: What :func:`verified_solutions` returns: the fields of a :class:`Found` and a count.
FoundArrays = tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_], NDArray[np.int64], int]


def verified_solutions(solver: ClosedFormSolver, T: NDArray[np.float64], near: NDArray[np.float64] | None,
                       weights: NDArray[np.float64] | None, within_limits: bool = False,
                       nearest: bool = False, threads: int = 0) -> FoundArrays:
    """The verified closed-form solutions of the targets ``T`` ``(..., 4, 4)``, nearest first,
    in one core call for any number of poses.

    ``T`` exactly rigid (as :func:`armkit.spatial.check_transform` returns it), ``near``
    ``(N, n)`` or ``(n,)`` (None: zeros) and ``weights`` ``(n,)`` (None: ones), all C-ordered
    float64. Returns the fields of a :class:`Found` (``q``, ``errors``, ``flags``, ``count``;
    the caller wraps them in one where it reads more than ``q`` and ``count``: a Python object
    fewer on the way of one pose) and the number of poses without a usable candidate. Per pose,
    the usable candidates come first, nearest to ``near`` first; ``count`` is zero for a pose
    without any. ``nearest``: only the first is wanted.
    """
    return _core.solve(solver.core, T, near, weights, within_limits, nearest, threads)


def with_turn_copies(chain: Chain, found: Found, near: NDArray[np.float64] | None,
                     weights: NDArray[np.float64] | None, joints: NDArray[np.bool_] | None = None, *,
                     max_rows: float = math.inf, threads: int = 0) -> tuple[Found, NDArray[np.float64]]:
    """The usable solutions in ``found`` (each pose's first ``count``) with every whole-turn copy
    inside the limits of those inside (see the module's docstring), nearest to ``near`` first
    (``(N, n)``, ``(n,)`` or None: zeros; ``weights`` None: ones), at most :data:`MAX_SOLUTIONS` per
    pose, in one core call for the whole batch; ``joints`` ``(n,)``: the joints whose copies count
    (None: all; held joints keep their value).

    Returns the listing, a :class:`Found` padded with NaN (``count``: each pose's listed copies,
    each with its solution's FK residuals and flags: a copy has its solution's tool pose), and
    how many copies each pose has ``(N,)`` (more than listed: some were left off, see
    :func:`left_off_warning`). If ``N`` times the longest listing would exceed ``max_rows``,
    nothing is listed: the listing's arrays are None and ``count`` says how many would be.
    """
    q, errors, flags, count, total = _core.turn_copies(chain._core, *found, near, weights, joints,
                                                       MAX_SOLUTIONS, max_rows, threads)
    return Found(q, errors, flags, count), total


def left_off_warning(chain: Chain, listed: int, total: float,
                     joints: NDArray[np.bool_] | None = None) -> SolutionsLeftOffWarning:
    """The warning for a pose with ``total`` solutions inside the limits (whole-turn copies
    counted) of which only the ``listed`` nearest are listed (:data:`MAX_SOLUTIONS`)."""
    copied = ", ".join(f"q{j + 1}" for j in chain.spans_turns if joints is None or joints[j])
    return SolutionsLeftOffWarning(f"{total:.0f} solutions inside the limits (whole-turn copies of joints "
                                   f"{copied}): the {listed} nearest to near are listed")


def count_turn_copies(chain: Chain, q: NDArray[np.float64], joints: NDArray[np.bool_] | None = None) -> int:
    """How many configurations inside the limits the solutions ``q`` ``(k, n)`` (inside the
    limits) of one pose and their whole-turn copies make, without listing them: ``k`` when no
    joint's limits span more than a whole turn. ``joints`` ``(n,)``: the joints whose copies
    count (None: all), as in :func:`with_turn_copies`.

    Examples
    --------
    >>> import armkit
    >>> ur5 = armkit.load("ur5")                  # every joint within +-360 degrees
    >>> q = ur5.ik(ur5.fk([0.3, -1.0, 1.2, 0.4, 0.7, -0.2]), all_solutions=True)
    >>> len(q), count_turn_copies(ur5.chain, q)
    (8, 512)
    """
    n = chain.n
    q = np.ascontiguousarray(q, dtype=np.float64).reshape(1, -1, n)
    k = q.shape[1]
    flags = np.ones((1, k, 4), dtype=bool)
    joints = None if joints is None else np.ascontiguousarray(joints, dtype=bool)
    return int(_core.turn_copies(chain._core, q, np.zeros((1, k, 2)), flags, np.array([k]), None, None,
                                 joints, 0, math.inf, 1)[4][0])


def numeric_fallback(chain: Chain, c: Found, T: NDArray[np.float64], near: NDArray[np.float64],
                     labels: Labels, within_limits: bool = True) -> None:
    """The poses of ``c`` without a usable candidate (``count == 0``): raise the error that says
    why (:mod:`armkit.ik.messages`), or, where the closed form's candidates all miss the pose
    (degenerate geometry at a doubly singular pose, where a root of the closed form's equations
    is multiple) but numeric IK from ``near`` ``(N, n)`` reaches it exactly, put that solution
    first in ``c`` (in place) and count it, so a reachable pose is never called out of reach."""
    for i in np.flatnonzero(c.count == 0):
        if c.keep[i].any():
            first = np.flatnonzero(c.keep[i])[0]
            raise outside_limits(chain, c.q[i, first], labels[i])
        closest = numeric_ik(chain, T[i], q0=near[i], within_limits=False,
                             max_restarts=CLOSEST_POSE_RESTARTS, rng=0)
        if not closest.success:
            raise out_of_reach(closest, labels[i])
        if within_limits and not chain.within_limits(wrap_into_limits(chain, closest.q, near[i])):
            inside = numeric_ik(chain, T[i], q0=near[i], max_restarts=CLOSEST_POSE_RESTARTS, rng=0)
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
    c.flags[i, 0] = True, True, bool(chain.within_limits(q)), bool(S[-1] <= SINGULAR * S[0] or len(S) < 6)
