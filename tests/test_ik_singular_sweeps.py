"""Exactly singular poses of published industrial arms: every branch is listed (issue 21 item 4).

Ten OPW arms (six revolute joints, axes 2 and 3 parallel, a spherical wrist; Brandstoetter,
Angerer and Hofbaur 2014) with the parameters published by rs-opw-kinematics
(``src/parameters_robots.rs``; the FANUC M-16iB from its ``tests/data/fanuc/fanuc_m16ib20.yaml``),
each swept at three kinds of exactly singular pose built from a configuration ``q``:

* **wrist aligned**: ``q5 = 0``, where only ``q4 + q6`` is fixed (a family);
* **wrist centre on axis 1**: ``q1`` free, the wrist following (a family); arms whose wrist
  centre is off the plane of axis 1 (offset ``b``, the Staubli TX40's 35 mm) never get there
  and say so (``test_an_arm_with_a_lateral_offset_never_has_its_wrist_centre_on_axis_1``);
* **elbow stretched**: ``q3`` at the stretch (or the fold) of the forearm, where the two elbow
  branches meet (a double root, no family).

At each pose the listing ``ik_solutions(robot, T)`` (default ``near``: zeros, so a family's
member is wherever the walk to zeros puts it) must hold ``q`` itself or a flagged family member
from which ``q`` is reached along the solution set (a walk on the null space of the Jacobian,
each step put back onto the solutions by Newton steps), and so must every solution a
many-seed numeric search finds (armkit's compiled Levenberg-Marquardt from random seeds).
"""

from __future__ import annotations

import os

import numpy as np
import pytest
from helpers import newton_root

import armkit
from armkit.ik import ik_solutions
from armkit.ik.numeric import NumericIK
from armkit.kinematics import geometric_jacobian, pose_error
from armkit.poe import poe_from_chain

pi = np.pi

#: OPW parameters [m] (a1, a2, b, c1, c2, c3, c4), joint offsets [rad] and sign corrections,
#: as rs-opw-kinematics publishes them: model angle = sign * joint - offset.
OPW_ARMS = {
    "ABB IRB 2400/10": ((0.100, -0.135, 0.0, 0.615, 0.705, 0.755, 0.085), (0, 0, -pi / 2, 0, 0, 0), None),
    "ABB IRB 2600-12/1.65": ((0.150, -0.115, 0.0, 0.445, 0.700, 0.795, 0.085), (0, 0, -pi / 2, 0, 0, 0),
                             None),
    "ABB IRB 4600-60/2.05": ((0.175, -0.175, 0.0, 0.495, 0.900, 0.960, 0.135), (0, 0, -pi / 2, 0, 0, 0),
                             None),
    "KUKA KR6 R700 sixx": ((0.025, -0.035, 0.0, 0.400, 0.315, 0.365, 0.080), (0, -pi / 2, 0, 0, 0, 0),
                           (-1, 1, 1, -1, 1, -1)),
    "FANUC R-2000iB/200R": ((0.720, -0.225, 0.0, 0.600, 1.075, 1.280, 0.235), (0, 0, -pi / 2, 0, 0, 0), None),
    "FANUC M-16iB/20": ((0.15, -0.10, 0.0, 0.525, 0.77, 0.74, 0.10), (0, 0, -pi / 2, 0, 0, pi),
                        (1, 1, -1, -1, -1, -1)),
    "Staubli TX40": ((0.0, 0.0, 0.035, 0.320, 0.225, 0.225, 0.065), (0, 0, -pi / 2, 0, 0, 0), None),
    "Staubli TX2-140": ((0.150, 0.0, 0.0, 0.550, 0.625, 0.625, 0.110), (0,) * 6, None),
    "Staubli RX160": ((0.15, 0.0, 0.0, 0.55, 0.825, 0.625, 0.11), (0,) * 6, None),
    "igus ReBeL": ((0.149, -0.119, 0.0, 0.1, 0.2384, 0.17, 0.1208), (0,) * 6, (-1, 1, 1, 1, 1, 1)),
}
#: Arms whose wrist centre can reach axis 1 (lateral offset b = 0).
ON_AXIS_1 = [name for name, (geometry, _, _) in OPW_ARMS.items() if geometry[2] == 0.0]

