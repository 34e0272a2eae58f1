"""armkit.plan_path: collision-free motions, checked here independently of the planner's own check."""

from __future__ import annotations

import numpy as np
import pytest

import armkit
import armkit.plan
from armkit.errors import CollisionError, InputError, PlanningError
from armkit.plan import UNBOUNDED_MARGIN, _bounds, _timed, collision_time, goal_configurations, plan_path
from armkit.spatial.rotations import matrix_from_euler
from armkit.spatial.transforms import transform_from
from armkit.trajectory import plan_trajectory

pytest.importorskip("ompl")

#: The UR5 reaching along -x (start) and along -y (goal), a wall on the diagonal between (as
#: examples/data/ur5_wall.toml): the straight joint motion hits it.
Q_START = np.array([0.0, -1.2, 1.2, 0.0, 1.57, 0.0])
Q_GOAL = np.array([1.57, -1.2, 1.2, 0.0, 1.57, 0.0])
#: Sampling rate [Hz] of the independent check: at the UR5's 180 deg/s per joint no point of the
#: arm moves more than about 1 mm between two samples.
CHECK_RATE_HZ = 10_000.0


@pytest.fixture(scope="module")
def ur5():
    return armkit.load("ur5")


@pytest.fixture(scope="module")
def wall_scene(ur5):
    wall = armkit.Box([0.5, 0.04, 0.5], transform_from(matrix_from_euler([0, 0, np.pi / 4], "xyz-fixed"),
                                                       [-0.35355, -0.35355, 0.25]), name="wall")
    return armkit.Scene(ur5, [wall], floor=0.0)


@pytest.fixture(scope="module")
def planned(wall_scene):
    return plan_path(wall_scene, Q_START, Q_GOAL, seed=0)


def assert_collision_free(scene, trajectory):
    """Every sample at CHECK_RATE_HZ free, with positive clearance (MuJoCo's distances, not the planner)."""
    samples = trajectory.sample(CHECK_RATE_HZ)
    assert samples.t.size > 1000
    collides = scene.collides(samples.q)
    assert not collides.any(), f"collides at t = {samples.t[np.argmax(collides)]:.4f} s"
    assert scene.clearance(samples.q).min() > 0.0


def test_the_straight_motion_past_the_wall_collides(ur5, wall_scene):
    assert not wall_scene.collides(Q_START) and not wall_scene.collides(Q_GOAL)
    assert wall_scene.path_collides(Q_START, Q_GOAL)
    straight = plan_trajectory(ur5, [Q_START, Q_GOAL])
    hit = collision_time(wall_scene, straight)
    assert 0.0 < hit < straight.duration
    assert wall_scene.collides(straight.at_time(hit)[0])
    assert {part for _, part in wall_scene.contacts(straight.at_time(hit)[0])} == {"wall"}


def test_a_planned_motion_past_the_wall_is_free_at_a_fine_resolution(wall_scene, planned):
    assert_collision_free(wall_scene, planned)
    assert collision_time(wall_scene, planned) is None


def test_a_planned_motion_starts_and_ends_at_rest_where_asked(planned):
    np.testing.assert_array_equal(planned.waypoints[0], Q_START)
    np.testing.assert_array_equal(planned.waypoints[-1], Q_GOAL)
    q0, qd0, qdd0 = planned.at_time(0.0)
    q1, qd1, qdd1 = planned.at_time(planned.duration)
    np.testing.assert_allclose(q0, Q_START, atol=1e-12)
    np.testing.assert_allclose(q1, Q_GOAL, atol=1e-12)
    for value in (qd0, qd1, qdd0, qdd1):
        np.testing.assert_allclose(value, 0.0, atol=1e-9)


def test_a_planned_motion_keeps_every_limit(ur5, wall_scene, planned):
    assert planned.position_limit_violations(ur5) == []
    assert np.all(planned.peak_velocity <= ur5.max_velocity * (1 + 1e-9))
    slow = plan_path(wall_scene, Q_START, Q_GOAL, seed=0, max_velocity=1.0, max_acceleration=2.0)
    assert np.all(slow.peak_velocity <= 1.0 + 1e-9) and np.all(slow.peak_acceleration <= 2.0 + 1e-9)
    assert slow.duration > planned.duration
    assert_collision_free(wall_scene, slow)


