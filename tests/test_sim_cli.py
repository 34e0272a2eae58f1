"""``armkit export`` and ``armkit sim`` on the command line."""

from __future__ import annotations

import json
import re

import mujoco
import numpy as np
from conftest import WAIT_S
from PIL import Image

from armkit.cli.main import main


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_export_writes_both_and_refuses_to_overwrite(capsys, tmp_path):
    urdf, mjcf = tmp_path / "anno.urdf", tmp_path / "anno.xml"
    code, out, _ = run(capsys, "export", "probot-anno", "--urdf", urdf, "--mjcf", mjcf)
    assert code == 0 and "wrote" in out
    assert mujoco.MjModel.from_xml_path(str(mjcf)).njnt == 6
    assert mujoco.MjModel.from_xml_path(str(urdf)).njnt == 6
    mjcf.write_text("mine")
    code, _, err = run(capsys, "export", "probot-anno", "--urdf", urdf, "--mjcf", mjcf)
    assert code == 1 and "already exists; pass --force" in err
    assert mjcf.read_text() == "mine"
    code, _, _ = run(capsys, "export", "probot-anno", "--mjcf", mjcf, "--force", "--no-gravity")
    assert code == 0 and mujoco.MjModel.from_xml_path(str(mjcf)).opt.gravity[2] == 0


def test_export_needs_an_output(capsys):
    code, _, err = run(capsys, "export", "ur5")
    assert code == 1 and "--urdf FILE and/or --mjcf FILE" in err


def test_export_of_a_zero_length_arm_is_a_clear_error(capsys, tmp_path):
    robot = tmp_path / "point.toml"
    robot.write_text('convention = "standard"\nlength_unit = "m"\nangle_unit = "rad"\n'
                     '[[joints]]\nalpha = 0\na = 0\nd = 0\ntheta = 0\n')
    code, _, err = run(capsys, "export", robot, "--mjcf", tmp_path / "point.xml")
    assert code == 1 and "cannot be simulated" in err and "Traceback" not in err
    assert not (tmp_path / "point.xml").exists()


def test_sim_checks_the_report_configuration(capsys, tmp_path):
    png = tmp_path / "anno.png"
    code, out, _ = run(capsys, "sim", "probot-anno", "0.927", "-0.687", "-0.396", "0", "1.083", "0.927",
                       "--json", "--png", png)
    data = json.loads(out)
    assert code == 0
    np.testing.assert_allclose(data["mj_kinematics (qpos set)"]["computed"][0][:3],
                               [0.150047, 0.199940, 0.200756], atol=1e-6)
    assert max(data["mj_kinematics (qpos set)"]["position_error_m"]) < 1e-12
    assert max(data["servos from home in 1 s, then 0.5 s hold"]["position_error_m"]) < 1e-6
    assert Image.open(png).size[0] > 100


def test_sim_drives_a_trajectory_csv(capsys, tmp_path):
    csv = tmp_path / "traj.csv"
    t = np.linspace(0, 1, 11)
    q = np.outer(t, [0.5, 0.4, 0.01, 0.2])
    np.savetxt(csv, np.column_stack([t, q]), delimiter=",", header="t,q1,q2,q3,q4", comments="")
    gif = tmp_path / "scara.gif"
    code, out, _ = run(capsys, "sim", "grb400-scara", "--trajectory", csv, "--json", "--gif", gif)
    data = json.loads(out)
    assert code == 0 and data["steps"] == 1001 and data["gravity"] is True
    assert data["max_tool_position_error_m"] < 1e-3
    assert Image.open(gif).n_frames > 5


def test_sim_trajectory_with_too_many_columns(capsys, tmp_path):
    csv = tmp_path / "traj.csv"
    np.savetxt(csv, np.zeros((3, 7)), delimiter=",", header="t,q1,q2,q3,q4,q5,q6", comments="")
    code, _, err = run(capsys, "sim", "grb400-scara", "--trajectory", csv)
    assert code == 1 and "has 6 joint columns" in err and "4 joints" in err


def test_sim_random_table(capsys):
    code, out, _ = run(capsys, "sim", "zju-i", "--random", "2", "--euler", "xyz-euler", "--deg",
                       "--no-gravity", "--json")
    data = json.loads(out)
    assert code == 0 and np.shape(data["q"]) == (2, 6) and data["convention"] == "xyz-euler"
    assert max(data["servos from home in 1 s, then 0.5 s hold"]["orientation_error_rad"]) < 1e-6


