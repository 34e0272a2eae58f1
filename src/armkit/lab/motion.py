"""Lab experiments on motion: a straight line by velocity control, a minimum-jerk trajectory
through waypoints and a rotation about the tool point, each computed by armkit and then
driven in MuJoCo (gravity on, gravity compensation, servos at 1 kHz).

Each function returns a :class:`~armkit.lab.report.Section`.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from armkit import animation
from armkit.control import move_linear, rotate_about_tool_point
from armkit.lab import published
from armkit.lab.context import LabContext, fmt, fmt_error, fmt_q
from armkit.lab.report import Section, Table
from armkit.plots import Figure, plot_pva
from armkit.robot import Robot
from armkit.sim.runner import SimResult
from armkit.spatial.rotations import rotation_angle_between
from armkit.spatial.transforms import pose_from_transform, transform_from_pose
from armkit.trajectory import plan_trajectory
from armkit.trajectory.waypoints import write_waypoints

__all__ = ["TRAJECTORY_FILE", "WAYPOINTS_FILE", "experiment_waypoints", "fixed_point_rotation",
           "linear_motion", "not_applicable", "ready_configuration", "save_figure", "save_gif", "tool_errors",
           "trajectory_experiment"]

LINE_SECONDS = 5.0
#: Files of the report folder holding experiment 4's samples and waypoints (``armkit lab --view`` plays them).
TRAJECTORY_FILE = "trajectory.csv"
WAYPOINTS_FILE = "trajectory_waypoints.csv"
ROTATION_RATE = 0.2  # rad/s, for a user's arm
USER_ROTATION_ANGLE = np.radians(60.0)
MIN_TURN_DEG = 40.0  # the seed experiment's minimum
MOTION_TOLERANCE = 1e-3  # m: the reports' millimetre level; a worse end or drift counts as failed
#: Directions (base frame) tried for the straight line of a user's arm, in this order.
LINE_DIRECTIONS = ([1, 0, -1], [0, 1, 0], [0, 0, -1], [-1, 0, 0], [0, -1, 1], [1, 1, 0])
#: Relative residual below which a tool twist counts as one the arm can make (in its Jacobian's range).
TWIST_TOLERANCE = 1e-6


def twist_possible(robot: Robot, q: NDArray, twist: NDArray) -> bool:
    """Whether some joint rates at ``q`` give the tool exactly the twist ``[v; w]`` (base frame).

    An arm with fewer than six joints (or at a singularity) reaches only a subspace of
    twists: a 3R arm cannot move its tool point without turning the tool, so it cannot
    follow a line with the orientation held, nor turn the tool about its own point.
    """
    J = robot.jacobian(q)
    rates = np.linalg.lstsq(J, twist, rcond=None)[0]
    return bool(np.linalg.norm(J @ rates - twist) <= TWIST_TOLERANCE * np.linalg.norm(twist))


def not_applicable(section: Section, because: str) -> Section:
    """Mark ``section`` as an experiment this arm cannot do, saying why once (in its note)."""
    section.status, section.headline = "n/a", ""
    section.notes.append(f"Not applicable, because {because}.")
    return section


#: Seed of a user's arm's trajectory waypoints (experiment 4, whose trajectory experiment 6 reuses).
WAYPOINT_SEED = 2024


def ready_configuration(robot: Robot, rng: np.random.Generator, scene=None) -> NDArray[np.float64]:
    """A well-conditioned configuration inside the limits: of 64 random ones, those clear of the
    floor and of the arm itself in ``scene`` (all if none is), the one with the largest smallest
    singular value."""
    q = robot.random_q(64, rng=rng)
    margin = 0.15 * np.ptp(np.where(np.isfinite(robot.limits), robot.limits, 0), axis=1)
    q = np.clip(q, robot.limits[:, 0] + margin, robot.limits[:, 1] - margin)
    if scene is not None:
        free = ~scene.collides(q)
        q = q[free] if free.any() else q
    return q[int(np.argmax(robot.singular_values(q)[:, -1]))]


def _free_offset(robot: Robot, q0: NDArray[np.float64], rng: np.random.Generator,
                 scene) -> NDArray[np.float64]:
    """``q0`` moved by a random offset inside the limits (up to 0.5 rad or 0.1 m per joint): the
    first of 16 draws clear of the floor and of the arm itself in ``scene``."""
    span = np.where(robot.chain.prismatic, 0.1, 0.5)
    draws = np.clip(q0 + rng.uniform(-span, span, (16, robot.n)), *robot.limits.T)
    return draws[int(np.argmax(~scene.collides(draws)))]


def _simulate(ctx: LabContext, t: NDArray, q: NDArray, mode: str = "position") -> SimResult:
    if mode == "position":  # the same commanded motion run in velocity mode is recorded once
        ctx.record(q)
    return ctx.sim.run(t, q, mode=mode)


def save_gif(ctx: LabContext, name: str, result: SimResult, title: str, caption: str, section: Section,
             scene=None) -> None:
    """An animation of the simulated motion (``scene``'s obstacles outlined, if given)."""
    path = ctx.path(name)
    stride = max(1, len(result.t) // 400)
    animation.animate_trajectory(ctx.robot, result.q[::stride], path, t=result.t[::stride] - result.t[0],
                                 frames=ctx.gif_frames, dpi=ctx.gif_dpi, title=title, scene=scene)
    section.images.append((path.name, caption))


def save_figure(ctx: LabContext, figure: Figure, name: str, caption: str, section: Section) -> None:
    path = ctx.path(name)
    if figure.get_layout_engine() is None:
        figure.subplots_adjust(left=0.08, right=0.98, bottom=0.16, top=0.9, wspace=0.28)
    figure.savefig(path, dpi=70 if ctx.quick else 100)
    section.images.append((path.name, caption))


def tool_errors(robot: Robot, result: SimResult) -> tuple[NDArray, NDArray]:
    """Simulated vs commanded tool: position distance [m] and rotation [rad] per step."""
    T_command = robot.fk(result.q_command)
    return (np.linalg.norm(result.T_tool[:, :3, 3] - T_command[:, :3, 3], axis=-1),
            rotation_angle_between(result.T_tool, T_command))


def _line_deviation(points: NDArray, start: NDArray, displacement: NDArray) -> NDArray:
    """Distance [m] of each point from the straight segment ``start -> start + displacement``."""
    s = np.clip((points - start) @ displacement / (displacement @ displacement), 0.0, 1.0)
    return np.linalg.norm(points - (start + s[:, None] * displacement), axis=-1)


def _linear_plan(ctx: LabContext) -> tuple[NDArray, NDArray, object] | None:
    """Start, displacement and the computed motion; ``None`` if the arm can move along no direction tried."""
    robot = ctx.robot
    if ctx.seeds:
        q0 = np.zeros(6)
        displacement = np.array(published.PROBOT_LINE_DISPLACEMENT)
        return q0, displacement, move_linear(robot, q0, displacement, LINE_SECONDS)
    q0 = ready_configuration(robot, ctx.rng, ctx.scene)
    length = 0.15 * max(np.linalg.norm(robot.fk(q0)[:3, 3]), 0.1)
    plan = None
    for direction in LINE_DIRECTIONS:
        displacement = length * np.array(direction, dtype=float) / np.linalg.norm(direction)
        if not twist_possible(robot, q0, np.append(displacement, np.zeros(3))):
            continue
        plan = q0, displacement, move_linear(robot, q0, displacement, LINE_SECONDS)
        if (plan[2].success and plan[2].max_position_error < 1e-4
                and not ctx.scene.collides(plan[2].q[:: max(1, len(plan[2].q) // 500)]).any()):
            break  # a line the arm follows, clear of the floor and of itself (the UR5's first went down)
    return plan


def linear_motion(ctx: LabContext) -> Section:
    """Experiment 3: the tool along a straight line by resolved-rate (Jacobian) control."""
    section = Section("line", "3. Straight line by velocity control", (
        "armkit.control.move_linear follows p(t) = p0 + s(t) d with a quintic time law in closed "
        "loop through the Jacobian (resolved rate, orientation held). The joint motion is then "
        "driven in MuJoCo twice: with position and velocity servos, and with the velocity servo "
        "alone" + (", as the report published joint velocities to Gazebo." if ctx.seeds else ".")))
    robot = ctx.robot
    plan = _linear_plan(ctx)
    if plan is None:
        return not_applicable(section, (
            f"move_linear holds the tool's orientation while its point moves, and this arm "
            f"({robot.n} joints) cannot move its tool point without turning the tool in any of the "
            f"{len(LINE_DIRECTIONS)} directions tried"))
    q0, displacement, motion = plan
    start = motion.poses[0, :3, 3]
    both = _simulate(ctx, motion.t, motion.q)
    velocity = _simulate(ctx, motion.t, motion.q, mode="velocity")
    runs = [("armkit (computed)", motion.poses), ("MuJoCo, position + velocity servos", both.T_tool),
            ("MuJoCo, velocity servo only", velocity.T_tool)]
    report_end = published.PROBOT_LINE_END if ctx.seeds else None
    rows = []
    for label, poses in runs:
        end = poses[-1, :3, 3]
        deviation = _line_deviation(poses[:, :3, 3], start, displacement)
        turn = rotation_angle_between(poses[0], poses).max()
        rows.append([label, fmt_q(start, 4), fmt_q(end, 6), fmt_q(end - start, 6),
                     fmt_error(np.linalg.norm(end - (start + displacement))), fmt_error(deviation.max()),
                     fmt_error(turn)])
    if report_end is not None:
        rows.insert(0, ["report (Gazebo)", fmt_q(published.PROBOT_LINE_START, 4),
                        fmt_q(published.PROBOT_LINE_END_GAZEBO, 6),
                        fmt_q(np.subtract(published.PROBOT_LINE_END_GAZEBO, published.PROBOT_LINE_START), 6),
                        fmt_error(np.linalg.norm(np.subtract(published.PROBOT_LINE_END_GAZEBO, report_end))),
                        "", ""])
        gazebo = fmt_q(published.PROBOT_LINE_END_GAZEBO, 4)
        section.published = f"end at {fmt_q(report_end, 3)} (Gazebo {gazebo})"
    section.tables.append(Table(
        f"Target: the tool along d = {fmt_q(displacement, 3)} m in {motion.t[-1]:.1f} s from "
        f"q0 = {fmt_q(q0, 3)} (the rows: where each run ended and how far it moved)",
        ["run", "start [m]", "end [m]", "moved [m]", "|end - target| [m]", "max distance from the line [m]",
         "max orientation change [rad]"], rows, note=motion.message))
    position_error, _ = tool_errors(robot, both)
    miss = np.linalg.norm(both.T_tool[-1, :3, 3] - start - displacement)
    section.headline = (f"ends {miss:.1e} m from the target in MuJoCo; "
                        f"tracking within {position_error.max():.1e} m")
    if miss > MOTION_TOLERANCE:
        section.status = "failed"
        section.notes.append(f"The tool ended {miss:.1e} m from the end of the line ({motion.message}).")
    figure = Figure(figsize=(8.5, 3.2))
    ax_position, ax_deviation = figure.subplots(1, 2)
    for k, name in enumerate("xyz"):
        ax_position.plot(motion.t, motion.poses[:, k, 3], color=f"C{k}", lw=2.2, alpha=0.5,
                         label=f"{name} armkit")
        ax_position.plot(both.t, both.T_tool[:, k, 3], color=f"C{k}", lw=1.0, ls="--", label=f"{name} MuJoCo")
    ax_position.set(xlabel="time [s]", ylabel="tool position [m]", title="Tool position")
    ax_position.legend(fontsize=7, ncol=3)
    for label, poses, t in (("armkit", motion.poses, motion.t), ("MuJoCo, both servos", both.T_tool, both.t),
                            ("MuJoCo, velocity servo", velocity.T_tool, velocity.t)):
        ax_deviation.semilogy(t, np.maximum(_line_deviation(poses[:, :3, 3], start, displacement), 1e-12),
                              label=label, lw=1.2)
    ax_deviation.set(xlabel="time [s]", ylabel="distance [m]", title="Distance from the straight line")
    ax_deviation.legend(fontsize=7)
    for ax in (ax_position, ax_deviation):
        ax.grid(True, lw=0.3)
    save_figure(ctx, figure, "line_tracking.png", "Tool position over time (computed and simulated) and its "
                "distance from the ideal straight line.", section)
    save_gif(ctx, "line.gif", both, "Straight line in MuJoCo", "The straight-line motion in MuJoCo, tool "
             "path traced.", section)
    return section


#: Segment durations [s] of a user's arm whose file gives neither velocity nor acceleration limits.
UNLIMITED_SEGMENT_SECONDS = 4.0


def experiment_waypoints(ctx: LabContext) -> tuple[NDArray, NDArray | None, NDArray | None, NDArray | None]:
    """Joint waypoints, their target poses (or None), the report's joint values (or None), durations
    (None for a user's arm with limits: the fastest timing within them)."""
    robot = ctx.robot
    if not ctx.seeds:  # drawn from their own seed: experiments 4 and 6 get the same ones
        rng = np.random.default_rng(WAYPOINT_SEED)
        q0 = ready_configuration(robot, rng, ctx.scene)
        q = [q0] + [_free_offset(robot, q0, rng, ctx.scene) for _ in range(3)]
        limited = np.isfinite(robot.max_velocity).any() or np.isfinite(robot.max_acceleration).any()
        return np.array(q), None, None, None if limited else np.full(3, UNLIMITED_SEGMENT_SECONDS)
    poses = np.array(published.PROBOT_WAYPOINT_POSES)
    q, near = [], np.zeros(6)
    for pose in poses:
        near = robot.ik(transform_from_pose(pose), near=near)
        q.append(near)
    return (np.array(q), poses, np.array(published.PROBOT_WAYPOINT_JOINTS),
            np.full(3, published.PROBOT_SEGMENT_SECONDS))


def _literal_157(robot: Robot, poses: NDArray) -> NDArray:
    """IK of the waypoint poses with +-pi/2 replaced by the printed +-1.57, each nearest the previous."""
    printed = poses.copy()
    angles = printed[:, 3:]
    quarter = np.isclose(np.abs(angles), np.pi / 2)
    angles[quarter] = np.sign(angles[quarter]) * 1.57
    q, near = [], np.zeros(robot.n)
    for pose in printed:
        near = robot.ik(transform_from_pose(pose), near=near)
        q.append(near)
    return np.array(q)


def _waypoint_table(ctx: LabContext, q: NDArray, poses: NDArray | None, report_q: NDArray | None,
                    times: NDArray, result: SimResult) -> Table:
    robot = ctx.robot
    rows = []
    targets = robot.fk(q) if poses is None else transform_from_pose(poses)
    literal = None if report_q is None else _literal_157(robot, poses)
    for k, (q_k, t_k) in enumerate(zip(q, times, strict=True)):
        step = int(np.argmin(np.abs(result.t - t_k)))
        T_sim = result.T_tool[step]
        pose = pose_from_transform(targets[k])
        residual = published.PROBOT_WAYPOINT_RESIDUALS[k - 1] if ctx.seeds and k in (1, 2) else None
        rows.append([str(k + 1), f"{t_k:.1f}", fmt_q(pose, 4), fmt_q(q_k),
                     "" if report_q is None else fmt_error(np.abs(q_k - report_q[k]).max()),
                     "" if literal is None else fmt_error(np.abs(literal[k] - report_q[k]).max()),
                     fmt_error(np.linalg.norm(T_sim[:3, 3] - targets[k][:3, 3])),
                     fmt_error(rotation_angle_between(T_sim, targets[k])),
                     "" if residual is None else fmt_error(residual)])
    note = ""
    if ctx.seeds:
        note = ("The report's joint waypoints are the IK solutions of the poses with 1.57 taken literally "
                "(they match those to the digits printed), not of pi/2; armkit uses pi/2, hence the "
                "1e-3 rad difference. Waypoints 2-4 have pitch = -pi/2, the gimbal lock of roll-pitch-yaw "
                "angles, so per-angle errors are meaningless there; the rotation error (angle between the "
                "orientations) is not. The report's figure sums all six pose errors.")
    title = ("Waypoints: target pose, armkit IK, report, and where MuJoCo passes them" if ctx.seeds
             else "Waypoints: pose, joint values, and where MuJoCo passes them")
    return Table(title,
                 ["#", "t [s]", "pose x y z [m], roll pitch yaw [rad]", "armkit q [rad]",
                  "max |q - report q|", "same, IK of 1.57", "MuJoCo position error [m]",
                  "MuJoCo rotation error [rad]", "report: sum |pose error| (Gazebo)"], rows, note=note)


def trajectory_experiment(ctx: LabContext) -> Section:
    """Experiment 4: a minimum-jerk trajectory through four waypoints, tracked in MuJoCo."""
    section = Section("trajectory", "4. Minimum-jerk trajectory through four waypoints", (
        "armkit.trajectory joins quintic segments through the waypoints with continuous velocity "
        "and acceleration, minimising the integral of squared jerk over all segments"
        + (" (the report's QP)" if ctx.seeds else "") + ", at rest at both ends. "
        + ("Waypoints given as poses are solved by IK, each nearest the previous solution. " if ctx.seeds
           else "The waypoints are a well-conditioned configuration and three random moves from it. ")
        + "MuJoCo tracks the 1 kHz samples with gravity on."))
    q, poses, report_q, durations = experiment_waypoints(ctx)
    robot = ctx.robot
    trajectory = plan_trajectory(robot, q, durations)
    if durations is None:
        section.notes.append("Timed to the arm's own limits: the fastest motion along the path within its "
                             "velocity and acceleration limits (and torque limits, where the robot file has "
                             "them), as 'armkit traj --auto-time'.")
    elif not ctx.seeds:
        section.notes.append(f"The robot file gives no velocity or acceleration limits, so each segment "
                             f"takes {UNLIMITED_SEGMENT_SECONDS:g} s.")
    samples = trajectory.sample(1000.0)
    ctx.record(samples.q)
    result = ctx.sim.run(samples.t, samples.q, samples.qd)
    trajectory.to_csv(ctx.path(TRAJECTORY_FILE), rate_hz=100.0, overwrite=True)
    write_waypoints(ctx.path(WAYPOINTS_FILE), robot, q, overwrite=True)
    section.notes.append(f"The trajectory (100 Hz samples) and its waypoints are saved next to this page "
                         f"as {TRAJECTORY_FILE} and {WAYPOINTS_FILE}; play them in the 3-D viewer with "
                         f"'armkit lab --view' or 'armkit view ROBOT --trajectory {TRAJECTORY_FILE}'.")
    section.tables.append(_waypoint_table(ctx, q, poses, report_q, trajectory.waypoint_times, result))
    limit_rows = []
    for j, name in enumerate(robot.joint_names):
        unit = "m" if robot.chain.prismatic[j] else "rad"
        limit_rows.append([name, f"{fmt(trajectory.peak_velocity[j], 4)} {unit}/s",
                           f"{fmt(robot.max_velocity[j], 4)} {unit}/s",
                           f"{fmt(trajectory.peak_acceleration[j], 4)} {unit}/s²",
                           f"{fmt(robot.max_acceleration[j], 4)} {unit}/s²",
                           f"{fmt_error(np.abs(result.joint_error[:, j]).max())} {unit}"])
    position_error, rotation_error = tool_errors(robot, result)
    T_goal = robot.fk(q[-1])
    final = np.append(result.T_tool[-1, :3, 3] - T_goal[:3, 3],
                      rotation_angle_between(result.T_tool[-1], T_goal))
    note = (f"Segments {', '.join(f'{d:.2f}' for d in trajectory.durations)} s "
            f"(stretch {', '.join(f'{s:.3f}' for s in trajectory.stretch)}). Tool tracking in MuJoCo: "
            f"position within {position_error.max():.1e} m, rotation within {rotation_error.max():.1e} rad. "
            f"Final error (MuJoCo - target): x y z {', '.join(fmt_error(e) for e in final[:3])} m, "
            f"rotation {fmt_error(final[3])} rad.")
    if ctx.seeds:
        note += (" The report's final pose error in Gazebo: "
                 f"{', '.join(fmt_error(e) for e in published.PROBOT_TRAJECTORY_FINAL_ERROR)}.")
        section.published = "final error 1.4e-4 m, 5e-3 rad (Gazebo)"
    section.tables.append(Table("Peaks against the joint limits, and tracking in MuJoCo (gravity on)",
                                ["joint", "peak |qd|", "max velocity", "peak |qdd|", "max acceleration",
                                 "max |q_MuJoCo - q_command|"], limit_rows, note=note))
    section.headline = (f"{trajectory.duration:.3g} s, within limits; tracked in MuJoCo to "
                        f"{position_error.max():.1e} m, {rotation_error.max():.1e} rad")
    save_figure(ctx, plot_pva(trajectory, robot), "trajectory_pva.png", "Position, velocity and "
                "acceleration of every joint (dots: waypoints, dashed: limits).", section)
    figure = Figure(figsize=(8.5, 3.0))
    ax_joint, ax_tool = figure.subplots(1, 2)
    _plot_joint_errors(ax_joint, robot, result)
    ax_rotation = ax_tool.twinx()
    ax_tool.plot(result.t, position_error * 1e3, lw=1.0, color="C0", label="position (left) [mm]")
    ax_rotation.plot(result.t, rotation_error * 1e3, lw=1.0, color="C1", ls="--",
                     label="rotation (right, dashed) [mrad]")
    ax_tool.set(xlabel="time [s]", ylabel="position error [mm]", title="Tool: MuJoCo vs commanded")
    ax_rotation.set_ylabel("rotation error [mrad]")
    lines = ax_tool.get_lines() + ax_rotation.get_lines()
    ax_tool.legend(lines, [line.get_label() for line in lines], fontsize=7)
    for ax in (ax_joint, ax_tool):
        ax.grid(True, lw=0.3)
        for t_k in trajectory.waypoint_times:
            ax.axvline(t_k, color="0.6", lw=0.6, ls=":")
    save_figure(ctx, figure, "trajectory_tracking.png",
                "Tracking error in MuJoCo with gravity on and gravity compensation.", section)
    save_gif(ctx, "trajectory.gif", result, "Minimum-jerk trajectory in MuJoCo",
             "The trajectory in MuJoCo with the tool path traced.", section)
    return section


def _plot_joint_errors(ax, robot: Robot, result: SimResult) -> None:
    """``q_MuJoCo - q_command`` per joint: revolute joints in rad on the left axis, prismatic in m
    (dashed, on a right-hand axis when the arm has both kinds)."""
    prismatic = np.asarray(robot.chain.prismatic)
    axes = {False: ax, True: ax.twinx() if prismatic.any() and not prismatic.all() else ax}
    for j, name in enumerate(robot.joint_names):
        axes[bool(prismatic[j])].plot(result.t, result.joint_error[:, j], lw=1.0, color=f"C{j}",
                                      ls="--" if prismatic[j] else "-", label=name)
    if not prismatic.all():
        ax.set_ylabel("revolute joints [rad]")
    if prismatic.any():
        axes[True].set_ylabel("prismatic joints (dashed) [m]")
    ax.set(xlabel="time [s]", title="q_MuJoCo - q_command")
    lines = [line for a in {id(a): a for a in axes.values()}.values() for line in a.get_lines()]
    ax.legend(lines, [line.get_label() for line in lines], fontsize=7, ncol=3)


def rotation_axes(robot: Robot, q0: NDArray) -> list[tuple[NDArray, str]]:
    """Candidate axes (base frame, unit) for the fixed-point rotation of a user's arm, best first.

    The base x axis (as in the seed experiment), then axes perpendicular to the last revolute
    joint's axis, then base y and z; an axis within 25 deg of the last joint's axis is left out,
    since turning about it only turns that joint and tests nothing.
    """
    angular = robot.jacobian(q0)[3:]
    revolute = np.flatnonzero(np.linalg.norm(angular, axis=0) > 0.5)
    last = angular[:, revolute[-1]] if len(revolute) else np.zeros(3)
    helper = np.eye(3)[int(np.argmin(np.abs(last)))]
    across = np.cross(last, helper)
    across = across / np.linalg.norm(across) if np.linalg.norm(across) > 0 else np.array([0.0, 1.0, 0.0])
    named = [(np.array([1.0, 0.0, 0.0]), "the base x axis, as in the seed experiment"),
             (across, "an axis perpendicular to the last joint's axis"),
             (np.cross(last, across) if len(revolute) else across,
              "an axis perpendicular to the last joint's axis"),
             (np.array([0.0, 1.0, 0.0]), "the base y axis"), (np.array([0.0, 0.0, 1.0]), "the base z axis")]
    candidates = []
    for axis, why in named:
        if np.linalg.norm(axis) > 0.5 and abs(axis @ last) < np.cos(np.radians(25.0)):
            candidates += [(axis, why), (-axis, why)]
    return candidates


def _rotation_plan(ctx: LabContext) -> tuple[NDArray, NDArray, object, str] | None:
    """Start, axis, the computed motion, and a sentence on why this axis; ``None`` if the arm can
    turn its tool about no candidate axis with the tool point held."""
    robot = ctx.robot
    if ctx.seeds:  # the twist [v; w] = [0, 0, 0, -0.2, 0, 0]: 0.2 rad/s about -x
        w = np.array(published.PROBOT_ROTATION_TWIST[3:])
        angle = np.radians(45.0) if ctx.quick else 2 * np.pi
        axis = w / np.linalg.norm(w)
        motion = rotate_about_tool_point(robot, np.zeros(6), axis, angle,
                                         angular_velocity=float(np.linalg.norm(w)))
        return np.zeros(6), axis, motion, "The axis is the report's: -x of the base frame."
    q0 = ready_configuration(robot, ctx.rng, ctx.scene)
    T0 = robot.fk(q0)
    candidates = [(axis, why) for axis, why in rotation_axes(robot, q0)
                  if twist_possible(robot, q0, np.append(np.zeros(3), axis))]
    if not candidates:
        return None
    best, best_turn = None, -1.0
    for axis, why in candidates:
        motion = rotate_about_tool_point(robot, q0, axis, USER_ROTATION_ANGLE, angular_velocity=ROTATION_RATE)
        turn = float(np.abs(_signed_turn(motion.poses, T0, axis)).max())
        held = motion.orientation_error < 1e-3 and motion.max_position_error < 1e-3
        if motion.success and held:
            return q0, axis, motion, (f"The axis is {why}, the first candidate the arm follows for "
                                      f"{np.degrees(USER_ROTATION_ANGLE):.0f} deg with the tool point held.")
        if held and turn > best_turn:
            best, best_turn = (q0, axis, motion, why), turn
    if best is None:
        axis, why = candidates[0]
        turn = rotate_about_tool_point(robot, q0, axis, USER_ROTATION_ANGLE, angular_velocity=ROTATION_RATE)
        best = (q0, axis, turn, why)
    q0, axis, motion, why = best
    return q0, axis, motion, (f"No candidate axis (base x, perpendicular to the last joint's axis, base y, "
                              f"base z) could be followed for {np.degrees(USER_ROTATION_ANGLE):.0f} deg; "
                              f"shown: {why}, the one turned farthest with the tool point held.")


def fixed_point_rotation(ctx: LabContext) -> Section:
    """Experiment 5: turn the tool about an axis through its own origin, position held."""
    section = Section("rotation", "5. Fixed-point rotation", (
        "armkit.control.rotate_about_tool_point turns the tool at 0.2 rad/s about an axis "
        "through the tool point"
        + (" (the report's twist [0, 0, 0, -0.2, 0, 0] about the base x axis at the home pose)" if ctx.seeds
           else "") + " while the Jacobian loop keeps the tool position; the motion "
        "stops at the first joint limit. MuJoCo then drives the joint motion with gravity on."))
    plan = _rotation_plan(ctx)
    if plan is None:
        return not_applicable(section, (
            f"this arm ({ctx.robot.n} joints) cannot turn its tool about any of the axes tried (base x, y, z "
            f"and two perpendicular to the last joint's axis; turning about that axis alone tests nothing) "
            f"while its tool point stays where it is"))
    q0, axis, motion, why = plan
    result = _simulate(ctx, motion.t, motion.q)
    rows, turns = [], []
    for label, poses in (("armkit (computed)", motion.poses), ("MuJoCo (servos, gravity)", result.T_tool)):
        drift = np.linalg.norm(poses[:, :3, 3] - motion.poses[0, :3, 3], axis=-1)
        turns.append(np.degrees(np.abs(np.unwrap(_signed_turn(poses, motion.poses[0], axis))).max()))
        rows.append([label, fmt(turns[-1], 2), fmt_error(drift.max()), fmt_error(drift[-1])])
    if ctx.seeds:
        rows.insert(0, ["report (Gazebo)", "> 180", "millimetre level", ""])
        section.published = published.PROBOT_ROTATION_REPORTED
    title = (f"Rotation about {fmt_q(axis / np.linalg.norm(axis), 3)} through the tool point "
             f"from q0 = {fmt_q(q0, 3)}")
    swept = np.ptp(motion.q, axis=0)
    moving = [name for name, sweep, prismatic in zip(ctx.robot.joint_names, swept, ctx.robot.chain.prismatic,
                                                      strict=True) if sweep > (1e-3 if prismatic else 0.0175)]
    note = (f"{why} Joints that moved (more than 1 deg or 1 mm): {', '.join(moving) or 'none'} "
            f"({len(moving)} of {ctx.robot.n}). {motion.message}")
    section.tables.append(Table(title, ["run", "angle turned [deg]", "max position drift [m]",
                                        "final drift [m]"], rows, note=note))
    drift_sim = np.linalg.norm(result.T_tool[:, :3, 3] - motion.poses[0, :3, 3], axis=-1)
    turned = float(turns[0])
    section.headline = f"turned {turned:.0f} deg; MuJoCo tool point drift {drift_sim.max():.1e} m"
    if turned < MIN_TURN_DEG or drift_sim.max() > MOTION_TOLERANCE:
        section.status = "failed"
        section.notes.append(f"The tool turned {turned:.1f} deg (at least {MIN_TURN_DEG:g} deg asked) with "
                             f"its point drifting up to {drift_sim.max():.1e} m: {motion.message}")
    figure = Figure(figsize=(8.5, 3.0))
    ax_angle, ax_drift = figure.subplots(1, 2)
    ax_angle.plot(motion.t, np.degrees(np.unwrap(_signed_turn(motion.poses, motion.poses[0], axis))), lw=1.4)
    ax_angle.set(xlabel="time [s]", ylabel="angle [deg]", title="Angle turned about the axis")
    ax_drift.semilogy(result.t, np.maximum(drift_sim, 1e-12), lw=1.0, label="MuJoCo")
    drift_computed = np.linalg.norm(motion.poses[:, :3, 3] - motion.poses[0, :3, 3], axis=-1)
    floor = " (below 1e-12 m: drawn at 1e-12)" if drift_computed.max() < 1e-12 else ""
    ax_drift.semilogy(motion.t, np.maximum(drift_computed, 1e-12), lw=1.0, label=f"armkit{floor}")
    ax_drift.set(xlabel="time [s]", ylabel="drift [m]", title="Tool point drift")
    ax_drift.legend(fontsize=7)
    for ax in (ax_angle, ax_drift):
        ax.grid(True, lw=0.3)
    save_figure(ctx, figure, "rotation.png", "Angle turned and tool-point drift over time.", section)
    save_gif(ctx, "rotation.gif", result, "Rotation about the tool point in MuJoCo",
             "The fixed-point rotation in MuJoCo (tool frame drawn).", section)
    return section


def _signed_turn(poses: NDArray, T0: NDArray, axis: NDArray) -> NDArray:
    """Signed rotation angle [rad] of each pose's orientation relative to ``T0`` about ``axis``."""
    from armkit.spatial.rotations import axis_angle_from_matrix

    relative = poses[:, :3, :3] @ T0[:3, :3].T
    return axis_angle_from_matrix(relative) @ (axis / np.linalg.norm(axis))
