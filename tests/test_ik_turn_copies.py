"""All solutions list each solution once, or with ``turn_copies=True`` every whole-turn copy inside the
limits (issue 10, item 5; issue 20, item 3).

The expected copies are counted here independently: for each solution (listed once with
``turn_copies=False``) and each joint, the whole numbers ``t`` with ``q + 2 pi t`` inside
the limits of a joint that spans more than a turn.
"""

from __future__ import annotations

import importlib
import json
import math
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit
from armkit import Robot
from armkit.chain import LIMIT_TOLERANCE, DHRow, chain_from_dh
from armkit.cli.main import main
from armkit.errors import InputError, SolutionsLeftOffWarning
from armkit.ik import ik_solutions
from armkit.ik.pipeline import MAX_SOLUTIONS

UR5 = armkit.load("ur5")
Q = np.array([0.3, -1.0, 1.2, 0.4, 0.7, 0.5])


def with_limits(robot: Robot, limits) -> Robot:
    dh = robot.dh
    return Robot.from_dh(dh.rows, dh.convention, limits=limits, base_rows=dh.base_rows,
                         tool_rows=dh.tool_rows, T_base=dh.T_base, T_tool=dh.T_tool)


def expected_copies(robot: Robot, q: np.ndarray) -> list[list[float]]:
    """Per joint of one solution, the values its copies take there."""
    values = []
    for j, (lower, upper) in enumerate(zip(robot.chain.lower, robot.chain.upper, strict=True)):
        wide = (not robot.chain.prismatic[j] and math.isfinite(lower) and math.isfinite(upper)
                and upper - lower > 2 * math.pi + 2 * LIMIT_TOLERANCE)
        if not wide:
            values.append([q[j]])
            continue
        low, high = lower - LIMIT_TOLERANCE, upper + LIMIT_TOLERANCE
        turns = range(math.ceil((low - q[j]) / (2 * math.pi)), math.floor((high - q[j]) / (2 * math.pi)) + 1)
        values.append([q[j] + 2 * math.pi * t for t in turns])
    return values


def as_set(q: np.ndarray) -> set[tuple[float, ...]]:
    return {tuple(row) for row in np.round(q, 7)}


def check_all_copies(robot: Robot, T: np.ndarray, near: np.ndarray) -> np.ndarray:
    once = robot.ik(T, all_solutions=True, near=near, turn_copies=False)
    listed = robot.ik(T, all_solutions=True, near=near, turn_copies=True)
    expected = set()
    for q in once:
        for copy in np.stack(np.meshgrid(*expected_copies(robot, q), indexing="ij"), -1).reshape(-1, robot.n):
            expected.add(tuple(np.round(copy, 7)))
    assert len(listed) == len(expected) == len(as_set(listed))  # every copy, each once
    assert as_set(listed) == expected
    assert robot.within_limits(listed).all()
    np.testing.assert_allclose(robot.fk(listed), np.broadcast_to(T, (len(listed), 4, 4)), rtol=0, atol=1e-9)
    distance = np.linalg.norm(listed - near, axis=1)
    assert np.all(np.diff(distance) >= -1e-12)  # nearest first
    np.testing.assert_allclose(listed[0], robot.ik(T, near=near), rtol=0, atol=1e-12)
    return listed


def test_ur5_at_plus_minus_360_degrees_lists_2_to_the_6_copies_of_each_solution():
    T = UR5.fk(Q)
    assert UR5.chain.spans_turns == (0, 1, 2, 3, 4, 5)
    listed = check_all_copies(UR5, T, Q)
    assert len(UR5.ik(T, all_solutions=True)) == 8 and len(listed) == 512   # each once by default
    found = ik_solutions(UR5, T, near=Q, turn_copies=True)
    np.testing.assert_array_equal(found.q, listed)
    assert found.within_limits.all() and found.position_error.max() < 1e-12
    other = UR5.fk(-Q)  # a pose with 4 solutions
    batch = ik_solutions(UR5, np.stack([T, other]), near=Q, turn_copies=True)
    assert batch.counts.tolist() == [512, 64 * len(UR5.ik(other, all_solutions=True, turn_copies=False))] \
        == [512, 256]
    np.testing.assert_array_equal(batch[0].q, listed)
    assert len(UR5.ik(np.stack([T, T]), all_solutions=True, near=Q, turn_copies=True)[1]) == 512
    assert len(UR5.ik(np.stack([T, T]), all_solutions=True, near=Q)[1]) == 8


@settings(max_examples=25, deadline=None)
@given(st.lists(st.sampled_from([170.0, 180.0, 185.0, 270.0, 360.0, 400.0]), min_size=6, max_size=6),
       st.integers(0, 2**32 - 1))
def test_copies_of_random_limits(half_spans, seed):
    """Joints spanning less than, exactly, a little more than, and more than two turns."""
    robot = with_limits(UR5, [(-math.radians(h), math.radians(h)) for h in half_spans])
    q = robot.random_q(rng=seed)
    near = robot.random_q(rng=seed + 1)
    check_all_copies(robot, robot.fk(q), near)


