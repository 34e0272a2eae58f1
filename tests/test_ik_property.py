"""IK property test over random arms of every closed-form class, degenerate ones included.

For every arm kind (spherical wrist with each way joints 1-3 place the wrist centre, a
prismatic joint 3 among them; spherical base; three parallel axes 1-3, 2-4, 3-5, 4-6;
SCARA; planar 2R / 3R), with generic or degenerate geometry (twists on multiples of 90
degrees, zero offsets, joint offsets and joint values on the pi/2 grid, exactly singular
poses such as an aligned wrist): every solution returned reproduces the pose by forward
kinematics, and the configuration that made the pose is found, by ``ik(T, near=q)`` and
among (or in a flagged family of) ``ik_solutions``. Where EAIK (nobody here wrote it)
solves the arm, our solutions and its exact ones agree at generic poses.

``make test`` runs a few examples per class (derandomized in CI); ``make fuzz`` many more.
"""

import os

import numpy as np
import pytest
from helpers import assert_same_as_eaik, joint_distance, random_arm, random_transform
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from armkit.chain import DHRow, chain_from_dh
from armkit.ik import ik, ik_solutions
from armkit.ik.messages import Labels
from armkit.ik.pipeline import Found, numeric_fallback
from armkit.ik.structure import analyze_structure
from armkit.kinematics import fk, singular_values
from armkit.spatial.rotations import matrix_from_axis_angle

pi = np.pi
GRID = np.array([0.0, pi / 2, -pi / 2, pi])
#: Joint distance [rad or m, after the 2 pi wrap] within which the generating q counts as found.
FOUND = 1e-6
#: Every solution reproduces the pose to this [m, rad] (the pipeline's verify tolerance).
REPRODUCED = 1e-9

SIX_JOINT_CLASSES = ([("spherical-wrist", case) for case in range(5)]
                     + [("spherical-wrist", "prismatic3"), ("spherical-base", None)]
                     + [("three-parallel", b) for b in (1, 2, 3, 4)])
#: A few examples per class in ``make test``; ``make fuzz`` (HYPOTHESIS_PROFILE=fuzz) runs its profile's 400.
EXAMPLES = {} if os.environ.get("HYPOTHESIS_PROFILE") == "fuzz" else {"max_examples": 6}
PLANAR_CLASSES = [("revolute", "revolute", "prismatic", "revolute"), ("revolute",) * 3,
                  ("revolute", "prismatic", "revolute"), ("revolute",) * 2]


def _grid_transform(rng):
    """A base or tool transform: identity, a quarter-turn grid rotation, or random."""
    choice = rng.integers(3)
    T = np.eye(4)
    if choice == 1:
        axis = np.eye(3)[rng.integers(3)]
        T[:3, :3] = np.round(matrix_from_axis_angle(axis * rng.choice(GRID)))
        T[:3, 3] = np.where(rng.random(3) < 0.5, 0.0, rng.uniform(-0.3, 0.3, 3))
    elif choice == 2:
        T = random_transform(rng)
    return T


def degenerate_six_joint_arm(rng, kind, case, convention):
    """A 6-joint DH arm of ``kind`` with twists on multiples of 90 degrees, offsets that are
    zero half of the time and joint offsets on the pi/2 grid (see ``random_arm``)."""
    a = np.where(rng.random(7) < 0.5, 0.0, rng.uniform(-0.4, 0.4, 7))
    d = np.where(rng.random(7) < 0.5, 0.0, rng.uniform(-0.4, 0.4, 7))
    alpha = rng.choice([-pi / 2, pi / 2], 7)
    theta = rng.choice(GRID, 7)
    prismatic3 = case == "prismatic3"
    if kind in ("spherical-wrist", "spherical-base"):
        first, last = (4, 5) if kind == "spherical-wrist" else (1, 2)
        a[first] = a[last] = d[last] = 0.0
        side = [1, 2] if kind == "spherical-wrist" else [4, 5]
        case = 0 if prismatic3 else case
        if case == 0:
            a[side[0]] = 0.0
        elif case == 1:
            alpha[side[1]] = 0.0
        elif case == 2:
            a[side[1]] = 0.0
        elif case == 3:
            alpha[side[0]] = 0.0
    else:
        alpha[case] = alpha[case + 1] = 0.0
    kinds = ["revolute"] * 6
    if prismatic3:
        kinds[2] = "prismatic"
    if convention == "standard":
        rows = [DHRow(alpha[i], a[i], d[i], theta[i], kinds[i - 1]) for i in range(1, 7)]
    else:
        rows = [DHRow(alpha[i - 1], a[i - 1], d[i], theta[i], kinds[i - 1]) for i in range(1, 7)]
    limits = [(-pi, pi) if k == "revolute" else (-0.6, 0.6) for k in kinds]
    return chain_from_dh(rows, convention, limits=limits, T_base=_grid_transform(rng),
                         T_tool=_grid_transform(rng))


