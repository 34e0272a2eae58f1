"""A 7-joint arm's self-motion in the viewer: ghosts along a branch, the arm moved along it
(a real viser server in this process, no page connected). ``armkit view --free-joint``: test_view.py."""

from __future__ import annotations

import numpy as np
import pytest

import armkit
from armkit.errors import InputError

pytest.importorskip("viser")

from armkit.view import Viewer  # noqa: E402  (after the importorskip)
from armkit.view.self_motion_ghosts import SELF_MOTION_GHOSTS  # noqa: E402

PANDA = armkit.load("panda")
Q0 = np.array([0.3, -0.4, 0.2, -2.0, 0.1, 1.8, 0.6])
SAMPLES = 17


@pytest.fixture(scope="module")
def viewer():
    with Viewer(PANDA, port=0, q=Q0) as viewer:
        yield viewer


def _revolute_gap(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.abs(np.angle(np.exp(1j * (a - b)))).max(axis=-1)


def test_the_ghosts_are_the_self_motion_samples_of_the_arms_branch_and_their_tools_are_on_the_target(viewer):
    viewer.q = Q0
    T = PANDA.fk(Q0)
    shown = viewer.show_self_motion(2, samples=SAMPLES)
    expected = armkit.self_motion(PANDA, T, free_joint=2, samples=SAMPLES)
    np.testing.assert_array_equal(shown.values, expected.values)
    np.testing.assert_array_equal(shown.q, expected.q)  # NaN in the same places
    assert viewer.self_motion is shown
    part = viewer._self_motion
    # the branch shown is the one passing nearest the arm, and the arm is on its nearest sample
    gaps = np.where(np.isfinite(shown.q).all(axis=-1), _revolute_gap(shown.q, Q0), np.inf)
    branch, k = np.unravel_index(np.argmin(gaps), gaps.shape)
    assert part.branch == branch
    np.testing.assert_array_equal(viewer.q, shown.q[branch, k])
    np.testing.assert_allclose(PANDA.fk(viewer.q), T, atol=1e-9)
    # the ghosts: spread over the branch's samples, each drawn where robot.fk puts that sample
    existing = np.flatnonzero(np.isfinite(shown.q[branch]).all(axis=-1))
    assert len(part.shown) == min(SELF_MOTION_GHOSTS, len(existing)) >= 2
    assert set(part.shown) <= set(existing) and {existing[0], existing[-1]} <= set(part.shown)
    assert [g.visible for g in part.ghosts] == [True] * len(part.shown) + [False] * (SELF_MOTION_GHOSTS
                                                                                   - len(part.shown))
    for ghost, s in zip(part.ghosts, part.shown, strict=False):
        np.testing.assert_allclose(ghost.placement.link_frames, PANDA.link_frames(shown.q[branch, s]),
                                   atol=1e-12)
        np.testing.assert_allclose(ghost.placement.joint_origins,
                                   armkit.kinematics.joint_frames(PANDA, shown.q[branch, s])[0][:, :3, 3],
                                   atol=1e-12)
        np.testing.assert_allclose(ghost.placement.link_frames[-1], T, atol=1e-9)


def test_moving_along_the_self_motion_keeps_the_tool_on_the_target(viewer):
    viewer.q = Q0
    T = PANDA.fk(Q0)
    motion = viewer.show_self_motion("q3", samples=SAMPLES)
    branch = viewer._self_motion.branch
    existing = np.flatnonzero(np.isfinite(motion.q[branch]).all(axis=-1))
    for k in existing[::3]:
        q = viewer.move_along_self_motion(motion.values[k] + 1e-4)   # the sample nearest the value
        np.testing.assert_array_equal(q, motion.q[branch, k])
        np.testing.assert_array_equal(viewer.q, q)
        np.testing.assert_allclose(PANDA.fk(q), T, atol=1e-9)
        assert viewer.self_motion is motion        # still on the target: the ghosts stay
    # the panel's slider [deg] does the same
    viewer.move_along_self_motion(motion.values[existing[-1]])
    viewer._self_motion.slider.value = float(np.degrees(motion.values[existing[0]]))
    np.testing.assert_array_equal(viewer.q, motion.q[branch, existing[0]])
    assert f"{np.degrees(motion.values[existing[0]]):.4g}</span> deg" in viewer._self_motion.status.content


def test_a_value_where_the_branch_does_not_exist_is_an_error_and_the_arm_stays(viewer):
    viewer.q = Q0
    motion = viewer.show_self_motion(2, samples=SAMPLES)
    missing = np.argwhere(~np.isfinite(motion.q).all(axis=-1))
    if len(missing) == 0:
        pytest.fail("every branch exists at every sample: choose a pose whose self-motion has gaps")
    branch, k = missing[0]
    before = viewer.q
    with pytest.raises(InputError, match=f"branch {branch + 1} has no solution at q3 = "):
        viewer.move_along_self_motion(motion.values[k], branch=int(branch) + 1)
    np.testing.assert_array_equal(viewer.q, before)
    with pytest.raises(InputError, match=f"branch {len(motion.q) + 1}: the self-motion has {len(motion.q)}"):
        viewer.move_along_self_motion(0.0, branch=len(motion.q) + 1)


def test_moving_the_arm_off_the_target_by_its_joints_takes_the_self_motion_away(viewer):
    viewer.q = Q0
    viewer.show_self_motion(2, samples=SAMPLES)
    assert any(g.visible for g in viewer._self_motion.ghosts)
    viewer.q = Q0 + 0.05
    assert viewer.self_motion is None and not any(g.visible for g in viewer._self_motion.ghosts)
    with pytest.raises(InputError, match="no self-motion shown"):
        viewer.move_along_self_motion(0.0)


def test_the_self_motion_of_an_explicit_target_moves_the_handle_there(viewer):
    q_target = Q0 + np.array([0.1, 0.1, -0.1, 0.2, 0.0, -0.1, 0.3])
    T = PANDA.fk(q_target)
    motion = viewer.show_self_motion(6, T, samples=SAMPLES)
    np.testing.assert_array_equal(viewer.target, T)
    assert motion.free_joint == 6
    np.testing.assert_allclose(PANDA.fk(viewer.q), T, atol=1e-9)


def test_a_six_joint_arm_has_no_self_motion_panel_and_says_why():
    with Viewer("ur5", port=0) as viewer:
        assert viewer._self_motion is None
        with pytest.raises(InputError, match="self-motion: needs a 7-joint arm.*UR5 has 6"):
            viewer.show_self_motion(2)
    with Viewer(PANDA, port=0) as viewer, pytest.raises(InputError, match="free_joint 'elbow'"):
        viewer.show_self_motion("elbow")


def _branch_with_gaps_and_its_samples(motion, branch):
    return np.flatnonzero(np.isfinite(motion.q[branch]).all(axis=-1))


def test_a_value_that_is_not_a_finite_number_or_a_bad_branch_is_an_error_and_the_arm_stays(viewer):
    viewer.q = Q0
    motion = viewer.show_self_motion(2, samples=SAMPLES)
    before = viewer.q
    for value in (np.nan, np.inf, -np.inf, "0.4", None, [0.4], True):
        with pytest.raises(InputError, match=r"value: expected a finite value of q3 \[rad\], got "):
            viewer.move_along_self_motion(value)
        np.testing.assert_array_equal(viewer.q, before)
    count = len(motion.q)
    for branch in (True, 1.0, 1.5, "1", 0, -1, count + 1):
        with pytest.raises(InputError, match=rf"branch {branch!r}: the self-motion has {count} branches; "
                                             rf"expected a whole number from 1 to {count}"):
            viewer.move_along_self_motion(0.2, branch=branch)
        np.testing.assert_array_equal(viewer.q, before)
    # the page's slider: a NaN from a client is the status line, the arm stays
    viewer._self_motion.slider.value = float("nan")
    assert "value: expected a finite value of q3 [rad], got nan" in viewer._status.content
    np.testing.assert_array_equal(viewer.q, before)
    # a value past the samples takes the nearest one (the last), a whole number too
    branch = viewer._self_motion.branch
    existing = np.flatnonzero(np.isfinite(motion.q[branch]).all(axis=-1))
    if existing[-1] == SAMPLES - 1:
        np.testing.assert_array_equal(viewer.move_along_self_motion(np.float32(2.95)), motion.q[branch, -1])
    np.testing.assert_array_equal(viewer.move_along_self_motion(0, branch=np.int64(branch + 1)),
                                  motion.q[branch, np.argmin(np.abs(motion.values))])


def test_sampling_runs_outside_the_viewers_lock_and_a_target_moved_meanwhile_is_an_error(viewer, monkeypatch):
    import threading

    import armkit.view.viewer as viewer_module

    free = []

    def try_the_lock() -> None:  # as a page's callback or the player would, from another thread
        taken = viewer._lock.acquire(blocking=False)
        if taken:
            viewer._lock.release()
        free.append(taken)

    def sample_checking_the_lock(*args, **kwargs):
        other = threading.Thread(target=try_the_lock)
        other.start()
        other.join()
        return armkit.self_motion(*args, **kwargs)

    viewer.q = Q0
    monkeypatch.setattr(viewer_module, "sample_self_motion", sample_checking_the_lock)
    viewer.show_self_motion(2, samples=SAMPLES)
    part = viewer._self_motion
    part.samples.value = SAMPLES
    for callback in part.sample_button._impl.update_cb:   # the page's button
        callback(None)
    assert free == [True, True]
    assert viewer.self_motion is not None and part.status.content.count("branch") >= 2

    def sample_while_the_target_moves(*args, **kwargs):
        viewer.q = Q0 + 0.05                               # the page moves the arm meanwhile
        return armkit.self_motion(*args, **kwargs)

    monkeypatch.setattr(viewer_module, "sample_self_motion", sample_while_the_target_moves)
    with pytest.raises(InputError, match="the IK target moved while its self-motion was sampled"):
        viewer.show_self_motion(2, samples=SAMPLES)
    np.testing.assert_array_equal(viewer.q, Q0 + 0.05)
    assert viewer.self_motion is None


def test_the_panel_takes_at_most_its_stated_samples():
    from armkit.view.self_motion_ghosts import PANEL_MAX_SAMPLES

    with Viewer(PANDA, port=0, q=Q0) as viewer:
        part = viewer._self_motion
        assert part.samples.max == PANEL_MAX_SAMPLES == 256
        part.samples.value = 1000                         # a client past the box's maximum
        for callback in part.sample_button._impl.update_cb:
            callback(None)
        assert "samples: expected a whole number from 2 to 256, got 1000" in viewer._status.content
        assert viewer.self_motion is None


def test_the_panel_follows_the_angle_unit(viewer):
    viewer.q = Q0
    motion = viewer.show_self_motion(2, samples=SAMPLES)
    part = viewer._self_motion
    assert part.slider.label == "q3 [deg]"
    viewer._joints.units.value = "rad"
    try:
        assert part.slider.label == "q3 [rad]"
        assert part.slider.min <= motion.values[0] < motion.values[-1] <= part.slider.max
        assert part.slider.value == round(float(viewer.q[2]), 3)
        assert f"{viewer.q[2]:.4g}</span> rad" in part.status.content
        branch = part.branch
        k = np.flatnonzero(np.isfinite(motion.q[branch]).all(axis=-1))[0]
        part.slider.value = float(motion.values[k])       # the slider now in rad
        np.testing.assert_array_equal(viewer.q, motion.q[branch, k])
    finally:
        viewer._joints.units.value = "deg"
    assert part.slider.label == "q3 [deg]"
    assert f"{np.degrees(viewer.q[2]):.4g}</span> deg" in part.status.content


def test_the_arm_set_elsewhere_on_the_target_moves_the_slider_and_the_text_and_off_it_clears_them(viewer):
    viewer.q = Q0
    T = PANDA.fk(Q0)
    motion = viewer.show_self_motion(2, samples=SAMPLES)
    part = viewer._self_motion
    q_between = PANDA.ik(T, near=Q0, free_joint=2, free_value=0.123)   # between two samples of q3
    viewer.q = q_between
    assert viewer.self_motion is motion                                 # still on the target
    assert part.slider.value == round(float(np.degrees(0.123)), 1)
    assert f"{np.degrees(0.123):.4g}</span> deg, on the target, at no sample of branch" in part.status.content
    viewer.q = Q0 + 0.05                                                # off the target
    assert viewer.self_motion is None and part.slider.disabled
    assert "sample the self-motion of the IK target" in part.status.content
    assert "the arm at" not in part.status.content


def test_another_branch_starts_at_the_sample_nearest_the_arm_modulo_a_turn(viewer):
    viewer.q = Q0
    motion = viewer.show_self_motion(2, samples=SAMPLES)
    part = viewer._self_motion
    found = np.isfinite(motion.q).all(axis=-1)
    here = motion.values[part.sample]
    # the arm a turn further on its free joint: the same pose (viewer.q does not enforce limits)
    viewer.q = viewer.q + np.eye(7)[2] * 2 * np.pi
    assert viewer.self_motion is motion
    other = next(b for b in range(len(motion.q)) if b != part.branch and found[b].sum() >= 2)
    part.branch_pick.value = part.branch_pick.options[other]
    existing = np.flatnonzero(found[other])
    expected = existing[np.argmin(np.abs(np.angle(np.exp(1j * (motion.values[existing] - here)))))]
    assert part.branch == other and part.sample == expected
    np.testing.assert_array_equal(viewer.q, motion.q[other, expected])


def _railed_stanford_arm():
    """A 7-joint arm with a prismatic free joint: the Stanford arm on a vertical rail named ``rail<1>``."""
    import tomllib
    from importlib.resources import files

    data = tomllib.loads(files("armkit").joinpath("robots/stanford.toml").read_text())
    data["name"] = "railed <Stanford>"
    data["joints"].insert(0, {"type": "prismatic", "name": "rail<1>", "d": 0, "a": 0, "alpha": 0, "theta": 0,
                              "limits": [-0.3, 0.3]})
    data.pop("description", None)
    return armkit.robot_from_dict(data)


def test_a_prismatic_free_joint_moves_in_metres_and_its_name_is_escaped():
    robot = _railed_stanford_arm()
    q0 = np.array([0.1, 0.3, -0.5, 0.6, 0.2, 0.7, -0.4])
    T = robot.fk(q0)
    with Viewer(robot, port=0, q=q0) as viewer:
        motion = viewer.show_self_motion("rail<1>", samples=SAMPLES)
        part = viewer._self_motion
        assert motion.free_joint == 0 and part.slider.label == "rail<1> [m]"
        assert "rail&lt;1&gt;" in part.status.content and "rail<1>" not in part.status.content
        viewer._joints.units.value = "rad"                  # the angle unit leaves metres alone
        assert part.slider.label == "rail<1> [m]"
        branch = part.branch
        existing = np.flatnonzero(np.isfinite(motion.q[branch]).all(axis=-1))
        for k in existing[::4]:
            q = viewer.move_along_self_motion(float(motion.values[k]) + 1e-5)
            np.testing.assert_array_equal(q, motion.q[branch, k])
            np.testing.assert_allclose(robot.fk(q), T, atol=1e-9)
        with pytest.raises(InputError, match=r"value: expected a finite value of rail<1> \[m\], got nan"):
            viewer.move_along_self_motion(float("nan"))
