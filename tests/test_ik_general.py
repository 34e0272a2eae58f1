"""Every IK solution of a general 6R arm (Raghavan-Roth elimination in the core).

The ground truth for "every solution" is a many-seed search by SciPy's Levenberg-Marquardt
(``scipy.optimize.least_squares``, not armkit's solver) on armkit's FK (itself checked
against pinocchio): every solution it finds must be listed, every listed one must reproduce
its pose to 1e-9, and the configuration that generated the pose must be among them.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers import joint_distance, newton_root
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import least_squares
from test_ik_singular_sweeps import represented

import armkit
from armkit.chain import DHRow
from armkit.ik import ik_solutions
from armkit.ik.structure import analyze_structure
from armkit.poe import poe_from_chain

#: Seeds of the numeric search per pose.
SEARCH_SEEDS = 40


def general_arm(rng: np.random.Generator, slide: int | None = None) -> armkit.Robot:
    """A random 6R arm in standard DH with every length and twist non-zero (no Pieper class);
    joint ``slide`` (0-based) prismatic if given."""
    rows = [DHRow(rng.uniform(0.2, 2.9) * rng.choice([-1, 1]), rng.uniform(0.05, 0.5), rng.uniform(-0.4, 0.4),
                  rng.uniform(-np.pi, np.pi), "prismatic" if j == slide else "revolute") for j in range(6)]
    return armkit.Robot.from_dh(rows, "standard", name="general")


def moved_lines(name: str, axes: np.ndarray, points: np.ndarray) -> armkit.Robot:
    """Built-in ``name`` with its joint lines at q = 0 replaced by ``axes``, ``points`` (its tool
    pose, joint kinds and limits kept)."""
    chain = armkit.load(name).chain
    kinds = ["prismatic" if p else "revolute" for p in chain.prismatic]
    return armkit.Robot.from_poe(axes, points, poe_from_chain(chain).M, name=name, kinds=kinds,
                                 limits=list(zip(chain.lower, chain.upper, strict=True)))


def calibrated(name: str, deviation: float, rng: np.random.Generator) -> armkit.Robot:
    """Built-in ``name`` with every joint line moved by about ``deviation`` (a calibrated arm)."""
    poe = poe_from_chain(armkit.load(name).chain)
    axes = poe.axes + deviation * rng.normal(size=(6, 3))
    axes /= np.linalg.norm(axes, axis=1)[:, None]
    return moved_lines(name, axes, poe.points + deviation * rng.normal(size=(6, 3)))


def angle_gap(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Largest joint difference modulo 2 pi, over the last axis."""
    return np.abs(np.angle(np.exp(1j * (a - b)))).max(axis=-1)


def numeric_solutions(robot: armkit.Robot, T: np.ndarray, rng: np.random.Generator) -> list[np.ndarray]:
    """The distinct solutions SciPy's LM finds from SEARCH_SEEDS random seeds (residual < 1e-10),
    each taken by Newton onto the solution it stands for (``helpers.newton_root``)."""

    def residual(q):
        F = robot.fk(q)
        return np.concatenate([(F[:3, :3] - T[:3, :3]).ravel(), F[:3, 3] - T[:3, 3]])

    found: list[np.ndarray] = []
    for _ in range(SEARCH_SEEDS):
        fit = least_squares(residual, rng.uniform(-np.pi, np.pi, robot.n), method="lm",
                            xtol=1e-15, ftol=1e-15, gtol=1e-15)
        if np.abs(fit.fun).max() >= 1e-10:
            continue
        q = np.where(robot.chain.prismatic, fit.x, np.angle(np.exp(1j * fit.x)))
        q = newton_root(robot.chain, T, q)
        if all(joint_distance(robot.chain, q, f) > 1e-6 for f in found):
            found.append(q)
    return found


