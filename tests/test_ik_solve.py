"""Robot.ik and the IK dispatcher: seed cases, round trips on every built-in, batches, errors."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import assert_transform_close, core_internals
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit
from armkit.chain import DHRow
from armkit.errors import InputError, JointLimitError, NoClosedFormError, UnreachableError
from armkit.ik import IKSolutionsBatch, closed_form_solver, ik_solutions
from armkit.ik.pipeline import Found
from armkit.ik.results import residuals
from armkit.spatial import matrix_from_axis_angle, matrix_from_euler, rotation_angle_between, transform_from

CLOSED_FORM = ["probot-anno", "zju-i", "puma560", "ur5", "stanford", "grb400-scara"]
HALF_PI = np.pi / 2
#: The report prints its solutions with six significant digits.
REPORT_DIGITS = 5e-6


def pose(position, angles):
    return transform_from(matrix_from_euler(angles, "xyz-fixed"), position)


def joint_difference(robot, a, b):
    """``a - b`` with revolute differences taken modulo 2 pi, ``(..., n)``."""
    d = np.asarray(a) - np.asarray(b)
    return np.where(robot.chain.prismatic, d, (d + np.pi) % (2 * np.pi) - np.pi)


def contains(robot, solutions, q, atol=1e-7):
    return bool(np.any(np.abs(joint_difference(robot, solutions, q)).max(axis=-1) < atol))


# ------------------------------------------------------------------ report 000
REPORT_CASES = [
    (pose([0.2, 0.2, 0.2007], [HALF_PI, -HALF_PI, 0]),
     [[0.943488, -0.924743, -0.347274, -2.17673, 0.173647, 2.89722],
      [0.943488, -0.924743, -0.347274, 0.964865, 2.96795, -0.244375],
      [-2.1981, 0.924743, 3.48887, 0.964865, 0.173647, 2.89722],
      [-2.1981, 0.924743, 3.48887, -2.17673, 2.96795, -0.244375]], 4),
    (pose([0.15, 0.2, 0.2007], [0, 0, 0]),
     [[1.03907, -1.00894, -0.0831629, -0.585271, -0.408274, 1.31351],
      [-2.10252, 1.00894, 3.22476, 2.55632, -0.408274, 1.31351]], 4),
    (pose([0.3, 0, 0.122], [HALF_PI, 0, 0]), [[0, -1.11165, -0.0152543, 0, 1.1269, 0]], None),
]


@pytest.mark.parametrize(("T", "listed", "count"), REPORT_CASES)
def test_report_000_ik_cases(T, listed, count):
    robot = armkit.load("probot-anno")
    found = robot.ik(T, all_solutions=True)
    for q in listed:
        assert contains(robot, found, q, atol=REPORT_DIGITS), q
    if count is not None:
        assert found.shape == (count, 6)
    assert robot.within_limits(found).all()
    assert_transform_close(robot.fk(found), np.broadcast_to(T, (len(found), 4, 4)), 1e-9, 1e-9)


def test_report_000_first_case_has_eight_solutions_in_all():
    robot = armkit.load("probot-anno")
    every = ik_solutions(robot.chain, REPORT_CASES[0][0])
    assert len(every.q) == 8 and every.within_limits.sum() == 4
    assert np.all(every.position_error < 1e-12) and np.all(every.orientation_error < 1e-12)
    np.testing.assert_array_equal(robot.ik(REPORT_CASES[0][0], all_solutions=True, within_limits=False),
                                  every.q)


# ------------------------------------------------------------------ round trips
@pytest.mark.parametrize("name", CLOSED_FORM)
def test_round_trip_all_solutions(name):
    robot = armkit.load(name)
    for q in robot.random_q(15, rng=42):
        T = robot.fk(q)
        found = robot.ik(T, all_solutions=True)
        assert contains(robot, found, q), (q, found)
        assert robot.within_limits(found).all()
        assert_transform_close(robot.fk(found), np.broadcast_to(T, (len(found), 4, 4)), 1e-9, 1e-9)
        nearest = robot.ik(T, near=q)
        assert np.abs(joint_difference(robot, nearest, q)).max() < 1e-7


def test_round_trip_panda_numeric_near_a_seed():
    panda = armkit.load("panda")
    rng = np.random.default_rng(3)
    for q in panda.random_q(10, rng=rng):
        T = panda.fk(q)
        found = panda.ik(T, near=q + rng.normal(0, 0.3, 7), rng=0)
        assert found.shape == (7,) and panda.within_limits(found)
        assert_transform_close(panda.fk(found), T, 1e-9, 1e-9)


@settings(max_examples=25, deadline=None)
@given(st.sampled_from(CLOSED_FORM), st.integers(0, 2**32 - 1))
def test_hypothesis_round_trip_returns_the_configuration_itself(name, seed):
    robot = armkit.load(name)
    q = robot.random_q(rng=seed)
    T = robot.fk(q)
    nearest = robot.ik(T, near=q)
    assert_transform_close(robot.fk(nearest), T, 1e-9, 1e-9)
    assert np.abs(joint_difference(robot, nearest, q)).max() < 1e-7  # at singular poses too


@settings(max_examples=20, deadline=None)
@given(st.floats(-0.7, 0.7), st.floats(-1.0, 1.0), st.floats(-0.5, 0.5), st.floats(-2.0, 2.0),
       st.floats(-2.0, 2.0))
def test_hypothesis_wrist_singularity_is_answered_with_a_family(q1, q2, q3, q4, q6):
    robot = armkit.load("puma560")
    q = np.array([q1, q2, q3, q4, 0.0, q6])
    T = robot.fk(q)
    found = ik_solutions(robot.chain, T, near=q)
    assert found.family.any()
    assert_transform_close(robot.fk(found.q), np.broadcast_to(T, (len(found.q), 4, 4)), 1e-9, 1e-9)
    # the family member with q5 = 0 has the same q4 + q6; the one nearest to q is q itself
    # when q is inside the limits (the ranges drawn here reach beyond them: a family member
    # that starts inside the limits is not moved out of them)
    singular = found.family & (np.abs(found.q[:, 4]) < 1e-7)
    sums = found.q[singular, 3] + found.q[singular, 5] - (q4 + q6)
    assert np.any(np.abs((sums + np.pi) % (2 * np.pi) - np.pi) < 1e-7)
    if robot.within_limits(q):
        assert np.abs(joint_difference(robot, found.q[0], q)).max() < 1e-7


# ------------------------------------------------------------------ batches
@pytest.mark.parametrize("name", ["probot-anno", "ur5", "stanford"])
def test_batch_equals_one_at_a_time(name):
    robot = armkit.load(name)
    q = robot.random_q(12, rng=5)
    T = robot.fk(q)
    near = robot.random_q(12, rng=6)
    batch = robot.ik(T, near=near)
    assert batch.shape == (12, robot.n)
    one_at_a_time = [robot.ik(t, near=s) for t, s in zip(T, near, strict=True)]
    np.testing.assert_array_equal(batch, np.stack(one_at_a_time))
    every = robot.ik(T, all_solutions=True)
    assert isinstance(every, list) and len(every) == 12
    for found, t in zip(every, T, strict=True):
        np.testing.assert_array_equal(found, robot.ik(t, all_solutions=True))


def test_numeric_batch_equals_one_at_a_time():
    panda = armkit.load("panda")
    q = panda.random_q(3, rng=8)
    T = panda.fk(q)
    batch = panda.ik(T, near=q + 0.05, rng=2)
    assert batch.shape == (3, 7)
    for found, t, s in zip(batch, T, q + 0.05, strict=True):
        np.testing.assert_array_equal(found, panda.ik(t, near=s, rng=2))
        assert_transform_close(panda.fk(found), t, 1e-9, 1e-9)


def test_near_picks_the_closest_solution_by_weighted_distance():
    robot = armkit.load("probot-anno")
    T = REPORT_CASES[0][0]
    every = robot.ik(T, all_solutions=True)
    for target in every:
        np.testing.assert_allclose(robot.ik(T, near=target + 0.01), target, atol=1e-12)
    distance = np.linalg.norm(every - every[2], axis=-1)
    np.testing.assert_allclose(robot.ik(T, all_solutions=True, near=every[2]), every[np.argsort(distance)])


def test_revolute_angles_are_wrapped_into_the_limits():
    robot = armkit.load("panda")  # the Panda's joint 6 limits are [-0.0175, 3.7525]
    q = np.array([0.2, 0.3, -0.1, -1.5, 0.4, 3.5, 0.1])
    found = robot.ik(robot.fk(q), near=q - [0, 0, 0, 0, 0, 2 * np.pi, 0], rng=1)
    assert robot.within_limits(found)


def test_position_only_target_via_mask():
    rows = [DHRow(0, 0, 0.3, 0), DHRow(np.pi / 2, 0, 0, 0), DHRow(0, 0.3, 0, 0),
            DHRow(0, 0.25, 0, 0), DHRow(-np.pi / 2, 0, 0.1, 0)]
    robot = armkit.Robot.from_dh(rows, "modified", name="5R")
    T = robot.fk([0.3, 0.2, -0.4, 0.5, 0.1])
    T[:3, :3] = np.eye(3)
    q = robot.ik(T, mask=[1, 1, 1, 0, 0, 0], rng=0)
    np.testing.assert_allclose(robot.fk(q)[:3, 3], T[:3, 3], atol=1e-9)


# ------------------------------------------------------------------ bad input
def test_non_rigid_matrix_and_nan():
    robot = armkit.load("probot-anno")
    T = robot.fk(np.zeros(6))
    with pytest.raises(InputError, match="rotation part is not a rotation matrix"):
        robot.ik(T * [[1.1], [1], [1], [1]])
    T[0, 3] = np.nan
    with pytest.raises(InputError, match="NaN"):
        robot.ik(T)
    with pytest.raises(InputError, match="NaN"):
        robot.ik(T, all_solutions=True)
    with pytest.raises(InputError, match="NaN"):
        robot.ik(np.stack([robot.fk(np.zeros(6)), T]))  # a batch: checked by the core, then explained
    with pytest.raises(InputError, match=r"expected shape \(\.\.\., 4, 4\)"):
        robot.ik(np.eye(3))


def test_pose_out_of_reach_says_how_far_the_closest_pose_is():
    robot = armkit.load("probot-anno")
    T = pose([2.0, 0.0, 0.3], [HALF_PI, 0, 0])
    message = r"out of reach: the closest pose found is [\d.]+ m and"
    with pytest.raises(UnreachableError, match=message) as info:
        robot.ik(T)
    reach = 0.225 + 0.2289 + 0.055
    assert 2.0 - reach - 0.2 < info.value.position_error < 2.0 - reach + 0.2
    with pytest.raises(UnreachableError, match="pose 1 of 2: the target pose is out of reach"):
        robot.ik(np.stack([robot.fk(np.zeros(6)), T]))


def test_numeric_pose_out_of_reach():
    panda = armkit.load("panda")
    with pytest.raises(UnreachableError, match="no solution found by numeric IK .* the closest "
                                               "pose found is [\\d.]+ m and"):
        panda.ik(pose([1.5, 0, 0.3], [0, 0, 0]), max_restarts=2)


def test_reachable_only_outside_the_limits():
    source = armkit.load("probot-anno")
    narrow = armkit.Robot.from_dh(source.dh.rows, "modified", tool_rows=source.dh.tool_rows,
                                  limits=[(-0.1, 0.1)] * 6)
    T = narrow.fk(np.full(6, 0.5))
    with pytest.raises(JointLimitError, match="reachable, but only outside the joint limits"):
        narrow.ik(T)
    with pytest.raises(JointLimitError, match="outside the limits with within_limits=False or "
                                              "'armkit ik --outside'"):
        narrow.ik(T, all_solutions=True)
    assert contains(narrow, narrow.ik(T, all_solutions=True, within_limits=False), np.full(6, 0.5))


def test_all_solutions_of_a_chain_without_closed_form():
    panda = armkit.load("panda")
    with pytest.raises(NoClosedFormError, match="numeric IK returns one solution per seed: solve "
                                                r"once per seed configuration, near=q_seed or "
                                                r"'armkit ik --near Q\.\.\.'"):
        panda.ik(panda.fk(np.zeros(7)), all_solutions=True)
    with pytest.raises(NoClosedFormError, match="a task mask needs the numeric solver"):
        armkit.load("ur5").ik(np.eye(4), all_solutions=True, mask=[1, 1, 1, 0, 0, 0])


def test_bad_near_and_weights():
    robot = armkit.load("ur5")
    T = robot.fk(np.zeros(6))
    with pytest.raises(InputError, match=r"near: expected 6 joint values, got 3 \(UR5 has 6 joints\)"):
        robot.ik(T, near=[0, 0, 0])
    with pytest.raises(InputError, match=r"near: expected 6 finite joint values"):
        ik_solutions(robot.chain, T, near=[0, 0, 0])
    with pytest.raises(InputError, match=r"near: shape \(3, 6\) for target poses of shape \(2, 4, 4\)"):
        robot.ik(np.stack([T, T]), near=np.zeros((3, 6)))
    with pytest.raises(InputError, match=r"near: shape \(3, 6\) does not match 2 target poses"):
        ik_solutions(robot.chain, np.stack([T, T]), near=np.zeros((3, 6)))
    with pytest.raises(InputError, match="weights: expected 6 positive numbers"):
        robot.ik(T, weights=[1, 1, 1, 1, 1, -1])
    # a float64 array says the same as a list (robot.ik: in the robot's words)
    for bad in (np.array([0, 0, np.nan, 0, 0, 0]), [0, 0, np.nan, 0, 0, 0]):
        with pytest.raises(InputError, match=r"near: expected finite joint values, got nan at index 2"):
            robot.ik(T, near=bad)
        with pytest.raises(InputError, match=r"near: expected 6 finite joint values"):
            ik_solutions(robot, T, near=bad)
    with pytest.raises(InputError, match="weights: expected 6 positive numbers"):
        robot.ik(T, all_solutions=True, weights=np.array([1, 1, 1, 1, 0.0, 1]))
    with pytest.raises(InputError, match="weights: expected 6 positive numbers"):
        robot.ik(T, all_solutions=True, weights=np.array([1, 1, 1, 1, np.inf, 1]))


def _residuals(robot, q, T):
    """The compiled residuals of candidates ``q`` ``(N, k, n)`` of targets ``T`` ``(N, 4, 4)``."""
    errors = residuals(T[:, None], robot.fk(q))
    return errors[..., 0], errors[..., 1]


def rank(solver, found, poses, near, weights, within_limits):
    """The core's ranking stage on ``found`` (in place)."""
    poses = np.ascontiguousarray(poses, dtype=np.int64)
    core_internals().rank(solver.core, poses, near, weights, within_limits, *found)


