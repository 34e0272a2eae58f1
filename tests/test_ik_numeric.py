"""Numeric IK: the per-target pose error and the Levenberg-Marquardt solver."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import assert_transform_close
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit
from armkit.chain import DHRow
from armkit.errors import InputError
from armkit.ik.numeric import (
    NumericIK,
    _cholesky_solve,
    _damped_step,
    _TargetError,
    numeric_ik,
    wrap_into_limits,
)
from armkit.kinematics import pose_error
from armkit.spatial import matrix_from_axis_angle, transform_from


@pytest.mark.parametrize("name", ["panda", "stanford", "probot-anno"])
def test_target_error_matches_pose_error(name):
    robot = armkit.load(name)
    rng = np.random.default_rng(2)
    T_target = robot.fk(robot.random_q(rng=rng))
    error = _TargetError(T_target)
    poses = robot.fk(robot.random_q(50, rng=rng))
    near = T_target.copy()
    near[:3, :3] = near[:3, :3] @ matrix_from_axis_angle([0.0, 1e-9, 0.0])
    half_turn = T_target.copy()
    half_turn[:3, :3] = matrix_from_axis_angle(np.pi * np.array([0.6, 0.0, 0.8])) @ T_target[:3, :3]
    for T in [*poses, T_target, near, half_turn]:
        np.testing.assert_allclose(error(T), pose_error(T_target, T), atol=1e-12)


def _check_solution(robot, T_target, result, tol=1e-9):
    assert result.success
    assert robot.within_limits(result.q)
    assert_transform_close(robot.fk(result.q), T_target, tol, tol)
    assert result.position_error <= tol and result.orientation_error <= tol


def test_panda_random_reachable_poses_within_limits():
    panda = armkit.load("panda")
    targets = panda.fk(panda.random_q(40, rng=7))
    for i, T in enumerate(targets):
        _check_solution(panda, T, numeric_ik(panda.chain, T, rng=i))


@settings(max_examples=15, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_round_trip_on_a_pieper_arm_from_any_seed(seed):
    robot = armkit.load("puma560")
    rng = np.random.default_rng(seed)
    T = robot.fk(robot.random_q(rng=rng))
    _check_solution(robot, T, numeric_ik(robot.chain, T, q0=robot.random_q(rng=rng), rng=seed))


def test_prismatic_joint():
    robot = armkit.load("stanford")
    T = robot.fk(robot.random_q(rng=3))
    _check_solution(robot, T, numeric_ik(robot.chain, T, rng=3))


def test_position_only_target_for_a_five_joint_arm():
    rows = [DHRow(0, 0, 0.3, 0), DHRow(np.pi / 2, 0, 0, 0), DHRow(0, 0.3, 0, 0),
            DHRow(0, 0.25, 0, 0), DHRow(-np.pi / 2, 0, 0.1, 0)]
    robot = armkit.Robot.from_dh(rows, "modified", name="5R")
    target = robot.fk(robot.random_q(rng=4))
    target[:3, :3] = matrix_from_axis_angle([1.0, 2.0, 0.5])  # unreachable orientation
    result = numeric_ik(robot.chain, target, mask=[1, 1, 1, 0, 0, 0], rng=0)
    assert result.success and result.orientation_error == 0.0
    np.testing.assert_allclose(robot.fk(result.q)[:3, 3], target[:3, 3], atol=1e-9)
    full = numeric_ik(robot.chain, target, max_restarts=3, rng=0)
    assert not full.success and full.position_error + full.orientation_error > 1e-3


def test_unreachable_target_reports_the_closest_pose():
    panda = armkit.load("panda")
    target = transform_from(np.eye(3), [2.0, 0.0, 0.5])
    result = numeric_ik(panda.chain, target, max_restarts=5, rng=0)
    assert not result.success
    assert result.restarts == 5
    assert 0.9 < result.position_error < 1.3
    assert panda.within_limits(result.q)
    found = panda.fk(result.q)
    assert np.isclose(np.linalg.norm(found[:3, 3] - target[:3, 3]), result.position_error)


def test_seeded_runs_are_reproducible():
    panda = armkit.load("panda")
    T = panda.fk(panda.random_q(rng=11))
    a = numeric_ik(panda.chain, T, q0=np.zeros(7), rng=5)
    b = numeric_ik(panda.chain, T, q0=np.zeros(7), rng=5)
    np.testing.assert_array_equal(a.q, b.q)
    assert (a.iterations, a.restarts) == (b.iterations, b.restarts)


def test_bad_mask_and_seed():
    panda = armkit.load("panda")
    with pytest.raises(InputError, match="mask: expected 6 values of 0 or 1"):
        numeric_ik(panda.chain, np.eye(4), mask=[1, 1, 1])
    with pytest.raises(InputError, match="mask: expected 6 values"):
        numeric_ik(panda.chain, np.eye(4), mask=[0.5, 1, 1, 1, 1, 1])
    with pytest.raises(InputError, match="q0: expected 7 finite joint values"):
        numeric_ik(panda.chain, np.eye(4), q0=[0.0, np.nan, 0, 0, 0, 0, 0])


def test_a_reused_solver_equals_one_off_calls():
    panda = armkit.load("panda")
    solver = NumericIK(panda.chain)
    seeds = panda.random_q(5, rng=12)
    for i, T in enumerate(panda.fk(panda.random_q(5, rng=13))):
        reused, one_off = solver.solve(T, seeds[i], rng=i), numeric_ik(panda.chain, T, q0=seeds[i], rng=i)
        _check_solution(panda, T, reused)
        np.testing.assert_array_equal(reused.q, one_off.q)
        assert (reused.iterations, reused.restarts) == (one_off.iterations, one_off.restarts)


def test_solutions_with_joints_at_their_limits():
    panda = armkit.load("panda")
    lower, upper = panda.limits.T
    rng = np.random.default_rng(8)
    for k in range(panda.n):
        q = panda.random_q(rng=rng)
        q[k] = lower[k] if k % 2 else upper[k]
        T = panda.fk(q)
        _check_solution(panda, T, numeric_ik(panda.chain, T, q0=panda.random_q(rng=rng), rng=k))


def test_a_seed_outside_the_limits_is_moved_into_them():
    panda = armkit.load("panda")
    T = panda.fk(panda.random_q(rng=14))
    q0 = panda.limits[:, 1] + 0.5
    _check_solution(panda, T, numeric_ik(panda.chain, T, q0=q0, rng=0))


def test_without_limits_a_known_solution_outside_them_is_refined():
    panda = armkit.load("panda")
    q = panda.random_q(rng=15)
    q[3] = 0.3  # beyond joint 4's upper limit -0.0698
    T = panda.fk(q)
    result = numeric_ik(panda.chain, T, q0=q + 1e-4, respect_limits=False, max_restarts=0)
    assert result.success and result.restarts == 0
    assert result.q[3] > panda.limits[3, 1] + 0.2  # stayed near q, outside the limits
    assert_transform_close(panda.fk(result.q), T, 1e-9, 1e-9)


def test_bad_iteration_budget():
    with pytest.raises(InputError, match="max_iterations: expected at least 1 step per attempt, got 0"):
        NumericIK(armkit.load("panda").chain, max_iterations=0)


@pytest.mark.parametrize("name", armkit.builtin_robots())
def test_every_builtin_from_random_seeds(name):
    # near-singular poses included: with too large a damping floor some stalled above 1e-9
    robot = armkit.load(name)
    solver = NumericIK(robot.chain)
    seeds = robot.random_q(60, rng=2)
    for i, T in enumerate(robot.fk(robot.random_q(60, rng=1))):
        _check_solution(robot, T, solver.solve(T, seeds[i], rng=i))


@pytest.mark.parametrize("name", ["panda", "probot-anno", "stanford", "grb400-scara"])
def test_projection_follows_wrap_into_limits(name):
    """NumericIK._project's plain-Python rule equals wrap_into_limits toward the middle of the
    limits, then clamping, for joints outside their limits; joints inside stay put."""
    chain = armkit.load(name).chain
    solver = NumericIK(chain)
    rng = np.random.default_rng(4)
    for q in rng.uniform(chain.lower - 8.0, chain.upper + 8.0, (300, chain.n)):
        q = np.where(np.isfinite(q), q, rng.uniform(-1, 1, chain.n))
        projected, held = solver._project(q)
        outside = (q <= chain.lower) | (q >= chain.upper)
        middle = np.where(np.isfinite(chain.lower + chain.upper), (chain.lower + chain.upper) / 2, 0.0)
        expected = np.clip(wrap_into_limits(chain, q, np.where(outside, middle, q)), chain.lower, chain.upper)
        np.testing.assert_allclose(projected, expected, rtol=0, atol=1e-14)
        at_bound = [i for i in range(chain.n) if not chain.lower[i] < projected[i] < chain.upper[i]]
        assert [i for i, _ in held] == at_bound


def test_panda_success_rate_counted_by_forward_kinematics():
    """The benchmark's setting (bench_ik.py part b), smaller: random reachable poses, one random
    seed each; a pose counts as solved only if FK of the answer is within 1e-6 m and 1e-6 rad
    and the answer is inside the limits, whatever the solver's flag says."""
    panda = armkit.load("panda")
    solver = NumericIK(panda.chain)
    targets, seeds = panda.fk(panda.random_q(500, rng=20)), panda.random_q(500, rng=21)
    solved = 0
    for i, T in enumerate(targets):
        q = solver.solve(T, seeds[i], rng=i).q
        e = pose_error(T, panda.fk(q))
        solved += bool(np.linalg.norm(e[:3]) <= 1e-6 and np.linalg.norm(e[3:]) <= 1e-6
                       and panda.within_limits(q))
    assert solved / len(targets) >= 0.998


