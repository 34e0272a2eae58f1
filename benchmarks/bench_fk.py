"""FK and Jacobian speed: armkit against roboticstoolbox-python, side by side in one process.

Run: python benchmarks/bench_fk.py [--quick]
Prints median time per configuration and the ratio peer / armkit (> 1: armkit is faster).
"""

from __future__ import annotations

import argparse

import roboticstoolbox as rtb
from _timing import median_seconds

import armkit

MODELS = {"puma560": "Puma560", "ur5": "UR5", "panda": "Panda"}


def measure(ours: armkit.Robot, theirs, name: str, repeat: int, batch: int) -> list[tuple]:
    """Median time per configuration of armkit and rtb for one robot."""
    q = ours.random_q(rng=0)
    Q = ours.random_q(batch, rng=1)
    cases = [
        ("fk, one", lambda: ours.fk(q), lambda: theirs.fkine(q), 1),
        ("jacobian, one", lambda: ours.jacobian(q), lambda: theirs.jacob0(q), 1),
        (f"fk, batch {batch}", lambda: ours.fk(Q), lambda: theirs.fkine(Q), batch),
    ]
    rows = []
    for label, mine, peer, per in cases:
        runs = repeat if per == 1 else max(3, repeat // 50)
        rows.append((name, label, median_seconds(mine, runs) / per, median_seconds(peer, runs) / per))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--quick", action="store_true", help="fewer repetitions")
    args = parser.parse_args()
    repeat, batch = (50, 1000) if args.quick else (500, 10_000)
    rows = []
    for name, model in MODELS.items():
        rows += measure(armkit.load(name), getattr(rtb.models.DH, model)(), name, repeat, batch)
    print(f"{'robot':10} {'case':18} {'armkit [us]':>12} {'rtb [us]':>10} {'rtb/armkit':>11}")
    for name, label, t_ours, t_peer in rows:
        print(f"{name:10} {label:18} {t_ours * 1e6:12.2f} {t_peer * 1e6:10.2f} {t_peer / t_ours:11.2f}")


if __name__ == "__main__":
    main()