def test_the_same_call_gives_the_same_motion_and_another_seed_another(wall_scene, planned):
    again = plan_path(wall_scene, Q_START, Q_GOAL, seed=0)
    np.testing.assert_array_equal(again.coefficients, planned.coefficients)
    np.testing.assert_array_equal(again.piece_durations, planned.piece_durations)
    other = plan_path(wall_scene, Q_START, Q_GOAL, seed=1)
    assert other.waypoints.shape != planned.waypoints.shape or not np.array_equal(other.waypoints,
                                                                                   planned.waypoints)
    assert_collision_free(wall_scene, other)


def test_a_goal_pose_ends_at_a_collision_free_ik_solution(ur5, wall_scene):
    T = ur5.fk(Q_GOAL)
    goals = goal_configurations(wall_scene, T, near=Q_START)
    assert len(goals) > 1 and not wall_scene.collides(goals).any()
    every = ur5.ik(T, all_solutions=True, near=Q_START)
    np.testing.assert_array_equal(goals, every[~wall_scene.collides(every)])
    trajectory = plan_path(wall_scene, Q_START, T, seed=0)
    end = trajectory.waypoints[-1]
    assert np.min(np.abs(goals - end).max(axis=1)) < 1e-9       # one of the free solutions
    np.testing.assert_allclose(ur5.fk(end), T, atol=1e-9)
    assert_collision_free(wall_scene, trajectory)


def test_a_colliding_start_or_goal_is_refused_naming_the_pair(wall_scene):
    into_wall = np.array([0.785, -1.2, 1.2, 0.0, 1.57, 0.0])
    assert wall_scene.collides(into_wall)
    with pytest.raises(CollisionError, match=r"q_start \[0\.785, .*\] collides: .*link3-wall") as error:
        plan_path(wall_scene, into_wall, Q_GOAL)
    assert ("link3", "wall") in error.value.contacts
    np.testing.assert_array_equal(error.value.q, into_wall)
    with pytest.raises(CollisionError, match=r"goal \[0\.785, .*\] collides: .*link3-wall"):
        plan_path(wall_scene, Q_START, into_wall)


def test_a_goal_pose_whose_every_solution_collides_is_refused(ur5, wall_scene):
    T = transform_from(ur5.fk(Q_GOAL)[:3, :3], [-0.4, -0.4, 0.3])    # the tool inside the wall
    assert len(ur5.ik(T, all_solutions=True)) == 8
    with pytest.raises(CollisionError, match=r"goal pose: every IK solution collides \(\d+: .*wall"):
        plan_path(wall_scene, Q_START, T)


def test_no_path_within_the_time_budget_is_an_error(wall_scene):
    message = r"no collision-free path found within time_budget=1e-09 s"
    with pytest.raises(PlanningError, match=message) as error:
        plan_path(wall_scene, Q_START, Q_GOAL, time_budget=1e-9)
    assert (error.value.time_budget, error.value.segment) == (1e-9, None)


def test_a_start_already_at_the_goal_is_refused(ur5, wall_scene):
    with pytest.raises(InputError, match=r"goal: q_start \[0, -1.2, .*\] is already there"):
        plan_path(wall_scene, Q_START, Q_START.copy())
    with pytest.raises(InputError, match="is already there"):
        plan_path(wall_scene, Q_START, ur5.fk(Q_START))


@pytest.mark.parametrize(("keyword", "value", "message"), [
    ("time_budget", 0.0, "time_budget: expected a finite number > 0, got 0.0"),
    ("seed", -1, "seed: expected a whole number from 0"),
    ("resolution", float("nan"), "resolution: expected a finite number > 0, got nan"),
    ("resolution", 1e-300, "resolution: 1e-300 m is finer than the 0.0001 m plan_path checks at"),
    ("resolution", 10.0, "resolution: 10 m is coarser than the 0.02 m plan_path checks at"),
])
def test_bad_options_are_refused(wall_scene, keyword, value, message):
    with pytest.raises(InputError, match=message):
        plan_path(wall_scene, Q_START, Q_GOAL, **{keyword: value})