def planar_arm(rng, kinds, convention, degenerate):
    """A SCARA or planar arm (all twists 0), degenerate: offsets on the grid, zero heights."""
    rows = []
    for k in kinds:
        d = 0.0 if degenerate and rng.random() < 0.5 else rng.uniform(-0.2, 0.2)
        theta = rng.choice(GRID) if degenerate else rng.uniform(-pi, pi)
        rows.append(DHRow(0.0, rng.uniform(0.1, 0.4), d, theta, k))
    limits = [(-pi, pi) if k == "revolute" else (-0.2, 0.2) for k in kinds]
    T_base, T_tool = (_grid_transform(rng), _grid_transform(rng)) if degenerate else \
        (random_transform(rng), random_transform(rng))
    return chain_from_dh(rows, convention, limits=limits, T_base=T_base, T_tool=T_tool)


def _poses(rng, chain, count, degenerate):
    """Joint values: on the pi/2 grid with q5 in {0, pi} (degenerate), else uniform; prismatic
    ones on a grid of lengths including 0 (a wrist centre on the shoulder's centre)."""
    if not degenerate:
        return rng.uniform(chain.lower, chain.upper, (count, chain.n))
    q = rng.choice(GRID, (count, chain.n))
    if chain.n == 6:
        q[:, 4] = rng.choice([0.0, pi], count)
    lengths = np.array([0.0, -0.1, 0.15]) if chain.n < 6 else np.array([0.0, -0.3, 0.2, 0.5])
    q[:, chain.prismatic] = rng.choice(lengths, (count, int(chain.prismatic.sum())))
    return q


def _nullity(chain, q):
    S = singular_values(chain, q)
    return int((S <= 1e-8 * S[0]).sum() + max(0, min(6, chain.n) - len(S)))


def _assert_ik_properties(chain, q_all):
    """Every returned solution reproduces T; the generating q is found (see the module)."""
    structure = analyze_structure(chain)
    size = 1.0 + np.abs(fk(chain, np.zeros(chain.n))[:3, 3]).max()
    T_all = fk(chain, q_all)
    # the over-determined planar arms reach only poses of their plane; fk(q) is one
    for q, T in zip(q_all, T_all, strict=True):
        found = ik_solutions(chain, T, near=q)
        assert 1 <= len(found.q) <= structure.max_solutions or found.family.any()
        F = fk(chain, found.q)
        assert np.abs(F - T).max() <= REPRODUCED * size, f"q = {q.tolist()}: a solution misses T"
        apart = joint_distance(chain, found.q[:, None], found.q[None])
        assert (apart[~np.eye(len(found.q), dtype=bool)] > 1e-9).all(), f"q = {q.tolist()}: a solution twice"
        near = ik(chain, T, near=q, within_limits=False)
        assert np.abs(fk(chain, near) - T).max() <= REPRODUCED * size
        listed = (joint_distance(chain, found.q, q) <= FOUND).any()
        nearest = joint_distance(chain, near, q) <= FOUND
        if listed and nearest:
            continue
        # A family of two or more parameters (a prismatic joint 3 placing the wrist centre on
        # the shoulder's centre: q1, q2 and the wrist all free) is walked locally only: there
        # the pose must be answered by a flagged family member.
        assert _nullity(chain, q) >= 2 and found.family.any(), (
            f"q = {q.tolist()} not found: nearest {near.tolist()}, listed {found.q.tolist()}, "
            f"family {found.family.tolist()}")


