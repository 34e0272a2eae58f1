"""Closed-form position IK (issue 10 item 4): joints 1-3 carry the tool point to a position.

Random 3-joint arms (revolute, a prismatic third joint; standard and modified DH; generic
twists, or twists on multiples of 90 degrees with zero offsets and joint values on the pi/2
grid): every solution puts the tool point at the target (FK), the configuration that made
the target is found (or a flagged family stands for it), and numeric IK from many seeds
(nobody's closed form) finds no solution the closed form lacks.
"""

from __future__ import annotations

import itertools
import json
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit
from armkit.chain import DHRow, chain_from_dh
from armkit.cli.main import main
from armkit.errors import InputError, NoClosedFormError, UnreachableError
from armkit.ik import ik_position, ik_position_solutions, numeric_ik
from armkit.ik.position import position_case
from armkit.ik.structure import generic_rank
from armkit.kinematics import fk, geometric_jacobian
from armkit.spatial import transform_from

pi = np.pi
GRID = np.array([0.0, pi / 2, -pi / 2, pi])
POSITION_ONLY = [1, 1, 1, 0, 0, 0]


def joint_distance(chain, a, b):
    d = np.asarray(a) - np.asarray(b)
    d = np.where(chain.prismatic, d, (d + pi) % (2 * pi) - pi)
    return np.abs(d).max(axis=-1)


def three_joint_arm(rng, prismatic3, degenerate, convention):
    rows = []
    for j in range(3):
        kind = "prismatic" if prismatic3 and j == 2 else "revolute"
        if degenerate:
            a, d = (0.0 if rng.random() < 0.5 else rng.uniform(0.1, 0.4) for _ in range(2))
            alpha, theta = rng.choice([0.0, pi / 2, -pi / 2]), rng.choice(GRID)
        else:
            a, d = rng.uniform(-0.4, 0.4, 2)
            alpha, theta = rng.uniform(-pi, pi), rng.uniform(-pi, pi)
        if prismatic3 and not degenerate and j == (0 if convention == "standard" else 1):
            a = 0.0  # axes 1 and 2 meet: the case a prismatic third joint has (a quadratic)
        rows.append(DHRow(alpha, a, d, theta, kind))
    tool = DHRow(rng.choice([0.0, pi / 2]) if degenerate else rng.uniform(-pi, pi),
                 rng.uniform(0.05, 0.3), 0.0 if degenerate else rng.uniform(-0.2, 0.2), 0.0, None)
    limits = [(-pi, pi), (-pi, pi), (-0.5, 0.5) if prismatic3 else (-pi, pi)]
    return chain_from_dh(rows, convention, limits=limits, tool_rows=[tool])


def _root_width(chain, listed, result) -> float:
    """How far from a listed solution a numeric one may lie and still be that solution: 1e-5,
    or, beside a multiple root (the position rows of the Jacobian there rank-deficient), the
    distance its residual allows: there the residual grows only as the distance to the
    fourth power at most (a double root's fold meeting another singularity), so a numeric
    solution with residual r may stop r^(1/4) away (r = 1e-12 allows 1e-3)."""
    nearest = listed[np.argmin(joint_distance(chain, listed, result.q))]
    s = np.linalg.svd(geometric_jacobian(chain, nearest)[:3], compute_uv=False)
    multiple = s[-1] <= 1e-6 * s[0]
    return max(1e-5, 10.0 * result.position_error ** 0.25) if multiple else 1e-5


