"""Forward kinematics, Jacobians and manipulability of a :class:`~armkit.chain.Chain`.

All functions take joint values ``q`` of shape ``(..., n)`` (a single configuration is
a batch of one) and loop over the ``n`` joints only, never over the batch. Jacobian rows
are ``[v; w]``: linear velocity of the tool origin [m/s] over angular velocity [rad/s].
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from armkit.chain import Chain
from armkit.errors import InputError
from armkit.spatial.rotations import angular_velocity_matrix, euler_from_matrix

__all__ = [
    "analytic_jacobian",
    "fk",
    "geometric_jacobian",
    "joint_frames",
    "link_frames",
    "manipulability",
    "singular_values",
]


def _apply_motion(T: NDArray[np.float64], q_i: NDArray[np.float64], prismatic: bool) -> None:
    """Right-multiply ``T`` in place by ``Tz(q_i)`` or ``Rz(q_i)``."""
    if prismatic:
        T[..., :, 3] += q_i[..., None] * T[..., :, 2]
        return
    c, s = np.cos(q_i)[..., None], np.sin(q_i)[..., None]
    x, y = T[..., :, 0].copy(), T[..., :, 1]
    T[..., :, 0] = c * x + s * y
    T[..., :, 1] = c * y - s * x


def _start(chain: Chain, q: NDArray[np.float64]) -> NDArray[np.float64]:
    return np.broadcast_to(chain.T_between[0], (*q.shape[:-1], 4, 4)).copy()


def fk(chain: Chain, q: NDArray[np.float64]) -> NDArray[np.float64]:
    """Tool poses ``T_base_tool``, shape ``(..., 4, 4)``, for joint values ``(..., n)``."""
    T = _start(chain, q)
    for i, joint in enumerate(chain.joints):
        _apply_motion(T, q[..., i], joint.kind == "prismatic")
        T = T @ chain.T_between[i + 1]
    return T


def joint_frames(chain: Chain, q: NDArray[np.float64]) -> tuple[NDArray[np.float64],
                                                                  NDArray[np.float64]]:
    """Joint frames (after each motion) ``(..., n, 4, 4)`` and the tool pose ``(..., 4, 4)``.

    Joint ``i`` moves about or along the z axis of frame ``i`` of the first result.
    """
    T = _start(chain, q)
    frames = np.empty((*q.shape[:-1], chain.n, 4, 4))
    for i, joint in enumerate(chain.joints):
        _apply_motion(T, q[..., i], joint.kind == "prismatic")
        frames[..., i, :, :] = T
        T = T @ chain.T_between[i + 1]
    return frames, T


def link_frames(chain: Chain, q: NDArray[np.float64]) -> NDArray[np.float64]:
    """Poses of the base, every DH link frame and the tool: ``(..., n + 2, 4, 4)``.

    Index 0 is the base frame (after any base rows), ``i`` is link frame ``i`` of the DH
    table (after joint ``i``), and ``n + 1`` is the tool.
    """
    frames, T_tool = joint_frames(chain, q)
    base = np.broadcast_to(chain.T_base, (*q.shape[:-1], 1, 4, 4))
    links = frames @ np.stack([j.T_after for j in chain.joints])
    return np.concatenate([base, links, T_tool[..., None, :, :]], axis=-3)


def geometric_jacobian(chain: Chain, q: NDArray[np.float64],
                       frame: str = "base") -> NDArray[np.float64]:
    """Geometric Jacobian ``(..., 6, n)``, rows ``[v; w]``.

    Parameters
    ----------
    frame : {"base", "tool"}
        Frame the twist is expressed in. ``"base"``: ``[v; w]`` of the tool origin in base
        coordinates; ``"tool"``: the same twist in tool coordinates.
    """
    frames, T_tool = joint_frames(chain, q)
    z = frames[..., :3, 2]
    r = T_tool[..., None, :3, 3] - frames[..., :3, 3]
    prismatic = chain.prismatic
    v = np.where(prismatic[:, None], z, np.cross(z, r))
    w = np.where(prismatic[:, None], 0.0, z)
    J = np.concatenate([np.swapaxes(v, -1, -2), np.swapaxes(w, -1, -2)], axis=-2)
    if frame == "base":
        return J
    if frame == "tool":
        R_t = np.swapaxes(T_tool[..., :3, :3], -1, -2)
        return np.concatenate([R_t @ J[..., :3, :], R_t @ J[..., 3:, :]], axis=-2)
    raise InputError(f"frame {frame!r}: expected 'base' or 'tool'")


def analytic_jacobian(chain: Chain, q: NDArray[np.float64],
                      convention: str = "xyz-fixed") -> NDArray[np.float64]:
    """Analytic Jacobian ``(..., 6, n)``: rows ``[p'; angle rates]`` in a named convention.

    Relates joint rates to the rates of the tool position and of its angles in
    ``convention`` (see :mod:`armkit.spatial.rotations`).

    Raises
    ------
    InputError
        At a gimbal lock of the convention, where the angle rates are undefined.
    """
    J = geometric_jacobian(chain, q)
    T = fk(chain, q)
    E = angular_velocity_matrix(euler_from_matrix(T, convention), convention)
    det = np.abs(np.linalg.det(E))
    if np.any(det < 1e-9):
        raise InputError(f"the analytic Jacobian in {convention!r} is undefined at this pose: "
                         f"gimbal lock of that convention (use the geometric Jacobian)")
    return np.concatenate([J[..., :3, :], np.linalg.solve(E, J[..., 3:, :])], axis=-2)


def singular_values(chain: Chain, q: NDArray[np.float64]) -> NDArray[np.float64]:
    """Singular values of the base-frame geometric Jacobian, ``(..., min(6, n))``, descending."""
    return np.linalg.svd(geometric_jacobian(chain, q), compute_uv=False)


def manipulability(chain: Chain, q: NDArray[np.float64]) -> NDArray[np.float64]:
    """Yoshikawa's manipulability ``sqrt(det(J J^T))`` (product of singular values), ``(...)``.

    Zero at a singularity. For ``n < 6`` it is the product of the ``n`` singular values,
    i.e. ``sqrt(det(J^T J))``. Linear and angular rows are mixed as they are (m and rad).
    """
    return np.prod(singular_values(chain, q), axis=-1)