def check_pose(robot: armkit.Robot, q0: np.ndarray, rng: np.random.Generator) -> None:
    """The listing of fk(q0) holds q0 and every solution of the numeric search, each once, and
    every listed solution reproduces the pose to 1e-9."""
    T = robot.fk(q0)
    listed = robot.ik(T, all_solutions=True, within_limits=False)
    assert 1 <= len(listed) <= 16
    assert len(listed) % 2 == 0, "a generic pose has an even number of real solutions"
    for q in listed:
        assert np.abs(robot.fk(q) - T).max() <= 1e-9
    for q in [q0, *numeric_solutions(robot, T, rng)]:
        assert joint_distance(robot.chain, listed, q).min() <= 1e-6, \
            f"solution {q.tolist()} of the pose of {q0.tolist()} is not among {len(listed)} listed"
    gaps = joint_distance(robot.chain, listed[:, None], listed[None])[~np.eye(len(listed), dtype=bool)]
    assert gaps.min(initial=np.inf) > 1e-9, "a solution is listed twice"


def check_every_solution(robot: armkit.Robot, rng: np.random.Generator, poses: int) -> None:
    for _ in range(poses):
        check_pose(robot, rng.uniform(-np.pi, np.pi, robot.n), rng)


@pytest.mark.parametrize("seed", range(6))
def test_random_general_arms_list_every_solution_a_numeric_search_finds(seed):
    rng = np.random.default_rng(seed)
    robot = general_arm(rng)
    assert analyze_structure(robot).kind == "general-6r"
    check_every_solution(robot, rng, poses=2)


@pytest.mark.parametrize("slide", range(6))
def test_random_arms_with_one_prismatic_joint_list_every_solution_a_numeric_search_finds(slide):
    # 5R1P, the slide at every place in the chain: the elimination takes it as one of the two
    # joints it eliminates linearly (NoClosedFormError before)
    rng = np.random.default_rng([21, slide])
    robot = general_arm(rng, slide)
    structure = analyze_structure(robot)
    assert structure.kind == "general-5r1p" and structure.max_solutions == 16
    check_every_solution(robot, rng, poses=3)
    q0 = rng.uniform(-np.pi, np.pi, 6)
    q0[slide] = rng.choice([-1, 1]) * rng.uniform(4.0, 9.0)  # a slide of metres: no angle wraps it
    check_pose(robot, q0, rng)


def line_moved(name: str, joint: int, turn: bool, direction: np.ndarray, deviation: float) -> armkit.Robot:
    """Built-in ``name`` with joint ``joint``'s axis turned (``turn``), or its point moved, by
    ``deviation`` towards ``direction`` (a calibration that corrects a single joint)."""
    poe = poe_from_chain(armkit.load(name).chain)
    axes, points = poe.axes.copy(), poe.points.copy()
    direction = direction * deviation / np.linalg.norm(direction)
    if turn:
        axes[joint] += direction - (direction @ axes[joint]) * axes[joint]  # a turn of ~deviation rad
        axes[joint] /= np.linalg.norm(axes[joint])
    else:
        points[joint] += direction
    return moved_lines(name, axes, points)


def one_line_moved(name: str, deviation: float, rng: np.random.Generator) -> armkit.Robot:
    """Built-in ``name`` with one random joint's axis turned, or its point moved, by ``deviation``
    in a random direction."""
    joint, direction = rng.integers(6), rng.normal(size=3)
    return line_moved(name, joint, bool(rng.integers(2)), direction, deviation)


@pytest.mark.parametrize("name", ["ur5", "puma560", "probot-anno"])
@pytest.mark.parametrize("deviation", [1e-3, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9])
def test_calibrated_arms_near_a_class_list_every_solution_of_the_real_arm(name, deviation):
    rng = np.random.default_rng([len(name), round(-np.log10(deviation))])  # a draw per arm and size
    robot = calibrated(name, deviation, rng)
    assert analyze_structure(robot).kind == "general-6r"
    check_every_solution(robot, rng, poses=2)


@pytest.mark.parametrize("name", ["ur5", "puma560", "probot-anno"])
@pytest.mark.parametrize("deviation", [1e-9, 1e-7, 1e-4])
def test_one_joint_line_moved_in_a_random_direction_lists_every_solution_of_the_real_arm(name, deviation):
    rng = np.random.default_rng([len(name), round(-np.log10(deviation)), 1])
    robot = one_line_moved(name, deviation, rng)
    check_every_solution(robot, rng, poses=2)


