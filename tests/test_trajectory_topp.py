"""Time-optimal timing (TOPP-RA in the core) and the automatic timing built on it, against toppra."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import toppra_path
from hypothesis import assume, given
from hypothesis import strategies as st

import armkit
from armkit.errors import InputError
from armkit.trajectory import plan_trajectory, read_waypoints
from armkit.trajectory.topp import (
    LinearConstraint,
    ToppStatus,
    geometric_path,
    parameterize,
    time_optimal,
)

toppra = pytest.importorskip("toppra")
from toppra import algorithm as toppra_algorithm  # noqa: E402
from toppra import constraint as toppra_constraint  # noqa: E402

SEED = read_waypoints("examples/data/probot_seed_joints.csv", 6)
#: Our duration over toppra's on the same path, at most (the smoothing window adds ~1-3 %).
WITHIN_TOPPRA = 1.05
#: toppra's duration over ours at most: both solve the same problem on similar grids.
BELOW_TOPPRA = 1.01


@pytest.fixture(scope="module")
def robot():
    return armkit.load("probot-anno")


def toppra_duration(path, vmax, amax, gridpoints=None):
    """toppra's time-optimal duration along ``path`` (velocity and acceleration limits)."""
    toppra.setup_logging("WARNING")
    constraints = [toppra_constraint.JointVelocityConstraint(np.stack([-vmax, vmax], axis=1)),
                   toppra_constraint.JointAccelerationConstraint(
                       np.stack([-amax, amax], axis=1),
                       discretization_scheme=toppra_constraint.DiscretizationType.Interpolation)]
    instance = toppra_algorithm.TOPPRA(constraints, toppra_path(path), gridpoints=gridpoints,
                                       parametrizer="ParametrizeConstAccel")
    trajectory = instance.compute_trajectory()
    assert trajectory is not None
    return trajectory.duration, instance.gridpoints


def assert_within_limits_and_touching(traj, vmax, amax):
    samples = traj.sample(1000.0)
    velocity = np.abs(samples.qd).max(axis=0) / vmax
    acceleration = np.abs(samples.qdd).max(axis=0) / amax
    assert velocity.max() <= 1.0 and acceleration.max() <= 1.0
    exact = max((traj.peak_velocity / vmax).max(), (traj.peak_acceleration / amax).max())
    assert 1.0 - 1e-9 <= exact <= 1.0


def assert_through_waypoints(traj, waypoints):
    q, _, _ = traj.at_time(traj.waypoint_times)
    np.testing.assert_allclose(q, waypoints, rtol=0, atol=1e-12)


def test_a_straight_path_at_the_acceleration_limit_is_bang_bang():
    s = np.linspace(0.0, 1.0, 101)
    ones = np.ones((101, 1))
    result = parameterize(s, LinearConstraint(ones, 0 * ones, 0 * ones, -2.0, 2.0), np.full(101, np.inf))
    assert result.success and result.status == ToppStatus.SUCCESS
    assert result.t[-1] == pytest.approx(2 * np.sqrt(1.0 / 2.0), rel=1e-12)
    np.testing.assert_allclose(result.u, np.where(s[:-1] < 0.5, 2.0, -2.0), rtol=0, atol=1e-9)


def test_a_velocity_bound_gives_the_trapezoid():
    s = np.linspace(0.0, 4.0, 401)
    ones = np.ones((401, 1))
    result = parameterize(s, LinearConstraint(ones, 0 * ones, 0 * ones, -1.0, 1.0), np.full(401, 1.0))
    assert result.t[-1] == pytest.approx(4.0 / 1.0 + 1.0 / 1.0, rel=1e-12)    # L / v + v / a
    assert result.x.max() == pytest.approx(1.0, rel=1e-12)


