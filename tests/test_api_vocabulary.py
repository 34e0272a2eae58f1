"""One API vocabulary (issue 10, item 11): a Robot everywhere, one word per meaning, old names
kept as deprecated aliases that warn."""

from __future__ import annotations

import re

import numpy as np
import pytest

import armkit
from armkit import kinematics
from armkit.chain import as_chain
from armkit.errors import InputError
from armkit.ik import (
    NumericIK,
    analyze_structure,
    closed_form_ik,
    closed_form_solver,
    ik,
    ik_solutions,
    numeric_ik,
    wrap_into_limits,
)

Q_UR5 = np.array([0.3, -0.8, 1.1, -0.4, 0.6, 0.2])
Q_PANDA = np.array([0.1, -0.3, 0.2, -2.0, 0.1, 1.8, 0.5])


# ------------------------------------------------------------------ a Robot everywhere
def test_as_chain_takes_a_robot_or_a_chain_and_refuses_anything_else():
    robot = armkit.load("ur5")
    assert as_chain(robot) is robot.chain
    assert as_chain(robot.chain) is robot.chain
    locked = robot.lock({"q6": 0.5})
    assert as_chain(locked) is locked.chain
    with pytest.raises(InputError, match=r"robot: expected an armkit Robot .* got str 'ur5'"):
        as_chain("ur5")
    with pytest.raises(InputError, match="got ndarray"):
        ik_solutions(np.eye(4), np.eye(4))


def test_ik_functions_give_the_same_answer_for_a_robot_and_its_chain():
    robot = armkit.load("ur5")
    T = robot.fk(Q_UR5)
    by_robot, by_chain = ik_solutions(robot, T, near=Q_UR5), ik_solutions(robot.chain, T, near=Q_UR5)
    np.testing.assert_array_equal(by_robot.q, by_chain.q)
    np.testing.assert_allclose(by_robot.q[0], Q_UR5, atol=1e-9)
    np.testing.assert_array_equal(closed_form_ik(robot, T).q, closed_form_ik(robot.chain, T).q)
    assert closed_form_solver(robot) is closed_form_solver(robot.chain)
    np.testing.assert_allclose(ik(robot, T, near=Q_UR5), Q_UR5, atol=1e-9)
    assert analyze_structure(robot) == analyze_structure(robot.chain)
    np.testing.assert_array_equal(wrap_into_limits(robot, Q_UR5 + 2 * np.pi, Q_UR5),
                                  wrap_into_limits(robot.chain, Q_UR5 + 2 * np.pi, Q_UR5))

    panda = armkit.load("panda")
    T = panda.fk(Q_PANDA)
    a, b = numeric_ik(panda, T, q0=Q_PANDA, rng=0), numeric_ik(panda.chain, T, q0=Q_PANDA, rng=0)
    assert a.success and b.success
    np.testing.assert_array_equal(a.q, b.q)
    np.testing.assert_array_equal(NumericIK(panda).solve(T, Q_PANDA, rng=0).q, a.q)


def test_kinematics_functions_take_a_robot():
    robot = armkit.load("panda")
    np.testing.assert_array_equal(kinematics.fk(robot, Q_PANDA), robot.fk(Q_PANDA))
    np.testing.assert_array_equal(kinematics.geometric_jacobian(robot, Q_PANDA), robot.jacobian(Q_PANDA))
    np.testing.assert_array_equal(kinematics.link_frames(robot, Q_PANDA), robot.link_frames(Q_PANDA))
    np.testing.assert_array_equal(kinematics.joint_frames(robot, Q_PANDA)[1], robot.fk(Q_PANDA))
    np.testing.assert_array_equal(kinematics.singular_values(robot, Q_PANDA), robot.singular_values(Q_PANDA))
    assert kinematics.manipulability(robot, Q_PANDA) == robot.manipulability(Q_PANDA)
    np.testing.assert_array_equal(kinematics.analytic_jacobian(robot, Q_PANDA),
                                  robot.analytic_jacobian(Q_PANDA))
    np.testing.assert_array_equal(kinematics.ChainKernel(robot).pose(Q_PANDA), robot.fk(Q_PANDA))