def test_rough_candidates_are_refined_on_their_branch():
    robot = armkit.load("ur5")
    q_true = np.array([[0.3, -1.0, 1.2, 0.4, 0.9, -0.5], [2.0, -2.0, -1.0, 1.0, -1.0, 0.5]])
    T = robot.fk(q_true)
    found = Found.empty(2, 1, 6)
    found.q[...] = q_true[:, None, :] + 1e-7  # one candidate per target
    found.valid[...] = [[True], [False]]
    position_error, orientation_error = _residuals(robot, found.q, T)
    assert np.all(position_error > 1e-8)
    found.position_error[...], found.orientation_error[...] = position_error, orientation_error
    core_internals().verify_candidates(closed_form_solver(robot.chain).core, T, *found)
    assert found.position_error[0, 0] < 1e-12 and found.orientation_error[0, 0] < 1e-12
    np.testing.assert_allclose(robot.fk(found.q[0, 0]), T[0], atol=1e-12)
    assert np.abs(found.q[0, 0] - q_true[0]).max() < 1e-6
    np.testing.assert_array_equal(found.q[1, 0], q_true[1] + 1e-7)  # not a candidate: left alone


@pytest.mark.parametrize("name", ["probot-anno", "ur5", "grb400-scara"])
def test_residuals_agree_with_fk_and_rotation_angle(name):
    robot = armkit.load(name)
    q = robot.random_q((4, 3), rng=21)
    T = robot.fk(robot.random_q(4, rng=22))  # unrelated targets: errors up to pi
    position_error, orientation_error = _residuals(robot, q, T)
    F = robot.fk(q)
    np.testing.assert_allclose(position_error, np.linalg.norm(F[..., :3, 3] - T[:, None, :3, 3], axis=-1),
                               rtol=1e-12, atol=1e-15)
    # Both are atan2(|2 sin(angle) axis|, trace - 1) of products of the same rotations: they
    # differ by rounding only, about 1e-15 rad, also near pi (the arcsine of the chord
    # used before lost half the digits there and needed 1e-7).
    np.testing.assert_allclose(orientation_error, rotation_angle_between(F, T[:, None]), rtol=0, atol=1e-14)
    tiny = robot.fk(q[:, 0]) @ transform_from(matrix_from_euler([1e-11, 0, 0], "xyz-fixed"), [0, 0, 0])
    _, small = _residuals(robot, q[:, :1], tiny)
    np.testing.assert_allclose(small, 1e-11, rtol=1e-4)  # accurate near zero
    for distance in (0.0, 1e-9, 1e-6):  # and near a half turn, about a general axis
        turned = robot.fk(q[:, 0]) @ transform_from(
            matrix_from_axis_angle((np.pi - distance) * np.array([0.6, 0.8, 0.0])), [0, 0, 0])
        _, large = _residuals(robot, q[:, :1], turned)
        np.testing.assert_allclose(large, np.pi - distance, rtol=0, atol=1e-13)


