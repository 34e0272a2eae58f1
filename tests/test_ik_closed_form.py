"""Closed-form IK: round trips on built-ins and random Pieper arms, singular poses, EAIK."""

import numpy as np
import pytest
from helpers import CLOSED_FORM_ROBOTS, assert_same_as_eaik, joint_distance, random_arm, random_transform
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit
from armkit import _core
from armkit.chain import DHRow, chain_from_dh
from armkit.errors import InputError, NoClosedFormError
from armkit.ik import ik_solutions
from armkit.ik.closed_form import closed_form_ik, closed_form_solver
from armkit.ik.structure import analyze_structure
from armkit.ik.subproblems import sp1, sp4
from armkit.kinematics import fk, singular_values
from armkit.poe import poe_from_chain
from armkit.spatial.rotations import matrix_from_axis_angle, matrix_from_euler

seeds = st.integers(0, 2**32 - 1)


# ------------------------------------------------------------------- helpers
def _random_q(rng, chain, n):
    return rng.uniform(chain.lower, chain.upper, (n, chain.n))


def _assert_round_trip(chain, q, tol=1e-9):
    """Candidates of ``fk(q)`` contain ``q`` and every valid one reproduces the pose to ``tol``.

    A solution reproducing the pose to ``r`` fixes the joints only to about
    ``r / sigma_min`` of the Jacobian at ``q``: near a singular configuration (sigma_min =
    1e-8 happens in random samples) ``q`` and the solution found both reproduce the pose to
    1e-14 and differ by more than 1e-9. The joint tolerance is ``10 r / sigma_min`` within
    ``[1e-9, 1e-6]`` (at a double root the difference is sqrt(eps) ~ 1.5e-8).
    """
    T = fk(chain, q)
    sol = closed_form_ik(chain, T)
    residual = np.abs(fk(chain, sol.q) - T[:, None]).max(axis=(-1, -2))
    assert residual[sol.valid].max() < tol
    r = np.where(sol.valid, residual, 0.0).max(axis=-1) + 1e-16
    q_tol = np.clip(10 * r / singular_values(chain, q)[:, -1], 1e-9, 1e-6)
    found = (joint_distance(chain, sol.q, q[:, None, :]) < q_tol[:, None]) & sol.valid
    assert found.any(axis=-1).all(), f"missed q = {q[~found.any(axis=-1)][0].tolist()}"
    return sol


# -------------------------------------------------------------------- tests
@pytest.mark.parametrize("name", CLOSED_FORM_ROBOTS)
def test_round_trip_builtins(name):
    chain = armkit.load(name).chain
    rng = np.random.default_rng(abs(hash(name)) % 2**32)
    sol = _assert_round_trip(chain, _random_q(rng, chain, 300))
    assert sol.valid.sum(axis=-1).max() <= analyze_structure(chain).max_solutions


@pytest.mark.parametrize("kind", ["spherical-wrist", "spherical-base", "three-parallel"])
@pytest.mark.parametrize("convention", ["standard", "modified"])
@settings(max_examples=15, deadline=None)
@given(seed=seeds)
def test_round_trip_random_pieper_arms(kind, convention, seed):
    rng = np.random.default_rng(seed)
    chain = random_arm(rng, kind, convention)
    assert analyze_structure(chain).kind == kind
    _assert_round_trip(chain, _random_q(rng, chain, 40))


@pytest.mark.parametrize("convention", ["standard", "modified"])
@settings(max_examples=10, deadline=None)
@given(seed=seeds)
def test_round_trip_random_stanford_like_arms(convention, seed):
    rng = np.random.default_rng(seed)
    chain = random_arm(rng, "spherical-wrist", convention, prismatic3=True)
    _assert_round_trip(chain, _random_q(rng, chain, 40))


