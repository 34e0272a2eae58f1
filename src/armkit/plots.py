"""Figures of trajectories: position / velocity / acceleration per joint, and the tool path in 3-D.

Every function builds a :class:`matplotlib.figure.Figure` directly (no ``pyplot``, so no
global figure state and no GUI backend) and can save it to PNG, SVG or PDF.

>>> import armkit
>>> from armkit.trajectory import min_jerk
>>> robot = armkit.load("probot-anno")
>>> traj = min_jerk([[0.0] * 6, [0.5, -0.3, 0.2, 0.0, 0.4, 0.0]], [4.0])
>>> fig = plot_pva(traj, robot)
>>> len(fig.axes)
18
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from armkit._io import atomic_write, check_output_path
from armkit.errors import InputError, missing_extra
from armkit.robot import Robot
from armkit.trajectory.joint_trajectory import JointTrajectory

try:  # an optional dependency (the extra "plot")
    from matplotlib.figure import Figure
    from mpl_toolkits.mplot3d import Axes3D  # noqa: F401  (registers the "3d" projection)
except ImportError as exc:
    raise missing_extra("plot", "plots need matplotlib and Pillow") from exc

__all__ = ["plot_pva", "plot_tool_path", "save_figure"]

_FORMATS = (".png", ".svg", ".pdf")
_QUANTITIES = (("position", ""), ("velocity", "/s"), ("acceleration", "/s²"), ("torque", ""))


def save_figure(figure: Figure, path: str | Path, overwrite: bool = False, dpi: int = 150) -> Path:
    """Save ``figure`` as PNG, SVG or PDF (by extension); never over an existing file unless asked."""
    path = Path(path)
    if path.suffix.lower() not in _FORMATS:
        raise InputError(f"{path}: expected a figure file ending in {', '.join(_FORMATS)}")
    check_output_path(path, overwrite)
    with atomic_write(path) as partial:
        figure.savefig(partial, dpi=dpi)
    return path


#: Most samples a figure draws per curve by default (a long trajectory is drawn at a lower rate).
MAX_PLOT_SAMPLES = 100_000


def _rate(trajectory: JointTrajectory, rate_hz: float | None) -> float:
    """``rate_hz``, or by default 2000 samples or 50 Hz, whichever is more, up to MAX_PLOT_SAMPLES."""
    if rate_hz is not None:
        return rate_hz
    return min(max(50.0, 2000.0 / trajectory.duration), MAX_PLOT_SAMPLES / trajectory.duration)


#: A curve whose range is below this fraction of its size is at rest: drawn flat, not magnified.
_AT_REST = 1e-9


def plot_pva(trajectory: JointTrajectory, robot: Robot | None = None, *, rate_hz: float | None = None,
             title: str | None = None, torques: bool = False, degrees: bool = False) -> Figure:
    """Position, velocity and acceleration (and torque) of every joint against time, one panel each.

    Rows are position, velocity and acceleration, and with ``torques`` the joint torques
    (:meth:`JointTrajectory.torques`); columns are joints. Velocity, acceleration and torque
    limits of ``robot`` (if given and finite) are drawn as dashed red lines, its position
    limits when within 1.5 times the curve's range of it; waypoints are marked with dots
    and dotted vertical lines.

    Parameters
    ----------
    trajectory : JointTrajectory
    robot : Robot, optional
        For joint names, units and limits.
    rate_hz : float, optional
        Sampling rate of the curves [Hz]; default about 2000 points, at least 50 Hz.
    title : str, optional
    torques : bool
        Add a row of joint torques [N m or N]; needs ``robot`` with inertial parameters.
    degrees : bool
        Revolute joints in deg, deg/s, deg/s² (as ``armkit traj --deg`` prints them); prismatic
        ones stay in metres, torques in N m or N.

    Raises
    ------
    InputError
        If ``torques`` is asked for without a robot.
    """
    if torques and robot is None:
        raise InputError("plot_pva(torques=True): expected the robot too (its masses give the torques)")
    samples = trajectory.sample(_rate(trajectory, rate_hz))
    rows = [*samples[1:4]]
    if torques:
        rows.append(robot.inverse_dynamics(samples.q, samples.qd, samples.qdd))
    n = trajectory.n
    names = robot.joint_names if robot is not None else [f"q{j + 1}" for j in range(n)]
    prismatic = np.asarray(robot.chain.prismatic if robot is not None else [False] * n)
    scale = np.where(prismatic | (not degrees), 1.0, 180 / np.pi)  # SI to the shown unit, per joint
    limits = ([None if robot is None else robot.limits * scale[:, None],
               None if robot is None else robot.max_velocity * scale,
               None if robot is None else robot.max_acceleration * scale,
               None if robot is None else robot.max_torque])
    figure = Figure(figsize=(2.6 * n + 1.0, 2.4 * len(rows)), layout="constrained")
    axes = figure.subplots(len(rows), n, sharex=True, squeeze=False)
    times = trajectory.waypoint_times
    colors = [f"C{j}" for j in range(n)]
    for row, ((quantity, per), values) in enumerate(zip(_QUANTITIES, rows, strict=False)):
        for j in range(n):
            ax = axes[row, j]
            shown = values[:, j] * (scale[j] if quantity != "torque" else 1.0)
            ax.plot(samples.t, shown, color=colors[j], lw=1.6)
            for t in times:
                ax.axvline(t, color="0.6", lw=0.6, ls=":")
            if row == 0:
                ax.plot(times, trajectory.waypoints[:, j] * scale[j], "o", color="k", ms=4, zorder=3)
                ax.set_title(names[j], fontsize=10)
            _draw_limits(ax, limits[row], j, shown, row)
            if quantity == "torque":
                unit = "N" if prismatic[j] else "N m"
            else:
                unit = ("m" if prismatic[j] else "deg" if degrees else "rad") + per
            ax.set_ylabel(f"{quantity} [{unit}]" if j == 0 else f"[{unit}]", fontsize=9)
            ax.tick_params(labelsize=8)
            if np.ptp(shown) <= _AT_REST * max(1.0, np.abs(shown).max()):  # no "1e-16" scale on a flat line
                ax.set_ylim(shown.mean() - 1.0, shown.mean() + 1.0)
            ax.grid(True, lw=0.3, alpha=0.5)
    for ax in axes[-1, :]:
        ax.set_xlabel("time [s]", fontsize=9)
    label = title or (f"{robot.name + ': ' if robot is not None else ''}minimum-jerk trajectory, "
                      f"{trajectory.durations.size} segments, {trajectory.duration:.3g} s "
                      f"(dots: waypoints, dashed: limits)")
    figure.suptitle(label, fontsize=11)
    return figure


def _draw_limits(ax, limits, j: int, values: np.ndarray, row: int) -> None:
    if limits is None:
        return
    if row == 0:
        low, high = limits[j]
        reach = 1.5 * max(np.ptp(values), 1e-3)
        for bound in (low, high):
            if values.min() - reach <= bound <= values.max() + reach:
                ax.axhline(bound, color="tab:red", lw=1.0, ls="--")
        return
    bound = limits[j]
    if np.isfinite(bound):
        for sign in (1, -1):
            ax.axhline(sign * bound, color="tab:red", lw=1.0, ls="--")


def plot_tool_path(robot: Robot, trajectory: JointTrajectory, *, rate_hz: float | None = None,
                   title: str | None = None) -> Figure:
    """The tool position along the trajectory in 3-D (forward kinematics of the samples).

    The path is coloured by time; waypoints are black dots numbered in order, and the
    arm is drawn (link frames' origins) at the start and at the end.
    """
    samples = trajectory.sample(_rate(trajectory, rate_hz))
    path = robot.fk(samples.q)[:, :3, 3]
    figure = Figure(figsize=(7.0, 6.2), layout="constrained")
    ax = figure.add_subplot(projection="3d")
    points = ax.scatter(*path.T, c=samples.t, cmap="viridis", s=4, depthshade=False)
    ax.plot(*path.T, color="0.4", lw=0.6)
    corners = robot.fk(trajectory.waypoints)[:, :3, 3]
    ax.scatter(*corners.T, color="k", s=30, depthshade=False)
    for k, point in enumerate(corners, start=1):
        ax.text(*point, f"  {k}", fontsize=9)
    for q, style in ((trajectory.waypoints[0], "-"), (trajectory.waypoints[-1], "--")):
        links = robot.link_frames(q)[:, :3, 3]
        ax.plot(*links.T, style, color="tab:gray", lw=2.0, marker="o", ms=3, alpha=0.7)
    arm_points = robot.link_frames(trajectory.waypoints[[0, -1]])[..., :3, 3].reshape(-1, 3)
    everything = np.vstack([path, arm_points])
    center = (everything.max(axis=0) + everything.min(axis=0)) / 2
    radius = (everything.max(axis=0) - everything.min(axis=0)).max() / 2 * 1.05
    ax.set(xlim=(center[0] - radius, center[0] + radius), ylim=(center[1] - radius, center[1] + radius),
           zlim=(center[2] - radius, center[2] + radius), xlabel="x [m]", ylabel="y [m]", zlabel="z [m]")
    ax.set_box_aspect((1, 1, 1))
    figure.colorbar(points, ax=ax, shrink=0.6, label="time [s]")
    ax.set_title(title or f"{robot.name}: tool path ({trajectory.duration:.3g} s; grey: arm at start "
                          f"and end)", fontsize=10)
    return figure
