"""Example 14: a collision-free motion of a UR5 past a wall (OMPL RRT-Connect, smoothed, timed, checked).

Run: python examples/14_plan_past_a_wall.py   (needs pip install 'armkit[plan]')
"""

from pathlib import Path

import numpy as np

import armkit
from armkit.plan import collision_time

robot = armkit.load("ur5")
scene = armkit.load_scene(Path(__file__).parent / "data" / "ur5_wall.toml", robot)
start, goal = np.array([0, -1.2, 1.2, 0, 1.57, 0]), np.array([1.57, -1.2, 1.2, 0, 1.57, 0])

print(f"straight joint motion collides: {scene.path_collides(start, goal)}")
traj = armkit.plan_path(scene, start, goal)
samples = traj.sample(1000.0)
clearance = scene.clearance(samples.q).min()
print(f"planned: {len(traj.waypoints)} waypoints, {traj.duration:.3f} s; collides at a sample: "
      f"{bool(scene.collides(samples.q).any())}; smallest clearance {clearance * 1e3:.2f} mm; "
      f"first collision by the planner's own check: {collision_time(scene, traj)}")
print(f"peak joint speed / limit: {np.max(traj.peak_velocity / robot.max_velocity):.3f}")

pose = armkit.plan_path(scene, start, robot.fk(goal))   # a pose: any collision-free IK solution of it
error = np.linalg.norm(robot.fk(pose.waypoints[-1])[:3, 3] - robot.fk(goal)[:3, 3])
print(f"to the goal pose: the tool ends {error:.1e} m from it, at q = {pose.waypoints[-1].round(3)}")