def test_round_trip_random_scara_and_planar():
    rng = np.random.default_rng(7)
    for kinds in (["revolute", "revolute", "prismatic", "revolute"], ["revolute"] * 3,
                  ["revolute", "prismatic", "revolute"], ["revolute"] * 2):
        for convention in ("standard", "modified"):
            rows = [DHRow(0.0, rng.uniform(0.1, 0.4), rng.uniform(-0.2, 0.2),
                          rng.uniform(-np.pi, np.pi), k) for k in kinds]
            limits = [(-np.pi, np.pi) if k == "revolute" else (-0.2, 0.2) for k in kinds]
            chain = chain_from_dh(rows, convention, limits=limits, T_base=random_transform(rng),
                                  T_tool=random_transform(rng))
            assert analyze_structure(chain).closed_form
            _assert_round_trip(chain, _random_q(rng, chain, 50))


def test_seed_probot_ik_case():
    """Report 000: target [0.2, 0.2, 0.2007] with xyz-fixed [pi/2, -pi/2, 0]."""
    chain = armkit.load("probot-anno").chain
    T = np.eye(4)
    T[:3, :3] = matrix_from_euler([np.pi / 2, -np.pi / 2, 0], "xyz-fixed")
    T[:3, 3] = [0.2, 0.2, 0.2007]
    sol = closed_form_ik(chain, T)
    assert sol.q.shape == (8, 6) and sol.valid.all() and not sol.family.any()
    assert np.abs(fk(chain, sol.q) - T).max() < 1e-12
    listed = np.array([[0.943488, -0.924743, -0.347274, -2.17673, 0.173647, 2.89722],
                       [0.943488, -0.924743, -0.347274, 0.964865, 2.96795, -0.244375],
                       [-2.1981, 0.924743, 3.48887, 0.964865, 0.173647, 2.89722],
                       [-2.1981, 0.924743, 3.48887, -2.17673, 2.96795, -0.244375]])
    distance = joint_distance(chain, sol.q[None], listed[:, None])
    assert (distance.min(axis=1) < 1e-4).all()


def test_batch_shapes_and_single_pose():
    chain = armkit.load("ur5").chain
    q = _random_q(np.random.default_rng(3), chain, 6)
    T = fk(chain, q)
    batch = closed_form_ik(chain, T.reshape(2, 3, 4, 4))
    assert batch.q.shape == (2, 3, 8, 6) and batch.valid.shape == (2, 3, 8)
    single = closed_form_ik(chain, T[4])
    assert single.q.shape == (8, 6)
    np.testing.assert_array_equal(single.valid, batch.valid[1, 1])
    np.testing.assert_allclose(single.q[single.valid], batch.q[1, 1][single.valid], atol=1e-12)


def test_unreachable_pose_has_no_valid_candidate():
    for name in CLOSED_FORM_ROBOTS:
        if name == "stanford":  # candidates ignore limits: its prismatic joint reaches anything
            continue
        chain = armkit.load(name).chain
        T = fk(chain, np.zeros(chain.n))
        T[:3, 3] += [5.0, 5.0, 5.0]
        assert not closed_form_ik(chain, T).valid.any(), name
    scara = armkit.load("grb400-scara").chain
    T = fk(scara, np.array([0.5, 0.5, 0.01, 0.2]))
    T[:3, :3] = T[:3, :3] @ matrix_from_axis_angle([0.1, 0, 0])  # tilt: not a SCARA pose
    assert not closed_form_ik(scara, T).valid.any()


def test_no_closed_form_and_bad_input():
    with pytest.raises(NoClosedFormError, match="7 joints"):
        closed_form_ik(armkit.load("panda").chain, np.eye(4))
    chain = armkit.load("probot-anno").chain
    with pytest.raises(InputError, match="NaN"):
        closed_form_ik(chain, np.full((4, 4), np.nan))
    with pytest.raises(InputError, match="rotation"):
        closed_form_ik(chain, np.diag([2.0, 1.0, 1.0, 1.0]))
    assert closed_form_solver(chain) is closed_form_solver(chain)


# ------------------------------------------------------------ singular poses
def _wrist_singular_q5(chain):
    """The value of joint 5 that turns axis 6 onto axis 4 (SP1 on the axes at q = 0)."""
    poe = poe_from_chain(chain)
    return sp1(*(tuple(v) for v in (poe.axes[5], poe.axes[3], poe.axes[4])))[0]


