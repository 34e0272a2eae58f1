"""Multi-waypoint minimum jerk: the seed case, an independent dense QP, optimality checks."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import SEED_AMAX, SEED_VMAX, SEED_WAYPOINTS
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit
from armkit.errors import InputError
from armkit.trajectory import JointTrajectory, durations_from_times, min_jerk, quintic
from armkit.trajectory.polynomial import quintic_coefficients


def ends_of_segments(traj: JointTrajectory, order: int):
    """d^order q/dt^order at the start and the end of every segment, from the coefficients."""
    c = traj.coefficients
    k = np.arange(c.shape[0])
    factor = np.array([np.prod(np.arange(j - order + 1, j + 1)) if j >= order else 0.0 for j in k])
    start = c[order] * factor[order]
    end = np.einsum("kNn,kN->Nn", c * factor[:, None, None],
                    np.where(k[:, None] >= order, traj.durations ** np.maximum(k - order, 0)[:, None], 0.0))
    return start, end


def test_seed_trajectory_hits_waypoints_continuous_and_within_limits():
    traj = min_jerk(SEED_WAYPOINTS, [10, 10, 10])
    assert traj.duration == 30.0
    np.testing.assert_array_equal(traj.waypoint_times, [0, 10, 20, 30])
    q, qd, qdd = traj.at_time(traj.waypoint_times)
    np.testing.assert_allclose(q, SEED_WAYPOINTS, rtol=0, atol=1e-12)
    np.testing.assert_allclose(qd[[0, -1]], 0.0, atol=1e-15)
    np.testing.assert_allclose(qdd[[0, -1]], 0.0, atol=1e-15)
    for order in (0, 1, 2):
        start, end = ends_of_segments(traj, order)
        np.testing.assert_allclose(end[:-1], start[1:], rtol=0, atol=1e-9)
    robot = armkit.load("probot-anno")
    np.testing.assert_allclose(robot.max_velocity, SEED_VMAX, atol=5e-5)
    np.testing.assert_allclose(robot.max_acceleration, SEED_AMAX, atol=5e-5)
    assert np.all(traj.peak_velocity <= SEED_VMAX) and np.all(traj.peak_acceleration <= SEED_AMAX)
    samples = traj.sample(200.0)        # the exact peaks bound every sample
    assert np.all(np.abs(samples.qd).max(axis=0) <= traj.peak_velocity * (1 + 1e-12))
    assert np.all(np.abs(samples.qdd).max(axis=0) <= traj.peak_acceleration * (1 + 1e-12))


def dense_qp_coefficients(waypoints, durations):
    """Independent formulation: all 6 N coefficients of one joint as unknowns, a dense KKT solve."""
    N = durations.size
    Q = np.zeros((6 * N, 6 * N))
    rows, rhs = [], []
    for i, T in enumerate(durations):
        # integral over [0, T] of (6 c3 + 24 c4 t + 60 c5 t^2)^2
        d = np.array([6.0, 24.0, 60.0])
        e = np.arange(3)[:, None] + np.arange(3) + 1
        Q[6 * i + 3:6 * i + 6, 6 * i + 3:6 * i + 6] = np.outer(d, d) * T**e / e

        def row(t, order, segment=i):
            r = np.zeros(6 * N)
            for j in range(order, 6):
                r[6 * segment + j] = np.prod(np.arange(j - order + 1, j + 1)) * t ** (j - order)
            return r

        rows += [row(0.0, 0), row(T, 0)]
        rhs += [waypoints[i], waypoints[i + 1]]
        if i + 1 < N:
            for order in (1, 2):
                rows.append(row(T, order) - row(0.0, order, i + 1))
                rhs.append(0.0)
    for order in (1, 2):
        rows += [row(0.0, order, 0), row(durations[-1], order, N - 1)]
        rhs += [0.0, 0.0]
    A = np.array(rows)
    K = np.block([[2 * Q, A.T], [A, np.zeros((A.shape[0], A.shape[0]))]])
    solution = np.linalg.solve(K, np.concatenate([np.zeros(6 * N), rhs]))
    return solution[:6 * N].reshape(N, 6).T


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), M=st.integers(2, 9))
def test_matches_an_independent_dense_qp(seed, M):
    rng = np.random.default_rng(seed)
    waypoints = rng.uniform(-2, 2, (M, 3))
    durations = rng.uniform(0.3, 3.0, M - 1)
    traj = min_jerk(waypoints, durations)
    for j in range(3):
        expected = dense_qp_coefficients(waypoints[:, j], durations)
        scale = np.abs(expected).max(axis=0)
        np.testing.assert_allclose(traj.coefficients[:, :, j], expected, rtol=0, atol=1e-8 * scale.max())


def test_seed_matches_the_dense_qp_and_is_c4():
    durations = np.array([10.0, 10.0, 10.0])
    traj = min_jerk(SEED_WAYPOINTS, durations)
    for j in range(6):
        np.testing.assert_allclose(traj.coefficients[:, :, j], dense_qp_coefficients(SEED_WAYPOINTS[:, j],
                                   durations), rtol=1e-9, atol=1e-14)
    # Optimality (Euler-Lagrange) conditions: jerk and snap continuous at interior waypoints.
    for order in (3, 4):
        start, end = ends_of_segments(traj, order)
        np.testing.assert_allclose(end[:-1], start[1:], rtol=0, atol=1e-12)


def test_no_other_continuous_quintic_spline_has_less_jerk():
    durations = np.array([10.0, 10.0, 10.0])
    best = min_jerk(SEED_WAYPOINTS, durations)
    cost = best.jerk_cost()
    _, qd, qdd = best.at_time(best.waypoint_times)
    rng = np.random.default_rng(4)
    for scale in (1e-6, 1e-3, 1e-1):
        for _ in range(50):
            v = qd + np.pad(rng.normal(0, scale, (2, 6)), ((1, 1), (0, 0)))
            a = qdd + np.pad(rng.normal(0, scale / 10, (2, 6)), ((1, 1), (0, 0)))
            c = quintic_coefficients(SEED_WAYPOINTS[:-1], SEED_WAYPOINTS[1:], durations[:, None],
                                     v[:-1], v[1:], a[:-1], a[1:])
            other = JointTrajectory(durations, c, SEED_WAYPOINTS)
            assert np.all(other.jerk_cost() >= cost * (1 - 1e-12))
            assert other.jerk_cost().sum() > cost.sum()


def test_jerk_cost_is_the_integral_of_squared_jerk():
    traj = min_jerk(SEED_WAYPOINTS, [10, 7, 12])
    t = np.linspace(0, traj.duration, 290001)
    jerk = traj.sample(1.0 / (t[1] - t[0])).qddd
    numeric = np.trapezoid(jerk**2, dx=t[1] - t[0], axis=0)
    np.testing.assert_allclose(traj.jerk_cost(), numeric, rtol=1e-6)


def test_two_waypoints_give_the_quintic():
    traj = min_jerk([[0.0, 1.0], [1.0, -1.0]], [2.0], start_velocity=[0.2, 0.0], end_acceleration=0.1)
    seg = quintic([0.0, 1.0], [1.0, -1.0], 2.0, v0=[0.2, 0.0], a1=0.1)
    np.testing.assert_allclose(traj.coefficients[:, 0], seg.coefficients, atol=1e-15)


def test_given_end_velocities_and_accelerations_are_met():
    traj = min_jerk(SEED_WAYPOINTS, [3, 4, 5], start_velocity=0.1, end_velocity=-0.2,
                    start_acceleration=0.05, end_acceleration=[0.0, 0.1, 0.2, 0.3, 0.4, 0.5])
    _, qd, qdd = traj.at_time([0.0, traj.duration])
    np.testing.assert_allclose(qd, [[0.1] * 6, [-0.2] * 6], atol=1e-12)
    np.testing.assert_allclose(qdd, [[0.05] * 6, [0.0, 0.1, 0.2, 0.3, 0.4, 0.5]], atol=1e-12)


def test_long_trajectory_solves_in_one_banded_system():
    rng = np.random.default_rng(1)
    waypoints = rng.uniform(-1, 1, (1000, 6))
    traj = min_jerk(waypoints, np.full(999, 0.5))
    q, _, _ = traj.at_time(traj.waypoint_times)
    np.testing.assert_allclose(q, waypoints, atol=1e-10)
    for order in (1, 2, 3, 4):
        start, end = ends_of_segments(traj, order)
        np.testing.assert_allclose(end[:-1], start[1:], rtol=0, atol=1e-6 * np.abs(start).max())


@pytest.mark.parametrize(("waypoints", "durations", "message"), [
    ([[0.0, 1.0]], [], "at least two waypoints, got 1"),
    ([[0.0], [1.0], [2.0]], [1.0], "3 waypoints need 2 segment durations, got 1"),
    ([[0.0], [1.0], [2.0]], [1.0, 0.0], r"must be from 1e-06 s to 1e\+06 s, got 0 s for segment 2"),
    ([[0.0], [1.0], [2.0]], [1.0, -1.0], r"must be from 1e-06 s to 1e\+06 s, got -1 s"),
    ([[0.0], [np.nan], [2.0]], [1.0, 1.0], "waypoints: contains NaN"),
    ([[0.0], [1.0]], [np.inf], "durations: contains NaN or infinite"),
])
def test_bad_input_is_a_clear_error(waypoints, durations, message):
    with pytest.raises(InputError, match=message):
        min_jerk(waypoints, durations)


def test_durations_from_increasing_times():
    np.testing.assert_array_equal(durations_from_times([1.0, 2.5, 4.0]), [1.5, 1.5])
    with pytest.raises(InputError, match="increase, but waypoint 3 is at 2.5 s after waypoint 2 at 2.5 s"):
        durations_from_times([0.0, 2.5, 2.5])
    with pytest.raises(InputError, match="at least two"):
        durations_from_times([0.0])
