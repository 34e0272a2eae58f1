"""Example 1: describe an arm by its DH table, in a file or in code, and look at it.

Run: python examples/01_define_an_arm.py
"""

from pathlib import Path

import numpy as np

import armkit
from armkit import DHRow, Robot

HERE = Path(__file__).parent

# From a robot file (lengths and angles in the units the file names, SI inside).
arm = armkit.load(HERE / "data" / "my_arm.toml")
print(arm, "limits [rad]:", arm.limits.round(3).tolist())

# The same arm in code, SI units: DHRow(alpha, a, d, theta, joint).
same = Robot.from_dh(
    [DHRow(np.pi / 2, 0.0, 0.150, 0.0), DHRow(0.0, 0.250, 0.0, np.pi / 2), DHRow(0.0, 0.200, 0.0, 0.0)],
    "standard",
    name="my 3R arm (code)",
    limits=np.radians([[-170, 170], [-120, 120], [-150, 150]]),
    tool_rows=[DHRow(0.0, 0.060, 0.0, 0.0, joint=None)],
)
q = np.radians([30.0, -20.0, 45.0])
assert np.allclose(arm.fk(q), same.fk(q))
print("tool position at q = (30, -20, 45) deg:", arm.fk(q)[:3, 3].round(4), "m")

# A built-in robot: the PROBOT Anno of report 000.
probot = armkit.load("probot-anno")
print(probot, "with", probot.dh.convention, "DH; built-ins:", ", ".join(armkit.builtin_robots()))
