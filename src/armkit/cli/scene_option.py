"""The ``--scene FILE`` option (and ``--package-path DIR``) any command that moves the arm can take."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from armkit.robot import Robot

if TYPE_CHECKING:  # armkit.collision imports MuJoCo when a scene is built
    from armkit.collision.scene import Scene

__all__ = ["PackagePathOpt", "SceneOpt", "load_scene_option"]

SceneOpt = Annotated[Path | None, typer.Option(
    "--scene", metavar="FILE", help="A scene file (TOML: floor, obstacles; see docs/collision.md) to check "
                                    "the arm against for collisions.", show_default=False)]
PackagePathOpt = Annotated[list[Path] | None, typer.Option(
    "--package-path", metavar="DIR", help="URDF: a folder holding the packages its package:// meshes name "
                                          "(repeat for more; ROS_PACKAGE_PATH and the URDF's own folders are "
                                          "searched too).", show_default=False)]


def load_scene_option(robot: Robot, scene: Path | None,
                      package_paths: list[Path] | None = None) -> Scene | None:
    """The :class:`~armkit.collision.Scene` ``--scene`` names for ``robot``, or None without one."""
    if scene is None:
        return None
    from armkit.collision import load_scene

    return load_scene(scene, robot, package_paths=tuple(package_paths or ()))
