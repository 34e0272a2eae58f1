"""Locked joints: the reduced robot is the full one with some joints fixed, with its own closed form."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import assert_transform_close
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit
from armkit.errors import InputError, JointLimitError

# KUKA LBR iiwa 14, standard DH (the maker's lengths): a 7R arm with a spherical shoulder
# (axes 1-3) and a spherical wrist (axes 5-7), joint 3 the elbow roll.
IIWA = [armkit.DHRow(-np.pi / 2, 0, 0.36, 0), armkit.DHRow(np.pi / 2, 0, 0, 0),
        armkit.DHRow(np.pi / 2, 0, 0.42, 0), armkit.DHRow(-np.pi / 2, 0, 0, 0),
        armkit.DHRow(-np.pi / 2, 0, 0.4, 0), armkit.DHRow(np.pi / 2, 0, 0, 0), armkit.DHRow(0, 0, 0.126, 0)]


def iiwa() -> armkit.Robot:
    limits = np.radians([170, 120, 170, 120, 170, 120, 175])
    return armkit.Robot.from_dh(IIWA, "standard", name="iiwa", limits=[(-x, x) for x in limits])


def test_srs_arm_with_elbow_roll_locked_is_a_spherical_wrist_6r_arm():
    full = iiwa()
    assert armkit.analyze_structure(full.chain).kind == "none"
    arm = full.lock({"q3": 0.3})
    assert isinstance(arm, armkit.LockedRobot) and arm.n == 6
    assert arm.joint_names == ["q1", "q2", "q4", "q5", "q6", "q7"]
    assert armkit.analyze_structure(arm.chain).kind == "spherical-wrist"
    for q in arm.random_q(10, rng=3):
        T = arm.fk(q)
        solutions = arm.ik(T, all_solutions=True)
        full_q = arm.full_q(solutions)
        assert_transform_close(full.fk(full_q), np.broadcast_to(T, full_q.shape[:1] + (4, 4)), 1e-9, 1e-9)
        assert np.all(full_q[:, 2] == 0.3) and np.abs(solutions - q).max(axis=1).min() < 1e-6


@settings(max_examples=40, deadline=None)
@given(st.sampled_from(armkit.builtin_robots()), st.data())
def test_locked_robot_is_the_full_robot_with_those_joints_fixed(name, data):
    full = armkit.load(name)
    if full.n < 2:
        return
    indices = data.draw(st.lists(st.integers(0, full.n - 1), min_size=1, max_size=full.n - 1, unique=True))
    values = full.random_q(rng=data.draw(st.integers(0, 2**32 - 1)))
    keys = [full.joint_names[i] if data.draw(st.booleans()) else i for i in indices]
    arm = full.lock({key: values[i] for key, i in zip(keys, indices, strict=True)})
    assert sorted(arm.locked) == sorted(indices)
    q = arm.random_q(6, rng=1)
    q_full = arm.full_q(q)
    np.testing.assert_array_equal(arm.reduced_q(q_full), q)
    assert_transform_close(arm.fk(q), full.fk(q_full), 1e-12, 1e-12)
    np.testing.assert_allclose(arm.jacobian(q), full.jacobian(q_full)[..., arm.free], atol=1e-12)
    np.testing.assert_array_equal(arm.limits, full.limits[arm.free])


def test_locking_a_locked_robot_locks_more_joints_of_the_full_one():
    full = armkit.load("puma560")
    arm = full.lock({"q2": 0.1}).lock({3: -0.2})  # index 3 of the reduced robot is joint q5
    assert arm.full_robot is full and arm.locked == {1: 0.1, 4: -0.2}
    assert arm.joint_names == ["q1", "q3", "q4", "q6"]
    q = arm.random_q(rng=0)
    assert_transform_close(arm.fk(q), full.fk(arm.full_q(q)), 1e-12, 1e-12)


@pytest.mark.parametrize(("values", "error", "message"), [
    ({"q9": 0.1}, InputError,
     r"joint 'q9' to lock: expected a joint name \(q1, q2, q3, q4, q5, q6\) or an index"),
    ({6: 0.1}, InputError, r"joint 6 to lock: expected a joint name .* or an index 0 to 5"),
    ({True: 0.1}, InputError, "joint True to lock"),
    ({"q2": 0.1, 1: 0.2}, InputError, "joint q2 is locked twice"),
    ({"q2": "x"}, InputError, r"joint q2: lock value 'x' is not a number"),
    ({"q2": float("nan")}, InputError,
     r"joint q2: lock value nan is not a finite number from -1e\+06 to 1e\+06"),
    ({"q6": 1e300}, InputError,
     r"joint q6: lock value 1e\+300 is not a finite number from -1e\+06 to 1e\+06"),
    ({"q2": 4.0}, JointLimitError,
     r"cannot lock: joint q2 = 4 rad is outside its limits \[-0.785398, 3.92699\] rad"),
    ({f"q{i}": 0.0 for i in range(1, 7)}, InputError, "locking all 6 joints leaves no robot"),
    ({}, InputError, "expected a mapping"),
    ([("q1", 0.0)], InputError, "expected a mapping"),
])
def test_bad_locks_are_refused(values, error, message):
    with pytest.raises(error, match=message):
        armkit.load("puma560").lock(values)
