"""Trajectory benchmarks: armkit against roboticstoolbox-python and ruckig, side by side in one process.

Run: python benchmarks/bench_trajectory.py [--quick]

1. Solve time of the multi-waypoint minimum-jerk spline (6 joints; 4, 50, 1000 waypoints,
   1 s segments), and the peers doing comparable work: rtb ``mstraj`` (linear segments
   with polynomial blends, given segment times, sampled at 100 Hz: compared with armkit's
   solve *plus* sampling at 100 Hz), ruckig (no intermediate waypoints in its free
   edition: one time-optimal rest-to-rest ``calculate`` per segment), and, for two
   waypoints, rtb ``jtraj`` against armkit's ``quintic`` (the same quintic, 100 samples).
   Ratio = peer / armkit (> 1: armkit is faster).
2. The seed's four waypoints (report 000) with the PROBOT Anno limits: total duration,
   peak jerk and the largest velocity / acceleration ratios of armkit's auto-time,
   armkit with the report's 10 s segments, ruckig (stopping at each waypoint, jerk limit
   10x the acceleration limit) and rtb ``mstraj`` given the velocity limits (tacc = 1 s).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import roboticstoolbox as rtb
from _timing import median_seconds
from ruckig import InputParameter, Result, Ruckig, Trajectory

from armkit.trajectory import auto_time, min_jerk, quintic, read_waypoints
from armkit.trajectory.min_jerk import min_jerk_boundary_values

DATA = Path(__file__).parent.parent / "examples" / "data"
VMAX = np.array([0.7854, 0.6981, 0.7854, 0.9599, 0.9599, 0.9599])   # report 000, rad/s
AMAX = np.array([0.3491, 0.2618, 0.3491, 0.4363, 0.4363, 0.4363])   # rad/s^2


def ruckig_segments(waypoints: np.ndarray, vmax, amax, jmax) -> list[Trajectory]:
    """One time-optimal rest-to-rest ruckig trajectory per segment."""
    n = waypoints.shape[1]
    otg = Ruckig(n)
    out = []
    for a, b in zip(waypoints[:-1], waypoints[1:], strict=True):
        inp = InputParameter(n)
        inp.current_position, inp.target_position = a.tolist(), b.tolist()
        inp.max_velocity, inp.max_acceleration, inp.max_jerk = list(vmax), list(amax), list(jmax)
        trajectory = Trajectory(n)
        if otg.calculate(inp, trajectory) not in (Result.Working, Result.Finished):
            raise RuntimeError("ruckig failed")
        out.append(trajectory)
    return out


def fmt(seconds: float) -> str:
    return f"{seconds * 1e3:9.3f} ms" if seconds >= 1e-3 else f"{seconds * 1e6:9.1f} us"


def solve_times(quick: bool) -> None:
    print("1. Minimum-jerk solve, 6 joints, 1 s segments (median wall time)")
    header = f"{'waypoints':>9}  {'case':<44}{'armkit':>13}{'peer':>13}{'peer/armkit':>13}"
    print(header)
    print("-" * len(header))
    rng = np.random.default_rng(0)
    zero = (np.zeros(6), np.zeros(6))
    big = 10 * np.ones(6)
    for M in (4, 50, 1000):
        W = rng.uniform(-1, 1, (M, 6))
        D = np.ones(M - 1)
        repeat = 5 if quick else (200 if M < 1000 else 30)
        solve = median_seconds(lambda W=W, D=D: min_jerk_boundary_values(W, D, zero, zero), repeat)
        full = median_seconds(lambda W=W, D=D: min_jerk(W, D), repeat)
        print(f"{M:>9}  {'armkit banded KKT solve only':<44}{fmt(solve):>13}")
        print(f"{M:>9}  {'armkit min_jerk (solve + JointTrajectory)':<44}{fmt(full):>13}")
        peer_repeat = 3 if quick or M == 1000 else 20
        ours = median_seconds(lambda W=W, D=D: min_jerk(W, D).sample(100.0), repeat)
        mstraj = median_seconds(lambda W=W, D=D: rtb.mstraj(W[1:], 0.01, 0.2, tsegment=D, q0=W[0]),
                                peer_repeat)
        print(f"{M:>9}  {'min_jerk + sample 100 Hz  vs  rtb mstraj':<44}{fmt(ours):>13}{fmt(mstraj):>13}"
              f"{mstraj / ours:>13.1f}")
        ruck = median_seconds(lambda W=W: ruckig_segments(W, big, big, 10 * big), peer_repeat)
        print(f"{M:>9}  {'min_jerk  vs  ruckig calculate per segment':<44}{fmt(full):>13}{fmt(ruck):>13}"
              f"{ruck / full:>13.1f}")
    q0, q1 = rng.uniform(-1, 1, (2, 6))
    t = np.linspace(0, 1, 100)
    ours = median_seconds(lambda: quintic(q0, q1, 1.0).at_time(t), 50 if quick else 2000)
    theirs = median_seconds(lambda: rtb.jtraj(q0, q1, t), 50 if quick else 2000)
    print(f"{2:>9}  {'quintic + 100 samples  vs  rtb jtraj':<44}{fmt(ours):>13}{fmt(theirs):>13}"
          f"{theirs / ours:>13.1f}")


def seed_comparison() -> None:
    W = read_waypoints(DATA / "probot_seed_joints.csv", 6)
    print("\n2. Report 000's four waypoints, PROBOT Anno limits (ratios: peak / limit, > 1 exceeds)")
    header = (f"{'method':<46}{'duration':>10}{'peak jerk':>11}{'max v/vmax':>12}{'max a/amax':>12}"
              f"  through waypoints")
    print(header)
    print("-" * len(header))
    rows = []
    for name, traj in (("armkit auto-time (min-jerk, exact peaks)", auto_time(W, VMAX, AMAX)),
                       ("armkit, the report's 10 s segments", min_jerk(W, [10, 10, 10]))):
        rows.append((name, traj.duration, traj.peak_jerk.max(), (traj.peak_velocity / VMAX).max(),
                     (traj.peak_acceleration / AMAX).max(), "yes, not stopping"))
    segments = ruckig_segments(W, VMAX, AMAX, 10 * AMAX)
    dt = 1e-3
    v, a, j = [], [], []
    for segment in segments:
        times = np.arange(0, segment.duration, dt)
        samples = [segment.at_time(float(t)) for t in times]
        acc = np.array([s[2] for s in samples])
        v.append(np.array([s[1] for s in samples]))
        a.append(acc)
        j.append(np.diff(acc, axis=0) / dt)
    v, a, j = (np.concatenate(x) for x in (v, a, j))
    rows.append(("ruckig, stop at each waypoint, jmax = 10 amax", sum(s.duration for s in segments),
                 np.abs(j).max(), (np.abs(v).max(0) / VMAX).max(), (np.abs(a).max(0) / AMAX).max(),
                 "yes, stopping"))
    traj = rtb.mstraj(W[1:], dt, 1.0, qdmax=VMAX, q0=W[0])
    qd = np.gradient(traj.q, dt, axis=0)
    qdd = np.gradient(qd, dt, axis=0)
    qddd = np.gradient(qdd, dt, axis=0)
    rows.append(("rtb mstraj, qdmax = vmax, tacc = 1 s", traj.t[-1], np.abs(qddd).max(),
                 (np.abs(qd).max(0) / VMAX).max(), (np.abs(qdd).max(0) / AMAX).max(),
                 "no (blends cut corners)"))
    for name, duration, jerk, rv, ra, through in rows:
        print(f"{name:<46}{duration:>9.3f}s{jerk:>11.3f}{rv:>12.3f}{ra:>12.3f}  {through}")
    print("(peak jerk in rad/s^3: armkit exact; ruckig and rtb from 1 kHz finite differences)")
    if max(rows[0][3], rows[0][4], rows[1][3], rows[1][4]) > 1.0:
        sys.exit("armkit exceeded a limit")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="few repetitions (CI smoke run)")
    args = parser.parse_args()
    solve_times(args.quick)
    seed_comparison()


if __name__ == "__main__":
    main()
