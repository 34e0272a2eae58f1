"""Every closed-form IK solution of a Pieper arm, a SCARA or a planar arm, compiled.

:class:`ClosedFormSolver` takes, once per chain, the case the core's registry chose for it
(:mod:`armkit.ik.structure`: each case's detect function builds its geometry, the constant
part of its equations, in the core); then the compiled core (``armkit._core``,
``cpp/src/closed_form.cpp``) handles each pose: the case solver's candidates are mapped to
the user's joints, polished by two Newton steps on the full pose where they come from a
quartic, wrapped into ``[-pi, pi]``,
checked by forward kinematics where the chain is over-determined (SCARA, planar) or a
quartic was solved (``CANDIDATE_TOLERANCE``), and duplicates are merged. Nothing is
allocated per pose, so one pose costs about a microsecond and a batch splits over
threads.

Example
-------
>>> import numpy as np, armkit
>>> robot = armkit.load("probot-anno")
>>> sol = closed_form_ik(robot, robot.fk([0.3, -0.5, 0.4, 0.2, 0.6, -0.1]))
>>> int(sol.valid.sum())
8
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit import _core
from armkit.chain import Chain, as_chain
from armkit.errors import InputError, NoClosedFormError
from armkit.ik.cases import CaseGeometry
from armkit.ik.structure import ArmStructure, analyze_structure, arm_case
from armkit.spatial.transforms import check_transform

if TYPE_CHECKING:
    from armkit.robot import Robot

__all__ = ["ClosedFormSolutions", "ClosedFormSolver", "closed_form_ik", "closed_form_solver", "one_pose",
           "solver_or_reason", "CANDIDATE_TOLERANCE", "DUPLICATE_TOLERANCE"]

#: A candidate counts only if its FK matches the target to this, times ``1 + arm size``
#: (entries of the 4x4 matrix, metres / dimensionless). It only rejects non-solutions:
#: the solutions themselves reproduce reachable poses to about 1e-13, and what IK returns
#: is checked again, to :data:`armkit.ik.results.SOLUTION_TOLERANCE` (the core's,
#: ``cpp/include/armkit/tolerances.hpp``).
CANDIDATE_TOLERANCE: float = _core.CANDIDATE_TOLERANCE
#: Candidates closer than this in every joint [rad or m, modulo 2 pi] are one solution
#: (the core's, ``cpp/include/armkit/tolerances.hpp``).
DUPLICATE_TOLERANCE = _core.DUPLICATE_TOLERANCE

Array = NDArray[np.float64]
Mask = NDArray[np.bool_]


@dataclass(frozen=True)
class ClosedFormSolutions:
    """Candidate solutions of closed-form IK for a batch of poses.

    Attributes
    ----------
    q : ndarray (..., k_max, n)
        Candidate joint values [rad or m]; revolute ones in ``[-pi, pi]``, not fitted to
        the joint limits and not filtered by them.
    valid : ndarray of bool (..., k_max)
        Per candidate: it is a solution (reproduces the pose; duplicates are invalid). A
        mask over the candidates like :attr:`family` (not "it worked": that is
        :attr:`success`), so it keeps its name.
    family : ndarray of bool (..., k_max)
        The candidate is a representative of a one-parameter family of solutions (wrist
        singularity: only ``q4 + q6`` defined; shoulder singularity: ``q1`` free, ...).
    """

    q: Array
    valid: Mask
    family: Mask

    @property
    def success(self) -> bool | Mask:
        """Whether the pose has at least one solution: a bool for one pose, ``(N,)`` for a batch.

        >>> import armkit
        >>> robot = armkit.load("ur5")
        >>> closed_form_ik(robot, robot.fk([0.3] * 6)).success, closed_form_ik(robot, np.eye(4)).success
        (True, False)
        """
        found = self.valid.any(axis=-1)
        return bool(found) if found.ndim == 0 else found


# ------------------------------------------------------------- preparation
def case_chain(axes: ArrayLike, points: ArrayLike, prismatic: ArrayLike) -> _core.CaseChain:
    """The joint lines a case geometry starts from: axes ``(n, 3)``, points ``(n, 3)`` and joint
    kinds ``(n,)`` (for building a case's geometry by hand, as tests do)."""
    return _core.CaseChain(np.ascontiguousarray(axes, dtype=float), np.ascontiguousarray(points, dtype=float),
                           np.ascontiguousarray(prismatic, dtype=bool))


class ClosedFormSolver:
    """Closed-form IK of one chain: the case the core chose for it and the per-pose loop's
    constants, made once.

    Build it with :func:`closed_form_solver` (memoised per chain).
    """

    def __init__(self, chain: Chain, arm: _core.ArmCase) -> None:
        self.chain = chain
        self.structure: ArmStructure = analyze_structure(chain)
        #: The case solver's constants (one of the case geometries of :mod:`armkit.ik.cases`).
        self.geometry: CaseGeometry = arm.geometry
        #: Candidates per pose: 8; 2 for SCARA and planar arms, 16 for a general 6R or 5R1P arm.
        self.k = self.geometry.k
        #: The compiled per-pose loop's view of this solver (``_core.ClosedForm``; it holds
        #: copies of the chain and the geometry, so it lives on its own).
        self.core = _core.closed_form_of(chain._core, arm)

    # ------------------------------------------------------------------ public
    def solve(self, T_base_tool: ArrayLike) -> ClosedFormSolutions:
        """All candidates for poses ``(4, 4)`` or ``(..., 4, 4)``; see :func:`closed_form_ik`."""
        T = check_transform(T_base_tool, "T_base_tool")
        batch = T.shape[:-2]
        q, valid, family = self.candidates(T.reshape(-1, 4, 4))
        k, n = q.shape[-2:]
        return ClosedFormSolutions(q.reshape(*batch, k, n), valid.reshape(*batch, k),
                                   family.reshape(*batch, k))

    def candidates(self, T: Array, threads: int = 0) -> tuple[Array, Mask, Mask]:
        """``(q, valid, family)`` ``(N, k, n)``, ``(N, k)`` for rigid poses ``T`` ``(N, 4, 4)``
        (checked by :func:`armkit.spatial.check_transform`), split over ``threads``
        (0: all cores; the answer does not depend on it)."""
        T = np.ascontiguousarray(T, dtype=np.float64)
        if T.ndim != 3 or T.shape[1:] != (4, 4):
            raise InputError(f"T: expected shape (N, 4, 4), got {T.shape}")
        N, k = len(T), self.k
        q = np.empty((N, k, self.chain.n))
        valid, family = np.empty((N, k), dtype=bool), np.empty((N, k), dtype=bool)
        _core.candidates(self.core, T, q, valid, family, threads)
        return q, valid, family


def closed_form_solver(robot: Robot | Chain) -> ClosedFormSolver:
    """The closed-form solver of ``robot`` (made once per chain and kept with it; a
    :class:`~armkit.chain.Chain` is accepted too).

    Raises
    ------
    NoClosedFormError
        If the chain's geometry has no closed form here (the message says why).
    """
    solver = solver_or_reason(robot)
    if isinstance(solver, NoClosedFormError):
        raise solver
    return solver


def solver_or_reason(robot: Robot | Chain) -> ClosedFormSolver | NoClosedFormError:
    """The chain's closed-form solver, or the error saying why it has none (made once)."""
    chain = as_chain(robot)
    return chain.derived(_make_solver)


def _make_solver(chain: Chain) -> ClosedFormSolver | NoClosedFormError:
    arm = arm_case(chain)
    if arm.chosen < 0:
        return NoClosedFormError(f"no closed-form IK for this chain: {arm.description}")
    return ClosedFormSolver(chain, arm)


def one_pose(chain: Chain, T_base_tool: object, near: object, within_limits: object,
             nearest: bool) -> NDArray[np.float64] | None:
    """The answer of :meth:`armkit.Robot.ik` for one pose in one core call, if the inputs are
    as the core takes them and the pose has a usable solution; else None.

    The first step of ``robot.ik(T)``, kept thin: the same core solver as
    :func:`~armkit.ik.pipeline.verified_solutions` (candidates wrapped into the limits,
    FK-verified, family members moved towards ``near``, ranked), without its per-batch arrays
    and without a Python check of the inputs. Where it returns None, ``robot.ik`` goes on to
    :func:`~armkit.ik.solve.ik`, which checks the inputs and raises, or falls back to numeric IK.

    Parameters
    ----------
    chain : Chain
        The arm.
    T_base_tool : object
        The target pose: used if it is a C-ordered native float64 ``(4, 4)`` NumPy array that
        :func:`~armkit.spatial.check_transform` would return unchanged (exactly rigid).
    near : object
        None (zeros) or ``n`` finite joint values as such an array ``(n,)``.
    within_limits : object
        ``True`` or ``False`` (a Python bool): only solutions inside the limits.
    nearest : bool
        Only the nearest solution.

    Returns
    -------
    ndarray or None
        Every usable solution ``(k, n)``, nearest to ``near`` first (``k >= 1``), or with
        ``nearest`` the nearest ``(n,)``; None if the chain has no closed form, an input is not
        as described, or no candidate is usable (out of reach, or outside the limits).

    Examples
    --------
    >>> import armkit
    >>> robot = armkit.load("ur5")
    >>> T = robot.fk(np.array([0.3, -1.0, 1.2, 0.4, 0.7, -0.2]))
    >>> one_pose(robot.chain, T, None, True, False).shape
    (8, 6)
    >>> one_pose(robot.chain, T.tolist(), None, True, False) is None  # a list: robot.ik checks it
    True
    """
    solver = chain.derived(_make_solver)
    if isinstance(solver, NoClosedFormError) or type(within_limits) is not bool:
        return None
    return _core.solve_one(solver.core, T_base_tool, near, within_limits, nearest)


def closed_form_ik(robot: Robot | Chain, T_base_tool: ArrayLike) -> ClosedFormSolutions:
    """Every closed-form IK solution of ``robot`` for one pose or a batch of poses.

    Parameters
    ----------
    robot : Robot or Chain
        An arm with a closed form (see :func:`armkit.ik.analyze_structure`); a
        :class:`~armkit.chain.Chain` is accepted too.
    T_base_tool : array_like (4, 4) or (N, 4, 4)
        Target tool pose(s) in the base frame [m].

    Returns
    -------
    ClosedFormSolutions
        ``q`` of shape ``(k_max, n)`` (or ``(N, k_max, n)``), ``valid`` and ``family``
        masks ``(k_max,)`` (or ``(N, k_max)``). ``k_max`` is 8 for 6-joint arms and 2
        for SCARA and planar arms. An unreachable pose has no valid candidate.

    Raises
    ------
    NoClosedFormError
        For chains without closed form (e.g. the 7-joint Panda).
    InputError
        If a pose is not a rigid transform.

    Examples
    --------
    >>> import armkit
    >>> robot = armkit.load("ur5")
    >>> sol = closed_form_ik(robot, robot.fk(np.full(6, 0.3)))
    >>> sol.q.shape, int(sol.valid.sum())
    ((8, 6), 8)
    """
    return closed_form_solver(robot).solve(T_base_tool)
