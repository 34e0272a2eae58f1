"""Example 10: export an arm as URDF and MJCF, and check both against armkit's FK in MuJoCo.

Run: python examples/10_export_urdf_mjcf.py   (writes into a temporary folder)
"""

import tempfile
from pathlib import Path

import mujoco
import numpy as np

import armkit
from armkit.export import write_mjcf, write_urdf

robot = armkit.load("stanford")  # R-R-P-R-R-R: a prismatic joint too
folder = Path(tempfile.mkdtemp(prefix="armkit-export-"))
urdf = write_urdf(robot, folder / "stanford.urdf")
mjcf = write_mjcf(robot, folder / "stanford.xml")
print("wrote", urdf, "and", mjcf)

q = robot.random_q(5, rng=0)
for path, kind, name in ((mjcf, mujoco.mjtObj.mjOBJ_SITE, "tool"), (urdf, mujoco.mjtObj.mjOBJ_BODY, "tool")):
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    index = mujoco.mj_name2id(model, kind, name)
    worst = 0.0
    for q_k in q:
        data.qpos[:] = q_k
        mujoco.mj_kinematics(model, data)
        position = data.site_xpos[index] if kind == mujoco.mjtObj.mjOBJ_SITE else data.xpos[index]
        worst = max(worst, np.linalg.norm(position - robot.fk(q_k)[:3, 3]))
    print(f"{path.suffix}: {model.njnt} joints, {model.nu} actuators, "
          f"largest tool position difference to armkit FK: {worst:.1e} m")

try:
    write_mjcf(robot, mjcf)
except armkit.InputError as error:
    print("no silent overwrite:", error)
