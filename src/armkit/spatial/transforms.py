"""Homogeneous transforms: elementary rotations and translations, checks, inverses.

All functions are batch-first: an input of shape ``(...,)`` gives ``(..., 4, 4)``.
Lengths in metres, angles in radians.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit import _core
from armkit.errors import InputError
from armkit.spatial.rotations import AngleConvention, euler_from_matrix, matrix_from_euler

__all__ = [
    "check_transform",
    "invert_transform",
    "pose_from_transform",
    "rot_x",
    "rot_z",
    "transform_from",
    "transform_from_pose",
    "trans_x",
    "trans_z",
]

#: Tolerance on ``R^T R - I`` and ``det R - 1`` for a matrix to count as a rigid transform
#: (a rotation printed with six decimals deviates by up to about 2e-6; the core's
#: ``kRigidTolerance``).
RIGID_TOLERANCE: float = _core.RIGID_TOLERANCE


def _identity_batch(shape: tuple[int, ...]) -> NDArray[np.float64]:
    return np.broadcast_to(np.eye(4), (*shape, 4, 4)).copy()


def rot_x(angle: ArrayLike) -> NDArray[np.float64]:
    """Rotation about x by ``angle`` [rad], shape ``(..., 4, 4)``."""
    angle = np.asarray(angle, dtype=float)
    c, s = np.cos(angle), np.sin(angle)
    T = _identity_batch(angle.shape)
    T[..., 1, 1], T[..., 1, 2], T[..., 2, 1], T[..., 2, 2] = c, -s, s, c
    return T


def rot_z(angle: ArrayLike) -> NDArray[np.float64]:
    """Rotation about z by ``angle`` [rad], shape ``(..., 4, 4)``."""
    angle = np.asarray(angle, dtype=float)
    c, s = np.cos(angle), np.sin(angle)
    T = _identity_batch(angle.shape)
    T[..., 0, 0], T[..., 0, 1], T[..., 1, 0], T[..., 1, 1] = c, -s, s, c
    return T


def trans_x(distance: ArrayLike) -> NDArray[np.float64]:
    """Translation along x by ``distance`` [m], shape ``(..., 4, 4)``."""
    distance = np.asarray(distance, dtype=float)
    T = _identity_batch(distance.shape)
    T[..., 0, 3] = distance
    return T


def trans_z(distance: ArrayLike) -> NDArray[np.float64]:
    """Translation along z by ``distance`` [m], shape ``(..., 4, 4)``."""
    distance = np.asarray(distance, dtype=float)
    T = _identity_batch(distance.shape)
    T[..., 2, 3] = distance
    return T


def transform_from(rotation: ArrayLike, position: ArrayLike) -> NDArray[np.float64]:
    """Assemble ``(..., 4, 4)`` transforms from rotations ``(..., 3, 3)`` and positions ``(..., 3)``."""
    rotation = np.asarray(rotation, dtype=float)
    position = np.asarray(position, dtype=float)
    shape = np.broadcast_shapes(rotation.shape[:-2], position.shape[:-1])
    T = _identity_batch(shape)
    T[..., :3, :3] = rotation
    T[..., :3, 3] = position
    return T


def invert_transform(T: ArrayLike) -> NDArray[np.float64]:
    """Inverse of rigid transforms ``(..., 4, 4)``, using ``R^T`` rather than a general inverse."""
    T = np.asarray(T, dtype=float)
    R_t = np.swapaxes(T[..., :3, :3], -1, -2)
    return transform_from(R_t, -np.einsum("...ij,...j->...i", R_t, T[..., :3, 3]))


def check_transform(T: ArrayLike, name: str = "pose") -> NDArray[np.float64]:
    """Return ``T`` as float64 ``(..., 4, 4)`` after checking that it is a rigid transform.

    A rotation part that is orthonormal only to within ``RIGID_TOLERANCE`` (a matrix
    printed with six decimals, say) is replaced by the nearest rotation matrix (SVD
    projection), so what follows works with an exactly rigid pose.

    Raises
    ------
    InputError
        If the shape is not ``(..., 4, 4)``, a value is not finite, the last row is not
        ``[0, 0, 0, 1]`` or the rotation part is not orthonormal with determinant +1
        (tolerance ``RIGID_TOLERANCE``).
    """
    try:
        T = np.asarray(T, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{name}: expected a 4x4 numeric matrix, got {T!r}") from exc
    if T.ndim < 2 or T.shape[-2:] != (4, 4):
        raise InputError(f"{name}: expected shape (..., 4, 4), got {T.shape}")
    flat = np.ascontiguousarray(T.reshape(-1, 4, 4))
    finite, last_row, orthonormal, rough = _core.rigidity(flat)  # one pass in the core
    if not finite:
        raise InputError(f"{name}: contains NaN or infinite values")
    if last_row > RIGID_TOLERANCE:
        raise InputError(f"{name}: last row must be [0, 0, 0, 1], got {T[..., 3, :].tolist()}")
    if orthonormal > RIGID_TOLERANCE:
        R = flat[:, :3, :3]
        orth = np.abs(np.swapaxes(R, -1, -2) @ R - np.eye(3)).max(axis=(-1, -2))
        det = np.linalg.det(R)
        worst = np.argmax(np.maximum(orth, np.abs(det - 1.0)))
        raise InputError(
            f"{name}: rotation part is not a rotation matrix (max |R^T R - I| = "
            f"{orth.max():.3g}, det R = {det[worst]:.6g}); "
            f"expected an orthonormal matrix with determinant +1"
        )
    if rough:  # orthonormal only to within RIGID_TOLERANCE: the nearest rotation matrix
        flat = flat.copy()
        R = flat[:, :3, :3]
        off = np.abs(np.swapaxes(R, -1, -2) @ R - np.eye(3)).max(axis=(-1, -2)) > 1e-14
        U, _, Vt = np.linalg.svd(R[off])
        flat[off, :3, :3] = U @ Vt
        return flat.reshape(T.shape)
    return T


def pose_from_transform(T: ArrayLike, convention: str | AngleConvention = "xyz-fixed",
                        degrees: bool = False) -> NDArray[np.float64]:
    """Poses ``(..., 6)``, position [m] then three angles in ``convention``, from transforms.

    Parameters
    ----------
    T : array_like, shape (..., 4, 4)
        Rigid transforms (not checked; see :func:`check_transform`).
    convention : str
        Angle convention, e.g. ``"xyz-fixed"`` (roll, pitch, yaw); see :mod:`armkit.spatial.rotations`.
    degrees : bool
        Whether the angles come out in degrees (the position stays in metres).

    Examples
    --------
    >>> pose_from_transform(transform_from(rot_x(np.pi / 2)[:3, :3], [0.1, 0, 0.2])).round(4)
    array([0.1   , 0.    , 0.2   , 1.5708, 0.    , 0.    ])
    """
    T = np.asarray(T, dtype=float)
    return np.concatenate([T[..., :3, 3], euler_from_matrix(T, convention, degrees)], axis=-1)


def transform_from_pose(pose: ArrayLike, convention: str | AngleConvention = "xyz-fixed",
                        degrees: bool = False) -> NDArray[np.float64]:
    """Transforms ``(..., 4, 4)`` from poses ``(..., 6)``: x y z [m] then three angles.

    The inverse of :func:`pose_from_transform` (same ``convention`` and ``degrees``).

    Raises
    ------
    InputError
        If the last axis does not hold 6 values or a value is not finite.

    Examples
    --------
    >>> transform_from_pose([0.1, 0, 0.2, 90, 0, 0], degrees=True)[:3, 3]
    array([0.1, 0. , 0.2])
    """
    try:
        pose = np.asarray(pose, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InputError(f"pose: expected numbers x y z a b c, got {pose!r}") from exc
    if pose.ndim == 0 or pose.shape[-1] != 6:
        raise InputError(f"pose: expected 6 values (x y z a b c), got shape {pose.shape}")
    if not np.all(np.isfinite(pose)):
        raise InputError(f"pose: contains NaN or infinite values: {pose.tolist()}")
    return transform_from(matrix_from_euler(pose[..., 3:], convention, degrees), pose[..., :3])
