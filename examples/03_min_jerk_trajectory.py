"""Example 3: report 000's trajectory - four tool poses, minimum jerk, 10 s per segment.

Each pose goes through IK (the solution nearest the previous one), then one quintic per
segment with velocity and acceleration continuous at the waypoints and the interior
velocities and accelerations chosen to minimise the total squared jerk. Writes the
samples to CSV and the position / velocity / acceleration figure with the joint limits.

Run: python examples/03_min_jerk_trajectory.py     (writes the CSV and figures into a temporary folder)
"""

import tempfile
from pathlib import Path

import numpy as np

import armkit
from armkit.plots import plot_pva, plot_tool_path, save_figure
from armkit.trajectory import joint_waypoints_from_poses, read_waypoints

DATA = Path(__file__).parent / "data"
robot = armkit.load("probot-anno")

poses = read_waypoints(DATA / "probot_seed_poses.csv", columns=6)   # x y z roll pitch yaw
waypoints = joint_waypoints_from_poses(robot, poses, convention="xyz-fixed")
print("IK waypoints [rad] (report: p1..p4):\n", waypoints.round(4))

traj = armkit.min_jerk(waypoints, durations=[10.0, 10.0, 10.0])
q, qd, qdd = traj.at_time(traj.waypoint_times)
print(f"{traj}: waypoints hit to {np.abs(q - waypoints).max():.1e} rad")
print("velocity at the waypoints [rad/s]:\n", qd.round(4) + 0.0)
print("peak |qd| / vmax: ", (traj.peak_velocity / robot.max_velocity).round(3))
print("peak |qdd| / amax:", (traj.peak_acceleration / robot.max_acceleration).round(3))

folder = Path(tempfile.mkdtemp(prefix="armkit-example-03-"))   # not the folder it is run from
traj.to_csv(folder / "seed_trajectory.csv", rate_hz=50.0)
save_figure(plot_pva(traj, robot), folder / "seed_pva.png")
save_figure(plot_tool_path(robot, traj), folder / "seed_tool_path.png")
print(f"wrote seed_trajectory.csv, seed_pva.png, seed_tool_path.png in {folder}")
