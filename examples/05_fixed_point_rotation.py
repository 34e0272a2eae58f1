"""Example 5: fixed-point rotation, the tool turns about an axis through its own origin.

Report 000: PROBOT Anno from q = 0 turns about the base x axis at -0.2 rad/s (the twist
[0, 0, 0, -0.2, 0, 0]) while the tool stays at [0.2289, 0, 0.454]. Within the maker's
joint limits it turns 180 degrees, where joint 4 reaches -pi; asked for 200 degrees it
stops at that limit and says so.

Run: python examples/05_fixed_point_rotation.py
"""

import numpy as np

import armkit

robot = armkit.load("probot-anno")
q0 = np.zeros(6)
p0 = robot.fk(q0)[:3, 3]

half_turn = armkit.rotate_about_tool_point(robot, q0, [1, 0, 0], angle=-np.pi, angular_velocity=0.2)
drift = np.linalg.norm(half_turn.poses[:, :3, 3] - p0, axis=-1).max()
print(f"180 deg in {half_turn.t[-1]:.3f} s: position drift {drift:.2e} m, success: {half_turn.success}")
print("final joints:", half_turn.q_final.round(6), "(joint 4 at -pi)")
print("final roll pitch yaw [deg]:", np.degrees(robot.pose(half_turn.q_final)[3:]).round(4))
print("smallest singular value on the way:", half_turn.sigma_min.min().round(4))

more = armkit.rotate_about_tool_point(robot, q0, [1, 0, 0], angle=-np.radians(200), angular_velocity=0.2)
print(f"asked for 200 deg: success {more.success}: {more.message}")
print(f"  orientation still {np.degrees(more.orientation_error):.2f} deg short of the target")
