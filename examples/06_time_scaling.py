"""Example 6: point-to-point profiles, and fitting a trajectory to the joint limits.

A quintic, a cubic and an LSPB (trapezoid) for the same move; then the seed's waypoints
with segments that are too short, stretched as little as the velocity and acceleration
limits need, and with the shortest durations that meet them (auto-time).

Run: python examples/06_time_scaling.py
"""

from pathlib import Path

import numpy as np

import armkit
from armkit.trajectory import cubic, lspb, quintic, read_waypoints, stretch_to_limits

robot = armkit.load("probot-anno")

# 1. Point to point, 1 rad in 2 s: peaks of each profile.
t = np.linspace(0.0, 2.0, 2001)
for name, segment in (("quintic", quintic(0.0, 1.0, 2.0)), ("cubic", cubic(0.0, 1.0, 2.0)),
                      ("lspb", lspb(0.0, 1.0, 2.0))):
    _, qd, qdd, _ = segment.at_time(t)
    print(f"{name:8s} peak qd {np.abs(qd).max():.4f} rad/s, peak |qdd| {np.abs(qdd).max():.4f} rad/s^2, "
          f"qdd at the ends {qdd[0, 0]:+.3f} / {qdd[-1, 0]:+.3f}")

# 2. The seed's joint waypoints with 2 s segments: too fast for the PROBOT Anno.
waypoints = read_waypoints(Path(__file__).parent / "data" / "probot_seed_joints.csv", columns=6)
too_fast = armkit.min_jerk(waypoints, [2.0, 2.0, 2.0])
print("\n2 s segments, peak |qdd| / amax:", (too_fast.peak_acceleration / robot.max_acceleration).round(2))
fitted = stretch_to_limits(waypoints, [2.0, 2.0, 2.0], robot.max_velocity, robot.max_acceleration)
print("stretched durations [s]:", fitted.durations.round(3), " factors:", fitted.stretch.round(3))
print("now peak |qdd| / amax:  ", (fitted.peak_acceleration / robot.max_acceleration).round(3))

# 3. The shortest durations within the limits (armkit traj ... --auto-time).
fastest = armkit.plan_trajectory(robot, waypoints)          # durations=None: auto-time
print(f"\nauto-time: {fastest.duration:.3f} s, segments {fastest.durations.round(3)} s")
print("peak |qd| / vmax: ", (fastest.peak_velocity / robot.max_velocity).round(3))
print("peak |qdd| / amax:", (fastest.peak_acceleration / robot.max_acceleration).round(3))
