import numpy as np
import pytest

import armkit
from armkit import DHRow, Robot
from armkit.errors import InputError, JointLimitError, RobotDefinitionError


def test_fk_shapes_and_types():
    robot = armkit.load("probot-anno")
    assert robot.fk(np.zeros(6)).shape == (4, 4)
    assert robot.fk(np.zeros((7, 6))).shape == (7, 4, 4)
    assert robot.fk([0, 0, 0, 0, 0, 0]).dtype == np.float64
    assert repr(robot) == "Robot('PROBOT Anno', 6 joints RRRRRR)"


@pytest.mark.parametrize(("q", "message"), [
    ([0, 0, 0], r"expected 6 joint values, got 3 \(PROBOT Anno has 6 joints\)"),
    (1.0, "got a scalar"),
    ([0, 0, 0, 0, 0, np.nan], "expected finite joint values, got nan at index 5"),
    (np.array([0, 0, 0, 0, np.inf, 0]), "expected finite joint values, got inf at index 4"),
    (["a", 0, 0, 0, 0, 0], "expected 6 numbers"),
])
def test_bad_joint_values(q, message):
    with pytest.raises(InputError, match=message):
        armkit.load("probot-anno").fk(q)


def test_limits_checks_name_joint_value_and_range():
    robot = armkit.load("probot-anno")
    q = np.array([0, 0, 0, 0, 4.0, 0])
    assert not robot.within_limits(q)
    assert robot.within_limits(np.zeros((3, 6))).tolist() == [True] * 3
    with pytest.raises(JointLimitError,
                       match=r"joint q5 = 4 rad is outside its limits \[-0.785398, 3.92699\] rad"):
        robot.check_limits(q)
    np.testing.assert_array_equal(robot.check_limits(np.zeros(6)), np.zeros(6))


@pytest.mark.parametrize(("limits", "message"), [
    ((-1e298, 1e298), r"joint 'q2': limits \[-1e\+298, 1e\+298\] reach beyond 1e\+06 rad or m .*-inf, inf"),
    ((0.0, 2e6), r"limits \[0, 2e\+06\] reach beyond 1e\+06"),
    ((0.5, -0.5), r"limits \[0.5, -0.5\] are not increasing"),
])
def test_limits_beyond_a_million_or_decreasing_are_refused_naming_the_joint(limits, message):
    # a finite 1e298 rad is a typo or a sentinel (MJCF and robot files refuse it too); inf is no limit
    rows = [DHRow(0.0, 0.3, 0.0, 0.0)] * 3
    with pytest.raises(RobotDefinitionError, match=message):
        Robot.from_dh(rows, "standard", limits=[(-1.0, 1.0), limits, (-1.0, 1.0)])
    free = Robot.from_dh(rows, "standard", limits=[(-np.inf, np.inf)] * 3)
    assert np.isinf(free.limits).all()


def test_random_q_is_inside_limits_and_reproducible():
    robot = armkit.load("stanford")
    q = robot.random_q(100, rng=4)
    assert q.shape == (100, 6) and robot.within_limits(q).all()
    np.testing.assert_array_equal(q, robot.random_q(100, rng=4))


def test_from_dh_in_code_both_conventions_agree():
    # A planar 2R arm written in both conventions is the same arm.
    standard = Robot.from_dh([DHRow(0, 0.4, 0, 0), DHRow(0, 0.3, 0, 0)], "standard")
    modified = Robot.from_dh([DHRow(0, 0, 0, 0), DHRow(0, 0.4, 0, 0)], "modified",
                             tool_rows=[DHRow(0, 0.3, 0, 0, joint=None)])
    q = standard.random_q(10, rng=0)
    np.testing.assert_allclose(standard.fk(q), modified.fk(q), atol=1e-15)
    np.testing.assert_allclose(standard.jacobian(q), modified.jacobian(q), atol=1e-15)


def test_definition_errors():
    with pytest.raises(RobotDefinitionError, match="at least one joint"):
        Robot.from_dh([], "standard")
    with pytest.raises(RobotDefinitionError, match="unknown DH convention 'craig'"):
        Robot.from_dh([DHRow(0, 1, 0, 0)], "craig")
    with pytest.raises(RobotDefinitionError, match="limits has 1 entries; expected 2"):
        Robot.from_dh([DHRow(0, 1, 0, 0)] * 2, "standard", limits=[(-1, 1)])
    with pytest.raises(RobotDefinitionError, match="max_velocity = -1.0; expected a positive number"):
        Robot.from_dh([DHRow(0, 1, 0, 0)], "standard", max_velocity=[-1.0])
    with pytest.raises(RobotDefinitionError, match="type 'ball'"):
        Robot.from_dh([DHRow(0, 1, 0, 0, joint="ball")], "standard")