@pytest.mark.parametrize(("kind", "case"), SIX_JOINT_CLASSES)
@settings(**EXAMPLES, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 2**32 - 1))
def test_six_joint_arms(kind, case, seed):
    check_six_joint_arm(kind, case, seed, degenerate=False, drawn=True)


@pytest.mark.parametrize(("kind", "case"), SIX_JOINT_CLASSES)
@settings(**EXAMPLES, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 2**32 - 1))
def test_degenerate_six_joint_arms(kind, case, seed):
    check_six_joint_arm(kind, case, seed, degenerate=True, drawn=True)


def check_six_joint_arm(kind, case, seed, degenerate, *, drawn=False):
    """The IK properties (and, for a generic revolute arm, the EAIK cross-check) of the six-joint
    arm of ``kind`` and ``case`` made from ``seed``. A degenerate arm may have no closed form; one
    ``drawn`` at random (hypothesis, the sweep) is then passed over, returning False; a pinned seed
    that no longer gives a closed-form arm fails, so that it cannot pass having checked nothing."""
    rng = np.random.default_rng(seed)
    convention = ["standard", "modified"][seed % 2]
    if degenerate:
        chain = degenerate_six_joint_arm(rng, kind, case, convention)
    elif kind == "three-parallel":
        chain = random_arm(rng, kind, convention)
    else:
        chain = random_arm(rng, kind, convention, prismatic3=case == "prismatic3")
    if not analyze_structure(chain).closed_form:  # a degenerate arm may lose its closed form
        assert degenerate and drawn, (f"the {kind} arm (case {case}, seed {seed}, degenerate={degenerate}) "
                                      f"has no closed form: nothing would be checked")
        return False
    _assert_ik_properties(chain, _poses(rng, chain, 6, degenerate))
    if not degenerate and not chain.prismatic.any():  # EAIK's arms are revolute
        assert_same_as_eaik(chain, _poses(rng, chain, 6, False))
    return True


@pytest.mark.parametrize("kinds", PLANAR_CLASSES, ids=lambda k: "-".join(x[0] for x in k))
@settings(**EXAMPLES, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), degenerate=st.booleans())
def test_scara_and_planar_arms(kinds, seed, degenerate):
    rng = np.random.default_rng(seed)
    chain = planar_arm(rng, list(kinds), ["standard", "modified"][seed % 2], degenerate)
    assert analyze_structure(chain).closed_form
    _assert_ik_properties(chain, _poses(rng, chain, 6, degenerate))


def test_stanford_like_arm_at_an_aligned_wrist_on_the_grid():
    """Issue 10 item 3: before, 8 isolated solutions within 1e-8 of a family (an SP2 double
    root split by the square root of a rounding error), none the generating q, no flag."""
    rows = [DHRow(-pi / 2, 0.0, -0.2497, pi), DHRow(pi / 2, 0.0, 0.1364, pi),
            DHRow(pi / 2, 0.0, 0.3573, 0.0, "prismatic"), DHRow(-pi / 2, 0.0, 0.3382, pi / 2),
            DHRow(pi / 2, 0.0, 0.0, pi), DHRow(-pi / 2, 0.1364, 0.0, -pi / 2)]
    chain = chain_from_dh(rows, "standard", limits=[(-pi, pi)] * 2 + [(-0.6, 0.6)] + [(-pi, pi)] * 3)
    q = np.array([pi, pi, -0.3, pi, 0.0, pi])
    T = fk(chain, q)
    found = ik_solutions(chain, T, near=q)
    assert found.family.any() and (joint_distance(chain, found.q, q) <= FOUND).any()
    assert joint_distance(chain, ik(chain, T, near=q, within_limits=False), q) <= FOUND


