"""URDF import: exact mapping onto the chain (pinocchio as the referee), link selection, bad input."""

from __future__ import annotations

import os
import re
from pathlib import Path

import numpy as np
import pytest
from conftest import assert_transform_close
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import armkit
from armkit.errors import RobotDefinitionError
from armkit.export import urdf_from_robot, write_urdf
from armkit.urdf import robot_from_urdf

#: Examples per fuzz test; `make fuzz` runs many more (ARMKIT_FUZZ_EXAMPLES).
FUZZ_EXAMPLES = int(os.environ.get("ARMKIT_FUZZ_EXAMPLES", "300"))

pinocchio = pytest.importorskip("pinocchio")

# A 4-joint arm with everything URDF allows on a path: odd axes (not unit length), a continuous
# joint, a prismatic one, fixed joints between and after, a world link, side branches (a mimic
# finger, a floating sensor) that are not on the chain, and meshes.
ARM = """<?xml version="1.0"?>
<robot name="test arm">
  <link name="world"/>
  <link name="base_link"><visual><origin xyz="0 0 0.01"/>
    <geometry><mesh filename="package://arm/meshes/base.stl" scale="0.001 0.001 0.001"/></geometry></visual>
  </link>
  <link name="l1"/><link name="l1b"/><link name="l2"/><link name="l3"/><link name="l4"/><link name="flange"/>
  <link name="tool"><visual><geometry><mesh filename="meshes/tool.dae"/></geometry></visual></link>
  <link name="finger"/><link name="sensor"/><link name="cover">
    <visual><geometry><mesh filename="cover.stl"/></geometry></visual></link>
  <joint name="fix_world" type="fixed"><parent link="world"/><child link="base_link"/>
    <origin xyz="0.1 -0.2 0.05" rpy="0 0 0.3"/></joint>
  <joint name="j1" type="revolute"><parent link="base_link"/><child link="l1"/>
    <origin xyz="0 0 0.2" rpy="0.1 -0.2 0.3"/><axis xyz="0 0 2"/>
    <limit lower="-2.5" upper="2.5" velocity="3" effort="40"/></joint>
  <joint name="mid" type="fixed"><parent link="l1"/><child link="l1b"/>
    <origin xyz="0.05 0 0.1" rpy="1 0 0"/></joint>
  <joint name="j2" type="continuous"><parent link="l1b"/><child link="l2"/>
    <origin xyz="0 0.1 0" rpy="0 1.5707963267948966 0"/><axis xyz="0.3 -0.4 0.5"/></joint>
  <joint name="j3" type="prismatic"><parent link="l2"/><child link="l3"/>
    <origin xyz="0.3 0 0"/><axis xyz="-1 1 0"/>
    <limit lower="-0.1" upper="0.2" velocity="0.5" effort="100"/></joint>
  <joint name="j4" type="revolute"><parent link="l3"/><child link="l4"/>
    <origin xyz="0 0 0.25" rpy="3.141592653589793 0 0"/><axis xyz="0 -1 0"/>
    <limit lower="-1" upper="1" velocity="0" effort="5"/></joint>
  <joint name="to_flange" type="fixed"><parent link="l4"/><child link="flange"/>
    <origin xyz="0 0 0.08"/></joint>
  <joint name="to_tool" type="fixed"><parent link="flange"/><child link="tool"/>
    <origin xyz="0.01 0 0.02" rpy="0 0 1.5707963267948966"/></joint>
  <joint name="finger_joint" type="prismatic"><parent link="l4"/><child link="finger"/>
    <mimic joint="j4"/><limit lower="0" upper="0.04" velocity="1" effort="1"/></joint>
  <joint name="sensor_mount" type="floating"><parent link="l2"/><child link="sensor"/></joint>
  <joint name="cover_mount" type="fixed"><parent link="l3"/><child link="cover"/>
    <origin xyz="0 0.02 0"/></joint>
  <transmission name="t1"><joint name="j1"/></transmission>
</robot>
"""


