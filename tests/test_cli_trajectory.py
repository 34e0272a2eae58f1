"""``armkit traj``: the done-when command, outputs, auto-time and every bad-input error."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest
from helpers import SEED_AMAX, SEED_VMAX, SEED_WAYPOINTS
from PIL import Image

import armkit
from armkit.cli.main import main
from armkit.trajectory import min_jerk, read_waypoints

DATA = Path(__file__).parent.parent / "examples" / "data"
POSES = str(DATA / "probot_seed_poses.csv")
JOINTS = str(DATA / "probot_seed_joints.csv")


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_done_when_seed_poses_to_pva_figure(capsys, tmp_path):
    png = tmp_path / "pva.png"
    code, out, err = run(capsys, "traj", "probot-anno", "--waypoints", POSES, "--poses",
                         "--durations", "10", "10", "10", "--plot", png)
    assert code == 0, err
    assert "3 segments, 30 s" in out and "q5" in out and "0.9599" in out
    assert "0.7955" in out and "2.9451" in out                 # IK waypoints, report p2 and p4
    with Image.open(png) as image:
        assert image.width > 1500 and image.height > 700


def test_csv_output_is_the_min_jerk_trajectory(capsys, tmp_path):
    csv = tmp_path / "traj.csv"
    code, _, err = run(capsys, "traj", "probot-anno", "--waypoints", JOINTS, "--durations", "10", "10", "10",
                       "--rate", "20", "--out", csv)
    assert code == 0, err
    lines = csv.read_text().splitlines()
    assert lines[0] == "t," + ",".join(f"{p}{j}" for p in ("q", "qd", "qdd") for j in range(1, 7))
    table = np.loadtxt(csv, delimiter=",", skiprows=1)
    assert table.shape == (601, 19)
    samples = min_jerk(SEED_WAYPOINTS, [10, 10, 10]).sample(20.0)
    np.testing.assert_allclose(table[:, 1:7], samples.q, atol=1e-15)
    np.testing.assert_allclose(table[:, 7:13], samples.qd, atol=1e-15)


def test_auto_time_meets_the_limits_and_is_tight(capsys, tmp_path):
    npz = tmp_path / "traj.npz"
    code, out, err = run(capsys, "traj", "probot-anno", "--waypoints", JOINTS, "--auto-time",
                         "--rate", "1000", "--out", npz)
    assert code == 0, err
    with np.load(npz) as data:
        qd = np.column_stack([data[f"qd{j}"] for j in range(1, 7)])
        qdd = np.column_stack([data[f"qdd{j}"] for j in range(1, 7)])
        duration = data["t"][-1]
    assert np.all(np.abs(qd).max(axis=0) <= SEED_VMAX + 5e-5)    # robot file limits: whole degrees
    assert np.all(np.abs(qdd).max(axis=0) <= SEED_AMAX + 5e-5)
    assert (np.abs(qdd).max(axis=0) / SEED_AMAX).max() > 0.99                  # some joint at its limit
    assert duration < 10.0 and "1.000" in out


def test_times_are_the_same_as_durations(capsys):
    base = ["traj", "probot-anno", "--waypoints", JOINTS]
    code, by_times, _ = run(capsys, *base, "--times", "0", "10", "20", "30")
    code_d, by_durations, _ = run(capsys, *base, "--durations", "10", "10", "10")
    assert code == code_d == 0 and by_times == by_durations


def test_too_short_durations_are_stretched_and_reported(capsys):
    code, out, err = run(capsys, "traj", "probot-anno", "--waypoints", JOINTS, "--durations", "2", "2", "2")
    assert code == 0
    assert "stretched to meet the limits" in err


@pytest.mark.parametrize(("args", "message"), [
    (["--durations", "10", "10"], "4 waypoints need 3 segment durations, got 2"),
    (["--durations", "10", "0", "10"], r"must be from 1e-06 s to 1e\+06 s, got 0 s for segment 2"),
    (["--durations", "10", "-1", "10"], r"must be from 1e-06 s to 1e\+06 s, got -1 s"),
    (["--durations", "10", "x", "10"], "--durations: 'x' is not a number"),
    (["--durations", "10", "nan", "10"], "durations: contains NaN"),
    ([], r"give one of --durations D1 D2 ... .* --times T1 T2 ... .* or --auto-time"),
    (["--auto-time", "--durations", "1", "1", "1"], "give one of"),
    (["--times", "0", "10", "5", "30"], "times: must increase, but waypoint 3 is at 5 s after waypoint 2"),
    (["--times", "0", "10", "20"], "--times: 4 waypoints need 4 waypoint times, got 3"),
    (["--durations"], r"--durations: expected numbers \(seconds\) after it, got none"),
    (["--auto-time", "5"], "unexpected values 5"),
])
def test_bad_durations(capsys, args, message):
    code, _, err = run(capsys, "traj", "probot-anno", "--waypoints", JOINTS, *args)
    assert code == 1
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert re.search(message, " ".join(err.split())), err


@pytest.mark.parametrize(("text", "poses", "message"), [
    ("0,0,0,0,0,0\n", False, "at least two waypoints, found 1"),
    ("0,0,0,0,0,0\n1,1,1,1,1\n", False, "line 2: expected 6 values per waypoint, got 5"),
    ("0,0,0,0,0,0\n0,nan,0,0,0,0\n", False, "line 2: NaN"),
    ("0,0,0,0,0,0\n0,2.5,0,0,0,0\n", False, "waypoint 2: joint q2 = 2.5 rad is outside its limits"),
    ("0.2289,0,0.454,1.5707963,0,0\n2,0,0.3,0,0,0\n", True, "waypoint 2 .*"),
])
def test_bad_waypoint_files(capsys, tmp_path, text, poses, message):
    path = tmp_path / "w.csv"
    path.write_text(text)
    args = ["--poses"] if poses else []
    code, _, err = run(capsys, "traj", "probot-anno", "--waypoints", path, *args, "--durations", "5")
    assert code == 1 and "Traceback" not in err
    assert re.search(message, " ".join(err.split())), err


def test_never_overwrites_without_force(capsys, tmp_path):
    out = tmp_path / "traj.csv"
    out.write_text("keep me")
    args = ["traj", "probot-anno", "--waypoints", JOINTS, "--durations", "10", "10", "10", "--out", out]
    code, _, err = run(capsys, *args)
    assert code == 1 and "already exists; pass --force" in err
    assert out.read_text() == "keep me"
    code, _, err = run(capsys, *args, "--force")
    assert code == 0 and out.read_text().startswith("t,q1")
    code, _, err = run(capsys, "traj", "probot-anno", "--waypoints", JOINTS, "--auto-time", "--plot",
                       tmp_path / "pva.jpg")
    assert code == 1 and "expected a file name ending in .png, .svg, .pdf" in err


def test_a_path_that_would_overshoot_a_position_limit_is_kept_inside(capsys, tmp_path):
    path = tmp_path / "w.csv"
    path.write_text("0,0,0,0,0,0\n0,1.0,0,0,0,0\n0,2.0,0,0,0,0\n0,1.0,0,0,0,0\n")   # q2 limit 2.0071
    free = min_jerk(read_waypoints(path, 6), [10, 10, 10])
    assert free.position_limit_violations(armkit.load("probot-anno"))          # the spline alone overshoots
    out = tmp_path / "t.csv"
    code, stdout, err = run(capsys, "traj", "probot-anno", "--waypoints", path, "--durations", "10", "10",
                            "10", "--out", out, "--json")
    assert code == 0 and json.loads(stdout)["warnings"] == [] and "outside" not in err
    q2 = np.loadtxt(out, delimiter=",", skiprows=1)[:, 2]
    assert q2.max() <= 2.0 + 1e-12                                     # q2 at rest at the 2.0 rad waypoint


@pytest.mark.parametrize("out", ["/proc/x.csv", "/proc/x.npz"])
def test_unwritable_output_is_one_error_line(capsys, out):
    code, _, err = run(capsys, "traj", "probot-anno", "--waypoints", JOINTS, "--auto-time", "--out", out)
    assert code == 1 and err.count("\n") == 1 and out in err and "Traceback" not in err


def test_a_rate_whose_samples_cannot_fit_is_refused_with_the_count(capsys, tmp_path):
    code, _, err = run(capsys, "traj", "probot-anno", "--waypoints", JOINTS, "--durations", "10", "10", "10",
                       "--rate", "1e12", "--out", tmp_path / "big.csv")
    assert code == 1 and "asks for 3e+13 samples" in err and "lower the rate" in err
    assert not (tmp_path / "big.csv").exists()


def test_waypoints_in_degrees_give_the_radian_trajectory(capsys, tmp_path):
    degrees = tmp_path / "deg.csv"
    np.savetxt(degrees, np.degrees(SEED_WAYPOINTS), delimiter=",")
    code, out_deg, err = run(capsys, "traj", "probot-anno", "--waypoints", degrees, "--deg", "--auto-time",
                             "--json")
    assert code == 0, err
    code, out_rad, _ = run(capsys, "traj", "probot-anno", "--waypoints", JOINTS, "--auto-time", "--json")
    deg, rad = json.loads(out_deg), json.loads(out_rad)
    np.testing.assert_allclose(deg["waypoints"], rad["waypoints"], atol=1e-12)
    np.testing.assert_allclose(deg["duration_s"], rad["duration_s"], rtol=1e-9)
    code, out, _ = run(capsys, "traj", "probot-anno", "--waypoints", degrees, "--deg", "--auto-time")
    assert code == 0 and "deg/s" in out


def test_auto_time_without_acceleration_limits_warns_and_prints_none(capsys, tmp_path):
    arm = Path(__file__).parents[1] / "examples" / "data" / "my_arm.toml"
    waypoints = tmp_path / "w.csv"
    waypoints.write_text("0 0 0\n30 20 -40\n60 -10 20\n")
    code, out, err = run(capsys, "traj", arm, "--waypoints", waypoints, "--deg", "--auto-time")
    assert code == 0, err
    assert "no max_acceleration for base, shoulder, elbow" in err and "--auto-time cannot keep" in err
    assert not re.search(r"\binf\b|\s0\.000\s", out)  # no infinite limit, no ratio to it
    assert re.search(r"base\s.*90\.0000 deg/s.*90\.0000 deg/s.*1\.000.*deg/s².*none.*-", out)


def test_a_waypoint_outside_a_limit_is_reported_in_the_units_typed(capsys, tmp_path):
    path = tmp_path / "w.csv"
    np.savetxt(path, [[0, 0, 0, 0, 0, 0], [0, 0, 0, 0, 170, 0]], delimiter=",")
    code, _, err = run(capsys, "traj", "puma560", "--waypoints", path, "--deg", "--auto-time")
    assert code == 1
    assert err.strip() == "error: waypoint 2: joint q5 = 170 deg is outside its limits [-100, 100] deg"
    np.savetxt(path, [[0, 0, 0, 0, 0, 0], [0, 0, 0, 0, 2, 0]], delimiter=",")
    code, _, err = run(capsys, "traj", "puma560", "--waypoints", path, "--auto-time")
    assert code == 1 and err.strip() == ("error: waypoint 2: joint q5 = 2 rad is outside its limits "
                                         "[-1.74533, 1.74533] rad")


def test_a_bad_limit_option_is_said_as_typed_after_deg(capsys):
    code, _, err = run(capsys, "traj", "probot-anno", "--waypoints", JOINTS, "--auto-time", "--deg",
                       "--max-velocity=-10")
    assert code == 1 and "--max-velocity '-10': expected positive limits (inf for none)" in err
