"""Robot files in product-of-exponentials form and with plain base/tool transforms; round trips."""

from __future__ import annotations

import math
import textwrap
import tomllib

import numpy as np
import pytest
from conftest import assert_transform_close
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit
from armkit.errors import RobotDefinitionError
from armkit.ik import analyze_structure
from armkit.spatial.transforms import transform_from_pose

# The UR5 of the DH built-in, written as IK-Geo / EAIK write it: H, P at q = 0, in mm and deg.
UR5_POE = """
name = "UR5 (POE)"
convention = "poe"
length_unit = "mm"
angle_unit = "deg"
[[joints]]
axis = [0, 0, 1]
point = [0, 0, 89.459]
limits = [-360, 360]
[[joints]]
axis = [0, -1, 0]
point = [0, 0, 89.459]
limits = [-360, 360]
[[joints]]
axis = [0, -1, 0]
point = [-425, 0, 89.459]
limits = [-360, 360]
[[joints]]
axis = [0, -1, 0]
point = [-817.25, 0, 89.459]
limits = [-360, 360]
[[joints]]
axis = [0, 0, -1]
point = [-817.25, -109.15, 89.459]
limits = [-360, 360]
[[joints]]
axis = [0, -1, 0]
point = [-817.25, -109.15, -5.191]
limits = [-360, 360]
[tool]
xyz = [-817.25, -191.45, -5.191]
rpy = [90, 0, 0]
"""


def write(tmp_path, text, name="arm.toml"):
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return path


def test_a_joint_axis_too_short_to_be_a_direction_is_named_with_the_file(tmp_path):
    """Before: 'joint 'q1': axis [0.0, 0.0, 1e-300]: expected three finite numbers, not all zero', without
    the file, of an axis that is not zero."""
    path = write(tmp_path, UR5_POE.replace("axis = [0, 0, -1]", "axis = [0, 0, -1e-300]"))
    message = (r"arm.toml, joint 'q5': axis \[0.0, 0.0, -1e-300\]: its length 1e-300 is too small to be a "
               r"direction; expected three finite numbers of length at least 1e-12")
    with pytest.raises(RobotDefinitionError, match=message):
        armkit.load(path)


def test_ur5_from_joint_lines_equals_the_dh_ur5(tmp_path):
    poe = armkit.load(write(tmp_path, UR5_POE))
    dh = armkit.load("ur5")
    q = dh.random_q(20, rng=2)
    assert_transform_close(poe.fk(q), dh.fk(q), 1e-12, 1e-12)
    assert analyze_structure(poe.chain).kind == "three-parallel"
    np.testing.assert_allclose(poe.limits, dh.limits)
    assert poe.poe.length_unit == "mm" and poe.dh is None


def test_dh_file_with_plain_base_and_tool_transforms(tmp_path):
    text = """
    convention = "standard"
    length_unit = "mm"
    angle_unit = "deg"
    [[joints]]
    alpha = 0
    a = 300
    d = 0
    theta = 0
    [base]
    xyz = [100, 0, 50]
    rpy = [0, 0, 90]
    [tool]
    matrix = [[1, 0, 0, 0], [0, 0, -1, 0], [0, 1, 0, 20], [0, 0, 0, 1]]
    """
    robot = armkit.load(write(tmp_path, text))
    # base: rotated 90 deg about z, at (0.1, 0, 0.05); the link along the rotated x; tool 20 mm up
    T = robot.fk([0.0])
    np.testing.assert_allclose(T[:3, 3], [0.1, 0.3, 0.07], atol=1e-15)
    np.testing.assert_allclose(T[:3, :3], [[0, 0, 1], [1, 0, 0], [0, 1, 0]], atol=1e-15)
    assert robot.dh.T_tool is not None and robot.dh.tool_rows == ()


@pytest.mark.parametrize(("text", "message"), [
    ('[tool]\nxyz = [1, 2]', r"\[tool\], key 'xyz': expected 3 numbers, got \[1, 2\]"),
    ('[tool]\nrpy = [0, 0, "x"]', r"\[tool\], key 'rpy': expected a finite number, got 'x'"),
    ('[tool]\nmatrix = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]]', r"key 'matrix': expected 4 rows of 4"),
    ('[tool]\nmatrix = [[2, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]',
     r"key 'matrix': rotation part is not a rotation matrix"),
    ('[tool]\nmatrix = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]\nxyz = [0, 0, 0]',
     "either matrix or xyz and rpy"),
    ('[tool]\nquaternion = [1, 0, 0, 0]', r"\[tool\]: unknown key 'quaternion'"),
    ('tool = 3', r"tool must be a \[tool\] table \(xyz and rpy, or matrix\) or \[\[tool\]\] DH rows, got 3"),
])
def test_bad_transform_tables_are_refused(tmp_path, text, message):
    base = 'convention = "standard"\nlength_unit = "m"\nangle_unit = "rad"\n'
    joint = "[[joints]]\nalpha = 0\na = 1\nd = 0\ntheta = 0\n"
    with pytest.raises(RobotDefinitionError, match=message):
        body = text + "\n" + joint if text.startswith("tool") else joint + text
        armkit.load(write(tmp_path, base + body))