@pytest.mark.parametrize("name", ["probot-anno", "ur5", "puma560", "grb400-scara"])
def test_reported_residuals_are_those_of_one_configuration_fk_to_the_last_bit(name):
    # the core verifies a pose's candidates in FK blocks; each residual must be the one the
    # one-configuration FK gives (the same operations in the same order), not merely close
    robot = armkit.load(name)
    q = robot.random_q(40, rng=23)
    q[:10, min(4, robot.n - 1)] = 0.0  # some at a singular wrist: families walked, then verified again
    for T in robot.fk(q):
        found = ik_solutions(robot, T)
        assert len(found.q) > 0
        F = np.stack([robot.fk(row) for row in found.q])
        expected = residuals(np.broadcast_to(T, F.shape), F)
        np.testing.assert_array_equal(found.position_error, expected[:, 0])
        np.testing.assert_array_equal(found.orientation_error, expected[:, 1])


@pytest.mark.parametrize("name", ["probot-anno", "ur5"])
def test_batches_equal_one_at_a_time(name):
    """One pose goes through reused buffers, a batch through fresh ones: the same answers."""
    robot = armkit.load(name)
    count = 40
    T = robot.fk(robot.random_q(count, rng=31))
    near = robot.random_q(count, rng=32)
    picked = robot.ik(T, near=near)
    found = ik_solutions(robot.chain, T, near=near)
    assert isinstance(found, IKSolutionsBatch) and len(found) == count
    every = robot.ik(T, all_solutions=True, near=near)
    singles = [robot.ik(T[i], all_solutions=True, near=near[i]) for i in range(count)]
    for i in range(count):
        np.testing.assert_allclose(picked[i], robot.ik(T[i], near=near[i]), rtol=0, atol=1e-12)
        one = ik_solutions(robot.chain, T[i], near=near[i])
        for field in ("q", "position_error", "orientation_error"):
            np.testing.assert_allclose(getattr(found[i], field), getattr(one, field), rtol=0, atol=1e-12)
        for field in ("within_limits", "family"):
            np.testing.assert_array_equal(getattr(found[i], field), getattr(one, field))
        np.testing.assert_allclose(every[i], singles[i], rtol=0, atol=1e-12)  # earlier results intact
    assert [len(s.q) for s in found[:3]] == found.counts[:3].tolist()
    # a batch of one pose is a batch: its answers are not overwritten by later calls either
    first, first_all = robot.ik(T[:1], near=near[:1]), robot.ik(T[:1], all_solutions=True, near=near[:1])
    kept, kept_all = first.copy(), [q.copy() for q in first_all]
    robot.ik(T[1:2], near=near[1:2]), robot.ik(T[1:2], all_solutions=True, near=near[1:2])
    robot.ik(T[1], all_solutions=True)
    np.testing.assert_array_equal(first, kept)
    np.testing.assert_array_equal(first_all[0], kept_all[0])


