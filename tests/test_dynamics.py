"""Dynamics: against pinocchio on example-robot-data's arms, against hand-derived 2R and RP arms,
forward(inverse) round trips, locked joints, payloads, estimated inertia and every error."""

from __future__ import annotations

import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit
from armkit import dynamics
from armkit.chain import DHRow
from armkit.errors import InputError, RobotDefinitionError
from armkit.inertial import Inertial
from armkit.kinematics import joint_frames

G = 9.81


# ------------------------------------------------------------------ hand-derived arms
def planar_2r(m1=1.3, m2=0.7, l1=0.9, c1=0.4, c2=0.35, i1=0.05, i2=0.02):
    """A planar 2R arm in the x-y plane (joints about z), links along x, centres of mass at c1, c2."""
    return armkit.Robot.from_dh(
        [DHRow(0, l1, 0, 0), DHRow(0, 0.8, 0, 0)], "standard",
        inertials=[Inertial.from_values(m1, [c1 - l1, 0, 0], [0.01, 0.03, i1]),
                   Inertial.from_values(m2, [c2 - 0.8, 0, 0], [0.01, 0.02, i2])])


def test_a_planar_2r_arm_has_the_textbook_equations_of_motion():
    """Spong, Hutchinson and Vidyasagar's 2R arm, gravity along -y (in the arm's plane)."""
    m1, m2, l1, c1, c2, i1, i2 = 1.3, 0.7, 0.9, 0.4, 0.35, 0.05, 0.02
    robot = planar_2r(m1, m2, l1, c1, c2, i1, i2)
    gravity = [0.0, -G, 0.0]
    rng = np.random.default_rng(3)
    q, qd, qdd = rng.uniform(-3, 3, (3, 50, 2))
    cos2 = np.cos(q[:, 1])
    d11 = m1 * c1**2 + m2 * (l1**2 + c2**2 + 2 * l1 * c2 * cos2) + i1 + i2
    d12 = m2 * (c2**2 + l1 * c2 * cos2) + i2
    d22 = m2 * c2**2 + i2
    h = -m2 * l1 * c2 * np.sin(q[:, 1])
    g1 = (m1 * c1 + m2 * l1) * G * np.cos(q[:, 0]) + m2 * c2 * G * np.cos(q.sum(axis=1))
    g2 = m2 * c2 * G * np.cos(q.sum(axis=1))
    M = np.stack([np.stack([d11, d12], -1), np.stack([d12, np.full_like(d11, d22)], -1)], -2)
    coriolis = np.stack([h * (2 * qd[:, 0] * qd[:, 1] + qd[:, 1] ** 2), -h * qd[:, 0] ** 2], -1)
    gravity_torque = np.stack([g1, g2], -1)
    np.testing.assert_allclose(robot.mass_matrix(q), M, rtol=1e-13, atol=1e-13)
    np.testing.assert_allclose(robot.coriolis_torques(q, qd), coriolis, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(robot.gravity_torques(q, gravity=gravity), gravity_torque,
                               rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(robot.inverse_dynamics(q, qd, qdd, gravity=gravity),
                               np.einsum("kij,kj->ki", M, qdd) + coriolis + gravity_torque,
                               rtol=1e-12, atol=1e-12)


def test_an_rp_arm_prismatic_joint_has_the_textbook_equations_of_motion():
    """A revolute joint about z, then a prismatic joint sliding along the rotating x axis:
    M = diag(I1 + I2 + m2 r^2, m2), Coriolis 2 m2 r rd thd, centrifugal -m2 r thd^2."""
    m1, m2, i1, i2 = 2.0, 0.5, 0.04, 0.01
    robot = armkit.Robot.from_dh(
        [DHRow(0, 0, 0, -np.pi / 2), DHRow(-np.pi / 2, 0, 0, 0, joint="prismatic")], "modified",
        inertials=[Inertial.from_values(m1, [0, 0, 0], [0, 0, i1]),
                   Inertial.from_values(m2, [0, 0, 0], [i2, i2, i2])],
        limits=[(-np.pi, np.pi), (-2.0, 2.0)])
    # the slide's axis is radial, turning with the first joint in the base x-y plane
    frames, _ = joint_frames(robot, [[0.0, 0.0], [0.5, 0.0]])
    np.testing.assert_allclose(frames[:, 1, :3, 2], [[1.0, 0.0, 0.0], [np.cos(0.5), np.sin(0.5), 0.0]],
                               atol=1e-15)
    rng = np.random.default_rng(5)
    theta, r, thd, rd, thdd, rdd = rng.uniform(-1.5, 1.5, (6, 40))
    q, qd, qdd = np.stack([theta, r], -1), np.stack([thd, rd], -1), np.stack([thdd, rdd], -1)
    M = np.zeros((40, 2, 2))
    M[:, 0, 0] = i1 + i2 + m2 * r**2
    M[:, 1, 1] = m2
    np.testing.assert_allclose(robot.mass_matrix(q), M, rtol=1e-13, atol=1e-13)
    coriolis = np.stack([2 * m2 * r * rd * thd, -m2 * r * thd**2], -1)
    np.testing.assert_allclose(robot.coriolis_torques(q, qd), coriolis, rtol=1e-12, atol=1e-12)
    gravity = np.array([0.0, -G, 0.0])  # in the plane: the slide's weight along its axis and across it
    expected = np.stack([m2 * G * r * np.cos(theta), m2 * G * np.sin(theta)], -1)
    np.testing.assert_allclose(robot.gravity_torques(q, gravity=gravity), expected, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(robot.inverse_dynamics(q, qd, qdd, gravity=gravity),
                               np.einsum("kij,kj->ki", M, qdd) + coriolis + expected, rtol=1e-12, atol=1e-12)


# ------------------------------------------------------------------ properties
ARMS_WITH_INERTIA = ["puma560", "stanford", "probot-anno", "grb400-scara", "ur5"]


def arm(name: str) -> armkit.Robot:
    robot = armkit.load(name)
    return robot if robot.chain.joints[0].inertial is not None else robot.with_estimated_inertia(1200.0)


@settings(max_examples=40, deadline=None)
@given(st.sampled_from(ARMS_WITH_INERTIA), st.integers(0, 2**32 - 1))
def test_forward_dynamics_inverts_inverse_dynamics(name, seed):
    robot = arm(name)
    rng = np.random.default_rng(seed)
    q = robot.random_q(4, rng=rng)
    qd, qdd = rng.normal(0, 2, (2, 4, robot.n))
    gravity = rng.normal(0, 10, 3)
    tau = robot.inverse_dynamics(q, qd, qdd, gravity=gravity)
    np.testing.assert_allclose(robot.forward_dynamics(q, qd, tau, gravity=gravity), qdd, rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("name", ARMS_WITH_INERTIA)
def test_the_parts_add_up_and_the_mass_matrix_is_symmetric_positive_definite(name):
    robot = arm(name)
    rng = np.random.default_rng(8)
    q = robot.random_q(30, rng=rng)
    qd, qdd = rng.normal(0, 1.5, (2, 30, robot.n))
    M = robot.mass_matrix(q)
    assert np.array_equal(M, np.swapaxes(M, -1, -2))
    assert np.linalg.eigvalsh(M).min() > 0
    total = np.einsum("kij,kj->ki", M, qdd) + robot.coriolis_torques(q, qd) + robot.gravity_torques(q)
    np.testing.assert_allclose(robot.inverse_dynamics(q, qd, qdd), total, rtol=1e-10, atol=1e-10)


def test_kinetic_energy_rate_is_the_power_of_the_coriolis_free_torques():
    """d/dt (qd^T M qd / 2) = qd^T (tau - g) along any motion (M-dot - 2C skew), by finite differences."""
    robot = arm("puma560")
    rng = np.random.default_rng(2)
    q, qd, qdd = robot.random_q(rng=rng), rng.normal(size=6), rng.normal(size=6)
    h = 1e-6

    def energy(t: float) -> float:
        q_t, qd_t = q + qd * t + qdd * t**2 / 2, qd + qdd * t
        return 0.5 * qd_t @ robot.mass_matrix(q_t) @ qd_t

    rate = (energy(h) - energy(-h)) / (2 * h)
    power = qd @ (robot.inverse_dynamics(q, qd, qdd) - robot.gravity_torques(q))
    assert rate == pytest.approx(power, rel=1e-7)


def test_batches_match_single_states_whatever_the_thread_count():
    robot = arm("puma560")
    rng = np.random.default_rng(4)
    q = robot.random_q((5000,), rng=rng)
    qd, qdd = rng.normal(size=(2, 5000, 6))
    one = robot.inverse_dynamics(q, qd, qdd, threads=1)
    assert np.array_equal(one, robot.inverse_dynamics(q, qd, qdd, threads=2))
    assert np.array_equal(one[1234], robot.inverse_dynamics(q[1234], qd[1234], qdd[1234]))
    assert np.array_equal(robot.mass_matrix(q, threads=1), robot.mass_matrix(q, threads=2))
    assert np.array_equal(robot.forward_dynamics(q, qd, one, threads=1),
                          robot.forward_dynamics(q, qd, one, threads=2))
    shaped = [a.reshape(50, 100, 6) for a in (q, qd, qdd)]
    np.testing.assert_array_equal(robot.inverse_dynamics(*shaped), one.reshape(50, 100, 6))
    # broadcasting: one configuration, many velocities
    np.testing.assert_array_equal(robot.inverse_dynamics(q[0], qd[:3]),
                                  robot.inverse_dynamics(np.broadcast_to(q[0], (3, 6)), qd[:3]))


def test_a_locked_robot_carries_its_locked_links():
    """Torques of the free joints equal the full robot's with the locked joints still at their values."""
    full = arm("puma560")
    locked = full.lock({"q2": 0.4, "q5": -0.3})
    rng = np.random.default_rng(6)
    q, qd, qdd = locked.random_q(10, rng=rng), rng.normal(size=(10, 4)), rng.normal(size=(10, 4))
    zero = np.zeros((10, 6))
    qd_full, qdd_full = zero.copy(), zero.copy()
    qd_full[:, locked.free], qdd_full[:, locked.free] = qd, qdd
    expected = full.inverse_dynamics(locked.full_q(q), qd_full, qdd_full)[:, locked.free]
    np.testing.assert_allclose(locked.inverse_dynamics(q, qd, qdd), expected, rtol=1e-12, atol=1e-12)
    full_M = full.mass_matrix(locked.full_q(q))
    np.testing.assert_allclose(locked.mass_matrix(q), full_M[:, locked.free][:, :, locked.free], atol=1e-12)


def test_a_payload_adds_its_weight_through_the_jacobian_and_keeps_the_links_own():
    robot = arm("puma560")
    com = np.array([0.02, -0.01, 0.15])
    loaded = robot.with_payload(2.5, com, [0.01, 0.02, 0.03])
    assert loaded.chain.joints[-1].inertial.mass == pytest.approx(robot.chain.joints[-1].inertial.mass + 2.5)
    q = robot.random_q(20, rng=9)
    # the payload's centre, as a point on a tool extended by com: its weight through that point's Jacobian
    T_tool = np.eye(4)
    T_tool[:3, 3] = com
    point = armkit.Robot(armkit.Chain(robot.chain.joints, robot.chain.T_base, robot.chain.T_tool @ T_tool))
    J = point.jacobian(q)[:, :3]
    expected = robot.gravity_torques(q) - 2.5 * np.einsum("kij,i->kj", J, dynamics.GRAVITY)
    np.testing.assert_allclose(loaded.gravity_torques(q), expected, rtol=1e-12, atol=1e-12)
    assert np.array_equal(robot.with_payload(0.0).inverse_dynamics(q), robot.inverse_dynamics(q))


def test_estimated_inertia_is_export_s_capsules_scaled_by_density():
    from armkit.export.physical import DENSITY, physical_model

    robot = armkit.load("probot-anno")
    model = physical_model(robot)
    estimated = robot.with_estimated_inertia(density=2 * DENSITY)
    masses = [j.inertial.mass for j in estimated.chain.joints]
    np.testing.assert_allclose(masses, [2 * b.mass for b in model.bodies], rtol=1e-14)
    assert type(robot.lock({0: 0.1}).with_estimated_inertia()) is armkit.LockedRobot


def test_max_torque_from_a_robot_file_and_inf_where_none():
    robot = armkit.robot_from_dict({
        "convention": "standard",
        "joints": [{"a": 1, "alpha": 0, "d": 0, "theta": 0, "max_torque": 20, "mass": 1},
                   {"a": 1, "alpha": 0, "d": 0, "theta": 0, "mass": 2, "com": [-0.5, 0, 0]}]})
    assert robot.max_torque.tolist() == [20.0, np.inf]
    expected = [G * (1 + 2 * 1.5), G * 2 * 0.5]
    assert robot.gravity_torques([0, 0], gravity=[0, -G, 0]) == pytest.approx(expected, rel=1e-14)


def test_robot_files_in_millimetres_convert_com_and_inertia_and_write_them_back():
    data = {"convention": "modified", "length_unit": "mm", "angle_unit": "deg",
            "joints": [{"a": 0, "alpha": 0, "d": 0, "theta": 0, "mass": 1, "com": [100, 0, 0],
                        "inertia": [[1e4, 0, 0], [0, 2e4, 0], [0, 0, 3e4]]},
                       {"a": 300, "alpha": 90, "d": 0, "theta": 0, "mass": 0.5, "inertia": [1e3, 1e3, 1e3]}]}
    robot = armkit.robot_from_dict(data)
    np.testing.assert_allclose(robot.chain.joints[0].inertial.com, [0.1, 0, 0])
    np.testing.assert_allclose(robot.chain.joints[0].inertial.inertia.diagonal(), [0.01, 0.02, 0.03])
    import tomllib

    again = armkit.robot_from_dict(tomllib.loads(armkit.robot_to_toml(robot)))
    q = robot.random_q(5, rng=1)
    np.testing.assert_allclose(again.mass_matrix(q), robot.mass_matrix(q), rtol=1e-13, atol=1e-15)


def test_poe_robots_take_inertia_in_the_base_frame_and_a_urdf_robot_writes_back_as_poe():
    urdf = armkit.load("ur5").with_estimated_inertia()
    import tomllib

    poe = armkit.robot_from_dict(tomllib.loads(armkit.robot_to_toml(urdf.lock({0: 0.2}))))
    locked = urdf.lock({0: 0.2})
    q = locked.random_q(5, rng=2)
    qd = np.ones((5, 5))
    np.testing.assert_allclose(poe.inverse_dynamics(q, qd, qd), locked.inverse_dynamics(q, qd, qd),
                               rtol=1e-12, atol=1e-12)


# ------------------------------------------------------------------ errors
def test_an_arm_without_inertia_is_refused_naming_the_joint_and_the_way_out():
    robot = armkit.load("ur5")
    for call in (lambda: robot.inverse_dynamics(robot.home), lambda: robot.mass_matrix(robot.home),
                 lambda: robot.forward_dynamics(robot.home, robot.home, robot.home),
                 lambda: robot.with_payload(1.0)):
        with pytest.raises(RobotDefinitionError,
                           match=r"joint q1 has no inertial parameters.*with_estimated_inertia"):
            call()


def test_bad_states_gravity_payload_and_density_are_refused():
    robot = arm("puma560")
    with pytest.raises(InputError,
                       match=r"q: the robot has 6 joints, so expected shape \(\.\.\., 6\), got shape \(5,\)"):
        robot.mass_matrix(np.zeros(5))
    with pytest.raises(InputError, match=r"qd: expected finite joint values, got nan at index 2"):
        robot.inverse_dynamics(np.zeros(6), [0, 0, np.nan, 0, 0, 0], np.zeros(6))
    with pytest.raises(InputError, match=r"q: expected finite joint values, got inf"):
        robot.inverse_dynamics(np.array([np.inf, 0, 0, 0, 0, 0]), np.zeros(6), np.zeros(6))
    with pytest.raises(InputError, match=r"tau: expected 6 numbers per state"):
        robot.forward_dynamics(np.zeros(6), np.zeros(6), "x")
    with pytest.raises(InputError, match=r"q \(2, 6\), qd \(3, 6\): expected shapes that broadcast"):
        robot.inverse_dynamics(np.zeros((2, 6)), np.zeros((3, 6)))
    with pytest.raises(InputError, match=r"gravity: expected 3 finite numbers"):
        robot.gravity_torques(np.zeros(6), gravity=[0, 0])
    with pytest.raises(InputError, match=r"threads: expected None \(every core\) or a whole number of "):
        robot.mass_matrix(np.zeros(6), threads=-1)
    with pytest.raises(InputError, match=r"payload: mass = -1.0 kg; expected a finite number >= 0"):
        robot.with_payload(-1.0)
    with pytest.raises(InputError, match=r"payload: inertia = .* is not symmetric"):
        robot.with_payload(1.0, inertia=[[1, 2, 0], [0, 1, 0], [0, 0, 1]])
    for density in (-5, 1e-300, 1e308, "1000", True):  # 1e-300 / 1e308: another unit, absurd links
        message = rf"density \[kg/m\^3\]: expected a density from 1 to 100000, got {re.escape(repr(density))}"
        with pytest.raises(InputError, match=message):
            robot.with_estimated_inertia(density=density)


def test_a_joint_that_moves_no_mass_makes_forward_dynamics_say_so():
    robot = armkit.Robot.from_dh([DHRow(0, 1.0, 0, 0), DHRow(0, 1.0, 0, 0)], "standard",
                                 inertials=[Inertial.from_values(1.0, [0, 0, 0], [0, 0, 0]), Inertial.zero()])
    with pytest.raises(RobotDefinitionError, match=r"^the mass matrix \(q = \[0.0, 0.5\]\) is not positive "
                                                   r"definite: some joint moves no mass or inertia"):
        robot.forward_dynamics([0.0, 0.5], np.zeros(2), np.zeros(2))
    with pytest.raises(RobotDefinitionError,
                       match=r"mass matrix at state \(0, 0\) \(q = \[0.1, 0.2\]\) is not"):
        robot.forward_dynamics([[[0.1, 0.2], [0.0, 0.5]]], np.zeros(2), np.zeros(2))


@pytest.mark.parametrize(("joint", "message"), [
    ({"com": [0, 0, 0]}, r"joint 1, key 'com': needs 'mass' \[kg\] too"),
    ({"mass": -2}, r"joint 1, key 'mass': expected a mass from 0 to 1e\+06 kg, got -2"),
    ({"mass": 1e300}, r"joint 1, key 'mass': expected a mass from 0 to 1e\+06 kg, got 1e\+300"),
    ({"mass": 1, "inertia": [1, 2]}, r"joint 1, key 'inertia': expected 3 numbers \(the diagonal\) or a 3x3"),
    ({"mass": 1, "inertia": [[1, 2, 0], [0, 1, 0], [0, 0, 1]]}, r"joint 1: inertia = .* is not symmetric"),
    ({"mass": 1, "max_torque": 0}, r"joint 1, key 'max_torque': expected a positive number, got 0"),
])
def test_robot_file_inertia_mistakes_name_the_joint_and_key(joint, message):
    data = {"convention": "standard", "joints": [{"a": 1, "alpha": 0, "d": 0, "theta": 0, **joint}]}
    with pytest.raises(RobotDefinitionError, match=message):
        armkit.robot_from_dict(data)


def test_a_robot_file_with_mass_on_some_joints_only_is_refused():
    row = {"a": 1, "alpha": 0, "d": 0, "theta": 0}
    with pytest.raises(RobotDefinitionError, match=r"joint 2: no 'mass' while joint 1 has one"):
        armkit.robot_from_dict({"convention": "standard", "joints": [{**row, "mass": 1}, row]})


URDF = """<robot name="r">
  <link name="a"/>
  <link name="b">{inertial}</link>
  <joint name="j1" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" velocity="1" effort="{effort}"/></joint>
</robot>"""


def test_urdf_inertial_and_effort_are_read():
    inertial = ('<inertial><origin xyz="0.5 0 0" rpy="0 0 1.5707963267948966"/><mass value="2"/>'
                '<inertia ixx="0.1" ixy="0" ixz="0" iyy="0.3" iyz="0" izz="0.4"/></inertial>')
    robot = armkit.urdf.robot_from_urdf(URDF.format(inertial=inertial, effort="12.5"))
    assert robot.max_torque.tolist() == [12.5]
    body = robot.chain.joints[0].inertial
    np.testing.assert_allclose(body.com, [0.5, 0, 0], atol=1e-15)
    np.testing.assert_allclose(body.inertia.diagonal(), [0.3, 0.1, 0.4], atol=1e-15)  # turned 90 deg about z
    assert robot.mass_matrix([0.0])[0, 0] == pytest.approx(0.4 + 2 * 0.25)
    no_inertia = armkit.urdf.robot_from_urdf(URDF.format(inertial="", effort="0"))
    assert no_inertia.max_torque.tolist() == [np.inf] and no_inertia.chain.joints[0].inertial is None


@pytest.mark.parametrize(("inertial", "message"), [
    ("<inertial/>", r"link 'b': <inertial> has no <mass value"),
    ('<inertial><mass value="-1"/></inertial>', r"link 'b': <mass value=\"-1\">: expected a mass >= 0 kg"),
    ('<inertial><mass value="1"/><inertia ixx="nan"/></inertial>',
     r"link 'b': <inertia ixx=\"nan\">: expected 1"),
    ('<inertial><mass value="1"/><inertia ixx="1e308"/></inertial>',
     r"link 'b': <inertia ixx=\"1e308\">: expected 1 finite number of magnitude at most 1e\+06"),
])
def test_urdf_inertial_mistakes_name_the_link(inertial, message):
    with pytest.raises(RobotDefinitionError, match=message):
        armkit.urdf.robot_from_urdf(URDF.format(inertial=inertial, effort="1"))


def test_one_state_in_any_form_gives_the_batch_answer_in_its_shape():
    robot = arm("puma560")
    q, qd, qdd = robot.random_q(rng=1), np.full(6, 0.25), np.full(6, -0.5)  # float32-exact
    expected = robot.inverse_dynamics(q[None], qd[None], qdd[None], threads=1)
    assert expected.shape == (1, 6)
    for args in ((q, qd, qdd), (q.tolist(), qd.tolist(), qdd.tolist()), (q, qd.astype(np.float32), qdd)):
        np.testing.assert_allclose(robot.inverse_dynamics(*args), expected[0], rtol=1e-15)
    assert robot.mass_matrix(q[None]).shape == (1, 6, 6)
    np.testing.assert_allclose(robot.mass_matrix(q), robot.mass_matrix(q[None])[0], rtol=1e-15)
    tau = expected[0]
    np.testing.assert_allclose(robot.forward_dynamics(q, qd, tau), qdd, rtol=1e-10, atol=1e-12)
    with pytest.raises(InputError, match=r"tau: expected finite joint values, got nan at index 5"):
        robot.forward_dynamics(q, qd, np.array([0, 0, 0, 0, 0, np.nan]))
