"""``armkit lab``: run the seed experiments (or a user's arm) in MuJoCo and write an HTML report."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from armkit.cli.app import app, console
from armkit.cli.sim import require_mujoco


@app.command("lab")
def lab_command(
    robot: Annotated[str | None, typer.Option(
        help="A robot file (or built-in name) to run the experiments on, choosing reachable targets; "
             "default: the seed reports' arms.", show_default=False)] = None,
    out: Annotated[Path, typer.Option(help="Report folder.")] = Path("armkit-report"),
    quick: Annotated[bool, typer.Option("--quick", help="Small animations and short moves (fast).")] = False,
    force: Annotated[bool, typer.Option("--force", help="Write into a folder that is not an armkit "
                                                        "report.")] = False,
) -> None:
    """Reproduce the seed experiments (FK, IK, straight line, trajectory, rotation) in MuJoCo; write HTML."""
    require_mujoco()
    from armkit.lab import run_lab

    result = run_lab(robot, out, quick=quick, force=force)
    for section in result.sections:
        if section.status != "ok":
            console.print(f"[yellow]{section.title}: {section.status}[/yellow] {' '.join(section.notes)}",
                          highlight=False)
    console.print(f"report: {result.index} ({result.seconds:.0f} s)", highlight=False)