def check_arm(chain, q_all, seeds):
    for q in q_all:
        p = fk(chain, q)[:3, 3]
        found = ik_position_solutions(chain, p, near=q)
        assert len(found.q), f"q = {q.tolist()}: a reachable position has no solution"
        reached = fk(chain, found.q)[:, :3, 3]
        assert np.linalg.norm(reached - p, axis=1).max() <= 1e-9
        np.testing.assert_allclose(found.position_error, np.linalg.norm(reached - p, axis=1), atol=1e-15)
        if not found.family.any():
            assert joint_distance(chain, found.q, q).min() <= 1e-6, f"q = {q.tolist()} is not found"
            nearest = ik_position(chain, p, near=q, within_limits=False)
            assert joint_distance(chain, nearest, q) <= 1e-6
            # every solution numeric IK finds from many seeds is one of ours
            for seed in seeds:
                result = numeric_ik(chain, transform_from(np.eye(3), p), q0=seed, mask=POSITION_ONLY,
                                    within_limits=False, max_restarts=0)
                if result.success and result.position_error < 1e-10:
                    width = _root_width(chain, found.q, result)
                    assert joint_distance(chain, found.q, result.q).min() < width, \
                        f"numeric IK found {result.q.tolist()}, the closed form lists {found.q.tolist()}"
        assert len(found.q) <= 4


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), prismatic3=st.booleans(), degenerate=st.booleans())
def test_random_three_joint_arms(seed, prismatic3, degenerate):
    rng = np.random.default_rng(seed)
    chain = three_joint_arm(rng, prismatic3, degenerate, ["standard", "modified"][seed % 2])
    try:
        position_case(chain)
    except NoClosedFormError:  # e.g. axes 1-3 meeting at one point (the point moves on a sphere)
        assert degenerate
        return
    q = rng.choice(GRID, (4, 3)) if degenerate else rng.uniform(chain.lower, chain.upper, (4, 3))
    if prismatic3:
        q[:, 2] = rng.uniform(-0.5, 0.5, 4)
    check_arm(chain, q, rng.uniform(chain.lower, chain.upper, (6, 3)))


def test_the_readme_arm_has_four_position_solutions(capsys):
    """Before: 'armkit ik my_arm.toml --position 0.3 0.1 0.3 --all' said 'drop --all'."""
    robot = armkit.load("examples/data/my_arm.toml")
    args = ["ik", "examples/data/my_arm.toml", "--position", "0.3", "0.1", "0.3", "--all", "--json"]
    assert main(args) == 0
    data = json.loads(capsys.readouterr().out)
    q = np.array(data["solutions"])
    assert len(q) == 4 and "closed form, position only" in data["method"]
    np.testing.assert_allclose(robot.fk(q)[:, :3, 3], np.tile([0.3, 0.1, 0.3], (4, 1)), atol=1e-12)
    np.testing.assert_allclose(q, robot.ik_position([0.3, 0.1, 0.3], all_solutions=True), atol=0)


@pytest.mark.parametrize("name", ["puma560", "probot-anno", "stanford", "zju-i"])
def test_first_three_joints_of_six_joint_arms(name):
    """Joints 4..6 held at near's values: the tool point (not the wrist centre) is placed."""
    robot = armkit.load(name)
    rng = np.random.default_rng(3)
    for q in robot.random_q(5, rng=rng):
        p = robot.fk(q)[:3, 3]
        found = robot.ik_position(p, all_solutions=True, near=q, within_limits=False)
        np.testing.assert_allclose(found[:, 3:], np.tile(q[3:], (len(found), 1)), atol=0)
        np.testing.assert_allclose(robot.fk(found)[:, :3, 3], np.tile(p, (len(found), 1)), atol=1e-9)
        assert joint_distance(robot.chain, found, q).min() <= 1e-9