def test_family_flag_survives_refinement():
    """A singular representative first found rough, then refined, is still flagged a family."""
    robot = armkit.load("puma560")
    q_true = np.array([0.2, -0.4, 0.3, 0.0, 0.0, 0.5])  # q5 = 0: wrist singularity
    T = robot.fk(q_true)[None]
    found = Found.empty(1, 1, 6)
    found.q[...] = q_true + 1e-7
    found.valid[...], found.family[...] = True, True
    found.position_error[...], found.orientation_error[...] = _residuals(robot, found.q, T)
    solver = closed_form_solver(robot.chain)
    rank(solver, found, np.array([0]), np.zeros(6), np.ones(6), True)
    assert not found.keep[0, 0]  # 1e-7 away: not kept yet
    core_internals().verify_candidates(solver.core, T, *found)
    rank(solver, found, np.array([0]), None, None, True)  # None: zeros and ones
    assert found.keep[0, 0] and found.family[0, 0]


def test_ranking_sorts_usable_candidates_first_nearest_first():
    """The core's ranking: kept (residual <= 1e-9) and inside the limits first, by weighted distance."""
    robot = armkit.load("puma560")
    solver = closed_form_solver(robot.chain)
    q = robot.random_q(4, rng=5)
    found = Found.empty(1, 4, 6)
    found.q[0] = q
    found.q[0, 3, 1] = robot.chain.upper[1] + 0.1  # outside the limits
    found.valid[...], found.family[...] = True, False
    found.errors[...] = 0.0
    found.errors[0, 2] = 2e-9, 0.0  # not kept
    near, weights = q[1] + 0.01, np.array([1.0, 2.0, 1.0, 1.0, 1.0, 0.5])
    rank(solver, found, np.array([0]), near, weights, True)
    kept = [q[0], q[1]]
    distance = [np.linalg.norm(weights * (v - near)) for v in kept]
    assert found.count[0] == 2
    np.testing.assert_array_equal(found.q[0, :2], np.array(kept)[np.argsort(distance)])
    # then the others in their order: the rough one (not kept), the one outside the limits
    assert found.keep[0].tolist() == [True, True, False, True]
    assert found.inside[0].tolist() == [True, True, True, False]
    rank(solver, found, np.array([0]), near, weights, False)  # outside the limits counts too
    assert found.count[0] == 3