#: Poses per arm and kind of singularity; seeds of the numeric search per pose.
#: Singular poses per arm and kind: 8 in ``make test`` (CI), 40 in ``make fuzz`` (ARMKIT_SWEEP_POSES=40,
#: about 30 minutes on two loaded cores; the figures in docs/ik.md are from 40).
POSES = int(os.environ.get("ARMKIT_SWEEP_POSES", "8"))
SEARCH_SEEDS = 24
#: A listed solution is q within this [rad] (a double root is exact only to ~sqrt(eps) in q).
FOUND = 1e-6
#: Steps along a family [rad].
STEP = 0.05


def _rotate(axis: np.ndarray, angle: float, v: np.ndarray) -> np.ndarray:
    """``v`` turned by ``angle`` about the unit ``axis`` (Rodrigues)."""
    return v * np.cos(angle) + np.cross(axis, v) * np.sin(angle) + axis * (axis @ v) * (1 - np.cos(angle))


def opw_robot(name: str) -> armkit.Robot:
    """The OPW arm ``name`` as joint lines (the arm upright at model angles 0), in its own joint angles.

    Model zero: axis 1 is z through the origin, axes 2 and 3 are y through ``(a1, 0, c1)`` and
    ``(a1, 0, c1 + c2)``, the wrist centre is ``(a1 + a2, b, c1 + c2 + c3)`` with axes 4 and 6
    along z and axis 5 along y through it, the tool ``c4`` above it. The joint lines at the
    user's zero are the model's at ``-offset``, each axis times its sign.
    """
    (a1, a2, b, c1, c2, c3, c4), offsets, signs = OPW_ARMS[name]
    signs = np.ones(6) if signs is None else np.asarray(signs, dtype=float)
    z, y = np.array([0.0, 0.0, 1.0]), np.array([0.0, 1.0, 0.0])
    centre = np.array([a1 + a2, b, c1 + c2 + c3])
    axes = [z, y, y, z, y, z]
    points = [np.zeros(3), np.array([a1, 0.0, c1]), np.array([a1, 0.0, c1 + c2]), centre, centre, centre]
    M = np.eye(4)
    M[:3, 3] = centre + c4 * z
    # move every line beyond joint i by joint i's model angle -offset_i
    for i in range(6):
        angle = -offsets[i]
        if angle == 0.0:
            continue
        for j in range(i + 1, 6):
            axes[j] = _rotate(axes[i], angle, axes[j])
            points[j] = points[i] + _rotate(axes[i], angle, points[j] - points[i])
        M[:3, :3] = np.array([_rotate(axes[i], angle, c) for c in M[:3, :3].T]).T
        M[:3, 3] = points[i] + _rotate(axes[i], angle, M[:3, 3] - points[i])
    return armkit.Robot.from_poe(np.array(axes) * signs[:, None], np.array(points), M, name=name,
                                 limits=[(-pi, pi)] * 6)


def model_to_joints(name: str, q_model: np.ndarray) -> np.ndarray:
    """The arm's joint angles of OPW model angles ``q_model`` (..., 6), wrapped to [-pi, pi)."""
    _, offsets, signs = OPW_ARMS[name]
    signs = np.ones(6) if signs is None else np.asarray(signs, dtype=float)
    return np.angle(np.exp(1j * signs * (q_model + np.asarray(offsets))))