@pytest.mark.parametrize(("kind", "case", "seed"), [("spherical-wrist", 2, 3236), ("spherical-wrist", 0, 56)])
def test_families_that_cross(kind, case, seed):
    """Two lines of solutions that cross (two pairs of collinear axes, e.g. axes 2 and 5 at one
    end of the aligned wrist's line q4 - q6): the generating q lies on the other line. Before,
    the walk stopped where the distance to q, taken after the 2 pi wrap, has a saddle (seed
    3236, a CI failure), or moved along the second pair with the axes of the first position
    (seed 56)."""
    check_six_joint_arm(kind, case, seed, degenerate=True)


def test_curved_family_is_traced():
    """A family that is a curve in joint space (three parallel axes 3-5 on the grid, seed 9):
    the null vector turns along it, so neither its tangent line nor local steps from the
    closed form's member reach q; tracing the curve does."""
    check_six_joint_arm("three-parallel", 2, 9, degenerate=True)


@pytest.mark.parametrize("seed", [21, 45, 40])
def test_families_of_the_parallel_base(seed):
    """Axes 1-3 parallel with the rest on the grid: the two equations in (q4, q6) are one
    (seeds 21, 45: the quartic vanishes, every q6 has its q4), or axis 5 is parallel to axes
    1-3 (seed 40: four parallel axes, q5 free). Before, the family's representative was
    q6 = 0 or q5 = 0, where the planar 2R cannot reach: every candidate invalid and a
    reachable pose called out of reach. Now the member the 2R reaches best stands for it."""
    check_six_joint_arm("three-parallel", 1, seed, degenerate=True)


@pytest.mark.parametrize(("kind", "case", "seed"), [("spherical-wrist", 4, 28), ("spherical-base", None, 0)])
def test_multiple_roots_of_the_quartic(kind, case, seed):
    """A double (or higher) root of the quartic path, which Newton steps reach only to
    ~1e-5 here: put exactly on the root of F's derivative, so the aligned wrist's family is
    recognised (before: q lost, and a reachable pose called out of reach)."""
    check_six_joint_arm(kind, case, seed, degenerate=True)


@pytest.mark.parametrize(("kind", "case", "seed"), [("spherical-wrist", 0, 63), ("spherical-wrist", 4, 99)])
def test_unflagged_families(kind, case, seed):
    """Families the case solver did not flag: two exact solutions 1e-5 apart at a singular
    configuration (seed 63), and a wrist aligned to ~1e-12 behind the arm joints' rounding
    (seed 99). Both are now flagged and walked to q."""
    check_six_joint_arm(kind, case, seed, degenerate=True)


def test_reachable_pose_of_issue_10_item_1_is_not_called_out_of_reach():
    """Issue 10 item 1, the instance reported: a modified-DH arm (axes 1-3 parallel) at a
    configuration with smallest singular value 5e-17. Before, every closed-form candidate was
    invalid and ``ik(T, near=q, within_limits=False)`` raised UnreachableError "the closest
    pose found is 0 m and 0 rad away"; now q is returned, and it lies in a flagged family."""
    rows = [DHRow(0, 0, -0.13004872473233184, pi / 2), DHRow(0, 0.3662878291719564, 0, 0),
            DHRow(0, -0.333824686289266, 0, pi / 2), DHRow(-pi / 2, -0.5384063781810956, 0, pi),
            DHRow(-pi / 2, -0.36990051727425505, 0, 0), DHRow(-pi / 2, 0, 0.5542745276812061, 0)]
    tool = DHRow(pi / 2, -0.26072101981645507, 0.5069489404932912, 0, None)
    chain = chain_from_dh(rows, "modified", tool_rows=[tool])
    q = np.array([-pi, -pi / 2, pi / 2, -pi, pi / 2, -pi / 2])
    assert singular_values(chain, q)[-1] < 1e-15
    T = fk(chain, q)
    assert joint_distance(chain, ik(chain, T, near=q, within_limits=False), q) <= FOUND
    found = ik_solutions(chain, T, near=q)
    assert found.family.all() and len(found.q) > 0
    assert max(found.position_error.max(), found.orientation_error.max()) <= REPRODUCED
    assert joint_distance(chain, found.q[0], q) <= FOUND


