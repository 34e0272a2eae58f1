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
3. What users call for automatic timing: ``plan_trajectory(robot, waypoints)`` (TOPP-RA in the
   core along the minimum-jerk path, smoothed, scaled onto the limits) at 4, 100 and 1000
   random PROBOT Anno waypoints, against toppra's usual call (its cubic spline through the
   same waypoints, velocity and acceleration constraints, ``compute_trajectory``) and ruckig
   (one rest-to-rest ``calculate`` per segment, jerk limit 10x amax); and the durations of
   armkit and toppra on armkit's own path (the same path: ratio armkit / toppra).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import roboticstoolbox as rtb
import toppra
import toppra.algorithm
import toppra.constraint
from _timing import median_seconds
from ruckig import InputParameter, Result, Ruckig, Trajectory

import armkit
from armkit.trajectory import JointTrajectory, auto_time, min_jerk, plan_trajectory, quintic, read_waypoints
from armkit.trajectory.min_jerk import min_jerk_boundary_values
from armkit.trajectory.topp import geometric_path

DATA = Path(__file__).parent.parent / "examples" / "data"
ROBOT = armkit.load("probot-anno")                # report 000's limits, from its robot file (whole degrees)
VMAX, AMAX = ROBOT.max_velocity, ROBOT.max_acceleration   # rad/s, rad/s^2


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
    for name, traj in (("armkit plan_trajectory (time-optimal, smoothed)", plan_trajectory(ROBOT, W)),
                       ("armkit min-jerk durations fitted (auto_time)", auto_time(W, VMAX, AMAX)),
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
    if max(max(row[3], row[4]) for row in rows[:3]) > 1.0:
        sys.exit("armkit exceeded a limit")


class ArmkitPath(toppra.interpolator.AbstractGeometricPath):
    """armkit's geometric path (a JointTrajectory in its own time s) as toppra reads a path."""

    def __init__(self, path: JointTrajectory) -> None:
        self.path = path

    def __call__(self, s, order=0):
        s = np.asarray(s, dtype=float)
        values = self.path.at_time(np.atleast_1d(s))[order]
        return values if s.ndim else values[0]

    @property
    def dof(self) -> int:
        return self.path.n

    @property
    def path_interval(self) -> np.ndarray:
        return np.array([0.0, self.path.duration])

    @property
    def waypoints(self):
        return self.path.waypoint_times, self.path.waypoints


def toppra_trajectory(path, vmax: np.ndarray, amax: np.ndarray):
    """toppra's time-optimal trajectory along ``path`` under velocity and acceleration limits."""
    constraints = [toppra.constraint.JointVelocityConstraint(np.stack([-vmax, vmax], axis=1)),
                   toppra.constraint.JointAccelerationConstraint(np.stack([-amax, amax], axis=1))]
    instance = toppra.algorithm.TOPPRA(constraints, path, parametrizer="ParametrizeConstAccel")
    return instance.compute_trajectory()


def automatic_timing(quick: bool) -> None:
    robot, vmax, amax = ROBOT, VMAX, AMAX
    toppra.setup_logging("WARNING")
    print("\n3. Automatic timing, PROBOT Anno limits, random waypoints in the middle half of each joint's "
          "range (median wall time; ratio = peer / armkit)")
    header = (f"{'waypoints':>9}  {'armkit plan_trajectory':>23}{'toppra':>13}{'ratio':>8}{'ruckig':>13}"
              f"{'ratio':>8}  {'duration armkit / toppra, same path':>36}")
    print(header)
    print("-" * len(header))
    rng = np.random.default_rng(1)
    for M in (4, 100, 1000):
        low, high = robot.limits[:, 0], robot.limits[:, 1]
        W = rng.uniform(low + 0.25 * (high - low), high - 0.25 * (high - low), (M, 6))
        repeat = 3 if quick or M == 1000 else 20
        ours = median_seconds(lambda W=W: plan_trajectory(robot, W), repeat)
        spline = toppra.SplineInterpolator(np.linspace(0, 1, M), W)
        theirs = median_seconds(lambda spline=spline: toppra_trajectory(spline, vmax, amax), repeat)
        ruck = median_seconds(lambda W=W: ruckig_segments(W, vmax, amax, 10 * amax), repeat)
        traj = plan_trajectory(robot, W)
        same_path = toppra_trajectory(ArmkitPath(geometric_path(W, vmax, amax)), vmax, amax)
        over = max((traj.peak_velocity / vmax).max(), (traj.peak_acceleration / amax).max())
        ratio = traj.duration / same_path.duration
        print(f"{M:>9}  {fmt(ours):>23}{fmt(theirs):>13}{theirs / ours:>8.2f}{fmt(ruck):>13}"
              f"{ruck / ours:>8.2f}  {traj.duration:10.3f} s / {same_path.duration:10.3f} s = {ratio:.4f}"
              f"  (largest exact |qd|/vmax, |qdd|/amax: {over:.6f})")
        if over > 1.0:
            sys.exit("armkit exceeded a limit")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="few repetitions (CI smoke run)")
    args = parser.parse_args()
    solve_times(args.quick)
    seed_comparison()
    automatic_timing(args.quick)


if __name__ == "__main__":
    main()
