"""Forward kinematics, Jacobians and manipulability of a robot (or its :class:`~armkit.chain.Chain`).

All functions take joint values ``q`` of shape ``(..., n)`` (a single configuration is
a batch of one) and return batch-first arrays. Jacobian rows are ``[v; w]``: linear
velocity of the tool origin [m/s] over angular velocity [rad/s].

The formulas live in armkit's compiled core (``armkit._core``, C++): FK, joint frames,
the geometric Jacobian and the pose error of one configuration cost about half a microsecond
from Python (``benchmarks/bench_fk.py``), and batches are split over ``threads`` (default:
every core) with the same result whatever the thread count. FK and the Jacobian are one
core call each for any batch shape: the core reads ``q`` (a C-ordered float64 array as it is,
anything else as :func:`numpy.asarray` would), checks its values in its loop and returns a new
array; this module only words the errors for joint values the core refuses.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit import _core
from armkit._deprecation import deprecated_method
from armkit._params import core_ready, thread_count
from armkit.chain import Chain, as_chain
from armkit.errors import InputError
from armkit.spatial.rotations import angular_velocity_matrix, euler_from_matrix

if TYPE_CHECKING:  # armkit.robot imports this module
    from armkit.robot import Robot

__all__ = [
    "ChainKernel",
    "analytic_jacobian",
    "fk",
    "geometric_jacobian",
    "joint_frames",
    "link_frames",
    "manipulability",
    "pose_error",
    "singular_values",
]


def _joint_values(chain: Chain, q: ArrayLike) -> NDArray[np.float64]:
    """``q`` as C-ordered float64 ``(..., n)``, or :class:`InputError` naming the expected and
    actual shape. Finiteness is checked by the core, in its loop (see :func:`_raise_if_bad`)."""
    n = chain.n
    if core_ready(q, (n,)):
        return q
    try:
        q = np.asarray(q, dtype=np.float64, order="C")
    except (TypeError, ValueError) as exc:
        raise InputError(f"q: expected {n} joint values (shape (..., {n})), got {q!r}") from exc
    if q.shape[-1:] != (n,):
        got = "a scalar" if q.ndim == 0 else f"shape {q.shape}"
        raise InputError(f"q: the chain has {n} joints, so expected joint values of shape "
                         f"(..., {n}), got {got}")
    return q


def non_finite_error(q: NDArray[np.float64], name: str = "q", bad: int | None = None) -> InputError:
    """The error for the first non-finite value of ``q`` (at flat index ``bad``, if known)."""
    if bad is None:
        bad = int(np.flatnonzero(~np.isfinite(q))[0])
    index = np.unravel_index(bad, q.shape)
    where = tuple(int(i) for i in index) if q.ndim > 1 else int(index[0])
    return InputError(f"{name}: expected finite joint values, got {q.reshape(-1)[bad]} at index {where}")


def _raise_if_bad(q: NDArray[np.float64], bad: int) -> None:
    """Raise :class:`InputError` if the core found a non-finite value at flat index ``bad``."""
    if bad >= 0:
        raise non_finite_error(q, bad=bad)


def _refused(chain: Chain, q: ArrayLike, refused: Exception) -> InputError:
    """The error for joint values the core refused (``_core.RefusedJointValues``: the flat index
    of the first non-finite value, or -1 for values that are not ``(..., n)`` numbers, which
    :func:`_joint_values` raises for in its words)."""
    try:
        values, bad = _joint_values(chain, q), int(str(refused))
    except InputError as error:  # raised by the caller, without the core's refusal as its context
        return error
    if bad < 0:
        return InputError(f"q: expected {chain.n} joint values (shape (..., {chain.n})), got {q!r}")
    return non_finite_error(values, bad=bad)


def fk(robot: Robot | Chain, q: ArrayLike, *, threads: int | None = None) -> NDArray[np.float64]:
    """Tool poses ``T_base_tool`` [m], shape ``(..., 4, 4)``, for joint values ``(..., n)``.

    One core call for any batch shape (a single configuration is a batch of one): it reads
    ``q`` as :func:`numpy.asarray` would, checks its values in its loop and writes the poses
    into the array it returns.

    Parameters
    ----------
    robot : Robot or Chain
        The arm (every function here takes a Robot or its Chain, see :func:`armkit.chain.as_chain`).
    q : array_like, shape (..., n)
        Joint values [rad or m].
    threads : int, optional
        Threads for a batch: ``None`` (default) every core, else 1 to 1024; the result
        does not depend on it.

    Raises
    ------
    InputError
        If ``q`` is not numbers of shape ``(..., n)`` or holds NaN or infinity (also in
        :func:`joint_frames`, :func:`link_frames` and :func:`geometric_jacobian`).

    Examples
    --------
    >>> import armkit
    >>> fk(armkit.load("ur5"), np.zeros((1000, 6))).shape
    (1000, 4, 4)
    """
    return _fk(as_chain(robot), q, thread_count(threads))


def _fk(chain: Chain, q: ArrayLike, threads: int = 0) -> NDArray[np.float64]:
    """:func:`fk` of a chain, ``threads`` checked."""
    try:
        return _core.fk(chain._core, q, threads)
    except _core.RefusedJointValues as refused:
        raise _refused(chain, q, refused) from None


def joint_frames(robot: Robot | Chain, q: ArrayLike, *,
                 threads: int | None = None) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Joint frames (after each motion) ``(..., n, 4, 4)`` and the tool pose ``(..., 4, 4)``.

    Joint ``i`` moves about or along the z axis of frame ``i`` of the first result.
    """
    chain = as_chain(robot)
    return _joint_frames(chain, _joint_values(chain, q), thread_count(threads))


