"""``armkit ik``: the seed case, JSON, --matrix, --near with negative values, errors."""

from __future__ import annotations

import json

import numpy as np

import armkit
from armkit.cli.main import main

SEED_POSE = ["--pose", "0.2", "0.2", "0.2007", "1.5707963", "-1.5707963", "0"]
REPORT_SOLUTIONS = np.array([[0.943488, -0.924743, -0.347274, -2.17673, 0.173647, 2.89722],
                             [0.943488, -0.924743, -0.347274, 0.964865, 2.96795, -0.244375],
                             [-2.1981, 0.924743, 3.48887, 0.964865, 0.173647, 2.89722],
                             [-2.1981, 0.924743, 3.48887, -2.17673, 2.96795, -0.244375]])


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_seed_case_lists_exactly_the_four_solutions_of_report_000(capsys):
    code, out, _ = run(capsys, "ik", "probot-anno", *SEED_POSE, "--all", "--json")
    assert code == 0
    data = json.loads(out)
    found = np.array(data["solutions"])
    assert found.shape == (4, 6)
    # 1.5707963 (as typed) is pi/2 to 3e-8 rad, so the report's 6 digits still hold
    for q in REPORT_SOLUTIONS:
        assert np.abs(found - q).max(axis=1).min() < 5e-6
    assert all(data["within_limits"]) and max(data["position_error"]) < 1e-12


def test_seed_case_table(capsys):
    code, out, _ = run(capsys, "ik", "probot-anno", *SEED_POSE, "--all")
    assert code == 0
    assert "PROBOT Anno: 4 IK solutions, closed form" in out
    assert "-2.1981" in out and "0.9435" in out and "3.4889" in out
    assert out.count(" in ") >= 4 and "OUT" not in out


def test_outside_lists_all_eight_with_a_limits_column(capsys):
    code, out, _ = run(capsys, "ik", "probot-anno", *SEED_POSE, "--all", "--outside", "--json")
    data = json.loads(out)
    assert len(data["solutions"]) == 8 and sum(data["within_limits"]) == 4
    code, out, _ = run(capsys, "ik", "probot-anno", *SEED_POSE, "--all", "--outside")
    assert out.count("OUT") == 4


def test_degrees_and_other_conventions(capsys):
    robot = armkit.load("zju-i")
    q = np.array([0.3, -0.4, 0.5, 0.2, 0.6, -0.7])
    T = robot.fk(q)
    angles = np.degrees(robot.pose(q, "zyz-euler")[3:])
    code, out, _ = run(capsys, "ik", "zju-i", "--pose", *map(str, T[:3, 3]), *map(str, angles),
                       "--euler", "zyz-euler", "--deg", "--near", *map(str, np.degrees(q)), "--json")
    assert code == 0
    np.testing.assert_allclose(json.loads(out)["solutions"][0], q, atol=1e-9)


def test_matrix_and_near_with_negative_values(capsys):
    robot = armkit.load("ur5")
    q = np.array([-0.5, -1.2, 1.1, -0.4, 0.8, -2.0])
    T = robot.fk(q)
    code, out, _ = run(capsys, "ik", "ur5", "--matrix", *map(str, T.ravel()), "--near",
                       *map(str, q + 0.01), "--json")
    assert code == 0
    np.testing.assert_allclose(json.loads(out)["solutions"][0], q, atol=1e-9)


def test_numeric_robot(capsys):
    panda = armkit.load("panda")
    q = np.array([0.2, -0.3, 0.1, -2.0, 0.1, 1.8, 0.6])
    T = panda.fk(q)
    code, out, _ = run(capsys, "ik", "panda", "--matrix", *map(str, T.ravel()), "--near",
                       *map(str, q + 0.05), "--json")
    data = json.loads(out)
    assert code == 0 and data["method"].startswith("numeric")
    np.testing.assert_allclose(panda.fk(data["solutions"][0]), T, atol=1e-9)


def test_errors_are_one_line(capsys):
    code, _, err = run(capsys, "ik", "panda", "--pose", "0.4", "0", "0.5", "3.14159", "0", "0", "--all")
    assert code == 1 and "numeric IK returns one solution per seed" in err
    code, _, err = run(capsys, "ik", "probot-anno", "--pose", "2", "0", "0.3", "0", "0", "0")
    assert code == 1 and "out of reach: the closest pose found is" in err
    code, _, err = run(capsys, "ik", "ur5", "--pose", "0.3", "0", "0.3", "0", "0", "0", "0.1", "0.2")
    assert code == 1 and "joint values are given after --near" in err
    code, _, err = run(capsys, "ik", "ur5", *SEED_POSE, "--matrix", *["0"] * 16)
    assert code == 1 and "give the target as one of --pose" in err
    code, _, err = run(capsys, "ik", "ur5", "--matrix", *["1"] * 16)
    assert code == 1 and "--matrix" in err
    code, _, err = run(capsys, "ik", "ur5", *SEED_POSE, "--near", "0", "0")
    assert code == 1 and "UR5 has 6 joints" in err
    code, _, err = run(capsys, "ik", "ur5", "--pose", "0.2", "0.2", "0.2", "0", "inf", "0")
    assert code == 1 and "expected six finite numbers" in err


def test_position_only_target(capsys):
    code = main(["ik", "probot-anno", "--position", "0.3", "0.1", "0.2", "--json"])
    data = json.loads(capsys.readouterr().out)
    assert code == 0 and len(data["solutions"]) == 1
    reached = armkit.load("probot-anno").fk(data["solutions"][0])[:3, 3]
    np.testing.assert_allclose(reached, [0.3, 0.1, 0.2], atol=1e-9)


def test_near_without_values_means_zeros(capsys):
    assert main(["ik", "probot-anno", "--pose", "0.2289", "0", "0.454", "1.5707963267948966", "0", "0",
                 "--near", "--json"]) == 0
    solution = json.loads(capsys.readouterr().out)["solutions"][0]
    np.testing.assert_allclose(solution, np.zeros(6), atol=1e-9)


def test_angles_beyond_two_pi_without_deg_are_refused(capsys):
    assert main(["ik", "probot-anno", "--pose", "0.2", "0.2", "0.2007", "90", "-90", "0"]) == 1
    assert "add --deg if they are degrees" in capsys.readouterr().err
