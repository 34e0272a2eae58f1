"""``armkit move`` and ``armkit rotate``."""

import json

import numpy as np
import pytest

from armkit.cli.main import main

ZEROS = ["--from", *["0"] * 6]


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_move_seed_case_json(capsys):
    code, out, _ = run(capsys, "move", "probot-anno", *ZEROS, "--by", "0.15", "0", "-0.15",
                       "--duration", "3", "--json")
    assert code == 0
    data = json.loads(out)
    assert data["success"]
    assert np.linalg.norm(np.array(data["position_final"]) - [0.3789, 0, 0.304]) < 1e-5
    np.testing.assert_allclose(data["rpy_final"], [np.pi / 2, 0, 0], atol=1e-8)
    assert data["position_error"] < 1e-6 and data["max_joint_speed_ratio"] <= 1.0


def test_move_table_with_negative_start_values_in_degrees(capsys):
    code, out, _ = run(capsys, "move", "probot-anno", "--from", "-10", "-20", "30", "0", "45", "-5",
                       "--deg", "--by", "-0.02", "0.01", "-0.03", "--duration", "1")
    assert code == 0
    assert "straight move by [-0.02, 0.01, -0.03] m" in out
    assert "-10.000000" in out and "-20.000000" in out  # start joints, in degrees
    assert "pose error: position" in out and "[m]" in out


def test_rotate_seed_case_reaches_180_degrees(capsys):
    code, out, _ = run(capsys, "rotate", "probot-anno", *ZEROS, "--axis", "1", "0", "0",
                       "--angle", "-3.141592653589793", "--rate", "0.2", "--json")
    assert code == 0
    data = json.loads(out)
    assert data["success"] and data["max_position_error"] < 1e-4
    assert abs(data["q_final"][3] + np.pi) < 1e-6
    assert abs(data["duration"] - np.pi / 0.2) < 1e-9


def test_rotate_past_the_limit_stops_and_names_the_joint(capsys):
    code, out, err = run(capsys, "rotate", "probot-anno", *ZEROS, "--axis", "-1", "0", "0",
                         "--angle", "200", "--rate", "11.46", "--deg")
    assert code == 1
    assert "joint q4 reached its lower limit" in err
    assert "-180.000000" in out  # q4 stopped on its limit, printed in degrees


def test_move_held_back_by_velocity_limits_exits_1(capsys):
    code, _, err = run(capsys, "move", "probot-anno", "--by", "0.15", "0", "-0.15", "--duration", "0.5")
    assert code == 1 and "velocity limits held it back" in err


def test_rotate_smooth_turn_with_duration(capsys):
    code, out, _ = run(capsys, "rotate", "probot-anno", "--axis", "0", "0", "1", "--angle", "-0.3",
                       "--duration", "2", "--frame", "tool", "--json")
    assert code == 0 and json.loads(out)["max_position_error"] < 1e-4


def test_errors_are_one_line(capsys):
    code, _, err = run(capsys, "move", "probot-anno", "--from", "0", "0", "--by", "0.1", "0", "0")
    assert code == 1 and "6 joints" in err
    code, _, err = run(capsys, "move", "probot-anno", "0", "0", "--by", "0.1", "0", "0")
    assert code == 1 and "after --from" in err
    code, _, err = run(capsys, "move", "probot-anno", "--by", "0.1", "0", "0", "--duration", "-2")
    assert code == 1 and "duration [s]: expected a finite number > 0, got -2.0" in err
    code, _, err = run(capsys, "rotate", "probot-anno", "--axis", "0", "0", "0", "--angle", "1")
    assert code == 1 and "non-zero direction" in err
    code, _, err = run(capsys, "rotate", "probot-anno", "--axis", "1", "0", "0", "--angle", "1",
                       "--rate", "0.1", "--duration", "3")
    assert code == 1 and "give two of" in err


def test_rotate_opposite_signs_reported_in_the_units_typed(capsys):
    code, _, err = run(capsys, "rotate", "probot-anno", "--axis", "1", "0", "0", "--angle", "90",
                       "--rate", "-10", "--deg")
    assert code == 1 and "--angle 90 deg and --rate -10 deg/s have opposite signs" in err
    assert "rad" not in err


@pytest.mark.parametrize("command", [["move", "--by", "0.01", "0", "0"],
                                     ["rotate", "--axis", "1", "0", "0", "--angle", "10"]])
def test_a_start_outside_the_limits_is_said_in_the_units_typed(capsys, command):
    name, *rest = command
    assert main([name, "probot-anno", "--deg", "--from", "0", "300", "0", "0", "0", "0", *rest]) == 1
    err = capsys.readouterr().err
    assert "error: --from: joint q2 = 300 deg is outside its limits [-115, 115] deg" in err