def _joint_frames(chain: Chain, q: NDArray[np.float64],
                  threads: int = 0) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    frames, T = np.empty((*q.shape[:-1], chain.n, 4, 4)), np.empty((*q.shape[:-1], 4, 4))
    _raise_if_bad(q, _core.joint_frames(chain._core, q, frames, T, threads))
    return frames, T


def link_frames(robot: Robot | Chain, q: ArrayLike) -> NDArray[np.float64]:
    """Poses of the base, every DH link frame and the tool: ``(..., n + 2, 4, 4)``.

    Index 0 is the base frame (after any base rows), ``i`` is link frame ``i`` of the DH
    table (after joint ``i``), and ``n + 1`` is the tool.
    """
    chain = as_chain(robot)
    return link_frames_at(chain, _joint_values(chain, q))


def link_frames_at(chain: Chain, q: NDArray[np.float64]) -> NDArray[np.float64]:
    """:func:`link_frames` of joint values already checked (float64 ``(..., n)``, finite)."""
    frames, T_tool = _joint_frames(chain, q)
    base = np.broadcast_to(chain.T_base, (*q.shape[:-1], 1, 4, 4))
    links = frames @ np.stack([j.T_after for j in chain.joints])
    return np.concatenate([base, links, T_tool[..., None, :, :]], axis=-3)


def geometric_jacobian(robot: Robot | Chain, q: ArrayLike, frame: str = "base", *,
                       threads: int | None = None) -> NDArray[np.float64]:
    """Geometric Jacobian ``(..., 6, n)``, rows ``[v; w]`` (one core call, as :func:`fk`).

    Parameters
    ----------
    frame : {"base", "tool"}
        Frame the twist is expressed in. ``"base"``: ``[v; w]`` of the tool origin in base
        coordinates; ``"tool"``: the same twist in tool coordinates.
    threads : int, optional
        Threads for a batch: ``None`` (default) every core, else 1 to 1024; the result
        does not depend on it.
    """
    return _geometric_jacobian(as_chain(robot), q, frame, thread_count(threads))


#: The frames a Jacobian is expressed in: whether each is the tool frame.
_IS_TOOL_FRAME = {"base": False, "tool": True}


def is_tool_frame(frame: object) -> bool:
    """Whether a Jacobian's ``frame`` (``"base"`` or ``"tool"``) is the tool frame; an
    :class:`InputError` naming any other value."""
    try:
        return _IS_TOOL_FRAME[frame]  # type: ignore[index]
    except (KeyError, TypeError):
        raise InputError(f"frame {frame!r}: expected 'base' or 'tool'", parameter="frame",
                         value=frame) from None


def _geometric_jacobian(chain: Chain, q: ArrayLike, frame: str = "base",
                        threads: int = 0) -> NDArray[np.float64]:
    """:func:`geometric_jacobian` of a chain, ``threads`` checked."""
    tool = is_tool_frame(frame)
    try:
        return _core.jacobian(chain._core, q, tool, threads)
    except _core.RefusedJointValues as refused:
        raise _refused(chain, q, refused) from None


def analytic_jacobian(robot: Robot | Chain, q: NDArray[np.float64],
                      convention: str = "xyz-fixed") -> NDArray[np.float64]:
    """Analytic Jacobian ``(..., 6, n)``: rows ``[p'; angle rates]`` in a named convention.

    Relates joint rates to the rates of the tool position and of its angles in
    ``convention`` (see :mod:`armkit.spatial.rotations`).

    Raises
    ------
    InputError
        At a gimbal lock of the convention, where the angle rates are undefined.
    """
    chain = as_chain(robot)
    q = _joint_values(chain, q)
    J = _geometric_jacobian(chain, q)
    T = _fk(chain, q)
    E = angular_velocity_matrix(euler_from_matrix(T, convention), convention)
    det = np.abs(np.linalg.det(E))
    if np.any(det < 1e-9):
        raise InputError(f"the analytic Jacobian in {convention!r} is undefined at this pose: "
                         f"gimbal lock of that convention (use the geometric Jacobian)")
    return np.concatenate([J[..., :3, :], np.linalg.solve(E, J[..., 3:, :])], axis=-2)