@pytest.mark.parametrize("name", ["ur5", "grb400-scara"])
def test_batch_answers_do_not_depend_on_the_thread_count(name):
    """Enough poses for two threads to take half each: the same bits with one or two."""
    robot = armkit.load(name)
    count = 5000
    q = robot.random_q(count, rng=41)
    if robot.chain.n == 6:
        q[::7, 4] = 0.0  # some singular poses (family walk and refinement on the way)
    T = robot.fk(q)
    near = robot.random_q(count, rng=42)
    one, two = (ik_solutions(robot.chain, T, near=near, threads=t) for t in (1, 2))
    for field in ("q", "counts", "within_limits", "family", "position_error", "orientation_error"):
        np.testing.assert_array_equal(getattr(one, field), getattr(two, field))
    np.testing.assert_array_equal(robot.ik(T, near=near, threads=1, within_limits=False),
                                  robot.ik(T, near=near, threads=2, within_limits=False))
    solver = closed_form_solver(robot.chain)
    for a, b in zip(solver.candidates(T, threads=1), solver.candidates(T, threads=2), strict=True):
        np.testing.assert_array_equal(a, b)


def test_a_pose_printed_with_six_decimals_is_solved():
    # A rotation rounded to 6 decimals is projected onto the nearest rotation, not rejected.
    robot = armkit.load("puma560")
    q = np.array([0.3, -0.5, 0.4, 0.2, 0.6, -0.1])
    T = np.round(robot.fk(q), 6)
    found = robot.ik(T, near=q)
    np.testing.assert_allclose(found, q, atol=1e-5)