def test_both_loops_of_a_family_with_a_fourth_parallel_axis():
    """Axes 1-3 parallel and axis 6 parallel to them at the pose (seed 69: q4 = 0, q5 = pi):
    the two-angle system leaves q6 free and the planar 2R reaches two separate intervals of
    it, each a loop of the family. Before, one member stood for both loops, and the
    generating q, on the other loop, was never reached (the family walk cannot leave its
    loop)."""
    check_six_joint_arm("three-parallel", 1, 69, degenerate=True)


def test_exact_candidates_the_existence_tests_rejected_are_kept():
    """Axes 2-4 parallel at a doubly singular pose (seed 42, q = [-pi/2, 0, pi, 0, pi, 0]):
    every candidate failed the case's existence test (a multiple root) while several
    reproduce the pose exactly. Before, ``ik_solutions`` listed none and ``ik`` called the
    pose out of reach, "0 m away"; now FK decides."""
    check_six_joint_arm("three-parallel", 2, 42, degenerate=True)


@pytest.mark.parametrize(("block", "seed"), [(1, 29), (4, 1106)])
def test_a_family_that_touches_the_reach_of_the_planar_2r(block, seed):
    """Axes 1-3 (or 4-6) parallel and a fourth axis parallel to them at a doubly singular
    grid pose: the two-angle system leaves q6 free, but the planar 2R reaches the family at
    one value of it only (the family touches the 2R's outer reach there; seed 29, pose 5).
    Before, the member nearest among 64 samples (0.0087 rad off) stood for it: every
    candidate missed the pose by 0.16 m and the listing was empty (the xfail of issue 10
    item 3). Now the least distance to the 2R's middle reach is searched between samples."""
    check_six_joint_arm("three-parallel", block, seed, degenerate=True)


def test_a_member_placed_beside_the_crossing_of_two_families():
    """Spherical wrist (axes 1, 2 meet), q = [pi, -pi/2, 0, pi, pi, pi] (seed 1072, pose 4):
    the closed form's member lies ~1.6e-7 off the aligned wrist's line, on a family that
    crosses it, so axes 4 and 6 are one line only to 1.6e-7 and neither the line move nor
    the trace (no null space at 1e-8) reached q. Axes one line within 1e-6 are now moved
    along it and projected back onto the solutions."""
    check_six_joint_arm("spherical-wrist", 0, seed=1072, degenerate=True)


def test_a_rough_family_member_at_a_doubly_singular_pose_is_refined():
    """Prismatic joint 3 with a 0.4 mm offset, at a pose with two zero singular values
    (seed 1006, pose 0): every candidate reproduced the pose to ~1e-8 only, 9e-6 rad from
    an exact point, and refinement, limited to 1e-6 to stay on a branch, gave up: an empty
    listing. A family's representative may move up to 1e-3 (its exact neighbours are
    members of the family)."""
    check_six_joint_arm("spherical-wrist", "prismatic3", 1006, degenerate=True)


def test_exact_candidates_rejected_beside_valid_ones_are_kept():
    """Axes 2-4 parallel, q = [pi, pi, pi, -pi/2, 0, pi/2] with two zero singular values (seed
    2381, pose 5): two candidates passed the case's existence tests and six exact ones (FK
    residual 2e-15) failed them; FK decided only where none passed, so the six were lost and
    with them the family holding q."""
    check_six_joint_arm("three-parallel", 2, 2381, degenerate=True)


def test_a_rough_family_member_is_refined_before_its_walk():
    """Spherical wrist, q = [0, pi, 0, 0, 0, 0] and q5 = pi poses (seed 2292): the aligned
    wrist's representatives reproduced the pose to ~5e-9 only (q2 2e-6 off pi); the Python
    layer refined them after the core had walked its families, so they stayed where the
    closed form put them, 1.7 rad from q along the line q4 - q6. The core now refines a
    rough candidate when it verifies it, before the walk."""
    check_six_joint_arm("spherical-wrist", 0, 2292, degenerate=True)
    check_six_joint_arm("spherical-wrist", 4, 2292, degenerate=True)