def test_every_row_holds_at_every_grid_point_on_a_curved_path(robot):
    path = geometric_path(SEED, robot.max_velocity, robot.max_acceleration)
    s = np.linspace(0.0, path.duration, 301)
    _, dq, ddq = path.at_time(s)
    amax = robot.max_acceleration
    with np.errstate(divide="ignore"):
        x_max = np.min((robot.max_velocity / np.abs(dq)) ** 2, axis=1)
    result = parameterize(s, LinearConstraint(dq, ddq, 0 * dq, -amax, amax), x_max)
    acceleration = dq[:-1] * result.u[:, None] + ddq[:-1] * result.x[:-1, None]
    assert np.all(np.abs(acceleration) <= amax * (1 + 1e-9))
    assert np.all(result.x <= x_max * (1 + 1e-9)) and result.x[0] == result.x[-1] == 0.0


def test_the_core_matches_toppra_on_toppra_s_own_grid(robot):
    vmax, amax = robot.max_velocity, robot.max_acceleration
    path = geometric_path(SEED, vmax, amax)
    expected, grid = toppra_duration(path, vmax, amax)
    _, dq, ddq = path.at_time(grid)
    with np.errstate(divide="ignore"):
        x_max = np.min((vmax / np.abs(dq)) ** 2, axis=1)
    result = parameterize(grid, LinearConstraint(dq, ddq, 0 * dq, -amax, amax), x_max)
    assert result.t[-1] == pytest.approx(expected, rel=1e-6)


def test_an_unmeetable_row_is_a_status_not_an_exception():
    s = np.linspace(0.0, 1.0, 11)
    ones = np.ones((11, 1))
    gravity = np.where(s > 0.55, 3.0, 0.0)[:, None]          # beyond the bound from s = 0.6 on
    result = parameterize(s, LinearConstraint(0 * ones, 0 * ones, gravity, -2.0, 2.0), np.full(11, np.inf))
    assert not result.success and result.status == ToppStatus.INFEASIBLE and result.point == 10
    assert np.all(np.isnan(result.t))


def test_a_start_too_fast_to_stop_in_time_is_a_status():
    s = np.linspace(0.0, 1.0, 11)
    ones = np.ones((11, 1))
    result = parameterize(s, LinearConstraint(ones, 0 * ones, 0 * ones, -1.0, 1.0), np.full(11, np.inf),
                          x_start=4.0)                          # stopping from sd = 2 needs s = 2
    assert result.status == ToppStatus.START_UNREACHABLE and result.point == 0
    assert parameterize(s, LinearConstraint(ones, 0 * ones, 0 * ones, -1.0, 1.0), np.full(11, np.inf),
                        x_start=2.0).success                   # from sd = sqrt(2): exactly s = 1


def test_the_seed_trajectory_is_within_the_limits_through_the_waypoints_and_near_toppra(robot):
    vmax, amax = robot.max_velocity, robot.max_acceleration
    traj = plan_trajectory(robot, SEED)
    assert_within_limits_and_touching(traj, vmax, amax)
    assert_through_waypoints(traj, SEED)
    expected, _ = toppra_duration(geometric_path(SEED, vmax, amax), vmax, amax)
    assert expected / BELOW_TOPPRA <= traj.duration <= expected * WITHIN_TOPPRA
    assert traj.duration < 8.969            # the minimum-jerk timing fitted by bisection and SLSQP


def test_the_trajectory_is_twice_continuously_differentiable(robot):
    traj = time_optimal(SEED, robot.max_velocity, robot.max_acceleration)
    c, h = traj.coefficients, traj.piece_durations[:, None]
    powers = np.arange(6)[:, None, None]
    ends = [(c * h**powers).sum(axis=0),
            (c[1:] * powers[1:] * h ** (powers[1:] - 1)).sum(axis=0),
            (c[2:] * powers[2:] * (powers[2:] - 1) * h ** (powers[2:] - 2)).sum(axis=0)]
    starts = [c[0], c[1], 2 * c[2]]
    for order, (end, start) in enumerate(zip(ends, starts, strict=True)):
        scale = np.abs(start).max() + 1e-300
        np.testing.assert_allclose(end[:-1], start[1:], rtol=0, atol=1e-8 * scale, err_msg=f"order {order}")
    q0, qd0, qdd0 = traj.at_time(0.0)
    q1, qd1, qdd1 = traj.at_time(traj.duration)
    np.testing.assert_allclose(np.concatenate([qd0, qdd0, qd1, qdd1]), 0.0, atol=1e-12)   # rest to rest


