"""The viewer's fixed surroundings: the camera's first view, the floor grid with metre labels, the base
axes."""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["add_floor", "grid_step"]


def grid_step(length: float) -> float:
    """A round grid step [m] (0.05, 0.1, 0.2, 0.5, ...) giving about five cells over ``length`` [m].

    >>> grid_step(0.79), grid_step(2.0), grid_step(0.3)
    (0.2, 0.5, 0.1)
    """
    raw = length / 5
    power = 10 ** np.floor(np.log10(raw))
    return float(min((s * power for s in (1, 2, 5, 10) if s * power >= raw), default=raw))


def add_floor(server: Any, size: float) -> None:
    """Aim ``server``'s first camera at an arm ``size`` [m] long and draw the floor grid around it.

    The camera looks from the front right, aimed to the right of the arm, so that the panel
    floating over the page's right side leaves the arm in view.
    """
    scene = server.scene
    scene.set_up_direction("+z")
    server.initial_camera.look_at = (0.12 * size, 0.16 * size, 0.3 * size)
    server.initial_camera.position = (0.85 * size, -0.7 * size, 0.65 * size)
    step = grid_step(size)
    half = step * np.ceil(0.6 * size / step)
    scene.add_grid("/floor", width=2 * half, height=2 * half, cell_size=step / 2, section_size=step,
                   plane_opacity=0.0, shadow_opacity=0.0)
    ticks = np.arange(-half, half + step / 2, step)
    for value in ticks[np.abs(ticks) > step / 2]:
        scene.add_label(f"/floor/x{value:+.3f}", f"{value:g} m", position=(value, 0.0, 0.0),
                        font_screen_scale=0.7)
        scene.add_label(f"/floor/y{value:+.3f}", f"y {value:g} m", position=(0.0, value, 0.0),
                        font_screen_scale=0.7)
    scene.add_frame("/world", axes_length=0.6 * step, axes_radius=0.04 * step, origin_radius=0.0)
