"""Start-up costs a user meets first: import, the command line, the first IK, memory.

Each case runs in a fresh Python process (as a user's command does), several times; the
median wall time is printed, with pinocchio's and MuJoCo's import beside armkit's.

Run: python benchmarks/bench_startup.py [--quick]
"""

from __future__ import annotations

import argparse
import shutil
import statistics
import subprocess
import sys
import time

FIRST_IK = """
import time, numpy as np
start = time.perf_counter()
import armkit
robot = armkit.load("probot-anno")
T = robot.fk(np.array([0.927, -0.687, -0.396, 0.0, 1.083, 0.927]))
loaded = time.perf_counter()
robot.ik(T, all_solutions=True)
print(time.perf_counter() - loaded)
"""

MEMORY = """
import resource, sys
import {module}
print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)
"""


def wall_seconds(command: list[str], runs: int) -> float:
    """Median wall time [s] of ``command`` in a fresh process."""
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        subprocess.run(command, check=True, capture_output=True)
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def printed_value(code: str, runs: int) -> float:
    """Median of the number a fresh ``python -c code`` prints."""
    return statistics.median(
        float(subprocess.run([sys.executable, "-c", code], check=True, capture_output=True,
                             text=True).stdout) for _ in range(runs))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--quick", action="store_true", help="3 runs per case instead of 9")
    runs = 3 if parser.parse_args().quick else 9
    armkit_cli = shutil.which("armkit") or f"{sys.prefix}/bin/armkit"
    python = sys.executable
    rows = [
        ("python -c 'pass' (the interpreter alone)", wall_seconds([python, "-c", "pass"], runs), "s"),
        ("python -c 'import armkit'", wall_seconds([python, "-c", "import armkit"], runs), "s"),
        ("python -c 'import pinocchio'", wall_seconds([python, "-c", "import pinocchio"], runs), "s"),
        ("python -c 'import mujoco'", wall_seconds([python, "-c", "import mujoco"], runs), "s"),
        ("armkit --help", wall_seconds([armkit_cli, "--help"], runs), "s"),
        ("armkit fk probot-anno 0 0 0 0 0 0",
         wall_seconds([armkit_cli, "fk", "probot-anno", *"000000"], runs), "s"),
        ("armkit ik probot-anno --pose 0.2 0.2 0.2007 1.5708 -1.5708 0 --all",
         wall_seconds([armkit_cli, "ik", "probot-anno", "--pose", "0.2", "0.2", "0.2007", "1.5708", "-1.5708",
                       "0", "--all"], runs), "s"),
        ("first robot.ik(T, all_solutions=True) in a fresh process", printed_value(FIRST_IK, runs), "s"),
        ("memory after import armkit + load + fk",
         printed_value(MEMORY.format(module="armkit; armkit.load('ur5').fk([0] * 6)"), runs), "MB"),
        ("memory after import pinocchio", printed_value(MEMORY.format(module="pinocchio"), runs), "MB"),
    ]
    width = max(len(label) for label, _, _ in rows)
    print(f"{'case':{width}}  median ({runs} fresh processes)")
    for label, value, unit in rows:
        print(f"{label:{width}}  {value:8.3f} {unit}")


if __name__ == "__main__":
    main()
