"""Computed against simulated tool poses: the verification tables of the seed reports.

A :class:`PoseComparison` holds, per row, the pose armkit computed and the pose the
simulator produced, both as ``[x, y, z, a1, a2, a3]`` in a named angle convention
(e.g. ``"xyz-fixed"`` roll/pitch/yaw for report 000, ``"xyz-euler"`` in degrees for report
003), the per-axis error ``simulated - computed`` (angle differences wrapped to
``[-180, 180)`` deg or ``[-pi, pi)``), and the two numbers that do not depend on a
convention: position distance [m] and rotation angle between the orientations [rad].
Per-axis angle errors are meaningless near the convention's gimbal lock; the rotation
angle is not.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit._deprecation import deprecated_property
from armkit.errors import InputError
from armkit.spatial.rotations import parse_convention, rotation_angle_between
from armkit.spatial.transforms import check_transform, pose_from_transform

__all__ = ["PoseComparison", "compare_poses"]


@dataclass(frozen=True)
class PoseComparison:
    """Rows of computed vs simulated poses with their errors.

    Attributes
    ----------
    labels : list of str
    computed, simulated, error : ndarray (N, 6)
        ``[x, y, z]`` in ``length_unit`` then three angles in ``convention``
        (degrees if ``degrees``); ``error = simulated - computed``.
    position_error : ndarray (N,)
        Distance between the positions [m].
    orientation_error : ndarray (N,)
        Angle of the rotation between the orientations [rad] (as IK's ``orientation_error``;
        ``rotation_error`` is its deprecated old name).
    convention : str
    degrees : bool
    length_unit : {"m", "mm"}
    """

    labels: list[str]
    computed: NDArray[np.float64]
    simulated: NDArray[np.float64]
    error: NDArray[np.float64]
    position_error: NDArray[np.float64]
    orientation_error: NDArray[np.float64]
    convention: str
    degrees: bool
    length_unit: str

    rotation_error = deprecated_property("rotation_error", "orientation_error")

    @property
    def columns(self) -> list[str]:
        """Column names with units, e.g. ``["x [m]", ..., "a1 (x) [rad]", ...]``."""
        angle = "deg" if self.degrees else "rad"
        axes = parse_convention(self.convention).axes
        positions = [f"{c} [{self.length_unit}]" for c in "xyz"]
        return positions + [f"a{i + 1} ({a}) [{angle}]" for i, a in enumerate(axes)]

    def max_errors(self) -> tuple[float, float]:
        """Largest position error [m] and orientation error [rad] over all rows."""
        return float(self.position_error.max()), float(self.orientation_error.max())


def compare_poses(T_computed: ArrayLike, T_simulated: ArrayLike, *, convention: str = "xyz-fixed",
                  degrees: bool = False, length_unit: str = "m",
                  labels: Sequence[str] | None = None) -> PoseComparison:
    """Tabulate computed against simulated poses ``(N, 4, 4)`` in a named convention.

    Examples
    --------
    >>> import armkit
    >>> from armkit.sim import Simulation
    >>> robot = armkit.load("zju-i")
    >>> q = np.full((1, 6), np.pi / 12)
    >>> table = compare_poses(robot.fk(q), Simulation(robot).tool_pose(q), convention="xyz-euler",
    ...                       degrees=True)
    >>> table.computed[0].round(2).tolist()  # report 003: [0.226, 0.107, 0.552, -148.00, 36.35, -107.00]
    [0.23, 0.11, 0.55, -148.0, 36.35, -107.0]
    >>> bool(table.max_errors()[0] < 1e-12)
    True
    """
    T_c = check_transform(T_computed, "computed poses").reshape(-1, 4, 4)
    T_s = check_transform(T_simulated, "simulated poses").reshape(-1, 4, 4)
    if T_c.shape != T_s.shape:
        raise InputError(f"simulated poses: expected {len(T_c)} poses like the computed ones, got {len(T_s)}")
    if length_unit not in ("m", "mm"):
        raise InputError(f"length_unit {length_unit!r}: expected 'm' or 'mm'")
    scale = 1000.0 if length_unit == "mm" else 1.0
    half_turn = 180.0 if degrees else np.pi

    def pose(T: NDArray[np.float64]) -> NDArray[np.float64]:
        return pose_from_transform(T, convention, degrees) * [scale, scale, scale, 1.0, 1.0, 1.0]

    computed, simulated = pose(T_c), pose(T_s)
    error = simulated - computed
    error[:, 3:] = (error[:, 3:] + half_turn) % (2 * half_turn) - half_turn
    labels = [str(k + 1) for k in range(len(T_c))] if labels is None else list(labels)
    if len(labels) != len(T_c):
        raise InputError(f"labels: expected {len(T_c)}, got {len(labels)}")
    return PoseComparison(labels=labels, computed=computed, simulated=simulated, error=error,
                          position_error=np.linalg.norm(T_s[:, :3, 3] - T_c[:, :3, 3], axis=-1),
                          orientation_error=rotation_angle_between(T_s, T_c),
                          convention=parse_convention(convention).name, degrees=degrees,
                          length_unit=length_unit)
