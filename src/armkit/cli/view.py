"""``armkit view``: the arm in the browser, a thin layer over :class:`armkit.view.Viewer`."""

from __future__ import annotations

import warnings
import webbrowser
from pathlib import Path
from typing import Annotated

import typer

from armkit.cli.app import (
    BaseOpt,
    LockOpt,
    RobotArg,
    TipOpt,
    app,
    console,
    err_console,
    joint_option,
    load_robot,
    warn,
)
from armkit.cli.scene_option import PackagePathOpt, SceneOpt, load_scene_option

#: Exit code after Ctrl-C (128 + SIGINT), as shells report it.
INTERRUPTED = 130


def serve(viewer, open_browser: bool) -> None:
    """Print the address, open it in the browser unless told not to, serve until Ctrl-C."""
    try:  # Ctrl-C as soon as the address is out (a script reading it may send one at once) stops cleanly
        console.print(f"armkit view: {viewer.robot.name} at {viewer.url} (Ctrl-C to stop)", highlight=False)
        if open_browser:
            webbrowser.open(viewer.url)
        viewer.serve_forever()
    except KeyboardInterrupt:
        viewer.close()
        err_console.print("armkit view: stopped", highlight=False)
        raise SystemExit(INTERRUPTED) from None  # said in one line already


@app.command("view")
def view_command(
    robot: RobotArg,
    port: Annotated[int, typer.Option(help="TCP port of the page (the next free one if taken).")] = 8080,
    host: Annotated[str, typer.Option(help="Interface to listen on; 0.0.0.0 lets other machines "
                                           "open the page.")] = "127.0.0.1",
    trajectory: Annotated[Path | None, typer.Option(
        help="A trajectory file 'armkit traj' wrote, put on the timeline.", show_default=False)] = None,
    free_joint: Annotated[str | None, typer.Option(
        "--free-joint", metavar="JOINT", help="A 7-joint arm: show the self-motion of its start pose along "
        "this joint (name or number 1..n): ghosts along the arm's branch, a slider moving the arm along it.",
        show_default=False)] = None,
    no_browser: Annotated[bool, typer.Option("--no-browser", help="Do not open a browser.")] = False,
    base: BaseOpt = None,
    tip: TipOpt = None,
    lock: LockOpt = None,
    scene: SceneOpt = None,
    package_path: PackagePathOpt = None,
) -> None:
    """Interactive 3-D teach panel in the browser: joint sliders, every IK solution, trajectories.

    Examples: armkit view probot-anno; armkit view panda --free-joint 3
    """
    from armkit.view import Viewer

    arm = load_robot(robot, base, tip, lock)
    with warnings.catch_warnings(record=True) as said:  # a missing mesh: one "warning:" line
        warnings.simplefilter("always", UserWarning)
        viewer = Viewer(arm, port=port, host=host, package_paths=package_path or (),
                        scene=load_scene_option(arm, scene, package_path))
    for warning in said:
        warn(str(warning.message))
    try:
        if trajectory is not None:
            viewer.load(trajectory)
        if free_joint is not None:
            viewer.show_self_motion(joint_option(arm, free_joint, f"--free-joint {free_joint!r}"))
    except BaseException:
        viewer.close()
        raise
    serve(viewer, not no_browser)