@pytest.mark.parametrize(("kind", "case", "seed"),
                         [("spherical-wrist", 2, 148133808), ("spherical-base", None, 168)])
def test_rejected_candidates_near_a_fold_are_no_extra_solutions(kind, case, seed):
    """Generic random arms at poses near a fold (smallest singular value 4e-7, 8e-5), found by
    ``make fuzz`` once FK decided on rejected candidates beside accepted ones: the point
    between two twin roots (seed 148133808, pose 3) came within 2.3e-9 of the pose after its
    Newton steps and was listed; a rejected root 1e-6 from its accepted twin (seed 168, pose
    0) was listed beside it. A rejected candidate must now reproduce the pose to rounding and
    lie 1e-3 or more from every accepted one."""
    check_six_joint_arm(kind, case, seed, degenerate=False)


def test_a_pose_the_listing_misses_is_answered_by_numeric_ik():
    """When the closed form lists no usable candidate for a pose numeric IK reaches exactly
    (no known pose does since the cases above were fixed; the listing is emptied here by
    hand, at the doubly singular pose of seed 29), ``numeric_fallback`` does not call it out
    of reach: it puts the numeric solution first, flagged as a family member (the Jacobian
    there is singular), within the limits when asked."""
    rng = np.random.default_rng(29)
    chain = degenerate_six_joint_arm(rng, "three-parallel", 1, "modified")
    q = _poses(rng, chain, 6, True)[5]
    T = fk(chain, q)[None]
    for within_limits in (True, False):
        empty = Found(np.zeros((1, 8, 6)), np.full((1, 8, 2), np.nan), np.zeros((1, 8, 4), dtype=bool),
                      np.zeros(1, dtype=np.int64))
        numeric_fallback(chain, empty, T, (q + 0.01)[None], Labels(0), within_limits)
        assert empty.count[0] == 1 and empty.keep[0, 0] and empty.family[0, 0]
        assert np.abs(fk(chain, empty.q[0, 0]) - T[0]).max() <= REPRODUCED
        assert chain.within_limits(empty.q[0, 0]) or not within_limits


def test_a_loop_between_the_samples_of_the_family():
    """Axes 1-3 parallel and axis 6 parallel to them at q = [0, pi/2, pi, pi/2, pi, pi/2]
    (seed 287711068, pose 3, found by ``make fuzz``): the q6 family has two loops, q6 in
    [1.496, 1.530] and [pi/2, 1.605], both between two of the 64 samples of the 2R's reach
    along it, and q lies on the second, where its elbows meet. Before, one member stood for
    the family (on the first loop: a crossing of the middle reach found beside the least
    sample), and q was missed. Now every sampled extremum of the reach is refined and each
    loop gets its member."""
    check_six_joint_arm("three-parallel", 1, 287711068, degenerate=True)


@pytest.mark.parametrize(("kind", "case", "seed"),
                         [("spherical-wrist", 4, 287899), ("spherical-base", None, 452)])
def test_fold_twins_beside_other_solutions(kind, case, seed):
    """Generic arms at a pose near a fold (``make fuzz``): one pair of twin solutions ~1e-5
    apart beside solutions without a twin. The EAIK comparison asked every one of ours to
    have a twin when the counts differ, not only the extra ones; it now counts the extras."""
    check_six_joint_arm(kind, case, seed, degenerate=False)


def test_an_inexact_eaik_answer_is_not_a_solution_we_miss():
    """A generic three-parallel arm (seed 303, pose 5, ``make fuzz``): one of EAIK's answers
    reproduces the pose to 3.9e-7 only, and Newton steps cannot improve it (a zero singular
    value there, a 2R just out of reach); the comparison took it for a solution of ours
    missing. It now holds EAIK's answers to our own 1e-9."""
    check_six_joint_arm("three-parallel", 3, 303, degenerate=False)


