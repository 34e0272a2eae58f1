"""Exported MJCF and URDF carry the robot's own inertials: MuJoCo's ``mj_inverse`` and pinocchio's
``rnea`` on the exported files agree with armkit's inverse dynamics (prismatic joints too)."""

from __future__ import annotations

from importlib.metadata import distribution
from pathlib import Path

import numpy as np
import pytest

import armkit
from armkit.export import mjcf_from_robot, urdf_from_robot

mujoco = pytest.importorskip("mujoco")
pinocchio = pytest.importorskip("pinocchio")

ERD = Path(distribution("example-robot-data").locate_file("cmeel.prefix/share/example-robot-data/robots"))
# arms with physical inertias (every principal moment at most the sum of the other two): the URDFs'
# own, and estimates (a prismatic joint in the Stanford arm and the SCARA)
ROBOTS = ["stanford", "grb400-scara", "probot-anno", "ur_description/urdf/ur5_robot.urdf:tool0",
          "panda_description/urdf/panda.urdf:panda_hand_tcp"]


def with_inertia(name: str) -> armkit.Robot:
    if ":" in name:
        file, tip = name.split(":")
        return armkit.load(ERD / file, tip=tip)
    return armkit.load(name).with_estimated_inertia(1500.0)


@pytest.mark.parametrize("name", ROBOTS)
def test_mujoco_inverse_dynamics_of_the_exported_mjcf_equals_armkits(name):
    robot = with_inertia(name).with_payload(1.2, [0.01, 0.02, 0.05], [0.002, 0.003, 0.001])
    model = mujoco.MjModel.from_xml_string(mjcf_from_robot(robot))
    data = mujoco.MjData(model)
    rng = np.random.default_rng(1)
    for q in robot.random_q(20, rng=rng):
        qd, qdd = rng.normal(0, 1.0, (2, robot.n))
        data.qpos[:], data.qvel[:], data.qacc[:] = q, qd, qdd
        mujoco.mj_inverse(model, data)
        # the MJCF's joints also carry a reflected rotor inertia (armature): its torque comes on top
        expected = data.qfrc_inverse - model.dof_armature * qdd
        tau = robot.inverse_dynamics(q, qd, qdd)
        np.testing.assert_allclose(tau, expected, rtol=1e-9, atol=1e-9 * np.abs(expected).max())


@pytest.mark.parametrize("name", ROBOTS)
def test_pinocchio_on_the_exported_urdf_equals_armkit(name):
    robot = with_inertia(name)
    model = pinocchio.buildModelFromXML(urdf_from_robot(robot))
    data = model.createData()
    rng = np.random.default_rng(2)
    for q in robot.random_q(10, rng=rng):
        qd, qdd = rng.normal(0, 1.0, (2, robot.n))
        q_pin = np.concatenate([[v] if j.nq == 1 else [np.cos(v), np.sin(v)]
                                for v, j in zip(q, model.joints[1:], strict=True)])
        expected = pinocchio.rnea(model, data, q_pin, qd, qdd)
        np.testing.assert_allclose(robot.inverse_dynamics(q, qd, qdd), expected,
                                   rtol=1e-10, atol=1e-10 * np.abs(expected).max())
        M = pinocchio.crba(model, data, q_pin)
        np.testing.assert_allclose(robot.mass_matrix(q), np.triu(M) + np.triu(M, 1).T,
                                   rtol=1e-10, atol=1e-10 * np.abs(M).max())


def test_the_exported_urdf_keeps_the_ur5_urdf_mass_and_effort():
    robot = with_inertia("ur_description/urdf/ur5_robot.urdf:tool0")
    exported = armkit.urdf.robot_from_urdf(urdf_from_robot(robot))
    assert sum(j.inertial.mass for j in exported.chain.joints) == pytest.approx(
        sum(j.inertial.mass for j in robot.chain.joints), rel=1e-14)
    assert exported.max_torque.tolist() == robot.max_torque.tolist()
    model = mujoco.MjModel.from_xml_string(mjcf_from_robot(robot))
    assert model.body_mass[1:].sum() == pytest.approx(sum(j.inertial.mass for j in robot.chain.joints))


def test_an_inertia_no_rigid_body_has_is_made_one_keeping_its_largest_moment():
    """roboticstoolbox's PUMA 560: link 1 is massless with only a rotor moment, link 3's principal
    moments break A + B >= C. MuJoCo refuses both; the export lifts the smaller moments."""
    from armkit.export.physical import MIN_MASS, physical_model

    robot = armkit.load("puma560")
    bodies = physical_model(robot).bodies
    for joint, body in zip(robot.chain.joints, bodies, strict=True):
        own = np.linalg.eigvalsh(joint.inertial.inertia)
        exported = np.linalg.eigvalsh(body.inertia)
        assert exported[2] == pytest.approx(own[2], rel=1e-12)  # the largest moment is kept
        assert exported[0] + exported[1] >= exported[2] * (1 - 1e-12)
        if own[0] + own[1] >= own[2] and own[0] > 0:  # already physical: exactly as given
            np.testing.assert_array_equal(body.inertia, joint.inertial.moved(joint.T_after).inertia)
    assert bodies[0].mass == MIN_MASS and bodies[1].mass == 17.4
    model = mujoco.MjModel.from_xml_string(mjcf_from_robot(robot))  # MuJoCo takes it
    assert model.body_mass[1:].sum() == pytest.approx(23.45 + MIN_MASS, rel=1e-14)


def test_computed_torque_feedforward_from_armkit_tracks_better_than_bias_compensation():
    from armkit.sim import Simulation
    from armkit.trajectory import min_jerk

    robot = armkit.load("stanford").with_estimated_inertia(1000.0)  # what the simulation model has
    sim = Simulation(robot, gravity=True)
    q0 = robot.home
    traj = min_jerk([q0, q0 + [0.6, -0.4, 0.1, 0.5, 0.3, -0.6]], [1.5])
    samples = traj.sample(1000.0)
    compensated = sim.run(samples.t, samples.q, samples.qd)
    tau = robot.inverse_dynamics(samples.q, samples.qd, samples.qdd)
    feedforward = tau + sim.model.dof_armature * samples.qdd  # the MJCF's rotor inertia too
    fed = sim.run(samples.t, samples.q, samples.qd, feedforward=feedforward)
    assert fed.feedforward and not compensated.feedforward
    assert np.abs(fed.joint_error).max() < 0.5 * np.abs(compensated.joint_error).max()
    with pytest.raises(armkit.InputError, match=r"feedforward: expected shape \(1501, 6\), one torque per"):
        sim.run(samples.t, samples.q, samples.qd, feedforward=feedforward[:-1])
