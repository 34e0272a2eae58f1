"""Helpers several test modules share (random arms, joint distances, the EAIK cross-check): import
them as ``from helpers import random_arm``. Fixtures and the transform assertion live in conftest."""

from dataclasses import replace
from functools import cache
from importlib.metadata import distribution
from pathlib import Path

import numpy as np
import pytest

import armkit
from armkit.chain import Chain, DHRow, chain_from_dh
from armkit.ik import numeric_ik
from armkit.ik.closed_form import closed_form_ik
from armkit.kinematics import fk, geometric_jacobian, pose_error
from armkit.poe import poe_from_chain
from armkit.spatial.rotations import matrix_from_axis_angle
from armkit.spatial.transforms import invert_transform

#: The built-in robots with a closed form.
CLOSED_FORM_ROBOTS = ["probot-anno", "puma560", "stanford", "ur5", "zju-i", "grb400-scara"]


# ----------------------------------------------------------------- random arms
def random_transform(rng):
    T = np.eye(4)
    T[:3, :3] = matrix_from_axis_angle(unit_vector(rng) * rng.uniform(-np.pi, np.pi))
    T[:3, 3] = rng.uniform(-0.3, 0.3, 3)
    return T


def unit_vector(rng):
    v = rng.normal(size=3)
    return v / np.linalg.norm(v)


def random_arm(rng, kind, convention, prismatic3=False):
    """A random 6-joint DH arm of a Pieper kind, with random offsets, base and tool.

    Link ``i`` (between axes ``i`` and ``i + 1``) has length ``a[i]`` and twist ``alpha[i]``:
    ``a = 0`` makes the axes meet, ``alpha = 0`` parallel, in either convention.
    """
    a = rng.uniform(-0.4, 0.4, 7)
    alpha = rng.choice([-1, 1], 7) * rng.uniform(0.3, np.pi - 0.3, 7)
    d = rng.uniform(-0.4, 0.4, 7)
    theta = rng.uniform(-np.pi, np.pi, 7)
    if kind in ("spherical-wrist", "spherical-base"):
        first, last = (4, 5) if kind == "spherical-wrist" else (1, 2)
        a[first] = a[last] = 0.0  # axes first..last+1 meet ...
        d[last] = 0.0  # ... at one point
        side = [1, 2] if kind == "spherical-wrist" else [4, 5]
        case = rng.integers(5) if not prismatic3 else 0  # 4: axes 1-3 (4-6) general
        if case == 0:
            a[side[0]] = 0.0  # axes 1, 2 (or 5, 6) meet
        elif case == 1:
            alpha[side[1]] = 0.0  # axes 2, 3 (or 4, 5) parallel
        elif case == 2:
            a[side[1]] = 0.0  # axes 2, 3 (or 4, 5) meet
        elif case == 3:
            alpha[side[0]] = 0.0  # axes 1, 2 (or 5, 6) parallel
    elif kind == "three-parallel":
        block = rng.choice([1, 2, 3, 4])  # axes 1-3, 2-4, 3-5 or 4-6
        alpha[block] = alpha[block + 1] = 0.0
        if rng.random() < 0.5:  # the next two axes after (or before) the block meet
            a[{1: 4, 2: 5, 3: 1, 4: 2}[block]] = 0.0
    kinds = ["revolute"] * 6
    if prismatic3:
        kinds[2] = "prismatic"
    if convention == "standard":  # row i: theta_i, d_i, a_i, alpha_i
        rows = [DHRow(alpha[i], a[i], d[i], theta[i], kinds[i - 1]) for i in range(1, 7)]
    else:  # row i: alpha_{i-1}, a_{i-1}, theta_i, d_i
        rows = [DHRow(alpha[i - 1], a[i - 1], d[i], theta[i], kinds[i - 1]) for i in range(1, 7)]
    limits = [(-np.pi, np.pi) if k == "revolute" else (0.1, 0.6) for k in kinds]
    return chain_from_dh(rows, convention, limits=limits, T_base=random_transform(rng),
                         T_tool=random_transform(rng))


# ------------------------------------------------------------------- distances
def joint_distance(chain, q_a, q_b, joints=slice(None)):
    """Largest joint difference (revolute ones modulo 2 pi) over ``joints``."""
    d = (q_a - q_b)[..., joints]
    rev = ~chain.prismatic[joints]
    d[..., rev] = (d[..., rev] + np.pi) % (2 * np.pi) - np.pi
    return np.abs(d).max(axis=-1)


