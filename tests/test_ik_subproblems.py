"""Paden-Kahan subproblems against randomly constructed instances with known solutions."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from armkit.ik.subproblems import planar_2r, rotate, solve_trig_linear, sp1, sp2, sp3, sp4
from armkit.spatial.rotations import matrix_from_axis_angle

seeds = st.integers(0, 2**32 - 1)
INSTANCES = 20  # random instances per hypothesis example


def _unit(rng):
    v = rng.normal(size=3)
    return tuple(v / np.linalg.norm(v))


def _vector(rng):
    return tuple(rng.normal(size=3))


def _angle_diff(a, b):
    return np.abs((np.asarray(a) - b + np.pi) % (2 * np.pi) - np.pi)


@settings(max_examples=50, deadline=None)
@given(seeds)
def test_rotate_matches_rotation_matrix(seed):
    rng = np.random.default_rng(seed)
    for _ in range(INSTANCES):
        k, v, t = _unit(rng), _vector(rng), rng.uniform(-4, 4)
        R = matrix_from_axis_angle(t * np.array(k))
        np.testing.assert_allclose(R @ v, rotate(k, t, v), atol=1e-14)


@settings(max_examples=50, deadline=None)
@given(seeds)
def test_sp1_recovers_angle(seed):
    rng = np.random.default_rng(seed)
    for _ in range(INSTANCES):
        k, p, t = _unit(rng), _vector(rng), rng.uniform(-np.pi, np.pi)
        theta, free = sp1(p, rotate(k, t, p), k)
        assert not free
        assert _angle_diff(theta, t) < 1e-9


@settings(max_examples=50, deadline=None)
@given(seeds, st.floats(-10, -6))
def test_sp1_keeps_its_accuracy_for_points_next_to_the_axis(seed, log_offset):
    # p and q a distance e (1e-10 .. 1e-6) off the axis: the angle is known to ~1e-16 / e; its
    # cosine once lost that (an aligned wrist's q6 came out 0.5 rad off at e = 1e-9)
    rng = np.random.default_rng(seed)
    e = 10.0**log_offset
    for _ in range(INSTANCES):
        k, t = np.array(_unit(rng)), rng.uniform(-np.pi, np.pi)
        u = np.cross(k, _unit(rng))
        u /= np.linalg.norm(u)
        v = np.cross(k, u)
        along = rng.uniform(-2, 2) * k
        theta, free = sp1(along + e * u, along + e * (np.cos(t) * u + np.sin(t) * v), k)
        assert not free
        assert _angle_diff(theta, t) < 1e-14 / e


def test_sp1_point_on_axis_is_free():
    k = (0.0, 0.0, 1.0)
    theta, free = sp1((0.0, 0.0, 2.0), (0.0, 0.0, 2.0), k)
    assert free and theta == 0.0


@settings(max_examples=50, deadline=None)
@given(seeds)
def test_sp2_contains_constructed_solution(seed):
    rng = np.random.default_rng(seed)
    for _ in range(INSTANCES):
        k1, k2, p2 = _unit(rng), _unit(rng), _vector(rng)
        t1, t2 = rng.uniform(-np.pi, np.pi, 2)
        p1 = rotate(k1, -t1, rotate(k2, t2, p2))
        theta1, theta2, valid, free1, free2 = sp2(p1, p2, k1, k2)
        assert valid[0] and not free1 and not free2
        found = (_angle_diff(theta1, t1) < 1e-8) & (_angle_diff(theta2, t2) < 1e-8) & np.array(valid)
        assert found.any()
        for b in range(2):
            if valid[b]:
                residual = np.subtract(rotate(k1, theta1[b], p1), rotate(k2, theta2[b], p2))
                assert np.abs(residual).max() < 1e-12 * (1 + np.abs(p2).max())


def test_sp2_tangent_and_impossible():
    x, y, z = (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)
    # circles touch at one point: (s, s, 0) about x meets (s, 0, s) about z only at (s, 0, s)
    s = np.sqrt(0.5)
    theta1, theta2, valid, _, _ = sp2((s, s, 0.0), (s, 0.0, s), x, z)
    assert valid == (True, False)
    np.testing.assert_allclose([theta1[0], theta2[0]], [np.pi / 2, 0.0], atol=1e-7)
    # |p1| != |p2|: no solution
    _, _, valid, _, _ = sp2(z, (0.0, 0.0, 2.0), x, y)
    assert valid == (False, False)
    # p1 on k1: theta1 free, theta2 brings p2 onto p1
    theta1, theta2, valid, free1, _ = sp2(x, z, x, y)
    assert free1 and valid[0] and theta1[0] == 0.0
    np.testing.assert_allclose(rotate(y, theta2[0], z), x, atol=1e-15)


@settings(max_examples=50, deadline=None)
@given(seeds)
def test_sp3_contains_constructed_solution(seed):
    rng = np.random.default_rng(seed)
    for _ in range(INSTANCES):
        k, p1, p2 = _unit(rng), _vector(rng), _vector(rng)
        t = rng.uniform(-np.pi, np.pi)
        d = float(np.linalg.norm(np.subtract(rotate(k, t, p1), p2)))
        theta, valid, free = sp3(p1, p2, k, d)
        assert valid[0] and not free
        assert ((_angle_diff(theta, t) < 1e-6) & np.array(valid)).any()
        for b in range(2):
            if valid[b]:
                assert abs(np.linalg.norm(np.subtract(rotate(k, theta[b], p1), p2)) - d) < 1e-12


def test_sp3_tangent_and_out_of_reach():
    z = (0.0, 0.0, 1.0)
    p1, p2 = (1.0, 0.0, 0.0), (3.0, 0.0, 0.0)
    theta, valid, _ = sp3(p1, p2, z, 2.0)  # nearest point: one solution, t = 0
    assert valid == (True, False) and abs(theta[0]) < 1e-12
    _, valid, _ = sp3(p1, p2, z, 4.0 + 1e-12)  # farthest point, rounding: tangent
    assert valid == (True, False)
    _, valid, _ = sp3(p1, p2, z, 4.1)
    assert valid == (False, False)


@settings(max_examples=50, deadline=None)
@given(seeds)
def test_sp4_contains_constructed_solution(seed):
    rng = np.random.default_rng(seed)
    for _ in range(INSTANCES):
        h, k, p = _vector(rng), _unit(rng), _vector(rng)
        t = rng.uniform(-np.pi, np.pi)
        d = float(np.dot(h, rotate(k, t, p)))
        theta, valid, _ = sp4(h, p, k, d)
        assert ((_angle_diff(theta, t) < 1e-6) & np.array(valid)).any()
        for b in range(2):
            if valid[b]:
                residual = np.dot(h, rotate(k, theta[b], p)) - d
                assert abs(residual) < 1e-12 * (1 + np.abs(h).max() * np.abs(p).max())


def test_trig_linear_free_and_impossible():
    theta, valid, free = solve_trig_linear(0.0, 0.0, 0.0, 1.0)
    assert free and valid == (True, False) and theta[0] == 0.0
    _, valid, free = solve_trig_linear(0.0, 0.0, 1.0, 1.0)
    assert not free and valid == (False, False)
    theta, valid, _ = solve_trig_linear(1.0, 0.0, 0.5, 1.0)
    np.testing.assert_allclose(np.sort(theta), [-np.pi / 3, np.pi / 3], atol=1e-15)
    assert valid == (True, True)


@settings(max_examples=50, deadline=None)
@given(seeds)
def test_planar_2r_contains_constructed_solution(seed):
    rng = np.random.default_rng(seed)
    for _ in range(INSTANCES):
        h, a, b = _unit(rng), _vector(rng), _vector(rng)
        ta, tb = rng.uniform(-np.pi, np.pi, 2)
        v = rotate(h, ta, np.add(a, rotate(h, tb, b)))
        angles_a, angles_b, valid, free = planar_2r(h, a, b, v)
        assert valid[0] and not free
        hits = (_angle_diff(angles_a, ta) < 1e-6) & (_angle_diff(angles_b, tb) < 1e-6) & np.array(valid)
        assert hits.any()
        for s in range(2):
            if valid[s]:  # the in-plane part of the equation holds
                residual = np.subtract(rotate(h, angles_a[s], np.add(a, rotate(h, angles_b[s], b))), v)
                assert abs(np.linalg.norm(residual - np.dot(residual, h) * np.array(h))) < 1e-12 * (
                    1 + np.abs(a).max() + np.abs(b).max())
