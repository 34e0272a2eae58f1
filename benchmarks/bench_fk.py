"""FK and Jacobian speed: armkit against the peers' fastest paths, side by side in one process.

Peers: pinocchio (``forwardKinematics`` + ``updateFramePlacement`` and ``computeFrameJacobian``
on the URDF armkit exports, which pinocchio reproduces to 1e-15), dynibo
(``forward_kinematics`` / ``jacobian``, Rust, if installed) and roboticstoolbox-python's
compiled ETS (``ets().eval`` / ``ets().jacob0``, C++).

Run: python benchmarks/bench_fk.py [--quick]
Prints median time per configuration, the ratio peer / armkit (> 1: armkit is faster), batch
throughput in configurations per second from 1e3 to 1e7, and the peak memory a batch
allocates against the size of its output.
"""

from __future__ import annotations

import argparse
import os
import tempfile
import tracemalloc
from pathlib import Path

import numpy as np
import pinocchio as pin
import roboticstoolbox as rtb
from _timing import median_seconds

import armkit
from armkit.export import urdf_from_robot

try:
    import dynibo
except ImportError:  # optional peer
    dynibo = None

MODELS = {"puma560": "Puma560", "ur5": "UR5", "panda": "Panda"}


def pinocchio_model(urdf: str):
    model = pin.buildModelFromXML(urdf)
    return model, model.createData(), model.getFrameId("tool")


def dynibo_calls(urdf: str, q: np.ndarray):
    """dynibo's Jacobian (flat, column-major, rows [w; v]) as armkit's 6xn ``[v; w]`` for the check,
    and the calls to time (its own return types: a Pose object, a flat array)."""
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "arm.urdf"
        path.write_text(urdf)
        robot = dynibo.Robot.from_urdf(str(path))
    tool = robot.link_id("tool")
    J = np.asarray(robot.jacobian(q, tool)).reshape((6, q.size), order="F")[[3, 4, 5, 0, 1, 2]]
    return J, (lambda: robot.forward_kinematics(q, tool)), (lambda: robot.jacobian(q, tool))


def one_configuration(name: str, repeat: int) -> list[tuple]:
    """Median time of one FK and one Jacobian: armkit, pinocchio, dynibo, rtb's ETS."""
    ours = armkit.load(name)
    ets = getattr(rtb.models.DH, MODELS[name])().ets()
    urdf = urdf_from_robot(ours)
    model, data, tool = pinocchio_model(urdf)
    q = ours.random_q(rng=0)
    world = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED

    def pin_fk():
        pin.forwardKinematics(model, data, q)
        pin.updateFramePlacement(model, data, tool)
        return data.oMf[tool]

    def pin_jacobian():
        return pin.computeFrameJacobian(model, data, q, tool, world)

    pin_fk()
    checks = [(ours.fk(q), [ets.eval(q), data.oMf[tool].homogeneous]),
              (ours.jacobian(q), [ets.jacob0(q), pin_jacobian()])]
    dyn_fk = dyn_jacobian = None
    if dynibo is not None:
        J, dyn_fk, dyn_jacobian = dynibo_calls(urdf, q)
        checks[1][1].append(J)
    for mine, theirs in checks:
        for other in theirs:
            assert np.allclose(mine, other, atol=1e-10), "the peers disagree: nothing to compare"

    def time(call) -> float:
        return median_seconds(call, repeat) if call is not None else np.nan

    return [
        (name, "fk, one", time(lambda: ours.fk(q)), time(pin_fk), time(dyn_fk), time(lambda: ets.eval(q))),
        (name, "jacobian, one", time(lambda: ours.jacobian(q)), time(pin_jacobian), time(dyn_jacobian),
         time(lambda: ets.jacob0(q))),
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
    print("one configuration, median [us]; ratios peer / armkit (> 1: armkit faster)")
    print(f"{'robot':8} {'case':14} {'armkit':>7} {'pin':>6} {'dynibo':>6} {'rtb':>6} "
          f"{'pin/armkit':>10} {'dynibo/armkit':>13} {'rtb/armkit':>10}")
    for name, label, t_ours, t_pin, t_dyn, t_rtb in rows:
        print(f"{name:8} {label:14} {t_ours * 1e6:7.2f} {t_pin * 1e6:6.2f} {t_dyn * 1e6:6.2f} "
              f"{t_rtb * 1e6:6.2f} {t_pin / t_ours:10.2f} {t_dyn / t_ours:13.2f} {t_rtb / t_ours:10.2f}")
    print(f"\nbatch FK, UR5, {os.cpu_count()} cores: million configurations per second, "
          f"peak memory / output size")
    print(f"{'N':>10} {'armkit':>8} {'1 thread':>9} {'rtb ETS':>8} {'rtb/armkit':>10} {'memory':>7}")
    for N, ours_all, ours_one, theirs, memory in batches(sizes):
        print(f"{N:>10} {ours_all / 1e6:8.2f} {ours_one / 1e6:9.2f} {theirs / 1e6:8.2f} "
              f"{theirs / ours_all:10.3f} {memory:7.2f}")


if __name__ == "__main__":
    main()
