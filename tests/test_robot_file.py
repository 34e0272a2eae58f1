import math
import textwrap

import numpy as np
import pytest
from conftest import assert_transform_close

import armkit
from armkit.errors import RobotDefinitionError

MINIMAL = """
name = "two link"
convention = "standard"
length_unit = "mm"
angle_unit = "deg"
[[joints]]
alpha = 0
a = 300
d = 0
theta = 0
limits = [-90, 90]
max_velocity = 45
max_acceleration = 20
[[joints]]
type = "prismatic"
alpha = 0
a = 0
d = 10
theta = 90
limits = [0, 100]
max_velocity = 50
[[tool]]
alpha = 0
a = 0
d = 55
theta = 0
"""


def write(tmp_path, text, name="arm.toml"):
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return path


def test_every_builtin_loads():
    names = armkit.builtin_robots()
    assert {"probot-anno", "zju-i", "grb400-scara", "puma560", "stanford", "ur5", "panda"} <= set(names)
    for name in names:
        robot = armkit.load(name)
        assert robot.limits.shape == (robot.n, 2)
        assert np.all(robot.limits[:, 0] < robot.limits[:, 1])


def test_units_are_converted_once(tmp_path):
    robot = armkit.load(write(tmp_path, MINIMAL))
    assert robot.name == "two link" and robot.n == 2
    assert robot.joint_types == ["revolute", "prismatic"]
    np.testing.assert_allclose(robot.limits, [[-math.pi / 2, math.pi / 2], [0.0, 0.1]])
    np.testing.assert_allclose(robot.max_velocity, [math.radians(45), 0.05])
    np.testing.assert_allclose(robot.max_acceleration, [math.radians(20), np.inf])
    # q2 (prismatic) adds to d = 10 mm; tool adds 55 mm along z
    np.testing.assert_allclose(robot.fk([0.0, 0.02])[:3, 3], [0.3, 0.0, 0.01 + 0.02 + 0.055], atol=1e-15)


def test_probot_matches_its_dh_table_written_by_hand():
    robot = armkit.load("probot-anno")

    def mdh(alpha, a, d, theta):
        ca, sa, ct, st = math.cos(alpha), math.sin(alpha), math.cos(theta), math.sin(theta)
        return np.array([[ct, -st, 0, a], [st * ca, ct * ca, -sa, -sa * d],
                         [st * sa, ct * sa, ca, ca * d], [0, 0, 0, 1]])

    q = [0.3, -0.2, 0.5, 0.1, 0.7, -0.4]
    r = math.radians
    rows = [(0, 0, 0.284, 0), (r(90), 0, 0, r(90)), (0, 0.225, 0, 0), (r(90), 0, 0.2289, 0),
            (r(-90), 0, 0, r(-90)), (r(90), 0, 0, 0)]
    T = np.eye(4)
    for (alpha, a, d, theta), qi in zip(rows, q, strict=True):
        T = T @ mdh(alpha, a, d, theta + qi)
    T = T @ mdh(0, 0, 0.055, 0) @ mdh(r(-90), 0, 0, 0)
    assert_transform_close(robot.fk(q), T)


def test_round_trip_through_toml(tmp_path):
    for name in ("stanford", "panda", "probot-anno"):
        robot = armkit.load(name)
        again = armkit.load(write(tmp_path, armkit.robot_to_toml(robot), f"{name}.toml"))
        q = robot.random_q(5, rng=0)
        assert_transform_close(again.fk(q), robot.fk(q), 1e-14, 1e-14)
        np.testing.assert_allclose(again.limits, robot.limits)
        np.testing.assert_allclose(again.max_velocity, robot.max_velocity)