# ------------------------------------------------------------------ "it worked": success
def test_every_result_says_it_worked_with_success():
    robot = armkit.load("probot-anno")
    motion = armkit.move_linear(robot, np.zeros(6), [0.05, 0, -0.05], duration=1.0)
    assert motion.success is True and motion.message == "completed"
    blocked = armkit.rotate_about_tool_point(robot, np.zeros(6), [1, 0, 0], -np.radians(200),
                                             angular_velocity=0.5)
    assert blocked.success is False and "limit" in blocked.message

    T = robot.fk([0.3, -0.5, 0.4, 0.2, 0.6, -0.1])
    assert closed_form_ik(robot, T).success is True
    far = np.eye(4)
    far[:3, 3] = [5.0, 0.0, 0.0]
    assert closed_form_ik(robot, far).success is False
    np.testing.assert_array_equal(closed_form_ik(robot, np.stack([T, far])).success, [True, False])
    assert ik_solutions(robot, T).success and not ik_solutions(robot, far).success
    np.testing.assert_array_equal(ik_solutions(robot, np.stack([T, far, T])).success, [True, False, True])
    assert numeric_ik(robot, T, rng=0).success


def test_completed_is_a_deprecated_alias_of_success():
    robot = armkit.load("probot-anno")
    motion = armkit.move_linear(robot, np.zeros(6), [0.05, 0, -0.05], duration=1.0)
    with pytest.warns(DeprecationWarning, match=r"MotionResult.completed is deprecated in armkit 0.2: "
                                                r"use .success instead"):
        assert motion.completed is motion.success is True


# ------------------------------------------------------------ rates: rate_hz [Hz], angular_velocity [rad/s]
def test_cartesian_line_samples_at_rate_hz_and_rate_is_a_deprecated_alias():
    robot = armkit.load("probot-anno")
    T_goal = robot.fk([0.3, -0.5, 0.4, 0.2, 1.2, -0.3])
    line = armkit.cartesian_line(robot, np.zeros(6), T_goal, 2.0, rate_hz=10)
    np.testing.assert_allclose(line.t, np.linspace(0, 2, 21))
    with pytest.warns(DeprecationWarning, match=r"cartesian_line\(rate=...\) is deprecated in armkit 0.2: "
                                                r"use rate_hz=... instead"):
        old = armkit.cartesian_line(robot, np.zeros(6), T_goal, 2.0, rate=10)
    np.testing.assert_array_equal(old.q, line.q)
    with pytest.warns(DeprecationWarning), pytest.raises(InputError, match="got both rate=10 and rate_hz=20"):
        armkit.cartesian_line(robot, np.zeros(6), T_goal, 2.0, rate=10, rate_hz=20)


def test_rotation_takes_angular_velocity_in_rad_per_s_and_rate_is_a_deprecated_alias():
    robot = armkit.load("probot-anno")
    turn = armkit.rotate_about_tool_point(robot, np.zeros(6), [1, 0, 0], angular_velocity=-0.2, duration=1.0)
    assert turn.t[-1] == pytest.approx(1.0) and turn.success
    with pytest.warns(DeprecationWarning, match=r"rotate_about_tool_point\(rate=...\) is deprecated in "
                                                r"armkit 0.2: use angular_velocity=... instead"):
        old = armkit.rotate_about_tool_point(robot, np.zeros(6), [1, 0, 0], rate=-0.2, duration=1.0)
    np.testing.assert_array_equal(old.q, turn.q)
    with pytest.raises(InputError, match="give two of angle, angular_velocity and duration"):
        armkit.rotate_about_tool_point(robot, np.zeros(6), [1, 0, 0], 1.0)


# ------------------------------------------------------------ at_time(t) [s], sample(rate_hz) [Hz]; n
def test_segments_answer_at_time_and_their_sample_of_times_is_deprecated():
    from armkit.trajectory import lspb, quintic

    for segment, name in ((quintic([0.0, 1.0], [1.0, -1.0], 2.0), "PolynomialSegment"),
                          (lspb([0.0, 1.0], [1.0, -1.0], 2.0), "TrapezoidSegment")):
        q, qd, qdd, qddd = segment.at_time([0.0, 1.0, 2.0])
        np.testing.assert_allclose(q[[0, 2]], [[0.0, 1.0], [1.0, -1.0]], atol=1e-14)
        np.testing.assert_allclose(q[1], [0.5, 0.0], atol=1e-14)
        with pytest.warns(DeprecationWarning, match=rf"{name}.sample\(t\) is deprecated in armkit 0.2: "
                                                    r"use .at_time\(t\) instead"):
            old = segment.sample([0.0, 1.0, 2.0])
        for a, b in zip(old, (q, qd, qdd, qddd), strict=True):
            np.testing.assert_array_equal(a, b)
        assert segment.n == 2
        with pytest.warns(DeprecationWarning, match=rf"{name}.dof is deprecated in armkit 0.2: use .n"):
            assert segment.dof == 2


