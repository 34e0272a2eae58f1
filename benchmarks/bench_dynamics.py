"""Dynamics speed: armkit against pinocchio's fastest Python paths, side by side in one process.

pinocchio is given the same arm: the example-robot-data URDF reduced to the chain's joints
(``buildReducedModel``, as ``tests/test_dynamics_pinocchio.py``); its answers are checked
against armkit's before timing. One state per call: ``Robot.inverse_dynamics`` /
``mass_matrix`` / ``gravity_torques`` / ``forward_dynamics`` against ``pin.rnea`` / ``crba`` /
``computeGeneralizedGravity`` / ``aba`` (each one C++ call on preallocated ``Data``).
Batches: armkit's batch call against a Python loop of ``pin.rnea`` (pinocchio's Python API
has no batch inverse dynamics).

Run: python benchmarks/bench_dynamics.py [--quick]
Prints median time per call, the ratio pinocchio / armkit (> 1: armkit is faster), and batch
throughput in states per second.
"""

from __future__ import annotations

import argparse
import os
from importlib.metadata import distribution
from pathlib import Path

import numpy as np
import pinocchio as pin
from _timing import median_seconds

import armkit

ROBOTS = Path(distribution("example-robot-data").locate_file("cmeel.prefix/share/example-robot-data/robots"))
ARMS = {"ur5 (URDF)": ("ur_description/urdf/ur5_robot.urdf", "tool0"),
        "panda (URDF)": ("panda_description/urdf/panda.urdf", "panda_hand_tcp"),
        "xarm7 (URDF)": ("xarm_description/urdf/xarm7.urdf", None)}


def pair(label: str) -> tuple[armkit.Robot, pin.Model]:
    """armkit's robot and pinocchio's model of the same arm, joints in the same order."""
    file, tip = ARMS[label]
    robot = armkit.load(ROBOTS / file, tip=tip)
    full = pin.buildModelFromUrdf(str(ROBOTS / file))
    locked = [full.getJointId(name) for name in full.names[1:] if name not in robot.joint_names]
    return robot, pin.buildReducedModel(full, locked, pin.neutral(full))


def one_state(label: str, repeat: int) -> list[tuple]:
    robot, model = pair(label)
    data = model.createData()
    rng = np.random.default_rng(0)
    q = robot.random_q(rng=rng)
    qd, qdd, tau = rng.normal(size=(3, robot.n))
    M = pin.crba(model, data, q)
    checks = [(robot.inverse_dynamics(q, qd, qdd), pin.rnea(model, data, q, qd, qdd)),
              (robot.mass_matrix(q), np.triu(M) + np.triu(M, 1).T),
              (robot.gravity_torques(q), pin.computeGeneralizedGravity(model, data, q)),
              (robot.forward_dynamics(q, qd, tau), pin.aba(model, data, q, qd, tau))]
    for mine, theirs in checks:
        assert np.allclose(mine, theirs, rtol=1e-10, atol=1e-10), "pinocchio disagrees: nothing to compare"
    cases = [("inverse dynamics", lambda: robot.inverse_dynamics(q, qd, qdd),
              lambda: pin.rnea(model, data, q, qd, qdd)),
             ("mass matrix", lambda: robot.mass_matrix(q), lambda: pin.crba(model, data, q)),
             ("gravity", lambda: robot.gravity_torques(q),
              lambda: pin.computeGeneralizedGravity(model, data, q)),
             ("forward dynamics", lambda: robot.forward_dynamics(q, qd, tau),
              lambda: pin.aba(model, data, q, qd, tau))]
    return [(label, case, median_seconds(ours, repeat, 20), median_seconds(theirs, repeat, 20))
            for case, ours, theirs in cases]


def batches(sizes: list[int]) -> list[tuple]:
    """Inverse dynamics of N states of the UR5 URDF: armkit on every core and on one, pinocchio looped."""
    robot, model = pair("ur5 (URDF)")
    data = model.createData()
    rows = []
    for N in sizes:
        rng = np.random.default_rng(1)
        q = robot.random_q(N, rng=rng)
        qd, qdd = rng.normal(size=(2, N, robot.n))
        runs = max(3, int(2e6 // N))
        t_all = median_seconds(lambda q=q, qd=qd, qdd=qdd: robot.inverse_dynamics(q, qd, qdd), runs)
        t_one = median_seconds(lambda q=q, qd=qd, qdd=qdd: robot.inverse_dynamics(q, qd, qdd, threads=1),
                               runs)
        k = min(N, 20_000)  # pinocchio's loop timed on at most 20,000 states, per state

        def loop(k=k, q=q, qd=qd, qdd=qdd):
            for i in range(k):
                pin.rnea(model, data, q[i], qd[i], qdd[i])

        t_pin = median_seconds(loop, 3) / k * N
        rows.append((N, N / t_all, N / t_one, N / t_pin))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--quick", action="store_true", help="fewer repetitions, batches up to 1e5")
    args = parser.parse_args()
    repeat = 50 if args.quick else 500
    sizes = [1_000, 100_000] if args.quick else [1_000, 100_000, 1_000_000]
    print(f"{'robot':14} {'case':17} {'armkit [us]':>11} {'pinocchio [us]':>14} {'pin/armkit':>10}")
    for label in ARMS:
        for name, case, t_ours, t_pin in one_state(label, repeat):
            print(f"{name:14} {case:17} {t_ours * 1e6:11.2f} {t_pin * 1e6:14.2f} {t_pin / t_ours:10.2f}")
    print(f"\nbatch inverse dynamics, UR5 URDF, {os.cpu_count()} cores: million states per second")
    print(f"{'N':>10} {'armkit':>8} {'1 thread':>9} {'pin loop':>9} {'armkit/pin':>10}")
    for N, ours_all, ours_one, theirs in batches(sizes):
        print(f"{N:>10} {ours_all / 1e6:8.3f} {ours_one / 1e6:9.3f} {theirs / 1e6:9.3f} "
              f"{ours_all / theirs:10.1f}")


if __name__ == "__main__":
    main()
