"""``armkit lab``: run the seed experiments (or a user's arm) in MuJoCo and write an HTML report."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer
from rich.markup import escape

from armkit.cli.app import BaseOpt, LockOpt, TipOpt, app, console, load_robot, print_json
from armkit.cli.sim import require_mujoco
from armkit.errors import InputError
from armkit.robot import Robot


@app.command("lab")
def lab_command(
    robot: Annotated[str | None, typer.Option(
        help="A built-in name, robot TOML file or URDF file (--base/--tip choose its chain) to run the "
             "experiments on, choosing reachable targets; default: the seed reports' arms.",
        show_default=False)] = None,
    out: Annotated[Path, typer.Option(help="Report folder.")] = Path("armkit-report"),
    quick: Annotated[bool, typer.Option("--quick", help="Small animations and short moves (fast).")] = False,
    force: Annotated[bool, typer.Option("--force", help="Write into a folder that is not an armkit "
                                                        "report.")] = False,
    json_output: Annotated[bool, typer.Option("--json", help="Print JSON (each section's status and "
                                                             "headline) instead.")] = False,
    base: BaseOpt = None,
    tip: TipOpt = None,
    lock: LockOpt = None,
    view: Annotated[bool, typer.Option("--view", help="Afterwards open the 3-D viewer (armkit view) on "
                                                      "the robot with the trajectory experiment's motion "
                                                      "and waypoints.")] = False,
    port: Annotated[int, typer.Option(help="With --view: TCP port of the viewer.")] = 8080,
    no_browser: Annotated[bool, typer.Option("--no-browser", help="With --view: do not open a "
                                                                  "browser.")] = False,
) -> None:
    """Reproduce the seed experiments (FK, IK, straight line, trajectory, rotation) in MuJoCo; write HTML.

    Exits with code 1 if an experiment failed (the report is written either way); an
    experiment the arm cannot do is "not applicable", which is no failure.
    """
    require_mujoco()
    from armkit.lab import run_lab
    from armkit.lab.report import status_label

    if robot is None and (base or tip or lock):
        raise InputError("--base, --tip and --lock shape the arm given with --robot; give --robot too")
    arm = None if robot is None else load_robot(robot, base, tip, lock)
    result = run_lab(arm, out, quick=quick, force=force, progress=not json_output)
    failed = [s for s in result.sections if s.status == "failed"]
    if json_output:
        print_json({"report": str(result.index), "seconds": result.seconds, "failed": len(failed),
                    "sections": [{"key": s.key, "title": s.title, "status": s.status, "headline": s.headline,
                                  "notes": s.notes} for s in result.sections]})
    else:
        for section in result.sections:
            if section.status != "ok":
                why = escape(section.notes[0] if section.notes else section.headline)
                if section.status == "failed":
                    why = f"[red]{status_label(section.status, robot is None)}[/red]: {why}"
                console.print(f"{escape(section.title)}: {why}", highlight=False, soft_wrap=True)
        console.print(f"report: {escape(str(result.index))} ({result.seconds:.0f} s)", highlight=False)
    if view:
        _view(arm if arm is not None else "probot-anno", out, port, not no_browser)
    if failed:
        raise typer.Exit(1)


def _view(robot: str | Robot, out: Path, port: int, open_browser: bool) -> None:
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
