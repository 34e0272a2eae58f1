"""Collision-free motion: a path around a scene's obstacles, shortened, smoothed, timed and checked.

The pipeline of :func:`plan_path`
---------------------------------
1. **Goal set**: a goal configuration, or every collision-free IK solution of a goal pose
   (closed form where the arm has one, else numeric IK from several seeds).
2. **Path**: OMPL's RRT-Connect in joint space (a ``RealVectorStateSpace`` bounded by the joint
   limits), its states checked with ``scene.collides`` and every straight joint segment between
   them with ``scene.path_collides`` (no point of the arm moves more than ``resolution`` metres
   between two checks); a second search, stopped after a count of checks, may find a shorter way
   round, and the shorter of the two shortened paths is kept. A joint without position limits is
   bounded to half a turn beyond the span of its start and goal values (:data:`UNBOUNDED_MARGIN`):
   any angle is reachable within half a turn, so the bound removes no motion a whole-turn copy
   would not also give.
3. **Shortening**: OMPL's path simplifier (vertex reduction, partial shortcuts, collapsing close
   vertices) with a fixed number of steps, every shortcut checked as in 2.
4. **Timing**: :func:`~armkit.trajectory.plan_trajectory` through the shortened path's vertices:
   the minimum-jerk spline through them, timed time-optimally within the velocity, acceleration
   and (where the robot has them) torque limits.
5. **Check**: the spline cuts corners, so the timed trajectory is checked again
   (:func:`collision_time`). Where it collides or leaves a position limit, via-points are added
   to the segments there (midpoints, which pull the spline onto the checked straight path) and
   it is timed again; after :data:`VIA_POINT_ROUNDS` rounds the motion stops at every vertex
   instead (straight segments, each timed at rest at both ends). A motion that fails even that
   check is never returned: :class:`~armkit.errors.PlanningError` says which segment failed.

The same call gives the same answer: OMPL's random generator is seeded from ``seed``, the
simplifier runs a fixed number of steps, and only the search has a time budget (when it runs
out the call fails rather than returning something else).
"""

from __future__ import annotations

import threading
import time
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit._params import positive_float, whole_number
from armkit.errors import (
    ArmkitError,
    CollisionError,
    ConvergenceError,
    InputError,
    JointLimitError,
    NoClosedFormError,
    PlanningError,
    UnreachableError,
    pair_text,
)
from armkit.trajectory.joint_trajectory import JointTrajectory
from armkit.trajectory.plan import plan_trajectory, planning_limits

if TYPE_CHECKING:
    from armkit.collision.scene import Scene
    from armkit.robot import Robot

__all__ = ["DEFAULT_RESOLUTION", "DEFAULT_TIME_BUDGET", "MAX_RESOLUTION", "MIN_RESOLUTION",
           "UNBOUNDED_MARGIN", "VIA_POINT_ROUNDS", "collision_time", "goal_configurations", "plan_path"]

#: Largest displacement [m] of any point of the arm between two collision checks (default), and the
#: finest accepted (0.1 mm: a metre of motion is then 10,000 checks; finer asks for endless checking).
DEFAULT_RESOLUTION = 0.005
MIN_RESOLUTION = 1e-4
#: The coarsest accepted [m]: between two checks a link may step over an obstacle thinner than the
#: resolution (a 10 m "resolution" checked a UR5's motion at its two ends only and went through a wall).
MAX_RESOLUTION = 0.02
#: Seconds the search may take before :func:`plan_path` gives up (default).
DEFAULT_TIME_BUDGET = 10.0
#: Beyond the span of start and goal, the room [rad] a joint without position limits gets.
UNBOUNDED_MARGIN = np.pi
#: Rounds of added via-points before the motion stops at every vertex instead.
VIA_POINT_ROUNDS = 4
#: Rounds of the simplifier (each: vertex reduction, partial shortcuts, collapse); fewer if one gains nothing.
SIMPLIFY_ROUNDS = 5
#: RRT-Connect's longest step [rad or m of joint-space distance]: OMPL's default, a fifth of the space's
#: extent, is 6 rad for a UR5 (+-360 deg joints), whose long straight motions cost many checks and mostly
#: collide; with 1 rad the UR5 wall plans checked about 40 % fewer configurations (benchmarks/bench_plan.py).
RANGE = 1.0
#: Searches whose shortened paths compete (the shortest is kept), and the motion checks each search after
#: the first may make, as a multiple of the first's.
ATTEMPTS = 2
ATTEMPT_CHECKS = 2
#: Shortcut attempts of each simplifier step per round (a quarter of them in a row without gain ends it).
SIMPLIFY_STEPS = 100
#: Numeric IK seeds for a goal pose of an arm without a closed form: the start, home, and these many random.
IK_SEEDS = 16
#: Joint distance [rad or m] below which two configurations (IK solutions, start and goal) are the same.
_SAME_SOLUTION = 1e-6
#: Distance [rad or m] from its straight segment within which a stopping motion counts as on it (rounding).
_ON_PATH = 1e-9
#: Samples per polynomial piece of the on-the-chord test (more than its degree, 5, plus one).
_SAMPLES_PER_PIECE = 8