def test_without_mujoco_the_cli_still_works_and_names_the_extra(tmp_path):
    import subprocess
    import sys

    script = (
        "import sys\n"
        "class Block:\n"
        "    def find_spec(self, name, path, target=None):\n"
        "        if name == 'mujoco':\n"
        "            raise ImportError('no mujoco here')\n"
        "sys.meta_path.insert(0, Block())\n"
        "from armkit.cli.main import main\n"
        "codes = [main(['fk', 'ur5', '0', '0', '0', '0', '0', '0']), main(['lab', '--quick']),\n"
        "         main(['export', 'ur5', '--urdf', 'ur5.urdf'])]\n"
        "print('codes', codes)\n")
    result = subprocess.run([sys.executable, "-c", script], cwd=tmp_path, capture_output=True, text=True,
                            timeout=WAIT_S)
    assert "codes [0, 1, 0]" in result.stdout
    assert "needs MuJoCo: pip install 'armkit[sim]'" in result.stderr
    assert (tmp_path / "ur5.urdf").exists() and not (tmp_path / "armkit-report").exists()


def test_sim_drives_what_armkit_traj_writes(capsys, tmp_path):
    waypoints = tmp_path / "waypoints.csv"
    np.savetxt(waypoints, [[0, 0, 0, 0, 0, 0], [0.4, -0.3, 0.2, 0.1, 0.5, -0.2]], delimiter=",")
    for suffix in ("csv", "npz"):
        samples = tmp_path / f"traj.{suffix}"
        code, _, _ = run(capsys, "traj", "probot-anno", "--waypoints", waypoints, "--durations", "2",
                         "--out", samples)
        assert code == 0
        code, out, _ = run(capsys, "sim", "probot-anno", "--trajectory", samples, "--json")
        data = json.loads(out)
        assert code == 0 and data["duration_s"] >= 2.0  # stretched if the limits need it
        assert data["steps"] == round(data["duration_s"] * 1000) + 1
        assert data["max_tool_position_error_m"] < 1e-4


def test_sim_trajectory_file_errors(capsys, tmp_path):
    code, _, err = run(capsys, "sim", "ur5", "--trajectory", tmp_path / "missing.csv")
    assert code == 1 and "does not exist" in err
    broken = tmp_path / "broken.npz"
    broken.write_text("not an archive")
    code, _, err = run(capsys, "sim", "ur5", "--trajectory", broken)
    assert code == 1 and "not a readable NPZ archive" in err


def test_sim_random_count_and_export_suffix_are_checked(capsys, tmp_path):
    assert main(["sim", "ur5", "--random", "-3"]) == 1
    assert "--random -3: expected at least 1 configuration" in capsys.readouterr().err
    assert main(["export", "ur5", "--urdf", str(tmp_path / "arm.txt")]) == 1
    assert "expected a name ending in .urdf" in capsys.readouterr().err
    assert not (tmp_path / "arm.txt").exists()


def test_sim_warns_about_values_outside_the_limits(capsys, tmp_path):
    code, _, err = run(capsys, "sim", "probot-anno", "0", "0", "0", "0", "4.5", "0", "--json")
    assert code == 0 and "is outside its limits" in err
    csv = tmp_path / "traj.csv"
    t = np.linspace(0, 1, 11)
    q = np.outer(t, [0.5, 0.4, 0.01, 0.2])
    q[5:, 1] = 3.0  # joint 2 beyond its limits from t = 0.5 s
    np.savetxt(csv, np.column_stack([t, q]), delimiter=",", header="t,q1,q2,q3,q4", comments="")
    code, _, err = run(capsys, "sim", "grb400-scara", "--trajectory", csv, "--json")
    assert code == 0 and "the trajectory leaves the joint limits (6 of 11 samples, first at t = 0.5 s" in err


def test_sim_trajectory_summary_has_a_unit_on_every_number(capsys, tmp_path):
    csv = tmp_path / "t.csv"
    assert main(["traj", "grb400-scara", "--waypoints", str(_scara_waypoints(tmp_path)), "--durations", "1",
                 "--rate", "100", "--out", str(csv)]) == 0
    capsys.readouterr()
    code, out, err = run(capsys, "sim", "grb400-scara", "--trajectory", str(csv))
    assert code == 0, err
    assert re.search(r"duration: 1 s \(\d+ steps\)", out)
    assert re.search(r"q1 [0-9.e+-]+ rad, q2 [0-9.e+-]+ rad, q3 [0-9.e+-]+ m, q4 [0-9.e+-]+ rad", out)
    assert re.search(r"position [0-9.e+-]+ m, rotation [0-9.e+-]+ rad", out)


def _scara_waypoints(folder):
    path = folder / "w.csv"
    path.write_text("0 0 0 0\n0.5 0.4 0.03 0.3\n")
    return path


def test_sim_with_a_negative_seed_is_a_usage_error(capsys):
    code, _, err = run(capsys, "sim", "probot-anno", "--seed", "-1")
    assert code == 2 and "Traceback" not in err and "--seed" in err
