"""MJCF export: every built-in loads in MuJoCo and MuJoCo's FK equals armkit's."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest
from conftest import assert_transform_close

import armkit
from armkit.errors import InputError, RobotDefinitionError
from armkit.export import mjcf_from_robot, physical_model, write_mjcf
from armkit.sim import Simulation

BUILTINS = armkit.builtin_robots()


def zero_length_robot() -> armkit.Robot:
    return armkit.robot_from_dict({"convention": "modified", "joints": [
        {"alpha": 0, "a": 0, "d": 0, "theta": 0}, {"alpha": 90, "a": 0, "d": 0, "theta": 0}],
        "angle_unit": "deg"}, "point-arm.toml")


@pytest.mark.parametrize("name", BUILTINS)
def test_mjcf_tool_site_matches_fk_at_random_configurations(name):
    robot = armkit.load(name)
    sim = Simulation(robot, gravity=False)
    q = robot.random_q(20, rng=7)
    assert_transform_close(sim.tool_pose(q), robot.fk(q), position_tol=1e-6, angle_tol=1e-6)
    assert_transform_close(sim.tool_pose(q), robot.fk(q), position_tol=1e-12, angle_tol=1e-12)


@pytest.mark.parametrize("name", BUILTINS)
def test_mjcf_structure_limits_and_servos(name):
    robot = armkit.load(name)
    model = mujoco.MjModel.from_xml_string(mjcf_from_robot(robot))
    assert model.njnt == robot.n and model.nu == 2 * robot.n
    kinds = [mujoco.mjtJoint.mjJNT_SLIDE if p else mujoco.mjtJoint.mjJNT_HINGE for p in robot.chain.prismatic]
    assert model.jnt_type.tolist() == [int(k) for k in kinds]
    np.testing.assert_allclose(model.jnt_range, robot.limits, rtol=0, atol=1e-15)
    assert np.all(model.body_mass[1:-1] > 0) and model.body_mass[-1] == 0  # moving links; massless tool
    assert mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, model.nbody - 1) == "tool"
    assert np.all(model.actuator_gainprm[0::2, 0] > 0) and np.all(model.actuator_gainprm[1::2, 0] > 0)
    assert mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, "tool") >= 0
    np.testing.assert_allclose(model.opt.timestep, 1e-3)


def test_base_frame_is_world_origin():
    robot = armkit.load("probot-anno")
    sim = Simulation(robot, gravity=False)
    sim.tool_pose(np.zeros(6))
    np.testing.assert_allclose(sim.data.xpos[0], 0.0)
    np.testing.assert_allclose(sim.data.xpos[1], 0.0)  # joint 1 frame (modified DH: before d1)
    np.testing.assert_allclose(sim.data.xpos[2], [0, 0, 0.284], atol=1e-15)


def test_gravity_option_is_written():
    robot = armkit.load("zju-i")
    on = mujoco.MjModel.from_xml_string(mjcf_from_robot(robot, gravity=True))
    off = mujoco.MjModel.from_xml_string(mjcf_from_robot(robot, gravity=False))
    np.testing.assert_allclose(on.opt.gravity, [0, 0, -9.81])
    np.testing.assert_allclose(off.opt.gravity, 0.0)


def test_inertia_is_physical():
    for name in BUILTINS:
        for body in physical_model(armkit.load(name)).bodies:
            eigenvalues = np.linalg.eigvalsh(body.inertia)
            assert np.all(eigenvalues > 0)
            a, b, c = eigenvalues  # triangle inequality of principal moments
            assert c <= a + b + 1e-15


def test_zero_length_chain_cannot_be_simulated():
    with pytest.raises(RobotDefinitionError, match="cannot be simulated: every link offset is zero"):
        mjcf_from_robot(zero_length_robot())
    with pytest.raises(RobotDefinitionError, match="point-arm|cannot be simulated"):
        Simulation(zero_length_robot())


def test_write_mjcf_refuses_to_overwrite(tmp_path):
    robot = armkit.load("stanford")
    path = tmp_path / "arm.xml"
    write_mjcf(robot, path)
    first = path.read_text()
    path.write_text("user's file")
    with pytest.raises(InputError, match="already exists; pass overwrite=True"):
        write_mjcf(robot, path)
    assert path.read_text() == "user's file"
    write_mjcf(robot, path, overwrite=True)
    assert path.read_text() == first
    with pytest.raises(InputError, match="does not exist"):
        write_mjcf(robot, tmp_path / "missing" / "arm.xml")


def test_rounded_angles_leave_no_degenerate_capsules():
    """alpha = 1.5707963 (not quite pi/2) leaves sub-micron offsets that MuJoCo would reject as capsules."""
    robot = armkit.robot_from_dict({"convention": "standard", "joints": [
        {"alpha": 1.5707963, "a": 0, "d": 0.3, "theta": 0},
        {"alpha": 1.5707963, "a": 0, "d": 0, "theta": 1.5707963},
        {"type": "prismatic", "alpha": 0, "a": 0, "d": 0.2, "theta": 0, "limits": [0.1, 0.5]}]}, "rrp.toml")
    sim = Simulation(robot, gravity=False)
    q = robot.random_q(20, rng=5)
    assert_transform_close(sim.tool_pose(q), robot.fk(q), position_tol=1e-12, angle_tol=1e-12)
