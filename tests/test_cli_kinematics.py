import json

import numpy as np
import pytest

import armkit
from armkit.cli.main import main


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_fk_seed_case_prints_the_report_pose(capsys):
    code, out, _ = run(capsys, "fk", "probot-anno", "0.927", "-0.687", "-0.396", "0", "1.083", "0.927",
                       "--euler", "xyz-fixed")
    assert code == 0
    assert "[0.150047, 0.199940, 0.200756]" in out
    assert "1.570796" in out and "Rz(a3) Ry(a2) Rx(a1)" in out


def test_fk_json(capsys):
    code, out, _ = run(capsys, "fk", "zju-i", *["15"] * 6, "--deg", "--euler", "xyz-euler", "--json")
    data = json.loads(out)
    assert code == 0
    assert np.array(data["matrix"]).shape == (4, 4)
    np.testing.assert_allclose(data["position"], [0.225673, 0.10719, 0.55197], atol=1e-6)
    np.testing.assert_allclose(np.degrees(data["angles"]), [-148.0, 36.35, -107.0], atol=5e-3)  # SI: rad
    assert data["convention"] == "xyz-euler" and data["units"]["angles"] == "rad"
    assert data["units"]["q"] == "rad (revolute), m (prismatic)"
    assert data["q"][0] == pytest.approx(np.radians(15))


def test_fk_deg_leaves_prismatic_joints_in_metres(capsys):
    code, out, _ = run(capsys, "fk", "grb400-scara", "45", "45", "0.01", "0", "--deg", "--json")
    np.testing.assert_allclose(json.loads(out)["position"], [0.1414214, 0.3414214, 0.01], atol=1e-7)


def test_jacobian_json_and_table(capsys):
    code, out, _ = run(capsys, "jacobian", "ur5", "0", "-1", "1", "0", "1", "0", "--json")
    data = json.loads(out)
    assert code == 0 and np.array(data["jacobian"]).shape == (6, 6)
    assert data["manipulability"] > 0
    code, out, _ = run(capsys, "jacobian", "puma560", "0", "0.5", "-0.5", "0", "0", "0", "--frame", "tool")
    assert code == 0 and "tool frame" in out and "condition number" in out
    assert "singular configuration" in out  # q5 = 0: wrist axes 4 and 6 align


def test_robots_and_show(capsys):
    code, out, _ = run(capsys, "robots")
    assert code == 0 and "probot-anno" in out and "panda" in out
    code, out, _ = run(capsys, "show", "probot-anno")
    assert code == 0 and "modified DH" in out and "228.9" in out


@pytest.mark.parametrize(("argv", "message"), [
    (["fk", "ur5", "1", "2"], "expected 6 joint values, got 2 (UR5 has 6 joints)"),
    (["fk", "nosuchbot", "1"], "unknown robot 'nosuchbot'"),
    (["fk", "probot-anno", "0", "0", "0", "0", "0", "5", "--strict"],
     "joint q6 = 5 rad is outside its limits"),
    (["fk", "ur5", "0", "0", "0", "0", "0", "0", "--euler", "abc"], "unknown angle convention 'abc'"),
    (["jacobian", "ur5", "0", "0", "0", "0", "0", "0", "--frame", "world"], "frame 'world'"),
])
def test_errors_are_one_line_and_exit_1(capsys, argv, message):
    code, out, err = run(capsys, *argv)
    assert code == 1
    assert message in err and "Traceback" not in err
    assert err.strip().startswith("error:") and out == ""


def test_out_of_limits_warns_without_strict(capsys):
    code, out, err = run(capsys, "fk", "probot-anno", "0", "0", "0", "0", "0", "5")
    assert code == 0 and "warning: joint q6 = 5 rad is outside its limits" in err


def test_usage_error_exit_code(capsys):
    code, _, err = run(capsys, "fk")
    assert code == 2 and "Missing argument" in err


def test_degrees_everywhere_with_deg(capsys):
    code, _, err = run(capsys, "fk", "probot-anno", "0", "0", "0", "0", "0", "200", "--deg", "--strict")
    assert code == 1 and "joint q6 = 200 deg is outside its limits [-180, 180] deg" in err
    code, out, _ = run(capsys, "fk", "probot-anno", "0", "0", "0", "0", "0", "90", "--deg", "--json")
    data = json.loads(out)
    assert data["q"][5] == pytest.approx(np.pi / 2)          # --json is SI whatever --deg says


def test_non_numeric_joint_value_is_named(capsys):
    code, _, err = run(capsys, "fk", "probot-anno", "1", "2", "3", "abc", "5", "6")
    assert code == 1 and "joint values: 'abc' is not a number" in err


def test_show_writes_offsets_as_a_dh_table_does(capsys):
    code, out, _ = run(capsys, "show", "probot-anno")
    assert "q - 90" in out and "q + 90" in out and "-0 " not in out


def test_fk_prints_no_negative_zero_and_aligned_decimals(capsys):
    code, out, _ = run(capsys, "fk", "probot-anno", "0", "0", "0", "0", "0", "0")
    assert code == 0 and "-0.0" not in out
    assert "position [m]: [0.228900, 0.000000, 0.454000]" in out


