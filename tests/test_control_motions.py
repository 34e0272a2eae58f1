"""Closed-loop motions: the seed's straight move and fixed-point rotation, limits, drift."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

import armkit
from armkit.control import ResolvedRate, move_linear, rotate_about_tool_point, track_poses
from armkit.errors import InputError, JointLimitError, UnreachableError
from armkit.spatial.rotations import matrix_from_axis_angle, rotation_angle_between

PROBOT = armkit.load("probot-anno")
Q0 = np.zeros(6)


def test_seed_straight_move():
    result = move_linear(PROBOT, Q0, [0.15, 0.0, -0.15], duration=3.0)
    assert result.success, result.message
    start = PROBOT.fk(Q0)
    end = result.pose_final
    assert np.linalg.norm(end[:3, 3] - [0.3789, 0.0, 0.304]) < 1e-5
    assert rotation_angle_between(end, start) < 1e-8  # orientation unchanged
    # The whole path stays on the straight line and keeps the orientation.
    p = result.poses[:, :3, 3] - start[:3, 3]
    direction = np.array([1.0, 0.0, -1.0]) / np.sqrt(2)
    off_line = np.linalg.norm(p - np.outer(p @ direction, direction), axis=-1)
    assert off_line.max() < 1e-5
    assert rotation_angle_between(result.poses, start).max() < 1e-5
    assert np.all(np.abs(result.qd) <= PROBOT.max_velocity)
    assert PROBOT.within_limits(result.q).all()
    # The final joints are the IK solution of the target pose (closed-form IK, written apart).
    target = result.target
    np.testing.assert_allclose(result.q_final, PROBOT.ik(target, near=result.q_final), atol=1e-7)


def test_too_fast_a_move_is_held_back_by_the_velocity_limits_and_says_so():
    result = move_linear(PROBOT, Q0, [0.15, 0.0, -0.15], duration=0.5)
    assert not result.success
    assert "the joint velocity limits held it back" in result.message
    assert result.position_error > 0.1 and result.scale.min() < 0.1
    assert np.all(np.abs(result.qd) <= PROBOT.max_velocity * (1 + 1e-12))


def test_straight_move_in_the_tool_frame():
    start = PROBOT.fk(Q0)
    d_tool = np.array([0.02, -0.03, 0.01])
    in_tool = move_linear(PROBOT, Q0, d_tool, 1.0, frame="tool")
    in_base = move_linear(PROBOT, Q0, start[:3, :3] @ d_tool, 1.0)
    np.testing.assert_allclose(in_tool.q, in_base.q, atol=1e-12)
    np.testing.assert_allclose(in_tool.pose_final[:3, 3], start[:3, 3] + start[:3, :3] @ d_tool, atol=1e-8)


def test_seed_fixed_point_rotation_turns_180_degrees():
    # Base x axis at -0.2 rad/s, i.e. the twist [0, 0, 0, -0.2, 0, 0], for 180 degrees.
    result = rotate_about_tool_point(PROBOT, Q0, [1, 0, 0], angular_velocity=-0.2, angle=-np.pi)
    assert result.success, result.message
    assert result.t[-1] == pytest.approx(np.pi / 0.2)
    drift = np.linalg.norm(result.poses[:, :3, 3] - PROBOT.fk(Q0)[:3, 3], axis=-1)
    assert drift.max() < 1e-6  # README: ~1e-7 m over the half turn (measured 1.15e-7; margin for other BLAS)
    expected = matrix_from_axis_angle([-np.pi, 0, 0]) @ PROBOT.fk(Q0)[:3, :3]
    assert rotation_angle_between(result.pose_final[:3, :3], expected) < 1e-6
    assert result.q_final[3] == pytest.approx(-np.pi, abs=1e-6)  # joint 4 reaches -pi ...
    assert PROBOT.within_limits(result.q).all()  # ... and never passes it
    assert np.all(np.abs(result.qd) <= PROBOT.max_velocity)


def test_rotation_asked_for_more_stops_at_the_joint_limit():
    result = rotate_about_tool_point(PROBOT, Q0, [1, 0, 0], angular_velocity=-0.2, angle=-np.radians(200))
    assert not result.success
    assert "joint q4 reached its lower limit -3.14159 rad at t = " in result.message  # (no unit before)
    assert result.q[:, 3].min() >= -np.pi - 1e-12
    assert PROBOT.within_limits(result.q).all()
    turned = rotation_angle_between(result.pose_final, PROBOT.fk(Q0))
    assert np.degrees(turned) == pytest.approx(180.0, abs=0.01)
    assert result.orientation_error == pytest.approx(np.radians(20), abs=1e-3)  # short of the target
    with pytest.raises(JointLimitError, match="joint q4 reached its lower limit"):
        rotate_about_tool_point(PROBOT, Q0, [1, 0, 0], angular_velocity=-0.2, angle=-np.radians(200),
                                stop_at_limits=False)
    in_degrees = rotate_about_tool_point(PROBOT, Q0, [1, 0, 0], angular_velocity=-0.2,
                                         angle=-np.radians(200), message_degrees=True)
    assert "joint q4 reached its lower limit -180 deg at t = " in in_degrees.message
    np.testing.assert_array_equal(in_degrees.q, result.q)  # only the message's unit differs


def test_rotation_through_a_wrist_singularity_keeps_velocities_smooth_and_limited():
    q0 = np.array([0.0, 0.3, 0.5, 0.2, np.pi / 2 - 0.15, 0.1])
    damped = rotate_about_tool_point(PROBOT, q0, [0, 0, 1], angle=0.4, duration=4.0, frame="tool")
    undamped = rotate_about_tool_point(PROBOT, q0, [0, 0, 1], angle=0.4, duration=4.0, frame="tool",
                                       control=ResolvedRate(PROBOT, threshold=0.0, limit_velocity=False))
    assert damped.sigma_min.min() < 1e-3  # the motion really passes the singularity
    assert np.max(np.abs(undamped.qd) / PROBOT.max_velocity) > 5  # where the plain inverse explodes
    assert np.all(np.abs(damped.qd) <= PROBOT.max_velocity * (1 + 1e-12))
    jumps = np.abs(np.diff(damped.qd[:-1], axis=0)) / PROBOT.max_velocity
    assert jumps.max() < 0.01  # per 2 ms step: no jumps
    assert damped.success and damped.position_error < 1e-6  # it catches up afterwards


def test_closed_loop_does_not_drift_like_open_loop():
    result = rotate_about_tool_point(PROBOT, Q0, [1, 0, 0], angular_velocity=-0.2, angle=-np.pi / 2)
    control, q = ResolvedRate(PROBOT), Q0.copy()
    twist = np.array([0.0, 0.0, 0.0, -0.2, 0.0, 0.0])
    for dt in np.diff(result.t):
        q = q + control.step(q, twist).qd * dt
    open_drift = np.linalg.norm(PROBOT.fk(q)[:3, 3] - PROBOT.fk(Q0)[:3, 3])
    assert open_drift > 5e-6
    assert result.max_position_error < open_drift / 50


def test_track_poses_follows_a_given_reference():
    t = np.linspace(0.0, 1.0, 501)
    start = PROBOT.fk(Q0)
    reference = np.broadcast_to(start, (t.size, 4, 4)).copy()
    reference[:, 1, 3] += 0.02 * np.sin(np.pi * t)
    result = track_poses(PROBOT, Q0, t, reference)
    assert result.max_position_error < 1e-4 and result.position_error < 1e-6


@pytest.mark.parametrize(("call", "match"), [
    (lambda: move_linear(PROBOT, Q0, [0.1, 0, np.nan], 1.0), "NaN"),
    (lambda: move_linear(PROBOT, Q0, [0.1, 0], 1.0), "expected 3 numbers"),
    (lambda: move_linear(PROBOT, Q0, [0.1, 0, 0], -1.0),
     r"duration \[s\]: expected a finite number > 0, got -1.0"),
    (lambda: move_linear(PROBOT, [0] * 5, [0.1, 0, 0], 1.0), "6 joints"),
    (lambda: move_linear(PROBOT, Q0, [0.1, 0, 0], 1.0, frame="world"), "expected 'base' or 'tool'"),
    (lambda: move_linear(PROBOT, Q0, [0.1, 0, 0], 1.0, dt=0.1, gain=20), "gain \\* dt <= 1"),
    (lambda: rotate_about_tool_point(PROBOT, Q0, [0, 0, 0], angle=1.0, angular_velocity=0.1),
     "non-zero direction"),
    (lambda: rotate_about_tool_point(PROBOT, Q0, [0, 0, 1e-300], angle=1.0, angular_velocity=0.1),
     r"axis: expected a non-zero direction, got \[0.0, 0.0, 1e-300\]: its length 1e-300 is too small to be a "
     r"direction \(at least 1e-12\)"),
    (lambda: move_linear(PROBOT, Q0, [0.1, 0, 0], 5.0, dt=10.0),  # blamed the gain and a period of 5 s
     r"dt = 10 s with the feedback gain 20 1/s: expected gain \* dt <= 1 \(a stable loop\), a control period "
     r"of at most 0.05 s"),
    (lambda: rotate_about_tool_point(PROBOT, Q0, [1, 0, 0], angle=0.1, duration=5.0, dt=10.0), r"dt = 10 s"),
    (lambda: rotate_about_tool_point(PROBOT, Q0, [1, 0, 0], angle=1e300, angular_velocity=0.2),
     r"a turn of 1e\+300 rad at 0.2 rad/s takes 5e\+300 s; expected a duration from 1e-06 s to 1e\+06 s"),
    (lambda: rotate_about_tool_point(PROBOT, Q0, [1, 0, 0], angle=1.0, angular_velocity=1e300),
     r"a turn of 1 rad at 1e\+300 rad/s takes 1e-300 s; expected a duration from 1e-06 s"),
    (lambda: rotate_about_tool_point(PROBOT, Q0, [1, 0, 0], angle=2000.0, angular_velocity=0.2),
     r"a turn of 2000 rad at 0.2 rad/s takes 10000 s: 10000 s in steps of 0.002 s asks for 5e\+06"),
    (lambda: rotate_about_tool_point(PROBOT, Q0, [1, 0, 0], angle=1.0, duration=1e-300),
     r"the turn takes 1e-300 s; expected a duration"),
    (lambda: move_linear(PROBOT, Q0, [0.01, 0, 0], 1e-300),  # said 'segment 1'
     r"the move takes 1e-300 s; expected a duration from 1e-06 s to 1e\+06 s"),
    (lambda: rotate_about_tool_point(PROBOT, Q0, [1, 0, 0], angle=1.0), "give two of"),
    (lambda: rotate_about_tool_point(PROBOT, Q0, [1, 0, 0], angle=1.0, angular_velocity=0.1, duration=2.0),
     "give two of"),
    (lambda: rotate_about_tool_point(PROBOT, Q0, [1, 0, 0], angle=1.0, angular_velocity=-0.1),
     "opposite signs"),
    (lambda: rotate_about_tool_point(PROBOT, Q0, [1, 0, 0], angle=0.0, duration=1.0), "non-zero"),
    (lambda: rotate_about_tool_point(PROBOT, Q0, [1, 0, 0], angular_velocity=0.1, duration=-2.0), "> 0"),
    (lambda: track_poses(PROBOT, Q0, [0.0, 0.0], np.stack([np.eye(4)] * 2)), "increasing"),
    (lambda: track_poses(PROBOT, Q0, [0.0, 1.0], np.stack([np.eye(4), 2 * np.eye(4)])),
     "reference: last row"),
    (lambda: track_poses(PROBOT, Q0, [0.0, 1.0], np.stack([np.eye(4)] * 3)), "reference: expected 2 finite"),
])
def test_bad_input(call, match):
    with pytest.raises(InputError, match=match):
        call()


def test_an_axis_of_huge_components_is_still_a_direction():
    """Before: [1e308, 1e308, 0] had norm inf, so the axis became zero and the tool did not turn."""
    q0 = np.array([0.0, 0.3, 0.2, 0.0, 0.5, 0.0])
    result = rotate_about_tool_point(PROBOT, q0, [0.0, 1e308, 1e308], angle=0.1, duration=1.0)
    expected = rotate_about_tool_point(PROBOT, q0, [0.0, 1.0, 1.0], angle=0.1, duration=1.0)
    assert result.success
    np.testing.assert_array_equal(result.q_final, expected.q_final)


def test_start_outside_the_limits():
    with pytest.raises(JointLimitError, match="joint q5 = -2 rad is outside its limits"):
        move_linear(PROBOT, [0, 0, 0, 0, -2.0, 0], [0.1, 0, 0], 1.0)


@pytest.mark.parametrize("name", [n for n in armkit.builtin_robots() if n != "grb400-scara"])
def test_straight_move_on_every_arm(name):
    robot = armkit.load(name)  # 6 and 7 joints (panda), revolute and prismatic (stanford)
    candidates = robot.random_q(200, rng=3)
    q0 = candidates[np.argmax(robot.singular_values(candidates)[:, -1])]  # well away from singular
    result = move_linear(robot, q0, [0.03, -0.02, 0.02], 2.0)
    assert result.success, result.message
    assert result.position_error < 1e-8 and result.orientation_error < 1e-8


def test_straight_move_of_the_four_joint_scara():
    scara = armkit.load("grb400-scara")  # n < 6: the J^T J form of the damped solve
    q0 = np.array([np.radians(60), np.radians(50), 0.0, 0.0])
    result = move_linear(scara, q0, [0.03, -0.02, 0.01], 2.0)
    assert result.success, result.message
    np.testing.assert_allclose(result.pose_final[:3, 3], scara.fk(q0)[:3, 3] + [0.03, -0.02, 0.01], atol=1e-8)


@settings(max_examples=10, deadline=None)
@given(seed=st.integers(0, 10_000), axis=st.lists(st.floats(-1.0, 1.0), min_size=3, max_size=3),
       angle=st.floats(0.05, 0.3), frame=st.sampled_from(["base", "tool"]))
@example(seed=728, axis=[0.0, -1.0, 0.0], angle=0.25, frame="base")  # needed > 1 s within the limits
def test_property_turn_and_turn_back_returns_to_the_start(seed, axis, angle, frame):
    assume(np.linalg.norm(axis) > 0.1)
    candidates = PROBOT.random_q(20, rng=seed) * 0.5
    q0 = candidates[np.argmax(PROBOT.singular_values(candidates)[:, -1])]
    # 3 s keeps the joint rates inside PROBOT's velocity limits (0.7-0.96 rad/s) from any start.
    there = rotate_about_tool_point(PROBOT, q0, axis, angle, duration=3.0, frame=frame)
    assert there.success, there.message
    T0, T1 = PROBOT.fk(q0), there.pose_final
    expected = (matrix_from_axis_angle(angle * np.array(axis) / np.linalg.norm(axis))
                @ T0[:3, :3] if frame == "base" else
                T0[:3, :3] @ matrix_from_axis_angle(angle * np.array(axis) / np.linalg.norm(axis)))
    # (the loop ends within ~1e-7 of its target: its gain is finite and it stops at t = duration)
    assert rotation_angle_between(T1[:3, :3], expected) < 1e-6
    assert np.linalg.norm(T1[:3, 3] - T0[:3, 3]) < 1e-6
    # A turn leaves its own axis fixed, so in either frame the way back is the same axis.
    back = rotate_about_tool_point(PROBOT, there.q_final, axis, -angle, duration=3.0, frame=frame)
    # Not tighter: each leg ends ~1e-7 from its target pose, and a pose error maps to joints
    # through 1 / sigma_min, which is down to 0.045 for these starts (best of 20 random ones):
    # 2e-7 / 0.045 = 4.4e-6 (measured up to 1.5e-6 over 25 random cases).
    np.testing.assert_allclose(back.q_final, q0, atol=1e-5)


def test_target_beyond_reach_is_called_out_of_reach():
    # 0.78 m from the base: inside the bound of summed link lengths (0.79 m), beyond the arm's real reach
    result = move_linear(PROBOT, np.zeros(6), [0.4, 0.0, 0.0], 2.0)
    assert not result.success
    assert "near a singularity" in result.message
    # closed-form IK of the target decides it (before: 'either out of reach or the damping held it back')
    assert ("and IK of the target says: the target pose is out of reach: the closest pose found is"
            in result.message)
    assert "damping held" not in result.message


def test_a_reachable_turn_held_back_by_the_damping_is_not_called_out_of_reach_only():
    """The tester's case (armkit rotate's default 0.2 rad/s): a tool-frame quarter turn of the PROBOT
    from zero ends 7e-5 m short at sigma_min 0.026 (under the 0.04 threshold); the pose is reachable
    and a smooth turn over 20 s gets there."""
    axis = [0.0, 0.0, 1.0]
    fast = rotate_about_tool_point(PROBOT, np.zeros(6), axis, angle=np.pi / 2, angular_velocity=0.2,
                                   frame="tool")
    assert not fast.success and "near a singularity" in fast.message
    assert "the target is reachable (IK finds q = [" in fast.message
    assert "so the damping held the arm back near the singularity: move slower (a longer" in fast.message
    assert "out of reach" not in fast.message
    slow = rotate_about_tool_point(PROBOT, np.zeros(6), axis, angle=np.pi / 2, duration=20.0, frame="tool")
    assert slow.success
    # the q the message names reaches the target, inside the limits
    named = np.array(fast.message.split("IK finds q = [")[1].split("]")[0].split(", "), dtype=float)
    assert PROBOT.within_limits(named)
    np.testing.assert_allclose(PROBOT.fk(named), fast.target, atol=1e-3)  # printed to 4 digits



@pytest.mark.filterwarnings("error")
@pytest.mark.parametrize(("displacement", "frame", "shown", "distance"), [
    ([1e300, 0.0, 0.0], "base", r"\[1e\+300, 0, 0\] m \(base frame\)", 1e300),
    ([1e308, -1e308, 0.0], "base", r"\[1e\+308, -1e\+308, 0\] m \(base frame\)", 1.4142135623730951e308),
    ([0.0, 0.0, 2.0], "tool", r"\[0, 0, 2\] m \(tool frame\)", None),
])
def test_a_target_beyond_the_arms_reach_is_refused_before_the_motion_runs(displacement, frame, shown,
                                                                          distance):
    """Before: a 1e300 m move ran its whole 2 s of control steps and then said 'out of reach'.
    Now the target's distance from the base is held against the sum of the link lengths first
    (as 1e308 m, not inf)."""
    with pytest.raises(UnreachableError, match=f"displacement {shown}: the target is .* m from the base, "
                                               r"beyond the arm's reach \(0.7929 m") as error:
        move_linear(PROBOT, np.zeros(6), displacement, 2.0, frame=frame)
    if distance is not None:
        assert error.value.position_error == pytest.approx(distance - PROBOT.chain.reach, rel=1e-12)


def test_an_arm_with_fewer_than_six_joints_is_told_why_it_missed():
    arm = armkit.load(Path(__file__).parent.parent / "examples" / "data" / "my_arm.toml")
    result = move_linear(arm, np.radians([10, 20, 30]), [0.05, 0.0, 0.0], 2.0)
    assert not result.success and "an arm with 3 joints cannot follow every pose path" in result.message


def test_a_motion_reports_the_torques_that_drive_it():
    robot = armkit.load("puma560")
    q0 = np.array([0.0, 0.6, -0.8, 0.0, 0.5, 0.0])
    motion = armkit.move_linear(robot, q0, [0.05, 0.0, 0.0], duration=1.0)
    torques = motion.torques(robot)
    assert torques.tau.shape == motion.q.shape and np.array_equal(torques.t, motion.t)
    # the last sample is at rest: gravity alone
    np.testing.assert_allclose(torques.tau[-1], robot.gravity_torques(motion.q[-1]), rtol=0, atol=1e-12)
    # between samples the held velocity changes over one period: that acceleration drives it
    k = len(motion.t) // 2
    qdd = (motion.qd[k + 1] - motion.qd[k]) / (motion.t[k + 1] - motion.t[k])
    np.testing.assert_allclose(torques.tau[k], robot.inverse_dynamics(motion.q[k], motion.qd[k], qdd),
                               rtol=1e-12, atol=1e-12)
    assert np.all(torques.peak >= np.abs(torques.tau).max(axis=0) - 1e-15)
