"""URDF import on example-robot-data: load time per file and FK agreement with pinocchio.

Run: python benchmarks/bench_urdf.py
For every URDF of the package and every leaf link as the tip: armkit.load (median time) and
the largest difference of armkit's FK from pinocchio's on 5 random configurations.
"""

from __future__ import annotations

import time
import xml.etree.ElementTree as ET
from importlib.metadata import distribution
from pathlib import Path

import numpy as np
import pinocchio

import armkit
import armkit.urdf

ROBOTS = Path(distribution("example-robot-data").locate_file(
    "cmeel.prefix/share/example-robot-data/robots"))


def pinocchio_pose(model, data, robot: armkit.Robot, link: str, q: np.ndarray) -> np.ndarray:
    q_pin = pinocchio.neutral(model)
    for name, value in zip(robot.joint_names, q, strict=True):
        joint = model.joints[model.getJointId(name)]
        values = [value] if joint.nq == 1 else [np.cos(value), np.sin(value)]  # continuous: cos, sin
        q_pin[joint.idx_q:joint.idx_q + joint.nq] = values
    pinocchio.framesForwardKinematics(model, data, q_pin)
    return data.oMf[model.getFrameId(link)].homogeneous


def main() -> None:
    worst, chains, refused, load_times = 0.0, 0, 0, []
    for path in sorted(ROBOTS.rglob("*.urdf")):
        try:
            model = pinocchio.buildModelFromUrdf(str(path))
        except (RuntimeError, ValueError):
            continue
        data = model.createData()
        root = ET.parse(path).getroot()
        parents = {j.find("parent").get("link") for j in root.findall("joint")}
        for tip in [link.get("name") for link in root.findall("link") if link.get("name") not in parents]:
            started = time.perf_counter()
            try:
                robot = armkit.load(path, tip=tip)
            except armkit.RobotDefinitionError:
                refused += 1
                continue
            load_times.append(time.perf_counter() - started)
            chains += 1
            for q in robot.random_q(5, rng=chains):
                difference = robot.fk(q) - pinocchio_pose(model, data, robot, tip, q)
                worst = max(worst, float(np.abs(difference).max()))
    print(f"{chains} chains loaded ({refused} leaves refused: mimic joint on the way or no moving joint)")
    print(f"largest |armkit FK - pinocchio FK| entry: {worst:.2g}")
    print(f"armkit.load of one chain: median {np.median(load_times) * 1e3:.1f} ms, "
          f"max {np.max(load_times) * 1e3:.1f} ms")
    deep_urdf_order()


def deep_urdf_order(depth: int = 6000) -> None:
    """A 6000-link chain listed leaf first against root first: the cycle check is linear."""
    seconds = {}
    for leaf_first in (False, True):
        links = [f'<link name="l{i}"/>' for i in range(depth + 1)]
        joints = [f'<joint name="j{i}" type="{"continuous" if i == depth - 1 else "fixed"}">'
                  f'<parent link="l{i}"/><child link="l{i + 1}"/></joint>' for i in range(depth)]
        if leaf_first:
            links, joints = links[::-1], joints[::-1]
        text = '<robot name="deep">' + "".join(links) + "".join(joints) + "</robot>"
        runs = []
        for _ in range(3):
            started = time.perf_counter()
            armkit.urdf.robot_from_urdf(text)
            runs.append(time.perf_counter() - started)
        seconds[leaf_first] = min(runs)
    print(f"a {depth}-link URDF: root first {seconds[False] * 1e3:.0f} ms, leaf first "
          f"{seconds[True] * 1e3:.0f} ms (ratio {seconds[True] / seconds[False]:.2f}; quadratic before: 2.7)")


if __name__ == "__main__":
    main()
