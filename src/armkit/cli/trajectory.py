"""``armkit traj``: a minimum-jerk trajectory through waypoints, within the robot's limits."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import numpy as np
import typer
from rich.table import Table

from armkit._io import check_output_path
from armkit.cli.app import (
    ALLOW_NEGATIVE,
    BaseOpt,
    LockOpt,
    RobotArg,
    TipOpt,
    app,
    console,
    load_robot,
    parse_floats,
    warn,
)
from armkit.errors import InputError
from armkit.robot import Robot
from armkit.trajectory import JointTrajectory, durations_from_times, plan_trajectory, read_waypoints
from armkit.trajectory.export import write_csv, write_npz


def _check_output(path: Path | None, suffixes: tuple[str, ...], force: bool, what: str) -> None:
    if path is None:
        return
    if path.suffix.lower() not in suffixes:
        raise InputError(f"{what} {path}: expected a file name ending in {', '.join(suffixes)}")
    check_output_path(path, force, remedy="pass --force")


def _durations(values: list[str] | None, durations: bool, times: bool, auto: bool) -> np.ndarray | None:
    if values and not (durations or times):
        raise InputError(f"unexpected values {' '.join(values)}: segment durations are given "
                         f"after --durations (or waypoint times after --times)")
    if durations + times + auto != 1:
        raise InputError("give one of --durations D1 D2 ... (one per segment, seconds), "
                         "--times T1 T2 ... (one per waypoint, seconds) or --auto-time")
    if auto:
        return None
    option = "--durations" if durations else "--times"
    if not values:
        raise InputError(f"{option}: expected numbers (seconds) after it, got none")
    numbers = np.array(parse_floats(values, option))
    return numbers if durations else durations_from_times(numbers)


def _summary(robot: Robot, traj: JointTrajectory) -> Table:
    units = "rad/s, rad/s²" + (" (prismatic joints: m/s, m/s²)" if any(robot.chain.prismatic) else "")
    table = Table(title=f"{robot.name}: {traj.durations.size} segments, {traj.duration:.4g} s",
                  caption=f"peaks computed exactly from the polynomials; units {units}; "
                          f"ratio = peak / limit")
    for column in ("joint", "peak |qd|", "limit", "ratio", "peak |qdd|", "limit", "ratio"):
        table.add_column(column, justify="right")
    ratio_v = traj.peak_velocity / robot.max_velocity
    ratio_a = traj.peak_acceleration / robot.max_acceleration
    for j, name in enumerate(robot.joint_names):
        table.add_row(name, f"{traj.peak_velocity[j]:.4f}", f"{robot.max_velocity[j]:.4f}",
                      f"{ratio_v[j]:.3f}", f"{traj.peak_acceleration[j]:.4f}",
                      f"{robot.max_acceleration[j]:.4f}", f"{ratio_a[j]:.3f}")
    return table


def _waypoint_table(robot: Robot, traj: JointTrajectory) -> Table:
    table = Table(title="Waypoints: IK solutions, each nearest the previous (rad, m)")
    table.add_column("#", justify="right")
    table.add_column("t (s)", justify="right")
    for name in robot.joint_names:
        table.add_column(name, justify="right")
    for k, (t, q) in enumerate(zip(traj.waypoint_times, traj.waypoints, strict=True), start=1):
        table.add_row(str(k), f"{t:.4g}", *(f"{v:.4f}" for v in np.round(q, 4) + 0.0))
    return table


@app.command("traj", context_settings=ALLOW_NEGATIVE)
def traj_command(
    robot: RobotArg,
    duration_values: Annotated[list[str] | None, typer.Argument(
        metavar="[D... | T...]", help="Segment durations (s) after --durations, or waypoint times (s) "
                                      "after --times.", show_default=False)] = None,
    waypoints: Annotated[Path, typer.Option(
        help="CSV file, one waypoint per line (header allowed): joint values (rad, m), or with "
             "--poses x y z a b c (m, rad).", show_default=False)] = ...,
    poses: Annotated[bool, typer.Option("--poses", help="Waypoints are tool poses, solved by IK "
                                                        "(each nearest the previous).")] = False,
    euler: Annotated[str, typer.Option(help="Angle convention of the poses, e.g. xyz-fixed (roll "
                                            "pitch yaw), zyz-euler.")] = "xyz-fixed",
    durations: Annotated[bool, typer.Option("--durations", help="The segment durations D... that "
                                                                "follow (s), one per segment; "
                                                                "stretched if a limit needs it.")] = False,
    times: Annotated[bool, typer.Option("--times", help="The waypoint times T... that follow (s), "
                                                        "one per waypoint, increasing.")] = False,
    auto_time: Annotated[bool, typer.Option("--auto-time", help="The shortest durations within the "
                                                                "velocity and acceleration limits.")] = False,
    rate: Annotated[float, typer.Option(help="Sampling rate of --out (Hz).")] = 100.0,
    out: Annotated[Path | None, typer.Option(help="Write samples t,q1..,qd1..,qdd1.. to this .csv "
                                                  "or .npz file (SI units).", show_default=False)] = None,
    plot: Annotated[Path | None, typer.Option(help="Save the position/velocity/acceleration figure "
                                                   "(.png, .svg, .pdf).", show_default=False)] = None,
    plot_path: Annotated[Path | None, typer.Option(help="Save the 3-D tool path figure.",
                                                   show_default=False)] = None,
    force: Annotated[bool, typer.Option("--force", help="Replace existing output files.")] = False,
    base: BaseOpt = None,
    tip: TipOpt = None,
    lock: LockOpt = None,
) -> None:
    """Minimum-jerk trajectory through waypoints (piecewise quintic, continuous qd and qdd).

    Example: armkit traj probot-anno --waypoints examples/data/probot_seed_poses.csv --poses
    --durations 10 10 10 --plot pva.png
    """
    segment_durations = _durations(duration_values, durations, times, auto_time)
    _check_output(out, (".csv", ".npz"), force, "--out")
    for path, what in ((plot, "--plot"), (plot_path, "--plot-path")):
        _check_output(path, (".png", ".svg", ".pdf"), force, what)
    if not rate > 0:
        raise InputError(f"--rate: expected a positive sampling rate (Hz), got {rate:g}")
    arm = load_robot(robot, base, tip, lock)
    rows = read_waypoints(waypoints, 6 if poses else arm.n)
    if segment_durations is not None and segment_durations.size != len(rows) - 1:
        wanted = (f"{len(rows) - 1} segment durations" if durations else f"{len(rows)} waypoint times")
        raise InputError(f"{'--durations' if durations else '--times'}: {len(rows)} waypoints need "
                         f"{wanted}, got {len(duration_values)}")
    traj = plan_trajectory(arm, rows, segment_durations, poses=poses, convention=euler)
    samples = traj.sample(rate)
    for message in traj.position_limit_violations(arm):
        warn(message)
    if poses:
        console.print(_waypoint_table(arm, traj))
    console.print(_summary(arm, traj))
    final = ", ".join(f"{d:.4g}" for d in traj.durations)
    console.print(f"segment durations [s]: {final}", markup=False)
    if segment_durations is not None and np.any(traj.stretch > 1):
        warn("stretched to meet the limits: segment factors "
             + ", ".join(f"{k:.4g}" for k in traj.stretch)
             + f" (total {traj.duration / traj.requested_durations.sum():.4g}x)")
    if out is not None:
        (write_npz if out.suffix.lower() == ".npz" else write_csv)(samples, out, force)
        console.print(f"wrote {out} ({samples.t.size} samples at {rate:g} Hz)", markup=False)
    if plot is not None or plot_path is not None:
        from armkit.plots import plot_pva, plot_tool_path, save_figure  # matplotlib only when plotting
    if plot is not None:
        save_figure(plot_pva(traj, arm), plot, force)
        console.print(f"wrote {plot}", markup=False)
    if plot_path is not None:
        save_figure(plot_tool_path(arm, traj), plot_path, force)
        console.print(f"wrote {plot_path}", markup=False)
