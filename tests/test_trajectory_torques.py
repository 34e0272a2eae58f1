"""Joint torques along trajectories: ``JointTrajectory.torques``, the torque row of ``plot_pva``,
``armkit traj --torques``."""

import json
from dataclasses import replace

import numpy as np
import pytest

import armkit
from armkit.cli.main import main
from armkit.errors import InputError, RobotDefinitionError
from armkit.trajectory import min_jerk

WAYPOINTS = [[0, 0, 0, 0, 0, 0], [0.5, 0.3, -0.2, 0, 0.4, 0], [1, 0.5, -0.5, 0.2, 0.4, 0]]


def test_trajectory_torques_are_inverse_dynamics_of_the_samples():
    robot = armkit.load("puma560")
    traj = min_jerk(WAYPOINTS, [1.0, 1.5])
    torques = traj.torques(robot, rate_hz=200.0, gravity=[0, 0, -3.7])
    samples = traj.sample(200.0)
    assert np.array_equal(torques.t, samples.t)
    expected = robot.inverse_dynamics(samples.q, samples.qd, samples.qdd, gravity=[0, 0, -3.7])
    np.testing.assert_array_equal(torques.tau, expected)
    np.testing.assert_array_equal(torques.peak, np.abs(expected).max(axis=0))


def test_torques_need_masses_and_a_positive_rate():
    traj = min_jerk(WAYPOINTS, [1.0, 1.0])
    with pytest.raises(RobotDefinitionError, match="joint q1 has no inertial parameters"):
        traj.torques(armkit.load("ur5"))
    with pytest.raises(InputError, match="rate_hz: expected a positive sampling rate"):
        traj.torques(armkit.load("puma560"), rate_hz=0.0)


def test_plot_pva_adds_a_torque_row_with_the_limits():
    from armkit.plots import plot_pva

    robot = armkit.load("puma560")
    limited = armkit.Robot(armkit.Chain(tuple(replace(j, max_torque=50.0) for j in robot.chain.joints)),
                           name="limited")
    figure = plot_pva(min_jerk(WAYPOINTS, [1.0, 1.0]), limited, torques=True)
    assert len(figure.axes) == 4 * 6
    assert figure.axes[3 * 6].get_ylabel() == "torque [N m]"
    torque_axis = figure.axes[3 * 6 + 1]
    dashed = [line.get_ydata()[0] for line in torque_axis.lines if line.get_linestyle() == "--"]
    assert sorted(dashed) == [-50.0, 50.0]
    with pytest.raises(InputError, match=r"plot_pva\(torques=True\): expected the robot too"):
        plot_pva(min_jerk(WAYPOINTS, [1.0, 1.0]), torques=True)


def test_cli_traj_torques_reports_peaks_and_draws_the_row(capsys, tmp_path):
    waypoints = tmp_path / "w.csv"
    np.savetxt(waypoints, WAYPOINTS, delimiter=",")
    plot = tmp_path / "pvat.png"
    code = main(["traj", "puma560", "--waypoints", str(waypoints), "--durations", "1", "1", "--torques",
                 "--plot", str(plot), "--json"])
    out, _ = capsys.readouterr()
    assert code == 0 and plot.stat().st_size > 0
    data = json.loads(out)
    expected = min_jerk(WAYPOINTS, [1.0, 1.0]).torques(armkit.load("puma560"), 1000.0).peak
    np.testing.assert_allclose(data["peak_torque"], expected, rtol=1e-12)
    code = main(["traj", "ur5", "--waypoints", str(waypoints), "--durations", "1", "1", "--torques",
                 "--estimate-inertia", "1000"])
    out, _ = capsys.readouterr()
    assert code == 0 and "peak |torque|" in out and "N m" in out
