"""Example 15: a UR5 in a work cell: which IK solutions are free, clearance, contacts, a path check.

Run: python examples/15_collisions.py   (needs MuJoCo: pip install 'armkit[collision]')
"""

from pathlib import Path

import numpy as np

import armkit

robot = armkit.load("ur5")
scene = armkit.load_scene(Path(__file__).parent / "data" / "cell.toml", robot)
print("parts:", ", ".join(scene.parts))
print("pairs never checked:", len(scene.disabled_pairs), "e.g.", list(scene.disabled_pairs.items())[:3])

# Every IK solution of a pose beside the fixture, and which of them hit the table, an obstacle or the arm.
T = armkit.spatial.transforms.transform_from_pose([0.35, 0.3, 0.2, 180, 0, 0], degrees=True)
listed = robot.ik(T, all_solutions=True)
for k, q in enumerate(listed, 1):
    contacts = scene.contacts(q)
    state = "free" if not contacts else "hits " + ", ".join(f"{a}-{b}" for a, b in contacts)
    print(f"solution {k}: clearance {scene.clearance(q):+.3f} m, {state}")
free = robot.ik(T, all_solutions=True, scene=scene)
print(f"{len(free)} of {len(listed)} solutions are free")

# A batch: the share of random configurations in collision (checked in MuJoCo, threaded).
q = robot.random_q(20_000, rng=0)
print(f"{scene.collides(q).mean():.1%} of 20,000 random configurations collide")

# The straight joint-space motion between two free solutions, checked so that no point of the arm
# moves more than 5 mm between two checked configurations.
start, goal = free[0], free[-1]
bound = scene.displacement_bound(start, goal)
print(f"moving from solution 1 to the last free one: points move at most {bound:.2f} m; "
      f"collides: {scene.path_collides(start, goal, resolution=0.005)}")
print("nearest free solution to q = 0:", np.round(robot.ik(T, near=np.zeros(6), scene=scene), 3))