# OMPL draws every seed from one process-wide generator: one plan at a time, so that a seed
# gives the same answer whatever else runs.
_OMPL_LOCK = threading.Lock()


def plan_path(scene: Scene, q_start: ArrayLike, goal: ArrayLike, *, time_budget: float = DEFAULT_TIME_BUDGET,
              seed: int = 0, resolution: float = DEFAULT_RESOLUTION, max_velocity: ArrayLike | None = None,
              max_acceleration: ArrayLike | None = None,
              torque_limits: bool | None = None) -> JointTrajectory:
    """A timed, collision-free motion of ``scene.robot`` from ``q_start`` to ``goal``.

    Parameters
    ----------
    scene : Scene
        The robot and its obstacles (:class:`armkit.Scene`).
    q_start : (n,) array
        Start configuration [rad or m], inside the limits and free of collisions.
    goal : (n,) or (4, 4) array
        Goal configuration [rad or m], or a tool pose ``T_base_tool`` [m]: then any
        collision-free IK solution of it (:func:`goal_configurations`).
    time_budget : float
        Seconds the first search may take [s]; default :data:`DEFAULT_TIME_BUDGET` (the second
        search is bounded by a count of checks, the rest takes what it takes).
    seed : int
        Seed of the search and the simplifier (0 or more): the same call gives the same motion.
    resolution : float
        Largest displacement [m] of any point of the arm between two collision checks along a
        motion; default :data:`DEFAULT_RESOLUTION` (5 mm), from :data:`MIN_RESOLUTION` (0.1 mm) to
        :data:`MAX_RESOLUTION` (2 cm): an obstacle thinner than it can be stepped over unseen.
    max_velocity, max_acceleration : float or (n,) array, optional
        Limits in place of the robot's (:func:`~armkit.trajectory.planning_limits`).
    torque_limits : bool, optional
        Keep the joint torques within ``robot.max_torque`` (default: where the robot has them;
        :func:`~armkit.trajectory.plan_trajectory`).

    Returns
    -------
    JointTrajectory
        At rest at both ends, through the vertices of the shortened path (``waypoints``);
        collision-free by :func:`collision_time` at ``resolution``, within the position,
        velocity, acceleration (and torque) limits.

    Raises
    ------
    InputError
        Bad arguments, or ``q_start`` already at the goal.
    JointLimitError
        ``q_start`` or a goal configuration outside the joint limits.
    UnreachableError
        A goal pose out of reach.
    CollisionError
        ``q_start``, the goal configuration or every IK solution of the goal pose collides; the
        message names the pairs in contact (``link3-wall``), the attributes hold ``q`` and ``contacts``.
    PlanningError
        No path was found within ``time_budget``, or no timed motion passed the check.

    Examples
    --------
    A UR5 past a wall (examples/data/ur5_wall.toml): the straight joint motion would hit it.

    >>> import armkit
    >>> robot = armkit.load("ur5")
    >>> scene = armkit.load_scene("examples/data/ur5_wall.toml", robot)
    >>> start, goal = [0, -1.2, 1.2, 0, 1.57, 0], [1.57, -1.2, 1.2, 0, 1.57, 0]
    >>> scene.path_collides(start, goal)
    True
    >>> traj = plan_path(scene, start, goal)
    >>> traj.waypoints[[0, -1]].tolist() == [start, goal], collision_time(scene, traj) is None
    (True, True)
    """
    robot = scene.robot
    budget = positive_float(time_budget, "time_budget")
    seed = whole_number(seed, "seed", minimum=0, maximum=2**31 - 2)
    resolution = positive_float(resolution, "resolution")
    if resolution < MIN_RESOLUTION:
        raise InputError(f"resolution: {resolution:g} m is finer than the {MIN_RESOLUTION:g} m plan_path "
                         f"checks at (each metre of arm motion costs 1/resolution collision checks)")
    if resolution > MAX_RESOLUTION:
        raise InputError(f"resolution: {resolution:g} m is coarser than the {MAX_RESOLUTION:g} m plan_path "
                         f"checks at (a link could step over an obstacle thinner than that between checks)")
    vmax, amax = planning_limits(robot, max_velocity, max_acceleration)
    q_start = _free_configuration(scene, robot.check_q(q_start, "q_start"), "q_start")
    goals = goal_configurations(scene, goal, near=q_start, seed=seed)
    if np.any(np.max(np.abs(goals - q_start), axis=1) <= _SAME_SOLUTION):
        raise InputError(f"goal: q_start {_show(q_start)} is already there; there is no motion to plan")
    path = _search(scene, q_start, goals, time_budget=budget, seed=seed, resolution=resolution)
    return _timed(scene, path, resolution, vmax, amax, torque_limits)


