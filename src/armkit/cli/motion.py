"""``armkit move`` and ``armkit rotate``: the two velocity-control experiments from the CLI."""

from __future__ import annotations

from typing import TYPE_CHECKING, Annotated

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
    err_console,
    fmt_number,
    load_robot,
    option_values,
    print_json,
    to_si,
)
from armkit.errors import InputError, JointLimitError
from armkit.robot import Robot
from armkit.spatial.transforms import pose_from_transform

if TYPE_CHECKING:
    from armkit.control.motions import MotionResult

StartValues = Annotated[list[str] | None, typer.Argument(
    metavar="[Q...]", help="The rest of the --from joint values.", show_default=False)]
FromOpt = Annotated[str | None, typer.Option(
    "--from", metavar="Q...", help="Start joint values, e.g. --from 0 0 0 0 0 0 or --from 0,0,0,0,0,0 "
                                   "(rad and m; deg with --deg; default all zeros).", show_default=False)]
FrameOpt = Annotated[str, typer.Option(help="base or tool: the frame the vector is written in "
                                            "(tool = the start tool frame).")]
DtOpt = Annotated[float | None, typer.Option(
    "--dt", help="Control period in seconds [default: 0.002, armkit.control.DEFAULT_DT].",
    show_default=False)]
DegOpt = Annotated[bool, typer.Option("--deg", help="Revolute joint values and angles (also the "
                                                    "printed ones) in degrees.")]
JsonOpt = Annotated[bool, typer.Option("--json", help="Print JSON (SI units) instead of tables.")]


def _start(robot: Robot, first: str | None, rest: list[str] | None, degrees: bool) -> np.ndarray:
    words = option_values(first, rest, "--from", "start joint values")
    q = np.zeros(robot.n) if words is None else to_si(robot, words, degrees, "--from")
    if violations := robot.limit_violations(q, degrees):  # said in the units typed
        raise JointLimitError("--from: " + "; ".join(violations), q, **robot.chain.limit_fields(q))
    return q


def _report(robot: Robot, result: MotionResult, title: str, degrees: bool, json_output: bool) -> None:
    """Print the final joints, final and target poses and the errors; exit 1 if it stopped early."""
    angle_scale = 180 / np.pi if degrees else 1.0
    unit = "deg" if degrees else "rad"
    q_shown = np.where(robot.chain.prismatic, result.q_final, result.q_final * angle_scale)
    final, target = result.pose_final, result.target
    if json_output:
        print_json({"robot": robot.name, "success": result.success, "message": result.message,
                    "duration": result.t[-1], "q_start": result.q[0], "q_final": result.q_final,
                    "position_final": final[:3, 3], "rpy_final": pose_from_transform(final)[3:],
                    "position_target": target[:3, 3], "rpy_target": pose_from_transform(target)[3:],
                    "position_error": result.position_error,
                    "orientation_error": result.orientation_error,
                    "max_position_error": result.max_position_error,
                    "max_orientation_error": result.max_orientation_error,
                    "max_joint_speed_ratio": np.max(np.abs(result.qd) / robot.max_velocity),
                    "min_singular_value": result.sigma_min.min()},
                   {"duration": "s", "q_start": JOINT_UNITS, "q_final": JOINT_UNITS, "position_final": "m",
                    "rpy_final": "rad (xyz-fixed)", "position_target": "m", "rpy_target": "rad (xyz-fixed)",
                    "position_error": "m", "orientation_error": "rad", "max_position_error": "m",
                    "max_orientation_error": "rad", "min_singular_value": "m/s and rad/s mixed"})
    else:
        joints = Table(title=escape(f"{robot.name}: {title}"), caption="limit: the joint's max_velocity; "
                                                                      "- where the robot file gives none")
        for column in ("joint", "start", "final", "peak |qd| / limit"):
            joints.add_column(escape(column), justify="right")
        start = np.where(robot.chain.prismatic, result.q[0], result.q[0] * angle_scale)
        peaks = np.max(np.abs(result.qd), axis=0)
        for j, name in enumerate(robot.joint_names):
            joint_unit = "m" if robot.chain.prismatic[j] else unit
            limit = robot.max_velocity[j]
            joints.add_row(escape(name), f"{fmt_number(start[j], 6)} {joint_unit}",
                           f"{fmt_number(q_shown[j], 6)} {joint_unit}",
                           fmt_number(peaks[j] / limit, 3) if np.isfinite(limit) else "-")
        console.print(joints)
        poses = Table(title=escape(f"tool pose after {fmt_number(result.t[-1], 3)} s (roll pitch yaw = "
                                   f"xyz-fixed angles)"))
        for column in ("", "x [m]", "y [m]", "z [m]", f"roll [{unit}]", f"pitch [{unit}]", f"yaw [{unit}]"):
            poses.add_column(escape(column), justify="right")
        for label, T in (("final", final), ("target", target)):
            poses.add_row(label, *(fmt_number(v, 6) for v in pose_from_transform(T, "xyz-fixed", degrees)))
        console.print(poses)
        console.print(f"pose error: position {result.position_error:.3g} m, orientation "
                      f"{result.orientation_error * angle_scale:.3g} {unit}; largest along the way: "
                      f"{result.max_position_error:.3g} m, "
                      f"{result.max_orientation_error * angle_scale:.3g} {unit}", markup=False)
    if not result.success:
        err_console.print(f"[red]stopped:[/red] {result.message}", highlight=False, soft_wrap=True)
        raise typer.Exit(1)