@pytest.mark.parametrize("name", ["probot-anno", "puma560", "stanford"])
def test_wrist_singularity_returns_family(name):
    chain = armkit.load(name).chain
    q = _random_q(np.random.default_rng(11), chain, 20)
    q[:, 4] = _wrist_singular_q5(chain)
    T = fk(chain, q)
    sol = closed_form_ik(chain, T)
    assert np.abs(fk(chain, sol.q) - T[:, None]).max(axis=(-1, -2))[sol.valid].max() < 1e-12
    # q lies in a family whose representative has the same q1, q2, q3, q5 and q4 = 0
    kept = [0, 1, 2, 4]
    same = joint_distance(chain, sol.q, q[:, None], kept) < 1e-9
    assert (same & sol.family & sol.valid).any(axis=-1).all()
    assert np.all(sol.q[sol.family][:, 3] == 0.0)


def _plan_point(chain):
    from armkit.ik.structure import plan_closed_form
    return plan_closed_form(chain).point


def test_shoulder_singularity_returns_family():
    """PROBOT Anno with the wrist centre on axis 1: q1 is free, nothing else is lost."""
    chain = armkit.load("probot-anno").chain
    poe = poe_from_chain(chain)
    rng = np.random.default_rng(5)
    R = matrix_from_axis_angle(0.7 * np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8]))
    G = np.eye(4)
    G[:3, :3] = R
    G[:3, 3] = poe.points[0] + poe.axes[0] * rng.uniform(0.45, 0.55) - R @ _plan_point(chain)
    T = G @ poe.M
    sol = closed_form_ik(chain, T)
    assert sol.valid.sum() == 4 and (sol.family == sol.valid).all()
    assert np.abs(fk(chain, sol.q) - T).max(axis=(-1, -2))[sol.valid].max() < 1e-12
    # every q1 works: turning joint 1 and re-solving the wrist stays in the family
    assert np.all(sol.q[sol.valid][:, 0] == 0.0)


def _stretched(chain, i, j, k):
    """The value of joint ``j`` that lines up link ``i -> j`` with link ``j -> k`` (points)."""
    poe = poe_from_chain(chain)
    h = poe.axes[j]
    a, b = poe.points[j] - poe.points[i], k - poe.points[j]
    a, b = a - (a @ h) * h, b - (b @ h) * h
    return sp1(tuple(b), tuple(a), tuple(h))[0]


@pytest.mark.parametrize("name", ["probot-anno", "ur5"])
def test_stretched_elbow_gives_merged_double_solution(name):
    chain = armkit.load(name).chain
    poe = poe_from_chain(chain)
    far = _plan_point(chain) if name == "probot-anno" else poe.points[3]
    q = _random_q(np.random.default_rng(2), chain, 10)
    q[:, 2] = _stretched(chain, 1, 2, far)
    sol = _assert_round_trip(chain, q, tol=1e-12)
    if name == "probot-anno":  # axes 1 and 2 meet: both shoulder branches are stretched
        assert (sol.valid.sum(axis=-1) == 4).all()
    else:  # shoulder offset: only the shoulder branch of q is surely stretched
        assert (sol.valid.sum(axis=-1) <= 7).all()


def test_three_parallel_wrist_singularity_returns_family():
    chain = armkit.load("ur5").chain
    q = _random_q(np.random.default_rng(4), chain, 10)
    q[:, 4] = 0.0  # axis 6 parallel to axes 2-4
    T = fk(chain, q)
    sol = closed_form_ik(chain, T)
    assert np.abs(fk(chain, sol.q) - T[:, None]).max(axis=(-1, -2))[sol.valid].max() < 1e-12
    same = joint_distance(chain, sol.q, q[:, None], [0, 4]) < 1e-9
    assert (same & sol.family & sol.valid).any(axis=-1).all()




@pytest.mark.parametrize("name", ["probot-anno", "puma560", "ur5", "zju-i"])
def test_agrees_with_eaik_on_builtins(name):
    chain = armkit.load(name).chain
    assert_same_as_eaik(chain, np.random.default_rng(9).uniform(-np.pi, np.pi, (100, 6)))


