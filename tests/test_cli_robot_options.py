"""The command line on URDF arms: --base/--tip/--lock on every command taking ROBOT; the UR5 and
Panda of example-robot-data through ik, traj, sim and lab (issue 11's done-when)."""

from __future__ import annotations

import json
import warnings
from importlib.metadata import distribution
from pathlib import Path

import numpy as np
import pytest
from conftest import assert_transform_close

import armkit
from armkit.cli.main import main

ROBOTS = Path(distribution("example-robot-data").locate_file(
    "cmeel.prefix/share/example-robot-data/robots"))
UR5 = str(ROBOTS / "ur_description/urdf/ur5_robot.urdf")
PANDA = str(ROBOTS / "panda_description/urdf/panda.urdf")


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_show_ur5_urdf_reports_three_parallel_axes_like_the_dh_ur5(capsys):
    code, out, _ = run(capsys, "show", UR5, "--tip", "tool0")
    assert code == 0 and "joint axes at q = 0" in out and "shoulder_lift_joint" in out
    kind = out.splitlines()[-1]
    assert kind == run(capsys, "show", "ur5")[1].splitlines()[-1]
    assert kind.startswith("kind: three parallel axes: axes 2, 3, 4 are parallel")
    code, out, _ = run(capsys, "show", UR5, "--tip", "tool0", "--json")
    data = json.loads(out)
    assert data["urdf"]["tip"] == "tool0" and data["structure"]["kind"] == "three-parallel"
    np.testing.assert_allclose(data["axes"][1], [0, 1, 0], atol=1e-12)


def test_several_leaves_are_listed_and_the_error_is_one_line(capsys):
    code, _, err = run(capsys, "show", UR5)
    assert code == 1 and len(err.strip().splitlines()) == 1
    assert "3 leaf links below 'world': ee_link (6 moving joints), tool0 (6 moving joints)" in err
    assert "--tip LINK on the command line" in err


@pytest.mark.parametrize("command", ["fk", "jacobian", "show", "export"])
def test_every_command_takes_base_tip_and_lock(capsys, tmp_path, command):
    def arguments(n):
        if command == "export":
            return ["--urdf", tmp_path / f"arm{n}.urdf"]
        return [] if command == "show" else ["0.1"] * n

    full, locked = ["--base", "world", "--tip", "tool0"], ["--tip", "tool0", "--lock", "6=0.1"]
    for n, options in ((6, full), (5, locked)):
        code, out, err = run(capsys, command, UR5, *arguments(n), *options)
        assert code == 0, err
        if command == "export":
            assert armkit.load(tmp_path / f"arm{n}.urdf").n == n
        if command == "show":
            assert ("locked: wrist_3_joint = 0.1" in out) == (n == 5)


def test_every_command_taking_robot_has_base_tip_and_lock_and_says_what_robot_can_be():
    import typer.main

    from armkit.cli.app import app

    commands = typer.main.get_command(app).commands
    taking = {name: command for name, command in commands.items()
              if any(p.name == "robot" for p in command.params)}
    assert {"fk", "ik", "traj", "sim", "view", "workspace", "lab"} <= set(taking)
    for name, command in taking.items():
        options = {option for p in command.params if p.param_type_name == "option" for option in p.opts}
        assert {"--base", "--tip", "--lock"} <= options, name
        robot = next(p for p in command.params if p.name == "robot")
        assert all(word in robot.help for word in ("URDF", "TOML", "uilt-in name")), (name, robot.help)


def test_view_takes_base_tip_and_lock(capsys):
    """The page of a URDF's chain with a locked joint is served (the browser tests drive a page)."""
    import os
    import signal
    import subprocess
    import sys

    from conftest import WAIT_S, interruptible

    command = [sys.executable, "-m", "armkit.cli.main", "view", UR5, "--tip", "tool0", "--port", "0",
               "--no-browser", "--lock"]
    process = subprocess.Popen([*command, "wrist_3_joint=0.1"], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True, env={**os.environ, "PYTHONUNBUFFERED": "1"},
                               preexec_fn=interruptible)
    try:
        assert process.stdout.readline().startswith("armkit view: ur5 (wrist_3_joint = 0.1 locked) at http://")
        process.send_signal(signal.SIGINT)
        process.communicate(timeout=WAIT_S)
    finally:
        process.kill()
    assert process.returncode == 130
    refused = subprocess.run([*command, "wrist_3_joint=9"], capture_output=True, text=True, timeout=WAIT_S)
    assert refused.returncode == 1
    assert refused.stderr.startswith("error: cannot lock: joint wrist_3_joint = 9 rad")


def test_workspace_takes_base_tip_and_lock(capsys):
    pytest.importorskip("zarr")
    small = ["--resolution", "0.1", "--samples", "2e4", "--orientations", "0",
             "--manipulability-samples", "0", "--json"]
    code, out, err = run(capsys, "workspace", UR5, "--base", "world", "--tip", "tool0", "--lock",
                         "shoulder_pan_joint=0", *small)
    assert code == 0, err
    locked = json.loads(out)
    code, out, err = run(capsys, "workspace", UR5, "--tip", "tool0", *small)
    assert code == 0, err
    assert locked["reachable_volume"] < json.loads(out)["reachable_volume"]   # q1 held: a slice of it


