"""The lab's dynamics experiment: armkit's joint torques along experiment 4's trajectory against
MuJoCo's inverse dynamics (``mj_inverse``) of the simulated arm."""

from __future__ import annotations

import mujoco
import numpy as np

from armkit._format import fmt_significant
from armkit.dynamics import missing_inertia, with_body_inertials
from armkit.lab.context import LabContext, fmt, fmt_error
from armkit.lab.motion import experiment_waypoints, save_figure
from armkit.lab.report import Section, Table
from armkit.plots import Figure
from armkit.robot import Robot
from armkit.trajectory import plan_trajectory

__all__ = ["dynamics_experiment"]

#: Largest difference between armkit's and MuJoCo's torques, relative to the largest torque, that
#: counts as agreement: both compute the same rigid-body model in double precision (1e-15 relative
#: is typical), MuJoCo's body inertias pass through its principal-axis form (quaternion, rounding).
AGREEMENT = 1e-9


def simulated_robot(ctx: LabContext) -> Robot:
    """``ctx.robot`` with the inertials of the bodies its MuJoCo model has (its own, made simulatable,
    or the capsules' when it has none), moved back into the link frames."""
    return with_body_inertials(ctx.robot, ctx.sim.physical.bodies)


def dynamics_experiment(ctx: LabContext) -> Section:
    """Dynamics: joint torques along the trajectory, armkit against MuJoCo's inverse dynamics."""
    own = missing_inertia(ctx.robot.chain) is None
    section = Section("dynamics", "6. Joint torques along the trajectory: armkit against MuJoCo", (
        "armkit's inverse dynamics (recursive Newton-Euler in its C++ core) of experiment 4's trajectory, "
        "sampled at 1 kHz, against MuJoCo's mj_inverse of the same states in the simulated model, with "
        "gravity. " + ("The masses and inertias are the robot file's own. " if own else
                       "The robot file gives no masses: both use the simulation model's capsules (density "
                       "1000 kg/m^3, what robot.with_estimated_inertia(density=1000) gives). ")
        + "MuJoCo's joints also carry a reflected rotor inertia (armature), whose torque is taken off. "
        "Then MuJoCo tracks the motion twice with the same servos: with its own gravity and bias "
        "compensation (as in experiment 4), and with armkit's torques (plus the armature's) as "
        "computed-torque feedforward."))
    robot = simulated_robot(ctx)
    q_waypoints, _, _, durations = experiment_waypoints(ctx)
    trajectory = plan_trajectory(robot, q_waypoints, durations)
    torques = trajectory.torques(robot, 100.0 if ctx.quick else 1000.0)
    samples = trajectory.sample(100.0 if ctx.quick else 1000.0)
    model = ctx.sim.model
    data = mujoco.MjData(model)
    reference = np.empty_like(torques.tau)
    for k in range(samples.t.size):
        data.qpos[:], data.qvel[:], data.qacc[:] = samples.q[k], samples.qd[k], samples.qdd[k]
        mujoco.mj_inverse(model, data)
        reference[k] = data.qfrc_inverse - model.dof_armature * samples.qdd[k]
    difference = np.abs(torques.tau - reference).max(axis=0)
    scale = max(float(np.abs(reference).max()), 1e-300)
    rows = []
    for j, joint in enumerate(robot.chain.joints):
        unit = "N m" if joint.kind == "revolute" else "N"
        limit = robot.max_torque[j]
        rows.append([joint.name, f"{fmt_significant(torques.peak[j], scale)} {unit}",
                     f"{fmt_significant(np.abs(reference[:, j]).max(), scale)} {unit}",
                     f"{fmt_error(difference[j])} {unit}",
                     "none" if not np.isfinite(limit) else f"{fmt_significant(limit)} {unit}"])
    worst = float(difference.max() / scale)
    section.tables.append(Table("Peak |torque| along the trajectory", [
        "joint", "armkit", "MuJoCo mj_inverse", "max |difference|", "torque limit"], rows,
        note=f"{samples.t.size} states; largest difference {worst:.1e} of the largest torque."))
    if worst > AGREEMENT:
        section.status = "failed"
        section.notes.append(f"armkit and MuJoCo differ by {worst:.1e} of the largest torque, more than "
                             f"{AGREEMENT:g}")
    ctx.record(samples.q)
    compensated = ctx.sim.run(samples.t, samples.q, samples.qd)
    feedforward = torques.tau + model.dof_armature * samples.qdd  # the servo model's rotor inertia too
    fed = ctx.sim.run(samples.t, samples.q, samples.qd, feedforward=feedforward)
    error = {"bias": np.abs(compensated.joint_error).max(axis=0), "fed": np.abs(fed.joint_error).max(axis=0)}
    section.tables.append(Table("Tracking in MuJoCo: max |q_MuJoCo - q_command|", [
        "joint", "bias compensation (MuJoCo's)", "computed-torque feedforward (armkit's)"],
        [[name, fmt_error(error["bias"][j]), fmt_error(error["fed"][j])]
         for j, name in enumerate(robot.joint_names)],
        note="Same servos, same trajectory; rad for revolute joints, m for prismatic ones."))
    section.headline = (f"peak {fmt(float(torques.peak.max()), 2)} N m; armkit = MuJoCo to {worst:.0e} "
                        f"(relative) over {samples.t.size} states; feedforward tracks to "
                        f"{error['fed'].max():.0e} (bias compensation {error['bias'].max():.0e})")
    figure = Figure(figsize=(8.5, 3.2))
    ax_tau, ax_diff = figure.subplots(1, 2)
    for j, name in enumerate(robot.joint_names):
        ax_tau.plot(torques.t, torques.tau[:, j], lw=1.4, color=f"C{j}", label=name)
        ax_tau.plot(samples.t, reference[:, j], lw=0.8, color="k", ls=":")
        ax_diff.plot(samples.t, torques.tau[:, j] - reference[:, j], lw=0.8, color=f"C{j}")
    ax_tau.set(xlabel="time [s]", ylabel="torque [N m or N]", title="armkit (colour), MuJoCo (dotted)")
    ax_diff.set(xlabel="time [s]", ylabel="difference [N m or N]", title="armkit - MuJoCo")
    ax_tau.legend(fontsize=7, ncol=3)
    for ax in (ax_tau, ax_diff):
        ax.grid(True, lw=0.3)
    save_figure(ctx, figure, "dynamics_torques.png",
                "Joint torques along experiment 4's trajectory: armkit's inverse dynamics and MuJoCo's "
                "mj_inverse, and their difference.", section)
    return section
