"""JointTrajectory: evaluation shapes, sampling, CSV / NPZ export and overwrite protection."""

from __future__ import annotations

import numpy as np
import pytest

from armkit.errors import InputError
from armkit.trajectory import min_jerk

WAYPOINTS = np.array([[0.0, 1.0], [0.5, 0.0], [1.0, 2.0]])


@pytest.fixture
def traj():
    return min_jerk(WAYPOINTS, [1.0, 1.5])


def test_at_time_shapes_and_values(traj):
    q, qd, qdd = traj.at_time(1.0)
    assert q.shape == qd.shape == qdd.shape == (2,)
    np.testing.assert_allclose(q, WAYPOINTS[1], atol=1e-14)
    q, qd, qdd = traj.at_time(np.linspace(0, 2.5, 7))
    assert q.shape == (7, 2)
    with pytest.raises(InputError, match=r"t: expected times in \[0, 2.5\] s"):
        traj.at_time(3.0)


def test_sample_grid_includes_the_end(traj):
    samples = traj.sample(4.0)
    np.testing.assert_allclose(samples.t, np.arange(11) / 4.0)
    samples = traj.sample(3.0)
    assert samples.t[-1] == 2.5 and np.allclose(np.diff(samples.t[:-1]), 1 / 3)
    np.testing.assert_allclose(samples.q[-1], WAYPOINTS[-1], atol=1e-14)
    assert samples.qddd.shape == samples.q.shape
    with pytest.raises(InputError, match="positive sampling rate"):
        traj.sample(0.0)


def test_csv_header_and_values_round_trip(traj, tmp_path):
    path = traj.to_csv(tmp_path / "traj.csv", rate_hz=10.0)
    header = path.read_text().splitlines()[0]
    assert header == "t,q1,q2,qd1,qd2,qdd1,qdd2"
    table = np.loadtxt(path, delimiter=",", skiprows=1)
    samples = traj.sample(10.0)
    np.testing.assert_array_equal(table, np.column_stack([samples.t, samples.q, samples.qd, samples.qdd]))


def test_npz_has_the_csv_names(traj, tmp_path):
    path = traj.to_npz(tmp_path / "traj.npz", rate_hz=10.0)
    with np.load(path) as data:
        assert sorted(data.files) == sorted(["t", "q1", "q2", "qd1", "qd2", "qdd1", "qdd2"])
        np.testing.assert_array_equal(data["qd2"], traj.sample(10.0).qd[:, 1])


def test_refuses_to_overwrite_unless_asked(traj, tmp_path):
    path = tmp_path / "traj.csv"
    path.write_text("precious")
    with pytest.raises(InputError, match="already exists; pass overwrite=True"):
        traj.to_csv(path)
    assert path.read_text() == "precious"
    traj.to_csv(path, overwrite=True)
    assert path.read_text().startswith("t,q1")
    with pytest.raises(InputError, match="must end in .npz"):
        traj.to_npz(tmp_path / "traj.dat")


def test_arrays_are_read_only(traj):
    with pytest.raises(ValueError, match="read-only"):
        traj.durations[0] = 5.0


@pytest.mark.parametrize("suffix", [".csv", ".npz"])
def test_read_trajectory_round_trip(traj, tmp_path, suffix):
    import armkit
    from armkit.trajectory.export import read_trajectory

    robot = armkit.load("grb400-scara")  # 4 joints
    four = min_jerk(np.column_stack([WAYPOINTS, WAYPOINTS * 0.01]), [1.0, 1.5])
    path = tmp_path / f"traj{suffix}"
    (four.to_npz if suffix == ".npz" else four.to_csv)(path, rate_hz=20.0)
    samples = four.sample(20.0)
    t, q, qd = read_trajectory(path, robot)
    np.testing.assert_array_equal(t, samples.t)
    np.testing.assert_array_equal(q, samples.q)
    np.testing.assert_array_equal(qd, samples.qd)
    with pytest.raises(InputError, match="has 4 joint columns .* PROBOT Anno has 6 joints"):
        read_trajectory(path, armkit.load("probot-anno"))


def test_read_trajectory_csv_rules(tmp_path):
    import armkit
    from armkit.trajectory.export import read_trajectory

    robot = armkit.load("grb400-scara")
    path = tmp_path / "bare.csv"
    path.write_text("# t q1 q2 q3 q4\n0, 0 0 0 0\n1, 0.1 0 0 0  # end\n")
    t, q, qd = read_trajectory(path, robot)
    np.testing.assert_array_equal(t, [0.0, 1.0])
    assert q.shape == (2, 4) and q[1, 0] == 0.1 and qd is None
    path.write_text("t,q1,q2,q3,q4\n0,0,0,0,0\n1,0,0,0\n")
    with pytest.raises(InputError, match="line 3: expected 5 values per row, got 4"):
        read_trajectory(path, robot)
    path.write_text("t,q1,q2,q3,q4\n0,0,0,0,0\nq,0,0,0,0\n")
    with pytest.raises(InputError, match="line 3: expected 5 numbers"):
        read_trajectory(path, robot)
    with pytest.raises(InputError, match="does not exist"):
        read_trajectory(tmp_path / "missing.csv", robot)
