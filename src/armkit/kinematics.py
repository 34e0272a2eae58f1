"""Forward kinematics, Jacobians and manipulability of a :class:`~armkit.chain.Chain`.

All functions take joint values ``q`` of shape ``(..., n)`` (a single configuration is
a batch of one) and loop over the ``n`` joints only, never over the batch. Jacobian rows
are ``[v; w]``: linear velocity of the tool origin [m/s] over angular velocity [rad/s].

Solver and control loops evaluate one configuration at a time, thousands of times; for
them :class:`ChainKernel` gives the same tool pose and Jacobian from compiled code (numba:
:func:`chain_frames` and :func:`chain_jacobian`, which compiled solvers call directly), about
1 us for a 6- or 7-joint arm, where :func:`fk` plus :func:`geometric_jacobian` of one
configuration take over 100 us.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit
from numpy.typing import ArrayLike, NDArray

from armkit.chain import Chain
from armkit.errors import InputError
from armkit.spatial.rotations import angular_velocity_matrix, euler_from_matrix

__all__ = [
    "ChainKernel",
    "analytic_jacobian",
    "chain_frames",
    "chain_jacobian",
    "chain_pose",
    "fk",
    "geometric_jacobian",
    "joint_frames",
    "link_frames",
    "manipulability",
    "pose_error",
    "pose_error_into",
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


def _joint_values(chain: Chain, q: ArrayLike) -> NDArray[np.float64]:
    """``q`` as float64 ``(..., n)``, or :class:`InputError` naming the expected and actual shape."""
    try:
        q = np.asarray(q, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InputError(f"q: expected {chain.n} joint values (shape (..., {chain.n})), "
                         f"got {q!r}") from exc
    if q.shape[-1:] != (chain.n,):
        got = "a scalar" if q.ndim == 0 else f"shape {q.shape}"
        raise InputError(f"q: the chain has {chain.n} joints, so expected joint values of shape "
                         f"(..., {chain.n}), got {got}")
    if not np.isfinite(q).all():
        first = np.argwhere(~np.isfinite(q))[0]
        raise InputError(f"q: expected finite joint values, got {q[tuple(first)]} at index "
                         f"{tuple(first.tolist()) if q.ndim > 1 else int(first[0])}")
    return q


def _start(chain: Chain, q: NDArray[np.float64]) -> NDArray[np.float64]:
    return np.broadcast_to(chain.T_between[0], (*q.shape[:-1], 4, 4)).copy()


def fk(chain: Chain, q: ArrayLike) -> NDArray[np.float64]:
    """Tool poses ``T_base_tool`` [m], shape ``(..., 4, 4)``, for joint values ``(..., n)``.

    Raises
    ------
    InputError
        If ``q`` is not numbers of shape ``(..., n)`` or holds NaN or infinity (also in
        :func:`joint_frames`, :func:`link_frames` and :func:`geometric_jacobian`).
    """
    return _fk(chain, _joint_values(chain, q))


# The unchecked forms below are for callers that have checked q already (Robot.check_q).
def _fk(chain: Chain, q: NDArray[np.float64]) -> NDArray[np.float64]:
    if q.ndim == 1:  # one configuration: the compiled kernel (~2 us against ~60 us for the loop)
        return _pose(*chain._kernel_arrays, np.ascontiguousarray(q))
    T = _start(chain, q)
    for i, joint in enumerate(chain.joints):
        _apply_motion(T, q[..., i], joint.kind == "prismatic")
        T = T @ chain.T_between[i + 1]
    return T


def joint_frames(chain: Chain, q: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Joint frames (after each motion) ``(..., n, 4, 4)`` and the tool pose ``(..., 4, 4)``.

    Joint ``i`` moves about or along the z axis of frame ``i`` of the first result.
    """
    return _joint_frames(chain, _joint_values(chain, q))


