"""Paden-Kahan subproblems against randomly constructed instances with known solutions."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from armkit.ik.subproblems import cos_sin, rotate, rotation_matrix, solve_trig_linear, sp1, sp2, sp3, sp4

seeds = st.integers(0, 2**32 - 1)


def _unit(rng, shape=()):
    v = rng.normal(size=(*shape, 3))
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _angle_diff(a, b):
    return np.abs((a - b + np.pi) % (2 * np.pi) - np.pi)


@settings(max_examples=50, deadline=None)
@given(seeds)
def test_rotate_matches_rotation_matrix(seed):
    rng = np.random.default_rng(seed)
    k, v, t = _unit(rng, (5,)), rng.normal(size=(5, 3)), rng.uniform(-4, 4, 5)
    R = rotation_matrix(k, t)
    np.testing.assert_allclose((R @ v[..., None])[..., 0], rotate(k, t, v), atol=1e-14)
    np.testing.assert_allclose(np.swapaxes(R, -1, -2) @ R, np.broadcast_to(np.eye(3), R.shape),
                               atol=1e-14)


@settings(max_examples=50, deadline=None)
@given(seeds)
def test_sp1_recovers_angle(seed):
    rng = np.random.default_rng(seed)
    k, p, t = _unit(rng, (20,)), rng.normal(size=(20, 3)), rng.uniform(-np.pi, np.pi, 20)
    theta, free = sp1(p, rotate(k, t, p), k)
    assert not free.any()
    assert _angle_diff(theta, t).max() < 1e-9


def test_sp1_point_on_axis_is_free():
    k = np.array([0.0, 0.0, 1.0])
    theta, free = sp1(2.0 * k, 2.0 * k, k)
    assert free and theta == 0.0


@settings(max_examples=50, deadline=None)
@given(seeds)
def test_sp2_contains_constructed_solution(seed):
    rng = np.random.default_rng(seed)
    n = 20
    k1, k2, p2 = _unit(rng, (n,)), _unit(rng, (n,)), rng.normal(size=(n, 3))
    t1, t2 = rng.uniform(-np.pi, np.pi, n), rng.uniform(-np.pi, np.pi, n)
    p1 = rotate(k1, -t1, rotate(k2, t2, p2))
    theta1, theta2, valid, free1, free2 = sp2(p1, p2, k1, k2)
    assert valid[:, 0].all() and not free1.any() and not free2.any()
    found = (_angle_diff(theta1, t1[:, None]) < 1e-8) & (_angle_diff(theta2, t2[:, None]) < 1e-8)
    assert (found & valid).any(axis=1).all()
    residual = rotate(k1[:, None], theta1, p1[:, None]) - rotate(k2[:, None], theta2, p2[:, None])
    assert np.abs(residual[valid]).max() < 1e-12 * (1 + np.abs(p2).max())


def test_sp2_tangent_and_impossible():
    x, y, z = np.eye(3)
    # circles touch at one point: (s, s, 0) about x meets (s, 0, s) about z only at (s, 0, s)
    s = np.sqrt(0.5)
    theta1, theta2, valid, _, _ = sp2(np.array([s, s, 0]), np.array([s, 0, s]), x, z)
    assert valid.tolist() == [True, False]
    np.testing.assert_allclose([theta1[0], theta2[0]], [np.pi / 2, 0.0], atol=1e-7)
    # |p1| != |p2|: no solution
    _, _, valid, _, _ = sp2(z, 2 * z, x, y)
    assert not valid.any()
    # p1 on k1: theta1 free, theta2 brings p2 onto p1
    theta1, theta2, valid, free1, _ = sp2(x, z, x, y)
    assert free1 and valid[0] and theta1[0] == 0.0
    np.testing.assert_allclose(rotate(y, theta2[0], z), x, atol=1e-15)


@settings(max_examples=50, deadline=None)
@given(seeds)
def test_sp3_contains_constructed_solution(seed):
    rng = np.random.default_rng(seed)
    n = 20
    k, p1, p2 = _unit(rng, (n,)), rng.normal(size=(n, 3)), rng.normal(size=(n, 3))
    t = rng.uniform(-np.pi, np.pi, n)
    d = np.linalg.norm(rotate(k, t, p1) - p2, axis=-1)
    theta, valid, free = sp3(p1, p2, k, d)
    assert valid[:, 0].all() and not free.any()
    assert ((_angle_diff(theta, t[:, None]) < 1e-6) & valid).any(axis=1).all()
    residual = np.linalg.norm(rotate(k[:, None], theta, p1[:, None]) - p2[:, None], axis=-1) - d[:, None]
    assert np.abs(residual[valid]).max() < 1e-12


def test_sp3_tangent_and_out_of_reach():
    z = np.array([0.0, 0.0, 1.0])
    p1, p2 = np.array([1.0, 0, 0]), np.array([3.0, 0, 0])
    theta, valid, _ = sp3(p1, p2, z, np.array(2.0))  # nearest point: one solution, t = 0
    assert valid.tolist() == [True, False] and abs(theta[0]) < 1e-12
    _, valid, _ = sp3(p1, p2, z, np.array(4.0 + 1e-12))  # farthest point, rounding: tangent
    assert valid.tolist() == [True, False]
    _, valid, _ = sp3(p1, p2, z, np.array(4.1))
    assert not valid.any()


@settings(max_examples=50, deadline=None)
@given(seeds)
def test_sp4_contains_constructed_solution(seed):
    rng = np.random.default_rng(seed)
    n = 20
    h, k, p = rng.normal(size=(n, 3)), _unit(rng, (n,)), rng.normal(size=(n, 3))
    t = rng.uniform(-np.pi, np.pi, n)
    d = np.sum(h * rotate(k, t, p), axis=-1)
    theta, valid, _ = sp4(h, p, k, d)
    assert ((_angle_diff(theta, t[:, None]) < 1e-6) & valid).any(axis=1).all()
    residual = np.sum(h[:, None] * rotate(k[:, None], theta, p[:, None]), axis=-1) - d[:, None]
    assert np.abs(residual[valid]).max() < 1e-12 * (1 + np.abs(h).max() * np.abs(p).max())


def test_trig_linear_free_and_impossible():
    theta, valid, free = solve_trig_linear(np.array(0.0), np.array(0.0), np.array(0.0), np.array(1.0))
    assert free and valid.tolist() == [True, False] and theta[0] == 0.0
    _, valid, free = solve_trig_linear(np.array(0.0), np.array(0.0), np.array(1.0), np.array(1.0))
    assert not free and not valid.any()
    theta, valid, _ = solve_trig_linear(np.array(1.0), np.array(0.0), np.array(0.5), np.array(1.0))
    np.testing.assert_allclose(np.sort(theta), [-np.pi / 3, np.pi / 3], atol=1e-15)
    assert valid.all()


def test_cos_sin_from_the_tangent_matches_numpy():
    theta = np.concatenate([np.linspace(-7.0, 7.0, 4001), [np.pi, -np.pi, np.pi / 2, 0.0, 2 * np.pi]])
    cos, sin = cos_sin(theta)  # large: from tan(theta / 2)
    np.testing.assert_allclose(cos, np.cos(theta), rtol=0, atol=1e-15)
    np.testing.assert_allclose(sin, np.sin(theta), rtol=0, atol=1e-15)
    assert cos_sin(np.zeros(1000))[1].max() == 0.0 and cos_sin(np.zeros(1000))[0].min() == 1.0
