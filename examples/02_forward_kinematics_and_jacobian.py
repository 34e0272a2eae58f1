"""Example 2: forward kinematics in a named angle convention, batches, the Jacobian.

Run: python examples/02_forward_kinematics_and_jacobian.py
"""

import numpy as np

import armkit

robot = armkit.load("probot-anno")

# Report 000, FK group 1: the pose as [x, y, z, roll, pitch, yaw] (X-Y-Z fixed angles).
q = np.array([0.927, -0.687, -0.396, 0.0, 1.083, 0.927])
print("pose (xyz-fixed):", robot.pose(q, "xyz-fixed").round(6))  # [0.150047 0.19994 0.200756 1.570796 0 0]
print("pose (zyz-euler, deg):", robot.pose(q, "zyz-euler", degrees=True).round(3))

# A batch of configurations at once: (N, n) -> (N, 4, 4), no Python loop.
batch = robot.random_q(1000, rng=0)
T = robot.fk(batch)
print("batch FK:", T.shape, "highest tool z:", T[:, 2, 3].max().round(4), "m")

# Geometric Jacobian, rows [vx vy vz wx wy wz], base frame; and how far from singular.
J = robot.jacobian(q)
print("J shape:", J.shape, " manipulability:", robot.manipulability(q).round(6),
      " smallest singular value:", robot.singular_values(q)[-1].round(6))
qdot = np.linalg.lstsq(J, [0.01, 0, 0, 0, 0, 0], rcond=None)[0]
print("joint rates for 1 cm/s along x:", qdot.round(5))