@pytest.mark.parametrize("kind", ["spherical-wrist", "spherical-base", "three-parallel"])
@settings(max_examples=8, deadline=None)
@given(seed=seeds)
def test_agrees_with_eaik_on_random_arms(kind, seed):
    rng = np.random.default_rng(seed)
    chain = random_arm(rng, kind, ["standard", "modified"][seed % 2])
    assert_same_as_eaik(chain, rng.uniform(-np.pi, np.pi, (20, 6)))


@pytest.mark.parametrize("offset", [0.0, 1e-12, 1e-9, 1e-6, -1e-6])
def test_ur5_near_q1_half_pi_loses_no_branch(offset):
    """Where roboticstoolbox-python's analytic IK misses branches of UR arms."""
    chain = armkit.load("ur5").chain
    q = np.random.default_rng(8).uniform(-np.pi, np.pi, (40, 6))
    q[:, 0] = np.where(np.arange(40) % 2, np.pi / 2, -np.pi / 2) + offset
    _assert_round_trip(chain, q)
    assert_same_as_eaik(chain, q)


def test_duplicates_are_merged_modulo_two_pi():
    chain = armkit.load("stanford").chain  # joint 3 prismatic: no 2 pi there
    a = np.array([0.1, -0.2, 0.5, np.pi, 0.3, -np.pi + 1e-12])
    q = np.tile(a, (8, 1))
    q[1, 3] = -np.pi  # same angle as pi
    q[2, 2] += 2 * np.pi  # prismatic: a different solution
    q[3, 5] += 1e-6  # a different solution
    q[5, 0] += 2e-10  # within the duplicate tolerance
    valid = np.array([False, True, True, True, True, True, True, True])
    duplicate = np.empty(8, dtype=bool)
    _core.duplicates(q, valid, np.ascontiguousarray(chain.prismatic), duplicate)
    # candidate 0 is invalid, so 1 is the first kept; 4-7 repeat it, 2 and 3 differ
    assert duplicate.tolist() == [False, False, False, False, True, True, True, True]


@pytest.mark.parametrize("name", CLOSED_FORM_ROBOTS)
def test_every_joint_at_a_multiple_of_half_pi(name):
    """Where singularities pile up (stretched elbow + wrist + shoulder): nothing is lost.

    Every valid candidate reproduces the pose to machine precision, and the q that made
    the pose is among the candidates or the pose has a family representative.
    """
    import itertools

    chain = armkit.load(name).chain
    q = np.array(list(itertools.product([0.0, np.pi / 2, -np.pi / 2, np.pi], repeat=chain.n)))
    q[:, chain.prismatic] = 0.5
    T = fk(chain, q)
    sol = closed_form_ik(chain, T)
    assert np.abs(fk(chain, sol.q) - T[:, None]).max(axis=(-1, -2))[sol.valid].max() < 1e-12
    found = ((joint_distance(chain, sol.q, q[:, None]) < 1e-6) & sol.valid).any(axis=-1)
    assert (found | (sol.family & sol.valid).any(axis=-1)).all()
    assert sol.valid.any(axis=-1).all()


def test_skew_wrist_three_parallel_arm_aligned_wrist_family():
    """Axes 2-4 parallel, axes 5 and 6 skew (the quartic path), axis 6 turned onto h."""
    rng = np.random.default_rng(21)
    alpha = [np.pi / 2, 0.0, 0.0, 1.1, 1.1, 0.4]
    a = [0.05, 0.4, 0.35, 0.03, 0.08, 0.0]
    d = [0.3, 0.05, -0.04, 0.1, 0.09, 0.07]
    rows = [DHRow(alpha[i], a[i], d[i], rng.uniform(-1, 1)) for i in range(6)]
    chain = chain_from_dh(rows, "standard")
    assert analyze_structure(chain).kind == "three-parallel"
    assert not closed_form_solver(chain).geometry.rank1  # the quartic path
    poe = poe_from_chain(chain)
    h2, h6, h5 = (tuple(poe.axes[j]) for j in (1, 5, 4))
    aligned = [angle for side in (1.0, -1.0)
               for angle, ok in zip(*sp4(h2, h6, h5, side)[:2], strict=True) if ok]
    q = _random_q(rng, chain, 20)
    q[:, 4] = np.array(aligned)[rng.integers(len(aligned), size=20)]
    T = fk(chain, q)
    sol = closed_form_ik(chain, T)
    assert np.abs(fk(chain, sol.q) - T[:, None]).max(axis=(-1, -2))[sol.valid].max() < 1e-12
    same = joint_distance(chain, sol.q, q[:, None], [0, 4]) < 1e-9
    assert (same & sol.family & sol.valid).any(axis=-1).all()