def test_fk_with_a_locked_joint_is_the_full_fk(capsys):
    code, out, _ = run(capsys, "fk", UR5, "0.1", "-1", "1.2", "0.3", "0.4", "--tip", "tool0",
                       "--lock", "elbow_joint=1.2", "--json")
    full = armkit.load(UR5, tip="tool0")
    assert code == 0
    assert_transform_close(np.array(json.loads(out)["matrix"]), full.fk([0.1, -1, 1.2, 1.2, 0.3, 0.4]),
                           1e-6, 1e-6)


@pytest.mark.parametrize(("options", "message"), [
    (["--lock", "elbow_joint"], "--lock 'elbow_joint': expected JOINT=VALUE"),
    (["--lock", "7=0"], "joint number 7; expected 1 to 6"),
    (["--lock", "wrist=0"], "--lock 'wrist=0': no joint 'wrist'; expected a joint number 1 to 6 or a name "
                            "(shoulder_pan_joint, "),
    (["--lock", "1=abc"], "is not a number"),
    (["--lock", "1=9"], "cannot lock: joint shoulder_pan_joint = 9 rad is outside its limits"),
    (["--lock", "-1=0.3"], "--lock '-1=0.3': joint number -1; expected 1 to 6"),
    (["--lock", "0=0.3"], "--lock '0=0.3': joint number 0; expected 1 to 6"),
    (["--lock", "1=0.3", "--lock", "1=0.4"],
     "--lock '1=0.4': joint shoulder_pan_joint is already locked by --lock '1=0.3'; lock each joint once"),
    (["--lock", "shoulder_pan_joint=0.3", "--lock", "1=0.4"],
     "--lock '1=0.4': joint shoulder_pan_joint is already locked by --lock 'shoulder_pan_joint=0.3'"),
    (["--lock", "2=0.3", "--lock", "shoulder_lift_joint=0.3"],
     "--lock 'shoulder_lift_joint=0.3': joint shoulder_lift_joint is already locked by --lock '2=0.3'"),
    (["--lock", "6=1e300"], "joint wrist_3_joint: lock value 1e+300 is not a finite number from -1e+06 to "
                            "1e+06 (rad or m)"),
    (["--lock", "6=nan"], "joint wrist_3_joint: lock value nan is not a finite number"),
    (["--lock", "6=-inf"], "joint wrist_3_joint: lock value -inf is not a finite number"),
    (["--tip", "hand"], "tip link 'hand' is not in the file"),
])
def test_bad_options_get_one_line(capsys, options, message):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # one line, no RuntimeWarning before it
        code, _, err = run(capsys, "show", UR5, *([] if "--tip" in options else ["--tip", "tool0"]), *options)
    assert code == 1 and message in err and len(err.strip().splitlines()) == 1


def test_base_and_tip_on_a_robot_file_are_refused(capsys):
    code, _, err = run(capsys, "show", "ur5", "--tip", "tool0")
    assert code == 1 and "base and tip links choose a chain in a URDF file" in err


def test_ur5_and_panda_urdfs_through_ik_traj_and_sim(capsys, tmp_path):
    for path, tip, all_solutions in ((UR5, "tool0", True), (PANDA, "panda_hand_tcp", False)):
        robot = armkit.load(path, tip=tip)
        q = np.clip(robot.home + 0.3, *robot.limits.T)
        pose = robot.pose(q)
        code, out, err = run(capsys, "ik", path, "--tip", tip, "--pose", *pose,
                             *(["--all"] if all_solutions else []), "--json")
        assert code == 0, err
        solutions = np.array(json.loads(out)["solutions"])
        assert_transform_close(robot.fk(solutions), np.broadcast_to(robot.fk(q), (len(solutions), 4, 4)),
                               1e-9, 1e-9)
        if all_solutions:  # 8, each with its 2 whole-turn copies in every joint spanning +-360 deg
            assert len(solutions) == 8
            code, out, err = run(capsys, "ik", path, "--tip", tip, "--pose", *pose, "--all",
                                 "--turn-copies", "--json")
            copies = 2 ** len(robot.chain.spans_turns)
            assert code == 0 and len(json.loads(out)["solutions"]) == 8 * copies == 256
        waypoints = tmp_path / "poses.csv"
        np.savetxt(waypoints, robot.pose(np.stack([q, q - 0.2, q + 0.1])), delimiter=",")
        out_csv = tmp_path / f"{Path(path).stem}.csv"
        code, out, err = run(capsys, "traj", path, "--tip", tip, "--waypoints", waypoints, "--poses",
                             "--auto-time", "--out", out_csv)
        assert code == 0, err
        code, out, err = run(capsys, "sim", path, "--tip", tip, "--trajectory", out_csv, "--json")
        assert code == 0, err
        assert json.loads(out)["max_tool_position_error_m"] < 0.02
    code, out, err = run(capsys, "ik", PANDA, "--tip", "panda_hand_tcp", "--lock", "panda_joint7=0.5",
                         "--pose", *armkit.load(PANDA, tip="panda_hand_tcp").pose(
                             [0.3, 0.3, 0.3, -1.5, 0.3, 1.5, 0.5]), "--all", "--json")
    assert code == 0, err
    assert "closed form" in json.loads(out)["method"]


@pytest.mark.slow
def test_lab_on_the_ur5_urdf(tmp_path, capsys):
    out = tmp_path / "report"
    code, stdout, err = run(capsys, "lab", "--quick", "--robot", UR5, "--tip", "tool0", "--out", out)
    assert code == 0, err
    assert (out / "index.html").is_file() and "ur5 in MuJoCo" in (out / "index.html").read_text()
    assert "failed" not in stdout
