"""Trajectory figures: the P-V-A grid (limits, waypoints) and the 3-D tool path, saved headless."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from conftest import WAIT_S
from PIL import Image
from test_trajectory_min_jerk import SEED_WAYPOINTS

import armkit
from armkit.errors import InputError
from armkit.plots import plot_pva, plot_tool_path, save_figure
from armkit.trajectory import min_jerk


@pytest.fixture(scope="module")
def robot():
    return armkit.load("probot-anno")


@pytest.fixture(scope="module")
def traj():
    return min_jerk(SEED_WAYPOINTS, [10, 10, 10])


def test_pva_grid_draws_curves_limits_and_waypoints(robot, traj):
    figure = plot_pva(traj, robot)
    axes = np.array(figure.axes).reshape(3, 6)
    velocity_axis = axes[1, 4]
    levels = {round(line.get_ydata()[0], 6) for line in velocity_axis.get_lines()
              if line.get_linestyle() == "--"}
    assert levels == {round(robot.max_velocity[4], 6), round(-robot.max_velocity[4], 6)}
    acceleration_levels = {round(line.get_ydata()[0], 6) for line in axes[2, 1].get_lines()
                           if line.get_linestyle() == "--"}
    assert acceleration_levels == {round(robot.max_acceleration[1], 6), round(-robot.max_acceleration[1], 6)}
    markers = [line for line in axes[0, 1].get_lines() if line.get_marker() == "o"]
    np.testing.assert_allclose(markers[0].get_ydata(), SEED_WAYPOINTS[:, 1])
    curve = axes[0, 1].get_lines()[0]
    np.testing.assert_allclose(curve.get_xdata()[[0, -1]], [0, 30])


def test_pva_without_robot_has_no_limits(traj):
    figure = plot_pva(traj)
    assert all(line.get_linestyle() != "--" for ax in figure.axes for line in ax.get_lines())


def test_saved_png_and_svg(robot, traj, tmp_path):
    png = save_figure(plot_pva(traj, robot), tmp_path / "pva.png")
    with Image.open(png) as image:
        assert image.size[0] > 1000
        pixels = np.asarray(image.convert("RGB"))
    assert (np.abs(pixels.astype(int) - [214, 39, 40]).sum(axis=-1) < 60).any()   # red limit lines
    svg = save_figure(plot_tool_path(robot, traj), tmp_path / "path.svg")
    assert svg.read_text().lstrip().startswith("<?xml")
    with pytest.raises(InputError, match="already exists"):
        save_figure(plot_pva(traj, robot), png)
    with pytest.raises(InputError, match="ending in .png, .svg, .pdf"):
        save_figure(plot_pva(traj, robot), tmp_path / "pva.bmp")


def test_tool_path_is_the_fk_of_the_samples(robot, traj):
    figure = plot_tool_path(robot, traj, rate_hz=10.0)
    ax = figure.axes[0]
    path_line = ax.get_lines()[0]
    x, y, z = path_line.get_data_3d()
    expected = robot.fk(traj.sample(10.0).q)[:, :3, 3]
    np.testing.assert_allclose(np.column_stack([x, y, z]), expected, atol=1e-12)


def test_plots_never_import_pyplot():
    code = ("import sys, armkit, armkit.plots as p, armkit.trajectory as t; r = armkit.load('probot-anno'); "
            "tr = t.min_jerk([[0.0] * 6, [0.1] * 6], [1.0]); p.plot_pva(tr, r); p.plot_tool_path(r, tr); "
            "print('matplotlib.pyplot' in sys.modules)")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=WAIT_S)
    assert result.stdout.strip() == "False", result.stderr


def test_pva_in_degrees_scales_curves_waypoints_and_limits_and_a_joint_at_rest_has_no_offset(robot):
    waypoints = np.array(SEED_WAYPOINTS)
    waypoints[:, 3] = [0.3, np.nextafter(0.3, 1), 0.3, 0.3]   # joint 4 at rest, but for a rounding step
    traj = min_jerk(waypoints, [10, 10, 10])
    plain, degrees = plot_pva(traj, robot), plot_pva(traj, robot, degrees=True)
    for figure in (plain, degrees):
        figure.canvas.draw()
    rad, deg = np.array(plain.axes).reshape(3, 6), np.array(degrees.axes).reshape(3, 6)
    np.testing.assert_allclose(deg[0, 1].get_lines()[0].get_ydata(),
                               np.degrees(rad[0, 1].get_lines()[0].get_ydata()), rtol=1e-12)
    limit = {round(line.get_ydata()[0], 6) for line in deg[1, 4].get_lines() if line.get_linestyle() == "--"}
    vmax = np.degrees(robot.max_velocity[4])
    assert limit == {round(vmax, 6), round(-vmax, 6)}
    assert deg[1, 0].get_ylabel() == "velocity [deg/s]" and rad[1, 0].get_ylabel() == "velocity [rad/s]"
    for axes in (rad, deg):       # a flat line at its true scale, no "1e-16" above the axis
        assert all(axes[row, 3].yaxis.get_offset_text().get_text() == "" for row in range(3))
        assert all(np.ptp(axes[row, 3].get_ylim()) >= 1.0 for row in range(3))
