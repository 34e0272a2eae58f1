"""``armkit plan``: a collision-free motion from the command line, its outputs and its errors."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

import armkit
from armkit.cli.main import main
from armkit.plan import plan_path
from armkit.spatial.transforms import pose_from_transform

pytest.importorskip("ompl")

SCENE = Path(__file__).parent.parent / "examples" / "data" / "ur5_wall.toml"
START = ["0", "-1.2", "1.2", "0", "1.57", "0"]
GOAL = ["1.57", "-1.2", "1.2", "0", "1.57", "0"]


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture(scope="module")
def ur5_wall():
    robot = armkit.load("ur5")
    return robot, armkit.load_scene(SCENE, robot)


def test_plan_json_is_the_python_plan(capsys, ur5_wall):
    code, out, err = run(capsys, "plan", "ur5", "--scene", SCENE, "--from", *START, "--to", *GOAL, "--json")
    assert code == 0, err
    data = json.loads(out)
    trajectory = plan_path(ur5_wall[1], np.array(START, dtype=float), np.array(GOAL, dtype=float))
    np.testing.assert_array_equal(data["waypoints"], trajectory.waypoints)
    assert data["duration_s"] == trajectory.duration
    assert data["q_start"] == [float(v) for v in START] and data["q_goal"] == [float(v) for v in GOAL]
    assert 0.0 < data["min_clearance_m"] < 0.5
    assert all(p <= v * (1 + 1e-9) for p, v in zip(data["peak_velocity"], data["max_velocity"], strict=True))


def test_from_and_to_take_their_values_in_either_order_and_as_comma_lists(capsys):
    code, first, err = run(capsys, "plan", "ur5", "--scene", SCENE, "--from", *START, "--to", *GOAL, "--json")
    assert code == 0, err
    code, second, err = run(capsys, "plan", "ur5", "--to", ",".join(GOAL), "--scene", SCENE,
                            "--from", ",".join(START), "--json")
    assert code == 0, err
    code, third, err = run(capsys, "plan", "ur5", "--to", *GOAL, "--from", *START, "--scene", SCENE, "--json")
    assert code == 0, err
    assert json.loads(first)["waypoints"] == json.loads(second)["waypoints"] == json.loads(third)["waypoints"]


def test_degrees_give_the_same_motion(capsys):
    code, radians, err = run(capsys, "plan", "ur5", "--scene", SCENE, "--from", *START, "--to", *GOAL,
                             "--json")
    assert code == 0, err
    in_degrees = [str(np.degrees(float(v))) for v in (*START, *GOAL)]
    code, degrees, err = run(capsys, "plan", "ur5", "--scene", SCENE, "--from", *in_degrees[:6],
                             "--to", *in_degrees[6:], "--deg", "--json")
    assert code == 0, err
    np.testing.assert_allclose(json.loads(degrees)["waypoints"], json.loads(radians)["waypoints"], atol=1e-9)


@pytest.mark.slow   # a GIF of 40 frames: seconds of matplotlib
def test_table_plot_gif_and_samples(capsys, tmp_path):
    png, gif, csv = tmp_path / "pva.png", tmp_path / "plan.gif", tmp_path / "plan.csv"
    code, out, err = run(capsys, "plan", "ur5", "--scene", SCENE, "--from", *START, "--to", *GOAL,
                         "--plot", png, "--gif", gif, "--out", csv, "--rate", "50")
    assert code == 0, err
    assert "UR5: collision-free path" in out and "smallest clearance" in out
    with Image.open(png) as image:
        assert image.width > 1500
    with Image.open(gif) as image:
        assert image.n_frames > 10
    table = np.loadtxt(csv, delimiter=",", skiprows=1)
    np.testing.assert_allclose(table[0, 1:7], np.array(START, dtype=float), atol=1e-12)
    np.testing.assert_allclose(table[-1, 1:7], np.array(GOAL, dtype=float), atol=1e-12)


def test_a_goal_pose_ends_on_that_pose(capsys, ur5_wall):
    robot = ur5_wall[0]
    pose = pose_from_transform(robot.fk(np.array(GOAL, dtype=float)))
    code, out, err = run(capsys, "plan", "ur5", "--scene", SCENE, "--from", *START,
                         "--to-pose", *(repr(float(v)) for v in pose), "--json")
    assert code == 0, err
    end = np.array(json.loads(out)["q_goal"])
    np.testing.assert_allclose(robot.fk(end), robot.fk(np.array(GOAL, dtype=float)), atol=1e-9)


@pytest.mark.parametrize(("argv", "message"), [
    (["--from", *START, "--to", *GOAL], "--scene FILE: armkit plan needs the scene"),
    (["--scene", SCENE, "--from", *START], "give the goal as one of --to Q"),
    (["--scene", SCENE, "--from", *START, "--to", *GOAL, "--to-pose", "0", "0", "0", "0", "0", "0"],
     "give the goal as one of --to Q"),
    (["--scene", SCENE, "--from", *START, "--to", *GOAL[:5]], "--to: expected 6 joint values, got 5"),
    (["--scene", SCENE, "--from", *START, "--to", *GOAL, "7"], "unexpected values 7"),
    (["--scene", SCENE, "--from", "0.785", *START[1:], "--to", *GOAL],
     r"--from 0.7850 rad -1.2000 rad .* the arm collides there \(link3-wall, link4-wall\)"),
    (["--scene", SCENE, "--from", "0", "-68.75", "68.75", "0", "90", "0",
      "--to", "45", "-68.75", "68.75", "0", "90", "0", "--deg"],
     r"--to 45.0000 deg -68.7500 deg .* the arm collides there \(link3-wall, link4-wall\)"),
    (["--scene", SCENE, "--from", *START, "--to", *GOAL, "--time-budget", "1e-9"],
     "no collision-free path found within time_budget=1e-09 s"),
    (["--scene", SCENE, "--from", "0", "-68.75", "68.75", "0", "90", "0",
      "--to", "400", "-68.75", "68.75", "0", "90", "0", "--deg"],
     r"--to: joint q1 = 400 deg is outside its limits \[-360, 360\] deg"),
    (["--scene", SCENE, "--to", *GOAL], r"the start \(the home configuration: no --from given\) .* collides"),
])
def test_errors_are_one_line(capsys, argv, message):
    code, out, err = run(capsys, "plan", "ur5", *argv)
    assert code == 1 and out == ""
    assert re.search(message, err), err
    assert err.count("\n") == 1 and "Traceback" not in err
