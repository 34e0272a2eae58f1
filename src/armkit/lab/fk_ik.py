"""Lab experiments on poses: FK checked in MuJoCo, every IK solution driven in MuJoCo, FK tables.

Each function returns a :class:`~armkit.lab.report.Section`. Simulated poses come from
MuJoCo with gravity on and gravity compensation: the arm is servoed from its home
configuration to the configuration under test (minimum-jerk move, then a hold) and the
``tool`` site is read at the end, as the seed reports read Gazebo's link pose.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from armkit import animation
from armkit.errors import NoClosedFormError
from armkit.lab import published
from armkit.lab.context import LabContext, fmt, fmt_error, fmt_q
from armkit.lab.report import Section, Table
from armkit.robot import Robot
from armkit.sim.runner import Simulation
from armkit.sim.verify import compare_poses
from armkit.spatial.transforms import pose_from_transform, transform_from_pose

__all__ = ["fk_check", "fk_table_scara", "fk_table_zju", "ik_check"]

POSE_NAMES = ("x [m]", "y [m]", "z [m]", "roll [rad]", "pitch [rad]", "yaw [rad]")
MOVE_SECONDS, SETTLE_SECONDS = 2.0, 0.5


def _servo_poses(sim: Simulation, start: NDArray, q: NDArray, quick: bool) -> NDArray:
    """Tool poses after servoing from ``start`` to each row of ``q`` (gravity on): ``(m, 4, 4)``."""
    move = MOVE_SECONDS / 2 if quick else MOVE_SECONDS
    return np.array([sim.move(start, q_k, move, SETTLE_SECONDS).T_tool[-1] for q_k in q])


def fk_check(ctx: LabContext) -> Section:
    """Experiment 1: forward kinematics, computed by armkit and measured in MuJoCo."""
    robot = ctx.robot
    section = Section("fk", "1. Forward kinematics checked in simulation", (
        "armkit computes the tool pose of each configuration; MuJoCo then servos the exported "
        "model (gravity on, gravity compensation) from the home configuration to it and the tool "
        "site is read after a 0.5 s hold. Pose: x y z [m], roll pitch yaw = X-Y-Z fixed angles "
        "[rad], R = Rz(yaw) Ry(pitch) Rx(roll)."))
    if ctx.seeds:
        q = np.array([np.zeros(6), *[row[0] for row in published.PROBOT_FK]])
        reported = [(published.PROBOT_HOME_POSE, None), *[(row[1], row[2]) for row in published.PROBOT_FK]]
        section.published = "Gazebo - computed up to 3.4e-5 m"
    else:
        q = np.vstack([ctx.home, robot.random_q(4, rng=ctx.rng)])
        reported = [(None, None)] * len(q)
    computed = robot.fk(q)
    kinematic = ctx.sim.tool_pose(q)
    servo = _servo_poses(ctx.sim, ctx.home, q, ctx.quick)
    table = compare_poses(computed, servo)
    columns = ["configuration q [rad]", "", "report: computed", "report: Gazebo", "armkit FK",
               "MuJoCo (servo, gravity)", "armkit - report", "MuJoCo - armkit", "Gazebo - report"]
    rows, groups = [], set()
    for k in range(len(q)):
        groups.add(len(rows))
        for axis in range(6):
            report_c, report_g = reported[k]
            rows.append([fmt_q(q[k], 3) if axis == 0 else "", POSE_NAMES[axis],
                         "" if report_c is None else f"{report_c[axis]:g}",
                         "" if report_g is None else f"{report_g[axis]:g}",
                         fmt(table.computed[k, axis]), fmt(table.simulated[k, axis]),
                         "" if report_c is None else fmt_error(table.computed[k, axis] - report_c[axis]),
                         fmt_error(table.error[k, axis]),
                         "" if report_g is None else fmt_error(report_g[axis] - report_c[axis])])
    kin = compare_poses(computed, kinematic)
    stiff_only = Simulation(robot, gravity=True, gravity_compensation=False)
    sag = compare_poses(computed, _servo_poses(stiff_only, ctx.home, q, ctx.quick))
    title = ("Tool pose: published, computed by armkit, simulated in MuJoCo" if ctx.seeds
             else "Tool pose: computed by armkit, simulated in MuJoCo")
    section.tables.append(Table(title, columns, rows,
                                note=f"Largest MuJoCo - armkit distance {table.position_error.max():.1e} m, "
                                     f"rotation {table.orientation_error.max():.1e} rad (servoed, gravity "
                                     f"on). Kinematic check (qpos set, mj_kinematics): "
                                     f"{kin.position_error.max():.1e} m, "
                                     f"{kin.orientation_error.max():.1e} rad. "
                                     f"Without gravity compensation the stiff servos alone sag by up to "
                                     f"{sag.position_error.max():.1e} m, "
                                     f"{sag.orientation_error.max():.1e} rad."
                                     + (" The report prints 6 decimals and 1.5708 for pi/2." if ctx.seeds
                                        else ""),
                                groups=groups))
    section.headline = (f"max |MuJoCo - armkit| {table.position_error.max():.1e} m, "
                        f"{table.orientation_error.max():.1e} rad")
    picture = ctx.path("fk_configuration.png")
    animation.plot_configuration(robot, q[1], picture, dpi=80 if ctx.quick else 110,
                                 title=f"{robot.name}: base, DH link and tool frames")
    section.images.append((picture.name, f"q = {fmt_q(q[1], 3)} (second configuration of the table) with "
                                         f"every DH link frame (x red, y green, z blue) and the tool frame."))
    return section


def _nearest_published(solution: NDArray, listed: NDArray) -> tuple[int, float]:
    """Index of the listed solution closest to ``solution`` (angles compared modulo 2 pi), distance."""
    difference = np.abs((listed - solution + np.pi) % (2 * np.pi) - np.pi).max(axis=1)
    k = int(np.argmin(difference))
    return k, float(difference[k])


def _solutions(robot: Robot, T: NDArray, rng: np.random.Generator) -> tuple[NDArray, str]:
    try:
        method = "closed form, all solutions inside the limits"
        if robot.chain.spans_turns:  # each once: a UR5's 512 copies would say nothing more
            method += " (each once, not its whole-turn copies)"
        return np.atleast_2d(robot.ik(T, all_solutions=True, turn_copies=False)), method
    except NoClosedFormError:
        return np.atleast_2d(robot.ik(T, near=robot.random_q(rng=rng))), "numeric (no closed form)"


def _link_spread(robot: Robot, solutions: NDArray) -> float:
    """How different ``solutions`` look: the largest distance [m] of a link origin between two of them."""
    origins = robot.link_frames(solutions)[..., :3, 3]                       # (m, links, 3)
    return float(np.linalg.norm(origins[:, None] - origins[None], axis=-1).max())


def ik_check(ctx: LabContext) -> Section:
    """Experiment 2: every in-limit IK solution of each target, each driven in MuJoCo."""
    robot = ctx.robot
    section = Section("ik", "2. Inverse kinematics: every solution driven in simulation", (
        "For each target pose armkit lists every inverse-kinematics solution inside the joint "
        "limits. Each one is driven in MuJoCo (servoed from home, gravity on) and the simulated "
        "tool pose is compared with the target."
        + (" The report computed with pi/2 where it printed 1.57; the targets here use pi/2." if ctx.seeds
           else " The targets are the tool poses of random configurations inside the limits.")))
    if ctx.seeds:
        targets = [(np.array(p), np.array(s), e) for p, s, e in published.PROBOT_IK]
        listed_counts = " + ".join(str(len(t[1])) for t in targets)
        section.published = (f"lists {listed_counts} in-limit solutions (its text "
                             f"says {' + '.join(map(str, published.PROBOT_IK_STATED_COUNTS))}), Gazebo error "
                             f"up to 5.4e-3 m")
    else:  # the pictured target first: of three random ones, the one whose solutions differ most
        targets = [(pose_from_transform(robot.fk(q)), None, None) for q in robot.random_q(3, rng=ctx.rng)]
        spread = [_link_spread(robot, _solutions(robot, transform_from_pose(pose), ctx.rng)[0])
                  for pose, _, _ in targets]
        first = int(np.argmax(spread))
        targets = [targets[first]] + targets[:first] + targets[first + 1:]
    counts, worst_position, worst_rotation = [], 0.0, 0.0
    gif_q: list[NDArray] = []
    gif_labels: list[str] = []
    for index, (pose, listed, report_error) in enumerate(targets, start=1):
        T = transform_from_pose(pose)
        solutions, method = _solutions(robot, T, ctx.rng)
        moves = [ctx.sim.move(ctx.home, s, MOVE_SECONDS / 2 if ctx.quick else MOVE_SECONDS, SETTLE_SECONDS)
                 for s in solutions]
        if index == 1:
            gif_q = [m.q[:: max(1, len(m.q) // 12)] for m in moves]
            gif_labels = [f"solution {k + 1} of {len(moves)}" for k, q_k in enumerate(gif_q) for _ in q_k]
            picture = ctx.path("ik_solutions.png")
            animation.plot_configurations(robot, np.array([m.q[-1] for m in moves]), picture,
                                          titles=[f"solution {k + 1}" for k in range(len(moves))],
                                          dpi=60 if ctx.quick else 80, size=3.6)
            section.images.append((picture.name, "Target 1: every in-limit solution as MuJoCo holds it. The "
                                                 "same tool pose; the link frames show which joints are "
                                                 "turned (for this arm the solutions can share link "
                                                 "positions and differ by 180 deg joint turns)."))
        reached = np.array([m.T_tool[-1] for m in moves])
        table = compare_poses(np.broadcast_to(T, reached.shape), reached)
        counts.append(len(solutions))
        worst_position = max(worst_position, table.position_error.max())
        worst_rotation = max(worst_rotation, table.orientation_error.max())
        rows = []
        for k, q_k in enumerate(solutions):
            match = ""
            if listed is not None:
                j, distance = _nearest_published(q_k, listed)
                match = f"#{j + 1} ({distance:.1e})"
            fk_residual = np.linalg.norm(robot.fk(q_k)[:3, 3] - T[:3, 3])
            rows.append([str(k + 1), fmt_q(q_k), match, fmt_error(fk_residual),
                         " ".join(fmt_error(e) for e in table.error[k, :3]),
                         " ".join(fmt_error(e) for e in table.error[k, 3:]),
                         fmt_error(table.orientation_error[k])])
        note = f"{len(solutions)} solution(s), {method}."
        if listed is not None:
            stated = published.PROBOT_IK_STATED_COUNTS[index - 1]
            note += f" The report lists {len(listed)}"
            if stated != len(listed):
                note += (f" (its text says \"{stated} solutions in range\" but it prints {len(listed)}, "
                         f"and its video caption says {len(listed)})")
            note += f"; its Gazebo pose error: {', '.join(fmt_error(e) for e in report_error)}."
        section.tables.append(Table(
            f"Target {index}: [{', '.join(fmt(v, 4) for v in pose)}] (x y z [m], roll pitch yaw [rad])",
            ["#", "armkit solution q [rad]", "report's nearest (max |dq|)", "FK residual [m]",
             "MuJoCo - target: x y z [m]", "roll pitch yaw [rad]", "rotation [rad]"], rows, note=note))
    section.headline = (f"{' + '.join(map(str, counts))} solutions; in MuJoCo within {worst_position:.1e} m, "
                        f"{worst_rotation:.1e} rad of the target")
    if gif_q:
        gif = ctx.path("ik_solutions.gif")
        animation.animate_trajectory(robot, np.vstack(gif_q), gif, frames=ctx.gif_frames, dpi=ctx.gif_dpi,
                                     trace_tool=False, title=f"Target 1: {counts[0]} IK solutions in MuJoCo",
                                     labels=gif_labels)
        section.images.append((gif.name, "Each solution of target 1 driven in MuJoCo from the home "
                                         "configuration, one after the other."))
    return section


def _fk_rows(robot: Robot, sim: Simulation, q: NDArray, published_rows: list, convention: str,
             degrees: bool, quick: bool) -> tuple[list[list[str]], set[int], float]:
    start = robot.home
    table = compare_poses(robot.fk(q), _servo_poses(sim, start, q, quick), convention=convention,
                          degrees=degrees)
    rows, groups = [], set()
    for k in range(len(q)):
        groups.add(len(rows))
        report_c, report_s = published_rows[k] if k < len(published_rows) else (None, None)
        for axis, name in enumerate(table.columns):
            digits = 3 if (degrees and axis >= 3) else 6
            rows.append([fmt_q(np.degrees(q[k]) if degrees else q[k], 2) if axis == 0 else "", name,
                         "" if report_c is None else f"{report_c[axis]:g}",
                         "" if report_s is None else f"{report_s[axis]:g}",
                         fmt(table.computed[k, axis], digits), fmt(table.simulated[k, axis], digits),
                         "" if report_c is None else f"{table.computed[k, axis] - report_c[axis]:.1e}",
                         fmt_error(table.error[k, axis])])
    return rows, groups, float(table.position_error.max())


def fk_table_zju(ctx: LabContext) -> Section:
    """Report 003: ZJU-I forward kinematics in X-Y'-Z' Euler angles (degrees), with MuJoCo."""
    from armkit.robot_file import load

    robot = load("zju-i")
    sim = Simulation(robot, gravity=True)
    q = np.vstack([np.array(published.ZJU_FK[0][0]), robot.random_q(3, rng=ctx.rng)])
    rows, groups, worst = _fk_rows(robot, sim, q, [row[1:] for row in published.ZJU_FK], "xyz-euler",
                                   True, ctx.quick)
    section = Section("zju", "8. ZJU-I forward kinematics (report 003)", (
        "The ZJU-I arm (standard DH) in the report's pose format: position [m] and X-Y'-Z' Euler "
        "angles in degrees, R = Rx(a1) Ry(a2) Rz(a3). The report gives the joint values of its "
        "fifth row, q = pi/12 for every joint; the other rows are random configurations."))
    section.tables.append(Table("ZJU-I tool pose: report, armkit, MuJoCo (servo, gravity on)",
                                ["q [deg]", "", "report: computed", "report: CoppeliaSim", "armkit FK",
                                 "MuJoCo", "armkit - report", "MuJoCo - armkit"], rows, groups=groups,
                                note="The report prints 3 decimals of metres and 2 of degrees."))
    section.headline = f"report row reproduced; max |MuJoCo - armkit| {worst:.1e} m"
    section.published = "CoppeliaSim - computed up to 0.05 deg"
    picture = ctx.path("zju_configuration.png")
    animation.plot_configuration(robot, q[0], picture, dpi=80 if ctx.quick else 100,
                                 title="ZJU-I at q = 15 deg for every joint")
    section.images.append((picture.name, "ZJU-I at the report's configuration, with its DH link frames."))
    return section


def fk_table_scara(ctx: LabContext) -> Section:
    """Report 004: GRB400 SCARA tool coordinates in millimetres, with MuJoCo."""
    from armkit.robot_file import load

    robot = load("grb400-scara")
    sim = Simulation(robot, gravity=True)
    published_q = np.array([row[0] for row in published.SCARA_FK])  # deg and mm, as report 004
    q = np.where(robot.chain.prismatic, published_q * 1e-3, np.radians(published_q))
    computed = robot.fk(q)[:, :3, 3] * 1000
    start = robot.home
    simulated = _servo_poses(sim, start, q, ctx.quick)[:, :3, 3] * 1000
    rows, misses = [], []
    for k, (q_user, axis, value) in enumerate(published.SCARA_FK):
        i = "xyz".index(axis)
        misses.append(computed[k, i] - value)
        rows.append([f"{q_user[0]:g}, {q_user[1]:g}, {q_user[2]:g}, {q_user[3]:g}", axis, f"{value:.4f}",
                     f"{computed[k, i]:.4f}", f"{simulated[k, i]:.4f}", fmt_error(misses[-1]),
                     fmt_error(simulated[k, i] - computed[k, i])])
    section = Section("scara", "9. GRB400 SCARA forward kinematics (report 004)", (
        "The four-joint SCARA (R-R-P-R, l1 = l2 = 200 mm) with the report's joint values "
        "(theta1, theta2 [deg], d3 [mm], theta4 [deg]); the report checked them on the real arm."))
    section.tables.append(Table("SCARA tool coordinates [mm]",
                                ["t1, t2 [deg], d3 [mm], t4 [deg]", "coordinate", "report [mm]",
                                 "armkit [mm]", "MuJoCo [mm]", "armkit - report", "MuJoCo - armkit"], rows))
    worst = float(np.abs(simulated - computed).max())
    section.headline = (f"every published value within {np.abs(misses).max():.1e} mm; "
                        f"MuJoCo within {worst:.1e} mm")
    section.published = "real arm within 0.0006 mm of its computed values"
    picture = ctx.path("scara_configuration.png")
    animation.plot_configuration(robot, q[0], picture, dpi=80 if ctx.quick else 100,
                                 title="GRB400 SCARA at t1 = t2 = 45 deg")
    section.images.append((picture.name, "GRB400 SCARA at the first published configuration."))
    return section

