"""Rotation matrices and the angle conventions users name.

Every Euler/fixed-angle conversion takes a *convention string* so the convention is
never implied:

``"xyz-fixed"``
    Fixed (extrinsic) angles about the base axes x, then y, then z:
    ``R = Rz(a3) @ Ry(a2) @ Rx(a1)``. These are roll/pitch/yaw (aliases ``"rpy"``,
    ``"roll-pitch-yaw"``), the pose format of report 000.
``"xyz-euler"``
    Euler (intrinsic) angles about the moving axes X, then Y', then Z'':
    ``R = Rx(a1) @ Ry(a2) @ Rz(a3)`` (report 003).
``"zyz-euler"``
    ``R = Rz(a1) @ Ry(a2) @ Rz(a3)``.

Any of the 12 axis orders (``xyz``, ``xzy``, ..., ``zyz``, ``xyx`` ...) combines with
``-fixed`` or ``-euler``. Matrices are *active* rotations (they rotate vectors; a frame's
rotation matrix holds its axes as columns in the parent frame). Quaternions are
``wxyz`` (scalar first) in the names that take them.

Gimbal lock
-----------
When the middle angle makes the first and third axes coincide (±90° for Tait-Bryan
orders, 0°/180° for proper Euler orders), only their sum or difference is defined.
armkit then sets the **third angle as written to zero** and puts the whole rotation in
the first; the returned angles still reproduce the matrix exactly. The conversion itself
goes through SciPy's quaternion (``scipy.spatial.transform.Rotation``) and keeps full
precision arbitrarily close to the lock (SciPy's own ``as_euler`` snaps to the lock
within 1e-7 rad, which costs up to 1e-7 rad of accuracy).
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from armkit.errors import InputError

__all__ = [
    "AngleConvention",
    "CONVENTIONS",
    "angular_velocity_matrix",
    "axis_angle_from_matrix",
    "euler_from_matrix",
    "matrix_from_axis_angle",
    "matrix_from_euler",
    "matrix_from_quaternion_wxyz",
    "parse_convention",
    "quaternion_wxyz_from_matrix",
    "rotation_angle_between",
]

_ALIASES = {"rpy": "xyz-fixed", "roll-pitch-yaw": "xyz-fixed"}
_PATTERN = re.compile(r"^([xyz])([xyz])([xyz])-(fixed|euler)$")
_AXES = {"x": 0, "y": 1, "z": 2}

#: How close [rad] the middle angle must be to its lock value for the gimbal-lock rule to apply.
GIMBAL_LOCK_TOLERANCE = 1e-13


@dataclass(frozen=True)
class AngleConvention:
    """A parsed angle convention.

    Attributes
    ----------
    axes : str
        Three lower-case axis letters in the order the angles are written.
    extrinsic : bool
        True for fixed (extrinsic) angles, False for Euler (intrinsic) angles.
    """

    axes: str
    extrinsic: bool

    @property
    def name(self) -> str:
        """Canonical name, e.g. ``"xyz-fixed"``."""
        return f"{self.axes}-{'fixed' if self.extrinsic else 'euler'}"

    @property
    def scipy_sequence(self) -> str:
        """SciPy's spelling: lower case extrinsic, upper case intrinsic."""
        return self.axes if self.extrinsic else self.axes.upper()

    def formula(self) -> str:
        """The matrix product this convention stands for, e.g. ``Rz(a3) Ry(a2) Rx(a1)``."""
        factors = [f"R{axis}(a{i + 1})" for i, axis in enumerate(self.axes)]
        return " ".join(reversed(factors) if self.extrinsic else factors)


#: Canonical names of all 24 conventions (12 axis orders, fixed or Euler).
CONVENTIONS: tuple[str, ...] = tuple(
    f"{a}{b}{c}-{kind}"
    for kind in ("fixed", "euler")
    for a in "xyz" for b in "xyz" for c in "xyz"
    if a != b and b != c
)


def parse_convention(convention: str | AngleConvention) -> AngleConvention:
    """Parse a convention string such as ``"xyz-fixed"``, ``"zyz-euler"`` or ``"rpy"``.

    Raises
    ------
    InputError
        If the string names no convention; the message lists the valid ones.
    """
    if isinstance(convention, AngleConvention):
        return convention
    key = _ALIASES.get(str(convention).strip().lower(), str(convention).strip().lower())
    match = _PATTERN.match(key)
    if match is None or match[1] == match[2] or match[2] == match[3]:
        raise InputError(
            f"unknown angle convention {convention!r}; expected one of "
            f"{', '.join(CONVENTIONS)} (or 'rpy' = 'xyz-fixed')"
        )
    return AngleConvention(axes=match[1] + match[2] + match[3], extrinsic=match[4] == "fixed")