def singular_values(robot: Robot | Chain, q: NDArray[np.float64]) -> NDArray[np.float64]:
    """Singular values of the base-frame geometric Jacobian, ``(..., min(6, n))``, descending."""
    return np.linalg.svd(geometric_jacobian(robot, q), compute_uv=False)


def manipulability(robot: Robot | Chain, q: NDArray[np.float64]) -> NDArray[np.float64]:
    """Yoshikawa's manipulability ``sqrt(det(J J^T))`` (product of singular values), ``(...)``.

    Zero at a singularity. For ``n < 6`` it is the product of the ``n`` singular values,
    i.e. ``sqrt(det(J^T J))``. Linear and angular rows are mixed as they are (m and rad).
    """
    return np.prod(singular_values(robot, q), axis=-1)


def pose_error(T_target: ArrayLike, T: ArrayLike) -> NDArray[np.float64]:
    """Pose errors ``(..., 6)``: ``p_target - p`` [m] and the rotation vector of ``R_target R^T`` [rad].

    Both parts are in the base frame; the rotation vector's norm is the angle between
    the two orientations, exact (to rounding) up to and at ``pi`` (near a half turn the
    axis comes from the symmetric part of the rotation). Inputs ``(..., 4, 4)`` broadcast.

    Examples
    --------
    >>> from armkit.spatial import matrix_from_axis_angle, transform_from
    >>> T = transform_from(np.eye(3), [0.1, 0.0, 0.0])
    >>> T_target = transform_from(matrix_from_axis_angle([0.0, 0.0, 0.3]), [0.1, 0.2, 0.0])
    >>> pose_error(T_target, T).round(12) + 0.0
    array([0. , 0.2, 0. , 0. , 0. , 0.3])
    """
    T_target, T = np.broadcast_arrays(np.asarray(T_target, dtype=float), np.asarray(T, dtype=float))
    if T.shape[-2:] != (4, 4):
        raise InputError(f"pose_error: expected transforms of shape (..., 4, 4), got {T.shape}")
    e = np.empty((*T.shape[:-2], 6))
    _core.pose_error(np.ascontiguousarray(T_target), np.ascontiguousarray(T), e, 0)
    return e


class ChainKernel:
    """Tool pose and geometric Jacobian of ONE configuration, for solver and control loops.

    The same results as :func:`fk` and :func:`geometric_jacobian`, without their input
    checks: ``q`` must be a float64 array of shape ``(n,)``, finite. Every returned array
    is new. As everywhere in armkit, ``fk`` gives the 4x4 ``T_base_tool`` and a *pose* is the
    6-vector of :meth:`armkit.Robot.pose` (``pose`` and ``pose_jacobian`` are this class's
    deprecated old names of :meth:`fk` and :meth:`fk_jacobian`).

    Parameters
    ----------
    robot : Robot or Chain

    Examples
    --------
    >>> import armkit
    >>> robot = armkit.load("panda")
    >>> kernel = ChainKernel(robot)
    >>> q = np.array([0.1, -0.3, 0.2, -2.0, 0.1, 1.8, 0.5])
    >>> T, J = kernel.fk_jacobian(q)
    >>> bool(np.allclose(T, fk(robot, q), atol=1e-14))
    True
    >>> J.shape
    (6, 7)
    """

    def __init__(self, robot: Robot | Chain) -> None:
        chain = as_chain(robot)
        self.n = chain.n
        self._whole = chain
        self._chain = chain._core

    def fk(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        """Tool transform ``T_base_tool`` ``(4, 4)`` at joint values ``q`` ``(n,)`` [rad or m]."""
        return _fk(self._whole, q, 1)

    def fk_jacobian(self, q: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Tool transform ``T_base_tool`` ``(4, 4)`` and base-frame geometric Jacobian ``(6, n)``,
        rows ``[v; w]``."""
        T, J = np.empty((4, 4)), np.empty((6, self.n))
        _raise_if_bad(q, _core.pose_jacobian(self._chain, q, J, T, 1))
        return T, J

    def jacobian(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        """Base-frame geometric Jacobian ``(6, n)``, rows ``[v; w]`` [m/s, rad/s per joint rate]."""
        return self.fk_jacobian(q)[1]

    def joint_axes(self, q: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Joint axes ``(n, 3)`` (unit vectors) and points on them ``(n, 3)`` [m], base frame.

        Row ``i`` is the z axis of joint frame ``i`` (see :func:`joint_frames`) and its
        origin before the joint's motion: the same point for a revolute joint, the start
        of the travel (``q_i = 0``) for a prismatic one.
        """
        axes, points = np.empty((self.n, 3)), np.empty((self.n, 3))
        _core.joint_axes(self._chain, q, axes, points)
        return axes, points

    pose = deprecated_method("pose", "fk")
    pose_jacobian = deprecated_method("pose_jacobian", "fk_jacobian")