@pytest.mark.parametrize("name", ["ur5", "puma560", "probot-anno"])
def test_an_arm_within_rounding_of_its_class_keeps_it_and_a_calibrated_one_does_not(name):
    # a class is detected only to the rounding of a file's numbers (CLASS_TOLERANCE): moved by
    # 1e-14 the arm is still its class, and its solutions reproduce the real arm's poses;
    # moved by 1e-10 it is the general 6R arm it is (taken as the class before, its listing
    # lost the generating configuration on 5-12 of 100 poses at 1e-9)
    from armkit.ik.structure import CLASS_TOLERANCE

    assert CLASS_TOLERANCE == 1e-11
    ideal = analyze_structure(armkit.load(name)).kind
    rng = np.random.default_rng(len(name))
    assert analyze_structure(calibrated(name, 1e-14, rng)).kind == ideal
    assert analyze_structure(calibrated(name, 1e-10, rng)).kind == "general-6r"
    robot = calibrated(name, 1e-14, rng)
    for _ in range(20):
        q0 = rng.uniform(-np.pi, np.pi, 6)
        T = robot.fk(q0)
        listed = robot.ik(T, all_solutions=True, within_limits=False)
        assert np.abs(robot.fk(listed) - T).max() <= 1e-9
        assert angle_gap(listed, q0).min() <= 1e-6


def test_a_7r_arm_with_a_joint_locked_is_solved_exactly_at_that_value():
    panda = armkit.load("panda")
    arm = panda.lock({panda.joint_names[2]: 0.4})  # the upper-arm roll: no Pieper class is left
    assert analyze_structure(arm).kind == "general-6r"
    rng = np.random.default_rng(3)
    check_every_solution(arm, rng, poses=2)


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), slide=st.sampled_from([None, 0, 1, 2, 3, 4, 5]))
def test_the_generating_configuration_is_always_listed(seed, slide):
    rng = np.random.default_rng(seed)
    robot = general_arm(rng, slide)
    q0 = rng.uniform(-np.pi, np.pi, 6)
    T = robot.fk(q0)
    found = armkit.ik_solutions(robot, T)
    assert joint_distance(robot.chain, found.q, q0).min() <= 1e-7
    assert np.all(found.position_error <= 1e-9) and np.all(found.orientation_error <= 1e-9)


def test_a_pose_out_of_reach_of_a_general_arm_is_an_unreachable_error():
    robot = general_arm(np.random.default_rng(1))
    T = np.eye(4)
    T[:3, 3] = [50.0, 0.0, 0.0]
    with pytest.raises(armkit.errors.UnreachableError):
        robot.ik(T, all_solutions=True)


def panda_pose() -> tuple[armkit.Robot, np.ndarray, np.ndarray]:
    panda = armkit.load("panda")
    q = np.array([0.3, -0.4, 0.2, -2.0, 0.1, 1.8, 0.6])
    return panda, q, panda.fk(q)


def test_ik_at_a_free_joint_of_a_7r_arm_lists_every_solution_at_that_value():
    panda, q0, T = panda_pose()
    listed = panda.ik(T, all_solutions=True, free_joint=2, free_value=0.2, within_limits=False)
    assert listed.shape[1] == 7 and np.all(listed[:, 2] == 0.2)
    assert angle_gap(listed, q0).min() <= 1e-9
    for q in listed:
        assert np.abs(panda.fk(q) - T).max() <= 1e-9
    # every solution a numeric search over the other six joints finds is listed
    arm = panda.lock({2: 0.2})
    for q in numeric_solutions(arm, T, np.random.default_rng(8)):
        assert angle_gap(listed, arm.full_q(q)).min() <= 1e-6


def test_nearest_solution_at_a_free_joint_holds_near_s_value():
    panda, q0, T = panda_pose()
    near = q0 + 0.05
    q = panda.ik(T, near=near, free_joint="q3")
    assert q[2] == near[2] and np.abs(panda.fk(q) - T).max() <= 1e-9


@pytest.mark.parametrize("value", [float("nan"), float("inf"), True, "0.3"])
def test_a_free_value_that_is_no_finite_number_is_named_free_value(value):
    panda = armkit.load("panda")
    T = panda.fk(np.full(7, 0.3))
    with pytest.raises(armkit.InputError, match=r"free_value .*: expected a finite value of q3 \[rad\]"):
        panda.ik(T, free_joint=2, free_value=value)