def pinocchio_poses(path_or_text, robot: armkit.Robot, frame: str, q: np.ndarray) -> np.ndarray:
    """Pose of URDF link ``frame`` from pinocchio at armkit's configurations (joints by name)."""
    text = path_or_text if "<robot" in str(path_or_text) else Path(path_or_text).read_text()
    model = pinocchio.buildModelFromXML(text)
    data = model.createData()
    frame_id = model.getFrameId(frame)
    poses = []
    for q_k in np.atleast_2d(q):
        q_pin = pinocchio.neutral(model)
        for name, value in zip(robot.joint_names, q_k, strict=True):
            joint = model.joints[model.getJointId(name)]
            values = [value] if joint.nq == 1 else [np.cos(value), np.sin(value)]  # continuous: cos, sin
            q_pin[joint.idx_q:joint.idx_q + joint.nq] = values
        pinocchio.framesForwardKinematics(model, data, q_pin)
        poses.append(data.oMf[frame_id].homogeneous)
    return np.array(poses)


def test_every_kind_of_joint_and_axis_matches_pinocchio():
    robot = robot_from_urdf(ARM, tip="tool")
    assert robot.joint_names == ["j1", "j2", "j3", "j4"]
    assert robot.joint_types == ["revolute", "revolute", "prismatic", "revolute"]
    np.testing.assert_array_equal(robot.limits, [[-2.5, 2.5], [-np.inf, np.inf], [-0.1, 0.2], [-1, 1]])
    np.testing.assert_array_equal(robot.max_velocity, [3, np.inf, 0.5, np.inf])  # velocity 0: none
    assert robot.urdf.effort == (40.0, None, 100.0, 5.0)
    assert robot.urdf.links == ("l1", "l2", "l3", "l4") and robot.urdf.base == "world"
    q = robot.random_q(30, rng=5)
    assert_transform_close(robot.fk(q), pinocchio_poses(ARM, robot, "tool", q), 1e-12, 1e-12)
    # link frames are the URDF's child links
    frames = robot.link_frames(q)
    for i, link in enumerate(robot.urdf.links):
        assert_transform_close(frames[:, i + 1], pinocchio_poses(ARM, robot, link, q), 1e-12, 1e-12)


def test_meshes_of_links_moving_with_the_chain_are_kept():
    robot = robot_from_urdf(ARM, tip="tool")
    meshes = {m.link: m for m in robot.urdf.meshes}
    assert set(meshes) == {"base_link", "tool", "cover"}  # the finger and sensor branches move apart
    assert meshes["base_link"].filename == "package://arm/meshes/base.stl"
    assert meshes["base_link"].scale == (0.001, 0.001, 0.001) and meshes["base_link"].frame == 0
    assert meshes["tool"].filename == "meshes/tool.dae" and meshes["tool"].frame == 4
    assert meshes["cover"].frame == 3
    q = robot.random_q(5, rng=1)
    frames = robot.link_frames(q)
    for link in ("base_link", "tool", "cover"):
        mesh = meshes[link]
        expected = pinocchio_poses(ARM, robot, link, q)
        if link == "base_link":
            expected = expected @ armkit.spatial.transforms.transform_from(np.eye(3), [0, 0, 0.01])
        assert_transform_close(frames[:, mesh.frame] @ mesh.T_frame_mesh, expected, 1e-12, 1e-12)


def test_base_and_tip_choose_the_chain():
    robot = robot_from_urdf(ARM, base="l1b", tip="l3")
    assert robot.joint_names == ["j2", "j3"] and robot.urdf.base == "l1b"
    q = robot.random_q(10, rng=2)
    full = robot_from_urdf(ARM, tip="tool")
    q_full = np.column_stack([np.zeros(10), q, np.zeros(10)])
    T_base = pinocchio_poses(ARM, full, "l1b", q_full)
    T_tip = pinocchio_poses(ARM, full, "l3", q_full)
    assert_transform_close(robot.fk(q), np.linalg.inv(T_base) @ T_tip, 1e-12, 1e-12)


@pytest.mark.parametrize(("options", "message"), [
    ({}, r"URDF text: 4 leaf links below 'world': finger \(5 moving joints\), tool \(4 moving joints\), "
         r"sensor \(3 moving joints\), cover \(3 moving joints\); choose one as the tip \(tip=\.\.\. in "
         r"Python, --tip LINK on the command line\)"),
    ({"tip": "tool", "base": "tool"}, r"no moving joint between links 'tool' and 'tool'"),
    ({"tip": "l2", "base": "l3"}, r"tip link 'l2' is not below base link 'l3'"),
    ({"tip": "hand"}, r"tip link 'hand' is not in the file; its links: world, base_link, l1"),
    ({"base": "hand", "tip": "tool"}, r"base link 'hand' is not in the file"),
    ({"tip": "finger"}, r"joint 'finger_joint': a mimic joint \(it follows another joint\) on the path"),
    ({"tip": "sensor"}, r"joint 'sensor_mount': type 'floating' is not a joint of a serial arm"),
    ({"tip": "base_link"}, r"no moving joint between links 'world' and 'base_link'"),
])
def test_link_choices_get_clear_errors(options, message):
    with pytest.raises(RobotDefinitionError, match=message):
        robot_from_urdf(ARM, **options)


