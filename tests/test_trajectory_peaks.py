"""Exact segment peaks: never below any sample, reached by a dense sample, degenerate polynomials."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from armkit.trajectory.peaks import segment_peaks


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
