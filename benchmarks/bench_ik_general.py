"""Every IK solution of general 6R arms: armkit against roboticstoolbox-python 1.5's
Raghavan-Roth solver (``General6RIK``) and a many-seed numeric search.

Run: python benchmarks/bench_ik_general.py [--quick] [--rtb] [--ssik]

For each of a few random general 6R arms (standard DH, every length and twist non-zero):
- preparation: a new arm from its DH table to its first listing (armkit: ``Robot.from_dh``
  then ``robot.ik(T, all_solutions=True)``, modules already imported; rtb:
  ``General6RIK(robot)``, which derives the equations symbolically and generates Python code);
- one pose at a time: median time of ``robot.ik(T, all_solutions=True, within_limits=False)``
  and of rtb's ``solve(T, joint_limits=False)``; armkit's batched ``ik_solutions`` per pose;
- solutions per pose that reproduce the pose to 1e-6 (armkit's FK, which pinocchio checks),
  and on a few poses the distinct solutions SciPy's Levenberg-Marquardt finds from 40 seeds
  (the ground truth for "every solution"): how many of those each solver missed;
- armkit alone on the same table with joint 3 prismatic (a 5R1P arm; no peer here lists
  every solution of one).
``--rtb`` adds rtb's solver on every arm and ``--ssik`` the ssik package (PyPI) on the
first arm; each prepares an arm for minutes (rtb: 523 s for one arm on a loaded 2-core
machine), so both are off by default. Solutions per pose are counted on the same poses
for every solver. Ratios are peer time / armkit time (> 1: armkit faster).
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np
import roboticstoolbox as rtb
from roboticstoolbox.robot.symbolic_ik_rr import General6RIK
from scipy.optimize import least_squares

import armkit
from armkit.chain import DHRow

TOLERANCE = 1e-6


def general_rows(rng: np.random.Generator) -> list[DHRow]:
    return [DHRow(rng.uniform(0.2, 2.9) * rng.choice([-1, 1]), rng.uniform(0.05, 0.5), rng.uniform(-0.4, 0.4),
                  0.0) for _ in range(6)]


def rtb_robot(rows: list[DHRow]) -> rtb.DHRobot:
    return rtb.DHRobot([rtb.RevoluteDH(d=r.d, a=r.a, alpha=r.alpha) for r in rows])


def reproducing(robot: armkit.Robot, q: np.ndarray, T: np.ndarray) -> np.ndarray:
    q = np.atleast_2d(np.asarray(q, dtype=float)).reshape(-1, 6)
    if len(q) == 0:
        return q
    F = robot.fk(q)
    good = (np.abs(F - T).max(axis=(1, 2)) <= TOLERANCE)
    return q[good]


def gap(robot: armkit.Robot, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Largest joint difference (angles modulo 2 pi, slides as they are), over the last axis."""
    d = a - b
    return np.abs(np.where(robot.chain.prismatic, d, np.angle(np.exp(1j * d)))).max(axis=-1)


def search(robot: armkit.Robot, T: np.ndarray, rng: np.random.Generator, seeds: int = 40) -> list[np.ndarray]:
    def residual(q):
        F = robot.fk(q)
        return (F[:3] - T[:3]).ravel()

    found: list[np.ndarray] = []
    for _ in range(seeds):
        fit = least_squares(residual, rng.uniform(-np.pi, np.pi, 6), method="lm", xtol=1e-15, ftol=1e-15,
                            gtol=1e-15)
        q = np.where(robot.chain.prismatic, fit.x, np.angle(np.exp(1j * fit.x)))
        if np.abs(fit.fun).max() < 1e-10 and all(gap(robot, q, f) > 1e-6 for f in found):
            found.append(q)
    return found


def missed(robot: armkit.Robot, listed: np.ndarray, truth: list[np.ndarray]) -> int:
    if len(listed) == 0:
        return len(truth)
    return sum(gap(robot, listed, q).min() > 1e-5 for q in truth)


