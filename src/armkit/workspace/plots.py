"""Pictures of workspace maps: slices through the base axis and at heights, a 3-D cloud, histograms.

Every function returns a :class:`matplotlib.figure.Figure` (no pyplot state; save it with
:func:`armkit.plots.save_figure`). Axes are base-frame coordinates in metres; colour bars
name the quantity. Hit counts are shown on a log scale (they span orders of magnitude).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from armkit.errors import missing_extra
from armkit.workspace.grid import Grid
from armkit.workspace.maps import Workspace

try:  # an optional dependency (the extra "plot")
    from matplotlib.colors import LogNorm
    from matplotlib.figure import Figure
except ImportError as exc:
    raise missing_extra("plot", "plots need matplotlib and Pillow") from exc

__all__ = ["plot_cloud", "plot_histograms", "plot_horizontal_slices", "plot_sweep", "plot_vertical_slice"]

_AXES = "xyz"
#: Points drawn at most in the 3-D cloud (every k-th occupied voxel beyond that).
MAX_CLOUD_POINTS = 20_000


def _quantities(ws: Workspace) -> list[tuple[str, NDArray, dict]]:
    """(colour-bar label, 3-D array with NaN where empty, imshow options) of each map there is."""
    out = []
    if ws.reachability is not None:
        hits = ws.reachability.hits.astype(float)
        top = max(hits.max(), 2.0)
        out.append(("samples per voxel (log)", np.where(hits > 0, hits, np.nan),
                    {"norm": LogNorm(1, top), "cmap": "viridis"}))
    if ws.dexterity is not None:
        out.append((f"reachability index (of {ws.dexterity.orientations} orientations)",
                    ws.dexterity.reachable_fraction, {"vmin": 0, "vmax": 1, "cmap": "magma"}))
    if ws.manipulability is not None:
        out.append(("mean inverse condition number s_min/s_max", ws.manipulability.mean_inverse_condition,
                    {"vmin": 0, "cmap": "cividis"}))
    return out


def _layer(grid: Grid, axis: int, coordinate: float) -> int:
    """Index of the voxel layer along ``axis`` holding ``coordinate`` [m] (clipped into the grid)."""
    k = int(np.floor((coordinate - grid.lower[axis]) / grid.resolution))
    return int(np.clip(k, 0, grid.shape[axis] - 1))


def _extent(grid: Grid, a: int, b: int) -> list[float]:
    lo, h = grid.lower, grid.resolution
    return [lo[a], lo[a] + grid.shape[a] * h, lo[b], lo[b] + grid.shape[b] * h]


def _panel(figure: Figure, ax, grid: Grid, plane: NDArray, a: int, b: int, label: str, options: dict,
           title: str) -> None:
    image = ax.imshow(plane.T, origin="lower", extent=_extent(grid, a, b), interpolation="nearest", **options)
    ax.set_xlabel(f"{_AXES[a]} [m]")
    ax.set_ylabel(f"{_AXES[b]} [m]")
    ax.set_aspect("equal")
    ax.set_title(title, fontsize=10)
    figure.colorbar(image, ax=ax, label=label, shrink=0.85)


def plot_vertical_slice(ws: Workspace) -> Figure:
    """The plane ``y = 0`` through the base's z axis (for a planar arm: its plane), one panel per map."""
    grid, quantities = ws.grid, _quantities(ws)
    flat_axis = next((i for i, f in enumerate(grid.flat) if f), None)
    figure = Figure(figsize=(5.2 * len(quantities), 4.6), layout="constrained")
    for k, (label, values, options) in enumerate(quantities):
        ax = figure.add_subplot(1, len(quantities), k + 1)
        if flat_axis is None:
            j = _layer(grid, 1, 0.0)
            plane, (a, b), title = values[:, j, :], (0, 2), f"vertical slice y = {grid.axes[1][j]:+.3f} m"
        else:
            a, b = (i for i in range(3) if i != flat_axis)
            plane, title = np.take(values, 0, axis=flat_axis), "the arm's plane"
        _panel(figure, ax, grid, plane, a, b, label, options, title)
    figure.suptitle(f"{ws.robot.name}: through the base axis", fontsize=12)
    return figure


