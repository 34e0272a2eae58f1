"""Product of exponentials: an arm given by its joint lines at ``q = 0``, mapped onto the chain.

The product-of-exponentials (POE) form of a serial arm is::

    T_base_tool(q) = T_base · exp([xi_1] q_1) · ... · exp([xi_n] q_n) · M

where joint ``i`` turns about (revolute) or slides along (prismatic) the line with unit
direction ``axes[i]`` through ``points[i]``, both in the base frame with every joint at
zero, and ``M`` is the tool pose at ``q = 0`` (EAIK's and IK-Geo's ``H``, ``P`` form).

It maps exactly onto :mod:`armkit.chain`: with ``F_i`` the frame at ``points[i]`` whose z
axis is ``axes[i]`` (:func:`rotation_z_to`), ``exp([xi_i] q) = F_i · M_z(q) · F_i^-1``, so
``T_before_i = F_{i-1}^-1 F_i`` (``F_0 = I``), ``T_after_i = I`` and
``T_tool = F_n^-1 M``. Which rotation about the axis ``F_i`` uses does not matter: any
two commute with the joint's own motion.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit.chain import Chain, JointKind, chain_from_frames
from armkit.errors import RobotDefinitionError
from armkit.kinematics import joint_frames
from armkit.spatial.transforms import invert_transform, transform_from

__all__ = ["MIN_AXIS_LENGTH", "PoeDescription", "chain_from_poe", "direction", "poe_from_chain",
           "rotation_z_to", "unit_axis"]


@dataclass(frozen=True)
class PoeDescription:
    """The joint lines a robot was written with, kept for display and for writing it back.

    Attributes
    ----------
    axes, points : ndarray (n, 3)
        Unit joint directions and a point on each joint line, base frame, ``q = 0`` [m].
    M : ndarray (4, 4)
        Tool pose in the base frame at ``q = 0`` [m].
    T_base : ndarray (4, 4)
        Pose of the base frame (where the lines are given) in the world [m].
    length_unit, angle_unit : str
        The units the user wrote (the arrays are SI).
    """

    axes: NDArray[np.float64]
    points: NDArray[np.float64]
    M: NDArray[np.float64]
    T_base: NDArray[np.float64]
    length_unit: str = "m"
    angle_unit: str = "rad"


def rotation_z_to(axis: ArrayLike) -> NDArray[np.float64]:
    """The smallest rotation ``(3, 3)`` taking the z axis onto the unit vector ``axis``.

    Exact (integer entries) for the coordinate axes; rows of an axis pointing against z
    go through ``Rx(pi)`` so that no nearly opposite vectors are subtracted.

    Examples
    --------
    >>> rotation_z_to([1.0, 0.0, 0.0]) @ [0.0, 0.0, 1.0]
    array([1., 0., 0.])
    >>> rotation_z_to([0.0, 0.0, -1.0]).tolist()
    [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]]
    """
    a = np.asarray(axis, dtype=float)
    if a[2] < 0:  # R = Rx(pi) R', R' taking z to Rx(pi)^T a, which points along +z
        return np.diag([1.0, -1.0, -1.0]) @ rotation_z_to(a * [1.0, -1.0, -1.0])
    K = np.array([[0.0, 0.0, a[0]], [0.0, 0.0, a[1]], [-a[0], -a[1], 0.0]])  # [z x a]
    return np.eye(3) + K + K @ K / (1.0 + a[2])


#: Shortest axis vector [unitless] taken as a direction: shorter ones (1e-300, 0) are rounding noise.
MIN_AXIS_LENGTH = 1e-12


def direction(axis: NDArray[np.float64]) -> tuple[NDArray[np.float64] | None, float]:
    """A finite ``(3,)`` vector scaled to length one, and its length (without overflow: ``[1e308, 1e308, 0]``
    is 1.4e308 long, not inf); the direction is ``None`` if the length is below :data:`MIN_AXIS_LENGTH`.

    >>> direction(np.array([0.0, 3e300, 4e300]))
    (array([0. , 0.6, 0.8]), 5e+300)
    >>> direction(np.array([0.0, 0.0, 1e-300]))
    (None, 1e-300)
    """
    largest = float(np.abs(axis).max())
    if largest == 0.0:
        return None, 0.0
    scaled = axis / largest
    length = float(np.linalg.norm(scaled))
    return (scaled / length if length * largest >= MIN_AXIS_LENGTH else None), length * largest


def unit_axis(axis: ArrayLike, where: str) -> NDArray[np.float64]:
    """``axis`` ``(3,)`` scaled to length one, or a :class:`RobotDefinitionError` naming ``where``."""
    a = np.asarray(axis, dtype=float)
    if a.shape != (3,) or not np.isfinite(a).all() or not a.any():
        raise RobotDefinitionError(f"{where}: axis {np.asarray(axis).tolist()}: expected three "
                                   f"finite numbers, not all zero")
    unit, length = direction(a)
    if unit is None:
        raise RobotDefinitionError(f"{where}: axis {a.tolist()}: its length {length:.3g} is too small to "
                                   f"be a direction; expected three finite numbers of length at least "
                                   f"{MIN_AXIS_LENGTH:g}")
    return unit


def chain_from_poe(axes: ArrayLike, points: ArrayLike, M: ArrayLike, *,
                   kinds: Sequence[JointKind] | None = None, T_base: ArrayLike | None = None,
                   limits: Sequence[tuple[float, float] | None] | None = None,
                   max_velocity: Sequence[float | None] | None = None,
                   max_acceleration: Sequence[float | None] | None = None,
                   names: Sequence[str] | None = None) -> Chain:
    """A :class:`~armkit.chain.Chain` from joint lines in the base frame at ``q = 0``.

    Parameters
    ----------
    axes : array_like (n, 3)
        Joint directions (normalised here).
    points : array_like (n, 3)
        A point on each joint line [m].
    M : array_like (4, 4)
        Tool pose at ``q = 0`` [m].
    kinds : sequence of {"revolute", "prismatic"}, optional
        Default all revolute.
    T_base : array_like (4, 4), optional
        Pose of the base frame in the world [m].
    limits, max_velocity, max_acceleration, names
        As for :func:`armkit.chain.chain_from_frames`.

    Examples
    --------
    A planar 2R arm with unit links along x, turning about z:

    >>> from armkit import kinematics
    >>> M = np.eye(4); M[0, 3] = 2.0
    >>> chain = chain_from_poe([[0, 0, 1], [0, 0, 1]], [[0, 0, 0], [1, 0, 0]], M)
    >>> kinematics.fk(chain, [np.pi / 2, 0.0])[:3, 3].round(12) + 0.0
    array([0., 2., 0.])
    """
    axes = np.asarray(axes, dtype=float)
    points = np.asarray(points, dtype=float)
    if axes.ndim != 2 or axes.shape[1:] != (3,) or points.shape != axes.shape:
        raise RobotDefinitionError(f"axes and points: expected two (n, 3) arrays, got shapes "
                                   f"{axes.shape} and {points.shape}")
    n = len(axes)
    if n == 0:
        raise RobotDefinitionError("a product of exponentials needs at least one joint, got none")
    kinds = list(kinds) if kinds is not None else ["revolute"] * n
    names = list(names) if names is not None else [f"q{i + 1}" for i in range(n)]
    if len(kinds) != n or len(names) != n:
        raise RobotDefinitionError(f"{n} joint axes but {len(kinds)} kinds and {len(names)} names")
    frames = [transform_from(rotation_z_to(unit_axis(h, f"joint {names[i]!r}")), p)
              for i, (h, p) in enumerate(zip(axes, points, strict=True))]
    previous = [np.eye(4), *frames[:-1]]
    T_before = [invert_transform(F_prev) @ F for F_prev, F in zip(previous, frames, strict=True)]
    T_tool = invert_transform(frames[-1]) @ np.asarray(M, dtype=float)
    return chain_from_frames(kinds, T_before, [np.eye(4)] * n, limits=limits, max_velocity=max_velocity,
                             max_acceleration=max_acceleration,
                             T_base=None if T_base is None else np.asarray(T_base, dtype=float),
                             T_tool=T_tool, names=names)


def poe_from_chain(chain: Chain, length_unit: str = "m", angle_unit: str = "rad") -> PoeDescription:
    """The joint lines of any chain at ``q = 0``, in its base frame (``T_base`` kept apart).

    :func:`chain_from_poe` of the result has the chain's FK (to rounding).
    """
    base = np.array(chain.T_base)
    frames, T_tool = joint_frames(chain, np.zeros(chain.n))
    to_base = invert_transform(base)
    frames = to_base @ frames
    return PoeDescription(frames[:, :3, 2].copy(), frames[:, :3, 3].copy(), to_base @ T_tool, base,
                          length_unit, angle_unit)