def test_a_joint_spanning_exactly_one_turn_holds_one_copy():
    robot = with_limits(UR5, [(-math.pi, math.pi)] * 6)
    q = np.array([math.pi, -1.0, 1.2, 0.4, 0.7, -math.pi])
    assert robot.chain.spans_turns == ()
    listed = robot.ik(robot.fk(q), all_solutions=True, near=q, turn_copies=True)
    assert len(listed) == len(robot.ik(robot.fk(q), all_solutions=True)) <= 8


def test_unbounded_joints_hold_one_copy():
    robot = with_limits(UR5, [(-math.inf, math.inf)] + [(-math.pi, math.pi)] * 5)
    assert robot.chain.spans_turns == ()
    near = Q + np.array([4 * math.pi, 0, 0, 0, 0, 0])
    listed = robot.ik(robot.fk(Q), all_solutions=True, near=near, turn_copies=True)
    np.testing.assert_allclose(listed[0], near, atol=1e-9)  # the copy nearest to near, 2 turns up


def test_outside_the_limits_a_solution_is_listed_once():
    T = UR5.fk(Q)
    narrow = with_limits(UR5, [(-2 * math.pi, 2 * math.pi)] + [(-0.2, 0.2)] * 5)
    found = ik_solutions(narrow, T, near=Q, turn_copies=True)
    once = ik_solutions(narrow, T, near=Q)
    assert not found.within_limits.any() and len(found.q) == len(once.q) == 8


def test_more_copies_than_listed_warn_and_keep_the_nearest():
    wide = with_limits(UR5, [(-math.radians(1000), math.radians(1000))] * 6)  # 5 or 6 copies a joint
    T = wide.fk(Q)
    with pytest.warns(SolutionsLeftOffWarning, match=r"solutions inside the limits .* the 4096 nearest"):
        listed = wide.ik(T, all_solutions=True, near=Q, turn_copies=True)
    assert len(listed) == MAX_SOLUTIONS
    np.testing.assert_allclose(listed[0], Q, atol=1e-12)
    distance = np.linalg.norm(listed - Q, axis=1)
    assert np.all(np.diff(distance) >= -1e-12)
    # the nearest 4096 of all: no copy left off is nearer than the farthest one listed
    once = wide.ik(T, all_solutions=True, near=Q, turn_copies=False)
    everything = [np.linalg.norm(np.stack(np.meshgrid(*[np.array(v) - Q[j] for j, v in
                                                        enumerate(expected_copies(wide, q))],
                                                      indexing="ij"), -1).reshape(-1, 6), axis=1)
                  for q in once]
    assert np.sort(np.concatenate(everything))[MAX_SOLUTIONS - 1] == pytest.approx(distance[-1], abs=1e-9)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert len(wide.ik(T, all_solutions=True, turn_copies=False)) == 8


def test_cli_lists_each_solution_once_says_how_many_copies_and_turn_copies_lists_them(capsys):
    T = UR5.fk(Q)
    args = ["ik", "ur5", "--matrix", *map(str, T.ravel()), "--all", "--json"]
    assert main(args) == 0
    once = json.loads(capsys.readouterr().out)
    assert main([*args, "--turn-copies"]) == 0
    listed = json.loads(capsys.readouterr().out)
    assert len(listed["solutions"]) == 512 and listed["numbers"] == list(range(1, 513))
    assert len(once["solutions"]) == 8 and once["numbers"] == list(range(1, 9))
    assert once["configurations_inside_limits"] == len(listed["solutions"])
    assert listed["configurations_inside_limits"] is None
    assert main(args[:-1]) == 0
    out = capsys.readouterr().out
    assert "8 IK solutions" in out and "the 8 solutions inside the limits make 512 configurations" in out
    assert "--turn-copies lists them" in out
    assert main([*args[:-1], "--turn-copies"]) == 0
    assert "Whole-turn copies are listed" in capsys.readouterr().out


def test_the_nearest_solution_is_chosen_among_the_copies():
    near = Q - np.array([2 * math.pi, 0, 0, 0, 2 * math.pi, 0])      # a copy of Q, turns away
    np.testing.assert_allclose(UR5.ik(UR5.fk(Q), near=near), near, atol=1e-9)
    once = UR5.ik(UR5.fk(Q), all_solutions=True, near=near)
    np.testing.assert_allclose(once[0], near, atol=1e-9)           # each solution's nearest copy


def test_the_warning_names_the_callers_line_and_a_batch_warns_once():
    wide = with_limits(UR5, [(-math.radians(1000), math.radians(1000))] * 6)
    T = wide.fk(np.stack([Q, Q * 0.5, Q * 0.25]))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        found = ik_solutions(wide, T, near=Q, turn_copies=True)
    left_off = [w for w in caught if issubclass(w.category, SolutionsLeftOffWarning)]
    assert len(left_off) == 1 and "3 of 3 poses" in str(left_off[0].message)
    assert left_off[0].filename == __file__  # this test's line, not armkit's
    assert (found.counts == MAX_SOLUTIONS).all()


