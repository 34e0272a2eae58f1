"""Joint-space trajectories: polynomial segments, multi-waypoint minimum jerk, timing, export.

Modules: :mod:`~armkit.trajectory.polynomial` (quintic, cubic),
:mod:`~armkit.trajectory.trapezoid` (LSPB).
"""

from armkit.trajectory.polynomial import PolynomialSegment, cubic, quintic
from armkit.trajectory.trapezoid import TrapezoidSegment, lspb

__all__ = ["PolynomialSegment", "TrapezoidSegment", "cubic", "lspb", "quintic"]
