"""``armkit robots`` and ``armkit show``: what robots there are and what one looks like."""

from __future__ import annotations

import dataclasses
import math
from typing import Annotated

import numpy as np
import typer
from rich.markup import escape
from rich.table import Table

from armkit.cli.app import app, console, fmt_numbers, load_robot, print_json
from armkit.ik.structure import analyze_structure
from armkit.robot import Robot
from armkit.robot_file import builtin_robots, load


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
                     "convention": robot.dh.convention, "description": robot.description})
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


@app.command("show")
def show_command(
    robot: Annotated[str, typer.Argument(help="Built-in name or robot TOML file.")],
    json_output: Annotated[bool, typer.Option("--json", help="Print JSON instead.")] = False,
) -> None:
    """Print a robot's DH table, limits and the kind of arm it is."""
    arm = load_robot(robot)
    structure = analyze_structure(arm.chain)
    if json_output:
        print_json({"name": arm.name, "n": arm.n, "joint_types": arm.joint_types,
                    "convention": arm.dh.convention if arm.dh else None,
                    "limits": arm.limits, "max_velocity": arm.max_velocity,
                    "max_acceleration": arm.max_acceleration,
                    "structure": dataclasses.asdict(structure)})
        return
    console.print(dh_table(arm))
    home = arm.fk(np.zeros(arm.n))
    console.print(f"tool at q = 0: position {fmt_numbers(home[:3, 3], 6)} m", markup=False)
    console.print(f"kind: {structure.description}", markup=False)
