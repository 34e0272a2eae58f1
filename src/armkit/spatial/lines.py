"""Lines in space, each given by a point ``p`` [m] and a unit direction ``h``: joint axes.

The one place their closest points are computed (the closed-form IK's chain preparation and its
structure analysis both ask where two joint axes meet).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["closest_points"]


def closest_points(p_a: NDArray[np.float64], h_a: NDArray[np.float64], p_b: NDArray[np.float64],
                   h_b: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The points of lines ``(p_a, h_a)`` and ``(p_b, h_b)`` ``(3,)`` closest to each other, ``(3,)``
    each (for parallel lines, the least-squares pair nearest to ``p_a`` and ``p_b``).

    Examples
    --------
    >>> x, z = np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, 1.0])
    >>> a, b = closest_points(np.zeros(3), x, np.array([0.0, 2.0, 1.0]), z)
    >>> a.tolist(), b.tolist()
    ([0.0, 0.0, 0.0], [0.0, 2.0, 0.0])
    """
    s, t = np.linalg.lstsq(np.stack([h_a, -h_b], axis=1), p_b - p_a, rcond=None)[0]
    return p_a + s * h_a, p_b + t * h_b
