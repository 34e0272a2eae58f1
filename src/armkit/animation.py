"""Pictures of an arm: a still PNG of a configuration with its link frames, and GIF animations.

Drawn with matplotlib's 3-D axes without ``pyplot`` (no GUI backend, no global figure
state, no GPU, no ffmpeg; GIF frames are blitted and assembled by Pillow). The links
are the same cylinders the simulation model uses (:mod:`armkit.export.physical`): from
each joint along its axis, then to the next joint. Frames are drawn as red/green/blue
x/y/z arrows: the base, every DH link frame and the tool. A light grey shadow on the
floor helps the eye place the arm in depth.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit import kinematics
from armkit._io import atomic_write
from armkit.errors import InputError, missing_extra
from armkit.export.physical import PhysicalModel, physical_model
from armkit.robot import Robot

try:  # optional dependencies (the extra "plot")
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.ticker import MaxNLocator
    from mpl_toolkits.mplot3d import Axes3D  # noqa: F401  (registers the "3d" projection)
    from PIL import Image
except ImportError as exc:
    raise missing_extra("plot", "plots need matplotlib and Pillow") from exc

if TYPE_CHECKING:  # a scene is MuJoCo's: imported only by whoever builds one
    from armkit.collision.scene import Scene, WorldShape

__all__ = ["GHOST_ALPHA", "animate_trajectory", "plot_arm", "plot_configuration", "plot_configurations"]

_LINK_COLORS = ("#d9731f", "#3366bf")
_JOINT_COLOR = "#404047"
_AXIS_COLORS = ("#d62728", "#2ca02c", "#1f77b4")
_PATH_COLOR = "#8e44ad"
#: Most tick labels per axis of a 3-D picture (more overlap in the small multiples of plot_configurations).
TICKS = 4
_OBSTACLE_COLOR = "#b03a2e"
#: Points per circle of a sphere's or a cylinder's outline.
_CIRCLE_POINTS = 48


def _polylines(robot: Robot, model: PhysicalModel, q: NDArray[np.float64]) -> list[NDArray[np.float64]]:
    """World coordinates of every link cylinder: base first, one ``(k, 2, 3)`` array per body."""
    frames, _ = kinematics.joint_frames(robot, q)
    lines = [model.base.segments]
    for T, body, q_i, prismatic in zip(frames, model.bodies, q, robot.chain.prismatic, strict=True):
        segments = body.segments @ T[:3, :3].T + T[:3, 3]
        if prismatic:  # the sliding rod: from the joint frame before the motion to after it
            rod = np.array([[T[:3, 3] - q_i * T[:3, 2], T[:3, 3]]])
            segments = np.concatenate([rod, segments])
        lines.append(segments)
    return lines


def _outlines(shape: WorldShape) -> list[NDArray[np.float64]]:
    """Polylines ``(k, 3)`` [m] outlining one of a scene's geoms (:meth:`Scene.world_shapes`) in the
    base frame: a box's 12 edges, a sphere's three great circles, a cylinder's end circles and four
    lines along it, a mesh's triangle edges; the floor plane none (the axes show a floor)."""
    circle = np.linspace(0.0, 2.0 * np.pi, _CIRCLE_POINTS)
    ring = np.stack([np.cos(circle), np.sin(circle), np.zeros_like(circle)], axis=1)
    if shape.kind == "box":
        corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]) * shape.size
        local = [corners[[a, b]] for a in range(8) for b in range(a + 1, 8)
                 if np.count_nonzero(corners[a] != corners[b]) == 1]
    elif shape.kind == "sphere":
        local = [shape.size[0] * ring[:, order] for order in ([0, 1, 2], [0, 2, 1], [2, 0, 1])]
    elif shape.kind == "cylinder":
        radius, half = shape.size[0], shape.size[1]
        local = [radius * ring - [0, 0, half], radius * ring + [0, 0, half],
                 *(np.array([[radius * x, radius * y, -half], [radius * x, radius * y, half]])
                   for x, y in ((1, 0), (0, 1), (-1, 0), (0, -1)))]
    elif shape.kind == "mesh":
        edges = np.unique(np.sort(shape.faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1), axis=0)
        local = list(shape.vertices[edges])
    else:
        local = []
    T = shape.T_base_geom
    return [line @ T[:3, :3].T + T[:3, 3] for line in local]


