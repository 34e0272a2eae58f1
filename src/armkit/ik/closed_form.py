"""Every closed-form IK solution of a Pieper arm, a SCARA or a planar arm, compiled.

:class:`ClosedFormSolver` prepares, once per chain, what the case solvers of
:mod:`armkit.ik.cases` need (axes, points, the constant part of the case's equations);
then the compiled core (``armkit._core``, ``cpp/src/closed_form.cpp``) handles each pose:
the case solver's candidates are mapped to the user's joints, polished by two Newton
steps on the full pose where they come from a quartic, wrapped into ``[-pi, pi]``,
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
from armkit.ik.cases import POSITION_CASES, CaseGeometry, solve_pose
from armkit.ik.structure import ArmStructure, SolverPlan, plan_closed_form
from armkit.ik.subproblems import sp4, trig_coeffs
from armkit.spatial.lines import closest_points
from armkit.spatial.transforms import check_transform

if TYPE_CHECKING:
    from armkit.robot import Robot

__all__ = ["ClosedFormSolutions", "ClosedFormSolver", "closed_form_ik", "closed_form_solver",
           "solver_or_reason", "CANDIDATE_TOLERANCE", "DUPLICATE_TOLERANCE"]

#: A candidate counts only if its FK matches the target to this, times ``1 + arm size``
#: (entries of the 4x4 matrix, metres / dimensionless). It only rejects non-solutions:
#: the solutions themselves reproduce reachable poses to about 1e-13, and what IK returns
#: is checked again, to :data:`armkit.ik.results.SOLUTION_TOLERANCE`.
CANDIDATE_TOLERANCE = 1e-8
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
def _unit_normal(h: Array) -> Array:
    """A unit vector perpendicular to ``h``."""
    e = np.eye(3)[np.argmin(np.abs(h))]
    u = np.cross(h, e)
    return u / np.linalg.norm(u)


def _vector(v: ArrayLike | None) -> tuple[float, float, float]:
    return (0.0, 0.0, 0.0) if v is None else tuple(float(x) for x in np.asarray(v, dtype=float))


def _two_angle_system(Q: Array, f: tuple[float, float], snap_t2: bool = True) -> _core.TwoAngleSystem:
    """The constant part of a two-angle system ``P x(t1) - Q x(t2) = r`` (``ik_cases.hpp``):
    ``Q``, its inverse or, of rank 1, the combinations ``lam`` (holds ``t1`` alone) and ``mu``."""
    U, S, _ = np.linalg.svd(Q)
    rank1 = bool(S[1] <= _core.RANK_ONE_TOLERANCE * S[0])
    return _core.TwoAngleSystem(Q=Q, Q_inv=np.zeros((2, 2)) if rank1 else np.linalg.inv(Q), f=f, rank1=rank1,
                                lam=(float(U[0, 1]), float(U[1, 1])), mu=(float(U[0, 0]), float(U[1, 0])),
                                snap_t2=snap_t2)


def case_chain(poe) -> _core.CaseChain:
    """The joint lines a case geometry starts from: ``poe``'s axes, points and joint kinds."""
    return _core.CaseChain(np.ascontiguousarray(poe.axes), np.ascontiguousarray(poe.points),
                           np.ascontiguousarray(poe.prismatic, dtype=bool))


def point_geometry(poe, case: str, c: Array, o: Array | None, wrist: bool) -> CaseGeometry:
    """Joints 1-3 of ``poe`` carrying the point ``c`` (``o``: where axes 1, 2 or 2, 3 meet),
    by the position case ``case``: a spherical wrist at ``c`` (``wrist``) or position IK."""
    system, o2, o3 = _core.TwoAngleSystem(), _vector(None), _vector(None)
    if case == "general-123":
        system, o2, o3 = _general_position(poe, c)
    fields = dict(chain=case_chain(poe), system=system, position_case=POSITION_CASES.index(case),
                  c=_vector(c), o=_vector(o), o2=o2, o3=o3)
    if wrist:
        return _core.SphericalGeometry(**fields, u=_vector(_unit_normal(poe.axes[5])))
    return _core.PointGeometry(**fields)


