"""FK, Jacobians and manipulability; cross-checked against roboticstoolbox-python where it is installed."""

import numpy as np
import pytest
from conftest import assert_transform_close
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit
from armkit import DHRow, Robot
from armkit.errors import InputError
from armkit.kinematics import (
    ChainKernel,
    fk,
    geometric_jacobian,
    joint_frames,
    link_frames,
    pose_error,
)
from armkit.spatial import matrix_from_axis_angle, rotation_angle_between, transform_from

RTB_MODELS = {"puma560": "Puma560", "stanford": "Stanford", "ur5": "UR5", "panda": "Panda"}


@pytest.mark.parametrize("name", sorted(RTB_MODELS))
def test_builtins_match_roboticstoolbox(name):
    rtb = pytest.importorskip("roboticstoolbox")
    ours = armkit.load(name)
    theirs = getattr(rtb.models.DH, RTB_MODELS[name])()
    q = ours.random_q(25, rng=0)
    T = ours.fk(q)
    J = ours.jacobian(q)
    for k in range(len(q)):
        assert_transform_close(T[k], theirs.fkine(q[k]).A)
        np.testing.assert_allclose(J[k], theirs.jacob0(q[k]), atol=1e-10)
        np.testing.assert_allclose(ours.jacobian(q[k], frame="tool"), theirs.jacobe(q[k]), atol=1e-10)


def random_dh_arm(rng, convention):
    """A random DH arm (revolute and prismatic joints, offsets, base and tool) and its rows."""
    n = int(rng.integers(2, 8))
    rows = []
    for _ in range(n):
        alpha, a, d, theta = rng.choice([0, np.pi / 2, -np.pi / 2, rng.uniform(-3, 3)]), *rng.uniform(
            -0.5, 0.5, 2), rng.uniform(-np.pi, np.pi)
        prismatic = rng.random() < 0.3
        rows.append(DHRow(alpha, a, d, theta, "prismatic" if prismatic else "revolute"))
    base_row = DHRow(*rng.uniform(-1, 1, 4), joint=None)
    tool_row = DHRow(*rng.uniform(-1, 1, 4), joint=None)
    ours = Robot.from_dh(rows, convention, base_rows=[base_row], tool_rows=[tool_row])
    return ours, (rows, base_row, tool_row)


def random_dh_pair(rng, convention):
    """The arm of :func:`random_dh_arm` in armkit and in roboticstoolbox-python (skips without it)."""
    rtb = pytest.importorskip("roboticstoolbox")
    from spatialmath import SE3

    ours, (rows, base_row, tool_row) = random_dh_arm(rng, convention)
    links = []
    for row in rows:
        alpha, a, d, theta, prismatic = row.alpha, row.a, row.d, row.theta, row.joint == "prismatic"
        if convention == "standard":
            link = (rtb.PrismaticDH(theta=theta, a=a, alpha=alpha, offset=d) if prismatic
                    else rtb.RevoluteDH(d=d, a=a, alpha=alpha, offset=theta))
        else:
            link = (rtb.PrismaticMDH(theta=theta, a=a, alpha=alpha, offset=d) if prismatic
                    else rtb.RevoluteMDH(d=d, a=a, alpha=alpha, offset=theta))
        links.append(link)
    base = SE3(base_row.transform(convention), check=False)
    tool = SE3(tool_row.transform(convention), check=False)
    return ours, rtb.DHRobot(links, base=base, tool=tool)


@pytest.mark.parametrize("convention", ["standard", "modified"])
@pytest.mark.parametrize("seed", range(10))
def test_random_dh_robots_match_roboticstoolbox(convention, seed):
    rng = np.random.default_rng(seed)
    ours, theirs = random_dh_pair(rng, convention)
    for q in ours.random_q(5, rng=rng):
        assert_transform_close(ours.fk(q), theirs.fkine(q).A)
        np.testing.assert_allclose(ours.jacobian(q), theirs.jacob0(q), atol=1e-10)