@app.command("move", context_settings=ALLOW_NEGATIVE)
def move_command(
    robot: RobotArg,
    start_values: StartValues = None,
    start: FromOpt = None,
    by: Annotated[tuple[float, float, float], typer.Option(
        "--by", help="Tool displacement DX DY DZ, in metres.", show_default=False)] = ...,
    duration: Annotated[float, typer.Option(help="Duration in seconds (quintic time law).")] = 5.0,
    frame: FrameOpt = "base",
    dt: DtOpt = None,
    deg: DegOpt = False,
    json_output: JsonOpt = False,
    base: BaseOpt = None,
    tip: TipOpt = None,
    lock: LockOpt = None,
) -> None:
    """Move the tool along a straight line (closed-loop resolved-rate control).

    Exits with code 1 if the motion stopped at a joint limit or ended off its target.

    Example: armkit move probot-anno --from 0 0 0 0 0 0 --by 0.15 0 -0.15 --duration 3
    """
    from armkit.control.motions import DEFAULT_DT, move_linear

    arm = load_robot(robot, base, tip, lock)
    q0 = _start(arm, start, start_values, deg)
    result = move_linear(arm, q0, np.array(by), duration, frame=frame, dt=DEFAULT_DT if dt is None else dt,
                         message_degrees=deg and not json_output)  # JSON is in SI units
    _report(arm, result, f"straight move by {list(by)} m ({frame} frame)", deg, json_output)


@app.command("rotate", context_settings=ALLOW_NEGATIVE)
def rotate_command(
    robot: RobotArg,
    start_values: StartValues = None,
    start: FromOpt = None,
    axis: Annotated[tuple[float, float, float], typer.Option(
        "--axis", help="Rotation axis X Y Z through the tool origin.", show_default=False)] = ...,
    angle: Annotated[float, typer.Option(help="Signed angle about the axis (rad; deg with --deg).",
                                         show_default=False)] = ...,
    rate: Annotated[float | None, typer.Option(
        help="Constant angular speed (rad/s; deg/s with --deg); default 0.2 rad/s "
             "unless --duration is given.", show_default=False)] = None,
    duration: Annotated[float | None, typer.Option(
        help="Duration in seconds of a smooth (quintic) turn, instead of --rate.",
        show_default=False)] = None,
    frame: FrameOpt = "base",
    dt: DtOpt = None,
    deg: DegOpt = False,
    json_output: JsonOpt = False,
    base: BaseOpt = None,
    tip: TipOpt = None,
    lock: LockOpt = None,
) -> None:
    """Turn the tool about an axis through its own origin, keeping its position.

    Stops at a joint limit (exit code 1, naming the joint) rather than passing it.

    Example: armkit rotate probot-anno --from 0 0 0 0 0 0 --axis 1 0 0 --angle -180 --rate 11.46 --deg
    """
    from armkit.control.motions import DEFAULT_DT, rotate_about_tool_point

    arm = load_robot(robot, base, tip, lock)
    q0 = _start(arm, start, start_values, deg)
    scale = np.pi / 180 if deg else 1.0
    if rate is not None and rate < 0 < angle:
        unit = "deg" if deg else "rad"
        raise InputError(f"--angle {angle:g} {unit} and --rate {rate:g} {unit}/s have opposite signs; "
                         f"give the direction once (the sign of --angle)")
    if rate is None and duration is None:
        rate = 0.2 / scale
    result = rotate_about_tool_point(arm, q0, np.array(axis), angle * scale,
                                     angular_velocity=None if rate is None else rate * scale,
                                     duration=duration, frame=frame, dt=DEFAULT_DT if dt is None else dt,
                                     message_degrees=deg and not json_output)  # JSON is in SI units
    _report(arm, result, f"turn about {list(axis)} ({frame} frame) through the tool point", deg,
            json_output)
