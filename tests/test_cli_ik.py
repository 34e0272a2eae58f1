"""``armkit ik``: the seed case, JSON, --matrix, --near with negative values, errors."""

from __future__ import annotations

import json
import re

import numpy as np

import armkit
from armkit.cli.main import main
from armkit.ik import ik_solutions

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


def test_without_near_the_reference_is_zeros_and_a_bare_near_is_one_clear_error(capsys):
    home = ["ik", "probot-anno", "--pose", "0.2289", "0", "0.454", "1.5707963267948966", "0", "0"]
    assert main([*home, "--json"]) == 0
    solution = json.loads(capsys.readouterr().out)["solutions"][0]
    np.testing.assert_allclose(solution, np.zeros(6), atol=1e-9)
    code, out, err = run(capsys, *home, "--near", "--json")
    assert code == 1 and err.count("\n") == 1 and "--near: expected joint values after it" in err


def test_angles_beyond_two_pi_without_deg_are_refused(capsys):
    assert main(["ik", "probot-anno", "--pose", "0.2", "0.2", "0.2007", "90", "-90", "0"]) == 1
    assert "add --deg if they are degrees" in capsys.readouterr().err


def test_family_flags_agree_with_ik_solutions_at_a_wrist_singularity(capsys):
    """UR5 at q5 = 0: the CLI once asked ik_solutions with its first row as reference, which moved
    the other family's member, so 1 row was flagged where ik_solutions flags 2."""
    robot = armkit.load("ur5")
    T = robot.fk([0.3, -1.2, 1.0, -0.5, 0.0, 0.7])
    found = ik_solutions(robot.chain, T)
    code, out, _ = run(capsys, "ik", "ur5", "--matrix", *map(str, T.ravel()), "--all", "--outside", "--json")
    data = json.loads(out)
    assert code == 0 and ik_solutions(robot, T, turn_copies=False).family.sum() == 2
    listed = {tuple(np.round(q, 9)): bool(f) for q, f in zip(found.q, found.family, strict=True)}
    shown = {tuple(np.round(q, 9)): f for q, f in zip(data["solutions"], data["family"], strict=True)}
    assert shown == listed


def test_outside_keeps_the_numbers_of_the_in_limit_solutions(capsys):
    code, out, _ = run(capsys, "ik", "probot-anno", *SEED_POSE, "--all", "--json")
    inside = json.loads(out)
    code_all, out_all, _ = run(capsys, "ik", "probot-anno", *SEED_POSE, "--all", "--outside", "--json")
    everything = json.loads(out_all)
    assert code == code_all == 0 and len(everything["solutions"]) == 8
    assert inside["numbers"] == [1, 2, 3, 4] and everything["numbers"] == list(range(1, 9))
    np.testing.assert_allclose(everything["solutions"][:4], inside["solutions"], atol=1e-12)
    assert not any(everything["within_limits"][4:])
    code, out, _ = run(capsys, "ik", "probot-anno", *SEED_POSE, "--near", *map(str, inside["solutions"][2]),
                       "--json")
    assert json.loads(out)["numbers"] == [1]  # numbered from the --near given


def test_near_takes_its_values_directly_or_as_a_comma_list(capsys):
    q = [-1.0, -0.9, -0.3, 0.9, 2.9, -0.2]
    spaced = run(capsys, "ik", "probot-anno", *SEED_POSE, "--near", *map(str, q), "--json")
    commas = run(capsys, "ik", "probot-anno", *SEED_POSE, "--near", ",".join(map(str, q)), "--json")
    first = run(capsys, "ik", "probot-anno", "--near", *map(str, q), *SEED_POSE, "--json")
    assert spaced[0] == commas[0] == first[0] == 0
    assert json.loads(spaced[1])["solutions"] == json.loads(commas[1])["solutions"] \
        == json.loads(first[1])["solutions"]


def test_ik_table_has_units_and_no_negative_zero(capsys):
    code, out, _ = run(capsys, "ik", "stanford", "--pose", "0.3", "0.2", "0.4", "0", "0", "0", "--all",
                       "--outside")
    assert code == 0 and "q1 [rad]" in out and "q3 [m]" in out and "pos.err [m]" in out
    assert not re.search(r"-0\.0+(?![0-9])", out)
    code, _, err = run(capsys, "ik", "ur5", *SEED_POSE[:4], "1", "0", "0", "--euler", "quat")
    assert code == 1 and "output format" in err


def test_a_pose_reachable_only_outside_the_limits_is_reported_in_degrees_after_deg(capsys, tmp_path):
    from armkit.robot_file import robot_to_toml

    puma = armkit.load("puma560")
    narrow = armkit.Robot.from_dh(puma.dh.rows, puma.dh.convention, limits=[(-0.3, 0.3)] * 6, name="narrow")
    path = tmp_path / "narrow.toml"
    path.write_text(robot_to_toml(narrow))
    q = np.full(6, 0.5)                                  # outside every limit: no solution inside
    pose = [str(v) for v in narrow.pose(q, degrees=True)]
    code, _, err = run(capsys, "ik", str(path), "--pose", *pose, "--deg")
    assert code == 1 and len(err.strip().splitlines()) == 1
    assert "only outside the joint limits" in err and "[-17.1887, 17.1887] deg" in err and " rad" not in err
    code, _, err = run(capsys, "ik", str(path), "--pose", *map(str, narrow.pose(q)))
    assert code == 1 and "[-0.3, 0.3] rad" in err


PANDA_POSE = ["--pose", "0.4", "0.1", "0.5", "180", "0", "0", "--deg"]


def test_free_joint_lists_every_solution_of_a_7r_arm_with_that_joint_held(capsys):
    code, out, _ = run(capsys, "ik", "panda", *PANDA_POSE, "--all", "--outside", "--free-joint", "3",
                       "--free-value", "20", "--json")
    assert code == 0
    data = json.loads(out)
    found = np.array(data["solutions"])
    panda = armkit.load("panda")
    expected = panda.ik(panda.fk(found[0]), all_solutions=True, within_limits=False, free_joint=2,
                        free_value=np.radians(20))
    assert found.shape == expected.shape and np.allclose(found[:, 2], np.radians(20))
    assert max(data["position_error"]) < 1e-12 and "held at 20" in data["method"]


def test_self_motion_writes_its_plot_and_refuses_to_overwrite_it(capsys, tmp_path):
    path = tmp_path / "self_motion.png"
    code, out, _ = run(capsys, "ik", "panda", *PANDA_POSE, "--free-joint", "q3", "--self-motion", str(path))
    assert code == 0 and path.stat().st_size > 10_000
    assert re.search(r"Self-motion: \d+ branches along q3, written to", out)
    code, _, err = run(capsys, "ik", "panda", *PANDA_POSE, "--free-joint", "q3", "--self-motion", str(path))
    assert code == 1 and "already exists" in err


def test_free_joint_errors_are_one_line(capsys):
    code, _, err = run(capsys, "ik", "panda", *PANDA_POSE, "--self-motion", "x.png")
    assert code == 1 and "--self-motion: name the joint it sweeps with --free-joint" in err
    code, _, err = run(capsys, "ik", "panda", *PANDA_POSE, "--free-joint", "9")
    assert code == 1 and "--free-joint '9': joint number 9; expected 1 to 7" in err
    code, _, err = run(capsys, "ik", "panda", *PANDA_POSE, "--free-joint", "\u00b3")  # a digit to isdigit()
    assert code == 1 and "--free-joint '\u00b3': no joint '\u00b3'; expected a joint number 1 to 7" in err
