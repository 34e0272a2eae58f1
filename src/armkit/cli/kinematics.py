"""``armkit fk`` and ``armkit jacobian``."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import numpy as np
import typer
from rich.markup import escape
from rich.table import Table

from armkit._io import check_output_path
from armkit.cli.app import (
    ALLOW_NEGATIVE,
    JOINT_UNITS,
    QUATERNION_NAMES,
    BaseOpt,
    LockOpt,
    RobotArg,
    TipOpt,
    app,
    check_limits_or_warn,
    console,
    err_console,
    fmt_number,
    fmt_numbers,
    load_robot,
    print_json,
    to_si,
)
from armkit.errors import InputError
from armkit.spatial.rotations import euler_from_matrix, parse_convention, quaternion_wxyz_from_matrix

#: Picture files ``--plot`` writes, by extension.
FIGURE_SUFFIXES = (".png", ".svg", ".pdf")
#: Smallest singular value below which ``armkit jacobian`` calls a configuration singular.
SINGULAR_THRESHOLD = 1e-9

JointsArg = Annotated[list[str], typer.Argument(help="Joint values q1 ... qn (rad and m; "
                                                         "revolute in deg with --deg).")]
DegOpt = Annotated[bool, typer.Option("--deg", help="Revolute joint values (and printed "
                                                    "angles) in degrees.")]
StrictOpt = Annotated[bool, typer.Option("--strict", help="Fail on joint values outside the "
                                                          "limits instead of warning.")]
JsonOpt = Annotated[bool, typer.Option("--json", help="Print JSON instead of tables.")]


def _matrix_table(matrix: np.ndarray, title: str, row_names: list[str] | None = None,
                  column_names: list[str] | None = None) -> Table:
    table = Table(title=escape(title), show_header=column_names is not None)
    if row_names:
        table.add_column("")
    for name in column_names or [""] * matrix.shape[1]:
        table.add_column(escape(name), justify="right")
    for i, row in enumerate(matrix):
        table.add_row(*([row_names[i]] if row_names else []), *(fmt_number(v, 6) for v in row))
    return table


@app.command("fk", context_settings=ALLOW_NEGATIVE)
def fk_command(
    robot: RobotArg,
    q: JointsArg,
    deg: DegOpt = False,
    euler: Annotated[str, typer.Option(help="Convention of the printed orientation, e.g. xyz-fixed "
                                            "(roll pitch yaw), xyz-euler, zyz-euler, or quat (unit "
                                            "quaternion w x y z).")] = "xyz-fixed",
    strict: StrictOpt = False,
    json_output: JsonOpt = False,
    plot: Annotated[Path | None, typer.Option(
        "--plot", metavar="FILE", help="Also draw the arm at q (links, joint axes, base and tool frames) "
                                       "into FILE (.png, .svg, .pdf).", show_default=False)] = None,
    force: Annotated[bool, typer.Option("--force", help="Replace an existing --plot file.")] = False,
    base: BaseOpt = None,
    tip: TipOpt = None,
    lock: LockOpt = None,
) -> None:
    """Forward kinematics: the tool pose for joint values q1 ... qn.

    Example: armkit fk puma560 0 -0.5 0.5 0 1 0 --plot puma.png
    """
    arm = load_robot(robot, base, tip, lock)
    q_si = to_si(arm, q, deg)
    check_limits_or_warn(arm, q_si, strict, deg)
    if plot is not None:
        from armkit.plots import save_figure

        if plot.suffix.lower() not in FIGURE_SUFFIXES:
            raise InputError(f"--plot {plot}: expected a file name ending in {', '.join(FIGURE_SUFFIXES)}")
        check_output_path(plot, force, remedy="pass --force")
        save_figure(arm.plot(q_si), plot, overwrite=True)
        err_console.print(f"wrote {plot}", highlight=False)
    quaternion = euler.strip().lower() in QUATERNION_NAMES
    convention = None if quaternion else parse_convention(euler)
    T = arm.fk(q_si)
    unit = "deg" if deg else "rad"
    if quaternion:
        wxyz = quaternion_wxyz_from_matrix(T[:3, :3])
        orientation = {"quaternion_wxyz": wxyz}
        line = f"quaternion w x y z (unit, w >= 0): {fmt_numbers(wxyz, 6)}"
    else:
        angles = euler_from_matrix(T, convention, degrees=deg)
        orientation = {"angles": angles, "convention": convention.name,
                       "convention_formula": f"R = {convention.formula()}", "angle_unit": unit}
        line = f"{convention.name} angles [{unit}] (R = {convention.formula()}): {fmt_numbers(angles, 6)}"
    if json_output:  # SI, whatever --deg says
        if not quaternion:
            orientation |= {"angles": euler_from_matrix(T, convention, degrees=False)}
            del orientation["angle_unit"]
        print_json({"robot": arm.name, "q": q_si, "matrix": T, "position": T[:3, 3], **orientation},
                   {"q": JOINT_UNITS, "matrix": "m (translation column)", "position": "m", "angles": "rad",
                    "quaternion_wxyz": "1"})
        return
    console.print(_matrix_table(T, f"{arm.name}: T_base_tool (metres)"))
    console.print(f"position [m]: {fmt_numbers(T[:3, 3], 6)}", markup=False)
    console.print(line, markup=False)


@app.command("jacobian", context_settings=ALLOW_NEGATIVE)
def jacobian_command(
    robot: RobotArg,
    q: JointsArg,
    deg: DegOpt = False,
    frame: Annotated[str, typer.Option(help="base or tool: the frame the twist is in.")] = "base",
    strict: StrictOpt = False,
    json_output: JsonOpt = False,
    base: BaseOpt = None,
    tip: TipOpt = None,
    lock: LockOpt = None,
) -> None:
    """Geometric Jacobian (rows vx vy vz wx wy wz), manipulability and singular values."""
    arm = load_robot(robot, base, tip, lock)
    q_si = to_si(arm, q, deg)
    check_limits_or_warn(arm, q_si, strict, deg)
    J = arm.jacobian(q_si, frame=frame)
    sigma = arm.singular_values(q_si)
    if json_output:
        print_json({"robot": arm.name, "q": q_si, "frame": frame, "jacobian": J,
                    "rows": ["vx", "vy", "vz", "wx", "wy", "wz"],
                    "manipulability": float(np.prod(sigma)), "singular_values": sigma},
                   {"q": JOINT_UNITS, "jacobian": "rows vx vy vz in m/s, wx wy wz in rad/s, per rad/s "
                    "(revolute) or m/s (prismatic) of each joint", "singular_values": "m/s and rad/s mixed"})
        return
    console.print(_matrix_table(J, f"{arm.name}: geometric Jacobian, {frame} frame",
                                ["vx", "vy", "vz", "wx", "wy", "wz"], arm.joint_names))
    condition = sigma[0] / sigma[-1] if sigma[-1] > 0 else float("inf")
    console.print(f"manipulability: {np.prod(sigma):.6g}   smallest singular value: {sigma[-1]:.6g}   "
                  f"condition number: {condition:.6g}   (rows in m/s and rad/s per unit joint rate; "
                  f"singular values mix the two)", soft_wrap=True, markup=False)
    if sigma[-1] < SINGULAR_THRESHOLD:
        console.print("[yellow]singular configuration:[/yellow] the tool cannot move in every direction "
                      "here", soft_wrap=True)
