"""``armkit lab``: run the seed experiments (or a user's arm) in MuJoCo and write an HTML report."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from armkit.cli.app import BaseOpt, LockOpt, TipOpt, app, console, load_robot
from armkit.cli.sim import require_mujoco
from armkit.errors import InputError


@app.command("lab")
def lab_command(
    robot: Annotated[str | None, typer.Option(
        help="A robot file, URDF file or built-in name to run the experiments on, choosing reachable "
             "targets; default: the seed reports' arms.", show_default=False)] = None,
    out: Annotated[Path, typer.Option(help="Report folder.")] = Path("armkit-report"),
    quick: Annotated[bool, typer.Option("--quick", help="Small animations and short moves (fast).")] = False,
    force: Annotated[bool, typer.Option("--force", help="Write into a folder that is not an armkit "
                                                        "report.")] = False,
    base: BaseOpt = None,
    tip: TipOpt = None,
    lock: LockOpt = None,
) -> None:
    """Reproduce the seed experiments (FK, IK, straight line, trajectory, rotation) in MuJoCo; write HTML."""
    require_mujoco()
    from armkit.lab import run_lab

    if robot is None and (base or tip or lock):
        raise InputError("--base, --tip and --lock shape the arm given with --robot; give --robot too")
    arm = None if robot is None else load_robot(robot, base, tip, lock)
    result = run_lab(arm, out, quick=quick, force=force)
    for section in result.sections:
        if section.status != "ok":
            console.print(f"[yellow]{section.title}: {section.status}[/yellow] {' '.join(section.notes)}",
                          highlight=False)
    console.print(f"report: {result.index} ({result.seconds:.0f} s)", highlight=False)
