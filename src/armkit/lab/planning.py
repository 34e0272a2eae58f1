"""Lab experiment 7: a motion planned around an obstacle, run in MuJoCo and checked for collisions.

A box is put where the straight joint-space motion from the first waypoint of experiment 4 to a
goal (its last waypoint; else the first with joint 1 turned; else a random configuration with the
tool far from the start's) would carry the tool, so that the straight motion hits it;
:func:`armkit.plan_path`
(OMPL's RRT-Connect, shortened, timed within the joint limits) finds a motion around it; MuJoCo
runs the motion with gravity on; the simulated configurations are checked against the box, the
floor and the arm itself. No seed report planned a motion: the section is armkit's own check.
"""

from __future__ import annotations

import importlib.util

import numpy as np
from numpy.typing import NDArray

from armkit.errors import pair_text
from armkit.lab.context import FLOOR_HEIGHT, LabContext, fmt, fmt_q
from armkit.lab.motion import experiment_waypoints, not_applicable, save_figure, save_gif, tool_errors
from armkit.lab.report import Section, Table
from armkit.plots import plot_pva

__all__ = ["BOX_SIZES", "planned_motion"]

#: Edge lengths of the box tried, as fractions of the farthest the tool gets from the base along the
#: straight motion, largest first: the first whose box leaves start and goal free and blocks the motion.
BOX_SIZES = (0.3, 0.2, 0.12, 0.06)
#: Room [m] the planner keeps from the box: it plans around the box grown by this on every side (a
#: shortened path otherwise grazes the obstacle) and the simulated motion is checked against the box.
MARGIN = 0.01
#: Turns [rad] of the first joint that make the further goals tried (when the last waypoint gives no
#: blocked straight motion, e.g. waypoints close together), in this order.
BASE_TURNS = (np.pi / 2, -np.pi / 2, np.pi, -np.pi)
#: Joint limits [rad/s, rad/s² or m/s, m/s²] the motion is timed to where the robot gives none.
UNLIMITED_VELOCITY = 0.5
UNLIMITED_ACCELERATION = 1.0
#: Seed of the planner (the same report every run).
PLAN_SEED = 0
#: Random configurations the last goal tried is chosen from (the tool farthest from the start's).
_FAR_GOAL_DRAWS = 64
#: Configurations along the straight motion whose tool points place the box.
_STRAIGHT_SAMPLES = 64


def _goals(ctx: LabContext, q_start: NDArray, q_last: NDArray) -> list[tuple[NDArray, str]]:
    """The goals tried and what each is: the last waypoint, the start with the first joint turned
    by each of :data:`BASE_TURNS` (where its limits allow most of the turn), and of random
    collision-free configurations the one with the tool farthest from the start's."""
    robot = ctx.robot
    goals = [(q_last, "the last waypoint")]
    if not robot.chain.prismatic[0]:
        for turn in BASE_TURNS:
            goal = q_start.copy()
            goal[0] = np.clip(q_start[0] + turn, *robot.limits[0])
            if abs(goal[0] - q_start[0]) > 0.75 * abs(turn):
                goals.append((goal, f"the first waypoint with joint 1 turned by {np.degrees(turn):+.0f} deg"))
    # an arm whose tool is near axis 1 (a Panda at its ready pose) barely moves it by turning joint 1
    q = robot.random_q(_FAR_GOAL_DRAWS, rng=np.random.default_rng(PLAN_SEED))
    q = q[~ctx.scene.collides(q)]
    if len(q):
        far = np.linalg.norm(robot.fk(q)[:, :3, 3] - robot.fk(q_start)[:3, 3], axis=-1)
        goals.append((q[int(np.argmax(far))], "of 64 random configurations, the one with the tool farthest "
                                              "from the start's"))
    return goals


def _obstacle(ctx: LabContext, q_start: NDArray, q_goal: NDArray):  # -> tuple[Scene, Scene] | None
    """A box across the straight motion from ``q_start`` to ``q_goal``, centred on the tool point
    of that motion farthest from the tool at both ends: the scene with it (and the floor) and the
    scene with it grown by :data:`MARGIN`, the first size of :data:`BOX_SIZES` that blocks the
    motion and, grown, leaves both ends free."""
    from armkit.collision import Box, Scene

    robot = ctx.robot
    points = robot.fk(np.linspace(q_start, q_goal, _STRAIGHT_SAMPLES))[:, :3, 3]
    reach = float(np.max(np.linalg.norm(points - robot.chain.T_base[:3, 3], axis=-1)))
    away = np.minimum(np.linalg.norm(points - points[0], axis=-1),
                      np.linalg.norm(points - points[-1], axis=-1))
    pose = np.eye(4)
    pose[:3, 3] = points[int(np.argmax(away))]
    for fraction in BOX_SIZES:
        size = fraction * reach
        grown = Scene(robot, [Box([size + 2 * MARGIN] * 3, pose, name="box")], floor=FLOOR_HEIGHT)
        if grown.collides(np.array([q_start, q_goal])).any():
            continue
        scene = Scene(robot, [Box([size] * 3, pose, name="box")], floor=FLOOR_HEIGHT)
        if scene.path_collides(q_start, q_goal):
            return scene, grown
    return None