def wrist_centre(robot: armkit.Robot) -> np.ndarray:
    """The point where axes 4, 5 and 6 meet at ``q = 0`` (least squares over the three lines)."""
    poe = poe_from_chain(robot.chain)
    A = sum(np.eye(3) - np.outer(h, h) for h in poe.axes[3:])
    b = sum((np.eye(3) - np.outer(h, h)) @ p for h, p in zip(poe.axes[3:], poe.points[3:], strict=True))
    return np.linalg.solve(A, b)


def stretched_q3(robot: armkit.Robot) -> np.ndarray:
    """The two q3 (stretched, folded) where the wrist centre is farthest from and nearest to axis 2.

    Axes 2 and 3 parallel (direction h): in their plane the wrist centre is at u + R(h, q3) v
    from axis 2 (u: axis 3 from axis 2, v: the centre from axis 3), longest where R v turns
    along u.
    """
    poe = poe_from_chain(robot.chain)
    h = poe.axes[2]
    u, v = poe.points[2] - poe.points[1], wrist_centre(robot) - poe.points[2]
    u, v = u - (u @ h) * h, v - (v @ h) * h
    stretched = np.arctan2(h @ np.cross(v, u), v @ u)
    return np.angle(np.exp(1j * np.array([stretched, stretched + pi])))


def singular_configurations(name: str, kind: str, rng: np.random.Generator, count: int) -> np.ndarray:
    """``count`` configurations (count, 6) of the arm at exactly singular poses of ``kind``."""
    (a1, a2, _, _, c2, c3, _), _, _ = OPW_ARMS[name]
    q = rng.uniform(-pi, pi, (count, 6))
    psi3 = np.arctan2(a2, c3)  # the forearm's angle: the wrist centre at k (sin, cos)(q2 + q3 + psi3)
    if kind == "wrist aligned":
        q[:, 4] = 0.0
    elif kind == "elbow stretched":
        q[:, 2] = rng.choice([-psi3, pi - psi3], count)  # stretched or folded forearm
    elif kind == "wrist centre on axis 1":
        # a1 + c2 sin q2 + k sin(q2 + q3 + psi3) = 0: A sin q2 + B cos q2 = -a1
        k = np.hypot(a2, c3)
        A, B = c2 + k * np.cos(q[:, 2] + psi3), k * np.sin(q[:, 2] + psi3)
        R = np.hypot(A, B)
        reach = np.abs(a1) <= R
        q, A, B, R = q[reach], A[reach], B[reach], R[reach]
        elbow = rng.choice([0.0, 1.0], len(q))
        s = np.arcsin(-a1 / R)
        q[:, 1] = np.where(elbow == 0.0, s, pi - s) - np.arctan2(B, A)
    return model_to_joints(name, q)


