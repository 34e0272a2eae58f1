"""The voxel grid a workspace map lives on: where it is, how fine, which voxel a point falls in.

The grid is sized from a bound that no configuration can exceed, so no sample falls outside
it: the tool origin is the first joint frame's origin plus the fixed translations between
consecutive joint frames, each turned by the joints before it (a rotation keeps its length)
and, for a prismatic joint, its travel along z. Hence ``|p_tool - c| <= reach`` with
``reach = sum_i |t_i| + sum_prismatic max|q_i|``, whatever the joint limits (they only make
the real workspace smaller); ``c`` is ``o_1`` plus the part of the first translation along a
revolute first axis (which that joint does not turn), e.g. a shoulder height. The bound is a
cube around ``c``; voxel centres sit on whole multiples of the resolution, so one layer of
voxels is centred on every base-frame coordinate plane through the origin (the slices
through the base axis in :mod:`plots`).

A planar arm (all tool positions in one plane ``x``, ``y`` or ``z`` = const, found from a
pilot sample) gets one voxel layer on that axis, marked ``flat``: its map is 2-D and its
"volume" is an area [m^2].
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from armkit.errors import InputError
from armkit.robot import Robot
from armkit.workspace.sampling import joint_box, tool_positions

__all__ = ["Grid", "grid_for", "reach_bound"]

#: Tool positions spread less than this [m] along a base axis make the arm planar on it.
FLAT_SPREAD = 1e-9
#: Configurations of the pilot sample that looks for a planar arm.
_PILOT = 512
#: Voxels at most (a guard against a resolution typed in mm instead of m).
MAX_VOXELS = 2_000_000_000


@dataclass(frozen=True)
class Grid:
    """An axis-aligned voxel grid in the base frame.

    Attributes
    ----------
    lower : tuple of 3 float
        Base-frame coordinates [m] of the grid's lowest corner.
    resolution : float
        Voxel edge [m].
    shape : tuple of 3 int
        Voxels along x, y, z.
    flat : tuple of 3 bool
        Axes on which the arm does not move (one voxel layer; measured in fewer dimensions).

    Examples
    --------
    >>> grid = Grid((-0.05, -0.05, -0.05), 0.1, (1, 1, 1), (False, False, True))
    >>> grid.flat_index(np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])).tolist()
    [0, -1]
    >>> grid.cell_measure, grid.unit
    (0.010000000000000002, 'm^2')
    """

    lower: tuple[float, float, float]
    resolution: float
    shape: tuple[int, int, int]
    flat: tuple[bool, bool, bool] = (False, False, False)

    @property
    def size(self) -> int:
        """Number of voxels."""
        return int(np.prod(self.shape))

    @property
    def dimensions(self) -> int:
        """3, or 2 for a planar arm."""
        return 3 - sum(self.flat)

    @property
    def cell_measure(self) -> float:
        """Volume [m^3] (area [m^2] for a planar arm) of one voxel."""
        return self.resolution ** self.dimensions

    @property
    def unit(self) -> str:
        return f"m^{self.dimensions}"

    @property
    def axes(self) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """Voxel-centre coordinates [m] along x, y and z."""
        return tuple(lo + (np.arange(k) + 0.5) * self.resolution
                     for lo, k in zip(self.lower, self.shape, strict=True))  # type: ignore[return-value]

    def flat_index(self, p: NDArray[np.float64]) -> NDArray[np.int64]:
        """Raveled (C order) index of the voxel holding each point ``(N, 3)`` [m]; -1 outside the grid."""
        ijk = np.floor((p - np.asarray(self.lower)) / self.resolution).astype(np.int64)
        inside = np.all((ijk >= 0) & (ijk < np.asarray(self.shape)), axis=-1)
        flat = np.ravel_multi_index(tuple(np.where(inside, ijk.T, 0)), self.shape)
        return np.where(inside, flat, -1)

    def centres(self, flat: NDArray[np.int64]) -> NDArray[np.float64]:
        """Voxel centres ``(N, 3)`` [m] of raveled indices ``(N,)``."""
        ijk = np.stack(np.unravel_index(flat, self.shape), axis=-1)
        return np.asarray(self.lower) + (ijk + 0.5) * self.resolution

    def to_attrs(self) -> dict:
        return {"lower": list(self.lower), "resolution": self.resolution, "shape": list(self.shape),
                "flat": list(self.flat)}

    @classmethod
    def from_attrs(cls, attrs: dict) -> Grid:
        return cls(tuple(attrs["lower"]), attrs["resolution"], tuple(attrs["shape"]), tuple(attrs["flat"]))

    def union(self, other: Grid) -> Grid:
        """The smallest grid of this resolution holding both (the voxel centres stay aligned)."""
        if other.resolution != self.resolution or other.flat != self.flat:
            raise InputError(f"grids of resolution {self.resolution} m and {other.resolution} m (or "
                             f"different planar axes) cannot be merged")
        lower = np.minimum(self.lower, other.lower)
        upper = np.maximum(np.add(self.lower, np.multiply(self.shape, self.resolution)),
                           np.add(other.lower, np.multiply(other.shape, other.resolution)))
        shape = np.rint((upper - lower) / self.resolution).astype(int)
        return Grid(tuple(lower.tolist()), self.resolution, tuple(shape.tolist()), self.flat)


def reach_bound(robot: Robot) -> tuple[NDArray[np.float64], float]:
    """The first joint frame's origin ``(3,)`` [m] and a radius [m] no tool position exceeds.

    Examples
    --------
    >>> import armkit
    >>> centre, reach = reach_bound(armkit.load("probot-anno"))
    >>> centre.round(3).tolist(), round(reach, 4)
    ([0.0, 0.0, 0.284], 0.5089)
    """
    chain = robot.chain
    offsets = chain.T_between[1:, :3, 3].copy()
    centre = chain.T_between[0, :3, 3].copy()
    if not chain.prismatic[0]:  # the part along the first axis does not turn with it
        centre += chain.T_between[0, :3, 2] * offsets[0, 2]
        offsets[0, 2] = 0.0
    travel = np.abs(joint_box(robot)).max(axis=1)
    return centre, float(np.linalg.norm(offsets, axis=-1).sum() + travel[chain.prismatic].sum())


def grid_for(robot: Robot, resolution: float) -> Grid:
    """The grid at ``resolution`` [m] holding every tool position the robot can reach.

    Raises
    ------
    InputError
        If ``resolution`` is not a positive number or makes more than 2e9 voxels.

    Examples
    --------
    >>> import armkit
    >>> grid = grid_for(armkit.load("probot-anno"), 0.02)
    >>> grid.shape, grid.flat, grid.unit
    ((51, 51, 52), (False, False, False), 'm^3')
    """
    if not (np.isfinite(resolution) and resolution > 0):
        raise InputError(f"resolution: expected a positive length in metres, got {resolution!r}")
    centre, reach = reach_bound(robot)
    pilot = tool_positions(robot, robot.random_q(_PILOT, rng=0))
    flat = np.ptp(pilot, axis=0) < FLAT_SPREAD
    low = np.where(flat, pilot[0], centre - reach)
    high = np.where(flat, pilot[0], centre + reach)
    first = np.floor(low / resolution + 0.5) - 0.5      # voxel edges half a step off the multiples
    last = np.ceil(high / resolution - 0.5) + 0.5
    shape = np.maximum(np.rint(last - first).astype(int), 1)
    if np.prod(shape.astype(float)) > MAX_VOXELS:
        raise InputError(f"resolution {resolution} m makes {int(np.prod(shape.astype(float))):.3g} voxels "
                         f"for a reach of {reach:.3g} m (at most {MAX_VOXELS:.0e}); choose a coarser one "
                         f"(the resolution is in metres)")
    return Grid(tuple((first * resolution).tolist()), float(resolution), tuple(shape.tolist()),
                tuple(flat.tolist()))