def test_a_joint_without_limits_is_searched_half_a_turn_beyond_its_start_and_goals():
    robot = armkit.Robot.from_dh([armkit.DHRow(0.0, 0.3, 0.0, 0.0), armkit.DHRow(0.0, 0.2, 0.0, 0.0)],
                                 "standard", limits=[(-np.inf, np.inf), (-1.0, 1.0)])
    lower, upper = _bounds(robot, np.array([0.5, 0.0]), np.array([[2.0, 0.5], [-1.0, 0.2]]))
    np.testing.assert_allclose(lower, [-1.0 - UNBOUNDED_MARGIN, -1.0])
    np.testing.assert_allclose(upper, [2.0 + UNBOUNDED_MARGIN, 1.0])


@pytest.fixture(scope="module")
def corner_path(ur5, wall_scene):
    """A path whose straight segments are free but whose spline cuts into the wall: lift beside it,
    turn over it, lower beyond it."""
    lifted = [-1.9, 1.2]
    b = np.array([0.4, *Q_START[1:]])
    c = np.array([0.4, *lifted, *Q_START[3:]])
    d = np.array([1.05, *lifted, *Q_START[3:]])
    e = np.array([1.05, *Q_START[1:]])
    path = np.array([Q_START, b, c, d, e, Q_GOAL])
    assert not any(wall_scene.path_collides(path[k], path[k + 1]) for k in range(len(path) - 1))
    assert collision_time(wall_scene, plan_trajectory(ur5, path)) is not None
    return path


def test_where_the_spline_cuts_into_an_obstacle_via_points_pull_it_onto_the_path(ur5, wall_scene,
                                                                                 corner_path):
    trajectory = _timed(wall_scene, corner_path, 0.005, ur5.max_velocity, ur5.max_acceleration, None)
    assert len(trajectory.waypoints) > len(corner_path)
    kept = [np.flatnonzero(np.all(trajectory.waypoints == vertex, axis=1)) for vertex in corner_path]
    assert all(len(k) == 1 for k in kept) and np.all(np.diff(np.concatenate(kept)) > 0)
    assert_collision_free(wall_scene, trajectory)


def test_without_via_points_the_motion_stops_at_every_vertex(monkeypatch, ur5, wall_scene, corner_path):
    monkeypatch.setattr(armkit.plan, "VIA_POINT_ROUNDS", 0)
    trajectory = _timed(wall_scene, corner_path, 0.005, ur5.max_velocity, ur5.max_acceleration, None)
    np.testing.assert_array_equal(trajectory.waypoints, corner_path)
    _, qd, _ = trajectory.at_time(trajectory.waypoint_times)
    np.testing.assert_allclose(qd, 0.0, atol=1e-9)
    assert_collision_free(wall_scene, trajectory)


@pytest.mark.parametrize("limits", [{}, {"max_acceleration": 5.0}])
def test_the_stop_at_every_vertex_fallback_holds_short_fast_segments(monkeypatch, wall_scene, limits):
    """A short segment at high acceleration has polynomial coefficients of 1e7 and more: their
    rounding alone once failed the on-the-chord test (a PlanningError instead of the motion)."""
    monkeypatch.setattr(armkit.plan, "VIA_POINT_ROUNDS", 0)
    trajectory = plan_path(wall_scene, Q_START, Q_GOAL, **limits)
    _, qd, _ = trajectory.at_time(trajectory.waypoint_times)
    np.testing.assert_allclose(qd, 0.0, atol=1e-9)
    assert_collision_free(wall_scene, trajectory)


def test_a_spline_through_a_corner_is_not_on_its_chords(ur5):
    from armkit.plan import _on_segment

    corner = np.array([Q_START, [0.8, -1.6, 1.2, 0.0, 1.57, 0.0], Q_GOAL])
    smooth = plan_trajectory(ur5, corner)  # passes the middle waypoint moving: curved on both sides
    assert not _on_segment(smooth, 0) and not _on_segment(smooth, 1)
    stopping = armkit.plan._concatenated([plan_trajectory(ur5, corner[k:k + 2]) for k in range(2)])
    assert _on_segment(stopping, 0) and _on_segment(stopping, 1)
