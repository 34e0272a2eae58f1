"""Closed-form case solvers, one joint motion at a time, at the level of the screw axes.

Every valid candidate of ``solve_pose`` must reproduce the joint motion ``G`` through the
product of exponentials of the solver's own (possibly reversed) chain, built here with
SciPy's rotations, and the configuration that made ``G`` must be among the candidates.
The quartic's root finder is checked against NumPy's companion-matrix roots.
"""

from types import SimpleNamespace

import numpy as np
import pytest
from conftest import core_internals
from helpers import CLOSED_FORM_ROBOTS, random_arm, random_transform
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

import armkit
from armkit import _core
from armkit.chain import DHRow, chain_from_dh
from armkit.ik.cases import CASE_CANDIDATES, CASE_NAMES, MAX_CANDIDATES, SphericalGeometry, solve_pose
from armkit.ik.closed_form import closed_form_solver
from armkit.ik.structure import plan_closed_form
from armkit.poe import poe_from_chain

seeds = st.integers(0, 2**32 - 1)


def _motion(poe, q):
    """``G(q) = exp(xi_1 q_1) ... exp(xi_n q_n)`` ``(4, 4)`` and the space Jacobian ``(6, n)``."""
    G, J = np.eye(4), np.empty((6, poe.n))
    for j in range(poe.n):
        h, p = poe.axes[j], poe.points[j]
        h_now, p_now = G[:3, :3] @ h, G[:3, :3] @ p + G[:3, 3]
        J[:, j] = np.r_[h_now, 0, 0, 0] if poe.prismatic[j] else np.r_[np.cross(p_now, h_now), h_now]
        E = np.eye(4)
        if poe.prismatic[j]:
            E[:3, 3] = q[j] * h
        else:
            E[:3, :3] = Rotation.from_rotvec(q[j] * h).as_matrix()
            E[:3, 3] = p - E[:3, :3] @ p
        G = G @ E
    return G, J


def joint_distance(poe, a, b):
    d = np.asarray(a - b, dtype=float)
    rev = ~poe.prismatic
    d[..., rev] = (d[..., rev] + np.pi) % (2 * np.pi) - np.pi
    return np.abs(d).max(axis=-1)


def _assert_candidates(chain, q_user, tol):
    """Candidates of each joint motion reproduce it and contain the q that made it.

    With 6 joints every valid candidate is a solution (each subproblem checks its own
    branch); fewer joints over-determine the motion, so there a valid candidate may miss
    the orientation (the elbow of a planar 2R flipped) until forward kinematics sorts it
    out, and only the candidates that reproduce the motion are held to ``q``.
    """
    poe, geometry = plan_closed_form(chain).poe, closed_form_solver(chain).geometry
    size = 1.0 + np.abs(poe.points).max()
    for q in q_user:
        q_int = poe.sign * q[poe.index]
        G, J = _motion(poe, q_int)
        qs, valid, family = solve_pose(geometry, G[:3, :3].copy(), G[:3, 3].copy())
        assert qs.shape == (geometry.k, poe.n) and valid.shape == family.shape == (geometry.k,)
        residual = np.full(geometry.k, np.inf)
        residual[valid] = [np.abs(_motion(poe, c)[0] - G).max() for c in qs[valid]]
        solution = residual < tol * size
        assert solution.any() and (poe.n < 6 or solution[valid].all()), residual
        # the joints are fixed to about residual / sigma_min (see test_ik_closed_form)
        sigma = np.linalg.svd(J, compute_uv=False)[min(6, poe.n) - 1]
        q_tol = np.clip(10 * (residual[solution].max() + 1e-16) / sigma, 1e-9, 1e-6)
        found = joint_distance(poe, qs, q_int) < q_tol
        assert (found & solution).any() or (family & solution).any(), f"missed q = {q.tolist()}"


@pytest.mark.parametrize("name", CLOSED_FORM_ROBOTS)
def test_candidates_of_builtins(name):
    chain = armkit.load(name).chain
    rng = np.random.default_rng(len(name))
    _assert_candidates(chain, rng.uniform(chain.lower, chain.upper, (200, chain.n)), 1e-12)


@pytest.mark.parametrize("kind", ["spherical-wrist", "spherical-base", "three-parallel"])
@settings(max_examples=15, deadline=None)
@given(seed=seeds)
def test_candidates_of_random_pieper_arms(kind, seed):
    rng = np.random.default_rng(seed)
    stanford_like = seed % 5 == 0 and kind == "spherical-wrist"  # a prismatic third joint
    chain = random_arm(rng, kind, ["standard", "modified"][seed % 2], prismatic3=stanford_like)
    _assert_candidates(chain, rng.uniform(chain.lower, chain.upper, (30, chain.n)), 1e-9)