# ---------------------------------------------------------- EAIK cross-check
def _eaik_exact_solutions(chain, T):
    """EAIK's solutions (robot from our axes at q = 0) that reproduce ``T`` by our FK.

    None if EAIK has no decomposition for the arm (it does not cover every Pieper arm).
    """
    eaik_hp = pytest.importorskip("eaik.IK_HP")  # test-only dependency
    poe = poe_from_chain(chain)
    P = np.vstack([poe.points[0], np.diff(poe.points, axis=0), poe.M[:3, 3] - poe.points[-1]])
    robot = eaik_hp.HPRobot(poe.axes, P)
    if not robot.hasKnownDecomposition():  # e.g. axes 1-3 parallel: EAIK has no solver
        return None
    result = []
    to_base = invert_transform(poe.T_base)  # EAIK's robot stands at the origin
    for pose in T:
        target = to_base @ pose
        target[:3, :3] = target[:3, :3] @ poe.M[:3, :3].T  # EAIK's tool has no rotation
        Q = np.array(robot.IK(target).Q).reshape(-1, chain.n)
        Q = Q[np.abs(fk(chain, Q) - pose).max(axis=(-1, -2)) < 1e-6] if len(Q) else Q
        # Near a double root EAIK may answer with a least-squares point between two exact
        # solutions (seen: residual 9e-7, 0.008 rad from both): Newton steps take each answer
        # to the exact solution it stands for, so such a point merges with its neighbour.
        Q = np.array([_newton_refined(chain, pose, q) for q in Q]).reshape(-1, chain.n)
        # An answer Newton cannot take to the pose is no exact solution (seen: residual 3.9e-7
        # at a configuration with a zero singular value, where a 2R is just out of reach; the
        # same bar, 1e-9, as every solution of ours).
        Q = Q[np.abs(fk(chain, Q) - pose).max(axis=(-1, -2)) < 1e-9] if len(Q) else Q
        unique = [i for i in range(len(Q))
                  if not (joint_distance(chain, Q[:i], Q[i]) < 1e-4).any()]
        result.append(Q[unique])
    return result


def _newton_refined(chain, T, q):
    """``q`` moved onto the exact solution next to it (at most 1e-3 rad or m away), else ``q``."""
    result = numeric_ik(chain, T, q0=q, within_limits=False, max_restarts=0, max_iterations=20,
                        position_tolerance=1e-12, orientation_tolerance=1e-12)
    return result.q if result.success and np.abs(result.q - q).max() < 1e-3 else q


def newton_root(chain, T, q, steps=10):
    """The solution of ``T`` that plain Gauss-Newton steps from ``q`` converge to, or ``q`` as it
    was if, after ``steps`` of them, FK does not reproduce ``T`` to 1e-13 (times the arm's size).

    A numeric search's stopping test (a residual under 1e-10, say) passes points as far as
    residual / sigma_min from every solution: beside a near-double root, where the Jacobian's
    smallest singular value was 8e-8, a point 2e-3 rad from the nearest solution, and no solution
    itself (checked in 50-digit arithmetic: Newton takes it onto that neighbour). Undamped steps
    take such a point onto the solution it stands for (four steps seen); a point they do not take
    onto ``T``, or take farther than ten times that bound (onto another solution), is kept as
    found, so a search's solution is never dropped.
    """
    x = np.array(q, dtype=float)
    residual = np.linalg.norm(pose_error(T, fk(chain, x)))
    reach = 10 * residual / max(np.linalg.svd(geometric_jacobian(chain, x), compute_uv=False)[-1], 1e-300)
    for _ in range(steps):
        x = x + np.linalg.lstsq(geometric_jacobian(chain, x), pose_error(T, fk(chain, x)), rcond=None)[0]
    size = 1 + np.abs(fk(chain, np.zeros(chain.n))[:3, 3]).max()
    if not (np.abs(fk(chain, x) - T).max() <= 1e-13 * size and joint_distance(chain, x, q) <= reach):
        return q
    return np.where(chain.prismatic, x, np.angle(np.exp(1j * x)))