def test_a_stacked_batch_pads_with_nan():
    wide = with_limits(UR5, [(-2 * math.pi, 2 * math.pi)] + [(-math.pi, math.pi)] * 5)
    far = wide.fk(Q)
    far[:3, 3] += 10.0  # out of reach: no solution
    mixed = ik_solutions(wide, np.stack([wide.fk(Q), far]), near=Q, turn_copies=True)
    assert mixed.counts[0] == 16 and mixed.counts[1] == 0  # q1's two copies of each of 8
    assert np.isnan(mixed.q[1]).all() and np.isnan(mixed.position_error[1]).all()
    assert len(mixed[1].q) == 0


def test_prismatic_joints_with_wide_limits_have_no_copies():
    rows = [DHRow(0, 0.3, 0, 0), DHRow(0, 0.2, 0, 0, "prismatic")]
    chain = chain_from_dh(rows, "standard", limits=[(-math.pi, math.pi), (-20.0, 20.0)])
    assert chain.spans_turns == ()


def test_a_batch_whose_turn_copies_would_not_fit_is_refused_before_listing_them(monkeypatch):
    solve_module = importlib.import_module("armkit.ik.solve")
    monkeypatch.setattr(solve_module, "MAX_BATCH_ROWS", 2000)  # 1e7 in use: the rule, at a test's scale
    T = UR5.fk(UR5.random_q(3, rng=0))  # 512, 256 and 512 solutions with their copies
    message = (r"T_base_tool: 5 poses whose whole-turn copies give up to 512 solutions each \(pose 1\) "
               r"would list 2,560 rows \(about 0.000184 GB\), more than MAX_BATCH_ROWS = 2,000; solve at "
               r"most 3 poses at a time, or pass turn_copies=False")
    batch = np.concatenate([T, T[:2]])
    with pytest.raises(InputError, match=message):
        ik_solutions(UR5, batch, turn_copies=True)
    with pytest.raises(InputError, match=r"5 poses whose whole-turn copies"):
        UR5.ik(batch, all_solutions=True, turn_copies=True)
    assert ik_solutions(UR5, T, turn_copies=True).counts.tolist() == [512, 256, 512]  # 3 x 512 rows fit
    once = ik_solutions(UR5, batch, turn_copies=False).counts  # each solution once: 512 = 8 x 2^6
    assert once.tolist() == [8, 4, 8, 8, 4]


def test_a_batch_s_copies_are_listed_in_one_call_the_same_on_any_thread_count():
    """Enough poses for two threads (the core splits batches of 4096 or more): the same listing,
    bit for bit, and each pose's listing is the one it has alone."""
    wide = with_limits(UR5, [(-2 * math.pi, 2 * math.pi)] * 2 + [(-math.pi, math.pi)] * 4)
    T = wide.fk(wide.random_q(4100, rng=7))
    one, two = (ik_solutions(wide, T, near=Q, turn_copies=True, threads=t) for t in (1, 2))
    for field in ("q", "counts", "within_limits", "family", "position_error", "orientation_error"):
        np.testing.assert_array_equal(getattr(one, field), getattr(two, field))
    assert one.counts.max() == 32  # 8 solutions x 2 x 2 copies
    for i in (0, 1234, 4099):
        alone = ik_solutions(wide, T[i], near=Q, turn_copies=True)
        np.testing.assert_array_equal(alone.q, one[i].q)
        np.testing.assert_array_equal(alone.position_error, one[i].position_error)


def test_each_copy_carries_its_solution_s_residuals_and_flags():
    """A copy has its solution's tool pose, so it is listed with that solution's FK residuals and
    flags (not put through FK again); its own FK agrees to rounding."""
    T = UR5.fk(Q)
    once = ik_solutions(UR5, T, near=Q)
    listed = ik_solutions(UR5, T, near=Q, turn_copies=True)
    turns = (listed.q[:, None, :] - once.q[None, :, :]) / (2 * math.pi)
    copy_of = np.all(np.abs(turns - np.round(turns)) < 1e-9, axis=-1)  # (512, 8): whole turns apart
    assert len(listed.q) == 512 and (copy_of.sum(axis=1) == 1).all()
    source = copy_of.argmax(axis=1)
    np.testing.assert_array_equal(listed.position_error, once.position_error[source])
    np.testing.assert_array_equal(listed.orientation_error, once.orientation_error[source])
    np.testing.assert_array_equal(listed.family, once.family[source])
    F = UR5.fk(listed.q)
    np.testing.assert_allclose(np.linalg.norm(F[:, :3, 3] - T[:3, 3], axis=-1), listed.position_error,
                               rtol=0, atol=1e-14)
