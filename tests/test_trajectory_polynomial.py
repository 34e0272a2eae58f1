"""Quintic, cubic and LSPB segments: boundary values, derivatives by finite differences, errors."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from armkit.errors import InputError
from armkit.trajectory import cubic, lspb, quintic

finite = st.floats(-3, 3)


@settings(max_examples=50, deadline=None)
@given(q0=finite, q1=finite, T=st.floats(0.1, 10), v0=finite, v1=finite, a0=finite, a1=finite)
def test_quintic_meets_all_six_boundary_values(q0, q1, T, v0, v1, a0, a1):
    q, qd, qdd, _ = quintic(q0, q1, T, v0, v1, a0, a1).at_time([0.0, T])
    scale = 1 + abs(q0) + abs(q1) + T * (abs(v0) + abs(v1)) + T**2 * (abs(a0) + abs(a1))
    np.testing.assert_allclose(q[:, 0], [q0, q1], atol=1e-12 * scale)
    np.testing.assert_allclose(qd[:, 0], [v0, v1], atol=1e-11 * scale / T)
    np.testing.assert_allclose(qdd[:, 0], [a0, a1], atol=1e-10 * scale / T**2)


def test_quintic_rest_to_rest_classic_values():
    # q(t) = 10 s^3 - 15 s^4 + 6 s^5: peak velocity 15/8 h/T, peak acceleration 10/sqrt(3) h/T^2.
    seg = quintic(0.0, 2.0, 4.0)
    t = np.linspace(0, 4, 400001)
    _, qd, qdd, _ = seg.at_time(t)
    assert qd.max() == pytest.approx(15 / 8 * 2 / 4, rel=1e-12)
    assert np.abs(qdd).max() == pytest.approx(10 / np.sqrt(3) * 2 / 16, rel=1e-8)


@pytest.mark.parametrize("make", [
    lambda: quintic([0.1, -0.4, 2.0], [1.0, 0.3, -1.0], 2.5, v0=[0.2, 0, -0.1], a1=[0, 0.3, 0.1]),
    lambda: cubic([0.1, -0.4], [1.0, 0.3], 1.5, v0=[0.2, 0.0], v1=[-0.5, 0.1]),
    lambda: lspb([0.1, -0.4, 0.0], [1.0, 0.3, 0.0], 2.0),
])
def test_derivatives_match_finite_differences(make):
    seg = make()
    t = np.linspace(0.05, seg.duration - 0.05, 37)
    h = 1e-6
    values = seg.at_time(t)
    plus, minus = seg.at_time(t + h), seg.at_time(t - h)
    for order in range(3):
        fd = (plus[order] - minus[order]) / (2 * h)
        np.testing.assert_allclose(values[order + 1], fd, atol=1e-6)


def test_scalar_inputs_are_one_joint():
    q, qd, qdd, qddd = quintic(0, 1, 1).at_time(np.linspace(0, 1, 5))
    assert q.shape == qd.shape == qdd.shape == qddd.shape == (5, 1)
    assert quintic(0, 1, 1).n == 1 and quintic(0, 1, 1).degree == 5


def test_cubic_acceleration_jumps_at_the_ends():
    _, qd, qdd, _ = cubic(0.0, 1.0, 1.0).at_time([0.0, 1.0])
    np.testing.assert_allclose(qd[:, 0], [0, 0], atol=1e-15)
    np.testing.assert_allclose(qdd[:, 0], [6.0, -6.0])


def test_lspb_profile_is_trapezoidal():
    seg = lspb([0.0, 5.0], [2.0, 5.0], 4.0, velocity=[0.8, 1.0])
    assert seg.blend_time[0] == pytest.approx(4.0 - 2.0 / 0.8)
    q, qd, qdd, _ = seg.at_time(np.linspace(0, 4, 401))
    np.testing.assert_allclose(q[[0, -1]], [[0, 5], [2, 5]], atol=1e-14)
    assert qd[:, 0].max() == pytest.approx(0.8)
    np.testing.assert_allclose(np.unique(np.abs(qdd[:, 0])), [0.0, 0.8 / seg.blend_time[0]])
    np.testing.assert_array_equal(q[:, 1], 5.0)


def test_lspb_triangle_limit_and_rejects_impossible_speed():
    seg = lspb(0.0, 1.0, 2.0, velocity=1.0)  # 2 h / T: a triangle
    assert seg.blend_time[0] == pytest.approx(1.0)
    with pytest.raises(InputError, match=r"joint 1 needs a cruise speed in \(0.5, 1\]"):
        lspb(0.0, 1.0, 2.0, velocity=0.4)


@pytest.mark.parametrize(("call", "message"), [
    (lambda: quintic(0, 1, 0.0),
     r"duration: every segment duration must be from 1e-06 s to 1e\+06 s, got 0 s"),
    (lambda: quintic(0, np.nan, 1.0), "q1: contains NaN"),
    (lambda: quintic([0, 1], [1, 2, 3], 1.0), "incompatible shapes"),
    (lambda: quintic(0, 1, 1.0).at_time(1.5), r"t: expected times in \[0, 1\] s"),
    (lambda: cubic(0, 1, -2.0), r"must be from 1e-06 s to 1e\+06 s, got -2 s"),
])
def test_bad_input_is_a_clear_error(call, message):
    with pytest.raises(InputError, match=message):
        call()