def finite_difference_jacobian(robot, q, h=1e-6):
    """Central differences of FK: linear rows from positions, angular rows from dR R^T."""
    J = np.zeros((6, robot.n))
    T0 = robot.fk(q)
    for i in range(robot.n):
        dq = np.zeros(robot.n)
        dq[i] = h
        Tp, Tm = robot.fk(q + dq), robot.fk(q - dq)
        J[:3, i] = (Tp[:3, 3] - Tm[:3, 3]) / (2 * h)
        W = (Tp[:3, :3] - Tm[:3, :3]) / (2 * h) @ T0[:3, :3].T
        J[3:, i] = [W[2, 1], W[0, 2], W[1, 0]]
    return J


@pytest.mark.parametrize("name", ["probot-anno", "zju-i", "grb400-scara", "stanford", "panda"])
@given(seed=st.integers(0, 2**31))
@settings(max_examples=10, deadline=None)
def test_jacobian_matches_finite_differences(name, seed):
    robot = armkit.load(name)
    q = robot.random_q(rng=seed)
    np.testing.assert_allclose(robot.jacobian(q), finite_difference_jacobian(robot, q), atol=1e-7)


@pytest.mark.parametrize("convention", ["xyz-fixed", "zyz-euler", "xyz-euler"])
def test_analytic_jacobian_matches_finite_differences_of_angles(convention):
    robot = armkit.load("probot-anno")
    q = np.array([0.3, -0.4, 0.5, 0.2, 0.9, -0.3])
    h = 1e-6
    numeric = np.zeros((6, robot.n))
    for i in range(robot.n):
        dq = np.zeros(robot.n)
        dq[i] = h
        plus, minus = robot.pose(q + dq, convention), robot.pose(q - dq, convention)
        numeric[:, i] = (plus - minus) / (2 * h)
    np.testing.assert_allclose(robot.analytic_jacobian(q, convention), numeric, atol=1e-7)


def test_analytic_jacobian_refuses_gimbal_lock():
    scara = armkit.load("grb400-scara")  # tool rotation is always Rz(t1 + t2 + t4): Z-Y-Z is locked
    with pytest.raises(InputError, match="gimbal lock"):
        scara.analytic_jacobian([0.3, 0.5, 0.01, 0.2], "zyz-euler")


@pytest.mark.parametrize("name", ["probot-anno", "stanford", "panda", "grb400-scara"])
def test_batches_equal_one_at_a_time(name):
    robot = armkit.load(name)
    q = robot.random_q((3, 4), rng=1)
    T, J, F = robot.fk(q), robot.jacobian(q), robot.link_frames(q)
    assert T.shape == (3, 4, 4, 4) and J.shape == (3, 4, 6, robot.n) and F.shape == (3, 4, robot.n + 2, 4, 4)
    for idx in np.ndindex(3, 4):
        np.testing.assert_allclose(T[idx], robot.fk(q[idx]), atol=1e-15)
        np.testing.assert_allclose(J[idx], robot.jacobian(q[idx]), atol=1e-15)
        np.testing.assert_allclose(F[idx], robot.link_frames(q[idx]), atol=1e-15)


@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_link_frames_are_products_of_dh_rows(convention):
    rng = np.random.default_rng(7)
    ours, _ = random_dh_arm(rng, convention)
    q = ours.random_q(rng=rng)
    frames = ours.link_frames(q)
    T = ours.dh.base_rows[0].transform(convention)
    assert_transform_close(frames[0], T)
    for i, row in enumerate(ours.dh.rows):
        moved = DHRow(row.alpha, row.a, row.d + (q[i] if row.joint == "prismatic" else 0),
                      row.theta + (q[i] if row.joint == "revolute" else 0), None)
        T = T @ moved.transform(convention)
        assert_transform_close(frames[i + 1], T)
    assert_transform_close(frames[-1], ours.fk(q))


def test_manipulability_and_singular_values():
    robot = armkit.load("puma560")
    q = robot.random_q(rng=3)
    J = robot.jacobian(q)
    assert robot.manipulability(q) == pytest.approx(np.sqrt(np.linalg.det(J @ J.T)), rel=1e-9)
    np.testing.assert_allclose(robot.singular_values(q), np.linalg.svd(J, compute_uv=False))
    wrist_singular = np.array([0.1, 0.5, -0.7, 0.3, 0.0, 0.2])  # q5 = 0: axes 4 and 6 align
    assert robot.singular_values(wrist_singular)[-1] < 1e-12
    scara = armkit.load("grb400-scara")
    Js = scara.jacobian([0.3, 0.5, 0.01, 0.2])
    assert scara.manipulability([0.3, 0.5, 0.01, 0.2]) == pytest.approx(np.sqrt(np.linalg.det(Js.T @ Js)))


