"""Writing trajectory samples to CSV and NPZ (never over an existing file unless asked).

Column names: ``t`` [s], then ``q1..qn`` [rad or m], ``qd1..qdn`` [/s], ``qdd1..qddn`` [/s^2].
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from armkit._io import check_output_path
from armkit.errors import InputError

__all__ = ["column_names", "sample_columns", "write_csv", "write_npz"]


def column_names(n: int) -> list[str]:
    """``["t", "q1", ..., "qn", "qd1", ..., "qdd1", ...]`` for ``n`` joints."""
    return ["t"] + [f"{prefix}{j}" for prefix in ("q", "qd", "qdd") for j in range(1, n + 1)]


def sample_columns(samples) -> NDArray[np.float64]:
    """``(K, 1 + 3 n)`` table of ``t, q, qd, qdd`` from :class:`TrajectorySamples`."""
    return np.column_stack([samples.t, samples.q, samples.qd, samples.qdd])


def write_csv(samples, path: str | Path, overwrite: bool = False) -> Path:
    """Write :class:`TrajectorySamples` as CSV with a header line; returns the path."""
    path = check_output_path(path, overwrite)
    table = sample_columns(samples)
    names = column_names(samples.q.shape[1])
    np.savetxt(path, table, delimiter=",", header=",".join(names), comments="", fmt="%.17g")
    return path


def write_npz(samples, path: str | Path, overwrite: bool = False) -> Path:
    """Write :class:`TrajectorySamples` as NPZ, one array per column name; returns the path.

    ``path`` should end in ``.npz`` (numpy would otherwise append it).
    """
    path = check_output_path(path, overwrite)
    if path.suffix != ".npz":
        raise InputError(f"{path}: an NPZ file name must end in .npz")
    table = sample_columns(samples)
    names = column_names(samples.q.shape[1])
    np.savez(path, **{name: table[:, i] for i, name in enumerate(names)})
    return path