def _finite(values: ArrayLike, name: str, last: tuple[int, ...]) -> NDArray[np.float64]:
    try:
        array = np.asarray(values, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{name}: expected numbers, got {values!r}") from exc
    if array.shape[array.ndim - len(last):] != last:
        raise InputError(f"{name}: expected shape (..., {', '.join(map(str, last))}), "
                         f"got {array.shape}")
    if not np.all(np.isfinite(array)):
        raise InputError(f"{name}: contains NaN or infinite values")
    return array


def matrix_from_euler(angles: ArrayLike, convention: str | AngleConvention = "xyz-fixed",
                      degrees: bool = False) -> NDArray[np.float64]:
    """Rotation matrices from three angles in a named convention.

    Parameters
    ----------
    angles : array_like, shape (..., 3)
        Angles in the order the convention writes them [rad, or deg if ``degrees``].
    convention : str
        See the module docstring, e.g. ``"xyz-fixed"`` (roll, pitch, yaw).
    degrees : bool
        Whether ``angles`` are in degrees.

    Returns
    -------
    ndarray, shape (..., 3, 3)

    Examples
    --------
    >>> R = matrix_from_euler([np.pi / 2, 0, 0], "xyz-fixed")
    >>> np.round(R @ [0, 1, 0], 12) + 0.0
    array([0., 0., 1.])
    """
    conv = parse_convention(convention)
    angles = _finite(angles, "angles", (3,))
    return Rotation.from_euler(conv.scipy_sequence, angles, degrees=degrees).as_matrix()


def euler_from_matrix(R: ArrayLike, convention: str | AngleConvention = "xyz-fixed",
                      degrees: bool = False) -> NDArray[np.float64]:
    """Angles in a named convention from rotation matrices (or the rotation of 4x4 transforms).

    The first and third angles lie in ``[-pi, pi]``; the second in ``[-pi/2, pi/2]`` for
    Tait-Bryan orders and ``[0, pi]`` for proper Euler orders. At gimbal lock (middle angle
    within ``GIMBAL_LOCK_TOLERANCE`` of it) the third angle is set to zero (see the module
    docstring); the result still reproduces ``R``. The extraction goes through the
    quaternion (Bernardes & Viollet, 2022), which keeps full precision arbitrarily close
    to gimbal lock.

    Parameters
    ----------
    R : array_like, shape (..., 3, 3) or (..., 4, 4)
    convention : str
    degrees : bool
        Return degrees instead of radians.

    Returns
    -------
    ndarray, shape (..., 3)

    Examples
    --------
    >>> euler_from_matrix(matrix_from_euler([0.1, 0.2, 0.3], "zyz-euler"), "zyz-euler").round(12)
    array([0.1, 0.2, 0.3])
    """
    conv = parse_convention(convention)
    R = np.asarray(R, dtype=float)
    if R.shape[-2:] == (4, 4):
        R = R[..., :3, :3]
    R = _finite(R, "rotation matrix", (3, 3))
    quat = Rotation.from_matrix(R).as_quat(scalar_first=True)
    # Work with the extrinsic sequence; an intrinsic sequence is the extrinsic one reversed.
    axes = conv.axes if conv.extrinsic else conv.axes[::-1]
    i, j, k = (_AXES[a] for a in axes)
    proper = i == k
    if proper:
        k = 3 - i - j
    sign = (i - j) * (j - k) * (k - i) / 2
    w, v = quat[..., 0], quat[..., 1:]
    if proper:
        a, b, c, d = w, v[..., i], v[..., j], v[..., k] * sign
    else:
        a, b = w - v[..., j], v[..., i] + v[..., k] * sign
        c, d = v[..., j] + w, v[..., k] * sign - v[..., i]
    middle = 2 * np.arctan2(np.hypot(c, d), np.hypot(a, b))
    half_sum, half_diff = np.arctan2(b, a), np.arctan2(d, c)
    first, third = half_sum - half_diff, half_sum + half_diff
    at_zero = np.abs(middle) <= GIMBAL_LOCK_TOLERANCE
    at_pi = np.abs(middle - np.pi) <= GIMBAL_LOCK_TOLERANCE
    locked = at_zero | at_pi
    combined = np.where(at_zero, 2 * half_sum, np.where(at_pi, 2 * half_diff, 0.0))
    if conv.extrinsic:  # the third angle as written is the extrinsic third
        first = np.where(locked, combined * np.where(at_pi, -1.0, 1.0), first)
        third = np.where(locked, 0.0, third)
    else:  # the third angle as written is the extrinsic first
        first = np.where(locked, 0.0, first)
        third = np.where(locked, combined, third)
    if not proper:
        third = third * sign
        middle = middle - np.pi / 2
    angles = np.stack([first, middle, third], axis=-1)
    angles = (angles + np.pi) % (2 * np.pi) - np.pi
    angles[..., 1] = middle
    if not conv.extrinsic:
        angles = angles[..., ::-1]
    return np.degrees(angles) if degrees else angles


def quaternion_wxyz_from_matrix(R: ArrayLike) -> NDArray[np.float64]:
    """Unit quaternions ``(..., 4)`` in ``w, x, y, z`` order with ``w >= 0``."""
    q = Rotation.from_matrix(_finite(R, "rotation matrix", (3, 3))).as_quat(scalar_first=True)
    return np.where(q[..., :1] < 0, -q, q)


def matrix_from_quaternion_wxyz(q_wxyz: ArrayLike) -> NDArray[np.float64]:
    """Rotation matrices ``(..., 3, 3)`` from quaternions ``(..., 4)`` in ``w, x, y, z`` order.

    Raises
    ------
    InputError
        If a quaternion has zero norm (it is normalised otherwise).
    """
    q = _finite(q_wxyz, "quaternion", (4,))
    if np.any(np.linalg.norm(q, axis=-1) < 1e-12):
        raise InputError("quaternion: expected a non-zero quaternion, got norm 0")
    return Rotation.from_quat(q, scalar_first=True).as_matrix()


def axis_angle_from_matrix(R: ArrayLike) -> NDArray[np.float64]:
    """Rotation vectors ``(..., 3)``: unit axis times angle [rad], angle in ``[0, pi]``."""
    return Rotation.from_matrix(_finite(R, "rotation matrix", (3, 3))).as_rotvec()


def matrix_from_axis_angle(rotation_vector: ArrayLike) -> NDArray[np.float64]:
    """Rotation matrices ``(..., 3, 3)`` from rotation vectors (axis times angle [rad])."""
    return Rotation.from_rotvec(_finite(rotation_vector, "rotation vector", (3,))).as_matrix()


def rotation_angle_between(R_a: ArrayLike, R_b: ArrayLike) -> NDArray[np.float64]:
    """Angle [rad] of the rotation ``R_a^T R_b``, shape ``(...)``; accurate near zero."""
    R_a = np.asarray(R_a, dtype=float)[..., :3, :3]
    R_b = np.asarray(R_b, dtype=float)[..., :3, :3]
    R_rel = np.swapaxes(R_a, -1, -2) @ R_b
    # R - R^T = 2 sin(angle) [k]x and |[k]x|_F = sqrt(2) for a unit axis k.
    sin = np.linalg.norm(R_rel - np.swapaxes(R_rel, -1, -2), axis=(-1, -2)) / (2 * np.sqrt(2))
    cos = (np.trace(R_rel, axis1=-2, axis2=-1) - 1.0) / 2.0
    return np.arctan2(sin, cos)


def angular_velocity_matrix(angles: ArrayLike,
                            convention: str | AngleConvention = "xyz-fixed") -> NDArray[np.float64]:
    """The matrix ``E`` with ``omega = E @ angle_rates`` (omega in the base frame).

    Parameters
    ----------
    angles : array_like, shape (..., 3)
        Current angles [rad] in ``convention``.

    Returns
    -------
    ndarray, shape (..., 3, 3)
        Singular at gimbal lock.
    """
    conv = parse_convention(convention)
    angles = _finite(angles, "angles", (3,))
    # Write the rotation as a product of intrinsic factors R = Ra(t1) Rb(t2) Rc(t3);
    # then omega = ea t1' + Ra(t1) eb t2' + Ra(t1) Rb(t2) ec t3'.
    axes, order = (conv.axes[::-1], [2, 1, 0]) if conv.extrinsic else (conv.axes, [0, 1, 2])
    theta = angles[..., order]
    E = np.zeros((*angles.shape[:-1], 3, 3))
    R = np.broadcast_to(np.eye(3), (*angles.shape[:-1], 3, 3))
    for k, axis in enumerate(axes):
        E[..., :, order[k]] = R[..., :, _AXES[axis]]
        R = R @ Rotation.from_euler(axis, theta[..., k, None]).as_matrix()  # (..., 1): one angle each
    return E