def test_fk_quaternion_output_is_wxyz(capsys):
    from armkit import load
    from armkit.spatial.rotations import matrix_from_quaternion_wxyz

    q = ["0.3", "-0.5", "0.2", "0.1", "0.9", "-0.4"]
    code, out, _ = run(capsys, "fk", "puma560", *q, "--euler", "quat", "--json")
    data = json.loads(out)
    assert code == 0 and len(data["quaternion_wxyz"]) == 4 and data["quaternion_wxyz"][0] >= 0
    R = load("puma560").fk([float(v) for v in q])[:3, :3]
    np.testing.assert_allclose(matrix_from_quaternion_wxyz(data["quaternion_wxyz"]), R, atol=1e-12)
    code, out, _ = run(capsys, "fk", "puma560", *q, "--euler", "quat")
    assert code == 0 and "quaternion w x y z" in out


@pytest.mark.parametrize(("argv", "in_degrees"), [
    (["fk", "probot-anno", "0", "0.5", "0", "0", "0", "0"],
     ["fk", "probot-anno", "0", "{0.5}", "0", "0", "0", "0"]),
    (["jacobian", "probot-anno", "0", "0.5", "0", "0", "0", "0"],
     ["jacobian", "probot-anno", "0", "{0.5}", "0", "0", "0", "0"]),
    (["ik", "probot-anno", "--pose", "0.3", "0", "0.3", "0", "0.5", "0"],
     ["ik", "probot-anno", "--pose", "0.3", "0", "0.3", "0", "{0.5}", "0"]),
    (["dynamics", "puma560", "0", "0.5", "0", "0", "0", "0"],
     ["dynamics", "puma560", "0", "{0.5}", "0", "0", "0", "0"]),
])
def test_every_json_is_si_after_deg_and_says_its_units(capsys, argv, in_degrees):
    """docs/cli.md: --json is SI whatever --deg says, and its "units" object names each field's unit."""
    typed = [f"{np.degrees(float(w[1:-1])):.17g}" if w.startswith("{") else w for w in in_degrees]
    outputs = []
    for words in (argv, [*typed, "--deg"]):
        code, out, _ = run(capsys, *words, "--json")
        assert code == 0
        outputs.append(json.loads(out))
    si, from_degrees = outputs
    assert isinstance(si["units"], dict) and si["units"] and from_degrees["units"] == si["units"]
    for key, value in si.items():
        numbers = np.array(value, dtype=object) if isinstance(value, list | float) else None
        if numbers is not None and all(isinstance(v, float | int) for v in numbers.ravel()):
            np.testing.assert_allclose(np.array(from_degrees[key], dtype=float), numbers.astype(float),
                                       atol=1e-9, err_msg=key)


def test_show_json_says_its_units(capsys):
    code, out, _ = run(capsys, "show", "probot-anno", "--json")
    assert code == 0 and json.loads(out)["units"]["limits"] == "rad (revolute), m (prismatic)"


def test_fk_plot_draws_the_arm_at_q_and_never_over_an_existing_file(capsys, tmp_path):
    from PIL import Image

    path = tmp_path / "arm.png"
    code, _, err = run(capsys, "fk", "puma560", "0", "-30", "30", "0", "60", "0", "--deg", "--plot",
                       str(path))
    assert code == 0 and f"wrote {path}" in err
    with Image.open(path) as image:
        assert image.format == "PNG" and len(image.convert("RGB").getcolors(1 << 16)) > 20
    before = path.read_bytes()
    code, _, err = run(capsys, "fk", "puma560", *["0"] * 6, "--plot", str(path))
    assert code == 1 and "already exists; pass --force" in err and path.read_bytes() == before
    code, _, _ = run(capsys, "fk", "puma560", *["0"] * 6, "--plot", str(path), "--force")
    assert code == 0 and path.read_bytes() != before
    code, _, err = run(capsys, "fk", "puma560", *["0"] * 6, "--plot", str(tmp_path / "arm.gif"))
    assert code == 1 and "--plot" in err and "expected a file name ending in .png, .svg, .pdf" in err


def test_show_and_ik_all_on_a_general_arm_with_a_prismatic_joint(capsys, tmp_path):
    # an RRPRRR table of no class: the general 5R1P solver lists every solution
    joints = [(120, 40, 70, 10, "revolute"), (-30, 250, -60, 20, "revolute"), (80, 30, 45, -35, "prismatic"),
              (10, 60, 80, 50, "revolute"), (40, 20, -70, 15, "revolute"), (90, 15, 30, -5, "revolute")]
    text = 'name = "rrprrr"\nconvention = "standard"\nlength_unit = "mm"\nangle_unit = "deg"\n'
    for d, a, alpha, theta, kind in joints:
        text += f'\n[[joints]]\ntype = "{kind}"\nd = {d}\na = {a}\nalpha = {alpha}\ntheta = {theta}\n'
        text += "limits = [-1000, 1000]\n" if kind == "prismatic" else ""
    path = tmp_path / "rrprrr.toml"
    path.write_text(text)
    code, out, _ = run(capsys, "show", str(path))
    assert code == 0 and "general (general 5R1P solver, up to 16 solutions)" in out
    q0 = [0.3, -0.5, 0.12, 1.0, 0.7, -0.4]
    T = armkit.load(path).fk(q0)
    matrix = [repr(float(v)) for v in T.ravel()]
    code, out, err = run(capsys, "ik", str(path), "--matrix", *matrix, "--all", "--outside", "--json")
    assert code == 0, err
    listed = np.array(json.loads(out)["solutions"])
    assert np.abs(listed - q0).max(axis=1).min() <= 1e-9
