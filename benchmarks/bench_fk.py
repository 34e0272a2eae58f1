"""FK and Jacobian speed: armkit against the peers' fastest paths, side by side in one process.

Peers: roboticstoolbox-python's compiled ETS (``ets().eval`` / ``ets().jacob0``, C++) and
pinocchio (``framesForwardKinematics`` / ``computeFrameJacobian`` on the URDF armkit
exports, which pinocchio reproduces to 1e-15).

Run: python benchmarks/bench_fk.py [--quick]
Prints median time per configuration, the ratio peer / armkit (> 1: armkit is faster),
batch throughput in configurations per second from 1e3 to 1e7, and the peak memory a
batch allocates against the size of its output.
"""

from __future__ import annotations

import argparse
import os
import tracemalloc

import numpy as np
import pinocchio as pin
import roboticstoolbox as rtb
from _timing import median_seconds

import armkit
from armkit.export import urdf_from_robot

MODELS = {"puma560": "Puma560", "ur5": "UR5", "panda": "Panda"}


def pinocchio_model(robot: armkit.Robot):
    model = pin.buildModelFromXML(urdf_from_robot(robot))
    return model, model.createData(), model.getFrameId("tool")


def one_configuration(name: str, repeat: int) -> list[tuple]:
    """Median time of one FK and one Jacobian: armkit, rtb's ETS, pinocchio."""
    ours = armkit.load(name)
    ets = getattr(rtb.models.DH, MODELS[name])().ets()
    model, data, tool = pinocchio_model(ours)
    q = ours.random_q(rng=0)
    world = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED

    def pin_fk():
        pin.framesForwardKinematics(model, data, q)
        return data.oMf[tool].homogeneous

    checks = [(ours.fk(q), ets.eval(q), pin_fk()),
              (ours.jacobian(q), ets.jacob0(q), pin.computeFrameJacobian(model, data, q, tool, world))]
    for mine, *theirs in checks:
        for other in theirs:
            assert np.allclose(mine, other, atol=1e-10), "the peers disagree: nothing to compare"
    return [
        (name, "fk, one", median_seconds(lambda: ours.fk(q), repeat),
         median_seconds(lambda: ets.eval(q), repeat), median_seconds(pin_fk, repeat)),
        (name, "jacobian, one", median_seconds(lambda: ours.jacobian(q), repeat),
         median_seconds(lambda: ets.jacob0(q), repeat),
         median_seconds(lambda: pin.computeFrameJacobian(model, data, q, tool, world), repeat)),
    ]


def batches(sizes: list[int]) -> list[tuple]:
    """Batch FK of the UR5 (6R): armkit on every core and on one, rtb's ETS batch ``eval``."""
    ours = armkit.load("ur5")
    ets = rtb.models.DH.UR5().ets()
    rows = []
    for N in sizes:
        Q = ours.random_q(N, rng=1)
        runs = max(3, int(2e6 // N))
        t_all = median_seconds(lambda Q=Q: ours.fk(Q), runs)
        t_one = median_seconds(lambda Q=Q: ours.fk(Q, threads=1), runs)
        t_rtb = median_seconds(lambda Q=Q: ets.eval(Q), max(1, runs // 3)) if N <= 1_000_000 else np.nan
        tracemalloc.start()
        T = ours.fk(Q)
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        rows.append((N, N / t_all, N / t_one, N / t_rtb, peak / T.nbytes))
        del T
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--quick", action="store_true", help="fewer repetitions, batches up to 1e6")
    args = parser.parse_args()
    repeat = 200 if args.quick else 2000
    sizes = [1_000, 100_000, 1_000_000] if args.quick else [1_000, 100_000, 1_000_000, 10_000_000]
    rows = [row for name in MODELS for row in one_configuration(name, repeat)]
    print(f"{'robot':8} {'case':14} {'armkit [us]':>11} {'rtb ETS [us]':>12} {'pinocchio [us]':>14} "
          f"{'rtb/armkit':>10} {'pin/armkit':>10}")
    for name, label, t_ours, t_rtb, t_pin in rows:
        print(f"{name:8} {label:14} {t_ours * 1e6:11.2f} {t_rtb * 1e6:12.2f} {t_pin * 1e6:14.2f} "
              f"{t_rtb / t_ours:10.2f} {t_pin / t_ours:10.2f}")
    print(f"\nbatch FK, UR5, {os.cpu_count()} cores: million configurations per second, "
          f"peak memory / output size")
    print(f"{'N':>10} {'armkit':>8} {'1 thread':>9} {'rtb ETS':>8} {'rtb/armkit':>10} {'memory':>7}")
    for N, ours_all, ours_one, theirs, memory in batches(sizes):
        print(f"{N:>10} {ours_all / 1e6:8.2f} {ours_one / 1e6:9.2f} {theirs / 1e6:8.2f} "
              f"{theirs / ours_all:10.3f} {memory:7.2f}")


if __name__ == "__main__":
    main()