def test_free_value_without_free_joint_and_unknown_free_joint_are_input_errors():
    panda, _, T = panda_pose()
    with pytest.raises(armkit.InputError, match="free_value: given without free_joint"):
        panda.ik(T, free_value=0.3)
    with pytest.raises(armkit.InputError, match="free_joint 9: expected a joint name"):
        panda.ik(T, all_solutions=True, free_joint=9)


def test_self_motion_branches_are_solutions_and_hold_the_generating_configuration(tmp_path):
    panda, q0, T = panda_pose()
    values = q0[2] + np.linspace(-1.0, 1.0, 21)  # the generating value at index 10
    motion = armkit.self_motion(panda, T, free_joint=2, values=values)
    assert motion.q.ndim == 3 and motion.q.shape[1:] == (21, 7)
    finite = np.isfinite(motion.q).all(axis=-1)
    assert finite.any(axis=1).all()  # no empty branch
    for q in motion.q[finite]:
        assert np.abs(panda.fk(q) - T).max() <= 1e-9
    assert np.all(motion.q[finite][:, 2] == np.broadcast_to(values, finite.shape)[finite])
    assert angle_gap(motion.q[:, 10][finite[:, 10]], q0).min() <= 1e-9
    # nothing is lost in joining samples into branches: each sample holds every solution there
    for k, value in enumerate(values):
        at_value = panda.ik(T, all_solutions=True, free_joint=2, free_value=value, within_limits=False)
        assert finite[:, k].sum() == len(at_value)
    motion.plot(tmp_path / "self_motion.png")
    assert (tmp_path / "self_motion.png").stat().st_size > 10_000


def test_self_motion_samples_out_of_reach_are_nan_not_an_error():
    panda, q0, T = panda_pose()
    motion = armkit.self_motion(panda, T, free_joint=6, samples=32)  # the flange roll: reach is lost
    finite = np.isfinite(motion.q).all(axis=-1)
    assert finite.any() and not finite.any(axis=0).all()


def test_free_joint_with_one_near_per_pose_holds_each_pose_s_own_value():
    panda, q0, _ = panda_pose()
    Q = np.array([q0, q0 + 0.3])
    q = panda.ik(panda.fk(Q), near=Q, free_joint=2)
    assert q.shape == (2, 7) and np.all(q[:, 2] == Q[:, 2])


@pytest.mark.parametrize("index", [2, 3, 4])
def test_a_loop_joint_at_its_offset_plus_pi_is_found(index):
    # joints 3-5 of the loop are measured from offsets (0.3, 0.7, 1.1 rad); at offset + pi the
    # half-angle tangent is infinite and only the x^3 (or x^2) monomials of the null vector
    # are non-zero (x4, x5 from the largest pair by atan2; missed on 3 of 10 arms before)
    from armkit.ik.cases import GeneralGeometry, solve_pose
    from armkit.ik.closed_form import case_chain

    rng = np.random.default_rng(2005)
    robot = general_arm(rng)
    poe = poe_from_chain(robot.chain)
    geometry = GeneralGeometry(case_chain(poe.axes, poe.points, robot.chain.prismatic), shift=0)
    for _ in range(5):
        q0 = rng.uniform(-np.pi, np.pi, 6)
        q0[index] = np.angle(np.exp(1j * ([0.3, 0.7, 1.1][index - 2] + np.pi)))
        G = robot.fk(q0) @ np.linalg.inv(poe.M)
        q, valid, _ = solve_pose(geometry, np.ascontiguousarray(G[:3, :3]), np.ascontiguousarray(G[:3, 3]))
        assert angle_gap(q[valid], q0).min() <= 1e-6


def test_self_motion_checks_its_arguments():
    panda, _, T = panda_pose()
    with pytest.raises(armkit.InputError, match="samples: expected a whole number"):
        armkit.self_motion(panda, T, free_joint=2, samples=1)
    with pytest.raises(armkit.InputError, match="values: expected at least two finite values"):
        armkit.self_motion(panda, T, free_joint=2, values=[0.1, np.nan])