def _polished(chain, T, q, steps=12):
    """``q`` after Gauss-Newton steps towards ``T`` (each halved until it lowers the FK
    residual: near a fold the full step overshoots), with that residual: an exact
    solution's to rounding."""
    best, worst = q, np.abs(fk(chain, q) - T).max()
    for _ in range(steps):
        step = np.linalg.lstsq(geometric_jacobian(chain, best), pose_error(T, fk(chain, best)), rcond=None)[0]
        for _ in range(30):
            residual = np.abs(fk(chain, best + step) - T).max()
            if residual < worst:
                break
            step = step / 2
        else:
            break
        best, worst = best + step, residual
    return best, worst


def _two_roots(chain, T, a, b):
    """Whether ``a`` and ``b`` (close) are two distinct solutions of ``T``, not one listed
    twice: polished, each reproduces ``T`` to 1e-12 (times the arm's size), and the point
    between them misses it by more than ten times their residuals (a barrier: near a fold
    1e-13 to 1e-10 between twin roots of a pose just inside it)."""
    (a, at_a), (b, at_b) = _polished(chain, T, a), _polished(chain, T, b)
    step = np.where(chain.prismatic, b - a, (b - a + np.pi) % (2 * np.pi) - np.pi)
    worst = max(at_a, at_b)
    between = np.abs(fk(chain, a + step / 2) - T).max()
    size = 1 + np.abs(fk(chain, np.zeros(chain.n))[:3, 3]).max()
    return worst <= 1e-12 * size and between > 10 * max(worst, 1e-16)


def assert_same_as_eaik(chain, q):
    T = fk(chain, q)
    sol = closed_form_ik(chain, T)
    eaik_solutions = _eaik_exact_solutions(chain, T)
    if eaik_solutions is None:
        return
    missed_by_eaik = 0
    for i, theirs in enumerate(eaik_solutions):
        ours = sol.q[i][sol.valid[i]]
        assert len(ours), f"pose {i}: no solution found"
        assert np.abs(fk(chain, ours) - T[i]).max() < 1e-9
        generating = (joint_distance(chain, ours, q[i]) < 1e-4).any() or sol.family[i][sol.valid[i]].any()
        assert generating, f"pose {i}: the configuration that made the pose is not among the solutions"
        # EAIK's answers are refined exact solutions, so branches are matched to 1e-4 rad
        distance = joint_distance(chain, ours[:, None], theirs[None])
        assert (distance.min(axis=0, initial=np.inf) < 1e-4).all(), f"pose {i}: EAIK found one we miss"
        # EAIK rarely misses solutions itself (seen: a well-conditioned pose of a random
        # three-parallel arm where none of its answers reproduced the pose to 1e-6). Where it
        # found the configuration that made the pose, it must find every one of ours too.
        if (joint_distance(chain, theirs, q[i]) < 1e-4).any():
            assert (distance.min(axis=1) < 1e-4).all()
            if len(ours) != len(theirs):
                # near a fold (smallest singular value ~1e-7 to 1e-6, seen at uniform random
                # poses) two distinct exact solutions lie ~1e-5 apart, and EAIK gives one of
                # them: each extra one of ours must be such a twin of an earlier one
                apart = joint_distance(chain, ours[:, None], ours[None])
                extra = np.array([(apart[k, :k] < 1e-4).any() for k in range(len(ours))])
                assert len(ours) > len(theirs) and len(ours) - extra.sum() == len(theirs), \
                    f"pose {i}: {len(ours)} solutions, EAIK {len(theirs)}"
                for k in np.flatnonzero(extra):
                    twin = ours[np.flatnonzero(apart[k, :k] < 1e-4)[0]]
                    assert _two_roots(chain, T[i], ours[k], twin), f"pose {i}: a solution listed twice"
        else:
            missed_by_eaik += 1
    assert missed_by_eaik <= 1, f"EAIK missed the generating q of {missed_by_eaik} of {len(T)} poses"


# ------------------------------------------------------------------- toppra
@cache
def _toppra_path_type():
    """The class below, made on first use: toppra (a test-only dependency) takes 2 s to import."""
    import toppra

    class ToppraPath(toppra.interpolator.AbstractGeometricPath):
        """armkit's geometric path (a JointTrajectory in its own time s) as toppra sees a path."""

        def __init__(self, path):
            self.path = path

        def __call__(self, s, order=0):
            s = np.asarray(s, dtype=float)
            values = self.path.at_time(np.atleast_1d(s))[order]
            return values if s.ndim else values[0]

        @property
        def dof(self):
            return self.path.n

        @property
        def path_interval(self):
            return np.array([0.0, self.path.duration])

        @property
        def waypoints(self):
            return self.path.waypoint_times, self.path.waypoints

    return ToppraPath


