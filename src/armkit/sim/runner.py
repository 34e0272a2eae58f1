"""Run an armkit robot in MuJoCo: kinematic checks and servo-driven trajectories.

:class:`Simulation` loads the MJCF written by :func:`armkit.export.mjcf_from_robot` (base
frame at the world origin, ``tool`` site at the tool frame) and offers two checks:

* :meth:`Simulation.tool_pose` sets the joint positions and runs MuJoCo's kinematics:
  the simulator's FK, independent of armkit's.
* :meth:`Simulation.run` drives the joints with a command stream at the physics rate
  (1 kHz): each step the position servo gets the commanded position and the velocity
  servo the commanded velocity, ``tau = kp (q* - q) + kv (qd* - qd)``. With
  ``gravity_compensation`` the bias forces MuJoCo computes for the current state
  (gravity, Coriolis, centrifugal; ``qfrc_bias``) are added as ``qfrc_applied``, as a
  robot controller's gravity feed-forward would. In ``mode="velocity"`` only the
  velocity servo acts (the resolved-rate setting of report 000): positions drift freely.

Times in seconds, joint values in rad or m, poses as ``(..., 4, 4)`` in the base frame.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import mujoco
import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.interpolate import CubicHermiteSpline, CubicSpline

from armkit._time import even_time_grid
from armkit.errors import InputError
from armkit.export.mjcf import mjcf_from_robot
from armkit.export.physical import physical_model
from armkit.robot import Robot
from armkit.trajectory.polynomial import quintic

__all__ = ["SimResult", "Simulation"]

CommandMode = Literal["position", "velocity"]


@dataclass(frozen=True)
class SimResult:
    """What a simulated run recorded, one row per physics step.

    Attributes
    ----------
    t : ndarray (N,)
        Time [s].
    q, qd : ndarray (N, n)
        Simulated joint positions [rad or m] and velocities.
    q_command, qd_command : ndarray (N, n)
        What the servos were told at the same instants.
    T_tool : ndarray (N, 4, 4)
        Simulated tool pose (the MJCF ``tool`` site) in the base frame [m].
    gravity, gravity_compensation : bool
    mode : {"position", "velocity"}
    feedforward : bool
        Whether given joint torques (computed-torque feedforward) replaced the gravity compensation.
    """

    t: NDArray[np.float64]
    q: NDArray[np.float64]
    qd: NDArray[np.float64]
    q_command: NDArray[np.float64]
    qd_command: NDArray[np.float64]
    T_tool: NDArray[np.float64]
    gravity: bool
    gravity_compensation: bool
    mode: CommandMode
    feedforward: bool = False

    @property
    def joint_error(self) -> NDArray[np.float64]:
        """Simulated minus commanded joint positions, ``(N, n)``."""
        return self.q - self.q_command


class Simulation:
    """A robot loaded in MuJoCo from its exported MJCF.

    Parameters
    ----------
    robot : Robot
    gravity : bool
        Gravity ``-9.81 m/s^2`` along base z, or none.
    gravity_compensation : bool
        Add MuJoCo's bias forces (gravity, Coriolis) to the servo torques (see module doc).

    Raises
    ------
    RobotDefinitionError
        If the arm cannot be simulated (see :func:`armkit.export.physical_model`).

    Examples
    --------
    >>> import armkit
    >>> robot = armkit.load("probot-anno")
    >>> sim = Simulation(robot, gravity=False)
    >>> bool(np.allclose(sim.tool_pose([0, 0, 0, 0, 0, 0]), robot.fk([0, 0, 0, 0, 0, 0])))
    True
    """

    def __init__(self, robot: Robot, *, gravity: bool = True, gravity_compensation: bool = True) -> None:
        self.robot = robot
        self.gravity = gravity
        self.gravity_compensation = gravity_compensation
        self.physical = physical_model(robot)
        self.xml = mjcf_from_robot(robot, gravity=gravity, model=self.physical)
        self.model = mujoco.MjModel.from_xml_string(self.xml)
        self.data = mujoco.MjData(self.model)
        self._site = mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_SITE, "tool")

    @property
    def timestep(self) -> float:
        """Physics (and command) period [s]."""
        return float(self.model.opt.timestep)

    def _site_pose(self) -> NDArray[np.float64]:
        T = np.eye(4)
        T[:3, :3] = self.data.site_xmat[self._site].reshape(3, 3)
        T[:3, 3] = self.data.site_xpos[self._site]
        return T

    def tool_pose(self, q: ArrayLike) -> NDArray[np.float64]:
        """MuJoCo's tool pose for joint values ``(..., n)``: ``(..., 4, 4)`` [m].

        Sets ``qpos`` and runs ``mj_kinematics``: no dynamics, no servo error.
        """
        q = self.robot.check_q(q)
        flat = q.reshape(-1, self.robot.n)
        poses = np.empty((len(flat), 4, 4))
        for k, q_k in enumerate(flat):
            self.data.qpos[:] = q_k
            mujoco.mj_kinematics(self.model, self.data)
            poses[k] = self._site_pose()
        return poses.reshape(*q.shape[:-1], 4, 4)

    def _commands(self, t: ArrayLike, q: ArrayLike, qd: ArrayLike | None) -> tuple[NDArray, NDArray, NDArray]:
        """Command samples resampled at the physics rate: ``(t, q, qd)``."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        q = np.asarray(q, dtype=float)
        n = self.robot.n
        if q.ndim != 2 or q.shape[1] != n:
            raise InputError(f"trajectory q: {self.robot.name} has {n} joints, so expected shape "
                             f"(samples, {n}), got {q.shape}")
        self.robot.check_q(q, "trajectory q")
        if t.ndim != 1 or len(t) != len(q):
            raise InputError(f"trajectory t: expected {len(q)} times (one per row of q), got shape {t.shape}")
        if len(t) < 2 or not np.all(np.diff(t) > 0):
            raise InputError("trajectory t: expected at least two strictly increasing times [s]")
        grid = t[0] + self.timestep * np.arange(int(round((t[-1] - t[0]) / self.timestep)) + 1)
        grid = np.minimum(grid, t[-1])
        if qd is None:
            spline = CubicSpline(t, q, axis=0)
        else:
            qd = self.robot.check_q(qd, "trajectory qd")
            if qd.shape != q.shape:
                raise InputError(f"trajectory qd: expected shape {q.shape} like q, got {qd.shape}")
            spline = CubicHermiteSpline(t, q, qd, axis=0)
        return grid, spline(grid), spline(grid, 1)

    def run(self, t: ArrayLike, q: ArrayLike, qd: ArrayLike | None = None, *,
            mode: CommandMode = "position", feedforward: ArrayLike | None = None) -> SimResult:
        """Drive the servos along a joint trajectory and record every physics step.

        Parameters
        ----------
        t : array_like (K,)
            Sample times [s], strictly increasing; the run lasts ``t[-1] - t[0]``.
        q : array_like (K, n)
            Commanded joint positions [rad or m]; the arm starts at ``q[0]`` at rest speed
            ``qd[0]``.
        qd : array_like (K, n), optional
            Commanded velocities; default: the derivative of a cubic spline through ``q``.
            Samples are interpolated (cubic Hermite) to the 1 kHz physics rate.
        mode : {"position", "velocity"}
            ``"velocity"``: only the velocity servo acts (no position feedback).
        feedforward : array_like (K, n), optional
            Joint torques [N m or N] at the sample times (interpolated linearly to the physics
            rate), applied instead of the gravity compensation: computed-torque feedforward,
            e.g. armkit's inverse dynamics of the commanded motion; the servos correct the rest.

        Returns
        -------
        SimResult

        Raises
        ------
        InputError
            If ``q`` (or ``feedforward``) does not have one column per joint, the times are
            not increasing, or a value is not finite.

        Examples
        --------
        >>> import armkit
        >>> sim = Simulation(armkit.load("zju-i"), gravity=True)
        >>> result = sim.run([0.0, 1.0], [[0.0] * 6, [0.3] * 6])
        >>> result.q.shape, bool(abs(result.joint_error).max() < 1e-2)
        ((1001, 6), True)
        """
        if mode not in ("position", "velocity"):
            raise InputError(f"mode {mode!r}: expected 'position' or 'velocity'")
        grid, q_cmd, qd_cmd = self._commands(t, q, qd)
        m, d, n = self.model, self.data, self.robot.n
        if feedforward is not None:
            tau = self.robot.check_q(feedforward, "feedforward")
            if tau.shape != (len(np.atleast_1d(t)), n):
                raise InputError(f"feedforward: expected shape {(len(np.atleast_1d(t)), n)}, one torque per "
                                 f"sample and joint, got {tau.shape}")
            times = np.asarray(t, dtype=float)
            feedforward = np.stack([np.interp(grid, times, tau[:, j]) for j in range(n)], axis=-1)
        mujoco.mj_resetData(m, d)
        d.qpos[:], d.qvel[:] = q_cmd[0], qd_cmd[0]
        steps = len(grid)
        q_sim, qd_sim, poses = np.empty((steps, n)), np.empty((steps, n)), np.empty((steps, 4, 4))
        for k in range(steps):
            mujoco.mj_step1(m, d)  # kinematics and bias forces of the current state
            q_sim[k], qd_sim[k], poses[k] = d.qpos, d.qvel, self._site_pose()
            d.ctrl[0::2] = q_cmd[k] if mode == "position" else d.qpos
            d.ctrl[1::2] = qd_cmd[k]
            if feedforward is not None:
                d.qfrc_applied[:] = feedforward[k]
            else:
                d.qfrc_applied[:] = d.qfrc_bias if self.gravity_compensation else 0.0
            mujoco.mj_step2(m, d)
        return SimResult(t=grid, q=q_sim, qd=qd_sim, q_command=q_cmd, qd_command=qd_cmd, T_tool=poses,
                         gravity=self.gravity, gravity_compensation=self.gravity_compensation, mode=mode,
                         feedforward=feedforward is not None)

    def move(self, q_start: ArrayLike, q_goal: ArrayLike, duration: float = 1.0,
             settle: float = 0.5) -> SimResult:
        """Rest-to-rest quintic (minimum jerk) from ``q_start`` to ``q_goal`` in ``duration`` [s],
        then hold ``q_goal`` for ``settle`` [s]: the servo check of a configuration.

        Examples
        --------
        >>> import armkit
        >>> robot = armkit.load("grb400-scara")
        >>> result = Simulation(robot).move([0, 0, 0, 0], [1.0, 0.5, 0.02, 0.3])
        >>> bool(np.abs(result.q[-1] - [1.0, 0.5, 0.02, 0.3]).max() < 1e-6)
        True
        """
        q_start, q_goal = self.robot.check_q(q_start, "q_start"), self.robot.check_q(q_goal, "q_goal")
        if not (duration > 0 and settle >= 0):
            raise InputError(f"duration {duration}, settle {settle}: expected a positive move time "
                             f"and a non-negative settling time [s]")
        t = even_time_grid(duration, self.timestep)
        q, qd = quintic(q_start, q_goal, duration).at_time(t)[:2]
        if settle > 0:
            t, q, qd = np.append(t, duration + settle), np.vstack([q, q_goal]), np.vstack([qd, 0 * q_goal])
        return self.run(t, q, qd)

    def hold(self, q: ArrayLike, duration: float = 1.0) -> SimResult:
        """Start at ``q`` at rest and command it for ``duration`` seconds (settling check)."""
        q = self.robot.check_q(q)
        if not duration > 0:
            raise InputError(f"duration: expected a positive time [s], got {duration}")
        return self.run([0.0, duration], np.stack([q, q]), np.zeros((2, self.robot.n)))
