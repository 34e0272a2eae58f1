"""The one timing rule every benchmark uses: the median over repeated runs."""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np


def median_seconds(function: Callable[[], object], repeat: int, number: int = 1) -> float:
    """Median over ``repeat`` runs of the time per call [s], each run timing ``number`` calls."""
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        for _ in range(number):
            function()
        times.append((time.perf_counter() - start) / number)
    return float(np.median(times))
