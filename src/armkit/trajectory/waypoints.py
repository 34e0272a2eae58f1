"""Waypoints for a robot: read from CSV, given as joint values or as tool poses (through IK).

A waypoint file is CSV, one waypoint per line, an optional header line, ``#`` comments:
joint values in SI units, or with poses ``x y z a b c`` (metres, radians, the angles in a
named convention such as ``xyz-fixed``, i.e. roll pitch yaw).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit._io import atomic_write, check_output_path
from armkit.errors import InputError, JointLimitError, UnreachableError
from armkit.robot import Robot
from armkit.spatial.transforms import transform_from_pose
from armkit.trajectory._checks import check_waypoints
from armkit.trajectory.export import read_csv_rows

__all__ = ["joint_waypoints", "joint_waypoints_from_poses", "read_waypoints", "write_waypoints"]


def _show(values: NDArray[np.float64]) -> str:
    return "[" + ", ".join(f"{v:.6g}" for v in values) + "]"


def read_waypoints(path: str | Path, columns: int) -> NDArray[np.float64]:
    """The ``(M, columns)`` waypoints of a CSV file, with errors naming the file and line.

    Parameters
    ----------
    path : str or Path
        CSV file; the first non-comment line may be a header (it is skipped if not numeric).
    columns : int
        Values expected per line (the joint count, or 6 for poses).
    """
    _, rows = read_csv_rows(path, columns, "waypoint")
    if len(rows) < 2:
        raise InputError(f"{path}: a trajectory needs at least two waypoints, found {len(rows)}")
    return rows


def write_waypoints(path: str | Path, robot: Robot, waypoints: ArrayLike, overwrite: bool = False,
                    remedy: str = "pass overwrite=True") -> Path:
    """Write joint waypoints as the CSV :func:`read_waypoints` (and ``armkit traj --waypoints``) reads.

    Parameters
    ----------
    path : str or Path
        Output file; an existing file is replaced only with ``overwrite``.
    robot : Robot
        The arm: each waypoint needs ``robot.n`` values inside its position limits.
    waypoints : (M, n) array
        Joint values [rad or m].
    remedy : str
        How the caller allows overwriting, quoted in the error.

    Raises
    ------
    InputError, JointLimitError
        The file exists (and not ``overwrite``), a wrong joint count, a waypoint outside the limits.

    Examples
    --------
    >>> import armkit, tempfile
    >>> robot = armkit.load("probot-anno")
    >>> path = write_waypoints(Path(tempfile.mkdtemp()) / "w.csv", robot, [[0, 0, 0, 0, 0, 0], [0.1] * 6])
    >>> read_waypoints(path, robot.n)[1].tolist() == [0.1] * 6
    True
    """
    waypoints = joint_waypoints(robot, waypoints)
    path = check_output_path(path, overwrite, remedy=remedy)
    header = (f"# {robot.name}: {len(waypoints)} joint waypoints (rad, prismatic m)\n"
              + ",".join(f"q{j}" for j in range(1, robot.n + 1)))
    with atomic_write(path) as partial:
        np.savetxt(partial, waypoints, delimiter=",", header=header, comments="", fmt="%.17g")
    return path


def joint_waypoints(robot: Robot, waypoints: ArrayLike, degrees: bool = False) -> NDArray[np.float64]:
    """Joint waypoints ``(M, n)`` [rad or m] checked against the robot: joint count and position
    limits (the error shows revolute values in degrees with ``degrees``, as they were typed)."""
    waypoints = check_waypoints(waypoints)
    if waypoints.shape[1] != robot.n:
        raise InputError(f"waypoints: {robot.name} has {robot.n} joints, so each waypoint needs "
                         f"{robot.n} values, got {waypoints.shape[1]}")
    for k, q in enumerate(waypoints, start=1):
        violations = robot.limit_violations(q, degrees)
        if violations:
            raise JointLimitError(f"waypoint {k}: {'; '.join(violations)}", q.copy(),
                                  **robot.chain.limit_fields(q))
    return waypoints


def joint_waypoints_from_poses(robot: Robot, poses: ArrayLike, convention: str = "xyz-fixed",
                               q_start: ArrayLike | None = None) -> NDArray[np.float64]:
    """Joint waypoints ``(M, n)`` for tool poses, each the IK solution nearest the previous one.

    Where the arm needs numeric IK, its random restarts (when the start from the previous
    waypoint fails) are seeded by the waypoint's number: the same poses give the same
    waypoints every run.

    Parameters
    ----------
    poses : (M, 6) array
        ``x y z`` [m] and three angles [rad] in ``convention`` per waypoint.
    convention : str
        Angle convention, e.g. ``"xyz-fixed"`` (roll pitch yaw, ``R = Rz(c) Ry(b) Rx(a)``).
    q_start : (n,) array, optional
        The first waypoint's solution is the one nearest this [rad or m]; default zeros.

    Raises
    ------
    UnreachableError
        A pose has no solution (inside the joint limits); the message names the waypoint.

    Examples
    --------
    >>> import armkit, numpy as np
    >>> robot = armkit.load("probot-anno")
    >>> q = joint_waypoints_from_poses(robot, [[0.2289, 0, 0.454, np.pi / 2, 0, 0],
    ...                                        [0.3, 0.0, 0.3, np.pi / 2, 0, 0]])
    >>> q.shape, bool(np.allclose(q[0], 0.0, atol=1e-9))
    ((2, 6), True)
    """
    poses = check_waypoints(poses, "poses")
    if poses.shape[1] != 6:
        raise InputError(f"poses: expected 6 values per pose (x y z a b c), got {poses.shape[1]}")
    transforms = transform_from_pose(poses, convention)
    q_previous = np.zeros(robot.n) if q_start is None else robot.check_q(q_start, "q_start")
    solutions = []
    for k, T in enumerate(transforms, start=1):
        try:
            q_previous = robot.ik(T, near=q_previous, rng=k)  # seeded restarts: the same waypoints every run
        except UnreachableError as exc:
            raise UnreachableError(f"waypoint {k} (pose {_show(poses[k - 1])}): {exc}",
                                   exc.position_error, exc.orientation_error) from exc
        except JointLimitError as exc:
            raise JointLimitError(f"waypoint {k} (pose {_show(poses[k - 1])}): {exc}") from exc
        solutions.append(q_previous)
    return np.array(solutions)
