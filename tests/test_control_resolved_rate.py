"""Resolved-rate control: damped least squares, velocity scaling, frames (FK: ChainKernel)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit
from armkit.control import ResolvedRate, damping, joint_velocity, scale_to_limits
from armkit.control.resolved_rate import DEFAULT_MAX_DAMPING, DEFAULT_THRESHOLD
from armkit.errors import InputError

PROBOT = armkit.load("probot-anno")
#: PROBOT Anno's wrist is singular at q5 = pi/2 (axes 4 and 6 aligned).
WRIST_SINGULAR = np.array([0.0, 0.3, 0.5, 0.2, np.pi / 2, 0.1])


@pytest.mark.parametrize("name", armkit.builtin_robots())
def test_away_from_singularities_the_step_is_the_least_squares_solution(name):
    robot = armkit.load(name)
    control = ResolvedRate(robot, limit_velocity=False)
    rng = np.random.default_rng(7)
    checked = 0
    for q in robot.random_q(80, rng=rng):
        J = robot.jacobian(q)
        if np.linalg.svd(J, compute_uv=False)[-1] < 2 * DEFAULT_THRESHOLD:
            continue
        twist = rng.normal(size=6)
        step = control.step(q, twist)
        assert step.damping == 0.0 and step.scale == 1.0
        np.testing.assert_allclose(step.qd, np.linalg.lstsq(J, twist, rcond=None)[0], atol=1e-10)
        checked += 1
    assert checked >= 5


def test_damping_law():
    sigma = np.linspace(0.0, 0.1, 101)
    lam2 = damping(sigma, threshold=0.05, max_damping=0.08)
    assert lam2[0] == pytest.approx(0.08**2)
    assert np.all(lam2[sigma >= 0.05] == 0.0)
    below = sigma < 0.05
    assert np.all(np.diff(lam2[below]) < 0), "damping must grow as sigma_min falls"
    assert damping(0.05 - 1e-9, 0.05, 0.08) == pytest.approx(0.0, abs=1e-9)  # continuous at eps


def test_dls_matches_the_svd_formula_near_a_singularity():
    control = ResolvedRate(PROBOT, limit_velocity=False)
    twist = np.array([0.01, -0.02, 0.015, 0.1, -0.2, 0.3])
    for offset in (0.1, 1e-2, 1e-3, 1e-5, 0.0):
        q = WRIST_SINGULAR + [0, 0, 0, 0, offset, 0]
        U, s, Vt = np.linalg.svd(PROBOT.jacobian(q))
        step = control.step(q, twist)
        assert step.sigma_min == pytest.approx(s[-1], abs=1e-7)
        lam2 = damping(s[-1])
        expected = Vt.T @ ((s / (s**2 + lam2)) * (U.T @ twist))
        np.testing.assert_allclose(step.qd, expected, atol=1e-7 * np.abs(expected).max())


def test_joint_velocities_stay_bounded_as_the_singularity_nears():
    damped = ResolvedRate(PROBOT, limit_velocity=False)
    undamped = ResolvedRate(PROBOT, threshold=0.0, limit_velocity=False)
    twist = np.array([0.0, 0.0, 0.0, 0.3, 0.2, 0.0])
    gains, lam2 = [], []
    for offset in (0.3, 0.1, 3e-2, 1e-2, 1e-3, 1e-4):
        q = WRIST_SINGULAR + [0, 0, 0, 0, offset, 0]
        step = damped.step(q, twist)
        gains.append(np.linalg.norm(undamped.step(q, twist).qd) / np.linalg.norm(twist))
        lam2.append(step.damping)
        # With lambda_max = eps every direction's gain s / (s^2 + lambda^2) is <= 1 / eps.
        assert np.linalg.norm(step.qd) <= np.linalg.norm(twist) / DEFAULT_THRESHOLD * (1 + 1e-9)
    assert gains[-1] > 100 / DEFAULT_THRESHOLD  # the undamped solution blows up ...
    assert np.all(np.diff(lam2) >= 0) and lam2[-1] > 0.9 * DEFAULT_MAX_DAMPING**2  # ... damping grows


def test_velocity_scaling_keeps_the_direction():
    free = ResolvedRate(PROBOT, limit_velocity=False)
    limited = ResolvedRate(PROBOT)
    q = np.array([0.2, -0.4, 0.3, 0.5, 1.0, -0.2])
    twist = np.array([0.5, -0.3, 0.2, 1.0, 0.5, -2.0])
    raw, scaled = free.step(q, twist).qd, limited.step(q, twist)
    assert 0 < scaled.scale < 1
    np.testing.assert_allclose(scaled.qd, scaled.scale * raw, rtol=1e-12)
    assert np.max(np.abs(scaled.qd) / PROBOT.max_velocity) == pytest.approx(1.0)


def test_scale_to_limits():
    qd, scale = scale_to_limits([2.0, -0.5, 0.1], [1.0, 1.0, np.inf])
    np.testing.assert_allclose(qd, [1.0, -0.25, 0.05])
    assert scale == 0.5
    batch, scales = scale_to_limits([[0.5, 0.5], [4.0, 1.0]], [1.0, 1.0])
    np.testing.assert_allclose(batch, [[0.5, 0.5], [1.0, 0.25]])
    np.testing.assert_allclose(scales, [1.0, 0.25])
    np.testing.assert_allclose(scale_to_limits([4.0, 1.0], 2.0)[0], [2.0, 0.5])  # one limit for all
    with pytest.raises(InputError, match=r"max_velocity: expected one limit or one per joint \(2\)"):
        scale_to_limits([4.0, 1.0], [1.0, 1.0, 1.0])


def test_tool_frame_twist_is_the_base_twist_rotated():
    rng = np.random.default_rng(11)
    for q in PROBOT.random_q(10, rng=rng):
        twist_tool = rng.normal(size=6) * 0.01
        R = PROBOT.fk(q)[:3, :3]
        qd_tool = joint_velocity(PROBOT, q, twist_tool, "tool", limit_velocity=False)
        qd_base = joint_velocity(PROBOT, q, np.concatenate([R @ twist_tool[:3], R @ twist_tool[3:]]),
                                 "base", limit_velocity=False)
        np.testing.assert_allclose(qd_tool, qd_base, atol=1e-12)
        if PROBOT.singular_values(q)[-1] > DEFAULT_THRESHOLD:
            np.testing.assert_allclose(PROBOT.jacobian(q, "tool") @ qd_tool, twist_tool, atol=1e-12)


@pytest.mark.parametrize(("name", "q"), [
    ("probot-anno", WRIST_SINGULAR),
    # the Gram matrix's smallest eigenvalue comes out +4e-16 / +9e-18 here, not 0 or negative
    ("puma560", [1.402, -0.587, -1.045, 2.246, 0.0, -0.226]),
    ("ur5", [1.044, -1.542, -3.119, 2.136, 0.0, -1.77])])
def test_exactly_singular_without_damping_gives_the_least_squares_step(name, q):
    robot = armkit.load(name)
    control = ResolvedRate(robot, threshold=0.0, limit_velocity=False)
    twist = np.array([0.01, 0.02, -0.01, 0.1, 0.0, 0.05])
    step = control.step(np.array(q, dtype=float), twist)
    J = robot.jacobian(q)
    least_squares = np.linalg.pinv(J, rcond=1e-10) @ twist  # J's exact rank: the singular direction left out
    np.testing.assert_allclose(step.qd, least_squares, atol=1e-6 * np.abs(least_squares).max())
    assert 0.0 < step.damping <= 1e-9 * np.sum(J**2)


@pytest.mark.parametrize(("q", "twist", "frame", "match"), [
    ([0] * 6, [0, 0, np.nan, 0, 0, 0], "base", "NaN"),
    ([0] * 6, [0, 0, 0], "base", "expected 6 numbers"),
    ([0] * 5, [0] * 6, "base", "6 joints"),
    ([0] * 6, [0] * 6, "world", "expected 'base' or 'tool'"),
    ([[0] * 6] * 2, [0] * 6, "base", "one configuration"),
])
def test_bad_input(q, twist, frame, match):
    with pytest.raises(InputError, match=match):
        joint_velocity(PROBOT, q, twist, frame)


SOLVE_J = PROBOT.jacobian(np.array([0.1, 0.5, 0.4, 0.2, 0.7, 0.3]))


@pytest.mark.parametrize(("J", "twist", "match"), [
    (SOLVE_J, np.array([0.0, 0.0, np.nan, 0.0, 0.0, 0.0]),
     r"twist: contains NaN or infinite values: \[0.0, 0.0, nan, 0.0, 0.0, 0.0\]"),
    (SOLVE_J, np.array([np.inf, 0.0, 0.0, 0.0, 0.0, -np.inf]),
     r"twist: contains NaN or infinite values: \[inf"),
    (np.where(np.eye(6, dtype=bool), np.nan, SOLVE_J), np.full(6, 0.01), r"J: contains NaN or infinite"),
    (SOLVE_J[:, :5].copy(), np.zeros(6),
     r"J: expected a float64 array of shape \(6, 6\), got shape \(6, 5\)"),
    (SOLVE_J.tolist(), np.zeros(6), r"J: expected a float64 array of shape \(6, 6\), got list \(solve takes"),
    (SOLVE_J.astype(object), np.zeros(6),
     r"J: expected a float64 array of shape \(6, 6\), got shape \(6, 6\), dtype object"),
    (SOLVE_J, [0.0] * 6, r"twist: expected a float64 array of shape \(6,\), got list"),
    (SOLVE_J, np.array([1e308, -1e308, 1e308, 0.0, 0.0, 0.0]),
     r"twist: expected components from -1e\+06 to 1e\+06"),
])
def test_the_fast_solve_refuses_what_it_cannot_step_with_a_named_input_error(J, twist, match):
    """Before: a NaN or infinite twist went through solve() into NaN joint velocities, silently."""
    control = ResolvedRate(PROBOT, limit_velocity=False)
    with pytest.raises(InputError, match=match):
        control.solve(J, twist)
    with pytest.raises(InputError, match=match):
        ResolvedRate(PROBOT).solve(J, twist)


def test_a_step_that_overflows_is_refused_not_returned_as_inf():
    """A finite twist within MAX_VALUE through a J of 1e-308 entries: qd = pinv(J) twist is ~4e308,
    beyond the largest double. (Before J was rescaled, a J of 1e-155 overflowed too: its Gram matrix
    fell below the normal doubles; its true step, ~4e155, is now returned.)"""
    control = ResolvedRate(PROBOT, limit_velocity=False, max_damping=0.0, threshold=0.0)
    with pytest.raises(InputError, match=r"twist \[1.0, 0.0, 0.0, 0.0, 0.0, 0.0\]: the joint velocities "
                                         r"through J overflow"):
        control.solve(np.ascontiguousarray(SOLVE_J * 1e-308), np.array([1.0, 0, 0, 0, 0, 0]))


@pytest.mark.parametrize("size", [1e-300, 1e-155, 1e-20, 1e20, 1e155, 1e300])
@pytest.mark.parametrize(("threshold", "max_damping"), [(0.0, 0.0), (DEFAULT_THRESHOLD, DEFAULT_MAX_DAMPING)])
def test_a_jacobian_of_any_size_gets_its_true_step(size, threshold, max_damping):
    """Before: a J of 1e-300 entries (all finite, not zero) gave qd = 0 without damping (its Gram matrix
    J J^T underflowed to zero), and sigma_min = 0. The step is the SVD formula
    ``V diag(s / (s^2 + lambda^2)) U^T twist`` of ``size * J`` (written overflow-free for the test)."""
    control = ResolvedRate(PROBOT, threshold=threshold, max_damping=max_damping, limit_velocity=False)
    twist = np.array([0.01, -0.02, 0.015, 0.1, -0.2, 0.3])
    U, s, Vt = np.linalg.svd(SOLVE_J)  # singular values 1.77 .. 0.0188
    sigma = size * s  # the singular values of size * J, each a finite double
    lam2 = damping(sigma[-1], threshold, max_damping)
    expected = Vt.T @ ((U.T @ twist) / (sigma + lam2 / sigma))  # s / (s^2 + lambda^2), no s^2 formed
    step = control.solve(np.ascontiguousarray(SOLVE_J * size), twist)
    # the core's sigma_min comes from the Gram matrix's eigenvalue, whose error of ~eps sigma_max^2 is
    # ~2e-12 of sigma_min^2 here (measured 9e-13 of sigma_min at size 1 as at every size)
    assert step.sigma_min == pytest.approx(sigma[-1], rel=1e-11)
    assert step.damping == pytest.approx(lam2, rel=1e-11)
    np.testing.assert_allclose(step.qd, expected, rtol=1e-12, atol=0)
    limited = ResolvedRate(PROBOT, threshold=threshold, max_damping=max_damping).solve(
        np.ascontiguousarray(SOLVE_J * size), twist)  # with the velocity limits: the same direction
    ratio = np.abs(expected) / PROBOT.max_velocity
    np.testing.assert_allclose(limited.qd, expected / max(ratio.max(), 1.0), rtol=1e-12, atol=0)


def test_scaling_j_by_a_power_of_two_scales_the_undamped_step_exactly():
    """J is solved at the power of two that brings its largest entry into [0.5, 1), so the same J at
    any power of two (Gram matrix under- or overflowing, or not) gives the very same bits, scaled."""
    control = ResolvedRate(PROBOT, threshold=0.0, limit_velocity=False)
    twist = np.array([0.01, -0.02, 0.015, 0.1, -0.2, 0.3])
    step = control.solve(SOLVE_J, twist)
    for k in (-1000, -600, -40, 40, 600, 1000):
        scaled = control.solve(np.ascontiguousarray(np.ldexp(SOLVE_J, k)), twist)
        assert np.array_equal(scaled.qd, np.ldexp(step.qd, -k))
        assert scaled.sigma_min == np.ldexp(step.sigma_min, k)


@pytest.mark.parametrize("value", [-1.0, np.nan, "0.1", None, [0.1], True, 1e300])
def test_bad_settings(value):
    with pytest.raises(InputError, match=r"threshold: expected a smallest singular value from 0 to 1e\+06"):
        ResolvedRate(PROBOT, threshold=value)
    with pytest.raises(InputError, match=r"max_damping: expected a damping from 0 to 1e\+06, got"):
        ResolvedRate(PROBOT, max_damping=value)


def test_bad_values_of_the_public_helpers_are_named():
    with pytest.raises(InputError, match=r"sigma_min: expected finite singular values >= 0, got \[-1.0\]"):
        damping([-1.0])
    for limits in (0.0, -1.0, np.nan):
        with pytest.raises(InputError, match="max_velocity: expected limits > 0 .inf for none."):
            scale_to_limits([1.0, 2.0], limits)
    with pytest.raises(InputError, match="qd: expected finite joint velocities"):
        scale_to_limits([np.inf, 1.0], 1.0)
    with pytest.raises(InputError, match=r"twist: expected components from -1e\+06 to 1e\+06"):
        ResolvedRate(armkit.load("ur5")).joint_velocity(np.zeros(6), [1e308, 1e308, 0, 0, 0, 0])


finite = st.floats(-1.0, 1.0, allow_nan=False)


@settings(max_examples=60, deadline=None)
@given(fractions=st.lists(st.floats(0.0, 1.0), min_size=6, max_size=6),
       twist=st.lists(finite, min_size=6, max_size=6))
def test_property_inverse_away_from_singularities_and_limits_always(fractions, twist):
    lower, upper = PROBOT.limits.T
    q = lower + np.array(fractions) * (upper - lower)
    twist = np.array(twist)
    step = ResolvedRate(PROBOT).step(q, twist)
    free = ResolvedRate(PROBOT, limit_velocity=False).step(q, twist)
    assert np.all(np.abs(step.qd) <= PROBOT.max_velocity * (1 + 1e-12))
    np.testing.assert_allclose(step.qd, step.scale * free.qd, atol=1e-14)
    if free.sigma_min > DEFAULT_THRESHOLD:  # round trip: the twist the joints produce is the one asked
        np.testing.assert_allclose(PROBOT.jacobian(q) @ free.qd, twist, atol=1e-10)


def test_step_matches_a_jacobian_from_roboticstoolbox():
    rtb = pytest.importorskip("roboticstoolbox")
    from spatialmath import SE3

    d = np.pi / 180
    links = [rtb.RevoluteMDH(alpha=0, a=0, d=0.284), rtb.RevoluteMDH(alpha=90 * d, offset=90 * d),
             rtb.RevoluteMDH(a=0.225), rtb.RevoluteMDH(alpha=90 * d, d=0.2289),
             rtb.RevoluteMDH(alpha=-90 * d, offset=-90 * d), rtb.RevoluteMDH(alpha=90 * d)]
    theirs = rtb.DHRobot(links, tool=SE3.Tz(0.055) * SE3.Rx(-90 * d))
    control = ResolvedRate(PROBOT, limit_velocity=False)
    rng = np.random.default_rng(5)
    for q in PROBOT.random_q(10, rng=rng):
        twist = rng.normal(size=6)
        J = theirs.jacob0(q)
        U, s, Vt = np.linalg.svd(J)
        expected = Vt.T @ ((s / (s**2 + damping(s[-1]))) * (U.T @ twist))
        np.testing.assert_allclose(control.step(q, twist).qd, expected, atol=1e-9 * np.abs(expected).max())


def test_step_uses_the_public_damping_and_scaling():
    control = ResolvedRate(PROBOT)
    twist = np.array([0.5, -0.3, 0.2, 1.0, 0.5, -2.0])
    for q in (np.zeros(6), np.array([0.2, -0.4, 0.3, 0.5, 1.0, -0.2])):
        step = control.step(q, twist)
        sigma_min = np.linalg.svd(PROBOT.jacobian(q), compute_uv=False)[-1]
        below = min(sigma_min / DEFAULT_THRESHOLD, 1.0)  # the damping law, written out
        assert step.damping == pytest.approx((1 - below**2) * DEFAULT_MAX_DAMPING**2, rel=1e-9, abs=1e-15)
        free = ResolvedRate(PROBOT, limit_velocity=False).step(q, twist).qd
        ratio = np.max(np.abs(free) / PROBOT.max_velocity)  # scaling, written out
        assert step.scale == pytest.approx(1.0 / ratio if ratio > 1 else 1.0, rel=1e-15)
        np.testing.assert_allclose(step.qd, free * step.scale, rtol=1e-15)
    np.testing.assert_array_equal(damping([0.0, 0.1], threshold=0.0), [0.0, 0.0])