def test_bad_frame_is_named():
    with pytest.raises(InputError, match="frame 'world': expected 'base' or 'tool'"):
        armkit.load("ur5").jacobian(np.zeros(6), frame="world")


@pytest.mark.parametrize("name", armkit.builtin_robots())
def test_chain_kernel_joint_axes_are_the_joint_frames_z_axes(name):
    robot = armkit.load(name)
    kernel = ChainKernel(robot.chain)
    for q in robot.random_q(20, rng=3):
        frames, _ = joint_frames(robot.chain, q)
        axes, origins = kernel.joint_axes(q)
        np.testing.assert_allclose(axes, frames[:, :3, 2], rtol=0, atol=1e-14)
        travel = np.where(robot.chain.prismatic, q, 0.0)[:, None] * axes
        np.testing.assert_allclose(origins + travel, frames[:, :3, 3], rtol=0, atol=1e-14)


def test_chain_kernel_returns_new_arrays():
    robot = armkit.load("stanford")
    kernel = ChainKernel(robot.chain)
    q1, q2 = robot.random_q(2, rng=0)
    T1, J1 = kernel.fk_jacobian(q1)
    kernel.fk_jacobian(q2)
    np.testing.assert_allclose(T1, robot.fk(q1), atol=1e-14)
    np.testing.assert_allclose(J1, robot.jacobian(q1), atol=1e-14)


@given(st.lists(st.floats(-1, 1), min_size=3, max_size=3), st.floats(0.0, np.pi - 1e-6))
def test_pose_error_is_the_rotation_vector_in_the_base_frame(direction, angle):
    axis = np.asarray(direction)
    if np.linalg.norm(axis) < 1e-3:
        axis = np.array([0.0, 0.0, 1.0])
    w = axis / np.linalg.norm(axis) * angle
    T = transform_from(matrix_from_axis_angle([0.3, -0.2, 0.5]), [0.1, 0.2, 0.3])
    T_target = transform_from(matrix_from_axis_angle(w) @ T[:3, :3], [0.4, 0.2, 0.0])
    e = pose_error(T_target, T)
    np.testing.assert_allclose(e[:3], [0.3, 0.0, -0.3], atol=1e-15)
    np.testing.assert_allclose(e[3:], w, atol=1e-9)
    assert np.isclose(np.linalg.norm(e[3:]), rotation_angle_between(T_target, T), atol=1e-9)


def test_pose_error_at_a_half_turn():
    T = np.eye(4)
    for axis in np.eye(3):
        e = pose_error(transform_from(matrix_from_axis_angle(np.pi * axis), [0, 0, 0]), T)
        np.testing.assert_allclose(np.abs(e[3:]), np.pi * axis, atol=1e-12)


@pytest.mark.parametrize("distance", [0.0, 1e-12, 1e-9, 3e-8, 1e-7, 1e-6, 1e-4, 4e-3, 6e-3, 1e-2])
def test_pose_error_near_and_at_a_half_turn_keeps_angle_axis_and_sign(distance):
    """General axes (not only x, y, z) within ``distance`` of a half turn: the rotation vector
    itself, signed, to rounding; at exactly pi either sign of the axis is the same rotation."""
    rng = np.random.default_rng(7)
    axes = np.vstack([[0.6, 0.8, 0.0], rng.normal(size=(200, 3))])
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    T = transform_from(matrix_from_axis_angle([0.3, -0.2, 0.5]), [0.1, 0.2, 0.3])
    for axis in axes:
        w = (np.pi - distance) * axis
        T_target = transform_from(matrix_from_axis_angle(w) @ T[:3, :3], T[:3, 3])
        e = pose_error(T_target, T)[3:]
        if distance == 0.0 and np.dot(e, w) < 0:
            w = -w
        # From 120 degrees on the axis comes from R + R^T, whose rounding (~4e-16) is not
        # magnified: the rotation vector to rounding all the way to pi.
        np.testing.assert_allclose(e, w, rtol=0, atol=1e-14)


