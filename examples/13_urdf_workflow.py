"""Example 13: bring your own arm as URDF - load, show, every IK solution, a trajectory, MuJoCo.

Uses the UR5 URDF of example-robot-data (``pip install example-robot-data``, in armkit's
test extra) if it is installed; otherwise it writes armkit's built-in UR5 as a URDF and reads
that back, so the example runs anywhere. Then it locks one joint of the 7-joint Panda
(example-robot-data) to get a 6R arm with a closed form, if that file is there.

Run: python examples/13_urdf_workflow.py     (writes ur5.urdf into a temporary folder when example-robot-data
is missing)
"""

import tempfile
from importlib.metadata import PackageNotFoundError, distribution
from pathlib import Path

import numpy as np

import armkit
from armkit.poe import poe_from_chain
from armkit.sim import Simulation

try:
    ROBOTS = Path(distribution("example-robot-data").locate_file(
        "cmeel.prefix/share/example-robot-data/robots"))
    urdf, tip = ROBOTS / "ur_description/urdf/ur5_robot.urdf", "tool0"   # three leaves: name the tool
except PackageNotFoundError:
    ROBOTS = None
    urdf, tip = armkit.write_urdf(armkit.load("ur5"), Path(tempfile.mkdtemp(prefix="armkit-example-13-"))
                                  / "ur5.urdf"), "tool"

# Load: the serial chain from the root link to the tip, joint names and limits from the file.
robot = armkit.load(urdf, tip=tip)                       # CLI: armkit show ur5_robot.urdf --tip tool0
print(robot, "from", Path(urdf).name, "links", robot.urdf.base, "->", robot.urdf.tip)
print("joints:", robot.joint_names)
print("limits [rad]:", robot.limits[:, 1].round(4).tolist(), "max velocity [rad/s]:",
      robot.max_velocity.round(2).tolist())
print("kind:", armkit.analyze_structure(robot).description)   # found from the joint axes
lines = poe_from_chain(robot.chain)                       # the joint axes at q = 0, base frame
print("joint axes at q = 0:\n", lines.axes.round(6) + 0.0)

# Every closed-form IK solution of a pose, each checked by FK.
q_true = np.array([0.3, -1.2, 1.5, -0.7, 1.1, 0.4])
T = robot.fk(q_true)
solutions = robot.ik(T, all_solutions=True)
errors = np.linalg.norm(robot.fk(solutions)[:, :3, 3] - T[:3, 3], axis=-1)
print(f"{len(solutions)} IK solutions inside the limits, position errors <= {errors.max():.1e} m;",
      "the generating q is solution", int(np.argmin(np.abs(solutions - q_true).max(axis=1))) + 1)

# A minimum-jerk trajectory through three tool poses, timed to the URDF's velocity limits.
poses = robot.pose(np.array([q_true, q_true + 0.3, q_true - 0.2]))
traj = armkit.plan_trajectory(robot, poses, poses=True)
ratio = np.max(traj.peak_velocity / robot.max_velocity)
print(f"trajectory: {traj.duration:.2f} s, peak |qd| / limit {ratio:.3f}")

# Simulate it in MuJoCo (the MJCF is written from the same chain: capsules, masses, servos).
samples = traj.sample(1000.0)
result = Simulation(robot, gravity=True).run(samples.t, samples.q, samples.qd)
tool_error = np.linalg.norm(result.T_tool[:, :3, 3] - robot.fk(result.q_command)[:, :3, 3], axis=-1)
print(f"MuJoCo tracked it with max tool error {tool_error.max() * 1000:.1f} mm over {len(result.t)} steps")

# A 7-joint arm with one joint locked is a 6R arm of its own, with its own closed form.
if ROBOTS is not None:
    panda = armkit.load(ROBOTS / "panda_description/urdf/panda.urdf", tip="panda_hand_tcp")
    arm = panda.lock({"panda_joint7": 0.785})            # CLI: --lock panda_joint7=0.785
    print(arm, "kind:", armkit.analyze_structure(arm).kind)
    q6 = arm.ik(panda.fk(arm.full_q(arm.home + 0.2)), all_solutions=True)
    print(f"{len(q6)} closed-form solution(s) inside the limits, as full Panda configurations:\n",
          arm.full_q(q6).round(3))
