"""``armkit dynamics`` and the dynamics lines of ``armkit show``."""

import json

import numpy as np

import armkit
from armkit.cli.main import main


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_dynamics_json_is_robot_inverse_dynamics_in_si_units(capsys):
    code, out, _ = run(capsys, "dynamics", "puma560", "0", "30", "-45", "0", "20", "0", "--deg",
                       "--qd", "10,-20,0,0,0,5", "--qdd=-30,0,0,0,0,0", "--json")
    assert code == 0
    data = json.loads(out)
    robot = armkit.load("puma560")
    q = np.radians([0, 30, -45, 0, 20, 0])
    qd, qdd = np.radians([10, -20, 0, 0, 0, 5]), np.radians([-30, 0, 0, 0, 0, 0])
    np.testing.assert_allclose(data["tau"], robot.inverse_dynamics(q, qd, qdd), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(data["gravity_torques"], robot.gravity_torques(q), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(data["mass_matrix"], robot.mass_matrix(q), rtol=1e-12, atol=1e-12)
    assert data["max_torque"] == [None] * 6 and data["units"]["tau"] == "N m (revolute), N (prismatic)"


def test_dynamics_table_has_units_and_the_share_of_each_limit(capsys, tmp_path):
    path = tmp_path / "arm.toml"
    path.write_text('convention = "standard"\nlength_unit = "m"\nangle_unit = "deg"\n'
                    '[[joints]]\na = 1\nalpha = 90\nd = 0\ntheta = 0\nmass = 2\ncom = [-0.5, 0, 0]\n'
                    'max_torque = 5\n[[joints]]\ntype = "prismatic"\na = 0\nalpha = 0\nd = 0\ntheta = 0\n'
                    'mass = 1\nmax_torque = 20\n[base]\nrpy = [60, 0, 0]\n')  # both joints feel gravity
    code, out, _ = run(capsys, "dynamics", str(path), "0", "0.1")
    assert code == 0
    assert "N m" in out and " N " in out and "m/s^2" in out
    ratio = np.abs(armkit.load(path).gravity_torques([0.0, 0.1])) / [5.0, 20.0]
    assert ratio[0] > 1 > ratio[1] > 0.01
    assert "above the torque limit: q1\n" in out
    assert f"{100 * ratio[0]:.1f} %" in out and f"{100 * ratio[1]:.1f} %" in out


def test_dynamics_of_an_arm_without_masses_says_how_to_estimate_them(capsys):
    code, _, err = run(capsys, "dynamics", "ur5", "0", "0", "0", "0", "0", "0")
    assert code == 1 and "--estimate-inertia DENSITY" in err
    code, out, _ = run(capsys, "dynamics", "ur5", *["0"] * 6, "--estimate-inertia", "1000", "--payload", "2",
                       "--json")
    arm = armkit.load("ur5").with_estimated_inertia(1000.0).with_payload(2.0)
    expected = arm.gravity_torques(np.zeros(6))
    assert code == 0 and np.allclose(json.loads(out)["tau"], expected, rtol=1e-12, atol=1e-12)


def test_dynamics_bad_values_are_one_line_errors(capsys):
    for argv, message in ((["--qd", "1,2"], "--qd: expected 6 joint values, got 2"),
                          (["--qdd", "a,b,c,d,e,f"], "--qdd: 'a' is not a number"),
                          (["--payload=-1"], "--payload: expected a mass >= 0 kg, got -1.0"),
                          (["--estimate-inertia", "0"],
                           "density [kg/m^3]: expected a density from 1 to 100000, got 0.0")):
        code, _, err = run(capsys, "dynamics", "puma560", *["0"] * 6, *argv)
        assert code == 1 and message in err and err.count("\n") == 1, err


def test_show_prints_masses_and_torque_limits(capsys):
    code, out, _ = run(capsys, "show", "puma560")
    assert code == 0 and "link masses: 0, 17.4, 4.8, 0.82, 0.34, 0.09 kg (moving: 23.45 kg)" in out
    code, out, _ = run(capsys, "show", "ur5", "--json")
    data = json.loads(out)
    assert data["mass"] == [None] * 6 and data["max_torque"] == [None] * 6


def test_torques_print_in_significant_digits_not_fixed_decimals(capsys, tmp_path):
    path = tmp_path / "light.toml"
    path.write_text('convention = "standard"\nlength_unit = "m"\nangle_unit = "deg"\n'
                    '[[joints]]\na = 0.5\nalpha = 90\nd = 0\ntheta = 0\nmass = 1e-5\ncom = [-0.25, 0, 0]\n'
                    '[base]\nrpy = [90, 0, 0]\n')   # a 10 mg link: tens of micro-newton-metres
    tau = armkit.load(path).gravity_torques([0.0])[0]
    assert 1e-5 < abs(tau) < 1e-4
    code, out, _ = run(capsys, "dynamics", str(path), "0")
    assert code == 0 and f"{tau:.4g} N m" in out and "0.0000 N m" not in out