@pytest.mark.parametrize("function", [fk, joint_frames, geometric_jacobian, link_frames])
def test_kinematics_functions_check_joint_values(function):
    chain = armkit.load("ur5").chain
    np.testing.assert_allclose(np.asarray(function(chain, [0] * 6)[0]),
                               np.asarray(function(chain, np.zeros(6))[0]), atol=0)  # a list works
    with pytest.raises(InputError, match=r"6 joints, so expected joint values of shape \(\.\.\., 6\), "
                                         r"got shape \(5,\)"):
        function(chain, np.zeros(5))
    with pytest.raises(InputError, match="got a scalar"):
        function(chain, 0.0)
    with pytest.raises(InputError, match=r"expected 6 joint values"):
        function(chain, "abc")
    q = np.zeros((3, 6))
    q[1, 4] = np.nan
    with pytest.raises(InputError, match=r"expected finite joint values, got nan at index \(1, 4\)"):
        function(chain, q)


def test_chain_limits_are_read_only_arrays_and_within_limits_uses_them():
    robot = armkit.load("panda")
    chain = robot.chain
    np.testing.assert_array_equal(chain.lower, [j.lower for j in chain.joints])
    np.testing.assert_array_equal(chain.upper, [j.upper for j in chain.joints])
    np.testing.assert_array_equal(robot.limits, np.stack([chain.lower, chain.upper], axis=1))
    with pytest.raises(ValueError):
        chain.lower[0] = 0.0
    q = robot.random_q(4, rng=0)
    q[1, 3] = chain.upper[3] + 1e-6
    q[2, 0] = chain.lower[0] - 0.5e-9  # within the slack
    np.testing.assert_array_equal(chain.within_limits(q), [True, False, True, True])
    np.testing.assert_array_equal(robot.within_limits(q), chain.within_limits(q))


def _prismatic_arm():
    """A 5-joint arm with two prismatic joints (one first, one in the middle), base and tool rows."""
    rows = [DHRow(0.0, 0.0, 0.3, 0.2, "prismatic"), DHRow(np.pi / 2, 0.1, 0.0, 0.0),
            DHRow(-0.7, 0.25, 0.05, 0.4, "prismatic"), DHRow(np.pi / 2, 0.0, 0.2, 0.0),
            DHRow(-np.pi / 2, 0.05, 0.0, -0.3)]
    return Robot.from_dh(rows, "modified", base_rows=[DHRow(0.1, 0.2, 0.3, 0.4, joint=None)],
                         tool_rows=[DHRow(-0.2, 0.0, 0.1, 0.5, joint=None)], name="PRPRR")


_KERNEL_ROBOTS = {name: armkit.load(name) for name in armkit.builtin_robots()} | {"PRPRR": _prismatic_arm()}


@settings(max_examples=60, deadline=None)
@given(st.sampled_from(sorted(_KERNEL_ROBOTS)), st.lists(st.floats(-7.0, 7.0), min_size=7, max_size=7))
def test_jacobian_columns_are_finite_differences_of_fk(name, values):
    """Every column of the geometric Jacobian is the tool's twist per joint rate: central
    differences of FK (linear part of the position, rotation vector of the orientation)."""
    robot = _KERNEL_ROBOTS[name]
    q, h = np.array(values[:robot.n]), 1e-6
    J = robot.jacobian(q)
    for i in range(robot.n):
        dq = np.zeros(robot.n)
        dq[i] = h
        np.testing.assert_allclose(J[:, i], pose_error(robot.fk(q + dq), robot.fk(q - dq)) / (2 * h),
                                   atol=2e-8)


@pytest.mark.parametrize("function", [fk, joint_frames, geometric_jacobian])
def test_batches_are_identical_whatever_the_thread_count(function):
    chain = _prismatic_arm().chain
    q = np.random.default_rng(5).uniform(-3, 3, (50_003, chain.n))  # enough for two threads
    one, two = function(chain, q, threads=1), function(chain, q, threads=2)
    for a, b in zip(*(r if isinstance(r, tuple) else (r,) for r in (one, two)), strict=True):
        np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(fk(chain, q[:3], threads=2), fk(chain, q[:3], threads=1))
    with pytest.raises(InputError, match=r"threads: expected None \(every core\) or a whole number of "
                                         r"threads from 1 to 1024"):
        function(chain, q, threads=-1)