def _general_position(poe, c: Array) -> tuple[_core.TwoAngleSystem, tuple, tuple]:
    """Axes 1-3 general: two equations in q1 and q3 alone; the closest points ``o2, o3`` of axes 2, 3.

    With ``y = e1^-1 G c`` (q1) and ``x = e3 c`` (q3), ``e2 x = y`` keeps the height along
    axis 2 and the distance to a point ``o2`` of it: ``h2 . (y - o2) = h2 . (x - o2)`` and
    ``|y - o2|^2 = |x - o2|^2``, each first order in its angle.
    """
    h, p = poe.axes, poe.points
    o2, o3 = closest_points(p[1], h[1], p[2], h[2])
    height = trig_coeffs(_vector(h[1]), _vector(h[2]), _vector(c - o3))
    distance = trig_coeffs(_vector(2.0 * (o3 - o2)), _vector(h[2]), _vector(c - o3))
    Q = np.array([[height[1], height[2]], [distance[1], distance[2]]])
    f = (height[0] + float(h[1] @ (o3 - o2)),
         distance[0] + float((o3 - o2) @ (o3 - o2) + (c - o3) @ (c - o3)))
    return _two_angle_system(Q, f), _vector(o2), _vector(o3)


class ClosedFormSolver:
    """Closed-form IK of one chain, with everything that depends only on the chain cached.

    Build it with :func:`closed_form_solver` (memoised per chain).
    """

    def __init__(self, chain: Chain, plan: SolverPlan) -> None:
        self.chain = chain
        self.structure: ArmStructure = plan.structure
        poe = plan.poe
        kind = plan.structure.kind
        # Over-determined chains (fewer than 6 joints) must be checked by FK; for 6 joints
        # every subproblem checks its own existence, so the flags are exact.
        verify, polish = chain.n < 6, False
        #: The case solver's constants (one of the case geometries of :mod:`armkit.ik.cases`).
        self.geometry: CaseGeometry
        if kind in ("spherical-wrist", "spherical-base"):
            self.geometry = point_geometry(poe, plan.case, plan.point, plan.point2, wrist=True)
            polish = plan.case == "general-123"  # a quartic: polished on the full pose and checked by FK
        elif kind == "three-parallel" and plan.case == "parallel-123":
            self.geometry = self._parallel_base(poe)
            polish = not self.geometry.rank1
        elif kind == "three-parallel":
            self.geometry = self._three_parallel(poe)
            polish = not self.geometry.rank1
        elif kind == "general-6r":
            poe, shift = _general_formulation(chain, poe)
            self.geometry = _core.GeneralGeometry(case_chain(poe), shift)
            verify = polish = True
        else:
            self.geometry = self._planar(poe)
        size = 1.0 + max(np.abs(poe.points).max(), np.abs(poe.M[:3, 3]).max())
        M_inv = np.eye(4)
        M_inv[:3, :3] = poe.M[:3, :3].T
        M_inv[:3, 3] = -poe.M[:3, :3].T @ poe.M[:3, 3]
        #: Candidates per pose: 8; 2 for SCARA and planar arms, 16 for a general 6R arm.
        self.k = self.geometry.k
        #: The compiled per-pose loop's view of this solver (``_core.ClosedForm``; it holds
        #: copies of the chain and the geometry, so it lives on its own).
        self.core = _core.ClosedForm(chain._core, self.geometry,
                                     np.ascontiguousarray(poe.index, np.int64),
                                     np.ascontiguousarray(poe.sign, np.float64), M_inv, bool(poe.inverted),
                                     self.k, verify or polish, polish, CANDIDATE_TOLERANCE * size)

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

    # ------------------------------------------------------------ per case
    @staticmethod
    def _three_parallel(poe) -> _core.ThreeParallelGeometry:
        """Axes 2-4 parallel to ``h``: two equations in ``q1, q5``; ``p5, p6``: the closest
        points of axes 5 and 6."""
        h_all, p = poe.axes, poe.points
        h = h_all[1]
        p5, p6 = closest_points(p[4], h_all[4], p[5], h_all[5])
        # right-hand sides h . R(h5, q5) v = const + c cos q5 + d sin q5, for v = h6, p6 - p5
        rows = [trig_coeffs(_vector(h), _vector(h_all[4]), _vector(v)) for v in (h_all[5], p6 - p5)]
        Q = np.array([[r[1], r[2]] for r in rows])
        f = (rows[0][0], rows[1][0] + float(h @ (p5 - p[0])))
        # values of q5 that turn axis 6 parallel to h (a UR-like wrist singularity)
        q5_aligned = []
        for side in (1.0, -1.0):
            angles, ok, _ = sp4(_vector(h), _vector(h_all[5]), _vector(h_all[4]), side)
            q5_aligned += [angles[i] for i in range(2) if ok[i]]
        b_aligned = float(np.linalg.norm(np.cross(h_all[4], h))
                          * np.linalg.norm(np.cross(h_all[4], h_all[5])))
        # q5 near an aligned wrist is refined from sines, so its cosine equation must not snap
        return _core.ThreeParallelGeometry(case_chain(poe), _two_angle_system(Q, f, snap_t2=False),
                                           hp=_vector(h), u=_vector(_unit_normal(h)), p5=_vector(p5),
                                           p6=_vector(p6), q5_aligned=[float(x) for x in q5_aligned],
                                           b_aligned=b_aligned)

    @staticmethod
    def _parallel_base(poe) -> _core.ParallelBaseGeometry:
        """Axes 1-3 parallel to ``h``: two equations in ``q6, q4``; ``o4, o5, o6``: points
        of axes 4-6 (``o4, o5`` closest to each other)."""
        h_all, p = poe.axes, poe.points
        h = h_all[0]
        o4, o5 = closest_points(p[3], h_all[3], p[4], h_all[4])
        o6 = closest_points(p[4], h_all[4], p[5], h_all[5])[1]
        rows = [trig_coeffs(_vector(h), _vector(h_all[3]), _vector(v)) for v in (h_all[4], o5 - o4)]
        Q = np.array([[r[1], r[2]] for r in rows])
        f = (rows[0][0], rows[1][0] + float(h @ o4))
        return _core.ParallelBaseGeometry(case_chain(poe), _two_angle_system(Q, f), hp=_vector(h),
                                          u=_vector(_unit_normal(h)), o4=_vector(o4), o5=_vector(o5),
                                          o6=_vector(o6))

    @staticmethod
    def _planar(poe) -> _core.PlanarGeometry:
        """SCARA / planar: ``y`` a point moved by the first two revolute joints only."""
        rev = [j for j in range(poe.n) if not poe.prismatic[j]]
        pri = [j for j in range(poe.n) if poe.prismatic[j]]
        h = poe.axes[rev[0]]
        u = _unit_normal(h)
        y = poe.points[rev[2]] if len(rev) == 3 else poe.points[rev[1]] + u
        return _core.PlanarGeometry(case_chain(poe), hp=_vector(h), u=_vector(u), y=_vector(y), revolute=rev,
                                    prismatic_joint=pri[0] if pri else -1)