def median_us(times: list[float]) -> float:
    return 1e6 * float(np.median(times))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="one arm, fewer poses")
    parser.add_argument("--rtb", action="store_true", help="add rtb's General6RIK (minutes of preparation)")
    parser.add_argument("--ssik", action="store_true", help="add ssik (minutes of preparation per arm)")
    args = parser.parse_args()
    arms, poses, checked = (1, 30, 3) if args.quick else (3, 200, 10)
    compared = max(checked, poses // 4)  # poses every solver is timed and counted on
    rng = np.random.default_rng(2026)
    # the modules' first import is paid once per process, not per arm: a throwaway arm first
    warm = armkit.Robot.from_dh(general_rows(np.random.default_rng(1)), "standard")
    warm.ik(warm.fk(np.zeros(6)), all_solutions=True, within_limits=False)
    print(f"{'arm':>4} {'solver':<22} {'prepare':>10} {'one pose':>10} {'batched':>9} {'sol/pose':>8} "
          f"{'missed':>7} {'ratio':>6}")
    for arm in range(arms):
        rows = general_rows(rng)
        q = rng.uniform(-np.pi, np.pi, (poses, 6))
        robot, T, ours, truths, total = bench_armkit(arm, "armkit", rows, q, rng, checked, compared)
        # the same table with joint 3 prismatic (5R1P; no peer here lists those)
        slid = [DHRow(r.alpha, r.a, r.d, r.theta, "prismatic" if j == 2 else "revolute")
                for j, r in enumerate(rows)]
        bench_armkit(arm, "armkit, joint 3 slides", slid, q, rng, checked, compared)
        if args.ssik and arm == 0:
            bench_ssik(rows, robot, T[:compared], median_us(ours))
        if not args.rtb:
            continue
        peer = rtb_robot(rows)
        start = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            solver = General6RIK(peer)
            solver.solve(T[0], joint_limits=False)
        prepare_rtb = time.perf_counter() - start
        theirs, counts_rtb, miss_rtb = [], [], 0
        for i, Ti in enumerate(T[:compared]):
            t0 = time.perf_counter()
            sol = solver.solve(Ti, joint_limits=False)
            theirs.append(time.perf_counter() - t0)
            good = reproducing(robot, np.asarray(sol.q), Ti)
            counts_rtb.append(len(good))
            if i < checked:
                miss_rtb += missed(robot, good, truths[i])
        print(f"{arm:>4} {'rtb General6RIK':<22} {1e3 * prepare_rtb:>8.1f}ms {median_us(theirs):>8.1f}us "
              f"{'-':>9} {np.mean(counts_rtb):>8.2f} {miss_rtb:>3}/{total:<3} "
              f"{median_us(theirs) / median_us(ours):>6.1f}")


def bench_armkit(arm: int, label: str, rows: list[DHRow], q: np.ndarray, rng: np.random.Generator,
                 checked: int, compared: int
                 ) -> tuple[armkit.Robot, np.ndarray, list[float], list[list[np.ndarray]], int]:
    """armkit on the arm of ``rows`` at the poses of ``q``: prints its row; returns the robot,
    the poses, the one-pose times, the searches' solutions and their number."""
    start = time.perf_counter()
    robot = armkit.Robot.from_dh(rows, "standard")
    T = robot.fk(q)
    robot.ik(T[0], all_solutions=True, within_limits=False)
    prepare = time.perf_counter() - start
    ours, counts = [], []
    for Ti in T:
        t0 = time.perf_counter()
        listed = robot.ik(Ti, all_solutions=True, within_limits=False)
        ours.append(time.perf_counter() - t0)
        counts.append(len(reproducing(robot, listed, Ti)))
    t0 = time.perf_counter()
    armkit.ik_solutions(robot, T, turn_copies=False, threads=1)
    batched = (time.perf_counter() - t0) / len(q)
    truths = [search(robot, T[i], rng) for i in range(checked)]
    miss = sum(missed(robot, robot.ik(T[i], all_solutions=True, within_limits=False), truths[i])
               for i in range(checked))
    total = sum(len(t) for t in truths)
    print(f"{arm:>4} {label:<22} {1e3 * prepare:>8.1f}ms {median_us(ours):>8.1f}us {1e6 * batched:>7.1f}us "
          f"{np.mean(counts[:compared]):>8.2f} {miss:>3}/{total:<3} {'1.0':>6}")
    return robot, T, ours, truths, total


def bench_ssik(rows: list[DHRow], robot: armkit.Robot, T: np.ndarray, ours_us: float) -> None:
    """ssik on the same arm (its API: a manipulator from DH parameters, then solve)."""
    import ssik

    start = time.perf_counter()
    manipulator = ssik.Manipulator.from_dh([r.alpha for r in rows], [r.a for r in rows], [r.d for r in rows])
    manipulator.solve(T[0], respect_limits=False)
    prepare = time.perf_counter() - start
    times, counts = [], []
    for Ti in T:
        t0 = time.perf_counter()
        q = np.array([s.q for s in manipulator.solve(Ti, respect_limits=False)])
        times.append(time.perf_counter() - t0)
        counts.append(len(reproducing(robot, q, Ti)))
    print(f"{0:>4} {'ssik':<22} {1e3 * prepare:>8.1f}ms {median_us(times):>8.1f}us {'-':>9} "
          f"{np.mean(counts):>8.2f} {'-':>7} {median_us(times) / ours_us:>6.1f}")


if __name__ == "__main__":
    main()
