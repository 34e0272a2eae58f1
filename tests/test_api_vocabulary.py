"""One API vocabulary (issue 10, item 11): a Robot everywhere, one word per meaning, old names
kept as deprecated aliases that warn."""

from __future__ import annotations

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