@pytest.mark.parametrize(("name", "q"), [
    ("puma560", [0.3, -0.5, 0.2, 0.7, 0.0, 0.4]),  # aligned wrist: only q4 + q6 defined
    ("probot-anno", [0.3, -0.5, 0.2, 0.7, np.pi / 2, 0.4]),  # its wrist aligns at q5 = pi/2
    ("ur5", [0.3, -0.5, 0.2, 0.7, 0.0, 0.4]),  # axis 6 parallel to 2-4: a curved family
    ("ur5", [1.3, -1.5, 1.2, -0.7, 0.0, 2.4]),
])
def test_near_picks_the_member_of_a_singular_family_nearest_to_it(name, q):
    """At a singular pose the answer for near=q is q itself, not the family's representative."""
    robot = armkit.load(name)
    q = np.array(q)
    T = robot.fk(q)
    np.testing.assert_allclose(robot.ik(T, near=q), q, rtol=0, atol=1e-9)
    found = ik_solutions(robot.chain, T, near=q)
    assert found.family[0]
    np.testing.assert_allclose(found.q[0], q, rtol=0, atol=1e-9)
    assert found.position_error[0] < 1e-12 and found.orientation_error[0] < 1e-12
    # another reference picks another member, still an exact solution
    other = robot.ik(T, near=q + np.array([0, 0, 0, 0.5, 0, -0.5]))
    np.testing.assert_allclose(robot.fk(other), T, rtol=0, atol=1e-12)
    assert np.abs(other - q).max() > 0.1