def test_an_arm_with_parallel_and_meeting_axes_outside_every_class_lists_every_solution():
    # axes 2 and 3 parallel, 3 and 4 meeting, wrist twists of 55 degrees (no Pieper class):
    # the loop through joints 3-5 degenerates, so the solver must pick another loop
    rows = [DHRow(np.pi / 2, 0.0, 0.275, 0.0), DHRow(np.pi, 0.41, 0.0, 0.0),
            DHRow(np.pi / 2, 0.0, -0.01, 0.0), DHRow(np.radians(55), 0.0, -0.25, 0.0),
            DHRow(np.radians(55), 0.0, -0.085, 0.0), DHRow(0.0, 0.0, -0.16, 0.0)]
    robot = armkit.Robot.from_dh(rows, "standard", name="offset wrist")
    assert analyze_structure(robot).kind == "general-6r"
    check_every_solution(robot, np.random.default_rng(4), poses=3)


#: A UR5 whose DH numbers moved by 3e-6 (a calibrated arm, general 6R), as a tester wrote it.
_UR5_MOVED_3E6 = [  # alpha, a, d, theta per joint
    (np.pi / 2, 3e-6, 0.089462, 0.0), (-3e-6, -0.425, 0.0, -3e-6), (-3e-6, -0.392253, 3e-6, -3e-6),
    (np.pi / 2 - 3e-6, 3e-6, 0.109147, 0.0), (-np.pi / 2 - 3e-6, -3e-6, 0.094653, 0.0),
    (0.0, -3e-6, 0.082303, 3e-6)]


@pytest.mark.parametrize("q5", [1e-4, 1e-3, 3e-3])
def test_a_calibrated_ur5_near_its_wrist_singularity_lists_the_generating_configuration(q5):
    # the loop choice once ranked loops by their count of candidates near a solution first and took
    # one that lost a root beside a near-double one: 7 of 8 solutions, the generating one missing
    joints = [{"name": f"q{i + 1}", "type": "revolute", "alpha": alpha, "a": a, "d": d, "theta": theta}
              for i, (alpha, a, d, theta) in enumerate(_UR5_MOVED_3E6)]
    robot = armkit.robot_from_dict({"convention": "standard", "joints": joints}, "ur5 moved by 3e-6")
    assert analyze_structure(robot).kind == "general-6r"
    rng = np.random.default_rng(1)
    for _ in range(10):
        q0 = rng.uniform(-np.pi, np.pi, 6)
        q0[4] = q5
        listed = robot.ik(robot.fk(q0), all_solutions=True, within_limits=False)
        assert len(listed) % 2 == 0 and angle_gap(listed, q0).min() <= 1e-9, (q0, len(listed))


@pytest.mark.slow  # 240 poses, a 40-seed SciPy search each
@pytest.mark.parametrize("deviation", [1e-9, 1e-8, 7e-8, 1e-7, 1e-6])
@pytest.mark.parametrize("joint", range(6))
def test_a_ur5_with_one_line_moved_lists_every_solution_near_its_wrist_singularity(joint, deviation):
    # the UR5's axes 5 and 6 meet; one of them moved by 1e-8 .. 1e-6 left the arm exactly
    # three-parallel (axes 2-4 still parallel), whose two-angle system in q1, q5 is then nearly of
    # rank 1: at q5 = 1e-4 .. 1e-2 the class solver listed 1-6 of 8 solutions on 60 of 480 poses.
    # Such an arm is now the general solver's, seeded by the class on the arm with them meeting.
    rng = np.random.default_rng([joint, round(-10 * np.log10(deviation))])
    for turn in (True, False):
        robot = line_moved("ur5", joint, turn, rng.normal(size=3), deviation)
        for q5 in (1e-4, 1e-3, 7.7e-3, 1e-2):
            q0 = rng.uniform(-np.pi, np.pi, 6)
            q0[4] = q5 * rng.choice([-1.0, 1.0])
            check_pose(robot, q0, rng)