def test_joint_trajectory_has_n_and_dof_is_a_deprecated_alias():
    traj = armkit.min_jerk([[0.0, 0.0, 0.0], [1.0, -1.0, 0.5]], [2.0])
    assert traj.n == 3 and traj.sample(10.0).q.shape == (21, 3) and traj.at_time(1.0)[0].shape == (3,)
    assert armkit.load("ur5").n == traj.n + 3
    with pytest.warns(DeprecationWarning, match=r"JointTrajectory.dof is deprecated in armkit 0.2: use .n"):
        assert traj.dof == 3


# ------------------------------------------------------------ all_solutions, not the builtin's name
def test_ik_all_solutions_and_the_deprecated_all():
    robot = armkit.load("probot-anno")
    T = robot.fk([0.927, -0.687, -0.396, 0, 1.083, 0.927])
    every = robot.ik(T, all_solutions=True, within_limits=False)
    assert every.shape == (8, 6)
    np.testing.assert_array_equal(ik(robot, T, all_solutions=True, within_limits=False), every)
    with pytest.warns(DeprecationWarning, match=r"Robot.ik\(all=...\) is deprecated in armkit 0.2: "
                                                r"use all_solutions=... instead") as caught:
        old = robot.ik(T, all=True, within_limits=False)
    assert caught[0].filename == __file__  # the warning points at the caller's line
    np.testing.assert_array_equal(old, every)
    with pytest.warns(DeprecationWarning, match=r"^ik\(all=...\) is deprecated"):
        np.testing.assert_array_equal(ik(robot, T, all=True, within_limits=False), every)
    with pytest.warns(DeprecationWarning):  # batch path too
        assert len(robot.ik(np.stack([T, T]), all=True)) == 2
    with pytest.warns(DeprecationWarning), pytest.raises(InputError, match="got both all=True and "
                                                                           "all_solutions=True"):
        robot.ik(T, all=True, all_solutions=True)


# ------------------------------------------------------------ one name per tolerance
def test_the_two_ik_tolerances_have_two_names_and_the_old_one_warns():
    import armkit.ik.closed_form as closed_form
    import armkit.ik.results as results
    import armkit.ik.solve as solve
    from armkit import _core

    # what IK returns reproduces its target to SOLUTION_TOLERANCE (m and rad), the core's constant
    assert results.SOLUTION_TOLERANCE == solve.SOLUTION_TOLERANCE == _core.SOLUTION_TOLERANCE == 1e-9
    robot = armkit.load("ur5")
    found = ik_solutions(robot, robot.fk(Q_UR5))
    assert found.position_error.max() <= results.SOLUTION_TOLERANCE
    # a closed-form candidate is kept if its FK matrix matches to CANDIDATE_TOLERANCE * (1 + size)
    assert closed_form.CANDIDATE_TOLERANCE == 1e-8
    for module, new in ((closed_form, "CANDIDATE_TOLERANCE"), (results, "SOLUTION_TOLERANCE"),
                        (solve, "SOLUTION_TOLERANCE")):
        with pytest.warns(DeprecationWarning, match=rf"{module.__name__}.VERIFY_TOLERANCE is deprecated in "
                                                    rf"armkit 0.2: use {module.__name__}.{new} instead"):
            assert module.VERIFY_TOLERANCE == getattr(module, new)
        assert "VERIFY_TOLERANCE" not in module.__all__
        with pytest.raises(AttributeError):
            module.NO_SUCH_TOLERANCE  # noqa: B018