#: Configurations at which :func:`_general_formulation` compares the loops.
_FORMULATION_SAMPLES = 12
#: A loop whose raw candidates come within this [rad] of every sample's generating
#: configuration is taken without trying the others (Newton finishes such candidates).
_GOOD_LOOP = 1e-8


def _general_formulation(chain: Chain, poe):
    """The chain (``poe`` or ``poe.reversed()``) and the loop's first joint (``shift``, 0-5)
    on which the general 6R solver is best conditioned for this arm.

    The elimination keeps three consecutive joints of the loop and eliminates the other
    three; which ones decides the conditioning. An arm with parallel or meeting axes (many
    zero DH entries) degenerates in some loops and not in others, and an arm near a Pieper
    class loses digits in one order and far fewer in another (a PUMA with axes moved by
    1e-6: raw candidates ~1e-4 off in chain order, ~1e-8 reversed). The loops are run, once
    per arm, on the poses of ``_FORMULATION_SAMPLES`` seeded random configurations; the first
    within ``_GOOD_LOOP`` of every generating configuration is taken (a generic arm's first),
    else the one that comes closest (worst sample, then mean), ties to the first tried.
    """
    from armkit.kinematics import fk

    rng = np.random.default_rng(0)
    q = rng.uniform(-np.pi, np.pi, (_FORMULATION_SAMPLES, 6))
    T = fk(chain, q)
    scores, loops = [], []
    for candidate in (poe, poe.reversed()):
        M_inv = np.linalg.inv(candidate.M)
        for shift in range(6):
            geometry = _core.GeneralGeometry(case_chain(candidate), shift)
            errors = []
            for q_user, T_user in zip(q, T, strict=True):
                G = (np.linalg.inv(T_user) if candidate.inverted else T_user) @ M_inv
                R, t = np.ascontiguousarray(G[:3, :3]), np.ascontiguousarray(G[:3, 3])
                found, valid, _ = solve_pose(geometry, R, t)
                q_int = candidate.sign * q_user[candidate.index]
                gaps = np.abs(np.angle(np.exp(1j * (found[valid] - q_int)))).max(axis=1, initial=0.0)
                errors.append(gaps.min(initial=np.pi))
            scores.append((max(errors), float(np.mean(errors))))
            loops.append((candidate, shift))
            if scores[-1][0] <= _GOOD_LOOP:
                return loops[-1]
    return loops[min(range(len(loops)), key=scores.__getitem__)]


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
    plan = plan_closed_form(chain)
    if not plan.structure.closed_form:
        return NoClosedFormError(f"no closed-form IK for this chain: {plan.structure.description}")
    return ClosedFormSolver(chain, plan)


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
