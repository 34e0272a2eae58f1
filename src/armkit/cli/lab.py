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
    view: Annotated[bool, typer.Option("--view", help="Afterwards open the 3-D viewer (armkit view) on "
                                                      "the robot with the trajectory experiment's motion "
                                                      "and waypoints.")] = False,
    port: Annotated[int, typer.Option(help="With --view: TCP port of the viewer.")] = 8080,
    no_browser: Annotated[bool, typer.Option("--no-browser", help="With --view: do not open a "
                                                                  "browser.")] = False,
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
    if view:
        _view(robot or "probot-anno", out, port, not no_browser)


def _view(robot: str, out: Path, port: int, open_browser: bool) -> None:
    """The viewer on the lab's robot, with experiment 4's trajectory on the timeline and its waypoints."""
    from armkit.cli.view import serve
    from armkit.lab.motion import TRAJECTORY_FILE, WAYPOINTS_FILE
    from armkit.trajectory import read_waypoints
    from armkit.view import Viewer

    viewer = Viewer(robot, port=port)
    try:
        viewer.waypoints = read_waypoints(out / WAYPOINTS_FILE, viewer.robot.n)
        viewer.load(out / TRAJECTORY_FILE)
    except BaseException:
        viewer.close()
        raise
    serve(viewer, open_browser)
