"""MJCF import: the chain read from MuJoCo's compiled model, checked against MuJoCo's own kinematics
and dynamics (mj_kinematics, mj_fullM, qfrc_bias) on random configurations."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
from conftest import assert_transform_close
from typer.testing import CliRunner

import armkit
from armkit.errors import RobotDefinitionError
from armkit.export import write_mjcf
from armkit.mjcf import robot_from_mjcf

mujoco = pytest.importorskip("mujoco")

# Written by hand after MuJoCo Menagerie's universal_robots_ur5e/ur5e.xml (its bodies, joint
# classes, inertials and attachment site; capsules instead of the meshes): default classes,
# quaternions, joint axes along y, armature (which armkit ignores) and a site as the tool.
UR5E = """<mujoco model="ur5e">
  <compiler angle="radian" autolimits="true"/>
  <default>
    <default class="ur5e">
      <joint axis="0 1 0" range="-6.28319 6.28319" armature="0.1"/>
      <geom type="capsule" size="0.04 0.05" contype="0" conaffinity="0"/>
      <default class="size3"><joint actuatorfrcrange="-150 150"/>
        <default class="size3_limited"><joint range="-3.1415 3.1415"/></default>
      </default>
      <default class="size1"><joint actuatorfrcrange="-28 28"/></default>
    </default>
  </default>
  <worldbody>
    <body name="base" quat="0 0 0 -1" childclass="ur5e">
      <inertial mass="4.0" pos="0 0 0" diaginertia="0.00443333156 0.00443333156 0.0072"/>
      <geom/>
      <body name="shoulder_link" pos="0 0 0.163">
        <inertial mass="3.7" pos="0 0 0" diaginertia="0.0102675 0.0102675 0.00666"/>
        <joint name="shoulder_pan_joint" class="size3" axis="0 0 1"/>
        <geom/>
        <body name="upper_arm_link" pos="0 0.138 0" quat="1 0 1 0">
          <inertial mass="8.393" pos="0 0 0.2125" diaginertia="0.133886 0.133886 0.0151074"/>
          <joint name="shoulder_lift_joint" class="size3"/>
          <geom fromto="0 0 0 0 0 0.425"/>
          <body name="forearm_link" pos="0 -0.131 0.425">
            <inertial mass="2.275" pos="0 0 0.196" diaginertia="0.0311796 0.0311796 0.004095"/>
            <joint name="elbow_joint" class="size3_limited"/>
            <geom fromto="0 0 0 0 0 0.392"/>
            <body name="wrist_1_link" pos="0 0 0.392" quat="1 0 1 0">
              <inertial mass="1.219" pos="0 0.127 0" diaginertia="0.0025599 0.0025599 0.0021942"/>
              <joint name="wrist_1_joint" class="size1"/>
              <geom/>
              <body name="wrist_2_link" pos="0 0.127 0">
                <inertial mass="1.219" pos="0 0 0.1" diaginertia="0.0025599 0.0025599 0.0021942"/>
                <joint name="wrist_2_joint" axis="0 0 1" class="size1"/>
                <geom/>
                <body name="wrist_3_link" pos="0 0 0.1">
                  <inertial mass="0.1889" pos="0 0.0771683 0" quat="1 0 0 1"
                    diaginertia="0.000132134 9.90863e-05 9.90863e-05"/>
                  <joint name="wrist_3_joint" class="size1"/>
                  <geom/>
                  <site name="attachment_site" pos="0 0.1 0" quat="-1 1 0 0"/>
                </body>
              </body>
            </body>
          </body>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""

