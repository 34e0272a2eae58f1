"""``armkit export`` (URDF, MJCF) and ``armkit sim`` (check and drive a robot in MuJoCo)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import numpy as np
import typer
from rich.markup import escape
from rich.table import Table

from armkit._io import check_output_path
from armkit.cli.app import (
    ALLOW_NEGATIVE,
    JOINT_UNITS,
    BaseOpt,
    LockOpt,
    RobotArg,
    TipOpt,
    app,
    check_limits_or_warn,
    console,
    err_console,
    fmt_number,
    load_robot,
    print_json,
    to_si,
    warn,
)
from armkit.errors import ArmkitError, InputError
from armkit.robot import Robot
from armkit.spatial.rotations import rotation_angle_between
from armkit.trajectory import read_trajectory

if TYPE_CHECKING:  # armkit.sim needs MuJoCo, imported only when a command runs
    from armkit.sim.runner import SimResult
    from armkit.sim.verify import PoseComparison

ForceOpt = Annotated[bool, typer.Option("--force", help="Overwrite existing output files.")]


def require_mujoco() -> None:
    """Raise a one-line error naming the missing extra if MuJoCo is not installed."""
    try:
        import mujoco  # noqa: F401
    except ImportError as exc:
        raise ArmkitError("this command needs MuJoCo: pip install 'armkit[sim]' "
                          "(or pip install mujoco)") from exc


@app.command("export")
def export_command(
    robot: RobotArg,
    urdf: Annotated[Path | None, typer.Option(help="Write a URDF file here.", show_default=False)] = None,
    mjcf: Annotated[Path | None, typer.Option(help="Write an MJCF (MuJoCo XML) file here.",
                                              show_default=False)] = None,
    no_gravity: Annotated[bool, typer.Option("--no-gravity", help="MJCF without gravity.")] = False,
    force: ForceOpt = False,
    json_output: Annotated[bool, typer.Option("--json", help="Print JSON instead.")] = False,
    base: BaseOpt = None,
    tip: TipOpt = None,
    lock: LockOpt = None,
) -> None:
    """Export a robot as URDF and/or MJCF (capsule links, masses, limits, servos, a 'tool' frame)."""
    from armkit.export import write_mjcf, write_urdf

    if urdf is None and mjcf is None:
        raise InputError("nothing to write: give --urdf FILE and/or --mjcf FILE")
    arm = load_robot(robot, base, tip, lock)
    for path, suffix in ((urdf, ".urdf"), (mjcf, ".xml")):
        if path is not None and path.suffix.lower() != suffix:
            raise InputError(f"output file {str(path)!r}: expected a name ending in {suffix}")
    for path in (urdf, mjcf):
        if path is not None:
            check_output_path(path, force, remedy="pass --force")
    written = []
    if urdf is not None:
        written.append(write_urdf(arm, urdf, overwrite=force))
    if mjcf is not None:
        written.append(write_mjcf(arm, mjcf, overwrite=force, gravity=not no_gravity))
    if json_output:
        print_json({"robot": arm.name, "written": [str(path) for path in written]})
        return
    for path in written:
        console.print(f"wrote {path}", highlight=False, markup=False)


def _comparison_table(table: PoseComparison, title: str) -> Table:
    out = Table(title=title)
    for name in ["#", "", *table.columns, "|dp| [m]", "rot [rad]"]:
        out.add_column(escape(name), justify="right")
    for k, label in enumerate(table.labels):
        out.add_row(label, "computed", *(fmt_number(v, 6) for v in table.computed[k]), "", "")
        out.add_row("", "simulated", *(fmt_number(v, 6) for v in table.simulated[k]), "", "")
        out.add_row("", "error", *(f"{v:.1e}" for v in table.error[k]), f"{table.position_error[k]:.1e}",
                    f"{table.orientation_error[k]:.1e}", end_section=True)
    return out


def _tracking_summary(robot: Robot, result: SimResult) -> dict:
    T_command = robot.fk(result.q_command)
    return {"duration_s": float(result.t[-1] - result.t[0]), "steps": len(result.t),
            "gravity": result.gravity, "gravity_compensation": result.gravity_compensation,
            "max_joint_error": np.abs(result.joint_error).max(axis=0),
            "max_tool_position_error_m": float(np.linalg.norm(
                result.T_tool[:, :3, 3] - T_command[:, :3, 3], axis=-1).max()),
            "max_tool_orientation_error_rad": float(rotation_angle_between(result.T_tool, T_command).max())}


def _tracking_lines(robot: Robot, summary: dict) -> list[str]:
    """The tracking summary as lines of text, a unit on every number."""
    on = {True: "on", False: "off"}
    units = ["m" if prismatic else "rad" for prismatic in robot.chain.prismatic]
    joint_errors = ", ".join(f"{name} {error:.2e} {unit}" for name, error, unit in
                             zip(robot.joint_names, summary["max_joint_error"], units, strict=True))
    return [f"duration: {summary['duration_s']:.4g} s ({summary['steps']} steps); gravity "
            f"{on[summary['gravity']]}, gravity compensation {on[summary['gravity_compensation']]}",
            f"largest |q_MuJoCo - q_command|: {joint_errors}",
            f"largest tool error (MuJoCo vs FK of the command): position "
            f"{summary['max_tool_position_error_m']:.2e} m, "
            f"rotation {summary['max_tool_orientation_error_rad']:.2e} rad"]


@app.command("sim", context_settings=ALLOW_NEGATIVE)
def sim_command(
    robot: RobotArg,
    q: Annotated[list[float] | None, typer.Argument(help="Joint values q1 ... qn to check.",
                                                    show_default=False)] = None,
    random: Annotated[int, typer.Option(help="Check this many random configurations (no Q).")] = 5,
    seed: Annotated[int, typer.Option(min=0, help="Seed of the random configurations (0 or more).")] = 0,
    trajectory: Annotated[Path | None, typer.Option(
        help="Drive this trajectory (CSV or NPZ: t, q1..qn[, qd1..qdn]) instead.",
        show_default=False)] = None,
    gravity: Annotated[bool, typer.Option(help="Gravity on or off in the simulation.")] = True,
    compensation: Annotated[bool, typer.Option(help="Gravity compensation (qfrc_bias) in the "
                                                    "servos.")] = True,
    euler: Annotated[str, typer.Option(help="Angle convention of the table.")] = "xyz-fixed",
    deg: Annotated[bool, typer.Option("--deg", help="Joint values and angles in degrees.")] = False,
    gif: Annotated[Path | None, typer.Option(help="With --trajectory: write an animation GIF.",
                                             show_default=False)] = None,
    png: Annotated[Path | None, typer.Option(help="Write a picture of the (first) configuration.",
                                             show_default=False)] = None,
    force: ForceOpt = False,
    json_output: Annotated[bool, typer.Option("--json", help="Print JSON instead of tables.")] = False,
    base: BaseOpt = None,
    tip: TipOpt = None,
    lock: LockOpt = None,
) -> None:
    """Check a robot in MuJoCo: tool pose computed vs simulated, or a trajectory tracked by servos."""
    from armkit.animation import animate_trajectory, plot_configuration

    require_mujoco()
    from armkit.sim.runner import Simulation
    from armkit.sim.verify import compare_poses

    arm = load_robot(robot, base, tip, lock)
    if random < 1:
        raise InputError(f"--random {random}: expected at least 1 configuration")
    for path in (gif, png):
        if path is not None:
            check_output_path(path, force, remedy="pass --force")
    sim = Simulation(arm, gravity=gravity, gravity_compensation=compensation)
    if trajectory is not None:
        t, q_traj, qd = read_trajectory(trajectory, arm)
        outside = ~arm.within_limits(q_traj)
        if outside.any():  # the servos stop at the limits: say so before the table shows it
            first = int(np.argmax(outside))
            warn(f"the trajectory leaves the joint limits ({outside.sum()} of {len(t)} samples, first at "
                 f"t = {t[first]:.3g} s: " + "; ".join(arm.limit_violations(q_traj[first], deg)) + ")")
        result = sim.run(t, q_traj, qd)
        summary = _tracking_summary(arm, result)
        if json_output:
            print_json({"robot": arm.name, **summary,
                        "max_joint_error_units": ["m" if p else "rad" for p in arm.chain.prismatic]},
                       {"max_joint_error": JOINT_UNITS})
        else:
            for line in _tracking_lines(arm, summary):
                console.print(line, markup=False)
        if gif is not None:
            stride = max(1, len(result.t) // 200)
            animate_trajectory(arm, result.q[::stride], gif, t=result.t[::stride], title=arm.name)
            err_console.print(f"wrote {gif}", highlight=False)
        if png is not None:
            plot_configuration(arm, result.q[0], png)
            err_console.print(f"wrote {png}", highlight=False)
        return
    configurations = (to_si(arm, q, deg)[None] if q else arm.random_q(random, rng=seed))
    if q:
        check_limits_or_warn(arm, configurations[0], strict=False, degrees=deg)
    settled = np.array([sim.move(arm.home, q_k, 1.0, 0.5).T_tool[-1] for q_k in configurations])
    computed = arm.fk(configurations)
    rows = {"mj_kinematics (qpos set)": compare_poses(computed, sim.tool_pose(configurations),
                                                      convention=euler, degrees=deg),
            "servos from home in 1 s, then 0.5 s hold": compare_poses(computed, settled, convention=euler,
                                                                      degrees=deg)}
    if json_output:  # SI, whatever --deg says
        rows = {name: compare_poses(computed, simulated, convention=euler)
                for name, simulated in zip(rows, (sim.tool_pose(configurations), settled), strict=True)}
        print_json({"robot": arm.name, "q": configurations, "convention": euler, **{
            name: {"computed": c.computed, "simulated": c.simulated, "error": c.error,
                   "position_error_m": c.position_error, "orientation_error_rad": c.orientation_error}
            for name, c in rows.items()}},
                   {"q": JOINT_UNITS, "computed": "x y z in m, three angles in rad",
                    "simulated": "as computed", "error": "as computed"})
    else:
        for name, table in rows.items():
            console.print(_comparison_table(table, f"{arm.name}: armkit FK vs MuJoCo, {name} "
                                                   f"(gravity {'on' if gravity else 'off'})"))
    if png is not None:
        plot_configuration(arm, configurations[0], png)
        err_console.print(f"wrote {png}", highlight=False)
