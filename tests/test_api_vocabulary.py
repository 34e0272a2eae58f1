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

#: What every deprecation warning says (armkit/_deprecation.py: the version story).
OLD = r"is deprecated since armkit 0\.1\.0 \(removed in 0\.2\.0\)"
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
    np.testing.assert_array_equal(kinematics.ChainKernel(robot).fk(Q_PANDA), robot.fk(Q_PANDA))


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
    with pytest.warns(DeprecationWarning, match=rf"MotionResult.completed {OLD}: "
                                                r"use .success instead"):
        assert motion.completed is motion.success is True


# ------------------------------------------------------------ rates: rate_hz [Hz], angular_velocity [rad/s]
def test_cartesian_line_samples_at_rate_hz_and_rate_is_a_deprecated_alias():
    robot = armkit.load("probot-anno")
    T_goal = robot.fk([0.3, -0.5, 0.4, 0.2, 1.2, -0.3])
    line = armkit.cartesian_line(robot, np.zeros(6), T_goal, 2.0, rate_hz=10)
    np.testing.assert_allclose(line.t, np.linspace(0, 2, 21))
    with pytest.warns(DeprecationWarning, match=rf"cartesian_line\(rate=...\) {OLD}: "
                                                r"use rate_hz=... instead"):
        old = armkit.cartesian_line(robot, np.zeros(6), T_goal, 2.0, rate=10)
    np.testing.assert_array_equal(old.q, line.q)
    with pytest.warns(DeprecationWarning), pytest.raises(InputError, match="got both rate=10 and rate_hz=20"):
        armkit.cartesian_line(robot, np.zeros(6), T_goal, 2.0, rate=10, rate_hz=20)


def test_rotation_takes_angular_velocity_in_rad_per_s_and_rate_is_a_deprecated_alias():
    robot = armkit.load("probot-anno")
    turn = armkit.rotate_about_tool_point(robot, np.zeros(6), [1, 0, 0], angular_velocity=-0.2, duration=1.0)
    assert turn.t[-1] == pytest.approx(1.0) and turn.success
    with pytest.warns(DeprecationWarning, match=rf"rotate_about_tool_point\(rate=...\) {OLD}: "
                                                r"use angular_velocity=... instead"):
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
        with pytest.warns(DeprecationWarning, match=rf"{name}.sample\(t\) {OLD}: "
                                                    r"use .at_time\(t\) instead"):
            old = segment.sample([0.0, 1.0, 2.0])
        for a, b in zip(old, (q, qd, qdd, qddd), strict=True):
            np.testing.assert_array_equal(a, b)
        assert segment.n == 2
        with pytest.warns(DeprecationWarning, match=rf"{name}.dof {OLD}: use .n"):
            assert segment.dof == 2


def test_joint_trajectory_has_n_and_dof_is_a_deprecated_alias():
    traj = armkit.min_jerk([[0.0, 0.0, 0.0], [1.0, -1.0, 0.5]], [2.0])
    assert traj.n == 3 and traj.sample(10.0).q.shape == (21, 3) and traj.at_time(1.0)[0].shape == (3,)
    assert armkit.load("ur5").n == traj.n + 3
    with pytest.warns(DeprecationWarning, match=rf"JointTrajectory.dof {OLD}: use .n"):
        assert traj.dof == 3