def _bounds(robot: Robot, model: PhysicalModel, q: NDArray[np.float64],
            extra: Sequence[NDArray[np.float64]] = ()) -> tuple[NDArray, float]:
    """Centre and half-width of a cube holding the arm at every configuration ``(m, n)`` and the
    ``extra`` points ``(k, 3)`` (obstacle outlines)."""
    points = [np.zeros((1, 3)), *extra]
    for q_k in q:
        points += [seg.reshape(-1, 3) for seg in _polylines(robot, model, q_k)]
        points.append(robot.link_frames(q_k)[:, :3, 3])
    points = np.vstack(points)
    low, high = points.min(axis=0), points.max(axis=0)
    return (low + high) / 2, max(float((high - low).max()) / 2 * 1.1, 4 * model.radius)


def _setup_axes(ax, centre: NDArray, half: float, title: str) -> float:
    floor = centre[2] - half
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_zlim(floor, centre[2] + half)
    ax.set_box_aspect((1, 1, 1))
    ax.set_xlabel("x [m]", labelpad=-6, fontsize=8)
    ax.set_ylabel("y [m]", labelpad=-6, fontsize=8)
    ax.set_zlabel("z [m]", labelpad=-6, fontsize=8)
    ax.tick_params(labelsize=6, pad=-2)
    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        axis.set_major_locator(MaxNLocator(nbins=TICKS))   # labels that do not run into each other
        axis.set_pane_color((0.96, 0.96, 0.97, 1.0))
        axis._axinfo["grid"]["color"] = (0.85, 0.85, 0.88, 1.0)
    if title:
        ax.set_title(title, fontsize=10)
    return floor


def _draw_frame(ax, T: NDArray[np.float64], length: float, width: float, name: str,
                alpha: float = 1.0) -> None:
    """A triad: the frame's x, y, z axes as red, green, blue strokes of ``length`` [m] from its origin."""
    for k in range(3):
        end = T[:3, 3] + length * T[:3, k]
        ax.plot(*np.transpose([T[:3, 3], end]), color=_AXIS_COLORS[k], linewidth=width,
                solid_capstyle="round", gid=f"{name} {'xyz'[k]}", alpha=alpha)


def _draw_arm(ax, robot: Robot, model: PhysicalModel, q: NDArray[np.float64], floor: float,
              half: float, frames: bool, *, alpha: float = 1.0, base_frame: bool = False,
              joint_axes: bool = False, gid: str = "") -> None:
    """The arm at ``q``: link cylinders as thick strokes with their floor shadow, joint origins,
    the tool frame, and on request every link frame, the base frame and each joint's axis.

    Artists carry a ``gid`` naming what they show (``"base x"``, ``"link 3 z"``, ``"tool y"``,
    ``"axis q2"``, ``"joint origins"``), after the prefix ``gid``, so a figure can be read back by
    what it draws."""
    lines = _polylines(robot, model, q)
    width = 7.0
    for k, segments in enumerate(lines):
        for start, end in segments:
            xs, ys, zs = np.transpose([start, end])
            ax.plot(xs, ys, np.full(2, floor), color="#c8c8cc", linewidth=width * 0.8,
                    solid_capstyle="round", alpha=0.6 * alpha)
            color = _JOINT_COLOR if k == 0 else _LINK_COLORS[(k - 1) % 2]
            ax.plot(xs, ys, zs, color=color, linewidth=width, solid_capstyle="round", alpha=alpha)
    joints, T_tool = kinematics.joint_frames(robot, q)
    ax.scatter(*joints[:, :3, 3].T, s=70, color=_JOINT_COLOR, depthshade=False, zorder=5, alpha=alpha,
               gid=f"{gid}joint origins")
    if joint_axes:
        for name, T in zip(robot.joint_names, joints, strict=True):
            ends = T[:3, 3] + np.outer([-1.0, 1.0], 0.12 * half * T[:3, 2])
            ax.plot(*ends.T, color="#111111", linewidth=1.6, linestyle="--", alpha=alpha,
                    gid=f"{gid}axis {name}")
    every = robot.link_frames(q)
    drawn = every[:-1] if frames else every[:1] if base_frame else every[:0]
    for i, T in enumerate(drawn):
        _draw_frame(ax, T, 0.14 * half, 1.3, gid + ("base" if i == 0 else f"link {i}"), alpha)
    _draw_frame(ax, T_tool, 0.25 * half, 2.6, f"{gid}tool", alpha)
    ax.text(*(T_tool[:3, 3] + 0.06 * half), "tool", fontsize=8, color=_JOINT_COLOR, alpha=alpha)


