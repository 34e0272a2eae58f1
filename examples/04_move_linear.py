"""Example 4: velocity control, a straight tool move (report 000's Jacobian experiment).

From q = 0 the PROBOT Anno tool (at [0.2289, 0, 0.454]) moves by [0.15, 0, -0.15] m on a
straight line with a quintic time law, followed in closed loop by resolved-rate control
(damped least squares, joint velocities scaled to their limits).

Run: python examples/04_move_linear.py
"""

import numpy as np

import armkit
from armkit.control import ResolvedRate

robot = armkit.load("probot-anno")
q0 = np.zeros(6)

result = armkit.move_linear(robot, q0, [0.15, 0.0, -0.15], duration=3.0)
print("start position:", robot.fk(q0)[:3, 3].round(4), "m")
print("end position:  ", result.pose_final[:3, 3].round(6), "m   (report: [0.379, 0, 0.304])")
print(f"final error: {result.position_error:.2e} m, {result.orientation_error:.2e} rad;"
      f" largest along the line: {result.max_position_error:.2e} m")
print("final joints:", result.q_final.round(6), "rad")
print("peak |qd| / limit per joint:", (np.abs(result.qd).max(axis=0) / robot.max_velocity).round(3))

# One resolved-rate step by hand: the joint velocities for 1 cm/s down, in the tool frame.
control = ResolvedRate(robot)
qd = control.joint_velocity(q0, [0.0, 0.0, 0.01, 0.0, 0.0, 0.0], frame="tool")
print("qd for 1 cm/s along the tool z axis (base -y here):", qd.round(5), "rad/s")
