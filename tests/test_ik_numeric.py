"""Numeric IK: the Levenberg-Marquardt solver (armkit._core), its damped step, projection and batch."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import assert_transform_close, core_internals
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit
from armkit.chain import DHRow
from armkit.errors import InputError
from armkit.ik.numeric import IKResultBatch, NumericIK, numeric_ik, wrap_into_limits
from armkit.kinematics import pose_error
from armkit.spatial import matrix_from_axis_angle, transform_from


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
    result = numeric_ik(panda.chain, T, q0=q + 1e-4, within_limits=False, max_restarts=0)
    assert result.success and result.restarts == 0
    assert result.q[3] > panda.limits[3, 1] + 0.2  # stayed near q, outside the limits
    assert_transform_close(panda.fk(result.q), T, 1e-9, 1e-9)


def test_bad_iteration_budget():
    with pytest.raises(InputError, match="max_iterations: expected a whole number from 1 to 2147483647, "
                                         "got 0"):
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
    """The core's projection of every step into the limits equals wrap_into_limits toward the
    middle of the limits, then clamping, for joints outside their limits; joints inside stay put;
    the joints it reports at a bound are those at one."""
    chain = armkit.load(name).chain
    solver = NumericIK(chain)
    rng = np.random.default_rng(4)
    for q in rng.uniform(chain.lower - 8.0, chain.upper + 8.0, (300, chain.n)):
        q = np.where(np.isfinite(q), q, rng.uniform(-1, 1, chain.n))
        projected, sides = q.copy(), np.zeros(chain.n)
        core_internals().project(solver._solver, projected, sides)
        held = [(i, float(sides[i])) for i in np.flatnonzero(sides).tolist()]
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


def _free_jacobian(J, e, rows, sides):
    """J's task rows with the columns of joints held at a bound by the gradient zeroed."""
    Jm, em = J[rows].copy(), e[rows]
    frozen = em @ Jm * sides > 0.0
    Jm[:, frozen] = 0.0
    return Jm, em, frozen


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(4, 8),
       st.sampled_from([(0, 1, 2, 3, 4, 5), (0, 1, 2), (0, 2, 4, 5)]))
def test_damped_step_solves_the_damped_normal_equations(seed, n, rows):
    """Whichever system the core solves (m x m when m <= n, else n x n), the step satisfies
    (Jf^T Jf + damping I) dq = Jf^T e for the free columns Jf, and a joint pushed against its
    bound does not move."""
    rng = np.random.default_rng(seed)
    J, e = rng.normal(size=(6, n)), rng.normal(size=6)
    rows = np.array(rows, dtype=np.int64)
    sides = rng.choice([-1.0, 0.0, 1.0], n)
    damping = 10.0 ** rng.uniform(-4, 0)
    dq = np.empty(n)
    core_internals().damped_step(J, e, rows, sides, damping, dq)
    Jf, em, frozen = _free_jacobian(J, e, rows, sides)
    residual = (Jf.T @ Jf + damping * np.eye(n)) @ dq - Jf.T @ em
    np.testing.assert_allclose(residual, 0.0, atol=1e-10 * (1.0 + np.abs(Jf.T @ em).max()))
    np.testing.assert_array_equal(dq[frozen], 0.0)
    # a descent direction of the masked error: the first-order change of E = 1/2 |e|^2 is -e^T Jf dq
    assert em @ Jf @ dq >= 0.0


def test_damped_step_lowers_a_pose_error_like_finite_differences_predict():
    """On a real chain, J from the core's Jacobian: a small step along dq changes the pose error
    as J dq says (finite differences), and the full step lowers |e|."""
    panda = armkit.load("panda")
    rng = np.random.default_rng(6)
    rows, sides, dq = np.arange(6), np.zeros(7), np.empty(7)
    for _ in range(10):
        q = panda.random_q(rng=rng)
        T_target = panda.fk(q + rng.normal(scale=0.05, size=7))
        J = panda.jacobian(q)
        e = pose_error(T_target, panda.fk(q))
        core_internals().damped_step(np.ascontiguousarray(J), e, rows, sides, 1e-9, dq)
        h = 1e-6
        change = (pose_error(T_target, panda.fk(q + h * dq))
                  - pose_error(T_target, panda.fk(q - h * dq))) / (2 * h)
        np.testing.assert_allclose(change, -J @ dq, atol=1e-6)
        assert np.linalg.norm(pose_error(T_target, panda.fk(q + dq))) < 0.1 * np.linalg.norm(e)