def plot_horizontal_slices(ws: Workspace, heights: list[float] | None = None) -> Figure:
    """Planes ``z = const`` [m] (default: the quartiles of the reached heights) of the first map that
    best shows the arm (reachability index if computed, else samples per voxel)."""
    grid = ws.grid
    label, values, options = _quantities(ws)[1 if ws.dexterity is not None else 0]
    if heights is None:
        reached = np.flatnonzero((np.nan_to_num(values) > 0).any(axis=(0, 1)))
        z = grid.axes[2][reached] if len(reached) else grid.axes[2]
        heights = np.quantile(z, [0.25, 0.5, 0.75]).tolist() if grid.shape[2] > 1 else [z[0]]
    figure = Figure(figsize=(4.6 * len(heights), 4.4), layout="constrained")
    for k, height in enumerate(heights):
        ax = figure.add_subplot(1, len(heights), k + 1)
        j = _layer(grid, 2, height)
        _panel(figure, ax, grid, values[:, :, j], 0, 1, label, options, f"z = {grid.axes[2][j]:+.3f} m")
    figure.suptitle(f"{ws.robot.name}: horizontal slices", fontsize=12)
    return figure


def plot_cloud(ws: Workspace) -> Figure:
    """Occupied voxel centres in 3-D, coloured by the reachability index (or samples per voxel)."""
    grid = ws.grid
    label, values, options = _quantities(ws)[1 if ws.dexterity is not None else 0]
    occupied = np.flatnonzero(np.nan_to_num(values.ravel()) > 0)
    step = max(1, len(occupied) // MAX_CLOUD_POINTS)
    shown = occupied[::step]
    p = grid.centres(shown)
    figure = Figure(figsize=(6.4, 5.6), layout="constrained")
    ax = figure.add_subplot(projection="3d")
    points = ax.scatter(p[:, 0], p[:, 1], p[:, 2], c=values.ravel()[shown], s=3, alpha=0.5,
                        **{k: v for k, v in options.items() if k != "interpolation"})
    for name, setter in zip(_AXES, (ax.set_xlabel, ax.set_ylabel, ax.set_zlabel), strict=True):
        setter(f"{name} [m]")
    ax.set_box_aspect(np.maximum(np.ptp(p, axis=0), grid.resolution) if len(p) else None)
    figure.colorbar(points, ax=ax, label=label, shrink=0.7)
    note = f" (1 in {step} shown)" if step > 1 else ""
    ax.set_title(f"{ws.robot.name}: {len(occupied)} reached voxels{note}", fontsize=10)
    return figure


def plot_histograms(ws: Workspace) -> Figure:
    """Distributions over the reached voxels: samples per voxel, reachability index, manipulability."""
    panels = []
    if ws.reachability is not None:
        hits = ws.reachability.hits[ws.reachability.occupied]
        edges = np.unique(np.rint(np.logspace(0, np.log10(max(hits.max(initial=1), 2) + 1), 40))) - 0.5
        panels.append(("samples per reached voxel", hits, edges, True))
    if ws.dexterity is not None:
        dex, reached = ws.dexterity, ws.dexterity.reachable
        steps = (np.arange(dex.orientations + 2) - 0.5) / dex.orientations  # one bin per possible value
        panels.append(("reachability index", dex.reachable_fraction[reached], steps, False))
        panels.append(("IK solutions per orientation (voxel mean)", dex.mean_solutions[reached], 40, False))
    if ws.manipulability is not None:
        values = ws.manipulability.mean_manipulability
        panels.append(("mean manipulability per voxel", values[np.isfinite(values)], 40, False))
    figure = Figure(figsize=(4.2 * len(panels), 3.6), layout="constrained")
    for k, (label, values, bins, log) in enumerate(panels):
        ax = figure.add_subplot(1, len(panels), k + 1)
        if log:
            ax.set_xscale("log")
        ax.hist(values, bins=bins, color="#4c72b0")
        ax.set_xlabel(label)
        ax.set_ylabel("voxels")
    return figure


def plot_sweep(sweep) -> Figure:
    """Reachable volume (with its stated error) and mean reachability index over the swept values."""
    table = sweep.table()
    values = [row["value"] for row in table]
    figure = Figure(figsize=(9, 3.8), layout="constrained")
    ax = figure.add_subplot(1, 2, 1)
    volume, error = ([r[key] for r in table] for key in ("reachable_volume", "reachable_volume_error"))
    ax.errorbar(values, volume, yerr=error, marker="o", capsize=3)
    unit = "m" if sweep.parameter.rstrip("0123456789") in ("a", "d") else "rad"
    ax.set_xlabel(f"{sweep.parameter} [{unit}]")
    ax.set_ylabel(f"reachable volume [{table[0]['volume_unit']}]")
    ax = figure.add_subplot(1, 2, 2)
    index = [np.nan if r["mean_reachability_index"] is None else r["mean_reachability_index"] for r in table]
    ax.plot(values, index, marker="o")
    ax.set_xlabel(f"{sweep.parameter} [{unit}]")
    ax.set_ylabel("mean reachability index")
    ax.set_ylim(0, 1)
    figure.suptitle(f"design sweep over {sweep.parameter}", fontsize=12)
    return figure
