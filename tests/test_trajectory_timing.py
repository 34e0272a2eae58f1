"""Fitting durations to limits: violated before, met after, no segment longer than needed."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import SEED_AMAX, SEED_VMAX, SEED_WAYPOINTS
from hypothesis import given, settings
from hypothesis import strategies as st

from armkit.errors import InputError
from armkit.trajectory import auto_time, limit_ratio, limit_ratios, min_jerk, stretch_to_limits


def within(traj, vmax=SEED_VMAX, amax=SEED_AMAX) -> bool:
    return limit_ratio(traj, vmax, amax) <= 1.0


def assert_each_segment_tight(traj, lower):
    """Shrinking any segment above its lower bound by 1 % violates a limit."""
    for i, duration in enumerate(traj.durations):
        if duration > lower[i] * (1 + 1e-9):
            shorter = traj.durations.copy()
            shorter[i] *= 0.99
            assert not within(min_jerk(traj.waypoints, shorter)), f"segment {i + 1} could be shorter"


def test_uniform_scaling_is_exact():
    traj = min_jerk(SEED_WAYPOINTS, [2.0, 2.0, 2.0])
    k = limit_ratio(traj, SEED_VMAX, SEED_AMAX)
    assert k > 1
    scaled = min_jerk(SEED_WAYPOINTS, np.full(3, 2.0 * k))
    assert limit_ratio(scaled, SEED_VMAX, SEED_AMAX) == pytest.approx(1.0, rel=1e-12)
    np.testing.assert_allclose(scaled.peak_velocity, traj.peak_velocity / k, rtol=1e-12)
    np.testing.assert_allclose(scaled.peak_acceleration, traj.peak_acceleration / k**2, rtol=1e-12)


def test_stretch_violated_before_met_after_and_tight():
    requested = np.array([3.0, 1.5, 2.0])
    assert not within(min_jerk(SEED_WAYPOINTS, requested))
    traj = stretch_to_limits(SEED_WAYPOINTS, requested, SEED_VMAX, SEED_AMAX)
    assert within(traj)
    assert np.all(traj.durations >= requested)
    np.testing.assert_array_equal(traj.requested_durations, requested)
    np.testing.assert_allclose(traj.stretch, traj.durations / requested)
    assert np.any(traj.stretch > 1.1)
    assert_each_segment_tight(traj, requested)
    velocity, acceleration = limit_ratios(traj, SEED_VMAX, SEED_AMAX)
    assert max(velocity.max(), acceleration.max()) > 0.999     # it touches a limit


def test_stretch_leaves_a_feasible_trajectory_alone():
    traj = stretch_to_limits(SEED_WAYPOINTS, [10, 10, 10], SEED_VMAX, SEED_AMAX)
    np.testing.assert_array_equal(traj.durations, [10, 10, 10])
    np.testing.assert_array_equal(traj.stretch, 1.0)


def test_auto_time_is_the_shortest_within_limits():
    traj = auto_time(SEED_WAYPOINTS, SEED_VMAX, SEED_AMAX)
    assert within(traj)
    assert_each_segment_tight(traj, np.zeros(3))
    uniform = min_jerk(SEED_WAYPOINTS, np.full(3, 10.0))
    uniform_fit = uniform.duration * limit_ratio(uniform, SEED_VMAX, SEED_AMAX)
    assert traj.duration < uniform_fit            # per segment beats one global stretch
    shorter = min_jerk(SEED_WAYPOINTS, traj.durations * 0.99)
    assert not within(shorter)


def test_single_segment_auto_time_matches_the_closed_form():
    # Rest-to-rest quintic: peak acceleration 10/sqrt(3) h / T^2 and velocity 15/8 h / T.
    traj = auto_time([[0.0], [1.0]], 10.0, 1.0, tol=1e-9)
    assert traj.duration == pytest.approx(np.sqrt(10 / np.sqrt(3)), rel=1e-8)
    traj = auto_time([[0.0], [1.0]], 0.5, 100.0, tol=1e-9)
    assert traj.duration == pytest.approx(15 / 8 / 0.5, rel=1e-8)


@pytest.mark.parametrize(("call", "message"), [
    (lambda: stretch_to_limits(SEED_WAYPOINTS, [1, 1, 1], -1.0, 1.0), "max_velocity: expected positive"),
    (lambda: stretch_to_limits(SEED_WAYPOINTS, [1, 1, 1], np.inf, np.inf), "no finite limit"),
    (lambda: auto_time([[0.0], [0.0]], 1.0, 1.0), "waypoints that move"),
    (lambda: auto_time(SEED_WAYPOINTS, [1.0, 2.0], 1.0), "max_velocity"),
])
def test_bad_limits_are_clear_errors(call, message):
    with pytest.raises(InputError, match=message):
        call()


@settings(max_examples=4, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_stretch_on_random_waypoints_is_feasible_and_tight(seed):
    rng = np.random.default_rng(seed)
    waypoints = rng.uniform(-1.5, 1.5, (4, 6))
    requested = rng.uniform(0.5, 3.0, 3)
    traj = stretch_to_limits(waypoints, requested, SEED_VMAX, SEED_AMAX)
    assert within(traj) and np.all(traj.durations >= requested)
    assert_each_segment_tight(traj, requested)


def test_no_random_timing_within_the_limits_is_shorter_than_auto_time():
    """Random duration ratios, each scaled exactly onto the limits: none beats auto-time."""
    traj = auto_time(SEED_WAYPOINTS, SEED_VMAX, SEED_AMAX)
    rng = np.random.default_rng(7)
    shortest = np.inf
    for _ in range(300):
        candidate = traj.durations * np.exp(rng.normal(0, 0.3, 3))
        k = limit_ratio(min_jerk(SEED_WAYPOINTS, candidate), SEED_VMAX, SEED_AMAX)
        shortest = min(shortest, k * candidate.sum())
    assert traj.duration <= shortest * (1 + 1e-4)
    assert traj.duration < 9.0         # the coordinate descent alone stops at 9.356 s


def test_refinement_never_makes_it_longer():
    plain = auto_time(SEED_WAYPOINTS, SEED_VMAX, SEED_AMAX, refine=False)
    refined = auto_time(SEED_WAYPOINTS, SEED_VMAX, SEED_AMAX)
    assert refined.duration <= plain.duration and within(plain) and within(refined)