def test_damped_step_without_damping_on_a_singular_jacobian():
    """Not positive definite: close to the minimum-norm least-squares step (damping 1e-10
    trace(J^T J): about 1e-7 away on these rank-3 Jacobians); all zeros: no step."""
    rng = np.random.default_rng(3)
    rows, sides, dq = np.arange(6), np.zeros(7), np.empty(7)
    for _ in range(20):
        J = rng.normal(size=(6, 3)) @ rng.normal(size=(3, 7))  # rank 3
        e = rng.normal(size=6)
        core_internals().damped_step(J, e, rows, sides, 0.0, dq)
        np.testing.assert_allclose(dq, np.linalg.lstsq(J, e, rcond=None)[0], rtol=0, atol=1e-6)
    core_internals().damped_step(np.zeros((6, 7)), e, rows, sides, 0.0, dq)
    np.testing.assert_array_equal(dq, np.zeros(7))


def test_solutions_reproduce_the_target_in_roboticstoolbox():
    """Targets from roboticstoolbox-python's Panda FK; its FK of armkit's answers gives them back."""
    rtb = pytest.importorskip("roboticstoolbox")
    theirs = rtb.models.DH.Panda()
    panda = armkit.load("panda")
    q_true = panda.random_q(30, rng=30)
    targets = np.array([theirs.fkine(q).A for q in q_true])
    result = NumericIK(panda.chain).solve_batch(targets, rng=31)
    assert result.success.all()
    for T, q in zip(targets, result.q, strict=True):
        assert_transform_close(theirs.fkine(q).A, T, 1e-9, 1e-9)
        assert panda.within_limits(q)


def _same_batches(a, b):
    for field in ("q", "success", "iterations", "restarts", "position_error", "orientation_error"):
        np.testing.assert_array_equal(getattr(a, field), getattr(b, field))


def test_batch_results_do_not_depend_on_the_thread_count():
    # poses that need restarts (seeds far from the answer, unreachable targets) included;
    # the budget is generous so that no solve stops on time
    panda = armkit.load("panda")
    solver = NumericIK(panda.chain, max_restarts=20, time_budget=60.0)
    targets = panda.fk(panda.random_q(60, rng=40))
    targets[::10, :3, 3] += 1.0  # out of reach: every restart used
    seeds = panda.random_q(60, rng=41)
    one = solver.solve_batch(targets, seeds, rng=42, threads=1)
    assert one.restarts.max() == 20 and one.success.sum() == 54
    for threads in (2, 3, None):
        _same_batches(one, solver.solve_batch(targets, seeds, rng=42, threads=threads))


def test_batch_entries_are_single_solves():
    """Entry 0 is what solve() gives with the same rng; every entry is a valid IKResult."""
    panda = armkit.load("panda")
    solver = NumericIK(panda.chain)
    targets = panda.fk(panda.random_q(8, rng=43))
    seeds = panda.random_q(8, rng=44)
    batch = solver.solve_batch(targets, seeds, rng=7)
    assert isinstance(batch, IKResultBatch) and len(batch) == 8
    single = solver.solve(targets[0], seeds[0], rng=7)
    np.testing.assert_array_equal(batch[0].q, single.q)
    assert (batch[0].iterations, batch[0].restarts) == (single.iterations, single.restarts)
    for i in range(8):
        _check_solution(panda, targets[i], batch[i])
    shared = solver.solve_batch(targets, seeds[3], rng=7)  # one seed (n,) for every target
    _same_batches(shared, solver.solve_batch(targets, np.tile(seeds[3], (8, 1)), rng=7))
    assert solver.solve_batch(np.empty((0, 4, 4))).q.shape == (0, 7)


def test_fixed_rng_reproduces_restarts():
    """Far seeds and a tight iteration budget force restarts; the same rng (an int or a
    Generator in the same state) gives the same restarts and answers, another rng others."""
    panda = armkit.load("panda")
    solver = NumericIK(panda.chain, max_iterations=8)
    targets = panda.fk(panda.random_q(20, rng=45))
    a = solver.solve_batch(targets, rng=3)
    assert a.success.all() and (a.restarts > 0).sum() >= 10
    _same_batches(a, solver.solve_batch(targets, rng=3))
    b = solver.solve_batch(targets, rng=4)
    assert b.success.all() and not np.array_equal(a.restarts, b.restarts)
    g, h = np.random.default_rng(9), np.random.default_rng(9)
    for T in targets[:5]:
        x, y = solver.solve(T, rng=g), solver.solve(T, rng=h)
        np.testing.assert_array_equal(x.q, y.q)
        assert (x.iterations, x.restarts) == (y.iterations, y.restarts)


def test_panda_batch_success_rate_counted_by_forward_kinematics():
    """As the single-solve version, 1000 poses in one batch: every one solved within 1e-6."""
    panda = armkit.load("panda")
    targets, seeds = panda.fk(panda.random_q(1000, rng=22)), panda.random_q(1000, rng=23)
    result = NumericIK(panda.chain).solve_batch(targets, seeds, rng=24)
    e = pose_error(targets, panda.fk(result.q))
    solved = ((np.linalg.norm(e[:, :3], axis=1) <= 1e-6) & (np.linalg.norm(e[:, 3:], axis=1) <= 1e-6)
              & panda.within_limits(result.q))
    assert solved.all() and result.success.all()