@pytest.mark.parametrize("name", ["probot-anno", "puma560", "ur5", "zju-i"])
@pytest.mark.parametrize("offset", [1e-12, 1e-10, 1e-8, 1e-6])
def test_near_wrist_singularity_keeps_every_branch(name, offset):
    """q5 just off the wrist singularity: no branch lost, every one reproduces the pose.

    Within 1e-10 of the singularity the pose fixes q4 and q6 only to ~1e-16 / offset, so
    there q is looked for in the joints it does fix (all but q4 and q6); the pose is
    reproduced to 1e-11 (a wrist within 1e-12 of the singularity is answered as the family).
    """
    chain = armkit.load(name).chain
    q = _random_q(np.random.default_rng(6), chain, 30)
    three_parallel = analyze_structure(chain).kind == "three-parallel"
    q[:, 4] = (0.0 if three_parallel else _wrist_singular_q5(chain)) + offset
    if offset >= 1e-8:
        _assert_round_trip(chain, q, tol=1e-11)
        return
    T = fk(chain, q)
    sol = closed_form_ik(chain, T)
    assert np.abs(fk(chain, sol.q) - T[:, None]).max(axis=(-1, -2))[sol.valid].max() < 1e-11
    fixed = [0, 4] if three_parallel else [0, 1, 2, 4]
    found = (joint_distance(chain, sol.q, q[:, None], fixed) < 1e-6) & sol.valid
    assert found.any(axis=-1).all()


@pytest.mark.parametrize("name", ["probot-anno", "ur5", "grb400-scara"])
def test_batches_match_single_poses(name):
    robot = armkit.load(name)
    T = robot.fk(robot.random_q((2, 30), rng=17))  # (2, 30, 4, 4)
    batch = closed_form_ik(robot.chain, T)
    assert batch.q.shape[:2] == (2, 30) and batch.valid.shape == (2, 30, batch.q.shape[2])
    for i, j in ((0, 0), (0, 29), (1, 17)):
        one = closed_form_ik(robot.chain, T[i, j])
        np.testing.assert_array_equal(batch.valid[i, j], one.valid)
        np.testing.assert_allclose(batch.q[i, j][one.valid], one.q[one.valid], rtol=0, atol=1e-12)
        F = fk(robot.chain, batch.q[i, j][batch.valid[i, j]])
        np.testing.assert_allclose(F, np.broadcast_to(T[i, j], F.shape), rtol=0, atol=1e-12)


def test_a_rejected_twin_of_a_valid_candidate_is_not_listed_twice():
    """A random three-parallel arm (seed 898, pose 19, near a fold: smallest singular value
    3e-3): two candidates fail the case's existence test and are twins of two valid ones.
    FK now decides on rejected candidates also beside valid ones; after two Newton steps the
    twins reproduced the pose to 7e-9 only, were kept as solutions and, 1e-8 from their
    valid twins, not recognised as duplicates. Polished to rounding, they are."""
    rng = np.random.default_rng(898)
    chain = random_arm(rng, "three-parallel", "standard")
    q = rng.uniform(-np.pi, np.pi, (20, 6))
    T = fk(chain, q[19])
    sol = closed_form_ik(chain, T)
    ours = sol.q[sol.valid]
    assert len(ours) == 2 and np.abs(fk(chain, ours) - T).max() < 1e-12
    assert len(ik_solutions(chain, T).q) == 2
    assert_same_as_eaik(chain, q)