def _box_clearance(scene, q: NDArray) -> NDArray:
    """The arm's distance [m] from the box alone (``scene.clearance`` also measures the arm
    against itself and the floor)."""
    from itertools import combinations

    from armkit.collision import Scene

    box = scene.obstacles[0]
    arm = [part for part in scene.parts if part not in ("floor", box.name)]
    alone = Scene(scene.robot, [box], floor=None, disabled_pairs=list(combinations(arm, 2)), samples=0)
    return alone.clearance(q)


def planned_motion(ctx: LabContext) -> Section:
    """Experiment 7: a motion planned around an obstacle, run in MuJoCo, checked for collisions."""
    section = Section("plan", "7. A motion planned around an obstacle", (
        "A box is placed where the straight joint motion from the first waypoint of experiment 4 to a "
        "goal carries the tool: the last waypoint, else the first with joint 1 turned, else a random "
        "configuration with the tool far from the start's (the table says which). armkit.plan_path "
        "(OMPL's RRT-Connect, shortened, then timed within the joint limits) finds a motion around it, "
        f"keeping {MARGIN * 100:g} cm from it and checked every 5 mm of arm motion; MuJoCo runs it with "
        "gravity on, and every simulated configuration is checked against the box, the "
        "floor and the arm itself (docs/collision.md)."), own=True)
    if importlib.util.find_spec("ompl") is None:
        return not_applicable(section, "OMPL is not installed (pip install 'armkit[plan]')")
    from armkit.plan import plan_path

    robot = ctx.robot
    q, _, _, _ = experiment_waypoints(ctx)
    q_start = q[0]
    found = next(((goal, what, scenes) for goal, what in _goals(ctx, q_start, q[-1])
                  if (scenes := _obstacle(ctx, q_start, goal)) is not None), None)
    if found is None:
        return not_applicable(section, "no box across a straight motion from the first waypoint leaves its "
                                       "start and goal free")
    q_goal, goal_text, (scene, grown) = found
    box = scene.obstacles[0]
    straight = np.linspace(q_start, q_goal, 200)  # where it first hits the box itself
    first = int(np.argmax(scene.collides(straight)))
    vmax = np.where(np.isfinite(robot.max_velocity), robot.max_velocity, UNLIMITED_VELOCITY)
    amax = np.where(np.isfinite(robot.max_acceleration), robot.max_acceleration, UNLIMITED_ACCELERATION)
    if not (np.isfinite(robot.max_velocity).all() and np.isfinite(robot.max_acceleration).all()):
        section.notes.append(f"Where the robot gives no velocity or acceleration limit, the motion is timed "
                             f"to {UNLIMITED_VELOCITY:g} rad/s (m/s) and {UNLIMITED_ACCELERATION:g} rad/s² "
                             f"(m/s²).")
    trajectory = plan_path(grown, q_start, q_goal, seed=PLAN_SEED, max_velocity=vmax, max_acceleration=amax)
    samples = trajectory.sample(1000.0)
    ctx.record(samples.q)
    result = ctx.sim.run(samples.t, samples.q, samples.qd)
    hits = scene.collides(result.q)
    clearance = _box_clearance(scene, result.q)
    position_error, rotation_error = tool_errors(robot, result)
    size = box.size[0]
    section.tables.append(Table("The obstacle and the straight motion", ["", "value"], [
        ["box", f"{fmt(size, 3)} m cube centred at {fmt_q(box.pose[:3, 3], 4)} m"],
        ["start (waypoint 1)", fmt_q(q_start, 4)], ["goal", f"{fmt_q(q_goal, 4)} ({goal_text})"],
        ["straight joint motion", f"collides at {100 * first / (len(straight) - 1):.0f} % of the way: "
                                  f"{pair_text(scene.contacts(straight[first]))}"]]))
    rows = [[str(k + 1), f"{t:.3f}", fmt_q(v, 4)]
            for k, (t, v) in enumerate(zip(trajectory.waypoint_times, trajectory.waypoints, strict=True))]
    verdict = ("free of collisions" if not hits.any() else
               f"{int(hits.sum()):,} in collision, e.g. {pair_text(scene.contacts(result.q[hits][0]))}")
    section.tables.append(Table(
        "The planned motion: vertices of the shortened path and their times", ["vertex", "t [s]", "q"], rows,
        note=(f"{trajectory.duration:.2f} s through {len(rows)} vertices, timed within the velocity and "
              f"acceleration limits, planned {MARGIN * 1000:.0f} mm clear of the box. In MuJoCo: all "
              f"{len(result.q):,} simulated configurations (1 kHz) {verdict}; smallest distance from the box "
              f"{fmt(float(clearance.min()), 3)} m; tool within {position_error.max():.1e} m and "
              f"{rotation_error.max():.1e} rad of the commanded motion.")))
    if hits.any():
        section.status = "failed"
        section.headline = f"the simulated motion touches {pair_text(scene.contacts(result.q[hits][0]))}"
    else:
        section.headline = (f"around a {fmt(size, 3)} m box in {trajectory.duration:.2f} s; simulated "
                            f"distance from it {1000 * float(clearance.min()):.1f} mm or more")
    save_figure(ctx, plot_pva(trajectory, robot), "plan_pva.png",
                "The planned motion: position, velocity and acceleration of every joint (dots: the shortened "
                "path's vertices, dashed: limits).", section)
    save_gif(ctx, "plan.gif", result, "Planned around a box, in MuJoCo",
             "The planned motion in MuJoCo, the box outlined and the tool path traced.", section, scene=scene)
    return section