def test_a_wider_smoothing_window_trades_duration_for_jerk(robot):
    vmax, amax = robot.max_velocity, robot.max_acceleration
    sharp, smooth = (time_optimal(SEED, vmax, amax, smoothing=width) for width in (0.03, 0.3))
    assert smooth.peak_jerk.max() < 0.5 * sharp.peak_jerk.max()
    assert sharp.duration < smooth.duration
    assert_within_limits_and_touching(smooth, vmax, amax)


def test_random_waypoints_within_five_percent_of_toppra(robot):
    rng = np.random.default_rng(7)
    vmax, amax = robot.max_velocity, robot.max_acceleration
    low, high = 0.6 * robot.limits[:, 0], 0.6 * robot.limits[:, 1]
    ratios = []
    for _ in range(10):
        q = rng.uniform(low, high, (int(rng.integers(2, 9)), 6))
        traj = time_optimal(q, vmax, amax)
        expected, _ = toppra_duration(geometric_path(q, vmax, amax), vmax, amax)
        ratios.append(traj.duration / expected)
    assert 1 / BELOW_TOPPRA <= min(ratios) and max(ratios) <= WITHIN_TOPPRA, ratios


@given(st.integers(2, 7), st.integers(1, 6), st.integers(0, 2**32 - 1))
def test_any_waypoints_give_a_trajectory_within_the_limits_through_them(count, n, seed):
    rng = np.random.default_rng(seed)
    waypoints = rng.uniform(-2.0, 2.0, (count, n))
    still = rng.random((count, n)) < 0.2                 # some joints stay where they were
    for k in range(1, count):
        waypoints[k, still[k]] = waypoints[k - 1, still[k]]
    assume(np.all(np.abs(np.diff(waypoints, axis=0)).max(axis=1) > 0))
    vmax = rng.uniform(0.2, 3.0, n)
    amax = rng.uniform(0.2, 5.0, n)
    traj = time_optimal(waypoints, vmax, amax)
    assert_within_limits_and_touching(traj, vmax, amax)
    assert_through_waypoints(traj, waypoints)


def test_without_acceleration_limits_the_min_jerk_spline_is_scaled_onto_the_velocity_limits():
    """URDF arms carry no acceleration limits: jumping in speed would be 'fastest'; armkit keeps the
    minimum-jerk spline (rest to rest, zero acceleration at the ends) and scales it onto vmax."""
    waypoints = [[0.3, 0.3, 0.2], [0.07, 0.1, 0.14], [2.67, -0.72, -0.66]]
    vmax = np.array([2.175, 2.175, 2.61])
    traj = time_optimal(waypoints, vmax, np.inf)
    assert (traj.peak_velocity / vmax).max() == pytest.approx(1.0, rel=1e-9)
    assert np.all(traj.segment_pieces == 1)                          # the spline itself
    _, _, qdd = traj.at_time([0.0, traj.duration])
    np.testing.assert_allclose(qdd, 0.0, atol=1e-12)
    fitted = armkit.auto_time(waypoints, vmax, np.inf)                # durations searched segment by segment
    assert traj.duration <= 1.01 * fitted.duration


def test_a_joint_without_limits_follows_the_others():
    traj = time_optimal([[0.0, 0.0], [1.0, 2.0]], [1.0, np.inf], [1.0, np.inf])
    assert traj.peak_acceleration[0] == pytest.approx(1.0, rel=1e-9)
    np.testing.assert_allclose(traj.at_time(traj.duration)[0], [1.0, 2.0], atol=1e-12)


