"""URDFs nobody here wrote (example-robot-data): load, FK against pinocchio, closed forms, IK.

The package installs its robots as data files (``cmeel.prefix/share/example-robot-data/
robots/...``, no Python module); they are found through the installed distribution.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from importlib.metadata import PackageNotFoundError
from pathlib import Path

import numpy as np
import pytest
from conftest import assert_transform_close
from helpers import ARMS, example_robot_data_folder

import armkit
from armkit.errors import RobotDefinitionError

pinocchio = pytest.importorskip("pinocchio")
try:
    ROBOTS = example_robot_data_folder()
except PackageNotFoundError:  # pragma: no cover - the test extra installs it
    pytest.skip("example-robot-data is not installed", allow_module_level=True)
URDFS = sorted(ROBOTS.rglob("*.urdf"))



def leaves(path: Path) -> list[str]:
    root = ET.parse(path).getroot()
    parents = {j.find("parent").get("link") for j in root.findall("joint")}
    return [link.get("name") for link in root.findall("link") if link.get("name") not in parents]


class Pinocchio:
    """pinocchio's model of a URDF file, posed at armkit's joint values (matched by name)."""

    def __init__(self, path: Path) -> None:
        self.model = pinocchio.buildModelFromUrdf(str(path))
        self.data = self.model.createData()

    def poses(self, robot: armkit.Robot, link: str, q: np.ndarray, base: str | None = None) -> np.ndarray:
        frame = self.model.getFrameId(link)
        out = []
        for q_k in np.atleast_2d(q):
            q_pin = pinocchio.neutral(self.model)
            for name, value in zip(robot.joint_names, q_k, strict=True):
                joint = self.model.joints[self.model.getJointId(name)]
                q_pin[joint.idx_q:joint.idx_q + joint.nq] = (
                    [value] if joint.nq == 1 else [np.cos(value), np.sin(value)])  # continuous: cos, sin
            pinocchio.framesForwardKinematics(self.model, self.data, q_pin)
            T = self.data.oMf[frame].homogeneous
            if base is not None:
                T = np.linalg.inv(self.data.oMf[self.model.getFrameId(base)].homogeneous) @ T
            out.append(T)
        return np.array(out)


@pytest.mark.parametrize("path", URDFS, ids=[str(p.relative_to(ROBOTS)) for p in URDFS])
def test_every_file_and_every_leaf_loads_with_pinocchios_fk_or_says_why_not(path):
    """Every example-robot-data URDF, every leaf link as the tip: loads, or one clear error."""
    try:
        armkit.load(path)
    except RobotDefinitionError as exc:
        assert str(exc).startswith(str(path)) and "\n" not in str(exc)
    try:
        reference = Pinocchio(path)
    except (RuntimeError, ValueError):  # pinocchio refuses it too (ur3.urdf: an empty <robot>)
        with pytest.raises(RobotDefinitionError, match="no <link> elements"):
            armkit.load(path)
        return
    loaded = 0
    for tip in leaves(path):
        try:
            robot = armkit.load(path, tip=tip)
        except RobotDefinitionError as exc:  # a mimic joint on the way, or no moving joint
            assert "mimic joint" in str(exc) or "no moving joint" in str(exc), str(exc)
            continue
        loaded += 1
        q = robot.random_q(3, rng=loaded)
        assert_transform_close(robot.fk(q), reference.poses(robot, tip, q), 1e-12, 1e-12)
    assert loaded or reference.model.nq == 0  # only files without moving joints load no chain


@pytest.mark.parametrize(("file", "base", "tip", "kind"), ARMS,
                         ids=[f"{a[0].split('/')[-1]}:{a[2]}" for a in ARMS])
def test_serial_arms_fk_closed_form_and_ik(file, base, tip, kind):
    path = ROBOTS / file
    robot = armkit.load(path, base=base, tip=tip)
    q = robot.random_q(200, rng=11)
    expected = Pinocchio(path).poses(robot, robot.urdf.tip, q, base=base)
    assert_transform_close(robot.fk(q), expected, 1e-12, 1e-12)
    assert armkit.analyze_structure(robot.chain).kind == kind
    for q_k in q[:8]:
        T = robot.fk(q_k)
        if kind != "none":
            solutions = robot.ik(T, all_solutions=True, within_limits=False)
            assert_transform_close(robot.fk(solutions), np.broadcast_to(T, solutions.shape[:1] + (4, 4)),
                                   1e-9, 1e-9)
            gap = np.where(robot.chain.prismatic, solutions - q_k, np.angle(np.exp(1j * (solutions - q_k))))
            assert np.abs(gap).max(axis=1).min() < 1e-6  # the generating q is among them (up to whole turns)
        else:  # numeric: from a seed 0.2 rad away
            found = robot.ik(T, near=q_k + 0.2 * np.sign(robot.random_q(rng=1)))
            assert_transform_close(robot.fk(found), T, 1e-9, 1e-9)
            assert robot.within_limits(found)


def test_ur5_urdf_is_the_dh_ur5_up_to_base_and_tool_frames():
    """The same arm from two sources: the same joint geometry, so the same IK solutions count
    (each once: the limits differ, the URDF's elbow spans one turn, so whole-turn copies do too)."""
    urdf = armkit.load(ROBOTS / "ur_description/urdf/ur5_robot.urdf", tip="tool0")
    dh = armkit.load("ur5")
    q = dh.random_q(rng=4)
    assert len(urdf.ik(urdf.fk(q), all_solutions=True, within_limits=False, turn_copies=False)) == len(
        dh.ik(dh.fk(q), all_solutions=True, within_limits=False, turn_copies=False)) == 8
    assert len(urdf.chain.spans_turns) == 5 and len(dh.chain.spans_turns) == 6


def test_panda_with_a_wrist_joint_locked_is_a_spherical_base_6r_arm():
    panda = armkit.load(ROBOTS / "panda_description/urdf/panda.urdf", tip="panda_hand_tcp")
    locked = panda.lock({"panda_joint7": 0.4})
    assert armkit.analyze_structure(locked.chain).kind == "spherical-base"
    q = locked.random_q(rng=2)
    solutions = locked.ik(locked.fk(q), all_solutions=True, within_limits=False)
    full = locked.full_q(solutions)
    target = np.broadcast_to(locked.fk(q), full.shape[:1] + (4, 4))
    assert_transform_close(panda.fk(full), target, 1e-9, 1e-9)
    assert np.all(full[:, 6] == 0.4)
