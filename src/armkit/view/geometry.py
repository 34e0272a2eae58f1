"""What the viewer draws, as plain arrays: the arm's link and joint cylinders, meshes, the ellipsoid.

Nothing here knows about viser; :mod:`armkit.view.scene` hands these arrays to it. A cylinder
instance is the unit cylinder of :func:`unit_cylinder` (radius 1, height 1, centred on the
origin, along z) placed by a position, a ``wxyz`` quaternion and per-axis scales.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from armkit import kinematics
from armkit.robot import Robot
from armkit.spatial.rotations import quaternion_wxyz_from_matrix

__all__ = ["ArmPlacement", "arm_placement", "arm_size", "ellipsoid_axes", "label_positions", "rotations_z_to",
           "unit_cylinder", "unit_sphere"]

#: Segments shorter than this [m] are not drawn (coincident frame origins).
SHORTEST_SEGMENT = 1e-6


class ArmPlacement(NamedTuple):
    """Cylinder instances of one configuration: links first, then one per joint.

    Attributes
    ----------
    positions : (K, 3) centres [m]; wxyzs : (K, 4) orientations; scales : (K, 3) radius x, radius y,
    length [m]; joint_origins : (n, 3) [m]; joint_axes : (n, 3) unit vectors; link_frames :
    (n + 2, 4, 4) base, DH link frames and tool [m]; link_count : int, how many of the K are links.
    """

    positions: NDArray[np.float64]
    wxyzs: NDArray[np.float64]
    scales: NDArray[np.float64]
    joint_origins: NDArray[np.float64]
    joint_axes: NDArray[np.float64]
    link_frames: NDArray[np.float64]
    link_count: int


def arm_size(robot: Robot) -> float:
    """A length scale of the arm [m]: the chain's :attr:`~armkit.chain.Chain.link_length` and the
    base's offset (at least 0.1 m, so that an arm of zero size still draws).

    >>> import armkit
    >>> round(arm_size(armkit.load("probot-anno")), 4)
    0.7929
    """
    return float(max(robot.chain.link_length + np.linalg.norm(robot.chain.T_base[:3, 3]), 0.1))


def rotations_z_to(directions: NDArray[np.float64]) -> NDArray[np.float64]:
    """Rotations ``(..., 3, 3)`` whose z axis is each unit vector of ``directions`` ``(..., 3)``."""
    z = directions / np.linalg.norm(directions, axis=-1, keepdims=True)
    helper = np.where(np.abs(z[..., :1]) < 0.9, [1.0, 0.0, 0.0], [0.0, 1.0, 0.0])
    x = np.cross(helper, z)
    x /= np.linalg.norm(x, axis=-1, keepdims=True)
    return np.stack([x, np.cross(z, x), z], axis=-1)


def centre_line(T_joints: NDArray[np.float64], T_tool: NDArray[np.float64]) -> NDArray[np.float64]:
    """The drawn centre line: floor origin, each joint origin, tool origin, with a corner where an
    offset has a part along the previous joint's axis (a DH ``d``) and a part across it (an ``a``)."""
    frames = [np.eye(4), *T_joints, T_tool]
    points = [frames[0][:3, 3]]
    for A, B in zip(frames[:-1], frames[1:], strict=True):
        offset = B[:3, 3] - A[:3, 3]
        corner = A[:3, 3] + A[:3, 2] * (A[:3, 2] @ offset)
        points += [corner, B[:3, 3]]
    return np.array(points)


def arm_placement(robot: Robot, q: NDArray[np.float64], radius: float) -> ArmPlacement:
    """The cylinders of the arm at ``q`` [rad or m]: links of ``radius`` [m], joints a bit thicker.

    The link path runs from the floor origin through every joint origin to the tool; joint
    ``i`` is a short cylinder along its axis (the z axis of its joint frame).

    Examples
    --------
    >>> import armkit
    >>> robot = armkit.load("probot-anno")
    >>> p = arm_placement(robot, robot.home, 0.01)
    >>> p.positions.shape[0] == p.link_count + robot.n, p.joint_axes[0].round(6).tolist()
    (True, [0.0, 0.0, 1.0])
    """
    T_joints, T_tool = kinematics.joint_frames(robot, q)
    path = centre_line(T_joints, T_tool)
    starts, ends = path[:-1], path[1:]
    lengths = np.linalg.norm(ends - starts, axis=-1)
    keep = lengths > SHORTEST_SEGMENT
    starts, ends, lengths = starts[keep], ends[keep], lengths[keep]
    R_links = rotations_z_to(ends - starts) if len(starts) else np.zeros((0, 3, 3))
    axes = T_joints[:, :3, 2]
    R_joints = T_joints[:, :3, :3]
    link_scales = np.column_stack([np.full(len(lengths), radius), np.full(len(lengths), radius), lengths])
    joint_scales = np.tile([1.5 * radius, 1.5 * radius, 4.0 * radius], (robot.n, 1))
    return ArmPlacement(
        positions=np.concatenate([(starts + ends) / 2, T_joints[:, :3, 3]]),
        wxyzs=quaternion_wxyz_from_matrix(np.concatenate([R_links, R_joints])),
        scales=np.concatenate([link_scales, joint_scales]),
        joint_origins=T_joints[:, :3, 3], joint_axes=axes,
        link_frames=kinematics.link_frames(robot, q), link_count=len(lengths))