def edit(old: str, new: str):
    def apply(text: str) -> str:
        assert old in text, old
        return text.replace(old, new, 1)
    return apply


@pytest.mark.parametrize(("change", "message"), [
    (edit("</robot>", ""), r"URDF text: not valid XML: no element found: line \d+, column 0"),
    (edit('<link name="l2"/>', '<link name="l2">'), r"not valid XML: mismatched tag: line \d+"),
    (edit('<?xml version="1.0"?>', '<?xml version="1.0"?>\n<!DOCTYPE robot [<!ENTITY a "aaaa">]>'),
     r"URDF text, line 2: <!DOCTYPE declarations are refused \(entities can expand without bound\)"),
    (edit("<robot", '<!ENTITY x "y">\n<robot'), r"<!ENTITY declarations are refused"),
    (lambda t: t.replace("<robot", "<mujoco").replace("</robot>", "</mujoco>"),
     r"URDF text: the root element is <mujoco>; a URDF file has <robot>"),
    (edit('<link name="l2"/>', '<link/>'), r"<link> number 5 has no name"),
    (edit('<link name="l2"/>', '<link name="l2"/><link name="l2"/>'), r"two links are named 'l2'"),
    (edit('name="j3"', 'name="j2"'), r"two joints are named 'j2'"),
    (edit('<joint name="j3" type="prismatic">', '<joint name="j3" type="ball">'),
     r"joint 'j3': type 'ball'; expected one of revolute, continuous, prismatic, fixed"),
    (edit('<joint name="j3" type="prismatic">', '<joint name="j3">'), r"joint 'j3': type None; expected"),
    (edit('<parent link="l2"/><child link="l3"/>', '<child link="l3"/>'),
     r"joint 'j3': missing <parent link=\"...\"/>"),
    (edit('<parent link="l2"/><child link="l3"/>', '<parent link="l9"/><child link="l3"/>'),
     r"joint 'j3': parent link 'l9' is not a <link> of the file"),
    (edit('<parent link="l4"/><child link="flange"/>', '<parent link="l4"/><child link="l3"/>'),
     r"joint 'to_flange': link 'l3' already has parent joint 'j3'; a URDF is a tree"),
    (edit('<parent link="world"/><child link="base_link"/>', '<parent link="l1"/><child link="base_link"/>'),
     r"links base_link, l1 form a cycle; a URDF is a tree"),
    (edit('<parent link="world"/><child link="base_link"/>',
          '<parent link="base_link"/><child link="base_link"/>'),
     r"links base_link form a cycle"),
    (edit('<link name="world"/>', '<link name="world"/><link name="other"/>'),
     r"2 root links \(world, other\)"),
    (edit('<origin xyz="0.3 0 0"/>', '<origin xyz="0.3 0"/>'),
     r"joint 'j3': <origin xyz=\"0.3 0\">: expected 3 finite numbers of magnitude at most 1e\+06"),
    (edit('<origin xyz="0.3 0 0"/>', '<origin xyz="0.3 nan 0"/>'), r"joint 'j3': <origin xyz=\"0.3 nan 0\">"),
    (edit('<origin xyz="0.3 0 0"/>', '<origin xyz="1e308 0 0"/>'), r"joint 'j3': <origin xyz=\"1e308 0 0\">"),
    (edit('<origin xyz="0.3 0 0"/>', '<origin xyz="0.3 0 0" rpy="a b c"/>'),
     r"joint 'j3': <origin rpy=\"a b c\">"),
    (edit('<axis xyz="-1 1 0"/>', '<axis xyz="0 0 0"/>'),
     r"joint 'j3': axis \[0.0, 0.0, 0.0\]: expected three"),
    (edit('<axis xyz="-1 1 0"/>', '<axis/>'), r"joint 'j3': <axis> has no xyz=\"...\""),
    # before: 'expected three finite numbers, not all zero', of an axis that is not zero
    (edit('<axis xyz="-1 1 0"/>', '<axis xyz="0 0 1e-300"/>'),
     r"joint 'j3': axis \[0.0, 0.0, 1e-300\]: its length 1e-300 is too small to be a direction; expected "
     r"three finite numbers of length at least 1e-12"),
    (edit('<limit lower="-0.1" upper="0.2" velocity="0.5" effort="100"/>', ""),
     r"joint 'j3': a prismatic joint needs <limit lower=\.\.\. upper=\.\.\. velocity=\.\.\. effort=\.\.\.>"),
    (edit('lower="-0.1" upper="0.2"', 'lower="0.2" upper="-0.1"'),
     r"joint 'j3': <limit lower=\"0.2\" upper=\"-0.1\">"),
    (edit('velocity="0.5"', 'velocity="fast"'),
     r"joint 'j3': <limit velocity=\"fast\">: expected 1 finite number"),
    (edit('lower="-0.1"', 'lower="-inf"'), r"joint 'j3': <limit lower=\"-inf\">: expected 1 finite number"),
    (edit('<joint name="j3" type="prismatic">', '<joint name="j3" type="planar">'),
     r"joint 'j3': type 'planar' is not a joint of a serial arm"),
    (edit('<parent link="l2"/><child link="l3"/>',
          '<parent link="l2"/><child link="l3"/><mimic joint="j2"/>'),
     r"joint 'j3': a mimic joint"),
    (edit('<joint name="j1" type="revolute">', '<joint type="revolute">'), r"<joint> number 2 has no name"),
    (edit('<origin xyz="0.3 0 0"/>', '<origin xyz="1_0 0 0"/>'),
     r"joint 'j3': <origin xyz=\"1_0 0 0\">: expected 3"),
    (edit('<origin xyz="0.3 0 0"/>', '<origin xyz="\u0663 0 0"/>'),
     r"joint 'j3': <origin xyz=\"\u0663 0 0\">"),
    (edit('<origin xyz="0.3 0 0"/>', '<origin xyz="\uff11 0 0"/>'),
     r"joint 'j3': <origin xyz=\"\uff11 0 0\">"),
    (edit('<origin xyz="0.3 0 0"/>', '<origin xyz="0.3 0 0" rpy="infinity 0 0"/>'),
     r"joint 'j3': <origin rpy=\"infinity 0 0\">"),
    (edit('velocity="0.5"', 'velocity="0x1"'), r"joint 'j3': <limit velocity=\"0x1\">"),
])
def test_malformed_urdf_gets_one_clear_error(change, message):
    with pytest.raises(RobotDefinitionError, match=message):
        robot_from_urdf(change(ARM), tip="tool")


