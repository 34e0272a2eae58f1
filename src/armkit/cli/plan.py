"""``armkit plan``: a collision-free motion through a scene, timed within the robot's limits."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import numpy as np
import typer
from rich.markup import escape
from rich.table import Table

from armkit.cli.app import (
    ALLOW_NEGATIVE,
    JOINT_UNITS,
    BaseOpt,
    LockOpt,
    RobotArg,
    TipOpt,
    app,
    console,
    fmt_number,
    load_robot,
    print_json,
    reject_unknown_options,
    to_si,
)
from armkit.cli.ik import target_from_options
from armkit.cli.scene_option import PackagePathOpt, SceneOpt, load_scene_option
from armkit.cli.trajectory import (
    ForceOpt,
    JsonOpt,
    MaxAccelerationOpt,
    MaxVelocityOpt,
    OutOpt,
    PlotOpt,
    RateOpt,
    check_output_file,
    joint_scale,
    limit_option,
    trajectory_summary,
)
from armkit.errors import CollisionError, InputError, JointLimitError, pair_text
from armkit.robot import Robot
from armkit.spatial.rotations import parse_convention

__all__ = ["plan_command"]

#: Samples per second of the tool path in --gif and of the clearance in the summary (at least).
CHECK_RATE_HZ = 200.0


def _joint_lists(robot: Robot, typed: list[str], first: dict[str, str | None], rest: list[str],
                 degrees: bool) -> dict[str, np.ndarray | None]:
    """The joint values of each option in ``first`` (``--from``, ``--to``) in SI units.

    Typer options take one word, so each option takes its word (``--from 0,0,0`` or ``--from 0``)
    and, for the rest of its ``robot.n`` values, the trailing words that follow it on the command
    line: the options are served in the order they were typed (``typed``: the command's parameter
    names in the order Click processed them, which is the command-line order).
    """
    reject_unknown_options(rest)
    options = sorted((name for name, word in first.items() if word is not None),
                     key=lambda name: typed.index(_PARAMS[name]))
    values: dict[str, np.ndarray | None] = dict.fromkeys(first)
    remaining = list(rest)
    for option in options:
        word = first[option]
        if word.startswith("--"):
            raise InputError(f"{option}: expected {robot.n} joint values after it, got the option {word}")
        words = word.replace(",", " ").split()
        need = max(robot.n - len(words), 0)
        words, remaining = words + remaining[:need], remaining[need:]
        values[option] = to_si(robot, words, degrees, option)
    if remaining:
        raise InputError(f"unexpected values {' '.join(remaining)}: each of --from and --to takes "
                         f"{robot.n} joint values")
    return values


#: The Typer parameter behind each joint-list option (the name Click records it under).
_PARAMS = {"--from": "start", "--to": "goal"}


@app.command("plan", context_settings=ALLOW_NEGATIVE)
def plan_command(
    ctx: typer.Context,
    robot: RobotArg,
    values: Annotated[list[str] | None, typer.Argument(
        metavar="[Q...]", help="The rest of the --from and --to joint values.", show_default=False)] = None,
    scene: SceneOpt = None,
    package_path: PackagePathOpt = None,
    start: Annotated[str | None, typer.Option(
        "--from", metavar="Q...", help="Start joint values, e.g. --from 0 -1.2 1.2 0 1.57 0 or "
                                       "--from 0,-1.2,1.2,0,1.57,0 (rad and m; deg with --deg; default "
                                       "the robot's home).", show_default=False)] = None,
    goal: Annotated[str | None, typer.Option(
        "--to", metavar="Q...", help="Goal joint values (as --from).", show_default=False)] = None,
    to_pose: Annotated[tuple[float, float, float, float, float, float] | None, typer.Option(
        "--to-pose", help="Goal tool pose X Y Z (m) A B C (--euler angles): the motion ends at whichever "
                          "collision-free IK solution the planner reaches.", show_default=False)] = None,
    euler: Annotated[str, typer.Option(help="Convention of the --to-pose angles, e.g. xyz-fixed (roll "
                                            "pitch yaw).")] = "xyz-fixed",
    deg: Annotated[bool, typer.Option("--deg", help="Joint values and pose angles in degrees (also the "
                                                    "printed ones).")] = False,
    seed: Annotated[int, typer.Option(min=0, help="Seed of the planner: the same seed, the same "
                                                  "motion.")] = 0,
    time_budget: Annotated[float, typer.Option(help="Seconds the path search may take.")] = 10.0,
    resolution: Annotated[float, typer.Option(help="Largest move (m) of any point of the arm between two "
                                                   "collision checks.")] = 0.005,
    max_velocity: MaxVelocityOpt = None,
    max_acceleration: MaxAccelerationOpt = None,
    rate: RateOpt = 100.0,
    out: OutOpt = None,
    plot: PlotOpt = None,
    gif: Annotated[Path | None, typer.Option(help="Write an animation of the motion, the obstacles outlined "
                                                  "(.gif).", show_default=False)] = None,
    force: ForceOpt = False,
    json_output: JsonOpt = False,
    base: BaseOpt = None,
    tip: TipOpt = None,
    lock: LockOpt = None,
) -> None:
    """Collision-free motion (OMPL RRT-Connect, shortened, smoothed, timed within the limits, checked).

    Example: armkit plan ur5 --scene examples/data/ur5_wall.toml --from 0 -1.2 1.2 0 1.57 0
    --to 1.57 -1.2 1.2 0 1.57 0 --plot pva.png
    """
    from armkit.plan import plan_path  # the planner (OMPL) and the scene (MuJoCo) load only when planning
    from armkit.trajectory.export import write_csv, write_npz
    from armkit.trajectory.plan import planning_limits

    check_output_file(out, (".csv", ".npz"), force, "--out")
    check_output_file(plot, (".png", ".svg", ".pdf"), force, "--plot")
    check_output_file(gif, (".gif",), force, "--gif")
    if not rate > 0:
        raise InputError(f"--rate: expected a positive sampling rate (Hz), got {rate:g}")
    if scene is None:
        raise InputError("--scene FILE: armkit plan needs the scene to plan through (a TOML file of the "
                         "floor and obstacles, docs/collision.md), e.g. --scene examples/data/ur5_wall.toml")
    if (goal is None) == (to_pose is None):
        raise InputError("give the goal as one of --to Q... (joint values) or --to-pose X Y Z A B C")
    arm = load_robot(robot, base, tip, lock)
    joints = _joint_lists(arm, list(ctx.params), {"--from": start, "--to": goal}, values or [], deg)
    for option in ("--from", "--to"):  # said in the units typed, naming the option
        if joints[option] is not None and (outside := arm.limit_violations(joints[option], deg)):
            raise JointLimitError(f"{option}: {'; '.join(outside)}", joints[option],
                                  **arm.chain.limit_fields(joints[option]))
    q_start = arm.home if joints["--from"] is None else joints["--from"]
    target = (joints["--to"] if to_pose is None
              else target_from_options(to_pose, None, None, parse_convention(euler), deg))
    limits = planning_limits(arm, limit_option(max_velocity, arm, deg, "--max-velocity"),
                             limit_option(max_acceleration, arm, deg, "--max-acceleration"))
    world = load_scene_option(arm, scene, package_path)
    try:
        traj = plan_path(world, q_start, target, time_budget=time_budget, seed=seed, resolution=resolution,
                         max_velocity=limits[0], max_acceleration=limits[1])
    except CollisionError as exc:   # said again with the option and in the units typed
        if exc.q is None or np.ndim(exc.q) != 1:
            raise
        option = "--from" if np.array_equal(exc.q, q_start) else "--to"
        if option == "--from" and joints["--from"] is None:
            option = "the start (the home configuration: no --from given)"
        scale, units = joint_scale(arm, deg)
        shown = " ".join(f"{fmt_number(v, 4)} {unit}" for v, unit in zip(exc.q * scale, units, strict=True))
        raise CollisionError(f"{option} {shown}: the arm collides there ({pair_text(exc.contacts)})", q=exc.q,
                             contacts=exc.contacts) from None
    check = traj.sample(max(CHECK_RATE_HZ, 2.0 / traj.duration))
    clearance = float(np.min(world.clearance(check.q)))
    written = []
    if out is not None:
        samples = traj.sample(rate)
        written.append((write_npz if out.suffix.lower() == ".npz" else write_csv)(samples, out, force))
    if plot is not None:
        from armkit.plots import plot_pva, save_figure

        written.append(save_figure(plot_pva(traj, arm, degrees=deg), plot, force))
    if gif is not None:
        from armkit.animation import animate_trajectory

        written.append(animate_trajectory(arm, check.q, gif, t=check.t, title=f"{arm.name}: {scene.name}",
                                          scene=world))
    if json_output:
        print_json({"robot": arm.name, "scene": str(scene), "joint_names": arm.joint_names,
                    "q_start": traj.waypoints[0], "q_goal": traj.waypoints[-1], "duration_s": traj.duration,
                    "waypoints": traj.waypoints, "waypoint_times_s": traj.waypoint_times,
                    "peak_velocity": traj.peak_velocity, "max_velocity": limits[0],
                    "peak_acceleration": traj.peak_acceleration, "max_acceleration": limits[1],
                    "min_clearance_m": clearance, "seed": seed, "time_budget_s": time_budget,
                    "resolution_m": resolution, "written": [str(path) for path in written]},
                   {"q_start": JOINT_UNITS, "q_goal": JOINT_UNITS, "waypoints": JOINT_UNITS,
                    "peak_velocity": "rad/s, m/s", "max_velocity": "rad/s, m/s",
                    "peak_acceleration": "rad/s^2, m/s^2", "max_acceleration": "rad/s^2, m/s^2"})
        return
    console.print(_waypoint_table(arm, traj.waypoint_times, traj.waypoints, deg))
    console.print(trajectory_summary(arm, traj, limits, deg))
    console.print(f"collision-free at {resolution:g} m resolution; smallest clearance "
                  f"{fmt_number(clearance, 4)} m (sampled at {check.t.size / traj.duration:.4g} Hz)",
                  markup=False)
    for path in written:
        console.print(f"wrote {path}", markup=False)


def _waypoint_table(robot: Robot, times: np.ndarray, waypoints: np.ndarray, degrees: bool) -> Table:
    """The vertices of the planned path, with the times the motion passes them."""
    scale, units = joint_scale(robot, degrees)
    table = Table(title=escape(f"{robot.name}: collision-free path, {len(waypoints)} waypoints, "
                               f"{times[-1]:.4g} s"))
    table.add_column("#", justify="right")
    table.add_column(escape("t [s]"), justify="right")
    for name, unit in zip(robot.joint_names, units, strict=True):
        table.add_column(escape(f"{name} [{unit}]"), justify="right")
    for k, (t, q) in enumerate(zip(times, waypoints, strict=True), start=1):
        table.add_row(str(k), fmt_number(t, 4), *(fmt_number(v, 4) for v in q * scale))
    return table