@settings(max_examples=10, deadline=None)
@given(seed=seeds)
def test_candidates_of_random_scara_and_planar_arms(seed):
    rng = np.random.default_rng(seed)
    R, P = "revolute", "prismatic"
    for kinds in ([R, R, P, R], [R, R, R], [R, P, R], [R, R], [P, R, R]):
        rows = [DHRow(0.0, rng.uniform(0.1, 0.4), rng.uniform(-0.2, 0.2), rng.uniform(-np.pi, np.pi), k)
                for k in kinds]
        limits = [(-np.pi, np.pi) if k == R else (-0.2, 0.2) for k in kinds]
        chain = chain_from_dh(rows, ["standard", "modified"][seed % 2], limits=limits,
                              T_base=random_transform(rng), T_tool=random_transform(rng))
        _assert_candidates(chain, rng.uniform(chain.lower, chain.upper, (20, chain.n)), 1e-9)


def test_unreachable_motion_has_no_valid_candidate():
    for name in CLOSED_FORM_ROBOTS:
        if name == "stanford":  # its prismatic joint reaches any distance
            continue
        geometry = closed_form_solver(armkit.load(name).chain).geometry
        _, valid, _ = solve_pose(geometry, np.eye(3), np.array([5.0, 5.0, 5.0]))
        assert not valid.any(), name


def test_case_geometries_are_plain_structs_checked_by_the_core():
    chain = _core.CaseChain(np.eye(3).repeat(2, axis=0), np.zeros((6, 3)), np.zeros(6, bool))
    fields = dict(chain=chain, system=_core.TwoAngleSystem(), position_case=0, c=(0, 0, 0), o=(0, 0, 0),
                  o2=(0, 0, 0), o3=(0, 0, 0), u=(1, 0, 0))
    geometry = SphericalGeometry(**fields)
    assert (geometry.k, geometry.n, geometry.case) == (8, 6, "spherical")
    with pytest.raises(TypeError):
        SphericalGeometry(**{k: v for k, v in fields.items() if k != "u"})
    with pytest.raises(TypeError):
        SphericalGeometry(**fields, bogus=1)
    with pytest.raises(TypeError):
        SphericalGeometry(**{**fields, "c": (0.0, 1.0)})
    with pytest.raises(ValueError, match="position_case must be 0 .. 6"):
        SphericalGeometry(**{**fields, "position_case": 7})
    three = _core.CaseChain(np.eye(3), np.zeros((3, 3)), np.zeros(3, bool))
    with pytest.raises(ValueError, match="needs a chain of 6 joints, got 3"):
        SphericalGeometry(**{**fields, "chain": three})
    with pytest.raises(ValueError, match=r"h and p must both be \(n, 3\)"):
        _core.CaseChain(np.eye(3), np.zeros((2, 3)), np.zeros(3, bool))
    def sliding(*joints):
        return _core.CaseChain(np.eye(3).repeat(2, axis=0), np.zeros((6, 3)), np.isin(np.arange(6), joints))

    assert _core.GeneralGeometry(sliding(2), 2).n == 6  # joint 3 is the loop's joint 1: taken
    # six slides; joint 3 as the loop's joint 3
    for chain, shift in ((sliding(0, 1, 2, 3, 4, 5), 0), (sliding(2), 0)):
        with pytest.raises(ValueError, match="at most one prismatic joint, as the loop's joint 1 or 2"):
            _core.GeneralGeometry(chain, shift)


def test_every_registered_case_has_a_geometry_and_a_fixed_capacity():
    """The registry (the core's kCases) names every case once, the general 6R arm last, and
    the largest candidate count is the buffers' capacity."""
    assert CASE_NAMES[-1] == "general" and len(set(CASE_NAMES)) == len(CASE_NAMES)
    assert max(CASE_CANDIDATES) == MAX_CANDIDATES == 16
    for name in CLOSED_FORM_ROBOTS:
        geometry = closed_form_solver(armkit.load(name).chain).geometry
        assert geometry.case in CASE_NAMES
        assert geometry.k == CASE_CANDIDATES[CASE_NAMES.index(geometry.case)]