def test_fold_twins_with_a_singular_value_above_1e_6():
    """A generic spherical-wrist arm (seed 4087371, pose 2, ``make fuzz``): two of our
    solutions 5e-5 apart where EAIK gives one; the smallest singular value there is 1.9e-6,
    above the 1e-6 the comparison took for a fold. They are two roots (each exact to
    3e-16, the point between them 9e-11 off): the comparison now checks that directly."""
    check_six_joint_arm("spherical-wrist", 1, 4087371, degenerate=False)


def test_roots_split_on_either_side_of_a_family():
    """Spherical base, q = [-pi/2, 0, pi, -pi/2, 0, pi] (seed 1895, pose 0, ``make fuzz``):
    axes 1 and 3 are one line at q2 = 0, a family (q1 + q3 fixed), but the closed form's
    double root came out as two roots at q2 = +-2.2e-7, 1.2e-3 apart along the family, where
    the Jacobian is not singular to 1e-8: no family flag, and q missed. The point between
    two such roots, put onto the solution set, is singular: it now stands for the family."""
    check_six_joint_arm("spherical-base", None, 1895, degenerate=True)


def test_a_joint_on_its_pi_limit_at_an_ill_conditioned_pose():
    """Spherical wrist (axes 2, 3 meet), q = [-pi/2, -pi/2, -pi/2, pi/2, 0, pi] with limits
    +-pi (seed 11988646, pose 0, ``make fuzz``): smallest singular value 6.7e-5, so an FK
    residual of 1.7e-13 left q3 and q6 1.1e-9 off, and q6 at -pi + 1.1e-9 could not be
    wrapped to near's pi (1e-9 beyond the limit): ``ik(near=q)`` answered a solution pi away.
    Candidates above 1e-13 are now refined, wrapped towards near, and the nearest-only
    search measures a joint at a +-pi limit from near's side."""
    check_six_joint_arm("spherical-wrist", 2, 11988646, degenerate=True)


def test_split_roots_of_a_prismatic_arm_on_a_family():
    """Spherical wrist with a prismatic joint 3, q = [pi, -pi/2, 0, -pi/2, 0, pi] (seed
    13622, a sweep of 44,000 degenerate arms): the same kind of split double root as seed
    1895, 3.3e-4 apart; the singular point between them now stands for the family."""
    check_six_joint_arm("spherical-wrist", "prismatic3", 13622, degenerate=True)


@pytest.mark.parametrize(("case", "seed"), [(3, 10005), (2, 10910), (3, 11812), (2, 11878), (2, 12691)])
def test_families_of_three_parallel_middle_axes(case, seed):
    """Three parallel axes in the middle (2-4 or 3-5, solved as axes 2-4 of the arm or of
    its reverse) where the two equations in (q1, q5) are one (a sweep of 44,000 degenerate
    arms): every candidate took q1 = 0, where the 2R cannot reach, and none was valid: no
    solution at a reachable pose. The family's loops now get members as for axes 1-3."""
    check_six_joint_arm("three-parallel", case, seed, degenerate=True)


def test_a_vanishing_quartic_amplified_by_an_ill_conditioned_system():
    """Axes 4-6 parallel (seed 12421, pose 1): the quartic in q6 vanishes, but Q^-1 (an
    entry of 1.3e3) left its coefficients at 1e-12 in sum, just above the bar, so its
    remaining degree-1 part (noise) had no root and the pose had no solution. The bar is
    now scaled by |Q^-1|."""
    check_six_joint_arm("three-parallel", 4, 12421, degenerate=True)


def test_an_axis_parallel_to_rounding_after_a_near_tangent_root():
    """Axes 3-5 parallel (seed 11590, pose 2): q1 is a root of a near-tangent equation
    (its twin 7e-4 away), exact to ~1e-12 only, and axis 6 is then parallel to the three
    axes to 3.9e-12, just above the 1e-12 at which q6 is free: SP1 gave q6 0.008 off and
    the 2R could not reach. Where the 2R cannot follow and axis 6 is within 1e-11, q6 is
    now taken as free (the family's member, refined by FK)."""
    check_six_joint_arm("three-parallel", 3, 11590, degenerate=True)