def toppra_path(path):
    """``path`` (armkit's geometric path) as a toppra geometric path."""
    return _toppra_path_type()(path)


# ---------------------------------------------------------- shared data
# Report 000: IK solutions of the four Cartesian waypoints (SEED_ROBOTS.md, section 1).
SEED_WAYPOINTS = np.array([
    [0, 0, 0, 0, 0, 0],
    [0.795586, -0.772686, 0.205056, 1.08734, 2.51046, -0.842853],
    [0.387677, -1.07517, -0.199884, 0.404374, 2.86768, -0.114923],
    [-0.387371, -1.29256, -0.0658126, -0.394643, 2.94426, 0.0811483],
])
SEED_VMAX = np.array([0.7854, 0.6981, 0.7854, 0.9599, 0.9599, 0.9599])
SEED_AMAX = np.array([0.3491, 0.2618, 0.3491, 0.4363, 0.4363, 0.4363])

#: A PROBOT Anno motion out and back, for the torque-limited timing tests.
WAYPOINTS = np.array([[0, 0, 0, 0, 0, 0], [0.8, -0.6, 0.5, 0.3, 0.6, 0.2], [-0.5, 0.3, -0.4, -0.3, 0.2, 1.0],
                      [0, 0, 0, 0, 0, 0]])


def limited(max_torque) -> armkit.Robot:
    """The PROBOT Anno with estimated inertia (aluminium), its own velocity and acceleration
    limits, and ``max_torque`` [N m]."""
    base = armkit.load("probot-anno").with_estimated_inertia(density=2700.0)
    chain = base.chain
    joints = tuple(replace(j, max_torque=float(L)) for j, L in zip(chain.joints, max_torque, strict=True))
    return armkit.Robot(Chain(joints, chain.T_base, chain.T_tool), name="probot-anno, torque-limited")


#: Tight enough that joints 1-3 would pass their limits at the velocity/acceleration-optimal timing.
TIGHT = np.array([0.05, 6.0, 2.8, 0.15, 0.2, 0.003])


def example_robot_data_folder() -> Path:
    """Where example-robot-data installs its robots (data files, no Python module);
    :class:`importlib.metadata.PackageNotFoundError` if it is not installed."""
    installed = distribution("example-robot-data")
    return Path(installed.locate_file("cmeel.prefix/share/example-robot-data/robots"))


# Serial arms: (file, base, tip, closed form the geometry has). The UR files end in three leaves
# (base, ee_link, tool0), so they need a tip; 6R arms with a spherical wrist or three parallel
# axes must be found as such.
ARMS = [
    ("ur_description/urdf/ur3_robot.urdf", None, "tool0", "three-parallel"),
    ("ur_description/urdf/ur5_robot.urdf", None, "tool0", "three-parallel"),
    ("ur_description/urdf/ur10_robot.urdf", None, "tool0", "three-parallel"),
    ("ur_description/urdf/ur5_joint_limited_robot.urdf", None, "tool0", "three-parallel"),
    ("ur_description/urdf/ur3_gripper.urdf", None, "tool0", "three-parallel"),
    ("panda_description/urdf/panda.urdf", None, "panda_hand_tcp", "none"),
    ("kinova_description/robots/kinova.urdf", None, "j2s6s200_end_effector", "spherical-wrist"),
    ("xarm_description/urdf/xarm7.urdf", None, None, "none"),
    ("z1_description/urdf/z1.urdf", None, "link06", "three-parallel"),
    ("so_arm_description/urdf/so100.urdf", None, None, "three-parallel"),
    ("so_arm_description/urdf/so101.urdf", None, "gripper_frame_link", "none"),
    ("talos_data/robots/talos_left_arm.urdf", None, "gripper_left_base_link", "spherical-wrist"),
    ("baxter_description/urdf/baxter.urdf", None, "right_gripper", "none"),
    ("baxter_description/urdf/baxter.urdf", None, "left_gripper", "none"),
    ("pr2_description/urdf/pr2.urdf", "torso_lift_link", "r_gripper_palm_link", "none"),
    ("tiago_description/robots/tiago_no_hand.urdf", None, "arm_tool_link", "none"),
]