def test_a_constraint_row_from_python_joins_the_limits():
    """A torque-like row: the acceleration of joint 1 plus a constant load within [-0.5, 1.5]."""
    def load(s, q, dq, ddq):
        return LinearConstraint(dq[:, :1], ddq[:, :1], np.full((s.size, 1), 0.5), -0.5, 1.5)

    free = time_optimal([[0.0], [1.0]], 10.0, 2.0)
    limited = time_optimal([[0.0], [1.0]], 10.0, 2.0, constraints=[load])
    assert limited.duration > free.duration * 1.3                     # |qdd| <= 1 now binds
    samples = limited.sample(1000.0)
    assert samples.qdd.max() <= 1.0 + 0.02 and samples.qdd.min() >= -1.0 - 0.02   # smoothing's error
    impossible = [lambda s, q, dq, ddq: LinearConstraint(0 * dq, 0 * dq, np.full_like(dq, 3.0), -2.0, 2.0)]
    with pytest.raises(InputError, match=r"no motion along the path meets the limits: infeasible at s = "):
        time_optimal([[0.0], [1.0]], 10.0, 2.0, constraints=impossible)


def test_auto_time_keeps_a_path_that_would_overshoot_inside_the_position_limits(robot):
    q = np.zeros((3, 6))
    q[:, 1] = [-2.0, 2.0, 1.5]            # q2 turns 0.007 rad below its limit: the free path reaches 2.017
    assert geometric_path(q, robot.max_velocity, robot.max_acceleration).position_range[1][1] > 2.01
    traj = plan_trajectory(robot, q)
    assert traj.position_limit_violations(robot) == []
    low, high = traj.position_range
    assert low[1] == -2.0 and high[1] == pytest.approx(2.0, abs=1e-12)   # the turn is at the waypoint
    _, qd, qdd = traj.at_time(traj.waypoint_times[1])
    assert abs(qd[1]) < 1e-9 and abs(qdd[1]) < 1e-6                       # q2 at rest where it turns


@pytest.mark.parametrize(("call", "message"), [
    (lambda: parameterize([0.0, 0.0], LinearConstraint(*np.ones((3, 2, 1)), -1, 1), [1, 1]),
     "s: expected an increasing grid"),
    (lambda: parameterize([0.0, 1.0], LinearConstraint(*np.ones((3, 3, 1)), -1, 1), [1, 1]),
     r"a, b, c: expected \(2, m\) arrays"),
    (lambda: parameterize([0.0, 1.0], LinearConstraint(*np.ones((3, 2, 1)), 1, -1), [1, 1]),
     "lo, hi: expected lo <= hi"),
    (lambda: parameterize([0.0, 1.0], LinearConstraint(*np.ones((3, 2, 40)), -1, 1), [1, 1]),
     "a, b, c: at most 32 rows per grid point, got 40"),
    (lambda: time_optimal([[0.0, 1.0], [0.5, 1.0], [0.5, 1.0]], 1.0, 1.0),
     r"waypoints 2 and 3 are the same \(\[0\.5, 1\.0\]\)"),
    (lambda: time_optimal([[0.0, 1.0], [0.0, 2.0]], [1.0, np.inf], [1.0, np.inf]),
     "waypoints 1 to 2: only joints without a finite max_velocity or max_acceleration move"),
    (lambda: time_optimal([[0.0], [1.0]], np.inf, np.inf), "no finite limit"),
    (lambda: time_optimal([[0.0], [1.0]], -1.0, 1.0), "max_velocity: expected positive limits"),
    (lambda: time_optimal([[0.0], [1.0]], 1.0, 1.0, smoothing=0.0),
     r"smoothing: expected a fraction in \(0, 1\] of the time between waypoints, got 0"),
])
def test_bad_input_names_the_value(call, message):
    with pytest.raises(InputError, match=message):
        call()


def test_pieces_must_add_up_to_the_segments():
    message = r"segment_pieces: expected 2 counts adding up to 3 pieces, got \[1, 1\]"
    with pytest.raises(InputError, match=message):
        armkit.JointTrajectory([1.0] * 3, np.zeros((6, 3, 1)), [[0.0]] * 3, segment_pieces=[1, 1])
