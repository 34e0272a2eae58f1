"""``armkit robots`` and ``armkit show``: what robots there are and what one looks like."""

from __future__ import annotations

import dataclasses
import math
from typing import Annotated

import numpy as np
import typer
from rich.markup import escape
from rich.table import Table

from armkit.cli.app import (
    JOINT_UNITS,
    BaseOpt,
    LockOpt,
    RobotArg,
    TipOpt,
    app,
    console,
    fmt_numbers,
    load_robot,
    print_json,
)
from armkit.ik.structure import ArmStructure, analyze_structure
from armkit.poe import poe_from_chain
from armkit.robot import LockedRobot, Robot
from armkit.robot_file import builtin_robots, load
from armkit.spatial.rotations import euler_from_matrix


@app.command("robots")
def robots_command(
    json_output: Annotated[bool, typer.Option("--json", help="Print JSON instead.")] = False,
) -> None:
    """List the built-in robots."""
    rows = []
    for name in builtin_robots():
        robot = load(name)
        rows.append({"name": name, "robot": robot.name, "joints": "".join("P" if p else "R"
                                                                          for p in robot.chain.prismatic),
                     "convention": robot.dh.convention if robot.dh else "poe",
                     "description": robot.description})
    if json_output:
        print_json({"robots": rows})
        return
    table = Table(title="Built-in robots")
    for column in ("name", "robot", "joints", "DH", "description"):
        table.add_column(column)
    for row in rows:
        table.add_row(*(escape(str(value)) for value in row.values()))
    console.print(table)


def _fmt(value: float, scale: float) -> str:
    return "inf" if not math.isfinite(value) else f"{value / scale + 0.0:.6g}"


def dh_table(robot: Robot) -> Table:
    """The robot's DH table and limits, in the units the robot was written in."""
    dh = robot.dh
    length = 1e-3 if dh.length_unit == "mm" else 1.0
    angle = math.pi / 180 if dh.angle_unit == "deg" else 1.0
    names = (["alpha_{i-1}", "a_{i-1}", "theta_i", "d_i"] if dh.convention == "modified"
             else ["theta_i", "d_i", "a_i", "alpha_i"])
    keys = ["alpha", "a", "theta", "d"] if dh.convention == "modified" else [
        "theta", "d", "a", "alpha"]
    table = Table(title=escape(f"{robot.name}: {dh.convention} DH "
                               f"(lengths in {dh.length_unit}, angles in {dh.angle_unit})"))
    for column in ["joint", "type", *names, "limits", "max vel", "max acc"]:
        table.add_column(column, justify="right")
    rows = [(f"base {k + 1}", None, r) for k, r in enumerate(dh.base_rows)]
    rows += [(j.name, j, r) for j, r in zip(robot.chain.joints, dh.rows, strict=True)]
    rows += [(f"tool {k + 1}", None, r) for k, r in enumerate(dh.tool_rows)]
    for label, joint, row in rows:
        cells = []
        for key in keys:
            value = _fmt(getattr(row, key), angle if key in ("alpha", "theta") else length)
            variable = joint is not None and (
                (key == "theta") == (joint.kind == "revolute") and key in ("theta", "d"))
            offset = "" if value == "0" else (f" - {value[1:]}" if value.startswith("-") else f" + {value}")
            cells.append(f"q{offset}" if variable else value)
        if joint is None:
            table.add_row(escape(label), "fixed", *cells, "", "", "")
            continue
        unit = angle if joint.kind == "revolute" else length
        table.add_row(escape(label), joint.kind, *cells,
                      f"[{_fmt(joint.lower, unit)}, {_fmt(joint.upper, unit)}]",
                      "" if joint.max_velocity is None else _fmt(joint.max_velocity, unit),
                      "" if joint.max_acceleration is None else _fmt(joint.max_acceleration, unit))
    return table


def joint_line_table(robot: Robot) -> Table:
    """Each joint's line at q = 0 in the base frame (product of exponentials) and its limits."""
    poe = robot.poe if robot.poe is not None else poe_from_chain(robot.chain)
    length = 1e-3 if poe.length_unit == "mm" else 1.0
    angle = math.pi / 180 if poe.angle_unit == "deg" else 1.0
    table = Table(title=f"{robot.name}: joint axes at q = 0, base frame "
                        f"(lengths in {poe.length_unit}, angles in {poe.angle_unit})")
    for column in ["joint", "type", "axis", "point", "limits", "max vel", "max acc"]:
        table.add_column(column, justify="right")
    for joint, axis, point in zip(robot.chain.joints, poe.axes, poe.points, strict=True):
        unit = angle if joint.kind == "revolute" else length
        table.add_row(joint.name, joint.kind, " ".join(_fmt(v, 1.0) for v in np.round(axis, 9)),
                      " ".join(_fmt(v, length) for v in np.round(point, 9)),
                      f"[{_fmt(joint.lower, unit)}, {_fmt(joint.upper, unit)}]",
                      "" if joint.max_velocity is None else _fmt(joint.max_velocity, unit),
                      "" if joint.max_acceleration is None else _fmt(joint.max_acceleration, unit))
    if isinstance(robot, LockedRobot):
        full = robot.full_robot
        table.caption = "locked: " + ", ".join(
            f"{full.joint_names[i]} = {_fmt(v, angle if full.chain.joints[i].kind == 'revolute' else length)}"
            for i, v in robot.locked.items())
    return table


