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