def test_plain_decimals_as_the_spec_writes_them_are_read():
    text = edit('<origin xyz="0.3 0 0"/>', '<origin xyz="+.3E0 -0. 1e-3"/>')(ARM)
    again = robot_from_urdf(text, tip="tool")
    reference = robot_from_urdf(edit('<origin xyz="0.3 0 0"/>', '<origin xyz="0.3 0 0.001"/>')(ARM),
                                tip="tool")
    q = again.random_q(5, rng=1)
    np.testing.assert_array_equal(again.fk(q), reference.fk(q))


@pytest.mark.parametrize(("joint", "old", "new", "index"), [
    ("j3", '<limit lower="-0.1" upper="0.2" velocity="0.5" effort="100"/>', "<limit/>", 2),
    ("j1", '<limit lower="-2.5" upper="2.5" velocity="3" effort="40"/>',
     '<limit velocity="3" effort="40"/>', 0),
])
def test_a_limit_without_bounds_takes_the_spec_defaults_explicitly_with_a_warning(joint, old, new, index):
    message = (rf"joint '{joint}': <limit> has neither lower nor upper, so the URDF spec's defaults hold the "
               rf"(revolute|prismatic) joint at \[0, 0\] \(as urdfdom and pinocchio read it\); write both")
    with pytest.warns(UserWarning, match=message):
        robot = robot_from_urdf(edit(old, new)(ARM), tip="tool")
    assert robot.limits[index].tolist() == [0.0, 0.0]


