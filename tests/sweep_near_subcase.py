"""Sweep a built-in arm (UR5 by default) with one joint line moved against a many-seed numeric search,
near its wrist singularity.

For every size of the move, every joint, its axis turned or its point moved (two random
directions each), and every q5 of the poses (a random configuration with that q5, either
sign): the listing ``robot.ik(T, all_solutions=True, within_limits=False)`` must hold the
generating configuration and every solution armkit's Levenberg-Marquardt finds from 24
random seeds (the singular sweeps' search), and reproduce the pose to 1e-9. A search point
that Newton's steps do not take to the pose (CONFIRMED) is printed and not counted. Prints each
failing pose (with, per missed solution, how far the nearest listed one is and the accuracy
double precision allows there, 1e-16 / (sigma_min / sigma_max) of the Jacobian) and the count
per case and size::

    python tests/sweep_near_subcase.py                               # moves 1e-9 .. 1e-6, q5 1e-4 .. 1e-2
    python tests/sweep_near_subcase.py --moves 1e-5,1e-4,1e-3 --q5 1e-7,1e-6,1e-5 --seed 5
    python tests/sweep_near_subcase.py --arm stanford --moves 1e-9,1e-8,1e-7 --q5 1e-7,1e-6,1e-5
"""

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from helpers import joint_distance  # noqa: E402
from test_ik_general import line_moved  # noqa: E402
from test_ik_singular_sweeps import numeric_solutions  # noqa: E402

import armkit  # noqa: E402
from armkit.ik.structure import analyze_structure  # noqa: E402

#: A search point FK puts farther than this (times the arm's size) from the pose after Newton's
#: steps is not confirmed a solution: a real root reaches ~3e-16 in double, while points where the
#: search stopped on a nearly flat residual (a Jacobian 1e-11 .. 1e-12 singular) stay at 2e-13 ..
#: 4e-13; the four such points of the seed-11 sweep were checked in 60-digit arithmetic: Newton
#: takes each onto the root of a listed solution 0.007 .. 0.07 away, the residual falling
#: monotonically between them (no root at the point).
CONFIRMED = 1e-14


def _how_far(robot: armkit.Robot, listed: np.ndarray, missed: np.ndarray) -> str:
    """How far the listing is from a missed solution, against the accuracy double precision
    allows there along the weakest direction: 1e-16 / (sigma_min / sigma_max) of the Jacobian."""
    sigma = np.linalg.svd(robot.jacobian(missed), compute_uv=False)
    accuracy = 1e-16 * sigma[0] / sigma[-1]
    return f"nearest listed {joint_distance(robot.chain, listed, missed).min():.2g} rad or m off, " \
        f"accuracy there {accuracy:.2g}"


def _residual(robot: armkit.Robot, T: np.ndarray, q: np.ndarray) -> float:
    """How far FK puts ``q`` from ``T``, over the arm's size (1 + largest |coordinate| at q = 0)."""
    size = 1 + np.abs(robot.fk(np.zeros(robot.n))[:3, 3]).max()
    return float(np.abs(robot.fk(q) - T).max() / size)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--moves", default="1e-9,1e-8,7e-8,1e-7,1e-6", help="sizes of the move [rad or m]")
    parser.add_argument("--q5", default="1e-4,1e-3,0.0077,1e-2", help="q5 of the poses [rad]")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--arm", default="ur5", help="the built-in arm whose lines are moved")
    args = parser.parse_args()
    rng = np.random.default_rng(args.seed)
    failed, total, unconfirmed, per_case = 0, 0, 0, {}
    for move in [float(m) for m in args.moves.split(",")]:
        for joint in range(6):
            for turn in (True, False):
                for _ in range(2):
                    robot = line_moved(args.arm, joint, turn, rng.normal(size=3), move)
                    case = analyze_structure(robot).case
                    for q5 in [float(v) for v in args.q5.split(",")]:
                        q0 = rng.uniform(-np.pi, np.pi, 6)
                        q0[4] = q5 * rng.choice([-1.0, 1.0])
                        T = robot.fk(q0)
                        total += 1
                        line = "axis" if turn else "point"
                        where = f"move {move:g}, joint {joint + 1} {line}, case {case}, q5 {q5:g}"
                        try:
                            listed = robot.ik(T, all_solutions=True, within_limits=False)
                        except armkit.ArmkitError as error:
                            print(f"{where}: {type(error).__name__}: {error}", flush=True)
                            failed += 1
                            per_case[case, move] = per_case.get((case, move), 0) + 1
                            continue
                        assert np.abs(robot.fk(listed) - T).max() <= 1e-9, where
                        found = [q0, *numeric_solutions(robot, T, rng)]
                        far = [s for s in found if joint_distance(robot.chain, listed, s).min() > 1e-6]
                        missed = [s for s in far if _residual(robot, T, s) <= CONFIRMED]
                        for s in far:
                            if _residual(robot, T, s) > CONFIRMED:
                                unconfirmed += 1
                                print(f"{where}: search point not confirmed (FK off by "
                                      f"{_residual(robot, T, s):.2g} x size after Newton; "
                                      f"{_how_far(robot, listed, s)})", flush=True)
                        if missed:
                            print(f"{where}: {len(listed)} listed, {len(missed)} not ("
                                  + "; ".join(_how_far(robot, listed, s) for s in missed) + ")", flush=True)
                            failed += 1
                            per_case[case, move] = per_case.get((case, move), 0) + 1
    print(f"{failed} of {total} poses miss a solution; per (case, move): {per_case}; "
          f"{unconfirmed} search points not confirmed solutions (not counted)")


if __name__ == "__main__":
    main()