def test_out_of_reach_and_bad_input():
    robot = armkit.load("examples/data/my_arm.toml")
    with pytest.raises(UnreachableError, match=r"out of reach: the closest tool position found is 2.5\d* m"):
        robot.ik_position([3.0, 0.1, 0.3])
    with pytest.raises(InputError, match="position: expected 3 finite numbers"):
        robot.ik_position([0.3, np.nan, 0.3])
    with warnings.catch_warnings():  # no overflow on the way
        warnings.simplefilter("error")
        for far, distance in (([1e308, 0.0, 0.0], 1e308), ([1e300] * 3, np.sqrt(3) * 1e300),
                              ([0.0, -3e7, 0.0], 3e7)):
            with pytest.raises(UnreachableError, match="a million times the arm.s whole length") as error:
                robot.ik_position(far)
            assert error.value.position_error == pytest.approx(distance, rel=1e-15)
        stanford = armkit.load("stanford")  # an unlimited prismatic joint might reach anything
        unlimited = armkit.Robot.from_dh(stanford.dh.rows, stanford.dh.convention,
                                         limits=[(-3, 3)] * 2 + [(-np.inf, np.inf)] + [(-3, 3)] * 3)
        message = r"position \[1e\+308, 0, 0\] m: 1e\+308 m from the base; position IK takes targets up to"
        with pytest.raises(InputError, match=message):
            unlimited.ik_position([1e308, 0.0, 0.0])
    with pytest.raises(InputError, match="near: expected 3 finite joint values"):
        robot.ik_position([0.3, 0.1, 0.3], near=[0, 1])
    with pytest.raises(NoClosedFormError, match="needs 3 joints"):
        chain_2r = chain_from_dh([DHRow(0, 0.3, 0, 0)] * 2, "standard")
        ik_position(chain_2r, [0.3, 0.2, 0.0])


def test_a_shoulder_whose_axes_meet_moves_the_tool_point_on_a_sphere_only():
    """Axes 1-3 through one point: the tool point has two directions (rank 2), so no closed form."""
    tool = np.eye(4)
    tool[:3, 3] = [0.5, 0.0, 0.1]
    robot = armkit.Robot.from_poe(np.eye(3)[[2, 1, 0]], np.zeros((3, 3)), tool)
    assert generic_rank(robot.chain, joints=3, position_only=True) == 2
    assert generic_rank(armkit.load("ur5").chain, joints=3, position_only=True) == 3
    with pytest.raises(NoClosedFormError, match="only 2 independent directions"):
        robot.ik_position([0.0, 0.5, 0.1])


def test_a_family_is_flagged_on_axis_1():
    """The tool point on axis 1 of an elbow arm: q1 is free, the member found is flagged."""
    rows = [DHRow(pi / 2, 0, 0.2, 0), DHRow(0, 0.3, 0, 0), DHRow(0, 0.25, 0, 0)]
    chain = chain_from_dh(rows, "standard", limits=[(-pi, pi)] * 3)
    found = ik_position_solutions(chain, [0.0, 0.0, 0.45])
    assert found.family.all() and len(found.q)
    assert np.linalg.norm(fk(chain, found.q)[:, :3, 3] - [0, 0, 0.45], axis=1).max() < 1e-12


def test_held_joints_keep_their_values_and_only_joints_1_to_3_are_copied():
    """Joints 4..n keep near's values exactly (not wrapped into the limits), and the UR5's
    +-360 degree limits copy joints 1-3 only: 4 solutions x 2^3 = 32."""
    ur5 = armkit.load("ur5")
    near = np.array([0.1, -1.0, 1.0, 4.0, 0.5, -0.3])
    p = ur5.fk(near)[:3, 3]
    every = ur5.ik_position(p, all_solutions=True, near=near, within_limits=False, turn_copies=True)
    assert every.shape == (32, 6)
    np.testing.assert_array_equal(every[:, 3:], np.tile(near[3:], (32, 1)))
    np.testing.assert_allclose(every[0], near, atol=1e-9)
    assert len(ur5.ik_position(p, all_solutions=True, near=near)) == 4     # each once by default
    np.testing.assert_allclose(ur5.fk(every)[:, :3, 3], np.tile(p, (32, 1)), atol=1e-9)


def test_a_held_value_outside_its_limits_leaves_every_solution_outside():
    stanford = armkit.load("stanford")
    near = np.zeros(6)
    near[3] = 4.0  # q4's limits are narrower than that
    assert stanford.chain.upper[3] < 4.0
    p = stanford.fk(near)[:3, 3]
    found = ik_position_solutions(stanford, p, near=near)
    assert len(found.q) and not found.within_limits.any() and (found.q[:, 3] == 4.0).all()


