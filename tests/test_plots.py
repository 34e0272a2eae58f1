"""Trajectory figures: the P-V-A grid (limits, waypoints) and the 3-D tool path, saved headless."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from conftest import WAIT_S
from helpers import SEED_WAYPOINTS
from PIL import Image

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


@pytest.mark.slow
def test_without_the_plot_extra_everything_but_figures_works_and_a_figure_says_what_to_install(tmp_path):
    """matplotlib and Pillow are the extra "plot": with them hidden (an import finder refuses them, as
    on a machine where `pip install armkit` left them out), `import armkit` and kinematics, IK, a
    trajectory and the `armkit` command work, and a figure asked for is one armkit error naming
    the extra, from Python and from the command line."""
    waypoints = tmp_path / "waypoints.csv"
    waypoints.write_text("0,0,0,0,0,0\n0.1,-0.5,0.4,0,0.7,0.1\n")
    code = (
        "import sys\n"
        "class NoPlots:\n"
        "    def find_spec(self, name, path, target=None):\n"
        "        if name.split('.')[0] in ('matplotlib', 'PIL', 'mpl_toolkits'):\n"
        "            raise ImportError(f'No module named {name!r}')\n"
        "sys.meta_path.insert(0, NoPlots())\n"
        "import armkit\n"
        "from armkit.errors import ArmkitError\n"
        "robot = armkit.load('probot-anno')\n"
        "q = robot.ik(robot.fk([0.1, -0.5, 0.4, 0.0, 0.7, 0.1]), near=[0.1, -0.5, 0.4, 0.0, 0.7, 0.1])\n"
        "armkit.min_jerk([[0.0] * 6, q.tolist()], [2.0])\n"
        "print('computed', (q.round(3) + 0.0).tolist())\n"
        "for figure in (lambda: robot.plot(q), lambda: __import__('armkit.plots')):\n"
        "    try:\n"
        "        figure()\n"
        "    except ArmkitError as exc:\n"
        "        print('error', exc)\n"
        "from armkit.cli.main import main\n"
        "sys.argv = ['armkit', 'fk', 'probot-anno', '0', '0', '0', '0', '0', '0']\n"
        "fk_code = main()\n"
        f"sys.argv = ['armkit', 'traj', 'probot-anno', '--waypoints', {str(waypoints)!r},\n"
        f"            '--durations', '2', '--plot', {str(tmp_path / 'pva.png')!r}]\n"
        "print('exit codes', fk_code, main())\n")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=WAIT_S)
    lines = result.stdout.splitlines()
    assert result.returncode == 0, result.stderr
    assert lines[0] == "computed [0.1, -0.5, 0.4, 0.0, 0.7, 0.1]"
    needs = "plots need matplotlib and Pillow, which are not installed: pip install 'armkit[plot]'"
    assert lines[1:3] == [f"error {needs}"] * 2
    assert lines[-1] == "exit codes 0 1" and needs in result.stderr
    assert "Traceback" not in result.stderr and not (tmp_path / "pva.png").exists()
