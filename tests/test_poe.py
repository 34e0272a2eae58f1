"""Product of exponentials -> chain: checked against the textbook formula T = prod expm([xi] q) M."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg
from conftest import assert_transform_close
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit
from armkit.errors import RobotDefinitionError
from armkit.ik import analyze_structure
from armkit.poe import chain_from_poe, poe_from_chain, rotation_z_to


def poe_fk(axes, points, kinds, M, q):
    """Lynch & Park (4.14): twists [w; v] with v = -w x p (revolute) or [0; h] (prismatic)."""
    T = np.eye(4)
    for h, p, kind, q_i in zip(axes, points, kinds, q, strict=True):
        h = np.asarray(h, float) / np.linalg.norm(h)
        w, v = (np.zeros(3), h) if kind == "prismatic" else (h, -np.cross(h, p))
        twist = np.zeros((4, 4))
        twist[:3, :3] = [[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]]
        twist[:3, 3] = v
        T = T @ scipy.linalg.expm(twist * q_i)
    return T @ M


unit = st.lists(st.floats(-1, 1), min_size=3, max_size=3).filter(lambda v: np.linalg.norm(v) > 0.1)
point = st.lists(st.floats(-1, 1), min_size=3, max_size=3)


@st.composite
def poe_arms(draw):
    n = draw(st.integers(1, 7))
    axes = np.array([draw(unit) for _ in range(n)])
    points = np.array([draw(point) for _ in range(n)])
    kinds = [draw(st.sampled_from(["revolute", "revolute", "prismatic"])) for _ in range(n)]
    rpy = draw(st.lists(st.floats(-np.pi, np.pi), min_size=3, max_size=3))
    M = armkit.spatial.transforms.transform_from_pose([*draw(point), *rpy], "xyz-fixed")
    return axes, points, kinds, M, draw(st.integers(0, 2**32 - 1))


@settings(max_examples=60, deadline=None)
@given(poe_arms())
def test_chain_from_poe_equals_the_product_of_exponentials(arm):
    axes, points, kinds, M, seed = arm
    robot = armkit.Robot.from_poe(axes, points, M, kinds=kinds)
    q = robot.random_q(4, rng=seed)
    expected = np.array([poe_fk(axes, points, kinds, M, q_k) for q_k in q])
    assert_transform_close(robot.fk(q), expected, 1e-12, 1e-12)


@settings(max_examples=40, deadline=None)
@given(poe_arms())
def test_poe_of_a_chain_gives_the_chain_back(arm):
    axes, points, kinds, M, seed = arm
    chain = chain_from_poe(axes, points, M, kinds=kinds)
    poe = poe_from_chain(chain)
    np.testing.assert_allclose(poe.axes, axes / np.linalg.norm(axes, axis=1, keepdims=True), atol=1e-12)
    # the point may move along its line; its distance from the given line is what must vanish
    d = poe.points - points
    along = np.sum(d * poe.axes, axis=1, keepdims=True) * poe.axes
    np.testing.assert_allclose(d - along, 0, atol=1e-12)
    assert_transform_close(poe.M, M, 1e-12, 1e-12)


@pytest.mark.parametrize("axis", [[1, 0, 0], [0, 1, 0], [0, 0, 1], [-1, 0, 0], [0, -1, 0], [0, 0, -1],
                                  [1, 1, 1], [0.3, -0.2, -0.9], [1e-9, 0, -1], [0, 1e-12, 1]])
def test_rotation_z_to_is_a_rotation_onto_the_axis(axis):
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    R = rotation_z_to(a)
    np.testing.assert_allclose(R @ [0, 0, 1], a, atol=1e-15)
    np.testing.assert_allclose(R.T @ R, np.eye(3), atol=1e-15)
    assert np.linalg.det(R) == pytest.approx(1.0, abs=1e-15)


def test_coordinate_axes_give_exact_frames():
    assert rotation_z_to([1.0, 0, 0]).tolist() == [[0, 0, 1], [0, 1, 0], [-1, 0, 0]]
    assert rotation_z_to([0, 0, 1.0]).tolist() == np.eye(3).tolist()


def test_ur5_written_as_joint_lines_has_three_parallel_axes():
    """IK-Geo's / EAIK's H, P form of the UR5 (the DH built-in's lines at q = 0)."""
    ur5 = armkit.load("ur5")
    poe = poe_from_chain(ur5.chain)
    robot = armkit.Robot.from_poe(poe.axes, poe.points, poe.M, T_base=poe.T_base, limits=ur5.limits)
    assert analyze_structure(robot.chain).kind == "three-parallel"
    q = ur5.random_q(5, rng=1)
    assert_transform_close(robot.fk(q), ur5.fk(q), 1e-14, 1e-14)
    for q_k in q:
        assert_transform_close(robot.fk(robot.ik(robot.fk(q_k), near=q_k)), robot.fk(q_k), 1e-9, 1e-9)


@pytest.mark.parametrize(("axes", "points", "message"), [
    ([[0, 0, 0]], [[0, 0, 0]], r"joint 'q1': axis \[0.0, 0.0, 0.0\]: expected three finite numbers, not all "
                               r"zero"),
    ([[0, 0, 1]], [[0, 0]], r"expected two \(n, 3\) arrays"),
    (np.zeros((0, 3)), np.zeros((0, 3)), "at least one joint"),
    ([[0, 0, np.nan]], [[0, 0, 0]], "expected three finite numbers"),
])
def test_bad_joint_lines_are_refused(axes, points, message):
    with pytest.raises(RobotDefinitionError, match=message):
        chain_from_poe(axes, points, np.eye(4))