# --------------------------------------------------------------------- quartic
def _self_inversive(rng):
    """``z^2 F`` for ``F(t) = |W x(t) - w|^2 - 1`` in ``z = exp(i t)``: the quartics of the cases."""
    W, w = rng.normal(size=(2, 2)) * rng.choice([0.1, 1.0, 10.0]), rng.normal(size=2)
    S = W.T @ W
    m = W.T @ w
    A0, A1, B1 = 0.5 * np.trace(S) + w @ w - 1, -2 * m[0], -2 * m[1]
    A2, B2 = 0.5 * (S[0, 0] - S[1, 1]), S[0, 1]
    return np.array([complex(A2, -B2), complex(A1, -B1), 2 * A0, complex(A1, B1), complex(A2, B2)]) / 2


def _matched_distance(found, roots):
    """Largest distance from a root to the nearest found root, and the other way round."""
    d = np.abs(np.asarray(found)[:, None] - np.asarray(roots)[None])
    return max(d.min(axis=0).max(), d.min(axis=1).max())


def quartic_roots(c):
    """The core's quartic solver (a test binding, see conftest.core_internals)."""
    return core_internals().quartic_roots(c)


@settings(max_examples=50, deadline=None)
@given(seeds)
def test_quartic_roots_match_companion_matrix(seed):
    rng = np.random.default_rng(seed)
    for _ in range(20):
        c = _self_inversive(rng)
        roots = np.roots(c)
        assert _matched_distance(quartic_roots(c), roots) <= 1e-12 * max(1.0, np.abs(roots).max())


@pytest.mark.parametrize("gap", [1e-2, 1e-4, 1e-6, 1e-8, 0.0])
def test_quartic_near_double_roots_as_accurate_as_companion_matrix(gap):
    """A near-double root fixes its pair only to about eps / gap: no worse than LAPACK's."""
    rng = np.random.default_rng(int(gap * 1e9) + 1)
    ours, theirs = [], []
    for trial in range(300):
        t, s = rng.uniform(-np.pi, np.pi, 2)
        roots = np.exp(1j * np.array([t, t + gap, s, -s]))
        roots[3] *= 1.3 if trial % 2 else 1.0  # a root off the unit circle in half the cases
        c = np.poly(roots) * rng.normal()
        ours.append(_matched_distance(quartic_roots(c), roots))
        theirs.append(_matched_distance(np.roots(c), roots))
    ours, theirs = np.array(ours), np.array(theirs)
    assert np.median(ours) <= np.median(theirs) and ours.max() <= 2 * theirs.max()


@pytest.mark.parametrize("slide", range(6))
def test_every_loop_that_takes_a_slide_lists_the_configuration_among_its_candidates(slide):
    # a 5R1P arm: the slide as the loop's joint 1 or 2, the chain forward and reversed (the reversed
    # chain's slide runs the other way), slides of metres; the raw candidates, before any polish
    from test_ik_general import general_arm

    rng = np.random.default_rng([22, slide])
    chain = general_arm(rng, slide).chain
    lines = poe_from_chain(chain)
    poe = SimpleNamespace(n=6, axes=lines.axes, points=lines.points, prismatic=chain.prismatic, M=lines.M)
    R_M, t_M = poe.M[:3, :3], poe.M[:3, 3]
    backward = SimpleNamespace(n=6, axes=poe.axes[::-1] @ R_M, points=(poe.points[::-1] - t_M) @ R_M,
                               prismatic=poe.prismatic[::-1])  # the chain of T^-1: M^-1 of the lines
    for value in (0.5, 5.0, -20.0):
        q = rng.uniform(-np.pi, np.pi, 6)
        q[slide] = value
        G = _motion(poe, q)[0]
        assert np.allclose(_motion(backward, -q[::-1])[0], np.linalg.inv(poe.M) @ np.linalg.inv(G) @ poe.M,
                           atol=1e-12)
        for lines, at, q_lines in ((poe, slide, q), (backward, 5 - slide, -q[::-1])):
            case_chain = _core.CaseChain(lines.axes, lines.points, lines.prismatic)
            G_lines = _motion(lines, q_lines)[0]
            for shift in ((at - 1) % 6, at):  # the slide as the loop's joint 2, then 1
                qs, valid, _ = solve_pose(_core.GeneralGeometry(case_chain, shift), G_lines[:3, :3].copy(),
                                          G_lines[:3, 3].copy())
                assert joint_distance(lines, qs[valid], q_lines).min() <= 1e-6, (value, shift)