def test_non_finite_or_misshaped_target_is_an_input_error():
    panda = armkit.load("panda")
    T = panda.fk(np.zeros(7))
    for bad in (np.nan, np.inf):
        T_bad = T.copy()
        T_bad[1, 3] = bad
        with pytest.raises(InputError, match="T_base_tool: expected a finite 4x4 transform"):
            numeric_ik(panda.chain, T_bad)
    with pytest.raises(InputError, match="T_base_tool: expected a finite 4x4 transform"):
        numeric_ik(panda.chain, T[:3])
    with pytest.raises(InputError, match="q0: expected 7 finite joint values"):
        numeric_ik(panda.chain, T, q0=[0.0, np.inf, 0, 0, 0, 0, 0])


def _step_by_numpy(J, e, rows, sides, damping):
    """The documented damped step, written with NumPy: frozen columns, masked rows, normal equations."""
    J = J.copy()
    frozen = (e * np.isin(np.arange(6), rows)) @ J * sides > 0.0
    J[:, frozen] = 0.0
    J, e = J[rows], e[rows]
    if len(rows) <= J.shape[1]:
        return J.T @ np.linalg.solve(J @ J.T + damping * np.eye(len(rows)), e)
    return np.linalg.solve(J.T @ J + damping * np.eye(J.shape[1]), J.T @ e)


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(4, 8),
       st.sampled_from([(0, 1, 2, 3, 4, 5), (0, 1, 2), (0, 2, 4, 5)]))
