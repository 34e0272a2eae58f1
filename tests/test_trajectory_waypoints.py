"""Waypoints for a robot: CSV files, limits, poses through IK (nearest the previous solution)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import assert_transform_close
from helpers import SEED_WAYPOINTS

import armkit
from armkit.errors import InputError, JointLimitError, UnreachableError
from armkit.spatial import matrix_from_euler, transform_from
from armkit.trajectory import joint_waypoints, joint_waypoints_from_poses, plan_trajectory, read_waypoints

DATA = Path(__file__).parent.parent / "examples" / "data"


@pytest.fixture(scope="module")
def robot():
    return armkit.load("probot-anno")


def test_seed_files_hold_the_report_numbers():
    np.testing.assert_array_equal(read_waypoints(DATA / "probot_seed_joints.csv", 6), SEED_WAYPOINTS)
    poses = read_waypoints(DATA / "probot_seed_poses.csv", 6)
    np.testing.assert_allclose(poses[:, :3], [[0.2289, 0, 0.454], [0.3, 0.25, 0.322], [0.3, 0.1, 0.172],
                                              [0.3, -0.1, 0.122]])
    np.testing.assert_allclose(poses[:, 3:], [[np.pi / 2, 0, 0]] + [[np.pi / 2, -np.pi / 2, 0]] * 3)


@pytest.mark.parametrize(("angle", "tolerance"), [(np.pi / 2, 2e-3), (1.57, 1e-3)])
def test_seed_poses_give_the_report_joint_path(robot, angle, tolerance):
    poses = read_waypoints(DATA / "probot_seed_poses.csv", 6)
    poses[:, 3:] = np.where(np.abs(poses[:, 3:]) > 1, np.sign(poses[:, 3:]) * angle, 0.0)
    q = joint_waypoints_from_poses(robot, poses)
    T = transform_from(matrix_from_euler(poses[:, 3:], "xyz-fixed"), poses[:, :3])
    assert_transform_close(robot.fk(q), T, 1e-9, 1e-9)
    np.testing.assert_allclose(q, SEED_WAYPOINTS, atol=tolerance)   # the report printed 1.57 for pi/2


def test_each_ik_solution_is_the_one_nearest_the_previous(robot):
    rng = np.random.default_rng(3)
    q_true = np.cumsum(rng.normal(0, 0.05, (6, 6)), axis=0) + [0.2, -0.5, 0.8, 0.3, 1.2, 0.1]
    poses = np.concatenate([robot.fk(q_true)[:, :3, 3], robot.pose(q_true)[:, 3:]], axis=1)
    q = joint_waypoints_from_poses(robot, poses, q_start=q_true[0])
    np.testing.assert_allclose(q, q_true, atol=1e-8)


def test_unreachable_pose_names_the_waypoint(robot):
    poses = [[0.2289, 0, 0.454, np.pi / 2, 0, 0], [2.0, 0, 0.3, 0, 0, 0]]
    with pytest.raises(UnreachableError, match=r"waypoint 2 \(pose \[2, 0, 0.3, 0, 0, 0\]\)"):
        joint_waypoints_from_poses(robot, poses)


def test_joint_waypoints_check_count_and_limits(robot):
    with pytest.raises(InputError, match="PROBOT Anno has 6 joints, so each waypoint needs 6 values, got 5"):
        joint_waypoints(robot, np.zeros((3, 5)))
    outside = SEED_WAYPOINTS.copy()
    outside[2, 1] = 2.5
    with pytest.raises(JointLimitError, match=r"waypoint 3: joint q2 = 2.5 rad is outside its limits"):
        joint_waypoints(robot, outside)


@pytest.mark.parametrize(("text", "message"), [
    ("q1,q2,q3\n0,0,0\n", "at least two waypoints, found 1"),
    ("0,0,0\n1,1\n", "line 2: expected 3 values per waypoint, got 2"),
    ("0,0,0\n1,nan,1\n", "line 2: NaN or infinite"),
    ("0,0,0\n1,x,1\n", "line 2: expected 3 numbers, got '1,x,1'"),
])
def test_bad_waypoint_files(tmp_path, text, message):
    path = tmp_path / "w.csv"
    path.write_text(text)
    with pytest.raises(InputError, match=message):
        read_waypoints(path, 3)


def test_file_with_header_comments_and_spaces(tmp_path):
    path = tmp_path / "w.csv"
    path.write_text("# a comment\nq1, q2\n0.5, -1   # first\n\n1 2\n")
    np.testing.assert_array_equal(read_waypoints(path, 2), [[0.5, -1], [1, 2]])
    with pytest.raises(InputError, match="cannot read"):
        read_waypoints(tmp_path / "missing.csv", 2)


def test_plan_trajectory_from_poses_and_auto_time(robot):
    poses = read_waypoints(DATA / "probot_seed_poses.csv", 6)
    traj = plan_trajectory(robot, poses, poses=True)
    assert np.all(traj.peak_velocity <= robot.max_velocity)
    assert np.all(traj.peak_acceleration <= robot.max_acceleration)
    q, _, _ = traj.at_time(traj.waypoint_times)
    T = transform_from(matrix_from_euler(poses[:, 3:], "xyz-fixed"), poses[:, :3])
    assert_transform_close(robot.fk(q), T, 1e-9, 1e-9)


def test_numeric_waypoints_are_the_same_every_run():
    """The Panda (numeric IK) at a pose whose nearest solution would cross joint 4's limit:
    the solver restarts from random configurations; seeded, the waypoints (and so the
    trajectory and its simulation) are the same every run (before: a different branch, and
    a simulated tool error from 6e-5 to 0.04 m, from one run to the next)."""
    from test_cli_robot_options import PANDA
    robot = armkit.load(PANDA, tip="panda_hand_tcp")
    q = np.clip(robot.home + 0.3, *robot.limits.T)
    configurations = np.stack([q, q - 0.2, q + 0.1])
    first = joint_waypoints_from_poses(robot, robot.pose(configurations))
    for _ in range(3):
        np.testing.assert_array_equal(joint_waypoints_from_poses(robot, robot.pose(configurations)), first)
    assert_transform_close(robot.fk(first), robot.fk(configurations), 1e-9, 1e-9)