def _difference(robot: armkit.Robot, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``a - b`` (..., n), revolute joints modulo 2 pi into [-pi, pi]."""
    d = np.array(a - b, dtype=float)
    d[..., ~robot.chain.prismatic] = np.angle(np.exp(1j * d[..., ~robot.chain.prismatic]))
    return d


def _gap(robot: armkit.Robot, a: np.ndarray, b: np.ndarray, joints: slice = slice(None)) -> np.ndarray:
    """Largest joint difference over ``joints`` (revolute ones modulo 2 pi), over the last axis."""
    return np.abs(_difference(robot, a, b)[..., joints]).max(axis=-1)


def _project(robot: armkit.Robot, T: np.ndarray, q: np.ndarray) -> np.ndarray | None:
    """``q`` put onto the solutions of ``T`` by minimum-norm Newton steps, or None."""
    q = q.copy()
    for _ in range(30):
        e = pose_error(T, robot.fk(q))
        if np.abs(e).max() <= 1e-13:
            return q
        q += np.linalg.lstsq(geometric_jacobian(robot.chain, q), e, rcond=1e-10)[0]
    return None


def _null_space(robot: armkit.Robot, q: np.ndarray) -> np.ndarray:
    """Rows spanning the Jacobian's null space at ``q`` (singular values within 1e-8 of the largest)."""
    _, S, Vt = np.linalg.svd(geometric_jacobian(robot.chain, q))
    return Vt[np.concatenate([S, np.zeros(6 - len(S))]) <= 1e-8 * S[0]]


def _descend(robot: armkit.Robot, T: np.ndarray, p: np.ndarray, q: np.ndarray) -> bool:
    """Whether steps from ``p`` along the solutions (the null-space part of the way to ``q``) reach ``q``."""
    for _ in range(200):
        d = _difference(robot, q, p)
        if np.abs(d).max() <= FOUND:
            return True
        null = _null_space(robot, p)
        step = null.T @ (null @ d)
        length = np.linalg.norm(step)
        if len(null) == 0 or length <= 1e-3 * np.linalg.norm(d):
            return False  # stuck at a nearest point of the family, not at q
        p_next = _project(robot, T, p + step * min(1.0, STEP / length))
        if p_next is None or _gap(robot, p_next, q) >= _gap(robot, p, q) + 1e-12:
            return False
        p = p_next
    return False


def on_a_family_of(robot: armkit.Robot, T: np.ndarray, member: np.ndarray, q: np.ndarray) -> bool:
    """Whether ``q`` is reached from ``member`` along the solutions of ``T``.

    The family through the member is traced both ways (steps of STEP along the secant, each
    put back onto the solutions by Newton steps; a step that jumps is halved) until it closes
    or has run eight turns; from its point nearest to ``q`` (and from the member) steps along
    the null space towards ``q`` must reach it.
    """
    if _descend(robot, T, member, q):
        return True
    best, best_gap = member, _gap(robot, member, q)
    for way in (1.0, -1.0):
        null = _null_space(robot, member)
        if len(null) != 1:
            break  # a family of two or more parameters: the descent above only
        at, tangent, travelled, step = member, way * null[0], 0.0, STEP
        while travelled < 8 * 2 * pi and step >= 1e-4:
            nxt = _project(robot, T, at + step * tangent)
            moved = None if nxt is None else np.linalg.norm(nxt - at)
            if nxt is None or moved > 2 * step or (nxt - at) @ tangent <= 0:
                step /= 2
                continue
            tangent, at, travelled = (nxt - at) / moved, nxt, travelled + moved
            if _gap(robot, at, q) < best_gap:
                best, best_gap = at, _gap(robot, at, q)
            if travelled > 2 * STEP and _gap(robot, at, member) < STEP:
                break  # closed
            step = min(STEP, 2 * step)
    return _descend(robot, T, best, q)


def represented(robot: armkit.Robot, T: np.ndarray, found, q: np.ndarray) -> bool:
    """Whether the listing ``found`` holds ``q``, or a flagged member of a family holding it."""
    gap = _gap(robot, found.q, q)
    if (gap <= FOUND).any():
        return True
    return any(on_a_family_of(robot, T, member, q) for member in found.q[found.family])


def numeric_solutions(robot: armkit.Robot, T: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Solutions of ``T`` armkit's Levenberg-Marquardt finds from SEARCH_SEEDS random seeds, each
    taken by Newton onto the solution it stands for (``helpers.newton_root``)."""
    solver = NumericIK(robot, position_tolerance=1e-12, orientation_tolerance=1e-12, max_restarts=0,
                       max_iterations=60, within_limits=False)
    seeds = robot.random_q(SEARCH_SEEDS, rng=rng)
    result = solver.solve_batch(np.broadcast_to(T, (SEARCH_SEEDS, 4, 4)), seeds, threads=1)
    return np.array([newton_root(robot.chain, T, q) for q in result.q[result.success]]).reshape(-1, robot.n)


def missed_branches(robot: armkit.Robot, q_all: np.ndarray, rng: np.random.Generator) -> list[str]:
    """The poses fk(q) (one per row of ``q_all``) whose listing misses ``q`` or a numeric solution."""
    missed = []
    for q in q_all:
        T = robot.fk(q)
        found = ik_solutions(robot, T)
        assert np.abs(robot.fk(found.q) - T).max() <= 1e-9, f"q = {q.tolist()}: a listed row misses the pose"
        searched = [("numeric solution", s) for s in numeric_solutions(robot, T, rng)]
        for label, wanted in [("generating q", q), *searched]:
            if not represented(robot, T, found, wanted):
                missed.append(f"{label} {np.round(wanted, 6).tolist()} of q = {q.tolist()} not in "
                              f"{np.round(found.q, 6).tolist()} (family {found.family.tolist()})")
                break
    return missed


@pytest.mark.parametrize("name", OPW_ARMS)
def test_the_opw_arms_reproduce_their_published_geometry(name):
    # the wrist centre of the model's q = 0 is (a1 + a2, b, c1 + c2 + c3), the tool c4 above
    (a1, a2, b, c1, c2, c3, c4), _, _ = OPW_ARMS[name]
    robot = opw_robot(name)
    zero = model_to_joints(name, np.zeros(6))
    np.testing.assert_allclose(robot.fk(zero)[:3, 3], [a1 + a2, b, c1 + c2 + c3 + c4], atol=1e-15)
    assert armkit.ik.analyze_structure(robot.chain).kind == "spherical-wrist"


@pytest.mark.slow  # the sweeps: POSES poses, a numeric search and family traces each
@pytest.mark.parametrize("kind", ["wrist aligned", "elbow stretched"])
@pytest.mark.parametrize("name", OPW_ARMS)
def test_singular_poses_of_opw_arms_miss_no_branch(name, kind):
    robot = opw_robot(name)
    rng = np.random.default_rng(21)
    missed = missed_branches(robot, singular_configurations(name, kind, rng, POSES), rng)
    assert not missed, f"{len(missed)} of {POSES} poses miss a branch; first: {missed[0]}"


@pytest.mark.slow  # the sweeps: POSES poses, a numeric search and family traces each
@pytest.mark.parametrize("name", ON_AXIS_1)
def test_wrist_centre_on_axis_1_of_opw_arms_misses_no_branch(name):
    robot = opw_robot(name)
    rng = np.random.default_rng(21)
    q_all = singular_configurations(name, "wrist centre on axis 1", rng, POSES)
    assert len(q_all) >= POSES // 2, "the sweep must not thin out to nothing"
    centres = robot.fk(q_all)[:, :3, 3] - robot.fk(q_all)[:, :3, 2] * OPW_ARMS[name][0][6]
    np.testing.assert_allclose(centres[:, :2], 0.0, atol=1e-12)  # on axis 1 indeed
    missed = missed_branches(robot, q_all, rng)
    assert not missed, f"{len(missed)} of {len(q_all)} poses miss a branch; first: {missed[0]}"


def test_an_arm_with_a_lateral_offset_never_has_its_wrist_centre_on_axis_1():
    # the TX40's wrist centre stays b = 35 mm off the plane through axis 1 its arm turns in, so it
    # never gets within 35 mm of axis 1 and that sweep has no pose
    assert set(OPW_ARMS) - set(ON_AXIS_1) == {"Staubli TX40"}
    robot = opw_robot("Staubli TX40")
    q = np.random.default_rng(0).uniform(-pi, pi, (200, 6))
    centres = robot.fk(q)[:, :3, 3] - robot.fk(q)[:, :3, 2] * OPW_ARMS["Staubli TX40"][0][6]
    assert np.hypot(centres[:, 0], centres[:, 1]).min() >= 0.035 - 1e-12


@pytest.mark.parametrize(("name", "q"), [
    # q5 = 0 with q4 = 0: axis 5 parallel to axes 2 and 3, and a step across that nearly singular
    # direction landed on the other elbow's isolated solution
    ("ABB IRB 2600-12/1.65", [-1.121862583978964, 2.656419697403864, 1.638005129391422, 2.3508706030122877,
                              0.0, -2.2198351904728044]),
    # wrist centre on axis 1: a point sampled far along the curved q1 family was projected
    # onto the other wrist's family, and a long local step onto the other elbow's
    ("ABB IRB 2400/10", [2.646482332102484, -0.23953594170429587, -1.0665109838726718, -0.6180871763585495,
                         1.9975721030693059, -1.4879524435355973]),
    # ... with the two elbows 0.1 rad apart (near the stretch): once local steps were cut to a
    # trace step, the step across a nearby crossing jumped from one elbow's family to the other's
    ("ABB IRB 2400/10", [-0.5039474693281143, -0.042335436613628596, -1.4431303834023765, 1.1059715124787148,
                         -1.2019351819572106, 1.837694537115203]),
])
def test_a_family_walk_stays_on_its_family(name, q):
    robot = opw_robot(name)
    T = robot.fk(np.array(q))
    found = ik_solutions(robot, T)
    assert represented(robot, T, found, np.array(q))
    rng = np.random.default_rng(0)
    assert all(represented(robot, T, found, s) for s in numeric_solutions(robot, T, rng))


def test_rs_opw_kinematics_case_723_lists_the_aligned_wrist_branch():
    # IRB 2400, joints [157, -151, -119, 8, 0, 50] deg: [157, -151, -119, 0, 0, 58] is the same
    # pose (q4 + q6 = 58); the listing must hold that (q1, q2, q3) branch as a flagged family
    robot = opw_robot("ABB IRB 2400/10")
    q = np.radians([157.0, -151.0, -119.0, 8.0, 0.0, 50.0])
    other = np.radians([157.0, -151.0, -119.0, 0.0, 0.0, 58.0])
    T = robot.fk(q)
    np.testing.assert_allclose(robot.fk(other), T, atol=1e-15)
    found = ik_solutions(robot, T)
    assert represented(robot, T, found, q) and represented(robot, T, found, other)
    branch = _gap(robot, found.q, q, slice(0, 3)) <= FOUND
    assert branch.any() and found.family[branch].all()


@pytest.mark.parametrize("name", OPW_ARMS)
def test_the_stretch_of_the_elbow_is_where_the_published_geometry_puts_it(name):
    # the OPW forearm is stretched at model q3 = -atan2(a2, c3): the same q3 as found from the lines
    (_, a2, _, _, _, c3, _), _, _ = OPW_ARMS[name]
    model = np.zeros((2, 6))
    model[:, 2] = [-np.arctan2(a2, c3), pi - np.arctan2(a2, c3)]
    published = np.sort(model_to_joints(name, model)[:, 2])
    np.testing.assert_allclose(np.sort(stretched_q3(opw_robot(name))), published, atol=1e-12)


@pytest.mark.slow  # the sweeps: POSES poses, a numeric search and family traces each
@pytest.mark.parametrize("name", ["puma560", "stanford"])
def test_wrist_aligned_poses_of_the_built_ins_miss_no_branch(name):
    robot = armkit.load(name)
    rng = np.random.default_rng(21)
    q_all = robot.random_q(POSES, rng=rng)
    q_all[:, 4] = 0.0
    missed = missed_branches(robot, q_all, rng)
    assert not missed, f"{len(missed)} of {POSES} poses miss a branch; first: {missed[0]}"


@pytest.mark.slow  # the sweeps: POSES poses, a numeric search and family traces each
def test_elbow_stretched_poses_of_the_puma_560_miss_no_branch():
    robot = armkit.load("puma560")
    rng = np.random.default_rng(21)
    q_all = robot.random_q(POSES, rng=rng)
    q_all[:, 2] = rng.choice(stretched_q3(robot), POSES)
    missed = missed_branches(robot, q_all, rng)
    assert not missed, f"{len(missed)} of {POSES} poses miss a branch; first: {missed[0]}"