def test_bad_batch_inputs_are_input_errors():
    panda = armkit.load("panda")
    solver = NumericIK(panda.chain)
    T = panda.fk(panda.random_q(3, rng=0))
    with pytest.raises(InputError, match=r"T_base_tool: expected finite transforms \(N, 4, 4\), got an array "
                                         r"of shape \(4, 4\)"):
        solver.solve_batch(T[0])
    bad = T.copy()
    bad[1, 0, 3] = np.nan
    with pytest.raises(InputError, match=r"expected finite transforms \(N, 4, 4\), got non-finite values"):
        solver.solve_batch(bad)
    with pytest.raises(InputError, match=r"q0: expected finite joint values \(3, 7\) or \(7,\), got an "
                                         r"array of shape \(2, 7\)"):
        solver.solve_batch(T, np.zeros((2, 7)))
    with pytest.raises(InputError, match=r"q0: expected finite joint values \(3, 7\) or \(7,\), got non-fin"):
        solver.solve_batch(T, np.full((3, 7), np.inf))
    with pytest.raises(InputError, match=r"threads: expected None \(every core\)"):
        solver.solve_batch(T, threads=-1)
    with pytest.raises(InputError, match="T_base_tool: expected transforms"):
        solver.solve_batch("not poses")


def test_bad_rng_and_budgets_are_input_errors():
    panda = armkit.load("panda")
    T = panda.fk(np.zeros(7))
    for rng in (-1, 2**64, "seed"):
        with pytest.raises(InputError, match="rng: expected a seed in"):
            numeric_ik(panda.chain, T, rng=rng)
    with pytest.raises(InputError, match="max_restarts: expected a whole number from 0 to 2147483647, "
                                         "got -1"):
        NumericIK(panda.chain, max_restarts=-1)
    for budget in (-1.0, np.nan):
        with pytest.raises(InputError, match=r"time_budget: expected a number >= 0 \(inf: no bound\)"):
            NumericIK(panda.chain, time_budget=budget)


def test_a_zero_time_budget_stops_after_the_first_attempt():
    panda = armkit.load("panda")
    target = transform_from(np.eye(3), [2.0, 0.0, 0.5])  # out of reach
    result = numeric_ik(panda.chain, target, time_budget=0.0, rng=0)
    assert not result.success and result.restarts == 0


def test_the_same_call_gives_the_same_answer_and_no_clock_cuts_it_short():
    """Restarts are seeded by default and a time budget applies only when one is given."""
    panda = armkit.load("panda")
    for T in panda.fk(panda.random_q(40, rng=3)):
        np.testing.assert_array_equal(panda.ik(T), panda.ik(T))
    assert NumericIK(panda.chain).time_budget is None
    far = transform_from(np.eye(3), [2.0, 0.0, 0.5])       # out of reach: every restart is tried
    first, again = numeric_ik(panda.chain, far), numeric_ik(panda.chain, far)
    assert first.restarts == again.restarts == 100
    np.testing.assert_array_equal(first.q, again.q)


def test_wrap_into_limits_broadcasts_and_moves_by_whole_turns():
    chain = armkit.load("stanford").chain  # joint 3 prismatic
    rng = np.random.default_rng(5)
    q = rng.uniform(-12, 12, (4, 5, chain.n))
    wrapped = wrap_into_limits(chain, q, 0.0)
    assert wrapped.shape == q.shape
    turns = (wrapped - q) / (2 * np.pi)
    np.testing.assert_allclose(turns, np.round(turns), atol=1e-12)
    np.testing.assert_array_equal(wrapped[..., chain.prismatic], q[..., chain.prismatic])
    fits = np.ceil((chain.lower - q) / (2 * np.pi)) <= np.floor((chain.upper - q) / (2 * np.pi))
    inside = (wrapped >= chain.lower - 1e-9) & (wrapped <= chain.upper + 1e-9)
    assert inside[fits & ~chain.prismatic].all()
    with pytest.raises(InputError, match=r"wrap_into_limits: expected q \(\.\.\., 6\)"):
        wrap_into_limits(chain, np.zeros(5), 0.0)


@pytest.mark.parametrize("distance", [1e10, 1e160, 1e300])
def test_a_target_too_far_for_squares_is_out_of_reach_by_its_distance_not_inf(distance):
    # The squared error of a target 1e160 m away overflows; the reported distance must not.
    from armkit.errors import UnreachableError

    robot = armkit.load("ur5")
    T = np.eye(4)
    T[0, 3] = distance
    with pytest.raises(UnreachableError, match="out of reach") as caught:
        robot.ik(T)
    assert caught.value.position_error == pytest.approx(distance, rel=1e-6)
    assert 0.0 <= caught.value.orientation_error <= np.pi
