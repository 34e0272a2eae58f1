"""Exact segment peaks: never below any sample, reached by a dense sample, degenerate polynomials."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from armkit.errors import InputError
from armkit.trajectory.peaks import segment_peaks, segment_ranges


def sampled_peaks(coefficients, durations, order, count=20001):
    out = np.zeros(coefficients.shape[1:])
    for i, T in enumerate(durations):
        t = np.linspace(0, T, count)
        c = coefficients[:, i, :]
        for _ in range(order):
            c = np.polynomial.polynomial.polyder(c, axis=0)
        out[i] = np.abs(np.polynomial.polynomial.polyval(t, c)).max(axis=1)
    return out


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), order=st.integers(0, 3), degree=st.integers(1, 5))
def test_exact_peaks_bound_and_match_dense_samples(seed, order, degree):
    rng = np.random.default_rng(seed)
    coefficients = np.zeros((6, 3, 2))
    coefficients[:degree + 1] = rng.normal(0, 1, (degree + 1, 3, 2))
    coefficients[:, 2, 1] = 0.0                       # a joint that does not move
    durations = rng.uniform(0.2, 3.0, 3)
    exact = segment_peaks(coefficients, durations, order)
    sampled = sampled_peaks(coefficients, durations, order)
    assert np.all(exact >= sampled * (1 - 1e-12) - 1e-12)
    np.testing.assert_allclose(exact, sampled, rtol=1e-6, atol=1e-12)
    assert exact[2, 1] == 0.0


def test_interior_peak_of_the_rest_to_rest_quintic():
    # q = 10 s^3 - 15 s^4 + 6 s^5 on [0, 1]: peak velocity 15/8 at s = 1/2, acceleration 10/sqrt(3).
    coefficients = np.array([0, 0, 0, 10, -15, 6], dtype=float)[:, None, None]
    durations = np.array([1.0])
    assert segment_peaks(coefficients, durations, 1)[0, 0] == 15 / 8
    np.testing.assert_allclose(segment_peaks(coefficients, durations, 2)[0, 0], 10 / np.sqrt(3), rtol=1e-14)
    np.testing.assert_allclose(segment_peaks(coefficients, durations, 3)[0, 0], 60.0, rtol=1e-14)


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), degree=st.integers(1, 5))
def test_exact_ranges_bound_and_match_dense_samples(seed, degree):
    rng = np.random.default_rng(seed)
    coefficients = np.zeros((6, 3, 2))
    coefficients[:degree + 1] = rng.normal(0, 1, (degree + 1, 3, 2))
    durations = rng.uniform(0.2, 3.0, 3)
    low, high = segment_ranges(coefficients, durations)
    for i, T in enumerate(durations):
        q = np.polynomial.polynomial.polyval(np.linspace(0, T, 20001), coefficients[:, i, :])
        assert np.all(low[i] <= q.min(axis=1) + 1e-12) and np.all(high[i] >= q.max(axis=1) - 1e-12)
        np.testing.assert_allclose(low[i], q.min(axis=1), rtol=1e-6, atol=1e-9)
        np.testing.assert_allclose(high[i], q.max(axis=1), rtol=1e-6, atol=1e-9)


def test_position_limit_violations_find_the_overshoot_between_waypoints():
    import armkit
    from armkit.chain import LIMIT_TOLERANCE
    from armkit.trajectory import min_jerk

    robot = armkit.load("probot-anno")                   # q2 limits +-2.00713 rad
    inside = min_jerk([[0] * 6, [0, 1.9, 0, 0, 0, 0], [0] * 6], [1.0, 1.0])
    assert inside.position_limit_violations(robot) == []
    overshoot = min_jerk([[0] * 6, [0, 1.9, 0, 0, 0, 0], [0] * 6], [1.0, 0.3])
    assert robot.within_limits(overshoot.waypoints).all()
    (message,) = overshoot.position_limit_violations(robot, degrees=True)
    assert message.startswith("joint q2 = 0 .. 209.6") and "limits [-115, 115] deg" in message
    high = overshoot.position_range[1][1]
    assert high >= overshoot.sample(2000.0).q[:, 1].max()
    upper = robot.limits[0, 1]                          # a waypoint exactly on a limit is allowed
    on_limit = min_jerk([[upper + 0.5 * LIMIT_TOLERANCE] + [0] * 5, [0] * 6], [1.0])
    assert on_limit.position_limit_violations(robot) == []
    with pytest.raises(InputError, match="GRB400 SCARA has 4 joints, the trajectory 6"):
        overshoot.position_limit_violations(armkit.load("grb400-scara"))


@pytest.mark.parametrize(("roots", "scale"), [
    ([0.5, 0.5], 1.0),                          # s^2 (1 - s)^2-like: a double root of p'
    ([0.3, 0.3 + 1e-6, 0.8], 1.0),              # two turning points a micro-step apart
    ([0.1, 0.25, 0.4, 0.55, 0.7, 0.85], 1e3),   # degree 7: six turning points
])
def test_turning_points_close_together_or_many_are_all_found(roots, scale):
    """p' = scale * prod (s - r): p's extremes at those roots, against a sampling 1e6 fine."""
    derivative = scale * np.polynomial.polynomial.polyfromroots(roots)
    p = np.polynomial.polynomial.polyint(derivative)
    coefficients = p[:, None, None]
    low, high = segment_ranges(coefficients, np.array([1.0]))
    q = np.polynomial.polynomial.polyval(np.linspace(0, 1, 1_000_001), p)
    candidates = np.polynomial.polynomial.polyval(np.array([0.0, 1.0, *roots]), p)
    np.testing.assert_allclose([low[0, 0], high[0, 0]], [candidates.min(), candidates.max()], rtol=1e-13,
                               atol=1e-15)
    assert low[0, 0] <= q.min() + 1e-15 and high[0, 0] >= q.max() - 1e-15