@pytest.mark.parametrize("bad", [{"position": "abc"}, {"near": "abc"}, {"near": [0, 0, [1]]}])
def test_text_or_ragged_input_is_an_input_error(bad):
    arm = armkit.load("examples/data/my_arm.toml")
    kwargs = {"position": [0.3, 0.1, 0.3], **bad}
    with pytest.raises(InputError, match=next(iter(bad))):
        arm.ik_position(kwargs.pop("position"), **kwargs)


def test_robot_ik_position_takes_its_options_by_name():
    arm = armkit.load("examples/data/my_arm.toml")
    with pytest.raises(TypeError):
        arm.ik_position([0.3, 0.1, 0.3], True)


def test_cli_position_all_with_and_without_turn_copies(capsys):
    assert main(["ik", "ur5", "--position", "0.3", "0.1", "0.3", "--all", "--turn-copies", "--json"]) == 0
    assert len(json.loads(capsys.readouterr().out)["solutions"]) == 32
    assert main(["ik", "ur5", "--position", "0.3", "0.1", "0.3", "--all", "--json"]) == 0
    once = json.loads(capsys.readouterr().out)
    assert len(once["solutions"]) == 4 and once["configurations_inside_limits"] == 32



def _poe_elbow_arm(tool):
    """A 6R POE arm: axis 1 meets axis 2, axes 2 and 3 parallel, the wrist centre on axis 3
    (so on the pi/2 grid the tool point often lies on axis 3 and q3 turns it nowhere)."""
    axes = [[0, 0, 1], [0, 1, 0], [0, 1, 0], [1, 0, 0], [0, 1, 0], [1, 0, 0]]
    centre = [0.4, 0.0, 0.3]
    points = [[0, 0, 0], [0, 0, 0.3], [0.4, 0, 0.3], centre, centre, centre]
    return armkit.Robot.from_poe(axes, points, transform_from(np.eye(3), np.add(centre, tool)))


def _covered(chain, row, is_family, q) -> bool:
    """``row`` is ``q`` (joints 1-3, modulo 2 pi), or a flagged family member that differs from
    ``q`` in one joint only, a joint that moves the tool point nowhere (the family holds ``q``)."""
    d = np.abs((row[:3] - q[:3] + pi) % (2 * pi) - pi)
    if d.max() <= 1e-6:
        return True
    for j in range(3):
        if is_family and np.delete(d, j).max() <= 1e-6:
            moved = row.copy()
            moved[j] = q[j]
            return bool(np.linalg.norm(fk(chain, moved)[:3, 3] - fk(chain, row)[:3, 3]) <= 1e-9)
    return False


@pytest.mark.parametrize("tool", [[0.0, 0.0, 0.1], [0.1, 0.0, 0.0]])
def test_every_position_on_the_grid_of_a_poe_elbow_arm_is_found(tool):
    """Issue 26 item 6: with the tool point on axis 3 (to rounding) the planar 2R's second link
    has length 0, and SP3 measured the rounding of |a|^2 - |v|^2 against their difference (0)
    instead of against |a|^2: 'out of reach ... 5.55e-17 m away', or the branch lost."""
    robot = _poe_elbow_arm(tool)
    for q in itertools.product(GRID, repeat=6):
        q = np.array(q)
        p = robot.fk(q)[:3, 3]
        nearest = robot.ik_position(p, near=q, within_limits=False)
        assert np.linalg.norm(robot.fk(nearest)[:3, 3] - p) <= 1e-9
        found = ik_position_solutions(robot, p, near=q)
        rows = zip(found.q, found.family, strict=True)
        assert any(_covered(robot.chain, row, fam, q) for row, fam in rows), \
            f"q = {q.tolist()}: listed {found.q[:, :3].tolist()}, family {found.family.tolist()}"