def test_batch_fk_equals_fk_of_each_configuration_and_keeps_the_batch_shape():
    chain = armkit.load("ur5").chain
    q = np.random.default_rng(6).uniform(-3, 3, (4, 5, 6))  # blocks of 8 and a tail of 4
    T = fk(chain, q)
    assert T.shape == (4, 5, 4, 4)
    for index in np.ndindex(4, 5):
        np.testing.assert_array_equal(T[index], fk(chain, q[index]))
    assert fk(chain, np.zeros((0, 6))).shape == (0, 4, 4)
    frames, tool = joint_frames(chain, q)
    assert frames.shape == (4, 5, 6, 4, 4) and tool.shape == (4, 5, 4, 4)
    np.testing.assert_array_equal(tool, T)
    assert geometric_jacobian(chain, q).shape == (4, 5, 6, 6)
    many = np.zeros((100_000, 6))
    many[77_777, 2] = np.inf
    many[88_888, 1] = np.nan
    with pytest.raises(InputError, match=r"got inf at index \(77777, 2\)"):
        fk(chain, many)


def test_the_prismatic_test_arm_has_prismatic_joints_and_matches_finite_differences():
    robot = _prismatic_arm()
    assert robot.chain.prismatic.tolist() == [True, False, True, False, False]
    q, h = np.array([0.1, 0.4, -0.2, 1.0, -0.5]), 1e-6
    _, J = ChainKernel(robot.chain).fk_jacobian(q)
    for i in range(robot.n):
        dq = np.zeros(robot.n)
        dq[i] = h
        e = pose_error(robot.fk(q + dq), robot.fk(q - dq)) / (2 * h)
        np.testing.assert_allclose(J[:, i], e, atol=1e-8)


def test_batch_poses_use_the_same_sines_as_one_configuration():
    """Blocks of eight configurations and single configurations take their sines and cosines
    from one function, so batch FK and FK of each agree to the last bit at any angle."""
    robot = armkit.load("panda")
    q = np.random.default_rng(9).uniform(-1e4, 1e4, (64, 7))
    np.testing.assert_array_equal(robot.fk(q), np.stack([robot.fk(qi) for qi in q]))


def test_joint_values_in_any_form_give_the_same_numbers_and_errors():
    """``robot.fk`` / ``robot.jacobian`` make one core call whatever the form of ``q`` (it reads
    them as ``numpy.asarray`` would): the same numbers, a fresh writable array each call, and the
    same error for a value that is not finite."""
    robot = armkit.load("ur5")
    q = np.random.default_rng(10).uniform(-3, 3, 6)
    T, J = robot.fk(q), robot.jacobian(q)
    assert T.flags.writeable and T is not robot.fk(q) and J.shape == (6, robot.n)
    for call in (robot.fk, robot.jacobian, lambda q: robot.jacobian(q, frame="tool")):
        for bad in (np.array([0, 0, np.nan, 0, 0, 0]), [0, 0, np.nan, 0, 0, 0]):
            with pytest.raises(InputError, match="got nan at index 2"):
                call(bad)
        with pytest.raises(InputError, match=r"got inf at index \(1, 3\)"):
            call(np.array([q, [0, 0, 0, np.inf, 0, 0]]))
    others = [q.tolist(), tuple(q), q.astype(">f8"), np.repeat(q, 2)[::2], q.reshape(1, 6)[0],
              np.ma.masked_array(q)]
    for other in others:
        np.testing.assert_array_equal(robot.fk(other), T)
        np.testing.assert_array_equal(robot.jacobian(other), J)
    assert robot.fk(q.reshape(1, 6)).shape == (1, 4, 4)
    with pytest.raises(InputError, match="got nan at index 2"):
        robot.fk(np.array([0, 0, np.nan, 0, 0, 0.0]))
    with pytest.raises(InputError, match="expected 6 joint values"):
        robot.jacobian(np.zeros(5))
    for call in (robot.fk, robot.jacobian, robot.pose):
        with pytest.raises(InputError, match="q: expected 6"):
            call(None)
    puma = armkit.load("puma560")
    zero = np.zeros(6)
    for call in (lambda: puma.inverse_dynamics(None), lambda: puma.mass_matrix(None),
                 lambda: puma.gravity_torques(None), lambda: puma.forward_dynamics(zero, None, zero),
                 lambda: puma.forward_dynamics(zero, zero, None)):
        with pytest.raises(InputError):
            call()