def label_positions(candidates: list[NDArray[np.float64]], spacing: float) -> NDArray[np.float64]:
    """One label position ``(G, 3)`` per ghost, every two at least ``spacing`` [m] apart.

    ``candidates[g]`` ``(K, 3)`` are the points of ghost ``g`` a label may mark (its joint
    origins). Ghost by ghost, the label goes to its candidate farthest from the labels placed
    so far (the middle candidate for the first); one still closer than ``spacing`` to a placed
    label (ghosts that differ only in their wrist) is lifted along z in steps of ``spacing``
    until it is clear.

    >>> same = [np.zeros((3, 3)), np.zeros((3, 3)), np.zeros((3, 3))]
    >>> label_positions(same, 0.1).round(6).tolist()
    [[0.0, 0.0, 0.0], [0.0, 0.0, 0.1], [0.0, 0.0, 0.2]]
    """
    placed: list[NDArray[np.float64]] = []
    for points in candidates:
        points = np.asarray(points, dtype=float)
        if not placed:
            placed.append(points[len(points) // 2])
            continue
        distance = np.linalg.norm(points[:, None] - np.array(placed)[None], axis=-1).min(axis=1)
        point = points[int(np.argmax(distance))].copy()
        while np.linalg.norm(np.array(placed) - point, axis=-1).min() < spacing:
            point[2] += spacing
        placed.append(point)
    return np.array(placed).reshape(-1, 3)


def unit_cylinder(segments: int = 24) -> tuple[NDArray[np.float32], NDArray[np.uint32]]:
    """Vertices ``(V, 3)`` and outward triangles ``(F, 3)`` of a closed cylinder: radius 1,
    height 1, centred on the origin, axis z."""
    angles = np.linspace(0.0, 2 * np.pi, segments, endpoint=False)
    ring = np.column_stack([np.cos(angles), np.sin(angles)])
    bottom = np.column_stack([ring, np.full(segments, -0.5)])
    top = np.column_stack([ring, np.full(segments, 0.5)])
    vertices = np.concatenate([bottom, top, [[0, 0, -0.5], [0, 0, 0.5]]])
    i = np.arange(segments)
    j = (i + 1) % segments
    c_bottom, c_top = 2 * segments, 2 * segments + 1
    sides = np.concatenate([np.column_stack([i, j, segments + j]),
                            np.column_stack([i, segments + j, segments + i])])
    caps = np.concatenate([np.column_stack([np.full(segments, c_bottom), j, i]),
                           np.column_stack([np.full(segments, c_top), segments + i, segments + j])])
    return vertices.astype(np.float32), np.concatenate([sides, caps]).astype(np.uint32)


def unit_sphere(rings: int = 12, segments: int = 24) -> tuple[NDArray[np.float32], NDArray[np.uint32]]:
    """Vertices and outward triangles of a sphere of radius 1 (latitude-longitude grid)."""
    polar = np.linspace(0.0, np.pi, rings + 1)
    azimuth = np.linspace(0.0, 2 * np.pi, segments, endpoint=False)
    P, A = np.meshgrid(polar, azimuth, indexing="ij")
    vertices = np.stack([np.sin(P) * np.cos(A), np.sin(P) * np.sin(A), np.cos(P)], axis=-1).reshape(-1, 3)
    r, s = np.meshgrid(np.arange(rings), np.arange(segments), indexing="ij")
    a = r * segments + s
    b = r * segments + (s + 1) % segments
    c, d = a + segments, b + segments
    faces = np.concatenate([np.stack([a, c, b], -1).reshape(-1, 3), np.stack([b, c, d], -1).reshape(-1, 3)])
    return vertices.astype(np.float32), faces.astype(np.uint32)


def ellipsoid_axes(robot: Robot, q: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The tool's translational velocity ellipsoid at ``q``: rotation ``(3, 3)`` whose columns
    are its principal directions, and the semi-axes ``(3,)`` [m/s per unit joint-rate norm].

    The ellipsoid is ``{J_v qd : |qd| <= 1}`` with ``J_v`` the position rows of the geometric
    Jacobian (base frame).

    >>> import armkit
    >>> robot = armkit.load("probot-anno")
    >>> R, semi = ellipsoid_axes(robot, [0.3, -0.5, 0.4, 0.1, 0.6, 0.0])
    >>> bool(np.isclose(np.linalg.det(R), 1.0)), bool(semi[0] >= semi[1] >= semi[2] >= 0)
    (True, True)
    """
    J_v = robot.jacobian(q)[:3]
    U, s, _ = np.linalg.svd(J_v)
    if np.linalg.det(U) < 0:
        U[:, 2] *= -1
    return U, np.pad(s, (0, 3 - len(s)))
