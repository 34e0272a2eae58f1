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
    code, _, err = run(capsys, "rotate", "probot-anno", "--from", "0", "abc", "0", "0", "0", "0",
                       "--axis", "1", "0", "0", "--angle", "1")
    assert code == 1 and "error: --from: 'abc' is not a number" in err  # it said 'joint values: ...'
    code, _, err = run(capsys, "move", "probot-anno", "--by", "0.1", "0", "0", "--dt", "10")
    assert code == 1 and "error: dt = 10 s with the feedback gain 20 1/s" in err and "at most 0.05 s" in err
    code, _, err = run(capsys, "rotate", "probot-anno", "--axis", "0", "0", "1e-300", "--angle", "1")
    assert code == 1 and "its length 1e-300 is too small to be a direction" in err
    code, _, err = run(capsys, "move", "probot-anno", "--by", "0.1", "0", "0", "--duration", "-2")
    assert code == 1 and "duration [s]: expected a finite number > 0, got -2.0" in err
    code, _, err = run(capsys, "rotate", "probot-anno", "--axis", "0", "0", "0", "--angle", "1")
    assert code == 1 and "non-zero direction" in err
    code, _, err = run(capsys, "rotate", "probot-anno", "--axis", "1", "0", "0", "--angle", "1",
                       "--rate", "0.1", "--duration", "3")
    assert code == 1 and "give two of" in err


def test_a_move_beyond_reach_is_one_error_before_any_step(capsys):
    code, out, err = run(capsys, "move", "probot-anno", "--by", "1e300", "0", "0")
    assert code == 1 and out == ""
    assert ("error: displacement [1e+300, 0, 0] m (base frame): the target is 1e+300 m from the base, "
            "beyond the arm's reach (0.7929 m" in err)


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


# A PUMA 560 move that ends 2e-5 m short at sigma_min 0.038 (under the 0.04 damping threshold): the
# target is reachable, at q2 = 31.27 deg, where the move stopped at 31.253 deg.
PUMA_START = np.array([1.8553, -0.0314, -0.3643, 1.0398, 0.6078, 2.0305])


def _puma_move(degrees: bool) -> list[str]:
    start = np.degrees(PUMA_START) if degrees else PUMA_START
    return ["--from", *(repr(float(v)) for v in start), "--by", "-0.1354", "0.0406", "0.1494",
            "--duration", "0.70225", *(["--deg"] if degrees else [])]


def _named_q(err: str) -> tuple[np.ndarray, str]:
    """The joint values a 'stopped:' message names after 'IK finds q = ', and their unit."""
    values, unit = err.split("IK finds q = [")[1].split(", inside the limits")[0].split("] ")
    return np.array(values.split(", "), dtype=float), unit


def test_a_move_held_back_by_the_damping_names_the_ik_solution_in_the_units_typed(capsys):
    """Before: with --deg the IK solution was printed in radians ('q = [2.028, 0.5458, ...] rad or m')."""
    import armkit

    code, _, err = run(capsys, "move", "puma560", *_puma_move(True))
    assert code == 1 and "so the damping held the arm back near the singularity: move slower" in err
    assert "the tool ended 2.07e-05 m and 0.000575 deg from the target" in err
    q_deg, unit = _named_q(err)
    code, _, err_rad = run(capsys, "move", "puma560", *_puma_move(False))
    q_rad, unit_rad = _named_q(err_rad)
    assert (unit, unit_rad) == ("deg", "rad")
    np.testing.assert_allclose(np.radians(q_deg), q_rad, atol=1e-3)  # both printed to 4 digits
    robot = armkit.load("puma560")  # and the degrees name the solution: FK of them reaches the target
    end = robot.fk(PUMA_START)
    end[:3, 3] += [-0.1354, 0.0406, 0.1494]
    np.testing.assert_allclose(robot.fk(np.radians(q_deg)), end, atol=2e-3)


def test_a_target_reachable_only_outside_the_limits_is_said_in_the_units_typed(capsys, tmp_path):
    """The same move on a PUMA whose q2 stops at 31.26 deg: IK's outside-the-limits message, in degrees."""
    from importlib import resources

    text = (resources.files("armkit") / "robots" / "puma560.toml").read_text()
    path = tmp_path / "puma.toml"
    path.write_text(text.replace("limits = [-45, 225]", "limits = [-45, 31.26]"))
    code, _, err = run(capsys, "move", str(path), *_puma_move(True))
    assert code == 1
    assert ("IK of the target says: the target pose is reachable, but only outside the joint limits (e.g. "
            "joint q2 = 148.735 deg is outside its limits [-45, 31.26] deg" in err)
    assert " rad" not in err