def goal_configurations(scene: Scene, goal: ArrayLike, *, near: ArrayLike | None = None,
                        seed: int = 0) -> NDArray[np.float64]:
    """The collision-free configurations ``(k, n)`` a motion to ``goal`` may end at.

    Parameters
    ----------
    scene : Scene
    goal : (n,) or (4, 4) array
        A configuration [rad or m] (then just it, checked), or a tool pose [m]: its IK solutions
        inside the limits, every closed-form one (nearest ``near`` first), or for an arm without
        a closed form numeric ones from ``near``, home and :data:`IK_SEEDS` random seeds.
    near : (n,) array, optional
        Reference configuration; default the robot's home.
    seed : int
        Seed of the random numeric-IK seeds.

    Raises
    ------
    CollisionError
        The goal configuration, or every IK solution of the pose, collides (naming the pairs).
    UnreachableError, JointLimitError
        The pose is out of reach, or reachable only outside the limits.
    """
    robot = scene.robot
    near = robot.home if near is None else robot.check_q(near, "near")
    try:
        goal = np.asarray(goal, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InputError(f"goal: expected {robot.n} joint values or a 4x4 tool pose, got {goal!r}") from exc
    if goal.shape != (4, 4):
        return _free_configuration(scene, robot.check_q(goal, "goal"), "goal")[None]
    candidates = _ik_candidates(robot, goal, near, seed)
    free = ~np.asarray(scene.collides(candidates), dtype=bool)
    if not free.any():
        listing = "; ".join(f"{_show(q)}: {pair_text(scene.contacts(q), 'in contact')}" for q in candidates)
        raise CollisionError(f"goal pose: every IK solution collides ({len(candidates)}: {listing})",
                             q=candidates, contacts=scene.contacts(candidates[0]))
    return candidates[free]


def collision_time(scene: Scene, trajectory: JointTrajectory,
                   resolution: float = DEFAULT_RESOLUTION) -> float | None:
    """The first time [s] at which ``trajectory`` collides in ``scene``, or ``None`` if it never does.

    Checked with ``scene.collides`` at times ``dt`` apart, so that no point of the arm moves more
    than ``resolution`` between two checks along the trajectory itself (not its chords): a point
    moves at most ``sum_j R_j |qd_j| dt`` in ``dt``, with ``R_j`` the reach beyond joint ``j`` of
    ``scene.displacement_bound`` and ``|qd_j|`` the exact peak speed of the joint.

    Examples
    --------
    >>> import armkit
    >>> robot = armkit.load("ur5")
    >>> scene = armkit.load_scene("examples/data/ur5_wall.toml", robot)
    >>> straight = plan_trajectory(robot, [[0, -1.2, 1.2, 0, 1.57, 0], [1.57, -1.2, 1.2, 0, 1.57, 0]])
    >>> t = collision_time(scene, straight)
    >>> round(t, 3), scene.contacts(straight.at_time(t)[0])
    (0.366, [('link5', 'wall'), ('link6', 'wall')])
    """
    resolution = positive_float(resolution, "resolution")
    low, high = trajectory.position_range
    farthest = np.where(np.abs(low) > np.abs(high), low, high)    # the prismatic travels' largest
    reach = np.array([scene.displacement_bound(farthest, farthest + step) for step in np.eye(trajectory.n)])
    speed = float(reach @ trajectory.peak_velocity)               # [m/s], at most, of any point
    count = max(int(np.ceil(speed * trajectory.duration / resolution)), 1)
    t = np.linspace(0.0, trajectory.duration, count + 1)
    q, _, _ = trajectory.at_time(t)
    hits = np.flatnonzero(scene.collides(q))
    return float(t[hits[0]]) if hits.size else None


# ----------------------------------------------------------------- goals
def _free_configuration(scene: Scene, q: NDArray[np.float64], name: str) -> NDArray[np.float64]:
    """``q`` ``(n,)`` checked: inside the joint limits and free of collisions."""
    robot = scene.robot
    if q.ndim != 1:
        raise InputError(f"{name}: expected one configuration ({robot.n} values), got shape {q.shape}")
    robot.check_limits(q)
    if scene.collides(q):
        contacts = scene.contacts(q)
        raise CollisionError(f"{name} {_show(q)} collides: {pair_text(contacts, 'in contact')}", q=q,
                             contacts=contacts)
    return q


def _ik_candidates(robot: Robot, T: NDArray[np.float64], near: NDArray[np.float64],
                   seed: int) -> NDArray[np.float64]:
    """Every IK solution of ``T`` inside the limits (closed form), or those numeric IK finds from
    several seeds; ``(k, n)``, nearest ``near`` first."""
    try:
        return np.atleast_2d(robot.ik(T, all_solutions=True, near=near))
    except NoClosedFormError:
        pass
    seeds = np.vstack([near, robot.home, robot.random_q(IK_SEEDS, rng=seed)])
    found: list[NDArray[np.float64]] = []
    error: ArmkitError | None = None
    for q0 in seeds:
        try:
            q = robot.ik(T, near=q0)
        except (UnreachableError, JointLimitError, ConvergenceError) as exc:
            error = exc
            continue
        if all(np.max(np.abs(q - other)) > _SAME_SOLUTION for other in found):
            found.append(q)
    if not found:
        raise error
    found.sort(key=lambda q: float(np.linalg.norm(q - near)))
    return np.array(found)


# ----------------------------------------------------------------- search
def _bounds(robot: Robot, q_start: NDArray[np.float64],
            goals: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Lower and upper bounds ``(n,)`` of the search: the joint limits; for a revolute joint without
    them, :data:`UNBOUNDED_MARGIN` beyond the span of start and goals."""
    lower, upper = robot.limits.T.copy()
    ends = np.vstack([q_start, goals])
    unbounded = ~np.isfinite(lower) | ~np.isfinite(upper)
    prismatic = np.asarray(robot.chain.prismatic) & unbounded
    if prismatic.any():
        name = robot.joint_names[int(np.argmax(prismatic))]
        raise InputError(f"joint {name}: prismatic without position limits; a planner searches within "
                         f"bounds: give it limits in the robot file")
    lower = np.where(np.isfinite(lower), lower, ends.min(axis=0) - UNBOUNDED_MARGIN)
    upper = np.where(np.isfinite(upper), upper, ends.max(axis=0) + UNBOUNDED_MARGIN)
    return lower, upper


def _search(scene: Scene, q_start: NDArray[np.float64], goals: NDArray[np.float64], *, time_budget: float,
            seed: int, resolution: float) -> NDArray[np.float64]:
    """RRT-Connect from ``q_start`` to any of ``goals``, shortened: the path's vertices ``(m, n)``.

    The first search has ``time_budget``; :data:`ATTEMPTS` - 1 more searches (each stopped after
    :data:`ATTEMPT_CHECKS` times the first one's motion checks: a count, so the answer does not
    depend on the machine's speed) may find paths in other ways around the obstacles; of the
    shortened paths the shortest in joint space is kept.
    """
    try:
        from ompl import base as ob
        from ompl import geometric as og
        from ompl import util as ou
    except ImportError as exc:
        raise ArmkitError("planning needs OMPL: pip install 'armkit[plan]' (or pip install ompl)") from exc
    robot = scene.robot
    n = robot.n
    lower, upper = _bounds(robot, q_start, goals)
    checks = [0]                              # motion checks so far

    def values(state) -> NDArray[np.float64]:
        return np.array([state[j] for j in range(n)])

    class SceneMotionValidator(ob.MotionValidator):
        """A straight joint segment is valid if ``scene.path_collides`` finds no contact along it."""

        def checkMotion(self, a, b) -> bool:  # noqa: N802  (OMPL's name)
            checks[0] += 1
            return not scene.path_collides(values(a), values(b), resolution=resolution)

    with _OMPL_LOCK:
        level = ou.getLogLevel()
        ou.setLogLevel(ou.LOG_NONE)   # OMPL's messages: its outcome becomes armkit's errors instead
        try:
            ou.RNG.setSeed(seed + 1)  # OMPL takes a seed of 0 as "from the clock"
            space = ob.RealVectorStateSpace(n)
            bounds = ob.RealVectorBounds(n)
            for j in range(n):
                bounds.setLow(j, float(lower[j]))
                bounds.setHigh(j, float(upper[j]))
            space.setBounds(bounds)
            si = ob.SpaceInformation(space)
            si.setStateValidityChecker(lambda state: not scene.collides(values(state)))
            si.setMotionValidator(SceneMotionValidator(si))
            si.setup()
            goal_states = ob.GoalStates(si)
            for q in goals:
                goal_states.addState(_state(si, q))
            simplifier = og.PathSimplifier(si, goal_states)
            paths = []
            for attempt in range(ATTEMPTS):
                problem = ob.ProblemDefinition(si)
                problem.addStartState(_state(si, q_start))
                problem.setGoal(goal_states)
                planner = og.RRTConnect(si)
                planner.setRange(RANGE)
                planner.setProblemDefinition(problem)
                planner.setup()
                before = checks[0]
                if attempt == 0:
                    started = time.monotonic()
                    planner.solve(float(time_budget))
                    first = max(checks[0], 1)
                else:
                    planner.solve(ob.PlannerTerminationCondition(
                        lambda before=before, first=first: checks[0] - before > ATTEMPT_CHECKS * first))
                if not problem.hasExactSolution():
                    if attempt == 0:
                        break
                    continue
                path = problem.getSolutionPath()
                for _ in range(SIMPLIFY_ROUNDS):
                    changed = [simplifier.reduceVertices(path, SIMPLIFY_STEPS, SIMPLIFY_STEPS // 4),
                               simplifier.partialShortcutPath(path, SIMPLIFY_STEPS, SIMPLIFY_STEPS // 4),
                               simplifier.collapseCloseVertices(path, SIMPLIFY_STEPS, SIMPLIFY_STEPS // 4)]
                    if not any(changed):
                        break
                paths.append(np.array([values(state) for state in path.getStates()]))
        finally:
            ou.setLogLevel(level)
    if not paths:
        raise PlanningError(f"no collision-free path found within time_budget={time_budget:g} s "
                            f"(RRT-Connect, {time.monotonic() - started:.3g} s): give a larger time_budget, "
                            f"or move the start or goal away from the obstacles", time_budget=time_budget)
    vertices = min(paths, key=lambda v: float(np.linalg.norm(np.diff(v, axis=0), axis=1).sum()))
    return vertices[np.concatenate([[True], np.any(np.diff(vertices, axis=0) != 0, axis=1)])]  # no repeats


def _state(si, q: NDArray[np.float64]):
    """An OMPL state of ``si`` holding ``q``."""
    state = si.allocState()
    for j, value in enumerate(q):
        state[j] = float(value)
    return state


# ----------------------------------------------------------------- timing
def _timed(scene: Scene, path: NDArray[np.float64], resolution: float, vmax: NDArray[np.float64],
           amax: NDArray[np.float64], torque_limits: bool | None) -> JointTrajectory:
    """The shortened path timed and checked: smooth through its vertices (with via-points where the
    spline collides), else stopping at every vertex; never an unchecked motion."""
    robot = scene.robot
    limits = {"max_velocity": vmax, "max_acceleration": amax, "torque_limits": torque_limits}
    via = path
    for _ in range(VIA_POINT_ROUNDS):
        try:
            trajectory = plan_trajectory(robot, via, **limits)
        except JointLimitError:               # the spline overshoots a position limit: pull it in everywhere
            via = _with_via_points(via, np.arange(len(via) - 1))
            continue
        hit = collision_time(scene, trajectory, resolution)
        if hit is None:
            return trajectory
        k = int(np.clip(np.searchsorted(trajectory.waypoint_times, hit, side="right") - 1, 0, len(via) - 2))
        via = _with_via_points(via, np.arange(max(k - 1, 0), min(k + 2, len(via) - 1)))
    trajectory = _concatenated([plan_trajectory(robot, path[k:k + 2], **limits)
                                for k in range(len(path) - 1)])
    # Straight segments, each at rest at both ends: the motion is the path the search checked, segment by
    # segment with scene.path_collides at the same resolution; it is checked again here in that way.
    for k in range(len(path) - 1):
        if not _on_segment(trajectory, k) or scene.path_collides(path[k], path[k + 1], resolution=resolution):
            raise PlanningError(f"the timed motion leaves its checked path on segment {k + 1} (to q = "
                                f"{_show(path[k + 1])}); try another seed or a finer resolution",
                                segment=k + 1)
    return trajectory


def _on_segment(trajectory: JointTrajectory, k: int) -> bool:
    """Whether segment ``k`` of ``trajectory`` runs along the straight line between its waypoints and
    no farther than them: sampled at :data:`_SAMPLES_PER_PIECE` points per polynomial piece (and at
    least 1 kHz), every sample within ``_ON_PATH`` of the chord and its progress along it in
    ``[0, 1]``. A piece is a polynomial of degree at most 5, so one that small at that many evenly
    spread points is small between them too (their Lebesgue constant is below 30); its
    coefficients cannot be compared instead: their rounding grows like ``L / T^5``."""
    a, b = trajectory.waypoints[k], trajectory.waypoints[k + 1]
    chord = b - a
    length = float(np.linalg.norm(chord))
    t0, t1 = trajectory.waypoint_times[k], trajectory.waypoint_times[k + 1]
    count = max(_SAMPLES_PER_PIECE * int(trajectory.segment_pieces[k]), int((t1 - t0) * 1000.0), 2)
    q, _, _ = trajectory.at_time(np.linspace(t0, t1, count))
    progress = (q - a) @ chord / length**2
    across = (q - a) - progress[:, None] * chord
    tol = _ON_PATH * max(1.0, length)
    return bool(np.abs(across).max() <= tol and progress.min() >= -tol and progress.max() <= 1 + tol)


def _with_via_points(via: NDArray[np.float64], segments: NDArray[np.int64]) -> NDArray[np.float64]:
    """``via`` with the midpoint of each of ``segments`` (indices of its straight segments) added."""
    midpoints = 0.5 * (via[segments] + via[segments + 1])
    return np.insert(via, segments + 1, midpoints, axis=0)


def _concatenated(parts: list[JointTrajectory]) -> JointTrajectory:
    """One trajectory running ``parts`` (each a single segment, at rest at both ends) one after another."""
    degree = max(part.coefficients.shape[0] for part in parts)
    coefficients = np.concatenate([np.pad(part.coefficients, ((0, degree - part.coefficients.shape[0]),
                                                              (0, 0), (0, 0))) for part in parts], axis=1)
    waypoints = np.vstack([parts[0].waypoints[:1], *(part.waypoints[1:] for part in parts)])
    return JointTrajectory(np.concatenate([part.piece_durations for part in parts]), coefficients, waypoints,
                           segment_pieces=np.concatenate([part.segment_pieces for part in parts]))


def _show(q: NDArray[np.float64]) -> str:
    return "[" + ", ".join(f"{v:.4g}" for v in np.asarray(q)) + "]"