def _axis_legend(ax) -> None:
    for k, (name, color) in enumerate(zip("xyz", _AXIS_COLORS, strict=True)):
        ax.text2D(0.86 + 0.04 * k, 0.95, name, transform=ax.transAxes, color=color, fontsize=9,
                  fontweight="bold")


def _trajectory(robot: Robot, q: ArrayLike) -> NDArray[np.float64]:
    q = robot.check_q(q, "trajectory q")
    if q.ndim != 2 or len(q) < 1:
        raise InputError(f"trajectory q: expected shape (samples, {robot.n}), got {q.shape}")
    return q


def plot_configuration(robot: Robot, q: ArrayLike, path: str | Path | None = None, *,
                       title: str | None = None, frames: bool = True, dpi: int = 110,
                       size: float = 4.8) -> Figure:
    """A 3-D picture of ``robot`` at ``q`` with its base, DH link and tool frames.

    Parameters
    ----------
    robot : Robot
    q : array_like (n,)
        Joint values [rad or m].
    path : str or Path, optional
        Save a PNG there (the figure is returned either way).
    title : str, optional
        Default: the robot's name and ``q``.
    frames : bool
        Draw the DH link frames (the tool frame is always drawn).
    dpi, size : int, float
        Resolution and figure size [inch].

    Examples
    --------
    >>> import armkit
    >>> figure = plot_configuration(armkit.load("probot-anno"), [0, -0.5, 0.5, 0, 1, 0])
    >>> len(figure.axes)
    1
    """
    q = robot.check_q(q)
    label = title if title is not None else f"{robot.name}   q = [{', '.join(f'{v:.3g}' for v in q)}]"
    return plot_configurations(robot, q[None], path, titles=[label], frames=frames, dpi=dpi, size=size)


