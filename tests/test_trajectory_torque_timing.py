"""Torque-limited automatic timing: TOPP-RA with the inverse dynamics' rows, then a 1 kHz check.

Cross-checked against toppra's ``JointTorqueConstraint`` (fed armkit's inverse dynamics, itself
checked against pinocchio and MuJoCo) on the same geometric path.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers import TIGHT, WAYPOINTS, limited, toppra_path

from armkit.errors import InputError
from armkit.trajectory.topp import geometric_path, slowed_to_torque_limits, time_optimal, torque_constraint

toppra = pytest.importorskip("toppra")
from toppra import algorithm as toppra_algorithm  # noqa: E402
from toppra import constraint as toppra_constraint  # noqa: E402


def test_torque_limited_timing_never_exceeds_a_torque_limit_at_1_khz_and_touches_one():
    robot = limited(TIGHT)
    unlimited = time_optimal(WAYPOINTS, robot.max_velocity, robot.max_acceleration)
    assert np.any(unlimited.torques(robot).peak > TIGHT)  # the limits matter here
    timed = slowed_to_torque_limits(time_optimal(WAYPOINTS, robot.max_velocity, robot.max_acceleration,
                                                 constraints=[torque_constraint(robot)]), robot)
    ratio = timed.torques(robot, rate_hz=1000.0).peak / TIGHT
    assert ratio.max() <= 1.0 and ratio.max() >= 0.99
    assert np.all(timed.peak_velocity <= robot.max_velocity)
    assert np.all(timed.peak_acceleration <= robot.max_acceleration)
    assert timed.duration > unlimited.duration
    q, _, _ = timed.at_time(timed.waypoint_times)
    np.testing.assert_allclose(q, WAYPOINTS, rtol=0, atol=1e-12)


def test_torque_limited_duration_is_within_five_percent_of_toppra_on_the_same_path():
    robot = limited(TIGHT)
    vmax, amax = robot.max_velocity, robot.max_acceleration
    timed = time_optimal(WAYPOINTS, vmax, amax, constraints=[torque_constraint(robot)])
    ours = slowed_to_torque_limits(timed, robot)
    path = geometric_path(WAYPOINTS, vmax, amax)
    toppra.setup_logging("WARNING")
    constraints = [
        toppra_constraint.JointVelocityConstraint(np.stack([-vmax, vmax], axis=1)),
        toppra_constraint.JointAccelerationConstraint(
            np.stack([-amax, amax], axis=1),
            discretization_scheme=toppra_constraint.DiscretizationType.Interpolation),
        toppra_constraint.JointTorqueConstraint(
            lambda q, qd, qdd: robot.inverse_dynamics(q, qd, qdd), np.stack([-TIGHT, TIGHT], axis=1),
            np.zeros(robot.n), discretization_scheme=toppra_constraint.DiscretizationType.Interpolation)]
    instance = toppra_algorithm.TOPPRA(constraints, toppra_path(path), parametrizer="ParametrizeConstAccel")
    theirs = instance.compute_trajectory()
    assert theirs is not None
    assert theirs.duration * 0.99 <= ours.duration <= theirs.duration * 1.05


def test_slowing_is_not_asked_where_the_torques_are_within():
    robot = limited(np.full(6, 1e3))
    timed = time_optimal(WAYPOINTS, robot.max_velocity, robot.max_acceleration)
    assert slowed_to_torque_limits(timed, robot) is timed


def test_a_torque_limit_below_what_gravity_needs_is_an_input_error_naming_the_joint():
    robot = limited(np.array([0.05, 0.5, 2.8, 0.15, 0.2, 0.003]))
    timed = time_optimal(WAYPOINTS, robot.max_velocity, robot.max_acceleration)
    with pytest.raises(InputError, match=r"joint q2 needs .* to hold the arm against gravity"):
        slowed_to_torque_limits(timed, robot)