def test_a_limit_with_one_bound_takes_the_spec_default_zero_for_the_other():
    text = edit('lower="-0.1" upper="0.2"', 'lower="-0.1"')(ARM)
    assert robot_from_urdf(text, tip="tool").limits[2].tolist() == [-0.1, 0.0]
    text = edit('lower="-0.1" upper="0.2"', 'upper="0.2"')(ARM)
    assert robot_from_urdf(text, tip="tool").limits[2].tolist() == [0.0, 0.2]


@pytest.mark.parametrize(("bounds", "limits"), [
    ('lower="-1e300" upper="1e300"', [-np.inf, np.inf]),  # Gazebo's 1e16 and larger: no limit
    ('lower="-1e16" upper="0.2"', [-np.inf, 0.2]),
    ('lower="-1e6" upper="1e6"', [-1e6, 1e6]),  # MAX_VALUE itself is still a limit
])
def test_a_position_limit_beyond_max_value_is_no_limit(bounds, limits):
    """URDF's way of saying "unbounded" for a joint that must have a <limit> (robot files and MJCF
    refuse such values instead: they have their own "no limits", see docs/urdf.md)."""
    text = edit('lower="-0.1" upper="0.2"', bounds)(ARM)
    assert robot_from_urdf(text, tip="tool").limits[2].tolist() == limits


def test_a_byte_order_mark_is_skipped(tmp_path):
    path = tmp_path / "arm.urdf"
    path.write_bytes(b"\xef\xbb\xbf" + ARM.encode())
    robot = armkit.load(path, tip="tool")
    q = robot.random_q(3, rng=2)
    np.testing.assert_array_equal(robot.fk(q), robot_from_urdf(ARM, tip="tool").fk(q))
    np.testing.assert_array_equal(robot_from_urdf("\ufeff" + ARM, tip="tool").fk(q), robot.fk(q))


def _deep_urdf(depth: int, leaf_first: bool) -> str:
    links = [f'<link name="l{i}"/>' for i in range(depth + 1)]
    joints = [f'<joint name="j{i}" type="{"continuous" if i == depth - 1 else "fixed"}"><parent link="l{i}"/>'
              f'<child link="l{i + 1}"/></joint>' for i in range(depth)]
    if leaf_first:
        links, joints = links[::-1], joints[::-1]
    return '<robot name="deep">' + "".join(links) + "".join(joints) + "</robot>"


@pytest.mark.parametrize("leaf_first", [False, True])
def test_a_deep_urdf_loads_whichever_end_is_listed_first(leaf_first):
    # the cycle check once walked each link up to the root with a list of the links met:
    # quadratic in the depth when the leaves come first; the speed comparison lives in
    # benchmarks/bench_urdf.py (a timed unit test fails on a loaded machine)
    robot = robot_from_urdf(_deep_urdf(6000, leaf_first))
    assert robot.n == 1 and robot.joint_names == ["j5999"]


def test_entity_expansion_is_refused_before_parsing():
    lol = ('<?xml version="1.0"?><!DOCTYPE lolz [<!ENTITY lol "lol">'
           + "".join(f'<!ENTITY lol{i} "{"&lol" + str(i - 1) + ";" if i > 1 else "&lol;"}' * 10 + '">'
                     for i in range(1, 10)) + ']><robot name="&lol9;"><link name="a"/></robot>')
    with pytest.raises(RobotDefinitionError, match="DOCTYPE declarations are refused"):
        robot_from_urdf(lol)


def test_files_non_utf8_empty_and_suffix(tmp_path):
    path = tmp_path / "arm.urdf"
    path.write_bytes(ARM.encode().replace(b"test arm", b"test \xff arm"))
    with pytest.raises(RobotDefinitionError, match=r"arm.urdf: not UTF-8 text \(byte \d+\)"):
        armkit.load(path, tip="tool")
    path.write_text('<robot name="r"></robot>')
    with pytest.raises(RobotDefinitionError, match=r"arm.urdf: no <link> elements; nothing to load"):
        armkit.load(path)
    path.write_text("")
    with pytest.raises(RobotDefinitionError, match=r"arm.urdf: the file is empty; expected a robot file"):
        armkit.load(path)
    with pytest.raises(RobotDefinitionError, match="base and tip links choose a chain in a URDF file"):
        armkit.load("ur5", tip="tool")


