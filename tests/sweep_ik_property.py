"""Sweep the IK property check of ``test_ik_property.py`` over a contiguous range of seeds.

``make fuzz`` draws hypothesis's seeds; this runs every seed of a range, for every
six-joint class, on all cores, and prints each failing arm (class, case, seed, message)
and the count::

    python tests/sweep_ik_property.py 10000 14000             # degenerate arms
    python tests/sweep_ik_property.py 0 4000 --generic        # generic arms, with the EAIK comparison

A failing arm is re-run alone by ``check_six_joint_arm(kind, case, seed, degenerate)``.
"""

import argparse
import os
import sys
import warnings
from multiprocessing import Pool

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from test_ik_property import SIX_JOINT_CLASSES, check_six_joint_arm  # noqa: E402


def _run(job: tuple) -> tuple | None:
    kind, case, seed, degenerate = job
    warnings.filterwarnings("ignore")
    try:
        check_six_joint_arm(kind, case, seed, degenerate=degenerate, drawn=True)
    except AssertionError as error:
        return kind, case, seed, str(error).splitlines()[0][:200] if str(error) else "assertion failed"
    return None


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("start", type=int, help="first seed")
    parser.add_argument("stop", type=int, help="one past the last seed")
    parser.add_argument("--generic", action="store_true", help="generic arms (default: degenerate)")
    args = parser.parse_args()
    jobs = [(kind, case, seed, not args.generic) for seed in range(args.start, args.stop)
            for kind, case in SIX_JOINT_CLASSES]
    with Pool(os.cpu_count()) as pool:
        failures = [f for f in pool.imap_unordered(_run, jobs, chunksize=8) if f]
    for failure in sorted(failures, key=lambda f: f[2]):
        print(*failure, sep="  ")
    print(f"{len(failures)} failing of {len(jobs)} arms ({'generic' if args.generic else 'degenerate'})")


if __name__ == "__main__":
    main()