def test_compiled_step_equals_the_numpy_formula(seed, n, rows):
    rng = np.random.default_rng(seed)
    J, e = rng.normal(size=(6, n)), rng.normal(size=6)
    rows = np.array(rows, dtype=np.int64)
    sides = rng.choice([-1.0, 0.0, 1.0], n)
    # frozen columns can leave J J^T singular, so the system's condition is about |J|^2 / damping:
    # from 1e-4 on the two solutions agree to 1e-9 whatever the rounding
    damping = 10.0 ** rng.uniform(-4, 0)
    dq = np.empty(n)
    _damped_step(J, e, rows, sides, damping, dq)
    expected = _step_by_numpy(J, e, rows, sides, damping)
    np.testing.assert_allclose(dq, expected, rtol=1e-9, atol=1e-12)


def test_compiled_step_without_damping_on_a_singular_jacobian():
    """Not positive definite: close to the minimum-norm least-squares step (damping 1e-10
    trace(J^T J): about 1e-7 away on these rank-3 Jacobians); all zeros: no step."""
    rng = np.random.default_rng(3)
    rows, sides, dq = np.arange(6), np.zeros(7), np.empty(7)
    for _ in range(20):
        J = rng.normal(size=(6, 3)) @ rng.normal(size=(3, 7))  # rank 3
        e = rng.normal(size=6)
        _damped_step(J, e, rows, sides, 0.0, dq)
        np.testing.assert_allclose(dq, np.linalg.lstsq(J, e, rcond=None)[0], rtol=0, atol=1e-6)
    _damped_step(np.zeros((6, 7)), e, rows, sides, 0.0, dq)
    np.testing.assert_array_equal(dq, np.zeros(7))


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 8))
def test_compiled_cholesky_solve_equals_numpy(seed, k):
    rng = np.random.default_rng(seed)
    M = rng.normal(size=(k, k))
    A, b = M @ M.T + 1e-3 * np.eye(k), rng.normal(size=k)
    x = b.copy()
    assert _cholesky_solve(A.copy(), x)
    np.testing.assert_allclose(A @ x, b, rtol=0, atol=1e-9 * np.linalg.cond(A))
    assert not _cholesky_solve(-A, b.copy())