@pytest.mark.parametrize("joint", [4, 5])
def test_a_three_parallel_arm_whose_wrist_axes_miss_lists_the_pair_beside_an_aligned_wrist(joint):
    # joint 5's or 6's point moved by 1e-2: axes 2-4 still parallel, axes 5 and 6 a centimetre
    # apart (the two-angle system's Q of rank 2). Within 1e-5 of an aligned wrist the quartic's two
    # roots there are a near-double pair, placed to ~1e-8 in q1 and ~1e-7 in q5: both were snapped
    # onto the aligned value, or polished onto one, and the generating configuration lost (4 of 72
    # poses in tests/sweep_near_subcase.py); now they are split from sines (split_near_aligned_pairs)
    rng = np.random.default_rng([joint, 21])
    axes = poe_from_chain(armkit.load("ur5").chain).axes
    for arm in range(3):  # moved mostly along the common normal of axes 5 and 6
        robot = line_moved("ur5", joint, False, np.cross(axes[4], axes[5]) + 0.5 * rng.normal(size=3), 1e-2)
        assert analyze_structure(robot).kind == "three-parallel"
        for pose in range(24):
            q0 = rng.uniform(-np.pi, np.pi, 6)
            q0[4] = rng.choice([-1.0, 1.0]) * 10.0 ** rng.uniform(-7, -5)
            if pose < 2:
                check_pose(robot, q0, rng)
                continue
            T = robot.fk(q0)
            listed = robot.ik(T, all_solutions=True, within_limits=False)
            assert np.abs(robot.fk(listed) - T).max() <= 1e-9
            assert angle_gap(listed, q0).min() <= 1e-6, (arm, q0.tolist(), listed.tolist())
        for _ in range(4):  # exactly aligned (the snap now only within 1e-10): a flagged family holds q0
            q0 = rng.uniform(-np.pi, np.pi, 6)
            q0[4] = 0.0
            T = robot.fk(q0)
            found = ik_solutions(robot, T)
            assert np.abs(robot.fk(found.q) - T).max() <= 1e-9
            assert represented(robot, T, found, q0), (arm, q0.tolist(), found.q.tolist())


def test_a_ur5_whose_wrist_axes_nearly_meet_is_solved_as_near_its_class():
    # within 1e-6 of meeting, not to rounding: refused by the three-parallel case (its system is
    # nearly of rank 1), solved by the general solver seeded by it; meeting to rounding: the class
    axes = poe_from_chain(armkit.load("ur5").chain).axes
    apart = np.cross(axes[4], axes[5])  # off the plane of axes 5 and 6
    structure = analyze_structure(line_moved("ur5", 4, False, apart, 7e-8))
    assert structure.kind == "general-6r" and "three-parallel case" in structure.description
    why = dict((case, reason) for case, _, reason in structure.why_not)
    assert "nearly meet" in why["three-parallel"]
    # axis 6 turned by 7e-8 out of the plane normal to axis 5: the wrist almost aligns
    turned = analyze_structure(line_moved("ur5", 5, True, axes[4], 7e-8))
    assert turned.kind == "general-6r"
    assert "nearly let the wrist align" in dict((c, r) for c, _, r in turned.why_not)["three-parallel"]
    assert analyze_structure(line_moved("ur5", 4, False, apart, 1e-14)).kind == "three-parallel"


@pytest.mark.parametrize("deviation", [1e-9, 1e-8, 1e-7, 3e-7])  # each line moved by ~1.6 x this
def test_a_stanford_arm_near_its_class_is_solved_through_its_prismatic_joint(deviation):
    # the general solver with its slide, seeded by the class's solutions on the arm moved onto it
    rng = np.random.default_rng([7, round(-np.log10(deviation))])
    robot = calibrated("stanford", deviation, rng)
    structure = analyze_structure(robot)
    assert structure.kind == "general-5r1p" and "spherical" in structure.description
    for q0 in robot.random_q(4, rng=rng):
        check_pose(robot, q0, rng)
    # near the wrist singularity too
    q0 = robot.random_q(rng=rng)
    q0[4] = 1e-3
    check_pose(robot, q0, rng)


@pytest.mark.parametrize("deviation", [1e-5, 1e-3, 1e-1])
def test_a_stanford_arm_far_from_its_class_lists_every_solution(deviation):
    # beyond 1e-6 no class seeds it (NoClosedFormError before, "numeric IK")
    rng = np.random.default_rng([8, round(-np.log10(deviation))])
    robot = calibrated("stanford", deviation, rng)
    structure = analyze_structure(robot)
    assert structure.kind == "general-5r1p" and "within 1e-6" not in structure.description
    check_every_solution(robot, rng, poses=3)
    q0 = robot.random_q(rng=rng)
    q0[4] = 1e-3  # near its wrist singularity
    check_pose(robot, q0, rng)