def _dynamics_line(robot: Robot) -> str:
    """The link masses and torque limits, one line (or that the robot has no inertia)."""
    torque = ", ".join("none" if not math.isfinite(t) else f"{t:.6g} {'N m' if kind == 'revolute' else 'N'}"
                       for t, kind in zip(robot.max_torque, robot.joint_types, strict=True))
    joints = robot.chain.joints
    if any(joint.inertial is None for joint in joints):
        mass = "no inertial parameters (armkit dynamics ... --estimate-inertia DENSITY estimates them)"
    else:
        masses = [joint.inertial.mass for joint in joints]
        mass = f"{', '.join(f'{m:.6g}' for m in masses)} kg (moving: {sum(masses):.6g} kg)"
    return f"link masses: {mass}\ntorque limits: {torque}"


def _case_line(structure: ArmStructure) -> str:
    """The IK engine's case for an arm: ``"spherical (closed form, up to 8 solutions)"``."""
    if structure.case is None:
        return "none (numeric IK)"
    solvers = {"general-6r": "general 6R solver", "general-5r1p": "general 5R1P solver"}
    what = solvers.get(structure.kind, "closed form")
    return f"{structure.case} ({what}, up to {structure.max_solutions} solutions)"


@app.command("show")
def show_command(
    robot: RobotArg,
    json_output: Annotated[bool, typer.Option("--json", help="Print JSON instead.")] = False,
    base: BaseOpt = None,
    tip: TipOpt = None,
    lock: LockOpt = None,
    why_not: Annotated[bool, typer.Option(
        "--why-not", help="Also say, for every IK case of the engine, why it does not apply.")] = False,
) -> None:
    """Print a robot's DH table (or joint axes), limits, the kind of arm it is and its IK case."""
    arm = load_robot(robot, base, tip, lock)
    structure = analyze_structure(arm)
    if json_output:
        poe = poe_from_chain(arm.chain)
        print_json({"name": arm.name, "n": arm.n, "joint_names": arm.joint_names,
                    "joint_types": arm.joint_types, "convention": arm.dh.convention if arm.dh else None,
                    "source": arm.source, "limits": arm.limits, "max_velocity": arm.max_velocity,
                    "max_acceleration": arm.max_acceleration, "axes": poe.axes, "points": poe.points,
                    "urdf": None if arm.urdf is None else {
                        "base": arm.urdf.base, "tip": arm.urdf.tip, "links": arm.urdf.links,
                        "effort": arm.urdf.effort, "meshes": len(arm.urdf.meshes)},
                    "mass": [None if j.inertial is None else j.inertial.mass for j in arm.chain.joints],
                    "max_torque": arm.max_torque,
                    "locked": None if not isinstance(arm, LockedRobot) else {
                        arm.full_robot.joint_names[i]: v for i, v in arm.locked.items()},
                    "structure": dataclasses.asdict(structure)},
                   {"limits": JOINT_UNITS, "max_velocity": "rad/s, m/s", "max_acceleration": "rad/s^2, m/s^2",
                    "axes": "1 (unit vectors, base frame)", "points": "m", "mass": "kg",
                    "max_torque": "N m, N",
                    "locked": JOINT_UNITS})
        return
    console.print(dh_table(arm) if arm.dh is not None else joint_line_table(arm))
    for label, T in (("base", arm.dh and arm.dh.T_base), ("tool", arm.dh and arm.dh.T_tool)):
        if T is not None:
            rpy = euler_from_matrix(T[:3, :3], "xyz-fixed")
            console.print(f"{label} transform: xyz {np.round(T[:3, 3], 6).tolist()} m, "
                          f"rpy {np.round(rpy, 6).tolist()} rad", highlight=False)
    if arm.urdf is not None:
        console.print(f"URDF {arm.urdf.path}: links {arm.urdf.base} to {arm.urdf.tip}, "
                      f"{len(arm.urdf.meshes)} visual meshes", highlight=False)
    console.print(_dynamics_line(arm), markup=False)
    home = arm.fk(np.zeros(arm.n))
    console.print(f"tool at q = 0: position {fmt_numbers(home[:3, 3], 6)} m", markup=False)
    console.print(f"IK case: {_case_line(structure)}", markup=False)
    console.print(f"kind: {structure.description}", markup=False)
    if why_not:
        refused = [(case, fit, reason) for case, fit, reason in structure.why_not if fit != "applies"]
        if refused and {reason for *_, reason in refused} == {structure.description}:
            console.print(f"  no case ({', '.join(case for case, *_ in refused)}): the reason above",
                          markup=False)  # an arm every case refuses alike (a 7-joint arm) says it once
        else:
            for case, fit, reason in refused:
                console.print(f"  not {case} ({fit}): {reason}", markup=False)