def test_chain_arrays_are_read_only():
    robot = armkit.load("ur5")
    with pytest.raises(ValueError, match="read-only"):
        robot.chain.T_tool[0, 0] = 2.0
    with pytest.raises(ValueError, match="read-only"):
        robot.chain.joints[0].T_after[0, 3] = 1.0


def test_home_is_zero_clipped_into_the_limits():
    stanford = armkit.load("stanford")
    np.testing.assert_array_equal(stanford.home, [0.0, 0.0, stanford.limits[2, 0], 0.0, 0.0, 0.0])
    assert stanford.limits[2, 0] > 0 and stanford.within_limits(stanford.home)
    np.testing.assert_array_equal(armkit.load("probot-anno").home, np.zeros(6))


def test_analytic_jacobian_of_a_batch_of_three_is_each_one():
    robot = armkit.load("probot-anno")
    q = np.random.default_rng(5).uniform(-1, 1, (3, 6))
    batch = robot.analytic_jacobian(q, "zyz-euler")
    assert batch.shape == (3, 6, 6)
    for k in range(3):
        np.testing.assert_allclose(batch[k], robot.analytic_jacobian(q[k], "zyz-euler"), atol=1e-15)
    assert robot.analytic_jacobian(np.zeros((3, 6))).shape == (3, 6, 6)


@pytest.mark.parametrize("near, message", [
    ("abc", "near: expected 6 numbers, got 'abc'"),
    ([np.zeros(6), 1], "near: expected 6 numbers"),
    (np.zeros((2, 6)), r"near: shape \(2, 6\) for one target pose"),
    ([0, 0, np.nan, 0, 0, 0], "near: expected finite joint values, got nan at index 2"),
])
def test_ik_with_a_bad_near_is_one_input_error(near, message):
    robot = armkit.load("probot-anno")
    with pytest.raises(InputError, match=message):
        robot.ik(robot.fk(np.zeros(6)), near=near)


def test_ik_of_no_poses_is_empty():
    robot = armkit.load("probot-anno")
    assert robot.ik(np.zeros((0, 4, 4))).shape == (0, 6)
    assert robot.ik(np.zeros((0, 4, 4)), all_solutions=True) == []


def test_random_q_with_a_negative_seed_is_one_input_error():
    """Found by the CLI fuzz: 'armkit sim probot-anno --seed -1' ended in numpy's ValueError."""
    with pytest.raises(InputError, match="non-negative integer seed"):
        armkit.load("probot-anno").random_q(3, rng=-1)


@pytest.mark.filterwarnings("error")
def test_a_huge_joint_value_is_named_as_it_is_not_as_inf():
    # rounding to 1e-9 by scaling by 1e9 overflowed: "q1 = inf rad" and a RuntimeWarning
    chain = armkit.load("ur5").chain
    message = chain.limit_violations(np.array([1e300, 0, 0, 0, 0, -1e-14]))[0]
    assert message.startswith("joint q1 = 1e+300 rad"), message


@pytest.mark.filterwarnings("error")
def test_a_joint_value_too_large_for_degrees_is_named_in_radians():
    chain = armkit.load("ur5").chain
    message = chain.limit_violations(np.array([1e307, 0, 0, 0, 0, 0]), degrees=True)[0]
    assert message.startswith("joint q1 = 1e+307 rad is outside its limits [-6.28319, 6.28319] rad"), message


@pytest.mark.parametrize("q", [["0"] * 6, [True] * 6, [None] * 6, ["0.1", 0, 0, 0, 0, 0]])
def test_joint_values_that_are_not_numbers_are_refused(q):
    """Text, bools and None are not joint values (np.asarray(q, dtype=float) took "0" as 0.0)."""
    robot = armkit.load("ur5")
    with pytest.raises(InputError, match=r"q: expected 6 numbers, got \["):
        robot.check_q(q)
    with pytest.raises(InputError, match=r"q: expected 6 numbers"):
        robot.fk(q)
    with pytest.raises(InputError, match=r"near: expected 6 numbers"):
        robot.ik(robot.fk(np.zeros(6)), near=q)