@pytest.mark.parametrize(("edit", "message"), [
    (lambda t: t.replace('convention = "standard"', 'convention = "craig"'),
     r"arm.toml: convention = 'craig'; expected one of 'standard', 'modified'"),
    (lambda t: t.replace('length_unit = "mm"', 'length_unit = "inch"'),
     r"length_unit = 'inch'; expected one of 'm', 'mm'"),
    (lambda t: t.replace('angle_unit = "deg"', 'angle_unit = "grad"'),
     r"angle_unit = 'grad'; expected one of 'rad', 'deg'"),
    (lambda t: t.replace("a = 300", "a = 300\nlenght = 3"),
     r"arm.toml, joint 1: unknown key 'lenght'"),
    (lambda t: t.replace("a = 300\n", ""), r"arm.toml, joint 1: missing key 'a'"),
    (lambda t: t.replace("a = 300", 'a = "300"'),
     r"arm.toml, joint 1, key 'a': expected a finite number, got '300'"),
    (lambda t: t.replace("d = 10", "d = nan"), r"joint 2, key 'd': expected a finite number, got nan"),
    (lambda t: t.replace('type = "prismatic"', 'type = "spherical"'),
     r"joint 2: type = 'spherical'; expected one of 'revolute', 'prismatic'"),
    (lambda t: t.replace("limits = [-90, 90]", "limits = [90, -90]"),
     r"joint 1, key 'limits': lower 90 must be below upper -90"),
    (lambda t: t.replace("limits = [-90, 90]", "limits = [-90]"),
     r"joint 1, key 'limits': expected \[lower, upper\], got \[-90\]"),
    (lambda t: t.replace("max_velocity = 45", "max_velocity = -45"),
     r"joint 1, key 'max_velocity': expected a positive number, got -45"),
    (lambda t: t.replace("d = 55", "d = 55\nlimits = [0, 1]"), r"tool row 1: unknown key 'limits'"),
    (lambda t: t.replace('name = "two link"', 'name = "two link"\ncolour = "red"'),
     r"arm.toml: unknown key 'colour'"),
    (lambda t: t.replace('convention = "standard"\n', ""), r"arm.toml: missing key 'convention'"),
    (lambda t: t.replace('angle_unit = "deg"\n', ""), r"arm.toml: missing key 'angle_unit'"),
    (lambda t: t.replace('length_unit = "mm"\n', ""), r"arm.toml: missing key 'length_unit'"),
    (lambda t: t.replace("[[joints]]", "[[joint]]"), r"unknown key 'joint'"),
    (lambda t: t + "\n[broken", r"arm.toml: not valid TOML"),
])
def test_bad_files_name_file_joint_and_key(tmp_path, edit, message):
    path = write(tmp_path, edit(MINIMAL))
    with pytest.raises(RobotDefinitionError, match=message):
        armkit.load(path)


def test_empty_joint_list_is_refused():
    with pytest.raises(RobotDefinitionError, match="'joints' must be a non-empty array"):
        armkit.robot_from_dict({"convention": "standard", "joints": []}, "mine.toml")


def test_unknown_robot_lists_builtins():
    with pytest.raises(RobotDefinitionError, match=r"unknown robot 'kuka': not a built-in \(grb400-scara"):
        armkit.load("kuka")


@pytest.mark.parametrize(("name", "text", "message"), [
    ("empty.xml", "  \n", "the file is empty; expected a robot file"),
    ("empty.toml", "", "the file is empty; expected a robot file"),
    ("arm.xml", "a = 1\n", r"not XML \(a .xml file should hold a URDF <robot> or an MJCF <mujoco>"),
    ("arm.urdf", "name = 'x'\n", r"not XML \(a .urdf file"),
])
def test_empty_and_non_xml_files_are_named_for_what_they_are(tmp_path, name, text, message):
    path = tmp_path / name
    path.write_text(text)
    with pytest.raises(RobotDefinitionError, match=message):
        armkit.load(path)


@pytest.mark.parametrize("name", ["arm.urdf", "arm.xml"])
def test_a_utf16_xml_file_is_asked_for_as_utf8(tmp_path, name):
    path = tmp_path / name
    path.write_text('<robot name="r"><link name="a"/></robot>', encoding="utf-16")
    with pytest.raises(RobotDefinitionError, match=r"not UTF-8 text \(byte 0\); save the URDF as UTF-8"):
        armkit.load(path)



def test_a_robot_file_with_more_joints_than_armkit_handles_is_refused_at_load_in_one_line(tmp_path, capsys):
    from armkit.chain import MAX_JOINTS
    from armkit.cli.main import main

    joint = '[[joints]]\nd = 0\na = 100\nalpha = 0\ntheta = 0\nlimits = [-90, 90]\n'
    path = tmp_path / "long.toml"
    head = 'name = "long"\nconvention = "standard"\nlength_unit = "mm"\nangle_unit = "deg"\n'
    path.write_text(head + joint * (MAX_JOINTS + 1))
    with pytest.raises(RobotDefinitionError, match=f"a chain of {MAX_JOINTS + 1} moving joints: armkit "
                                                   f"handles at most {MAX_JOINTS}"):
        armkit.load(path)
    assert main(["show", str(path)]) == 1
    err = capsys.readouterr().err
    assert err.startswith("error: ") and "at most 16" in err and len(err.strip().splitlines()) == 1
    path.write_text(head + joint * MAX_JOINTS)        # the most it handles: FK and IK work
    robot = armkit.load(path)
    q = np.full(MAX_JOINTS, 0.05)
    np.testing.assert_allclose(robot.fk(robot.ik(robot.fk(q), near=q)), robot.fk(q), atol=1e-9)


def test_a_folder_is_named_a_folder(tmp_path):
    with pytest.raises(RobotDefinitionError, match="a folder, not a robot file"):
        armkit.load(tmp_path)
