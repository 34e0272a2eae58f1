"""Cartesian straight lines: line + SLERP poses, IK and closed-loop joint paths, failures."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation, Slerp

import armkit
from armkit.control import cartesian_line, line_poses
from armkit.errors import InputError, UnreachableError
from armkit.spatial.transforms import transform_from

PROBOT = armkit.load("probot-anno")
Q0 = np.zeros(6)
T_GOAL = PROBOT.fk([0.3, -0.5, 0.4, 0.2, 1.2, -0.3])


def test_line_poses_are_a_line_and_a_slerp():
    T0 = PROBOT.fk(Q0)
    t = np.linspace(0.0, 2.0, 41)
    poses, twists, rates = line_poses(T0, T_GOAL, t, 2.0)
    s = (poses[:, :3, 3] - T0[:3, 3]) @ (T_GOAL[:3, 3] - T0[:3, 3]) / np.sum((T_GOAL[:3, 3] - T0[:3, 3]) ** 2)
    np.testing.assert_allclose(poses[:, :3, 3], T0[:3, 3] + np.outer(s, T_GOAL[:3, 3] - T0[:3, 3]),
                               atol=1e-15)  # on the line
    slerp = Slerp([0.0, 1.0], Rotation.from_matrix([T0[:3, :3], T_GOAL[:3, :3]]))
    np.testing.assert_allclose(poses[:, :3, :3], slerp(s).as_matrix(), atol=1e-12)
    np.testing.assert_allclose(twists[[0, -1]], 0.0, atol=1e-15)  # starts and ends at rest
    np.testing.assert_allclose(rates[[0, -1]], 0.0, atol=1e-15)
    np.testing.assert_allclose(np.gradient(poses[:, :3, 3], t, axis=0)[1:-1], twists[1:-1, :3], atol=2e-3)


def test_ik_line_reproduces_every_pose_with_consistent_derivatives():
    line = cartesian_line(PROBOT, Q0, T_GOAL, 4.0, rate_hz=200)
    assert line.q.shape == (801, 6) and line.t[-1] == 4.0
    np.testing.assert_allclose(PROBOT.fk(line.q), line.poses, atol=1e-9)
    np.testing.assert_allclose(PROBOT.fk(line.q[-1]), T_GOAL, atol=1e-9)
    np.testing.assert_allclose(line.qd[[0, -1]], 0.0, atol=1e-12)
    np.testing.assert_allclose(line.qdd[[0, -1]], 0.0, atol=1e-9)
    # J qd = twist by construction; check qd and qdd against finite differences of the samples.
    # (second-order differences at 5 ms: errors ~1e-5, against peaks of ~0.5 rad/s and rad/s^2)
    np.testing.assert_allclose(np.gradient(line.q, line.t, axis=0)[1:-1], line.qd[1:-1], atol=5e-5)
    np.testing.assert_allclose(np.gradient(line.qd, line.t, axis=0)[1:-1], line.qdd[1:-1], atol=5e-5)


def test_closed_loop_line_agrees_with_the_ik_line():
    by_ik = cartesian_line(PROBOT, Q0, T_GOAL, 4.0, rate_hz=50)
    by_loop = cartesian_line(PROBOT, Q0, T_GOAL, 4.0, rate_hz=50, method="closed-loop")
    np.testing.assert_allclose(by_loop.q, by_ik.q, atol=1e-4)
    assert by_loop.method == "closed-loop"


@pytest.mark.parametrize("method", ["ik", "closed-loop"])
def test_unreachable_point_is_named(method):
    far = transform_from(np.eye(3), [0.6, 0.0, 0.3])
    with pytest.raises(UnreachableError, match=r"Cartesian line: the point at t = [0-9.]+ s, position"):
        cartesian_line(PROBOT, Q0, far, 4.0, method=method)


def test_csv_export(tmp_path):
    line = cartesian_line(PROBOT, Q0, T_GOAL, 1.0, rate_hz=20)
    path = line.to_csv(tmp_path / "line.csv")
    header = path.read_text().splitlines()[0]
    assert header == "t," + ",".join(f"{p}{j}" for p in ("q", "qd", "qdd") for j in range(1, 7))
    np.testing.assert_allclose(np.loadtxt(path, delimiter=",", skiprows=1)[:, 1:7], line.q)
    with pytest.raises(InputError, match="already exists"):
        line.to_csv(path)


@pytest.mark.parametrize(("kwargs", "match"), [
    ({"duration": -1.0}, r"duration \[s\]: expected a finite number > 0, got -1.0"),
    ({"method": "spline"}, "expected 'ik' or 'closed-loop'"),
    ({"rate_hz": 0.0}, r"rate_hz \[Hz\]: expected a finite number > 0, got 0.0"),
    ({"T_goal": np.full((4, 4), np.nan)}, "NaN"),
    ({"q0": [0.0] * 5}, "6 joints"),
])
def test_bad_input(kwargs, match):
    args = {"q0": Q0, "T_goal": T_GOAL, "duration": 1.0} | kwargs
    with pytest.raises(InputError, match=match):
        cartesian_line(PROBOT, **args)


def test_a_line_through_the_wrist_singularity_fails_clearly():
    # q4 and q6 change sign across q5 = pi/2: the IK path has to jump (branch change) there.
    q0 = np.array([0.0, 0.3, 0.5, 0.2, np.pi / 2 - 0.15, 0.1])
    T_goal = PROBOT.fk([0.0, 0.3, 0.5, -0.2, np.pi / 2 + 0.15, -0.1])
    with pytest.raises(UnreachableError, match=r"t = 1 s, .* joint q\d jumps by [0-9.]+ between samples"):
        cartesian_line(PROBOT, q0, T_goal, 2.0, rate_hz=50)
    with pytest.raises(UnreachableError, match="not reached by the closed loop .* near a singularity"):
        cartesian_line(PROBOT, q0, T_goal, 2.0, rate_hz=50, method="closed-loop")