def test_a_member_where_the_split_roots_of_two_crossing_families_meet():
    """Spherical base, q = [pi, pi/2, pi/2, pi, pi, pi] (seed 11812, pose 4; a sweep of
    44,000 degenerate arms): axes 1, 3 and axes 4, 6 are both one line there (two families
    cross), but the closed form's members, both flagged, lay 1.7e-6 off the crossing, where
    axes 1 and 3 are one line only to 1.7e-6 and the walk drifted. The point between two such
    members, more singular than either, now stands for them."""
    check_six_joint_arm("spherical-base", None, 11812, degenerate=True)


def test_a_free_shoulder_joint_whose_member_has_an_aligned_wrist():
    """Spherical wrist (axes 2, 3 meet), q = [-pi/2, pi, 0, pi, 0, pi] (seed 10492, pose 5):
    the wrist centre lies on axis 2, so q2 turns freely while the wrist follows, and the
    closed form's member (q2 = 0) has an aligned wrist, where the Jacobian lacks the family's
    direction: the walk could not follow it to q2 = pi. A second member, where the wrist is
    farthest from aligned, now takes a free slot."""
    check_six_joint_arm("spherical-wrist", 2, 10492, degenerate=True)


def test_members_placed_along_a_family_the_case_did_not_see():
    """Spherical base, q = [-pi/2, pi/2, pi/2, -pi/2, 0, pi/2] (seed 20875, pose 0; a sweep
    of 44,000 degenerate arms): axes 1 and 5 are one line there, and the closed form, its
    equations ill-conditioned beside the family (a tangent root split by 1e-6), placed all 8
    candidates at different points of it, rough (6e-10) and not flagged: none was walked,
    and q was missed. A rough candidate that, refined, lies on a family (a step along its
    null space stays a solution) is now flagged and walked."""
    check_six_joint_arm("spherical-base", None, 20875, degenerate=True)


def test_a_residual_minimum_beside_a_root_is_not_a_second_solution():
    """A generic spherical-wrist arm near a fold (seed 57992, pose 5, found by hypothesis):
    the closed form listed a second candidate 1.5e-6 from an exact root, at a residual
    minimum of 5.5e-14 that Newton steps cannot lower, the point between them 1.2e-13 off:
    one solution listed twice. It is now dropped."""
    check_six_joint_arm("spherical-wrist", 3, 57992, degenerate=False)


@pytest.mark.parametrize("case", [0, 4, "prismatic3"])
def test_twin_roots_beside_a_fold_stay_two(case):
    """Generic spherical-wrist arms near a fold (seed 4728, pose 1; a sweep of 22,000 generic
    arms): twin roots 3.6e-6 apart, each exact to 8e-16, the point between them 7.5e-13 off.
    A first rule merged candidates whose midpoint reproduced the pose to 1e-12 and lost the
    generating one; the rule now asks for no barrier above the candidates' own residuals."""
    check_six_joint_arm("spherical-wrist", case, 4728, degenerate=False)


def test_a_walk_across_the_crossing_of_two_families():
    """Axes 3-5 parallel, q = [pi, pi/2, pi/2, -pi/2, 0, -pi/2] (seed 20377, pose 5; the
    one failure of 198,000 arms swept before this fix): q lies on the line where axes 3 and
    5 are one (the 2R folded onto its first axis); the closed form's member lies on a family
    in which q1, q3 and q5 turn together (axis 1 parallel to the three), which meets that
    line at q1 = pi with a kink. The trace stopped short of the kink, and the local steps
    from there, along the one null direction, ended 0.02 rad off it. A step that ends
    stuck is now tried once more over the directions whose singular values are below 5 %
    of the largest (the other family's, near the crossing)."""
    check_six_joint_arm("three-parallel", 3, 20377, degenerate=True)