def test_continuous_joints_in_ik_random_q_and_trajectories():
    robot = robot_from_urdf(ARM, tip="tool")
    q = robot.random_q(2000, rng=0)
    assert np.abs(q[:, 1]).max() <= np.pi and np.ptp(q[:, 1]) > 6.0
    target = robot.random_q(rng=3)
    near = target + [0.0, 4 * np.pi, 0.0, 0.0]  # the continuous joint two turns on: IK keeps the turns
    found = robot.ik(robot.fk(target), near=near)
    np.testing.assert_allclose(found, near, atol=1e-7)
    traj = armkit.plan_trajectory(robot, np.stack([robot.home, target]), [1.0])
    assert np.isfinite(traj.sample(50.0)[1]).all()


# ------------------------------------------------------------------ export and import
@pytest.mark.parametrize("name", armkit.builtin_robots())
def test_exported_urdf_loads_back_with_the_same_fk(name, tmp_path):
    robot = armkit.load(name)
    path = write_urdf(robot, tmp_path / f"{name}.urdf")
    again = armkit.load(path)
    assert again.joint_names == robot.joint_names and again.joint_types == robot.joint_types
    assert again.urdf.tip == "tool"
    bounded = np.isfinite(robot.limits).all(axis=1) | ~robot.chain.prismatic
    np.testing.assert_array_equal(again.limits[bounded], robot.limits[bounded])
    q = robot.random_q(50, rng=7)
    assert_transform_close(again.fk(q), robot.fk(q), 1e-12, 1e-12)
    assert_transform_close(pinocchio_poses(path, again, "tool", q), again.fk(q), 1e-12, 1e-12)
    assert armkit.analyze_structure(again.chain).kind == armkit.analyze_structure(robot.chain).kind


# ------------------------------------------------------------------ fuzzing
ATTRIBUTE = re.compile(r'="([^"]*)"')


@st.composite
def mutated_urdfs(draw):
    exported = urdf_from_robot(armkit.load(draw(st.sampled_from(["ur5", "stanford"]))))
    text = ARM if draw(st.booleans()) else exported
    for _ in range(draw(st.integers(1, 4))):
        if not text.strip():
            break
        kind = draw(st.sampled_from(["attribute", "drop", "duplicate", "byte", "cut"]))
        if kind == "attribute":
            spots = list(ATTRIBUTE.finditer(text))
            if not spots:
                continue
            m = draw(st.sampled_from(spots))
            value = draw(st.sampled_from(["", "0", "nan", "1e308", "-1e308", "1 2", "0 0 0", "a", "floating",
                                          "mimic", "world", "tool", "l1", "j1", "1e400 0 0", "-0 -0 -0",
                                          "&amp;", "1_0 0 0", "\u0661", "inf", ".5e+1 -0. +3"]))
            text = text[:m.start(1)] + value + text[m.end(1):]
        elif kind in ("drop", "duplicate"):
            lines = text.splitlines()
            i = draw(st.integers(0, len(lines) - 1))
            lines[i:i + 1] = [] if kind == "drop" else [lines[i], lines[i]]
            text = "\n".join(lines)
        elif kind == "cut":
            text = text[:draw(st.integers(0, len(text)))]
        else:
            data = bytearray(text.encode())
            data[draw(st.integers(0, len(data) - 1))] = draw(st.integers(0, 255))
            return bytes(data), draw(st.sampled_from([None, "tool", "l3"]))
    return text.encode(), draw(st.sampled_from([None, "tool", "l3"]))


@settings(max_examples=FUZZ_EXAMPLES, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mutated_urdfs())
def test_mutated_urdfs_load_or_get_armkit_errors(case):
    data, tip = case
    try:
        robot = robot_from_urdf(data, tip=tip)
    except RobotDefinitionError as exc:
        assert str(exc).strip() and "\n" not in str(exc)
        return
    q = robot.random_q(3, rng=0)
    assert np.isfinite(robot.fk(q)).all() and np.isfinite(robot.jacobian(q)).all()


@pytest.mark.parametrize("key", ["velocity", "effort"])
def test_a_negative_velocity_or_effort_limit_is_one_error_not_no_limit(tmp_path, key):
    text = ARM.replace(f'{key}="', f'{key}="-', 1)
    assert text != ARM
    with pytest.raises(RobotDefinitionError, match=f'<limit {key}="-[0-9.]+">: expected a number >= 0'):
        robot_from_urdf(text, tip="tool")
