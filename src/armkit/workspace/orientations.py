"""A fixed, near-uniform set of tool orientations: the super-Fibonacci spiral on SO(3).

Alexa, "Super-Fibonacci Spirals: Fast, Low-Discrepancy Sampling of SO(3)", CVPR 2022: for
``i = 0 .. n-1``, with ``s = i + 1/2``, ``r = sqrt(s / n)``, ``R = sqrt(1 - s / n)``,
``a = 2 pi s / phi`` and ``b = 2 pi s / psi`` (``phi = sqrt 2``, ``psi`` the root of
``psi^4 = psi + 4``), the unit quaternion ``(r sin a, r cos a, R sin b, R cos b)``. Any ``n``
works, the points cover SO(3) evenly (no pole clustering as in Euler-angle grids), and the
set is deterministic, so every voxel is tested with the same orientations.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from armkit.errors import InputError
from armkit.spatial.rotations import matrix_from_quaternion_wxyz

__all__ = ["super_fibonacci"]

_PHI = np.sqrt(2.0)
_PSI = 1.533751168755204288118041


def super_fibonacci(n: int) -> NDArray[np.float64]:
    """``n`` near-uniform rotation matrices ``(n, 3, 3)``.

    Examples
    --------
    >>> R = super_fibonacci(100)
    >>> R.shape, bool(np.allclose(R @ R.transpose(0, 2, 1), np.eye(3)))
    ((100, 3, 3), True)
    """
    if not (isinstance(n, int | np.integer) and n > 0):
        raise InputError(f"orientations: expected a positive whole number, got {n!r}")
    s = np.arange(n) + 0.5
    r, R = np.sqrt(s / n), np.sqrt(1.0 - s / n)
    a, b = 2 * np.pi * s / _PHI, 2 * np.pi * s / _PSI
    return matrix_from_quaternion_wxyz(np.stack([r * np.sin(a), r * np.cos(a), R * np.sin(b), R * np.cos(b)],
                                                axis=-1))
