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
goes through the quaternion (Bernardes & Viollet, 2022) and keeps full precision
arbitrarily close to the lock (SciPy's ``as_euler`` snaps to the lock within 1e-7 rad,
which costs up to 1e-7 rad of accuracy).

The quaternion of a matrix is Shepperd's method (the largest of ``w, x, y, z`` computed
from the diagonal, the others from off-diagonal sums), written here in NumPy rather than
imported from ``scipy.spatial.transform``: importing that module costs half a second,
more than every command that converts one pose.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

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


def _elementary(axis: str, angle: NDArray[np.float64]) -> NDArray[np.float64]:
    """Rotations ``(..., 3, 3)`` by ``angle`` ``(...)`` [rad] about the base axis ``axis``."""
    c, s = np.cos(angle), np.sin(angle)
    i = _AXES[axis]
    j, k = (i + 1) % 3, (i + 2) % 3
    R = np.zeros((*np.shape(angle), 3, 3))
    R[..., i, i] = 1.0
    R[..., j, j] = R[..., k, k] = c
    R[..., k, j], R[..., j, k] = s, -s
    return R


def _quaternion_wxyz(R: NDArray[np.float64]) -> NDArray[np.float64]:
    """Unit quaternions ``(..., 4)``, ``w >= 0``, of rotation matrices ``(..., 3, 3)`` (Shepperd).

    Of ``4 w^2 = 1 + trace``, ``4 x^2 = 1 + 2 R00 - trace`` (and y, z alike) the largest
    is taken from the diagonal, the other three from sums and differences of the
    off-diagonal pairs divided by it: never a division by less than 1/2.
    """
    R00, R11, R22 = R[..., 0, 0], R[..., 1, 1], R[..., 2, 2]
    trace = R00 + R11 + R22
    squares = np.stack([1 + trace, 1 + 2 * R00 - trace, 1 + 2 * R11 - trace, 1 + 2 * R22 - trace], axis=-1)
    largest = np.argmax(squares, axis=-1)
    d = 0.5 * np.sqrt(np.take_along_axis(squares, largest[..., None], axis=-1)[..., 0])  # |c|
    sxy, dxy = R[..., 1, 0] + R[..., 0, 1], R[..., 1, 0] - R[..., 0, 1]
    sxz, dxz = R[..., 0, 2] + R[..., 2, 0], R[..., 0, 2] - R[..., 2, 0]
    syz, dyz = R[..., 2, 1] + R[..., 1, 2], R[..., 2, 1] - R[..., 1, 2]
    # row c: 2 c (w, x, y, z), for each choice of the largest component c
    candidates = np.stack([
        np.stack([2 * d * d, dyz / 2, dxz / 2, dxy / 2], axis=-1),
        np.stack([dyz / 2, 2 * d * d, sxy / 2, sxz / 2], axis=-1),
        np.stack([dxz / 2, sxy / 2, 2 * d * d, syz / 2], axis=-1),
        np.stack([dxy / 2, sxz / 2, syz / 2, 2 * d * d], axis=-1),
    ], axis=-2)
    q = np.take_along_axis(candidates, largest[..., None, None], axis=-2)[..., 0, :] / d[..., None]
    q /= np.linalg.norm(q, axis=-1, keepdims=True)
    return np.where(q[..., :1] < 0, -q, q)


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
    if degrees:
        angles = np.radians(angles)
    factors = [_elementary(axis, angles[..., i]) for i, axis in enumerate(conv.axes)]
    a, b, c = reversed(factors) if conv.extrinsic else factors
    return a @ b @ c


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
    quat = _quaternion_wxyz(R)
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
    return _quaternion_wxyz(_finite(R, "rotation matrix", (3, 3)))


def matrix_from_quaternion_wxyz(q_wxyz: ArrayLike) -> NDArray[np.float64]:
    """Rotation matrices ``(..., 3, 3)`` from quaternions ``(..., 4)`` in ``w, x, y, z`` order.

    Raises
    ------
    InputError
        If a quaternion has zero norm (it is normalised otherwise).
    """
    q = _finite(q_wxyz, "quaternion", (4,))
    size = np.linalg.norm(q, axis=-1, keepdims=True)
    if np.any(size < 1e-12):
        raise InputError("quaternion: expected a non-zero quaternion, got norm 0")
    w, x, y, z = np.moveaxis(q / size, -1, 0)
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], axis=-1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], axis=-1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=-1),
    ], axis=-2)


def axis_angle_from_matrix(R: ArrayLike) -> NDArray[np.float64]:
    """Rotation vectors ``(..., 3)``: unit axis times angle [rad], angle in ``[0, pi]``."""
    q = _quaternion_wxyz(_finite(R, "rotation matrix", (3, 3)))
    sine = np.linalg.norm(q[..., 1:], axis=-1)  # sin(angle / 2), with w = cos(angle / 2) >= 0
    angle = 2.0 * np.arctan2(sine, q[..., 0])
    # angle / sin(angle / 2) -> 2 for small angles
    scale = np.divide(angle, sine, out=np.full_like(angle, 2.0), where=sine > 1e-300)
    return q[..., 1:] * scale[..., None]


def matrix_from_axis_angle(rotation_vector: ArrayLike) -> NDArray[np.float64]:
    """Rotation matrices ``(..., 3, 3)`` from rotation vectors (axis times angle [rad])."""
    v = _finite(rotation_vector, "rotation vector", (3,))
    angle = np.linalg.norm(v, axis=-1, keepdims=True)
    half_sinc = 0.5 * np.sinc(angle / (2 * np.pi))  # sin(angle / 2) / angle, 1/2 at 0
    return matrix_from_quaternion_wxyz(np.concatenate([np.cos(angle / 2), half_sinc * v], axis=-1))


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
        R = R @ _elementary(axis, theta[..., k])
    return E