def _joint_frames(chain: Chain, q: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    T = _start(chain, q)
    frames = np.empty((*q.shape[:-1], chain.n, 4, 4))
    for i, joint in enumerate(chain.joints):
        _apply_motion(T, q[..., i], joint.kind == "prismatic")
        frames[..., i, :, :] = T
        T = T @ chain.T_between[i + 1]
    return frames, T


def link_frames(chain: Chain, q: ArrayLike) -> NDArray[np.float64]:
    """Poses of the base, every DH link frame and the tool: ``(..., n + 2, 4, 4)``.

    Index 0 is the base frame (after any base rows), ``i`` is link frame ``i`` of the DH
    table (after joint ``i``), and ``n + 1`` is the tool.
    """
    return _link_frames(chain, _joint_values(chain, q))


def _link_frames(chain: Chain, q: NDArray[np.float64]) -> NDArray[np.float64]:
    frames, T_tool = _joint_frames(chain, q)
    base = np.broadcast_to(chain.T_base, (*q.shape[:-1], 1, 4, 4))
    links = frames @ np.stack([j.T_after for j in chain.joints])
    return np.concatenate([base, links, T_tool[..., None, :, :]], axis=-3)


def geometric_jacobian(chain: Chain, q: ArrayLike,
                       frame: str = "base") -> NDArray[np.float64]:
    """Geometric Jacobian ``(..., 6, n)``, rows ``[v; w]``.

    Parameters
    ----------
    frame : {"base", "tool"}
        Frame the twist is expressed in. ``"base"``: ``[v; w]`` of the tool origin in base
        coordinates; ``"tool"``: the same twist in tool coordinates.
    """
    return _geometric_jacobian(chain, _joint_values(chain, q), frame)


def _geometric_jacobian(chain: Chain, q: NDArray[np.float64], frame: str = "base") -> NDArray[np.float64]:
    if frame not in ("base", "tool"):
        raise InputError(f"frame {frame!r}: expected 'base' or 'tool'")
    if q.ndim == 1:  # one configuration: the compiled kernels (~5 us against ~100 us below)
        T_tool, J = _pose_jacobian(*chain._kernel_arrays, np.ascontiguousarray(q))
    else:
        frames, T_tool = _joint_frames(chain, q)
        z = frames[..., :3, 2]
        r = T_tool[..., None, :3, 3] - frames[..., :3, 3]
        prismatic = chain.prismatic
        v = np.where(prismatic[:, None], z, np.cross(z, r))
        w = np.where(prismatic[:, None], 0.0, z)
        J = np.concatenate([np.swapaxes(v, -1, -2), np.swapaxes(w, -1, -2)], axis=-2)
    if frame == "base":
        return J
    R_t = np.swapaxes(T_tool[..., :3, :3], -1, -2)
    return np.concatenate([R_t @ J[..., :3, :], R_t @ J[..., 3:, :]], axis=-2)


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
    q = _joint_values(chain, q)
    J = _geometric_jacobian(chain, q)
    T = _fk(chain, q)
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


#: Below this ``|2 sin(angle)|`` (angle within 5e-3 rad of ``pi``) :func:`pose_error` takes the
#: axis from the symmetric part of the rotation: ``v / |v|`` would lose ``eps / |v|`` there.
HALF_TURN_NORM = 1e-2


def pose_error(T_target: ArrayLike, T: ArrayLike) -> NDArray[np.float64]:
    """Pose errors ``(..., 6)``: ``p_target - p`` [m] and the rotation vector of ``R_target R^T`` [rad].

    Both parts are in the base frame; the rotation vector's norm is the angle between
    the two orientations, exact (to rounding) up to and at ``pi``. Inputs ``(..., 4, 4)`` broadcast.

    Examples
    --------
    >>> from armkit.spatial import matrix_from_axis_angle, transform_from
    >>> T = transform_from(np.eye(3), [0.1, 0.0, 0.0])
    >>> T_target = transform_from(matrix_from_axis_angle([0.0, 0.0, 0.3]), [0.1, 0.2, 0.0])
    >>> pose_error(T_target, T).round(12) + 0.0
    array([0. , 0.2, 0. , 0. , 0. , 0.3])
    """
    T_target, T = np.asarray(T_target, dtype=float), np.asarray(T, dtype=float)
    R = T_target[..., :3, :3] @ np.swapaxes(T[..., :3, :3], -1, -2)
    flat = R.reshape(*R.shape[:-2], 9)
    e = np.empty((*R.shape[:-2], 6))
    e[..., :3] = T_target[..., :3, 3] - T[..., :3, 3]
    v = flat[..., [7, 2, 3]] - flat[..., [5, 6, 1]]  # 2 sin(angle) * axis
    norm = np.sqrt(np.einsum("...i,...i->...", v, v))
    trace = flat[..., 0] + flat[..., 4] + flat[..., 8]
    angle = np.arctan2(norm, trace - 1.0)
    # angle / (2 sin angle) -> 1/2 for small angles
    scale = np.divide(angle, norm, out=np.full_like(angle, 0.5), where=norm > 1e-300)
    e[..., 3:] = v * scale[..., None]
    half_turn = (norm <= HALF_TURN_NORM) & (trace <= 0.0)
    if np.any(half_turn):  # near pi v / |v| loses digits: axis from R + R^T, same angle
        e[half_turn, 3:] = angle[half_turn, None] * _half_turn_axis(R[half_turn], trace[half_turn],
                                                                      v[half_turn])
    return e


def _half_turn_axis(R: NDArray[np.float64], trace: NDArray[np.float64],
                    v: NDArray[np.float64]) -> NDArray[np.float64]:
    """Unit axes ``(k, 3)`` of rotations ``R`` ``(k, 3, 3)`` near a half turn.

    ``(R + R^T) / 2 - cos(angle) I = (1 - cos(angle)) axis axis^T``: its column with the
    largest diagonal entry is the axis times a factor. The sign is that of ``v`` (``2
    sin(angle) axis``), which decides it whenever the angle is not exactly ``pi``.
    """
    S = 0.5 * (R + np.swapaxes(R, -1, -2))
    S -= ((trace - 1.0) / 2.0)[:, None, None] * np.eye(3)
    k = np.argmax(np.diagonal(S, axis1=-2, axis2=-1), axis=-1)
    axis = np.take_along_axis(S, k[:, None, None], axis=-1)[..., 0]
    axis /= np.linalg.norm(axis, axis=-1, keepdims=True)
    flip = np.einsum("...i,...i->...", axis, v) < 0.0
    axis[flip] *= -1.0
    return axis


@njit(cache=True)
def pose_error_into(T_target: NDArray[np.float64], T: NDArray[np.float64], e: NDArray[np.float64]) -> None:
    """Compiled :func:`pose_error` of ONE pose ``T`` ``(4, 4)`` to ``T_target``, written into ``e`` ``(6,)``.

    The same formulas, the half-turn case included (axis from ``R + R^T`` when
    ``2 sin(angle) <= HALF_TURN_NORM`` and the trace is not positive).
    """
    X = np.empty((3, 3))  # R_target R^T
    for a in range(3):
        e[a] = T_target[a, 3] - T[a, 3]
        for b in range(3):
            X[a, b] = T_target[a, 0] * T[b, 0] + T_target[a, 1] * T[b, 1] + T_target[a, 2] * T[b, 2]
    vx, vy, vz = X[2, 1] - X[1, 2], X[0, 2] - X[2, 0], X[1, 0] - X[0, 1]  # 2 sin(angle) * axis
    norm = math.sqrt(vx * vx + vy * vy + vz * vz)
    trace = X[0, 0] + X[1, 1] + X[2, 2]
    angle = math.atan2(norm, trace - 1.0)
    if norm <= HALF_TURN_NORM and trace <= 0.0:  # axis from the symmetric part, as _half_turn_axis
        cosine = (trace - 1.0) / 2.0
        k = 0
        for j in (1, 2):
            if X[j, j] - cosine > X[k, k] - cosine:
                k = j
        ax = 0.5 * (X[0, k] + X[k, 0]) - (cosine if k == 0 else 0.0)
        ay = 0.5 * (X[1, k] + X[k, 1]) - (cosine if k == 1 else 0.0)
        az = 0.5 * (X[2, k] + X[k, 2]) - (cosine if k == 2 else 0.0)
        scale = angle / math.sqrt(ax * ax + ay * ay + az * az)
        if ax * vx + ay * vy + az * vz < 0.0:
            scale = -scale
        e[3], e[4], e[5] = scale * ax, scale * ay, scale * az
        return
    scale = angle / norm if norm > 1e-300 else 0.5  # angle / (2 sin angle) -> 1/2 for small angles
    e[3], e[4], e[5] = scale * vx, scale * vy, scale * vz


@njit(cache=True)
def chain_frames(T_between: NDArray[np.float64], prismatic: NDArray[np.bool_], q: NDArray[np.float64],
                 T: NDArray[np.float64], axes: NDArray[np.float64], points: NDArray[np.float64]) -> None:
    """Compiled FK of ONE configuration, written into work arrays (no checks, no allocation).

    ``T`` ``(4, 4)`` receives the tool pose, ``axes`` ``(n, 3)`` the z axis of every joint
    frame and ``points`` ``(n, 3)`` its origin before the joint's motion (the same point
    for a revolute joint, the start of the travel for a prismatic one), all in the base
    frame. ``T_between`` ``(n + 1, 4, 4)`` is :attr:`armkit.chain.Chain.T_between`,
    ``prismatic`` ``(n,)`` the chain's prismatic mask and ``q`` ``(n,)`` float64 [rad or m].

    Examples
    --------
    >>> import armkit
    >>> chain = armkit.load("ur5").chain
    >>> q = np.array([0.1, -1.2, 1.5, -0.3, 1.6, 0.2])
    >>> T, axes, points, J = np.empty((4, 4)), np.empty((6, 3)), np.empty((6, 3)), np.empty((6, 6))
    >>> chain_frames(chain.T_between, chain.prismatic, q, T, axes, points)
    >>> chain_jacobian(T, axes, points, chain.prismatic, J)
    >>> bool(np.allclose(T, fk(chain, q), atol=1e-14)), bool(np.allclose(J, geometric_jacobian(chain, q)))
    (True, True)
    """
    _copy_transform(T_between[0], T)
    for i in range(q.shape[0]):
        for r in range(3):
            axes[i, r] = T[r, 2]
            points[i, r] = T[r, 3]
        _advance(T, q[i], prismatic[i], T_between[i + 1])


@njit(cache=True)
def chain_pose(T_between: NDArray[np.float64], prismatic: NDArray[np.bool_], q: NDArray[np.float64],
               T: NDArray[np.float64]) -> None:
    """Compiled FK of ONE configuration: the tool pose written into ``T`` ``(4, 4)``.

    :func:`chain_frames` without the joint axes and points (verification loops).
    """
    _copy_transform(T_between[0], T)
    for i in range(q.shape[0]):
        _advance(T, q[i], prismatic[i], T_between[i + 1])


@njit(cache=True)
def _copy_transform(source: NDArray[np.float64], T: NDArray[np.float64]) -> None:
    for r in range(4):  # loops, not slice assignments: those cost seconds of compile time
        for k in range(4):
            T[r, k] = source[r, k]


@njit(cache=True)
def _advance(T: NDArray[np.float64], q_i: float, prismatic_i: bool, L: NDArray[np.float64]) -> None:
    """``T <- T Rz(q_i) L`` (or ``T Tz(q_i) L``) for rigid transforms: only the top three
    rows change (the last stays ``[0, 0, 0, 1]``, as does ``L``'s)."""
    if prismatic_i:
        for r in range(3):
            T[r, 3] += q_i * T[r, 2]
    else:
        c, s = math.cos(q_i), math.sin(q_i)
        for r in range(3):
            x, y = T[r, 0], T[r, 1]
            T[r, 0] = c * x + s * y
            T[r, 1] = c * y - s * x
    for r in range(3):
        a0, a1, a2, a3 = T[r, 0], T[r, 1], T[r, 2], T[r, 3]
        for k in range(3):
            T[r, k] = a0 * L[0, k] + a1 * L[1, k] + a2 * L[2, k]
        T[r, 3] = a0 * L[0, 3] + a1 * L[1, 3] + a2 * L[2, 3] + a3


@njit(cache=True)
def chain_jacobian(T: NDArray[np.float64], axes: NDArray[np.float64], points: NDArray[np.float64],
                   prismatic: NDArray[np.bool_], J: NDArray[np.float64]) -> None:
    """Compiled base-frame geometric Jacobian ``(6, n)`` written into ``J``, rows ``[v; w]``.

    From the tool pose, axes and points of :func:`chain_frames`: column ``i`` is
    ``[z_i x (p - o_i); z_i]`` for a revolute joint, ``[z_i; 0]`` for a prismatic one.
    """
    px, py, pz = T[0, 3], T[1, 3], T[2, 3]
    for i in range(axes.shape[0]):
        zx, zy, zz = axes[i, 0], axes[i, 1], axes[i, 2]
        if prismatic[i]:
            J[0, i], J[1, i], J[2, i] = zx, zy, zz
            J[3, i] = J[4, i] = J[5, i] = 0.0
        else:
            rx, ry, rz = px - points[i, 0], py - points[i, 1], pz - points[i, 2]
            J[0, i], J[1, i], J[2, i] = zy * rz - zz * ry, zz * rx - zx * rz, zx * ry - zy * rx
            J[3, i], J[4, i], J[5, i] = zx, zy, zz


@njit(cache=True)
def _pose(T_between: NDArray[np.float64], prismatic: NDArray[np.bool_],
          q: NDArray[np.float64]) -> NDArray[np.float64]:
    T = np.empty((4, 4))
    chain_pose(T_between, prismatic, q, T)
    return T


@njit(cache=True)
def _pose_jacobian(T_between: NDArray[np.float64], prismatic: NDArray[np.bool_],
                   q: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    n = q.shape[0]
    T, J, axes, points = np.empty((4, 4)), np.empty((6, n)), np.empty((n, 3)), np.empty((n, 3))
    chain_frames(T_between, prismatic, q, T, axes, points)
    chain_jacobian(T, axes, points, prismatic, J)
    return T, J


@njit(cache=True)
def _joint_axes(T_between: NDArray[np.float64], prismatic: NDArray[np.bool_],
                q: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    n = q.shape[0]
    axes, points = np.empty((n, 3)), np.empty((n, 3))
    chain_frames(T_between, prismatic, q, np.empty((4, 4)), axes, points)
    return axes, points


class ChainKernel:
    """Tool pose and geometric Jacobian of ONE configuration, for solver and control loops.

    The same results as :func:`fk`, :func:`joint_frames` and :func:`geometric_jacobian`
    (to rounding) from one call of compiled code (numba, :func:`chain_frames` and
    :func:`chain_jacobian`): about 1 us for a 6- or 7-joint arm, where :func:`fk` plus
    :func:`geometric_jacobian` of one configuration take over 100 us. The first call in a
    fresh environment compiles the kernels (cached on disk afterwards). Inputs are not
    checked: ``q`` must be a float64 array of shape ``(n,)``. Every returned array is new.

    Parameters
    ----------
    chain : Chain

    Examples
    --------
    >>> import armkit
    >>> robot = armkit.load("panda")
    >>> kernel = ChainKernel(robot.chain)
    >>> q = np.array([0.1, -0.3, 0.2, -2.0, 0.1, 1.8, 0.5])
    >>> T, J = kernel.pose_jacobian(q)
    >>> bool(np.allclose(T, fk(robot.chain, q), atol=1e-14))
    True
    >>> bool(np.allclose(J, geometric_jacobian(robot.chain, q), atol=1e-14))
    True
    """

    def __init__(self, chain: Chain) -> None:
        self.n = chain.n
        # the chain's fixed transforms (n + 1, 4, 4) and prismatic mask (n,) as the kernels take them
        self._arrays = chain._kernel_arrays

    def pose(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        """Tool pose ``T_base_tool`` ``(4, 4)`` at joint values ``q`` ``(n,)`` [rad or m]."""
        return _pose(*self._arrays, q)

    def pose_jacobian(self, q: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Tool pose ``(4, 4)`` and base-frame geometric Jacobian ``(6, n)``, rows ``[v; w]``."""
        return _pose_jacobian(*self._arrays, q)

    def jacobian(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        """Base-frame geometric Jacobian ``(6, n)``, rows ``[v; w]`` [m/s, rad/s per joint rate]."""
        return _pose_jacobian(*self._arrays, q)[1]

    def joint_axes(self, q: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Joint axes ``(n, 3)`` (unit vectors) and points on them ``(n, 3)`` [m], base frame.

        Row ``i`` is the z axis of joint frame ``i`` (see :func:`joint_frames`) and its
        origin before the joint's motion: the same point for a revolute joint, the start
        of the travel (``q_i = 0``) for a prismatic one.
        """
        return _joint_axes(*self._arrays, q)
