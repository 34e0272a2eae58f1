"""``armkit traj``: a minimum-jerk trajectory through waypoints, within the robot's limits."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import numpy as np
import typer
from rich.markup import escape
from rich.table import Table

from armkit._format import fmt_significant
from armkit._io import check_output_path
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
    parse_floats,
    print_json,
    reject_unknown_options,
    warn,
)
from armkit.cli.dynamics import DensityOpt, with_inertia_options
from armkit.errors import InputError
from armkit.robot import Robot
from armkit.trajectory._checks import durations_from_times
from armkit.trajectory.export import write_csv, write_npz
from armkit.trajectory.waypoints import read_waypoints

if TYPE_CHECKING:  # the trajectory object and its planner load SciPy: imported where a plan is made
    from armkit.trajectory.joint_trajectory import JointTrajectory, TrajectoryTorques

#: Sampling rate [Hz] of ``--torques``' peaks (a 1 kHz controller's).
TORQUE_RATE_HZ = 1000.0

#: Options every command that writes a timed motion takes (``traj``, ``plan``).
RateOpt = Annotated[float, typer.Option(help="Sampling rate of --out (Hz).")]
OutOpt = Annotated[Path | None, typer.Option(help="Write samples t,q1..,qd1..,qdd1.. to this .csv or .npz "
                                                  "file (SI units).", show_default=False)]
PlotOpt = Annotated[Path | None, typer.Option(help="Save the position/velocity/acceleration figure (.png, "
                                                   ".svg, .pdf).", show_default=False)]
ForceOpt = Annotated[bool, typer.Option("--force", help="Replace existing output files.")]
JsonOpt = Annotated[bool, typer.Option("--json", help="Print JSON (SI units) instead of tables.")]
MaxVelocityOpt = Annotated[str | None, typer.Option(
    "--max-velocity", metavar="V[,V...]",
    help="Velocity limits in place of the robot file's: one value for every joint or one per joint, "
         "comma-separated (rad/s, m/s; deg/s with --deg), e.g. for an arm whose file has none.",
    show_default=False)]
MaxAccelerationOpt = Annotated[str | None, typer.Option(
    "--max-acceleration", metavar="A[,A...]",
    help="Acceleration limits in place of the robot file's (a URDF has none): one value or one per "
         "joint, comma-separated (rad/s², m/s²; deg/s² with --deg).", show_default=False)]


def check_output_file(path: Path | None, suffixes: tuple[str, ...], force: bool, what: str) -> None:
    """``path`` (an option ``what``'s value, None if not given) ends in one of ``suffixes`` and
    may be written (:func:`armkit._io.check_output_path`, overwritten only with ``--force``)."""
    if path is None:
        return
    if path.suffix.lower() not in suffixes:
        raise InputError(f"{what} {path}: expected a file name ending in {', '.join(suffixes)}")
    check_output_path(path, force, remedy="pass --force")


def _durations(values: list[str] | None, durations: bool, times: bool, auto: bool) -> np.ndarray | None:
    reject_unknown_options(values or [])
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


def joint_scale(robot: Robot, degrees: bool) -> tuple[np.ndarray, list[str]]:
    """Per joint: the factor from SI to the shown unit, and the unit (deg with ``--deg``, rad, m)."""
    revolute = ~np.asarray(robot.chain.prismatic)
    scale = np.where(revolute & degrees, 180 / np.pi, 1.0)
    units = ["m" if not r else ("deg" if degrees else "rad") for r in revolute]
    return scale, units


def _limit_cells(peak: float, limit: float, scale: float, unit: str, significant: float | None = None
                 ) -> list[str]:
    """``peak``, ``limit`` and ``peak / limit`` with units; a missing limit is "none" and its ratio "-".
    With ``significant`` (the column's largest magnitude), values in significant digits
    (:func:`fmt_significant`: torques span orders of magnitude), else 4 decimals."""
    def number(value: float) -> str:
        return fmt_number(value, 4) if significant is None else fmt_significant(value, significant)

    if not np.isfinite(limit):
        return [f"{number(peak * scale)} {unit}", "none", "-"]
    return [f"{number(peak * scale)} {unit}", f"{number(limit * scale)} {unit}", fmt_number(peak / limit, 3)]


def trajectory_summary(robot: Robot, traj: JointTrajectory, limits: tuple[np.ndarray, np.ndarray],
                       degrees: bool) -> Table:
    """The table ``armkit traj`` and ``armkit plan`` print: per joint its peaks against the limits."""
    table = Table(title=escape(f"{robot.name}: {traj.durations.size} segments, "
                               f"{traj.duration:.4g} s"),
                  caption="peaks computed exactly from the polynomials; ratio = peak / limit; "
                          "none: neither the robot file nor --max-velocity/--max-acceleration gives a limit")
    for column in ("joint", "peak |qd|", "limit", "ratio", "peak |qdd|", "limit", "ratio"):
        table.add_column(column, justify="right")
    scale, units = joint_scale(robot, degrees)
    for j, name in enumerate(robot.joint_names):
        table.add_row(escape(name),
                      *_limit_cells(traj.peak_velocity[j], limits[0][j], scale[j], f"{units[j]}/s"),
                      *_limit_cells(traj.peak_acceleration[j], limits[1][j], scale[j], f"{units[j]}/s²"))
    return table


def _torque_table(robot: Robot, torques: TrajectoryTorques, rate_hz: float) -> Table:
    """Peak |torque| per joint along the trajectory against the robot's torque limits."""
    table = Table(title="Joint torques (inverse dynamics of the samples)",
                  caption=f"at {rate_hz:g} Hz; ratio = peak / limit; none: no torque limit given")
    for column in ("joint", "peak |torque|", "limit", "ratio"):
        table.add_column(column, justify="right")
    largest = float(np.max(torques.peak))
    for j, name in enumerate(robot.joint_names):
        table.add_row(escape(name), *_limit_cells(torques.peak[j], robot.max_torque[j], 1.0,
                                                  "N" if robot.chain.prismatic[j] else "N m", largest))
    return table


def _waypoint_table(robot: Robot, traj: JointTrajectory, degrees: bool) -> Table:
    scale, units = joint_scale(robot, degrees)
    table = Table(title="Waypoints: IK solutions, each nearest the previous")
    table.add_column("#", justify="right")
    table.add_column(escape("t [s]"), justify="right")
    for name, unit in zip(robot.joint_names, units, strict=True):
        table.add_column(escape(f"{name} [{unit}]"), justify="right")
    for k, (t, q) in enumerate(zip(traj.waypoint_times, traj.waypoints, strict=True), start=1):
        table.add_row(str(k), fmt_number(t, 4), *(fmt_number(v, 4) for v in q * scale))
    return table


def _unlimited_warning(robot: Robot, limits: tuple[np.ndarray, np.ndarray]) -> str | None:
    """A warning naming the joints whose velocity or acceleration neither the robot file nor an
    option limits."""
    parts = []
    for what, values in zip(("max_velocity", "max_acceleration"), limits, strict=True):
        missing = [name for name, limit in zip(robot.joint_names, values, strict=True)
                   if not np.isfinite(limit)]
        if missing:
            parts.append(f"no {what} for {', '.join(missing)}")
    if not parts:
        return None
    urdf = " (a URDF has no acceleration limits)" if robot.urdf is not None else ""
    return (f"{robot.name}: {'; '.join(parts)} in the robot file{urdf}, so --auto-time cannot keep those "
            f"joints within such a limit; their peaks below are whatever the other limits give "
            f"(give them with --max-velocity/--max-acceleration, one value or one per joint, or add them "
            f"to the robot file, or give --durations)")


def limit_option(text: str | None, robot: Robot, degrees: bool, option: str) -> np.ndarray | None:
    """``--max-velocity``/``--max-acceleration``: one value or one per joint, comma-separated, in
    SI units (revolute joints in deg/s, deg/s² with ``--deg``); None if not given."""
    if text is None:
        return None
    values = np.array(parse_floats(text.replace(",", " ").split(), option))
    if values.size not in (1, robot.n):
        raise InputError(f"{option} {text!r}: expected one limit for every joint or {robot.n} (one per "
                         f"joint, comma-separated), got {values.size}")
    if np.any(np.isnan(values)) or np.any(values <= 0):   # said as typed (before any --deg conversion)
        raise InputError(f"{option} {text!r}: expected positive limits (inf for none)")
    return np.where(degrees & ~np.asarray(robot.chain.prismatic), np.radians(values), values)


@app.command("traj", context_settings=ALLOW_NEGATIVE)
def traj_command(
    robot: RobotArg,
    duration_values: Annotated[list[str] | None, typer.Argument(
        metavar="[D... | T...]", help="Segment durations (s) after --durations, or waypoint times (s) "
                                      "after --times.", show_default=False)] = None,
    waypoints: Annotated[Path, typer.Option(
        help="CSV file, one waypoint per line (header allowed): joint values (rad, m; deg with --deg), "
             "or with --poses x y z a b c (m, rad; deg with --deg).", show_default=False)] = ...,
    deg: Annotated[bool, typer.Option("--deg", help="Waypoint angles (revolute joints, pose angles) in "
                                                    "degrees; printed joint values in degrees.")] = False,
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
    rate: RateOpt = 100.0,
    out: OutOpt = None,
    plot: PlotOpt = None,
    plot_path: Annotated[Path | None, typer.Option(help="Save the 3-D tool path figure.",
                                                   show_default=False)] = None,
    force: ForceOpt = False,
    json_output: JsonOpt = False,
    torques: Annotated[bool, typer.Option("--torques", help="Joint torques along the motion (N m, N; "
                                                            "sampled at 1 kHz) against the torque limits, "
                                                            "and a torque row in --plot.")] = False,
    estimate_inertia: DensityOpt = None,
    max_velocity: MaxVelocityOpt = None,
    max_acceleration: MaxAccelerationOpt = None,
    base: BaseOpt = None,
    tip: TipOpt = None,
    lock: LockOpt = None,
) -> None:
    """Minimum-jerk trajectory through waypoints (piecewise quintic, continuous qd and qdd), inside the
    joint position limits all the way (a joint that would overshoot one comes to rest at the waypoint).

    Example: armkit traj probot-anno --waypoints examples/data/probot_seed_poses.csv --poses
    --durations 10 10 10 --plot pva.png
    """
    segment_durations = _durations(duration_values, durations, times, auto_time)
    check_output_file(out, (".csv", ".npz"), force, "--out")
    for path, what in ((plot, "--plot"), (plot_path, "--plot-path")):
        check_output_file(path, (".png", ".svg", ".pdf"), force, what)
    if not rate > 0:
        raise InputError(f"--rate: expected a positive sampling rate (Hz), got {rate:g}")
    arm = with_inertia_options(load_robot(robot, base, tip, lock), estimate_inertia, None)
    rows = read_waypoints(waypoints, 6 if poses else arm.n)
    if deg:  # revolute joint columns, or the three pose angles
        angles = np.zeros(rows.shape[1], dtype=bool)
        angles[3:] = True
        rows = np.where(angles if poses else ~np.asarray(arm.chain.prismatic), np.radians(rows), rows)
    if segment_durations is not None and segment_durations.size != len(rows) - 1:
        wanted = (f"{len(rows) - 1} segment durations" if durations else f"{len(rows)} waypoint times")
        raise InputError(f"{'--durations' if durations else '--times'}: {len(rows)} waypoints need "
                         f"{wanted}, got {len(duration_values)}")
    from armkit.trajectory.plan import plan_trajectory, planning_limits
    from armkit.trajectory.waypoints import joint_waypoints

    if not poses:
        joint_waypoints(arm, rows, deg)  # a waypoint outside a limit is said in the units typed

    limits = planning_limits(arm, limit_option(max_velocity, arm, deg, "--max-velocity"),
                             limit_option(max_acceleration, arm, deg, "--max-acceleration"))
    traj = plan_trajectory(arm, rows, segment_durations, poses=poses, convention=euler,
                           max_velocity=limits[0], max_acceleration=limits[1])
    samples = traj.sample(rate) if out is not None else None
    torque_samples = traj.torques(arm, TORQUE_RATE_HZ) if torques else None
    warnings = []  # (the path itself stays inside the position limits: plan_trajectory)
    if auto_time and (message := _unlimited_warning(arm, limits)) is not None:
        warnings.append(message)
    if segment_durations is not None and np.any(traj.stretch > 1):
        warnings.append("stretched to meet the limits: segment factors "
                        + ", ".join(fmt_number(k, 4) for k in traj.stretch)
                        + f" (total {fmt_number(traj.duration / traj.requested_durations.sum(), 4)}x)")
    for message in warnings:
        warn(message)
    written = []  # (path, what it holds)
    if out is not None:
        written.append(((write_npz if out.suffix.lower() == ".npz" else write_csv)(samples, out, force),
                        f" ({samples.t.size} samples at {rate:g} Hz)"))
    if plot is not None or plot_path is not None:
        from armkit.plots import plot_pva, plot_tool_path, save_figure  # matplotlib only when plotting
    if plot is not None:
        written.append((save_figure(plot_pva(traj, arm, torques=torques, degrees=deg), plot, force), ""))
    if plot_path is not None:
        written.append((save_figure(plot_tool_path(arm, traj), plot_path, force), ""))
    if json_output:
        print_json({"robot": arm.name, "joint_names": arm.joint_names, "duration_s": traj.duration,
                    "segment_durations_s": traj.durations, "stretch": traj.stretch,
                    "waypoint_times_s": traj.waypoint_times, "waypoints": traj.waypoints,
                    "peak_velocity": traj.peak_velocity, "max_velocity": limits[0],
                    "peak_acceleration": traj.peak_acceleration, "max_acceleration": limits[1],
                    "peak_torque": None if torque_samples is None else torque_samples.peak,
                    "max_torque": arm.max_torque,
                    "warnings": warnings, "samples": None if samples is None else samples.t.size,
                    "rate_hz": rate, "written": [str(path) for path, _ in written]},
                   {"waypoints": JOINT_UNITS, "peak_velocity": "rad/s, m/s", "max_velocity": "rad/s, m/s",
                    "peak_acceleration": "rad/s^2, m/s^2", "max_acceleration": "rad/s^2, m/s^2",
                    "peak_torque": "N m, N", "max_torque": "N m, N",
                    "limits": "null where neither the robot file nor --max-velocity/--max-acceleration "
                              "gives one"})
        return
    if poses:
        console.print(_waypoint_table(arm, traj, deg))
    console.print(trajectory_summary(arm, traj, limits, deg))
    if torque_samples is not None:
        console.print(_torque_table(arm, torque_samples, TORQUE_RATE_HZ))
    final = ", ".join(f"{d:.4g}" for d in traj.durations)
    console.print(f"segment durations [s]: {final}", markup=False)
    for path, what in written:
        console.print(f"wrote {path}{what}", markup=False)