@pytest.mark.parametrize(("name", "joint", "singular"), [
    ("probot-anno", 4, np.pi / 2), ("puma560", 4, 0.0), ("ur5", 4, 0.0), ("zju-i", 4, 0.0),
    ("stanford", 4, 0.0),
])
def test_near_returns_the_configuration_itself_at_singular_poses(name, joint, singular):
    """A family reaches q only modulo whole turns (e.g. q4 + pi, q6 + pi on an aligned wrist):
    the nearest member is still q itself, one pose at a time and as all solutions."""
    robot = armkit.load(name)
    q = robot.random_q(60, rng=7)
    q[:, joint] = singular
    T = robot.fk(q)
    nearest = robot.ik(T, near=q)
    assert np.abs(joint_difference(robot, nearest, q)).max() < 1e-7
    for i in range(0, 60, 12):
        nearest_first = robot.ik(T[i], all_solutions=True, near=q[i])[0]
        assert np.abs(joint_difference(robot, nearest_first, q[i])).max() < 1e-7


@pytest.mark.parametrize("name", ["puma560", "stanford", "probot-anno"])
def test_wrist_singular_poses_keep_the_generating_branch_of_joints_1_to_3(name):
    # at q5 = 0 a spherical wrist frees q4 + q6 only: joints 1-3 are fixed by the wrist centre,
    # so the listing must hold the generating (q1, q2, q3). The family walk towards near once
    # projected far points onto another elbow's branch (PUMA: 8 of 300 poses lost it, then 1:
    # a step across a nearly singular direction landed on another elbow's isolated solution)
    robot = armkit.load(name)
    rng = np.random.default_rng(0)
    missed = 0
    for _ in range(300):
        q = robot.random_q(rng=rng)
        q[4] = 0.0
        found = ik_solutions(robot, robot.fk(q), turn_copies=False)
        diff = found.q[:, :3] - q[:3]
        gap = np.where(robot.chain.prismatic[:3], np.abs(diff), np.abs(np.angle(np.exp(1j * diff))))
        missed += gap.max(axis=1).min(initial=np.inf) > 1e-6
    assert missed == 0


@pytest.mark.parametrize("name", ["ur5", "panda"])     # closed form and numeric alike
def test_a_misspelled_keyword_is_an_input_error_naming_it_and_the_valid_ones(name):
    robot = armkit.load(name)
    q = robot.home + 0.1
    T = robot.fk(q)
    with pytest.raises(InputError, match=r"unknown keyword arguments 'nearr' \(did you mean 'near'\?\), "
                                         r"'positon_tolerance' \(did you mean 'position_tolerance'\?\); "
                                         r"expected one of all_solutions, .*max_restarts, near, "):
        robot.ik(T, nearr=q, positon_tolerance=1.0)
    with pytest.raises(InputError, match="unknown keyword argument 'q0'"):      # ik sets q0 from near
        armkit.ik.ik(robot, T, q0=q)
    np.testing.assert_allclose(robot.fk(robot.ik(T, near=q, position_tolerance=1e-10)), T, atol=1e-9)
