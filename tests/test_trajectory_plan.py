"""plan_trajectory's arguments: limits in place of the robot file's (a URDF has no acceleration
limits), and a tolerance that must be a relative accuracy."""

from __future__ import annotations

import json
import re
import warnings
from importlib.metadata import distribution
from pathlib import Path

import numpy as np
import pytest

import armkit
from armkit.cli.main import main
from armkit.errors import ConvergenceError, InputError
from armkit.trajectory import plan_trajectory, planning_limits
from armkit.trajectory.timing import auto_time

UR5_URDF = str(Path(distribution("example-robot-data").locate_file(
    "cmeel.prefix/share/example-robot-data/robots")) / "ur_description/urdf/ur5_robot.urdf")
WAYPOINTS = np.array([[0.0, 0, 0, 0, 0, 0], [0.5, -0.5, 0.5, 0.3, 0.2, 0.1], [1.0, -1, 1, 0.5, 0.5, 0.5]])


@pytest.fixture(scope="module")
def ur5():
    return armkit.load(UR5_URDF, tip="tool0")


def test_a_urdf_arm_has_no_acceleration_limits_and_given_ones_are_kept(ur5):
    assert not np.isfinite(ur5.max_acceleration).any() and np.isfinite(ur5.max_velocity).all()
    amax = np.array([2.0, 2.0, 3.0, 4.0, 4.0, 4.0])
    traj = plan_trajectory(ur5, WAYPOINTS, max_acceleration=amax)
    assert np.all(traj.peak_acceleration <= amax * (1 + 1e-9))
    assert np.all(traj.peak_velocity <= ur5.max_velocity * (1 + 1e-9))
    assert np.isclose(traj.peak_acceleration / amax, 1, atol=1e-3).any()   # auto-timed: a limit binds
    slower = plan_trajectory(ur5, WAYPOINTS, max_velocity=0.5, max_acceleration=amax)
    assert np.all(slower.peak_velocity <= 0.5 * (1 + 1e-9)) and slower.duration > traj.duration
    stretched = plan_trajectory(ur5, WAYPOINTS, [0.1, 0.1], max_acceleration=1.0)
    assert np.all(stretched.peak_acceleration <= 1 + 1e-9) and np.all(stretched.stretch > 1)


@pytest.mark.parametrize(("limits", "message"), [
    ({"max_velocity": 0.0}, "max_velocity: expected positive limits"),
    ({"max_acceleration": [1.0, 2.0]}, "max_acceleration: expected one limit or 6 limits"),
    ({"max_acceleration": -1.0}, "max_acceleration: expected positive limits"),
    ({"max_velocity": "fast"}, "max_velocity: expected numbers"),
])
def test_bad_limits_are_input_errors_naming_them(ur5, limits, message):
    with pytest.raises(InputError, match=message):
        plan_trajectory(ur5, WAYPOINTS, **limits)
    with pytest.raises(InputError, match=message):
        planning_limits(ur5, **limits)


@pytest.mark.parametrize("tol", [0.0, -1e-4, float("nan"), 1.0, "small", "1e-3", 1e-300, True])
def test_a_tolerance_that_is_not_a_relative_accuracy_is_refused(tol):
    robot = armkit.load("probot-anno")
    message = "tol: expected a relative accuracy of each duration from 1e-12 to 0.5"
    with pytest.raises(InputError, match=message):
        plan_trajectory(robot, [[0.0] * 6, [0.5] * 6], tol=tol)
    with pytest.raises(InputError, match="tol: expected a relative accuracy"):
        plan_trajectory(robot, [[0.0] * 6, [0.5] * 6], [0.1], tol=tol)


@pytest.mark.parametrize(("limits", "takes"), [
    ({"max_acceleration": 1e-300}, "at least 6.32e+149 s"), ({"max_velocity": 1e-300}, "at least 1e+299 s"),
    ({"max_velocity": [1e-310, 1, 1, 1, 1, 1]}, "more seconds than a float holds"),  # overflows to inf
    ({"max_acceleration": 1e-310}, "more seconds than a float holds")])
def test_limits_too_small_for_any_trajectory_are_named(limits, takes):
    robot = armkit.load("ur5")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no overflow on the way
        with pytest.raises(InputError, match=f"waypoints 1 to 2: at joint 1's limits .* takes "
                                             f"{re.escape(takes)}, longer than a trajectory's longest"):
            plan_trajectory(robot, [[0.0] * 6, [0.1] + [0.0] * 5], **limits)


def test_limits_so_large_that_a_segment_is_shorter_than_a_microsecond_are_named():
    robot = armkit.load("ur5")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no overflow on the way
        with pytest.raises(InputError, match=r"waypoints 1 to 2: at the limits \(max_velocity 1e\+100, "
                                             r"max_acceleration 1e\+100 at most\) the move takes 6.32e-51 s"):
            plan_trajectory(robot, [[0.0] * 6, [0.1] * 6], max_velocity=1e100, max_acceleration=1e100)
        trajectory = plan_trajectory(robot, [[0.0] * 6, [0.1] * 6], max_velocity=1e200, max_acceleration=1.0)
    assert (trajectory.peak_acceleration <= 1.0 + 1e-9).all()


def test_the_timing_descent_checks_its_budget_and_says_what_it_spent():
    waypoints = np.array([[0.0, 0.0], [1.0, 0.3], [0.2, 1.5], [1.4, 0.1]])
    with pytest.raises(InputError, match="max_rounds: expected a whole number from 1"):
        auto_time(waypoints, 1.0, 1.0, max_rounds=0)
    with pytest.raises(ConvergenceError, match="still shortening after 1 rounds") as error:
        auto_time(waypoints, 1.0, 1.0, max_rounds=1, tol=1e-12)
    assert error.value.rounds == 1 and 1e-12 < error.value.last_change < 1e-3


def test_cli_traj_takes_max_velocity_and_acceleration_and_the_warning_names_them(capsys, tmp_path):
    path = tmp_path / "waypoints.csv"
    np.savetxt(path, WAYPOINTS, delimiter=",")
    args = ["traj", UR5_URDF, "--tip", "tool0", "--waypoints", str(path), "--auto-time", "--json"]
    assert main(args) == 0
    warned = json.loads(capsys.readouterr().out)
    assert warned["max_acceleration"] == [None] * 6
    assert any("a URDF has no acceleration limits" in w and "--max-velocity/--max-acceleration" in w
               for w in warned["warnings"])
    assert main([*args, "--max-acceleration", "2", "--max-velocity", "1,1,1,2,2,2"]) == 0
    limited = json.loads(capsys.readouterr().out)
    assert limited["warnings"] == [] and limited["max_acceleration"] == [2.0] * 6
    assert limited["max_velocity"] == [1.0, 1.0, 1.0, 2.0, 2.0, 2.0]
    assert max(limited["peak_acceleration"]) <= 2.0 * (1 + 1e-9)
    assert main([*args, "--deg", "--max-acceleration", str(np.degrees(2.0))]) == 0       # deg/s² with --deg
    np.testing.assert_allclose(json.loads(capsys.readouterr().out)["max_acceleration"], 2.0, rtol=1e-12)
    assert main([*args, "--max-acceleration", "1,2"]) == 1
    assert "--max-acceleration '1,2': expected one limit for every joint or 6" in capsys.readouterr().err