# ------------------------------------------------------------ all_solutions, not the builtin's name
def test_ik_all_solutions_and_the_deprecated_all():
    robot = armkit.load("probot-anno")
    T = robot.fk([0.927, -0.687, -0.396, 0, 1.083, 0.927])
    every = robot.ik(T, all_solutions=True, within_limits=False)
    assert every.shape == (8, 6)
    np.testing.assert_array_equal(ik(robot, T, all_solutions=True, within_limits=False), every)
    with pytest.warns(DeprecationWarning, match=rf"Robot.ik\(all=...\) {OLD}: "
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
    # the old name answers in one module, results (where SOLUTION_TOLERANCE lives), and warns
    with pytest.warns(DeprecationWarning, match=rf"armkit.ik.results.VERIFY_TOLERANCE {OLD}: "
                                                rf"use armkit.ik.results.SOLUTION_TOLERANCE instead"):
        assert results.VERIFY_TOLERANCE == results.SOLUTION_TOLERANCE
    for module in (closed_form, results, solve):
        assert "VERIFY_TOLERANCE" not in module.__all__
        with pytest.raises(AttributeError):
            module.NO_SUCH_TOLERANCE  # noqa: B018
    for module in (closed_form, solve):
        with pytest.raises(AttributeError):
            module.VERIFY_TOLERANCE  # noqa: B018


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
    with pytest.warns(DeprecationWarning, match=rf"numeric_ik\(respect_limits=...\) {OLD}: "
                                                r"use within_limits=... instead"):
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


# ------------------------------------------------------------------ threads=: one meaning, one check
THREADS_REFUSED = r"threads: expected None \(every core\) or a whole number of threads from 1 to 1024, got "


def _threaded_calls():
    """Every public call that takes ``threads=``, each as ``call(threads) -> result``."""
    from armkit.dynamics import inverse_dynamics, mass_matrix

    ur5, panda = armkit.load("ur5"), armkit.load("panda")
    q = ur5.random_q(5, rng=3)
    T = ur5.fk(q)
    T_panda = panda.fk(panda.random_q(3, rng=4))
    dynamic = ur5.with_estimated_inertia(density=2700.0)
    return {
        "kinematics.fk": lambda threads: kinematics.fk(ur5, q, threads=threads),
        "kinematics.joint_frames": lambda threads: kinematics.joint_frames(ur5, q, threads=threads)[0],
        "kinematics.geometric_jacobian": lambda threads: kinematics.geometric_jacobian(ur5, q,
                                                                                       threads=threads),
        "Robot.fk": lambda threads: ur5.fk(q, threads=threads),
        "Robot.jacobian": lambda threads: ur5.jacobian(q, threads=threads),
        "Robot.ik": lambda threads: ur5.ik(T, near=q, threads=threads),
        "ik_solutions": lambda threads: ik_solutions(ur5, T, near=q, threads=threads).q,
        "ik": lambda threads: ik(ur5, T, near=q, threads=threads),
        "NumericIK.solve_batch": lambda threads: NumericIK(panda).solve_batch(T_panda, rng=0,
                                                                              threads=threads).q,
        "mass_matrix": lambda threads: mass_matrix(dynamic, q, threads=threads),
        "inverse_dynamics": lambda threads: inverse_dynamics(dynamic, q, q, q, threads=threads),
    }


@pytest.mark.parametrize("name", list(_threaded_calls()))
def test_threads_means_the_same_everywhere(name):
    """None is every core, a whole number from 1 to 1024 that many threads (the answer does not
    depend on it), anything else an InputError naming the value: 0 too (it meant every core).
    (Moved here from test_params.py, and extended, in issue 25.)"""
    call = _threaded_calls()[name]
    every_core = call(None)
    for threads in (1, 2, 1024):
        np.testing.assert_array_equal(call(threads), every_core)
    for bad in (0, -1, -3, 1025, 2**31, 1.5, 2.0, True, "2"):
        with pytest.raises(InputError, match=THREADS_REFUSED + re.escape(repr(bad))) as caught:
            call(bad)
        assert caught.value.parameter == "threads" and caught.value.value is bad


def test_a_workspace_engine_counts_threads_as_everything_else():
    from armkit.workspace.engine import engine_threads

    assert engine_threads(3) == 3 and engine_threads(None) >= 1
    for bad in (0, -3):
        with pytest.raises(InputError, match=r"engine: expected None \(every core\) or a whole number of "
                                             rf"threads from 1 to 1024, got {bad}"):
            engine_threads(bad)


def test_public_ik_functions_default_threads_to_none():
    import inspect

    for function in (ik, ik_solutions, NumericIK.solve_batch, kinematics.fk, kinematics.geometric_jacobian,
                     armkit.Robot.fk, armkit.Robot.jacobian):
        assert inspect.signature(function).parameters["threads"].default is None, function.__qualname__


# ------------------------------------------------------------------ a 4x4 is fk's, a pose is a 6-vector
def test_fk_gives_the_4x4_and_pose_the_6_vector():
    robot = armkit.load("panda")
    kernel = kinematics.ChainKernel(robot)
    T = robot.fk(Q_PANDA)
    assert T.shape == (4, 4) and kernel.fk(Q_PANDA).shape == (4, 4)
    np.testing.assert_array_equal(kernel.fk(Q_PANDA), T)
    T_kernel, J_kernel = kernel.fk_jacobian(Q_PANDA)
    np.testing.assert_array_equal(T_kernel, T)
    np.testing.assert_array_equal(J_kernel, robot.jacobian(Q_PANDA))
    pose = robot.pose(Q_PANDA)
    assert pose.shape == (6,)
    np.testing.assert_array_equal(pose[:3], T[:3, 3])
    np.testing.assert_allclose(armkit.spatial.transform_from_pose(pose), T, atol=1e-15)
    with pytest.warns(DeprecationWarning, match=rf"ChainKernel.pose\(\) {OLD}: use .fk\(\) instead"):
        np.testing.assert_array_equal(kernel.pose(Q_PANDA), T)
    with pytest.warns(DeprecationWarning,
                      match=rf"ChainKernel.pose_jacobian\(\) {OLD}: use .fk_jacobian\(\)"):
        np.testing.assert_array_equal(kernel.pose_jacobian(Q_PANDA)[1], J_kernel)


# ------------------------------------------------------------------ within_limits: one meaning
def test_within_limits_is_one_test_whether_method_mask_or_request():
    """The method tests a configuration, the mask records that test of each solution, the request
    keeps only answers that pass it: the same test (Chain.outside_limits) everywhere."""
    robot = armkit.load("probot-anno")
    T = robot.fk([0.927, -0.687, -0.396, 0.0, 1.083, 0.927])
    found = ik_solutions(robot, T)
    assert found.within_limits.any() and not found.within_limits.all()  # this pose has both kinds
    np.testing.assert_array_equal(found.within_limits, robot.within_limits(found.q))
    np.testing.assert_array_equal(found.within_limits, robot.chain.within_limits(found.q))
    inside = robot.ik(T, all_solutions=True, within_limits=True)
    assert robot.within_limits(inside).all() and len(inside) == found.within_limits.sum()
    everything = robot.ik(T, all_solutions=True, within_limits=False)
    assert len(everything) == len(found.q) and not robot.within_limits(everything).all()
    panda = armkit.load("panda")
    result = NumericIK(panda, within_limits=True).solve(panda.fk(Q_PANDA), rng=0)
    assert result.success and panda.within_limits(result.q)


def test_a_joint_limit_error_carries_its_fields():
    from armkit.errors import JointLimitError

    robot = armkit.load("probot-anno")          # q2 within +-115 deg (2.00713 rad)
    q = np.array([0.0, 2.5, 0.0, 0.0, 0.0, 0.0])
    with pytest.raises(JointLimitError) as caught:
        robot.check_limits(q, degrees=True)  # q in rad; the message in degrees
    error = caught.value
    assert (error.joint, error.value) == ("q2", 2.5)
    assert error.limits == (robot.chain.lower[1], robot.chain.upper[1])
    np.testing.assert_array_equal(error.q, q)
    assert "joint q2 = 143.239 deg is outside its limits" in str(error)
    assert robot.chain.limit_fields(q) == {"joint": "q2", "value": 2.5, "limits": tuple(robot.limits[1])}
    assert robot.chain.limit_fields(np.zeros(6)) == {}
    # IK's error for a pose reachable only outside the limits names a joint of the solution it gives
    narrow = armkit.Robot.from_dh(robot.dh.rows, robot.dh.convention,
                                  limits=[(-0.1, 0.1)] + [tuple(lim) for lim in robot.limits[1:]])
    with pytest.raises(JointLimitError) as caught:
        narrow.ik(narrow.fk([0.5, 0.2, -0.3, 0.1, 0.6, 0.2]))
    error = caught.value
    assert error.joint == "q1" and error.limits == (-0.1, 0.1) and not -0.1 <= error.value <= 0.1
    assert error.value == error.q[0] and "joint q1 = " in str(error)
    # a limit stop of a motion says which joint, where and its limits
    with pytest.raises(JointLimitError) as caught:
        armkit.rotate_about_tool_point(robot, np.zeros(6), [1, 0, 0], -np.radians(200), angular_velocity=0.5,
                                       stop_at_limits=False)
    error = caught.value
    index = robot.joint_names.index(error.joint)
    assert error.value in error.limits and error.limits == tuple(robot.limits[index])


# ------------------------------------------------------------------ result names
def test_errors_between_poses_are_position_and_orientation_errors():
    from armkit.errors import UnreachableError
    from armkit.sim.verify import PoseComparison, compare_poses

    robot = armkit.load("ur5")
    T = robot.fk(Q_UR5)
    for result in (ik_solutions(robot, T), numeric_ik(robot, T, rng=0),
                   NumericIK(robot).solve_batch(T[None], rng=0)):
        assert np.all(result.position_error <= 1e-9) and np.all(result.orientation_error <= 1e-9)
    tilted = T.copy()
    tilted[:3, :3] = T[:3, :3] @ armkit.spatial.matrix_from_axis_angle(np.array([0.0, 0.0, 0.2]))
    table = compare_poses(T[None], tilted[None])
    assert isinstance(table, PoseComparison) and "orientation_error" in PoseComparison.__dataclass_fields__
    assert "rotation_error" not in PoseComparison.__dataclass_fields__
    np.testing.assert_allclose(table.orientation_error, [0.2], rtol=1e-12)
    with pytest.warns(DeprecationWarning,
                      match=rf"PoseComparison.rotation_error {OLD}: use .orientation_error"):
        np.testing.assert_array_equal(table.rotation_error, table.orientation_error)
    far = np.eye(4)
    far[:3, 3] = [5.0, 0.0, 0.0]
    with pytest.raises(UnreachableError) as caught:
        robot.ik(far)
    assert caught.value.position_error > 3.0 and np.isfinite(caught.value.orientation_error)


def test_the_batch_ik_result_is_exported_beside_the_single_one():
    robot = armkit.load("ur5")
    batch = ik_solutions(robot, robot.fk(np.stack([Q_UR5, Q_UR5 + 0.1])))
    assert isinstance(batch, armkit.IKSolutionsBatch) and isinstance(batch[0], armkit.IKSolutions)
    assert "IKSolutionsBatch" in armkit.__all__ and armkit.IKSolutionsBatch is armkit.ik.IKSolutionsBatch


def test_ik_position_pairs_with_ik_position_solutions_as_ik_with_ik_solutions():
    robot = armkit.load("examples/data/my_arm.toml")
    p = [0.3, 0.1, 0.3]
    found = armkit.ik_position_solutions(robot, p)
    np.testing.assert_array_equal(robot.ik_position(p, all_solutions=True), found.q[found.within_limits])
    with pytest.warns(DeprecationWarning,
                      match=rf"position_solutions\(\) {OLD}: use ik_position_solutions\(\)"):
        old = armkit.position_solutions(robot, p)
    np.testing.assert_array_equal(old.q, found.q)


# ------------------------------------------------------------------ core dependencies: a lean import
def test_import_armkit_fk_and_ik_load_neither_the_cli_nor_plots():
    """typer and rich are core dependencies (the `armkit` command must work after `pip install
    armkit`), matplotlib and Pillow the extra "plot"; none of them is loaded by `import armkit`, FK
    or IK of a built-in arm (tests/test_plots.py checks that without the extra only figures fail)."""
    import subprocess
    import sys

    code = ("import sys, armkit\n"
            "robot = armkit.load('ur5')\n"
            "robot.ik(robot.fk([0.1] * 6), near=[0.1] * 6)\n"
            "print(sorted({m.split('.')[0] for m in sys.modules} & {'typer', 'rich', 'click', 'matplotlib', "
            "'PIL', 'mpl_toolkits'}))\n")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert result.stdout.strip() == "[]"


def test_no_module_imports_a_private_name_of_another():
    """A name with a leading underscore is its module's own: what another module needs is public
    (private modules such as ``armkit._params`` are shared on purpose), whether imported by name or
    reached as an attribute of an imported module (``kinematics._frames``)."""
    import ast
    from pathlib import Path

    def private(name: str) -> bool:
        return name.startswith("_") and not name.startswith("__") and name != "_core"

    package = Path(armkit.__file__).parent
    found = []
    for path in package.rglob("*.py"):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        modules = set()  # names bound to public armkit modules in this file
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("armkit"):
                if node.module.rsplit(".", 1)[-1].startswith("_"):
                    continue
                found += [f"{path.relative_to(package)}: {node.module}.{alias.name}" for alias in node.names
                          if private(alias.name)]
                modules |= {alias.asname or alias.name for alias in node.names if not private(alias.name)}
            elif isinstance(node, ast.Import):
                modules |= {alias.asname or alias.name for alias in node.names
                            if alias.name.startswith("armkit")}
        for node in ast.walk(tree):
            if (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name)
                    and node.value.id in modules and private(node.attr)):
                found.append(f"{path.relative_to(package)}:{node.lineno}: {node.value.id}.{node.attr}")
    assert found == []
