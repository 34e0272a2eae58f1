"""armkit's dynamics against pinocchio's on every serial arm of example-robot-data armkit loads.

pinocchio's model of the whole URDF is reduced to the chain's joints with every other joint
held at zero (``buildReducedModel``): the bodies armkit merges into each link (fixed links,
hands and fingers beyond the tip) are the ones pinocchio merges.
"""

from __future__ import annotations

from importlib.metadata import PackageNotFoundError

import numpy as np
import pytest
from helpers import ARMS, example_robot_data_folder

import armkit

pinocchio = pytest.importorskip("pinocchio")
try:
    ROBOTS = example_robot_data_folder()
except PackageNotFoundError:  # pragma: no cover - the test extra installs it
    pytest.skip("example-robot-data is not installed", allow_module_level=True)
RELATIVE = 1e-10


class Reduced:
    """pinocchio's model of the URDF reduced to ``robot``'s joints, in armkit's joint order."""

    def __init__(self, robot: armkit.Robot, path) -> None:
        full = pinocchio.buildModelFromUrdf(str(path))
        locked = [full.getJointId(name) for name in full.names[1:] if name not in robot.joint_names]
        try:
            self.model = pinocchio.buildReducedModel(full, locked, pinocchio.neutral(full))
        except ValueError as exc:  # pinocchio's own limitation (so100: two frames named "gripper")
            pytest.skip(f"pinocchio cannot reduce this model: {exc}")
        self.data = self.model.createData()
        joints = [self.model.joints[self.model.getJointId(name)] for name in robot.joint_names]
        self.idx_q = [(j.idx_q, j.nq) for j in joints]
        self.idx_v = [j.idx_v for j in joints]
        # pinocchio's gravity is in the URDF root's frame, armkit's in the base link's (PR2: the torso)
        pinocchio.framesForwardKinematics(self.model, self.data, pinocchio.neutral(self.model))
        R_root_base = self.data.oMf[self.model.getFrameId(robot.urdf.base)].rotation
        self.gravity = R_root_base.T @ self.model.gravity.linear

    def q(self, q: np.ndarray) -> np.ndarray:
        out = pinocchio.neutral(self.model)
        for (start, nq), value in zip(self.idx_q, q, strict=True):
            out[start:start + nq] = [value] if nq == 1 else [np.cos(value), np.sin(value)]  # continuous
        return out

    def v(self, v: np.ndarray) -> np.ndarray:
        out = np.zeros(self.model.nv)
        out[self.idx_v] = v
        return out

    def ordered(self, values: np.ndarray) -> np.ndarray:
        return values[self.idx_v] if values.ndim == 1 else values[np.ix_(self.idx_v, self.idx_v)]


def close(actual: np.ndarray, expected: np.ndarray) -> None:
    scale = max(np.abs(expected).max(), 1e-300)
    assert np.abs(actual - expected).max() <= RELATIVE * scale, np.abs(actual - expected).max() / scale


@pytest.mark.parametrize(("file", "base", "tip", "kind"), ARMS,
                         ids=[f"{a[0].split('/')[-1]}:{a[2]}" for a in ARMS])
def test_dynamics_equal_pinocchios(file, base, tip, kind):
    path = ROBOTS / file
    robot = armkit.load(path, base=base, tip=tip)
    reference = Reduced(robot, path)
    rng = np.random.default_rng(17)
    q = robot.random_q(12, rng=rng)
    qd, qdd, tau = rng.normal(0, 1.5, (3, 12, robot.n))
    g = reference.gravity
    ours = {"rnea": robot.inverse_dynamics(q, qd, qdd, gravity=g), "crba": robot.mass_matrix(q),
            "gravity": robot.gravity_torques(q, gravity=g),
            "aba": robot.forward_dynamics(q, qd, tau, gravity=g),
            "nle": robot.inverse_dynamics(q, qd, gravity=g), "coriolis": robot.coriolis_torques(q, qd)}
    model, data = reference.model, reference.data
    for k in range(len(q)):
        q_pin, v, a, t = reference.q(q[k]), reference.v(qd[k]), reference.v(qdd[k]), reference.v(tau[k])
        close(ours["rnea"][k], reference.ordered(pinocchio.rnea(model, data, q_pin, v, a)))
        M = pinocchio.crba(model, data, q_pin)
        close(ours["crba"][k], reference.ordered(np.triu(M) + np.triu(M, 1).T))
        gravity = pinocchio.computeGeneralizedGravity(model, data, q_pin)
        close(ours["gravity"][k], reference.ordered(gravity))
        close(ours["aba"][k], reference.ordered(pinocchio.aba(model, data, q_pin, v, t)))
        nle = pinocchio.nonLinearEffects(model, data, q_pin, v)
        close(ours["nle"][k], reference.ordered(nle))
        close(ours["coriolis"][k], reference.ordered(nle - gravity))


def test_the_ur5_urdf_mass_is_kept_not_replaced_by_capsules():
    robot = armkit.load(ROBOTS / "ur_description/urdf/ur5_robot.urdf", tip="tool0")
    reference = Reduced(robot, ROBOTS / "ur_description/urdf/ur5_robot.urdf")
    moving = sum(inertia.mass for inertia in reference.model.inertias[1:])
    assert sum(j.inertial.mass for j in robot.chain.joints) == pytest.approx(moving, rel=1e-14)
    assert robot.max_torque.tolist() == [150.0, 150.0, 150.0, 28.0, 28.0, 28.0]
