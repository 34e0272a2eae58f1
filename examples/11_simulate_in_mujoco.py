"""Example 11: drive report 000's minimum-jerk trajectory in MuJoCo with gravity, with and
without gravity compensation, and tabulate computed vs simulated tool poses.

Run: python examples/11_simulate_in_mujoco.py
"""

import numpy as np

import armkit
from armkit.sim import Simulation, compare_poses
from armkit.spatial.rotations import rotation_angle_between
from armkit.trajectory import min_jerk

robot = armkit.load("probot-anno")

# Kinematic check: MuJoCo's FK (qpos set, mj_kinematics) against armkit's, roll-pitch-yaw.
q = robot.random_q(3, rng=1)
table = compare_poses(robot.fk(q), Simulation(robot, gravity=False).tool_pose(q), convention="xyz-fixed")
print("columns:", table.columns)
print("armkit :", table.computed[0].round(6))
print("MuJoCo :", table.simulated[0].round(6))
position_error, orientation_error = table.max_errors()
print(f"largest errors: {position_error:.1e} m, {orientation_error:.1e} rad")

# The report's joint waypoints, 10 s per segment, sampled at the 1 kHz physics rate.
waypoints = [[0, 0, 0, 0, 0, 0],
             [0.795586, -0.772686, 0.205056, 1.08734, 2.51046, -0.842853],
             [0.387677, -1.07517, -0.199884, 0.404374, 2.86768, -0.114923],
             [-0.387371, -1.29256, -0.0658126, -0.394643, 2.94426, 0.0811483]]
samples = min_jerk(waypoints, [10.0, 10.0, 10.0]).sample(1000.0)
for compensation in (True, False):
    sim = Simulation(robot, gravity=True, gravity_compensation=compensation)
    result = sim.run(samples.t, samples.q, samples.qd)
    T_command = robot.fk(result.q_command)
    position = np.linalg.norm(result.T_tool[:, :3, 3] - T_command[:, :3, 3], axis=-1).max()
    rotation = rotation_angle_between(result.T_tool, T_command).max()
    print(f"gravity on, compensation {'on ' if compensation else 'off'}: max joint error "
          f"{np.abs(result.joint_error).max():.1e} rad, tool {position:.1e} m, {rotation:.1e} rad "
          f"over {result.t[-1]:.0f} s ({len(result.t)} steps)")
