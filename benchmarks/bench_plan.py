"""Collision-free planning: a UR5 past one wall (examples/data/ur5_wall.toml); target < 2 s median.

Run: python benchmarks/bench_plan.py
Times armkit.plan_path (search, shortening, timing and the final check) once per seed over 10 seeds
and prints the median, beside the parts of it: the scene queries the planner made (collides and
path_collides, counted and timed by wrapping the scene's methods) and the timing of the straight
motion by plan_trajectory (no obstacles), as the floor any planned motion costs.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

import armkit
from armkit.plan import plan_path
from armkit.trajectory import plan_trajectory

SCENE = Path(__file__).resolve().parents[1] / "examples" / "data" / "ur5_wall.toml"
Q_START = np.array([0.0, -1.2, 1.2, 0.0, 1.57, 0.0])
Q_GOAL = np.array([1.57, -1.2, 1.2, 0.0, 1.57, 0.0])
SEEDS = range(10)
TARGET_S = 2.0


class CountingScene:
    """The scene, with the time spent in and the number of its collision queries recorded."""

    def __init__(self, scene: armkit.Scene) -> None:
        self.scene, self.robot = scene, scene.robot
        self.seconds, self.calls = 0.0, 0

    def _timed(self, name: str, *args, **kwargs):
        start = time.perf_counter()
        try:
            return getattr(self.scene, name)(*args, **kwargs)
        finally:
            self.seconds += time.perf_counter() - start
            self.calls += 1

    def collides(self, *args, **kwargs):
        return self._timed("collides", *args, **kwargs)

    def path_collides(self, *args, **kwargs):
        return self._timed("path_collides", *args, **kwargs)

    def __getattr__(self, name: str):
        return getattr(self.scene, name)


def main() -> None:
    robot = armkit.load("ur5")
    straight = []
    for _ in SEEDS:
        start = time.perf_counter()
        plan_trajectory(robot, [Q_START, Q_GOAL])
        straight.append(time.perf_counter() - start)
    print(f"UR5 past one wall ({SCENE.name}), {len(SEEDS)} seeds; the straight motion timed by "
          f"plan_trajectory (no obstacles) takes {np.median(straight) * 1e3:.2f} ms")
    for threads in (None, 1):   # the scene's batches over every core (default), or on the calling thread
        start = time.perf_counter()
        scene = armkit.load_scene(SCENE, robot, threads=threads)
        built = time.perf_counter() - start
        plan_path(scene, Q_START, Q_GOAL)     # imports (OMPL, SciPy) and first-call costs out of the timings
        totals, queries, calls, durations = [], [], [], []
        for seed in SEEDS:
            counting = CountingScene(scene)
            start = time.perf_counter()
            trajectory = plan_path(counting, Q_START, Q_GOAL, seed=seed)
            totals.append(time.perf_counter() - start)
            queries.append(counting.seconds)
            calls.append(counting.calls)
            durations.append(trajectory.duration)
        median = float(np.median(totals))
        print(f"scene threads={threads or 'every core'} (built in {built:.3g} s):")
        verdict = "met" if median < TARGET_S else "NOT met"
        print(f"  plan_path             median {median:.3f} s (min {min(totals):.3f}, "
              f"max {max(totals):.3f}); target < {TARGET_S:g} s: {verdict}; "
              f"{median / np.median(straight):.0f}x the straight motion's timing")
        print(f"  of it, scene queries  median {np.median(queries):.3f} s "
              f"({np.median(np.array(queries) / np.array(totals)):.0%}), {np.median(calls):.0f} calls")
        print(f"  motion duration       median {np.median(durations):.3f} s "
              f"(min {min(durations):.3f}, max {max(durations):.3f})")


if __name__ == "__main__":
    main()
