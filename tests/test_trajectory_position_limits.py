"""Trajectories stay inside the joint position limits between waypoints (issue 20, item 5).

The minimum-jerk spline through waypoints inside the limits can overshoot a limit between
two of them; given ``position_limits`` it holds the joint at rest at the waypoint beside the
overshoot instead (armkit.trajectory.min_jerk's notes). Checked by dense sampling and by the
polynomials' own extrema, for given durations and for the automatic timing.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers import TIGHT, WAYPOINTS, limited
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit
from armkit.errors import InputError, JointLimitError
from armkit.trajectory import min_jerk, plan_trajectory

ROBOT = armkit.load("probot-anno")
#: Rounding of a polynomial evaluated at a waypoint on a limit [rad or m]: far below the chain's
#: LIMIT_TOLERANCE (1e-9), which the check does not lean on.
ROUNDING = 1e-12


def _random_plan(seed: int, segments: int) -> tuple[np.ndarray, np.ndarray]:
    """Waypoints inside the limits, many near a limit, and segment durations of very different lengths."""
    rng = np.random.default_rng(seed)
    lower, upper = ROBOT.limits.T
    unit = rng.uniform(0.0, 1.0, (segments + 1, ROBOT.n)) ** rng.choice([0.2, 1.0, 5.0], ROBOT.n)
    waypoints = lower + unit * (upper - lower)
    return waypoints, rng.uniform(0.3, 6.0, segments)


def _assert_inside(traj, robot) -> None:
    lower, upper = robot.limits.T
    low, high = traj.position_range                                   # exact extrema of every piece
    assert np.all(low >= lower - ROUNDING) and np.all(high <= upper + ROUNDING), (low - lower, upper - high)
    q = traj.at_time(np.linspace(0.0, traj.duration, 4001))[0]        # and dense samples
    assert np.all(q >= lower - ROUNDING) and np.all(q <= upper + ROUNDING)


def test_the_free_spline_leaves_the_limits_for_some_of_these_plans():
    """The property below is not empty: without position limits, several of the plans overshoot."""
    overshooting = 0
    for seed in range(15):
        waypoints, durations = _random_plan(seed, 4)
        overshooting += bool(min_jerk(waypoints, durations).position_limit_violations(ROBOT))
    assert overshooting >= 3


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), segments=st.integers(1, 6))
def test_given_durations_never_leave_the_position_limits(seed, segments):
    waypoints, durations = _random_plan(seed, segments)
    traj = plan_trajectory(ROBOT, waypoints, durations)
    _assert_inside(traj, ROBOT)
    np.testing.assert_allclose(traj.at_time(traj.waypoint_times)[0], waypoints, atol=1e-9)
    assert np.all(traj.peak_velocity <= ROBOT.max_velocity * (1 + 1e-9))


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), segments=st.integers(1, 4))
def test_automatic_timing_never_leaves_the_position_limits(seed, segments):
    waypoints, _ = _random_plan(seed, segments)
    traj = plan_trajectory(ROBOT, waypoints)
    _assert_inside(traj, ROBOT)
    np.testing.assert_allclose(traj.at_time(traj.waypoint_times)[0], waypoints, atol=1e-9)


def test_a_joint_that_would_overshoot_comes_to_rest_at_the_waypoint_and_the_others_are_untouched():
    waypoints = np.zeros((3, 6))
    waypoints[:, 1] = [0.0, 1.95, 0.0]            # q2 turns 0.057 rad below its 2.00713 rad limit
    waypoints[:, 0] = [0.0, 0.5, 1.0]             # q1 moves on without turning
    durations = [2.0, 0.8]
    free = min_jerk(waypoints, durations)
    assert free.position_range[1][1] > ROBOT.limits[1, 1]
    inside = min_jerk(waypoints, durations, position_limits=ROBOT.limits)
    assert inside.position_limit_violations(ROBOT) == []
    _, qd, qdd = inside.at_time(2.0)
    assert qd[1] == 0.0 and qdd[1] == 0.0
    np.testing.assert_array_equal(inside.coefficients[:, :, 0], free.coefficients[:, :, 0])
    assert inside.jerk_cost()[1] > free.jerk_cost()[1]    # the price of staying inside, on q2 only


def test_a_spline_whose_fixed_end_velocity_leaves_the_limits_is_an_error_naming_the_joint():
    with pytest.raises(JointLimitError, match=r"^joint 2 = -0\.5 \.\. 1\.09163 between waypoints 1 and 2 is "
                                              r"outside its limits \[-1, 1\]"):
        min_jerk([[0.0, 0.0], [0.0, -0.5]], [1.0], start_velocity=[0.0, 6.0],
                 position_limits=[[-1, 1], [-1, 1]])


@pytest.mark.parametrize("limits", [[[-1, 1]], [[1, -1], [-1, 1]], [[0, np.nan], [-1, 1]], "wide"])
def test_position_limits_of_the_wrong_shape_or_order_are_refused(limits):
    with pytest.raises(InputError, match=r"^position_limits: expected \(2, 2\) rows \(lower, upper\)|"
                                         r"^position_limits: expected numbers"):
        min_jerk([[0.0, 0.0], [0.5, 0.5]], [1.0], position_limits=limits)


def test_given_durations_slow_down_to_the_torque_limits_as_the_automatic_timing_does():
    robot = limited(TIGHT)
    durations = np.full(3, 1.0)
    fast = plan_trajectory(robot, WAYPOINTS, durations, torque_limits=False)
    assert np.any(fast.torques(robot).peak > TIGHT)
    traj = plan_trajectory(robot, WAYPOINTS, durations)
    assert np.all(traj.torques(robot).peak <= TIGHT)
    np.testing.assert_allclose(traj.requested_durations, durations)
    assert np.all(traj.stretch > 1) and np.all(traj.stretch >= fast.stretch)
    exact = plan_trajectory(robot, WAYPOINTS, durations, fit_limits=False)   # as given: nothing fitted
    np.testing.assert_allclose(exact.durations, durations)
