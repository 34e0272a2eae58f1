"""``armkit dynamics``: joint torques of one state, their gravity part and the torque limits."""

from __future__ import annotations

from typing import Annotated

import numpy as np
import typer
from rich.markup import escape
from rich.table import Table

from armkit._format import fmt_significant
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
    fmt_number,
    load_robot,
    parse_floats,
    print_json,
    to_si,
)
from armkit.errors import InputError
from armkit.robot import Robot

QdOpt = Annotated[str | None, typer.Option(help="Joint velocities, one comma list (0,0.5,...): rad/s and m/s "
                                                "(deg/s with --deg); default zero.")]
QddOpt = Annotated[str | None, typer.Option(help="Joint accelerations, one comma list: rad/s^2 and m/s^2 "
                                                 "(deg/s^2 with --deg); default zero.")]
DegOpt = Annotated[bool, typer.Option("--deg", help="Revolute values, rates and accelerations in degrees.")]
JsonOpt = Annotated[bool, typer.Option("--json", help="Print JSON (SI units) instead of a table.")]
DensityOpt = Annotated[float | None, typer.Option(
    "--estimate-inertia", help="Estimate every link's inertia from capsules of this density [kg/m^3] (for a "
                               "robot file or URDF without masses).")]
PayloadOpt = Annotated[float | None, typer.Option(help="A point mass [kg] at the tool frame's origin.")]


def with_inertia_options(arm: Robot, estimate_inertia: float | None, payload: float | None) -> Robot:
    """``arm`` with ``--estimate-inertia`` and ``--payload`` applied."""
    if estimate_inertia is not None:
        arm = arm.with_estimated_inertia(density=estimate_inertia)
    if payload is not None:
        if not payload >= 0:
            raise InputError(f"--payload: expected a mass >= 0 kg, got {payload}")
        arm = arm.with_payload(payload)
    return arm


def _rates(robot: Robot, words: str | None, option: str, degrees: bool) -> np.ndarray:
    """One value per joint from a comma (or space) list, in SI units; zeros if not given."""
    if words is None:
        return np.zeros(robot.n)
    values = robot.check_q(np.array(parse_floats(words.replace(",", " ").split(), option)), option)
    return np.where(robot.chain.prismatic, values, np.radians(values)) if degrees else values


@app.command("dynamics", context_settings=ALLOW_NEGATIVE)
def dynamics_command(
    robot: RobotArg,
    q: Annotated[list[str], typer.Argument(help="Joint values q1 ... qn (rad and m; revolute in deg "
                                                "with --deg).")],
    qd: QdOpt = None,
    qdd: QddOpt = None,
    deg: DegOpt = False,
    payload: PayloadOpt = None,
    estimate_inertia: DensityOpt = None,
    json_output: JsonOpt = False,
    base: BaseOpt = None,
    tip: TipOpt = None,
    lock: LockOpt = None,
) -> None:
    """Inverse dynamics: the joint torques [N m] (forces [N] for prismatic joints) that move the arm
    with velocities --qd and accelerations --qdd at q1 ... qn, their gravity part and the limits."""
    arm = with_inertia_options(load_robot(robot, base, tip, lock), estimate_inertia, payload)
    q_si = to_si(arm, q, deg)
    check_limits_or_warn(arm, q_si, False, deg)
    qd_si, qdd_si = _rates(arm, qd, "--qd", deg), _rates(arm, qdd, "--qdd", deg)
    tau = arm.inverse_dynamics(q_si, qd_si, qdd_si)
    gravity = arm.gravity_torques(q_si)
    M = arm.mass_matrix(q_si)
    limit = arm.max_torque
    ratio = np.abs(tau) / limit
    if json_output:
        print_json({"q": q_si, "qd": qd_si, "qdd": qdd_si, "tau": tau, "gravity_torques": gravity,
                    "coriolis_torques": arm.coriolis_torques(q_si, qd_si), "mass_matrix": M,
                    "max_torque": limit, "masses": [j.inertial.mass for j in arm.chain.joints]},
                   {"q": JOINT_UNITS, "qd": "rad/s, m/s", "qdd": "rad/s^2, m/s^2",
                    "tau": "N m (revolute), N (prismatic)", "gravity_torques": "N m, N",
                    "coriolis_torques": "N m, N", "max_torque": "N m, N", "mass_matrix": "kg m^2, kg m, kg",
                    "masses": "kg"})
        return
    angle = "deg" if deg else "rad"
    table = Table(title=escape(f"{arm.name}: inverse dynamics, gravity 9.81 m/s^2 along -z of the base"))
    for column in ("joint", "q", "qd", "qdd", "torque", "gravity part", "max torque", "of limit"):
        table.add_column(column, justify="right")
    scale = float(np.max(np.abs(np.concatenate([tau, gravity]))))
    for j, joint in enumerate(arm.chain.joints):
        revolute = joint.kind == "revolute"
        shown = 180 / np.pi if deg and revolute else 1.0
        length = angle if revolute else "m"
        torque = "N m" if revolute else "N"
        table.add_row(escape(joint.name), f"{fmt_number(q_si[j] * shown)} {length}",
                      f"{fmt_number(qd_si[j] * shown)} {length}/s",
                      f"{fmt_number(qdd_si[j] * shown)} {length}/s^2",
                      f"{fmt_significant(tau[j], scale)} {torque}",
                      f"{fmt_significant(gravity[j], scale)} {torque}",
                      "none" if not np.isfinite(limit[j]) else f"{fmt_significant(limit[j])} {torque}",
                      "-" if not np.isfinite(limit[j]) else f"{100 * ratio[j]:.1f} %")
    console.print(table)
    over = [arm.joint_names[j] for j in np.flatnonzero(ratio > 1)]
    if over:
        console.print(f"above the torque limit: {', '.join(over)}", style="red", markup=False)
