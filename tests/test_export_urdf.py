"""URDF export: loads in MuJoCo and in pinocchio (written by others) with armkit's FK."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import mujoco
import numpy as np
import pytest
from conftest import assert_transform_close
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit
from armkit.errors import InputError, RobotDefinitionError
from armkit.export import urdf_from_robot, write_urdf
from armkit.sim import Simulation

BUILTINS = armkit.builtin_robots()


@pytest.mark.parametrize("name", BUILTINS)
def test_urdf_in_pinocchio_matches_fk(name):
    pinocchio = pytest.importorskip("pinocchio")
    robot = armkit.load(name)
    model = pinocchio.buildModelFromXML(urdf_from_robot(robot))
    data = model.createData()
    tool = model.getFrameId("tool")
    assert model.nq == robot.n
    q = robot.random_q(20, rng=3)
    poses = []
    for q_k in q:
        pinocchio.framesForwardKinematics(model, data, q_k)
        poses.append(data.oMf[tool].homogeneous)
    assert_transform_close(np.array(poses), robot.fk(q), position_tol=1e-9, angle_tol=1e-9)
    limited = np.isfinite(robot.limits).all(axis=1)
    np.testing.assert_allclose(model.lowerPositionLimit[limited], robot.limits[limited, 0], atol=1e-15)
    np.testing.assert_allclose(model.upperPositionLimit[limited], robot.limits[limited, 1], atol=1e-15)


@pytest.mark.parametrize("name", BUILTINS)
def test_urdf_in_mujoco_matches_fk(name):
    robot = armkit.load(name)
    model = mujoco.MjModel.from_xml_string(urdf_from_robot(robot))
    data = mujoco.MjData(model)
    tool = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "tool")
    assert tool >= 0 and model.njnt == robot.n
    q = robot.random_q(20, rng=4)
    poses = np.empty((20, 4, 4))
    for k, q_k in enumerate(q):
        data.qpos[:] = q_k
        mujoco.mj_kinematics(model, data)
        poses[k] = np.eye(4)
        poses[k, :3, :3] = data.xmat[tool].reshape(3, 3)
        poses[k, :3, 3] = data.xpos[tool]
    assert_transform_close(poses, robot.fk(q), position_tol=1e-6, angle_tol=1e-6)


def test_urdf_joint_types_and_tool_link():
    robot = armkit.load("stanford")
    root = ET.fromstring(urdf_from_robot(robot))
    joints = root.findall("joint")
    assert [j.get("type") for j in joints] == [*robot.joint_types, "fixed"]
    assert [j.find("axis").get("xyz") for j in joints[:-1]] == ["0 0 1"] * 6
    assert [link.get("name") for link in root.findall("link")] == [
        "base", *[f"link{i}" for i in range(1, 7)], "tool"]


def test_joints_named_like_the_tool_joint_give_a_urdf_armkit_loads_with_the_same_fk(tmp_path):
    dh = armkit.load("puma560").dh
    robot = armkit.Robot.from_dh(dh.rows, dh.convention, limits=armkit.load("puma560").limits,
                                 names=["q1", "q2", "q3", "tool_joint", "q5", "tool_joint_2"])
    names = [j.get("name") for j in ET.fromstring(urdf_from_robot(robot)).findall("joint")]
    assert names == [*robot.joint_names, "tool_joint_3"]
    back = armkit.load(write_urdf(robot, tmp_path / "arm.urdf"))
    assert back.joint_names == robot.joint_names
    q = np.array([0.1, -0.4, 0.3, 0.2, 0.5, -0.1])
    assert_transform_close(back.fk(q), robot.fk(q), 1e-12, 1e-12)


def test_unbounded_revolute_becomes_continuous():
    link = np.eye(4)
    link[0, 3] = 0.3
    chain = armkit.Chain((armkit.Joint("revolute", np.eye(4), link, -np.inf, np.inf, name="q1"),
                          armkit.Joint("revolute", np.eye(4), link, -1.0, 1.0, name="q2")))
    joints = ET.fromstring(urdf_from_robot(armkit.Robot(chain, "free"))).findall("joint")
    assert [j.get("type") for j in joints] == ["continuous", "revolute", "fixed"]


def test_zero_length_chain_and_overwrite(tmp_path):
    point = armkit.robot_from_dict({"convention": "standard", "joints": [
        {"alpha": 0, "a": 0, "d": 0, "theta": 0}]}, "point.toml")
    with pytest.raises(RobotDefinitionError, match="cannot be simulated"):
        urdf_from_robot(point)
    path = tmp_path / "arm.urdf"
    path.write_text("keep me")
    with pytest.raises(InputError, match="already exists"):
        write_urdf(armkit.load("ur5"), path)
    assert path.read_text() == "keep me"
    write_urdf(armkit.load("ur5"), path, overwrite=True)
    assert ET.parse(path).getroot().get("name") == "UR5"


@st.composite
def random_arms(draw):
    """Random DH arms: either convention, revolute and prismatic joints, a fixed tool row."""
    n = draw(st.integers(1, 7))
    length = st.floats(-0.5, 0.5, allow_nan=False)
    angle = st.floats(-np.pi, np.pi, allow_nan=False)
    joints = [{"type": draw(st.sampled_from(["revolute", "revolute", "prismatic"])), "alpha": draw(angle),
               "a": draw(length), "d": draw(length), "theta": draw(angle)} for _ in range(n)]
    joints[0]["d"] = 0.3  # some size, so the arm can be simulated
    for joint in joints:
        if joint["type"] == "prismatic":
            joint["limits"] = [-0.2, 0.3]
    tool = [{"alpha": draw(angle), "a": draw(length), "d": draw(length), "theta": draw(angle)}]
    data = {"convention": draw(st.sampled_from(["standard", "modified"])), "joints": joints, "tool": tool}
    return armkit.robot_from_dict(data, "random-arm.toml"), draw(st.integers(0, 2**32 - 1))


@settings(max_examples=25, deadline=None)
@given(random_arms())
def test_random_arms_round_trip_through_urdf_and_mjcf(arm):
    pinocchio = pytest.importorskip("pinocchio")
    robot, seed = arm
    q = robot.random_q(5, rng=seed)
    model = pinocchio.buildModelFromXML(urdf_from_robot(robot))
    data = model.createData()
    tool = model.getFrameId("tool")
    poses = []
    for q_k in q:
        pinocchio.framesForwardKinematics(model, data, q_k)
        poses.append(data.oMf[tool].homogeneous)
    assert_transform_close(np.array(poses), robot.fk(q), position_tol=1e-9, angle_tol=1e-9)
    assert_transform_close(Simulation(robot, gravity=False).tool_pose(q), robot.fk(q),
                           position_tol=1e-9, angle_tol=1e-9)