def plot_configurations(robot: Robot, q: ArrayLike, path: str | Path | None = None, *,
                        titles: list[str] | None = None, frames: bool = True, columns: int = 4,
                        dpi: int = 110, size: float = 4.8) -> Figure:
    """Several configurations side by side (e.g. every IK solution of one pose), same scale.

    Parameters
    ----------
    robot : Robot
    q : array_like (m, n)
        Joint values [rad or m], one picture each.
    path : str or Path, optional
        Save a PNG there.
    titles : list of str, optional
        One per configuration; default ``q`` itself.
    frames : bool
        Draw the DH link frames.
    columns : int
        Pictures per row.
    dpi, size : int, float
        Resolution and size of one picture [inch].

    Examples
    --------
    >>> import armkit
    >>> robot = armkit.load("probot-anno")
    >>> T = robot.fk([0.9, -0.7, -0.4, 0, 1.1, 0.9])
    >>> figure = plot_configurations(robot, robot.ik(T, all_solutions=True))
    >>> len(figure.axes)
    4
    """
    q = _trajectory(robot, q)
    titles = [f"q = [{', '.join(f'{v:.3g}' for v in q_k)}]" for q_k in q] if titles is None else titles
    if len(titles) != len(q):
        raise InputError(f"titles: expected {len(q)}, one per configuration, got {len(titles)}")
    model = physical_model(robot)
    centre, half = _bounds(robot, model, q)
    rows, cols = -(-len(q) // columns), min(columns, len(q))
    figure = Figure(figsize=(size * cols, size * rows), dpi=dpi)
    for k, (q_k, label) in enumerate(zip(q, titles, strict=True)):
        ax = figure.add_subplot(rows, cols, k + 1, projection="3d")
        ax.view_init(elev=22, azim=-58)
        floor = _setup_axes(ax, centre, half, label)
        _draw_arm(ax, robot, model, q_k, floor, half, frames)
        _axis_legend(ax)
    figure.subplots_adjust(left=0.02, right=0.95, bottom=0.03, top=0.93, wspace=0.05)
    if path is not None:
        with atomic_write(path) as partial:
            figure.savefig(partial, dpi=dpi)
    return figure


#: Opacity of the ghost arms of :func:`plot_arm` (every configuration of a batch but the last).
GHOST_ALPHA = 0.25


def plot_arm(robot: Robot, q: ArrayLike, *, ax: Any = None, frames: bool = False, joint_axes: bool = True,
             title: str | None = None, size: float = 5.0, elev: float = 22.0, azim: float = -58.0) -> Figure:
    """Draw ``robot`` at ``q`` in matplotlib 3-D (what :meth:`armkit.Robot.plot` calls).

    Links are thick strokes along the cylinders of the simulation model (from each joint along
    its axis, then to the next joint) with a shadow on the floor; joint origins are dots, each
    joint's axis a dashed stroke through its origin; the base and tool frames are red/green/blue
    x/y/z triads. The axes have equal scale in x, y and z.

    A batch ``q`` ``(N, n)`` draws every configuration into the same axes: the last one as the
    arm, the others as translucent ghosts (the IK solutions of one pose, a few samples of a
    motion). For a moving picture see :func:`animate_trajectory`.

    Parameters
    ----------
    robot : Robot
    q : array_like (n,) or (N, n)
        Joint values [rad or m].
    ax : mpl_toolkits.mplot3d.Axes3D, optional
        Draw into these axes (made with ``projection="3d"``); their limits grow to hold the arm.
        Default: a new figure of its own.
    frames : bool
        Also draw every link frame (after each joint).
    joint_axes : bool
        Draw each joint's axis.
    title : str, optional
        Default: the robot's name and the (last) ``q``.
    size : float
        Side of a new figure [inch].
    elev, azim : float
        Viewing angles of a new figure [deg] (matplotlib's ``view_init``).

    Returns
    -------
    matplotlib.figure.Figure
        The figure drawn into (``ax.figure`` when ``ax`` is given); save it with
        ``figure.savefig`` or :func:`armkit.plots.save_figure`.

    Raises
    ------
    InputError
        If ``q`` has the wrong shape or ``ax`` is not a 3-D axes.

    Examples
    --------
    >>> import armkit
    >>> robot = armkit.load("probot-anno")
    >>> figure = plot_arm(robot, [0, -0.5, 0.5, 0, 1, 0])
    >>> ax = figure.axes[0]
    >>> tool_x = next(line for line in ax.lines if line.get_gid() == "tool x")
    >>> bool(np.allclose(np.array(tool_x.get_data_3d())[:, 0], robot.fk([0, -0.5, 0.5, 0, 1, 0])[:3, 3]))
    True
    """
    q = robot.check_q(q)
    batch = q.reshape(-1, robot.n)
    if q.ndim > 2 or len(batch) == 0:
        raise InputError(f"q: expected shape ({robot.n},) or (N, {robot.n}), got {q.shape}")
    model = physical_model(robot)
    centre, half = _bounds(robot, model, batch)
    if ax is None:
        figure = Figure(figsize=(size, size), layout="constrained")
        ax = figure.add_subplot(projection="3d")
        ax.view_init(elev=elev, azim=azim)
    elif getattr(ax, "name", None) != "3d":
        raise InputError(f"ax: expected 3-D axes (figure.add_subplot(projection='3d')), got "
                         f"{type(ax).__name__}")
    elif ax.has_data():  # keep what the axes already show in view
        low, high = np.array([ax.get_xlim(), ax.get_ylim(), ax.get_zlim()]).T
        low, high = np.minimum(low, centre - half), np.maximum(high, centre + half)
        centre, half = (low + high) / 2, float((high - low).max()) / 2
    ghosts = f" and {len(batch) - 1} ghosts" if len(batch) > 1 else ""
    shown = ", ".join(f"{v:.3g}" for v in batch[-1])
    label = title if title is not None else f"{robot.name}   q = [{shown}]{ghosts}"
    floor = _setup_axes(ax, centre, half, label)
    for k, q_k in enumerate(batch):
        last = k == len(batch) - 1
        _draw_arm(ax, robot, model, q_k, floor, half, frames and last, alpha=1.0 if last else GHOST_ALPHA,
                  base_frame=last, joint_axes=joint_axes and last, gid="" if last else f"ghost {k + 1} ")
    _axis_legend(ax)
    return ax.figure


def animate_trajectory(robot: Robot, q: ArrayLike, path: str | Path, *, t: ArrayLike | None = None,
                       trace_tool: bool = True, frames: int = 40, fps: int = 12, dpi: int = 64,
                       size: float = 4.0, title: str = "", link_frames: bool = False,
                       labels: Sequence[str] | None = None, scene: Scene | None = None) -> Path:
    """Write a GIF of ``robot`` moving through the configurations ``q``.

    Frames are rendered with matplotlib (Agg) and assembled by Pillow, so neither ffmpeg
    nor a display is needed. The axes carry their numbers, in metres.

    Parameters
    ----------
    robot : Robot
    q : array_like (N, n)
        Configurations along the motion [rad or m]; ``frames`` of them are drawn, evenly
        spaced in index.
    path : str or Path
        The GIF to write.
    t : array_like (N,), optional
        Times [s] shown in the corner.
    trace_tool : bool
        Draw the tool path travelled so far (and faintly the whole path).
    frames, fps, dpi, size : int, int, int, float
        GIF length, speed, resolution and size [inch]; keep them small for small files.
    title : str
    link_frames : bool
        Draw every DH link frame (the tool frame is always drawn).
    labels : sequence of str, optional
        One text per configuration of ``q``, shown in the frames that draw it (e.g. which
        IK solution a frame shows).
    scene : Scene, optional
        Its obstacles are outlined in every frame, as its collision model holds them
        (:meth:`armkit.Scene.world_shapes`: meshes as their convex hulls' edges).

    Returns
    -------
    Path

    Examples
    --------
    >>> import armkit, tempfile, pathlib
    >>> robot = armkit.load("grb400-scara")
    >>> q = np.linspace([0, 0, 0, 0], [1.5, 1.2, 0.03, 1.0], 20)
    >>> out = animate_trajectory(robot, q, pathlib.Path(tempfile.mkdtemp()) / "scara.gif", frames=5)
    >>> out.stat().st_size > 0
    True
    """
    q = _trajectory(robot, q)
    times = None if t is None else np.asarray(t, dtype=float)
    if times is not None and times.shape != (len(q),):
        raise InputError(f"t: expected {len(q)} times, got shape {times.shape}")
    if labels is not None and len(labels) != len(q):
        raise InputError(f"labels: expected {len(q)}, one per configuration, got {len(labels)}")
    model = physical_model(robot)
    picks = np.unique(np.linspace(0, len(q) - 1, max(2, frames)).round().astype(int))
    if scene is not None:
        scene.check_robot(robot)
    outlines = [] if scene is None else [line for shape in scene.world_shapes() for line in _outlines(shape)]
    centre, half = _bounds(robot, model, q[picks], outlines)
    tool_path = robot.fk(q)[:, :3, 3]
    figure = Figure(figsize=(size, size), dpi=dpi)
    FigureCanvasAgg(figure)
    ax = figure.add_subplot(projection="3d")
    figure.subplots_adjust(left=0.0, right=1.0, bottom=0.0, top=0.94)
    ax.view_init(elev=22, azim=-58)
    floor = _setup_axes(ax, centre, half, title)
    if trace_tool:
        ax.plot(*tool_path.T, color=_PATH_COLOR, linewidth=0.8, alpha=0.25)
    for line in outlines:
        ax.plot(*line.T, color=_OBSTACLE_COLOR, linewidth=1.2)
    figure.canvas.draw()
    background = figure.canvas.copy_from_bbox(figure.bbox)  # axes drawn once; frames blit the arm on it
    images = []
    for k in picks:
        figure.canvas.restore_region(background)
        before = set(ax.lines) | set(ax.collections) | set(ax.texts)
        if trace_tool:
            ax.plot(*tool_path[: k + 1].T, color=_PATH_COLOR, linewidth=2.0)
        _draw_arm(ax, robot, model, q[k], floor, half, link_frames)
        if times is not None:
            ax.text2D(0.03, 0.03, f"t = {times[k]:.1f} s", transform=ax.transAxes, fontsize=8)
        if labels is not None:
            ax.text2D(0.03, 0.93, labels[k], transform=ax.transAxes, fontsize=8, fontweight="bold")
        added = [a for a in [*ax.lines, *ax.collections, *ax.texts] if a not in before]
        for artist in added:
            if hasattr(artist, "do_3d_projection"):
                artist.do_3d_projection()
            ax.draw_artist(artist)
        images.append(Image.fromarray(np.asarray(figure.canvas.buffer_rgba())[..., :3]).quantize(64))
        for artist in added:
            artist.remove()
    path = Path(path)
    with atomic_write(path) as partial:
        images[0].save(partial, save_all=True, append_images=images[1:], duration=int(1000 / fps), loop=0)
    return path