def test_an_arm_with_two_prismatic_joints_says_to_use_numeric_ik():
    rng = np.random.default_rng(7)
    rows = [DHRow(rng.uniform(0.2, 2.9), rng.uniform(0.05, 0.5), rng.uniform(-0.4, 0.4),
                  rng.uniform(-np.pi, np.pi), "prismatic" if j in (1, 2) else "revolute") for j in range(6)]
    robot = armkit.Robot.from_dh(rows, "standard", name="two slides")
    structure = analyze_structure(robot)
    assert structure.kind == "none" and "2 joints are prismatic" in structure.description
    assert "numeric IK" in structure.description
    with pytest.raises(armkit.NoClosedFormError, match="numeric IK"):
        robot.ik(robot.fk(robot.random_q(rng=rng)), all_solutions=True)


def test_a_stanford_arm_near_its_class_at_a_pose_very_near_its_wrist_singularity():
    # much nearer the wrist singularity than the arm is to its class (q5 = 1e-5 .. 1e-7, lines moved
    # by 1e-8): Newton stalled 1e-3 off a root beside a near-double one; the weak-direction search
    # (cpp/include/armkit/double_root.hpp) takes it there
    rng = np.random.default_rng(3)
    robot = calibrated("stanford", 1e-8, rng)
    assert analyze_structure(robot).kind == "general-5r1p"
    for q0, q5 in zip(robot.random_q(8, rng=rng), [1e-5, 1e-6, 1e-7] * 3, strict=False):
        q0[4] = q5
        check_pose(robot, q0, rng)


def test_rows_beside_a_near_double_root_are_taken_onto_their_roots():
    # a UR5 with joint 2's axis turned by 1e-8 at q5 = 1e-4 (general solver): Newton stalled 2.1e-6 rad
    # off the generating solution, at a residual of 9e-14, where the Jacobian's smallest singular value
    # is 1.5e-8 of its largest; a three-parallel arm (joint 1 turned by 1e-2, its class) at q5 = 1e-7 ..
    # 1e-6: rows 1e-4 .. 3e-2 off their roots at residuals of 1e-10. The weak-direction search
    # (double_root.hpp) takes both onto their roots.
    rng = np.random.default_rng([1, 80])
    cases = [(line_moved("ur5", 1, True, rng.normal(size=3), 1e-8), [1e-4])]
    cases.append((line_moved("ur5", 0, True, np.array([0.3, -0.5, 0.8]), 1e-2), [1e-7, 1e-6] * 3))
    for robot, q5s in cases:
        for q5 in q5s:
            q0 = rng.uniform(-np.pi, np.pi, 6)
            q0[4] = q5
            T = robot.fk(q0)
            listed = robot.ik(T, all_solutions=True, within_limits=False)
            assert angle_gap(listed, q0).min() <= 1e-6, (q0, listed)
            assert np.abs(robot.fk(listed) - T).max() <= 1e-14


def test_a_three_parallel_arm_at_a_pose_very_near_its_wrist_singularity():
    # joint 1's axis turned by 1e-2 (still the class), q5 = 1e-7 .. 1e-6 with the elbow nearly
    # stretched at one pose: the search once "found" a seventh solution 1.8e-3 rad from a listed
    # one, at residual 1.7e-10 where the Jacobian's smallest singular value is 8e-8; it was no
    # solution (Newton in 50-digit arithmetic takes it onto the listed one), and the oracle now
    # takes each found point onto the solution it stands for (helpers.newton_root)
    robot = line_moved("ur5", 0, True, np.array([0.3, -0.5, 0.8]), 1e-2)
    assert analyze_structure(robot).kind == "three-parallel"
    rng = np.random.default_rng(12)
    for q5 in (1e-7, 1e-6, 1e-7, 1e-6, 1e-7, 1e-6):
        q0 = rng.uniform(-np.pi, np.pi, 6)
        q0[4] = q5
        check_pose(robot, q0, rng)
