"""Example 7: joint torques: inverse and forward dynamics, a payload, torques along a trajectory.

Run: python examples/07_dynamics.py     (writes its figure into a temporary folder)
"""

import tempfile
from pathlib import Path

import numpy as np

import armkit
from armkit.plots import plot_pva, save_figure
from armkit.trajectory import min_jerk

# The PUMA 560 file carries roboticstoolbox's link masses, centres of mass and inertias.
puma = armkit.load("puma560")
q, qd, qdd = np.radians([0, 30, -45, 0, 20, 0]), np.full(6, 0.5), np.full(6, 1.0)
tau = puma.inverse_dynamics(q, qd, qdd)
print("torques [N m]:", tau.round(3))
print("of which gravity [N m]:", puma.gravity_torques(q).round(3))
print("mass matrix diagonal [kg m^2]:", np.diag(puma.mass_matrix(q)).round(4))
assert np.allclose(puma.forward_dynamics(q, qd, tau), qdd)  # forward dynamics undoes it

# A 2 kg payload 10 cm along the tool's z axis, added to the last link's own mass.
loaded = puma.with_payload(2.0, com=[0, 0, 0.1])
print("holding 2 kg, gravity torques [N m]:", loaded.gravity_torques(q).round(3))

# An arm whose file has no masses: ask for an explicit estimate (capsules of a given density).
ur5 = armkit.load("ur5").with_estimated_inertia(density=1000.0)
print("UR5 estimated link masses [kg]:", [round(j.inertial.mass, 3) for j in ur5.chain.joints])

# Torques along a minimum-jerk move, and the P-V-A-torque figure.
traj = min_jerk([puma.home, q], [1.5])
torques = traj.torques(puma, rate_hz=1000.0)
print("peak |torque| along the move [N m]:", torques.peak.round(3))
figure = save_figure(plot_pva(traj, puma, torques=True), Path(tempfile.mkdtemp(prefix="armkit-example-07-"))
                     / "pva_torques.png")
print(f"wrote {figure}")