# Everything else MJCF allows on a path: degrees and Euler angles, a joint away from its body's
# origin, a joint reference (ref) != 0, two joints in one body, a slide joint, an unlimited
# hinge, a fixed body between joints, a side branch with a hinge of its own (held at its ref),
# mass beyond the tip and a rotated site as the tool, all below a floating base.
ODD = """<mujoco model="odd arm">
  <compiler angle="degree" eulerseq="zyx"/>
  <worldbody>
    <body name="cart" pos="0.3 -0.2 0.1" euler="20 -10 5">
      <freejoint name="float"/>
      <geom type="box" size="0.1 0.1 0.05" mass="3"/>
      <body name="l1" pos="0 0 0.15" axisangle="1 1 0 30">
        <joint name="j1" type="hinge" axis="0 0 1" range="-170 170" ref="15"/>
        <geom type="capsule" fromto="0 0 0 0 0 0.3" size="0.03" mass="1.5"/>
        <body name="l2" pos="0.02 0 0.3">
          <joint name="j2a" type="hinge" axis="0.3 -0.4 0.5" pos="0.01 0.02 -0.03"/>
          <joint name="j2b" type="hinge" axis="1 0 0" pos="0 0.05 0" range="-90 120"/>
          <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.025" mass="1.1"/>
          <body name="spacer" pos="0.3 0 0" xyaxes="0 1 0 -1 0 0">
            <geom type="sphere" size="0.03" mass="0.4"/>
            <body name="l3" pos="0 0 0.05">
              <joint name="j3" type="slide" axis="-1 1 0.2" range="-0.1 0.2" ref="0.05"/>
              <geom type="box" size="0.02 0.02 0.1" mass="0.7"/>
              <body name="camera" pos="0.05 0 0">
                <joint name="pan" type="hinge" axis="0 0 1" ref="30"/>
                <geom type="sphere" size="0.02" mass="0.2"/>
              </body>
              <body name="l4" pos="0 0 0.12" quat="0.9 0.1 -0.3 0.2">
                <joint name="j4" type="hinge" axis="0 -1 0" range="-60 60" ref="-20"/>
                <geom type="capsule" fromto="0 0 0 0 0 0.08" size="0.02" mass="0.3"/>
                <site name="tcp" pos="0.01 0 0.1" euler="0 90 45"/>
                <body name="gripper" pos="0 0 0.1">
                  <geom type="box" size="0.03 0.01 0.02" mass="0.25"/>
                </body>
              </body>
            </body>
          </body>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def _pose(model, data, name: str) -> np.ndarray:
    """The world pose ``(4, 4)`` of a body or a site after mj_kinematics."""
    T = np.eye(4)
    site = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, name)
    if site >= 0:
        T[:3, :3], T[:3, 3] = data.site_xmat[site].reshape(3, 3), data.site_xpos[site]
    else:
        body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, name)
        T[:3, :3], T[:3, 3] = data.xmat[body].reshape(3, 3), data.xpos[body]
    return T


def _mujoco_tool(model, robot: armkit.Robot, q: np.ndarray, base: str, tip: str,
                 rng: np.random.Generator | None = None) -> np.ndarray:
    """MuJoCo's pose of ``tip`` in ``base`` at the chain joints' ``q`` ``(N, n)``; joints off the chain
    at their ref (a free base joint, when ``rng`` is given, anywhere: the pose in ``base`` ignores it)."""
    data = mujoco.MjData(model)
    out = []
    for q_k in q:
        data.qpos[:] = model.qpos0
        if rng is not None and model.jnt_type[0] == mujoco.mjtJoint.mjJNT_FREE:
            data.qpos[:3] = rng.uniform(-1, 1, 3)
            data.qpos[3:7] = rng.normal(size=4) / np.linalg.norm(rng.normal(size=4))
            data.qpos[3:7] /= np.linalg.norm(data.qpos[3:7])
        for name, value in zip(robot.joint_names, q_k, strict=True):
            data.qpos[model.jnt_qposadr[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name)]] = value
        mujoco.mj_kinematics(model, data)
        out.append(np.linalg.inv(_pose(model, data, base)) @ _pose(model, data, tip))
    return np.array(out)


def _mujoco_dynamics(model, robot: armkit.Robot, q: np.ndarray,
                     qd: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """MuJoCo's joint-space inertia without armature and its bias forces (Coriolis and gravity), on
    the chain's dofs (every other joint held still: the submatrix is the locked system's)."""
    data = mujoco.MjData(model)
    dofs = [model.jnt_dofadr[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name)]
            for name in robot.joint_names]
    data.qpos[:] = model.qpos0
    for name, value, rate in zip(robot.joint_names, q, qd, strict=True):
        joint = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name)
        data.qpos[model.jnt_qposadr[joint]] = value
        data.qvel[model.jnt_dofadr[joint]] = rate
    mujoco.mj_forward(model, data)
    M = np.zeros((model.nv, model.nv))
    try:
        mujoco.mj_fullM(model, data, M)  # MuJoCo 4
    except TypeError:
        mujoco.mj_fullM(model, M, data.qM)  # MuJoCo 3
    M -= np.diag(model.dof_armature)
    return M[np.ix_(dofs, dofs)], data.qfrc_bias[dofs]


@pytest.fixture
def ur5e_file(tmp_path: Path) -> Path:
    path = tmp_path / "ur5e.xml"
    path.write_text(UR5E)
    return path


def test_a_menagerie_style_ur5e_matches_mujocos_kinematics_at_its_attachment_site(ur5e_file):
    robot = armkit.load(ur5e_file, tip="attachment_site")
    assert robot.joint_names == ["shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint", "wrist_1_joint",
                                 "wrist_2_joint", "wrist_3_joint"]
    np.testing.assert_allclose(robot.limits[2], [-3.1415, 3.1415])
    np.testing.assert_allclose(robot.max_torque, [150, 150, 150, 28, 28, 28])
    q = robot.random_q(200, rng=1)
    model = mujoco.MjModel.from_xml_path(str(ur5e_file))
    assert_transform_close(robot.fk(q), _mujoco_tool(model, robot, q, "world", "attachment_site"),
                           1e-12, 1e-12)


def test_the_loaded_ur5e_is_a_closed_form_arm_whose_eight_solutions_reach_the_pose(ur5e_file):
    robot = armkit.load(ur5e_file, tip="attachment_site")
    assert armkit.analyze_structure(robot).closed_form
    T = robot.fk([0.4, -1.1, 1.3, -0.9, 1.2, 0.3])
    solutions = armkit.ik_solutions(robot, T, turn_copies=False)
    assert len(solutions.q) == 8
    assert_transform_close(robot.fk(solutions.q), np.broadcast_to(T, (8, 4, 4)), 1e-9, 1e-9)


def test_the_ur5e_dynamics_match_mujocos_mass_matrix_and_bias_forces_without_armature(ur5e_file):
    robot = armkit.load(ur5e_file, tip="attachment_site")
    model = mujoco.MjModel.from_xml_path(str(ur5e_file))
    rng = np.random.default_rng(2)
    for q in robot.random_q(20, rng=3):
        qd = rng.uniform(-2, 2, robot.n)
        M, bias = _mujoco_dynamics(model, robot, q, qd)
        np.testing.assert_allclose(robot.mass_matrix(q), M, rtol=1e-10, atol=1e-12)
        np.testing.assert_allclose(robot.inverse_dynamics(q, qd, np.zeros(robot.n)), bias, rtol=1e-10,
                                   atol=1e-10)


def test_every_mjcf_feature_on_a_path_matches_mujoco_in_the_base_bodys_frame():
    model = mujoco.MjModel.from_xml_string(ODD)
    robot = robot_from_mjcf(ODD, base="cart", tip="tcp")
    assert robot.joint_names == ["j1", "j2a", "j2b", "j3", "j4"]
    assert robot.joint_types == ["revolute", "revolute", "revolute", "prismatic", "revolute"]
    np.testing.assert_allclose(robot.limits[[0, 1, 3]],
                               [np.radians([-170, 170]), [-np.inf, np.inf], [-0.1, 0.2]])
    q = np.column_stack([robot.random_q(300, rng=4)[:, :1], np.random.default_rng(5).uniform(-4, 4, 300),
                         robot.random_q(300, rng=6)[:, 2:]])
    rng = np.random.default_rng(7)
    assert_transform_close(robot.fk(q), _mujoco_tool(model, robot, q, "cart", "tcp", rng), 1e-12, 1e-12)
    at_ref = model.qpos0[[model.jnt_qposadr[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name)]
                          for name in robot.joint_names]]
    assert_transform_close(robot.link_frames(at_ref)[-2], _mujoco_tool(model, robot, at_ref[None], "cart",
                                                                       "l4")[0], 1e-12, 1e-12)


def test_masses_of_fixed_bodies_side_branches_and_bodies_beyond_the_tip_join_their_link():
    robot = robot_from_mjcf(ODD, base="cart", tip="tcp")
    masses = [joint.inertial.mass for joint in robot.chain.joints]
    np.testing.assert_allclose(masses, [1.5, 0.0, 1.1 + 0.4, 0.7 + 0.2, 0.3 + 0.25])
    robot_world = robot_from_mjcf(ODD.replace('<freejoint name="float"/>', ""), tip="tcp")
    model = mujoco.MjModel.from_xml_string(ODD.replace('<freejoint name="float"/>', ""))
    rng = np.random.default_rng(8)
    for q in robot_world.random_q(10, rng=9):
        qd = rng.uniform(-1, 1, robot_world.n)
        M, bias = _mujoco_dynamics(model, robot_world, q, qd)
        np.testing.assert_allclose(robot_world.mass_matrix(q), M, rtol=1e-10, atol=1e-12)
        np.testing.assert_allclose(robot_world.inverse_dynamics(q, qd, np.zeros(robot_world.n)), bias,
                                   rtol=1e-10, atol=1e-10)


@pytest.mark.parametrize("name", ["puma560", "probot-anno", "grb400-scara"])
def test_armkits_own_mjcf_export_loads_back_with_the_same_kinematics(tmp_path, name):
    original = armkit.load(name)
    path = write_mjcf(original, tmp_path / f"{name}.xml")
    robot = armkit.load(path)
    assert robot.joint_names == original.joint_names and robot.joint_types == original.joint_types
    np.testing.assert_allclose(robot.limits, original.limits)
    q = original.random_q(200, rng=10)
    assert_transform_close(robot.fk(q), original.fk(q), 1e-12, 1e-12)
    model = mujoco.MjModel.from_xml_path(str(path))
    assert_transform_close(robot.fk(q), _mujoco_tool(model, robot, q, "world", "tool"), 1e-12, 1e-12)
    # the masses the export wrote (the robot's own, or estimated; PUMA link 1 raised to a rigid body's)
    qd = np.random.default_rng(11).uniform(-1, 1, robot.n)
    M, bias = _mujoco_dynamics(model, robot, q[0], qd)
    np.testing.assert_allclose(robot.mass_matrix(q[0]), M, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(robot.inverse_dynamics(q[0], qd, np.zeros(robot.n)), bias, rtol=1e-10,
                               atol=1e-10)


def test_velocity_acceleration_and_torque_limits_survive_an_mjcf_round_trip(tmp_path):
    # MJCF has no element for them: the export writes custom numerics, the import reads them back.
    from dataclasses import replace

    from armkit.chain import Chain

    original = armkit.load("puma560")
    joints = [replace(joint, max_velocity=1.0 + i, max_acceleration=10.0 + i,
                      max_torque=None if i == 2 else 100.0 + i)
              for i, joint in enumerate(original.chain.joints)]
    chain = Chain(joints, original.chain.T_base, original.chain.T_tool)
    arm = armkit.Robot(chain, name="limited")
    robot = armkit.load(write_mjcf(arm, tmp_path / "limited.xml"))
    for read, written in zip(robot.chain.joints, joints, strict=True):
        assert (read.max_velocity, read.max_acceleration, read.max_torque) == \
            (written.max_velocity, written.max_acceleration, written.max_torque)


@pytest.mark.parametrize("data", ["1 2", "-1", "0", "nan"])
def test_a_bad_limit_numeric_is_one_error_naming_it(data):
    text = (f'<mujoco><worldbody><body name="l1"><joint name="j1" axis="0 1 0"/><geom size="0.05"/>'
            f'<body name="f" pos="0 0 .5"/></body></worldbody>'
            f'<custom><numeric name="armkit:j1:max_velocity" data="{data}"/></custom></mujoco>')
    message = "MJCF text, custom numeric 'armkit:j1:max_velocity': expected one finite number > 0 .the max_v"
    with pytest.raises(RobotDefinitionError, match=message), warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        robot_from_mjcf(text)
    nan_warning = "MJCF text: MuJoCo warns: XML contains a 'NaN'. Please check it carefully."
    assert [str(w.message) for w in said] == ([nan_warning] if data == "nan" else [])


def test_every_command_taking_robot_reads_an_mjcf_file(ur5e_file):
    from armkit.cli.main import app

    result = CliRunner().invoke(app, ["fk", str(ur5e_file), "0", "-1", "1", "0", "1", "0", "--tip",
                                      "attachment_site", "--json"])
    assert result.exit_code == 0, result.output
    robot = armkit.load(ur5e_file, tip="attachment_site")
    import json

    position = json.loads(result.output)["position"]
    np.testing.assert_allclose(position, robot.fk([0, -1, 1, 0, 1, 0])[:3, 3], atol=1e-12)
    shown = CliRunner().invoke(app, ["show", str(ur5e_file), "--tip", "wrist_2_link"])
    assert shown.exit_code == 0 and "wrist_2_joint" in shown.output and "wrist_3_joint" not in shown.output


def test_an_mjcf_file_mujoco_cannot_compile_is_one_error_naming_the_file(tmp_path):
    path = tmp_path / "bad.xml"
    path.write_text('<mujoco><worldbody><body name="a"><joint type="hinge"/><geom size="-1"/></body>'
                    '<body name="a"/></worldbody></mujoco>')
    with pytest.raises(RobotDefinitionError, match=r"bad\.xml: MuJoCo cannot compile it: .*"):
        armkit.load(path)


def test_unknown_bodies_ball_joints_and_several_leaves_are_refused_by_name():
    with pytest.raises(RobotDefinitionError, match="tip 'hand' is neither a body nor a site.*l1"):
        robot_from_mjcf(ODD, base="cart", tip="hand")
    with pytest.raises(RobotDefinitionError, match="base body 'table' is not in the model"):
        robot_from_mjcf(ODD, base="table", tip="tcp")
    with pytest.raises(RobotDefinitionError, match="a free joint on the path from 'world' to 'tcp'.*base="):
        robot_from_mjcf(ODD, tip="tcp")
    with pytest.raises(RobotDefinitionError, match="2 leaf bodies below 'cart': .*camera.*gripper"):
        robot_from_mjcf(ODD, base="cart")
    with pytest.raises(RobotDefinitionError, match="tip body 'l1' is not below base body 'l3'"):
        robot_from_mjcf(ODD, base="l3", tip="l1")
    ball = ODD.replace('type="slide" axis="-1 1 0.2" range="-0.1 0.2" ref="0.05"', 'type="ball"')
    with pytest.raises(RobotDefinitionError, match="joint 'j3' of body 'l3': a ball joint"):
        robot_from_mjcf(ball, base="cart", tip="tcp")
    with pytest.raises(RobotDefinitionError, match="no joint between bodies 'l4' and 'gripper'"):
        robot_from_mjcf(ODD, base="l4", tip="gripper")


def test_a_urdf_named_xml_is_still_read_as_urdf(tmp_path):
    path = tmp_path / "arm.xml"
    path.write_text('<?xml version="1.0"?>\n<!-- a comment --><robot name="r"><link name="a"/>'
                    '<link name="b"/><joint name="j" type="continuous"><parent link="a"/><child link="b"/>'
                    '</joint></robot>')
    robot = armkit.load(path)
    assert robot.urdf is not None and robot.joint_names == ["j"]


def test_without_mujoco_an_mjcf_file_is_one_error_naming_the_extra(ur5e_file, monkeypatch):
    import sys

    from armkit.errors import ArmkitError

    monkeypatch.setitem(sys.modules, "mujoco", None)  # import mujoco now raises ImportError
    with pytest.raises(ArmkitError, match=r"reading an MJCF file needs MuJoCo: pip install 'armkit\[sim\]'"):
        armkit.load(ur5e_file)


def test_a_nan_joint_range_is_one_error_not_an_unlimited_joint(tmp_path, monkeypatch):
    text = ('<mujoco><worldbody><body name="l1"><joint name="j1" axis="0 1 0" range="nan 1" limited="true"/>'
            '<geom size="0.05"/><body name="f" pos="0 0 .5"/></body></worldbody></mujoco>')
    message = r"MJCF text, joint 'j1': range \[nan, .*expected two finite"
    monkeypatch.chdir(tmp_path)
    with pytest.raises(RobotDefinitionError, match=message), \
            pytest.warns(UserWarning, match="MJCF text: MuJoCo warns: XML contains a 'NaN'"):
        robot_from_mjcf(text)
    assert list(tmp_path.iterdir()) == []  # MuJoCo's own handler would append to MUJOCO_LOG.TXT here


@pytest.mark.parametrize(("compiler", "joint", "shown"), [
    ("", 'type="hinge" range="nan 90"',
     r"\[nan, 90\] degrees \(<compiler angle=\"degree\">, MuJoCo's default\)"),
    ('<compiler angle="degree"/>', 'range="-45 nan"', r"\[-45, nan\] degrees"),
    ('<compiler angle="radian"/>', 'range="nan 1.25"',
     r"\[nan, 1.25\] rad \(the file's <compiler angle=\"radian\">\)"),
    ('<compiler angle="degree"/>', 'type="slide" range="nan 0.25"', r"\[nan, 0.25\] m;"),
])
def test_a_bad_joint_range_is_shown_as_the_file_wrote_it(tmp_path, monkeypatch, compiler, joint, shown):
    """Before: a range in degrees (MuJoCo's default unit) was shown in radians, [nan, 1.5707963267948966]."""
    monkeypatch.chdir(tmp_path)  # MuJoCo's own compile below may append its warning to MUJOCO_LOG.TXT here
    path = tmp_path / "arm.xml"
    path.write_text(f'<mujoco>{compiler}<worldbody><body name="l1"><joint name="j1" axis="0 1 0" {joint} '
                    f'limited="true"/><geom size="0.05"/><body name="f" pos="0 0 .5"/></body></worldbody>'
                    f'</mujoco>')
    for load in (lambda: armkit.load(path), lambda: robot_from_mjcf(path.read_text())):
        with pytest.raises(RobotDefinitionError, match=f"joint 'j1': range {shown}.*expected two finite"), \
                pytest.warns(UserWarning, match="MuJoCo warns: XML contains a 'NaN'"):
            load()
    compiled = mujoco.MjModel.from_xml_path(str(path)) if "slide" not in joint else None
    if compiled is not None:  # a compiled model does not know the file's unit: its radians, said so
        with pytest.raises(RobotDefinitionError, match=r"range \[nan, [-\d.]+\] rad, as MuJoCo compiled it|"
                                                        r"range \[-[\d.]+, nan\] rad, as MuJoCo compiled it"):
            robot_from_mjcf(compiled)


def test_without_mujocos_spec_parser_a_bad_range_is_shown_in_compiled_radians(monkeypatch, tmp_path):
    """MuJoCo before 3.2 has no MjSpec to say the file's unit: the radians are said to be MuJoCo's."""
    monkeypatch.chdir(tmp_path)
    monkeypatch.delattr(mujoco, "MjSpec")
    text = ('<mujoco><worldbody><body name="l1"><joint name="j1" axis="0 1 0" range="nan 90" limited="true"/>'
            '<geom size="0.05"/><body name="f" pos="0 0 .5"/></body></worldbody></mujoco>')
    with pytest.raises(RobotDefinitionError, match=r"range \[nan, 1.5708\] rad, as MuJoCo compiled it"), \
            pytest.warns(UserWarning, match="MuJoCo warns"):
        robot_from_mjcf(text)


@pytest.mark.parametrize(("compiler", "joint", "shown"), [
    ("", 'range="-1e300 1e300"', r"\[-1e\+300, 1e\+300\] degrees \(<compiler angle=\"degree\">"),
    ('<compiler angle="radian"/>', 'range="-3 2e6"', r"\[-3, 2e\+06\] rad \(the file's"),
    ("", 'type="slide" range="-1e7 0.5"', r"\[-1e\+07, 0.5\] m"),
])
def test_a_joint_range_beyond_max_value_is_refused_naming_the_joint(tmp_path, compiler, joint, shown):
    """Before: range="-1e300 1e300" (degrees, MuJoCo's default) loaded as limits of +-1.7e298 rad. MJCF
    says "no limits" with limited="false" (or no range), so a range beyond MAX_VALUE is refused, as
    robot files refuse it (a URDF's is read as no limit: URDF has no other way to say it)."""
    path = tmp_path / "arm.xml"
    path.write_text(f'<mujoco>{compiler}<worldbody><body name="l1"><joint name="j1" axis="0 1 0" {joint}/>'
                    f'<geom size="0.05"/><body name="f" pos="0 0 .5"/></body></worldbody></mujoco>')
    message = (rf"arm.xml, joint 'j1': range {shown}[^;]*; expected two finite numbers of magnitude at most "
               rf"1e\+06 rad \(5.73e\+07 degrees\) or m \(for no limits: limited=\"false\"")
    with pytest.raises(RobotDefinitionError, match=message):
        armkit.load(path)


def test_a_joint_range_up_to_max_value_loads_and_an_unlimited_one_has_no_limits():
    def text(joint: str) -> str:
        return (f'<mujoco><compiler angle="radian"/><worldbody><body name="l1"><joint name="j1" axis="0 1 0" '
                f'{joint}/><geom size="0.05"/><body name="f" pos="0 0 .5"/></body></worldbody></mujoco>')

    assert robot_from_mjcf(text('range="-1e6 1e6"')).limits.tolist() == [[-1e6, 1e6]]
    unlimited = robot_from_mjcf(text('range="-1e300 1e300" limited="false"'))
    assert unlimited.limits.tolist() == [[-np.inf, np.inf]]


@pytest.mark.parametrize(("body", "joint", "geom", "message"), [
    ('pos="nan 0 0"', 'axis="0 1 0"', 'size="0.05"', r"MJCF text, body 'l1': pos \[nan, 0.0, 0.0\]; expe"),
    ('pos="0 0 0"', 'axis="nan 0 0"', 'size="0.05"', r"MJCF text, joint 'j1': axis \[nan, .*\]; expected"),
    ('pos="0 0 0"', 'axis="0 1 0"', 'size="0.05" mass="nan"', r"MJCF text: MuJoCo warns that the XML"),
])
def test_non_finite_geometry_or_mass_is_one_error_naming_it(body, joint, geom, message):
    text = (f'<mujoco><worldbody><body name="l1" {body}><joint name="j1" {joint}/><geom {geom}/>'
            f'<body name="f" pos="0 0 .5"/></body></worldbody></mujoco>')
    with pytest.raises(RobotDefinitionError, match=message), \
            pytest.warns(UserWarning, match="MuJoCo warns: XML contains a 'NaN'"):
        robot_from_mjcf(text)


def test_loading_mjcf_in_threads_leaves_mujocos_warning_handler_as_it_was():
    import threading

    text = ('<mujoco><worldbody><body name="l1"><joint name="j1" axis="0 1 0"/><geom size="0.05"/>'
            '<body name="f" pos="0 0 .5"/></body></worldbody></mujoco>')
    before = mujoco.get_mju_user_warning()
    loaders = [threading.Thread(target=lambda: [robot_from_mjcf(text) for _ in range(50)]) for _ in range(4)]
    for loader in loaders:
        loader.start()
    for loader in loaders:
        loader.join()
    assert mujoco.get_mju_user_warning() is before


def test_the_cli_shows_mujocos_warning_as_one_line(tmp_path, capsys):
    from armkit.cli.main import main

    path = tmp_path / "a.xml"
    path.write_text('<mujoco><worldbody><body name="l1"><joint name="j1" axis="0 1 0" range="0 nan" '
                    'limited="true"/><geom size="0.05"/><body name="f" pos="0 0 .5"/></body></worldbody>'
                    '</mujoco>')
    assert main(["show", str(path)]) == 1
    lines = capsys.readouterr().err.strip().splitlines()
    assert lines == [f"warning: {path}: MuJoCo warns: XML contains a 'NaN'. Please check it carefully.",
                     f"error: {path}, joint 'j1': range [0, nan] degrees (<compiler angle=\"degree\">, "
                     f"MuJoCo's default); expected two finite numbers of magnitude at most 1e+06 rad "
                     f"(5.73e+07 degrees) or m (for no limits: limited=\"false\", or no range)"]