@pytest.mark.parametrize(("edit", "message"), [
    (lambda t: t.replace("axis = [0, 0, 1]", "axis = [0, 0, 0]", 1), r"joint 'q1': axis \[0.0, 0.0, 0.0\]"),
    (lambda t: t.replace("point = [0, 0, 89.459]\n", "", 1), r"joint 1: missing key 'point'"),
    (lambda t: t.replace("axis = [0, 0, 1]", "axis = [0, 0, 1]\nalpha = 0", 1),
     r"joint 1: unknown key 'alpha'"),
    (lambda t: t.replace("[tool]", "[[tool]]"),
     r"tool must be a \[tool\] table \(xyz and rpy, or matrix\), got"),
])
def test_bad_poe_files_name_joint_and_key(tmp_path, edit, message):
    with pytest.raises(RobotDefinitionError, match=message):
        armkit.load(write(tmp_path, edit(UR5_POE)))


# ------------------------------------------------------------------ round trips
finite = st.floats(-2.0, 2.0, allow_nan=False)
angle = st.floats(-math.pi, math.pi, allow_nan=False)
names = st.text(st.characters(blacklist_categories=("Cs",)), min_size=1, max_size=8).filter(str.strip)


def transform_table(draw):
    return {"xyz": [draw(finite) for _ in range(3)], "rpy": [draw(angle) for _ in range(3)]}


@st.composite
def robot_dicts(draw):
    """A robot file's contents: DH (rows or transforms at the ends) or POE, units m/rad."""
    n = draw(st.integers(1, 7))
    convention = draw(st.sampled_from(["standard", "modified", "poe"]))
    joint_names = draw(st.lists(names, min_size=n, max_size=n, unique=True))
    joints = []
    for name in joint_names:
        kind = draw(st.sampled_from(["revolute", "prismatic"]))
        joint = {"name": name, "type": kind}
        if convention == "poe":
            joint["axis"] = [draw(finite) for _ in range(3)]
            if np.linalg.norm(joint["axis"]) < 0.1:
                joint["axis"] = [0.0, 0.0, 1.0]
            joint["point"] = [draw(finite) for _ in range(3)]
        else:
            joint.update(alpha=draw(angle), a=draw(finite), d=draw(finite), theta=draw(angle))
        if draw(st.booleans()):
            low = draw(st.floats(-3.0, 0.0))
            joint["limits"] = [low, low + draw(st.floats(0.1, 3.0))]
        if draw(st.booleans()):
            joint["max_velocity"] = draw(st.floats(0.1, 10.0))
        joints.append(joint)
    data = {"name": draw(names), "convention": convention, "joints": joints}
    for key in ("base", "tool"):
        form = draw(st.sampled_from(["none", "transform"] + ([] if convention == "poe" else ["rows"])))
        if form == "transform":
            data[key] = transform_table(draw)
        elif form == "rows":
            data[key] = [{"alpha": draw(angle), "a": draw(finite), "d": draw(finite), "theta": draw(angle)}
                         for _ in range(draw(st.integers(1, 2)))]
    return data, draw(st.integers(0, 2**32 - 1))


@settings(max_examples=80, deadline=None)
@given(robot_dicts())
def test_robot_to_toml_round_trips_every_form(case):
    data, seed = case
    robot = armkit.robot_from_dict(data, "random.toml")
    text = armkit.robot_to_toml(robot)
    again = armkit.robot_from_dict(tomllib.loads(text), "again.toml", require_units=True)
    assert ('convention = "poe"' in text) == (data["convention"] == "poe")
    assert again.name == robot.name and again.joint_names == robot.joint_names
    assert again.joint_types == robot.joint_types
    np.testing.assert_array_equal(again.limits, robot.limits)
    np.testing.assert_array_equal(again.max_velocity, robot.max_velocity)
    q = robot.random_q(5, rng=seed)
    assert_transform_close(again.fk(q), robot.fk(q), 1e-12, 1e-12)


@settings(max_examples=30, deadline=None)
@given(robot_dicts(), st.data())
def test_locked_and_urdf_robots_are_written_as_joint_lines(case, data):
    robot_data, seed = case
    robot = armkit.robot_from_dict(robot_data, "random.toml")
    if robot.n == 1:
        return
    index = data.draw(st.integers(0, robot.n - 1))
    locked = robot.lock({index: float(robot.random_q(rng=seed)[index])})
    again = armkit.robot_from_dict(tomllib.loads(armkit.robot_to_toml(locked)), "again.toml")
    assert again.poe is not None and again.joint_names == locked.joint_names
    q = locked.random_q(5, rng=seed)
    assert_transform_close(again.fk(q), locked.fk(q), 1e-12, 1e-12)


def test_dh_transforms_written_back_as_tables(tmp_path):
    T = transform_from_pose([0.1, -0.2, 0.3, 0.4, -0.5, 0.6], "xyz-fixed")
    robot = armkit.Robot.from_dh([armkit.DHRow(0.2, 0.3, 0.1, 0.0)], "modified", T_base=T, T_tool=T)
    text = armkit.robot_to_toml(robot)
    assert "[base]\nxyz = " in text and "[tool]\nxyz = " in text and "[[tool]]" not in text
    again = armkit.load(write(tmp_path, text))
    assert_transform_close(again.dh.T_tool, T, 1e-15, 1e-15)
    assert_transform_close(again.fk([0.7]), robot.fk([0.7]), 1e-15, 1e-15)