# ------------------------------------------------------------ the joint-limit test, once, on the chain
def test_every_limit_check_gives_the_chains_one_message():
    from armkit import _core
    from armkit.chain import LIMIT_TOLERANCE
    from armkit.errors import JointLimitError

    assert LIMIT_TOLERANCE == _core.LIMIT_TOLERANCE
    robot = armkit.load("probot-anno")          # q2 within +-115 deg (2.00713 rad)
    upper = robot.chain.upper[1]
    q = np.zeros(6)
    q[1] = upper + 0.5 * LIMIT_TOLERANCE
    assert not robot.chain.outside_limits(q).any() and robot.within_limits(q)
    q[1] = upper + 2 * LIMIT_TOLERANCE
    np.testing.assert_array_equal(robot.chain.outside_limits(q), [False, True, False, False, False, False])
    assert not robot.within_limits(q)
    q[1] = 2.5
    message = "joint q2 = 2.5 rad is outside its limits [-2.00713, 2.00713] rad"
    assert robot.limit_violations(q) == robot.chain.limit_violations(q) == [message]
    with pytest.raises(JointLimitError, match="^" + re.escape(message) + "$"):
        robot.check_limits(q)
    traj = armkit.min_jerk([np.zeros(6), q, np.zeros(6)], [1.0, 1.0])
    assert traj.position_limit_violations(robot)[0].startswith("joint q2 = 0 .. 2.5") and \
        traj.position_limit_violations(robot)[0].endswith(" rad between waypoints is outside its limits "
                                                          "[-2.00713, 2.00713] rad")
    # IK's error for a pose reachable only outside the limits names the joints the same way
    narrow = armkit.Robot.from_dh(robot.dh.rows, robot.dh.convention,
                                  limits=[(-0.1, 0.1)] + [tuple(lim) for lim in robot.limits[1:]])
    T = narrow.fk([0.5, 0.2, -0.3, 0.1, 0.6, 0.2])
    with pytest.raises(JointLimitError, match=r"only outside the joint limits \(e.g. joint q1 = -?[\d.]+ rad "
                                              r"is outside its limits \[-0.1, 0.1\] rad"):
        narrow.ik(T, near=[0.5, 0.2, -0.3, 0.1, 0.6, 0.2])


def test_numeric_ik_says_within_limits_as_robot_ik_does():
    panda = armkit.load("panda")
    T = panda.fk(Q_PANDA)
    new = numeric_ik(panda, T, q0=Q_PANDA + 1e-3, within_limits=False, max_restarts=0)
    with pytest.warns(DeprecationWarning, match=r"numeric_ik\(respect_limits=...\) is deprecated in armkit "
                                                r"0.2: use within_limits=... instead"):
        old = numeric_ik(panda, T, q0=Q_PANDA + 1e-3, respect_limits=False, max_restarts=0)
    np.testing.assert_array_equal(old.q, new.q)
    solver = NumericIK(panda, within_limits=False)
    assert solver.within_limits is False
    with pytest.warns(DeprecationWarning, match=r"NumericIK.respect_limits is deprecated"):
        assert solver.respect_limits is False
    with pytest.warns(DeprecationWarning, match=r"NumericIK\(respect_limits=...\) is deprecated"):
        assert NumericIK(panda, respect_limits=False).within_limits is False


def test_subpackages_work_after_a_plain_import_armkit_which_imports_none_of_them():
    import subprocess
    import sys

    code = ("import sys, armkit\n"
            "before = sorted(m for m in sys.modules if m.startswith('armkit.'))\n"
            "names = [armkit.trajectory.read_waypoints, armkit.export.write_urdf, armkit.workspace.compute,\n"
            "         armkit.ik.analyze_structure]\n"
            "print(' '.join(f.__module__ + '.' + f.__name__ for f in names))\n"
            "print(' '.join(before))\n"
            "try:\n"
            "    armkit.no_such_module\n"
            "except AttributeError as exc:\n"
            "    print(exc)\n")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    found, before, missing = result.stdout.splitlines()
    assert found.split() == ["armkit.trajectory.waypoints.read_waypoints", "armkit.export.urdf.write_urdf",
                             "armkit.workspace.maps.compute", "armkit.ik.structure.analyze_structure"]
    assert not {"armkit.trajectory", "armkit.export", "armkit.workspace", "armkit.ik"} & set(before.split())
    assert missing == "module 'armkit' has no attribute 'no_such_module'"
