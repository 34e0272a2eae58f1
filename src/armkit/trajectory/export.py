"""Trajectory files: writing samples to CSV and NPZ (never over an existing file unless asked),
reading them back, and the CSV line rules every armkit reader follows.

Column names: ``t`` [s], then ``q1..qn`` [rad or m], ``qd1..qdn`` [/s], ``qdd1..qddn`` [/s^2].
CSV rules: values separated by commas and/or spaces, ``#`` starts a comment, blank lines are
skipped, and the first non-comment line is a header if it is not all numbers.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from armkit._io import atomic_write, check_output_path
from armkit.errors import InputError
from armkit.robot import Robot

__all__ = ["column_names", "read_csv_rows", "read_trajectory", "sample_columns", "write_csv", "write_npz"]


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
    with atomic_write(path) as partial:
        np.savetxt(partial, table, delimiter=",", header=",".join(names), comments="", fmt="%.17g")
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
    with atomic_write(path) as partial:
        np.savez(partial, **{name: table[:, i] for i, name in enumerate(names)})
    return path


def _numbers(words: list[str]) -> list[float] | None:
    try:
        return [float(word) for word in words]
    except ValueError:
        return None


def read_csv_rows(path: str | Path, columns: int | None = None,
                  row_name: str = "row") -> tuple[list[str] | None, NDArray[np.float64]]:
    """The header (or ``None``) and the ``(K, columns)`` finite values of a CSV file.

    Parameters
    ----------
    path : str or Path
        CSV file following the rules in the module docstring.
    columns : int, optional
        Values expected per line; by default as many as the header names (or as the
        first numeric line holds).
    row_name : str
        What a line holds, for the error messages ("waypoint", "row").

    Raises
    ------
    InputError
        Naming the file and line: unreadable file, a non-numeric line after the header,
        a wrong value count, a NaN or infinite value.
    """
    path = Path(path)
    try:
        lines = path.read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError) as exc:
        reason = exc.strerror if isinstance(exc, OSError) else "not a text file"
        raise InputError(f"{path}: cannot read the file ({reason})") from exc
    header, rows, first = None, [], True
    for number, line in enumerate(lines, start=1):
        text = line.split("#", 1)[0].strip()
        if not text:
            continue
        words = text.replace(",", " ").split()
        values = _numbers(words)
        if values is None and first:
            header, first = words, False
            columns = len(words) if columns is None else columns
            continue
        first = False
        columns = len(words) if columns is None else columns
        if values is None:
            raise InputError(f"{path}, line {number}: expected {columns} numbers, got {text!r}")
        if len(values) != columns:
            raise InputError(f"{path}, line {number}: expected {columns} values per {row_name}, "
                             f"got {len(values)}")
        if not np.all(np.isfinite(values)):
            raise InputError(f"{path}, line {number}: NaN or infinite value in {text!r}")
        rows.append(values)
    return header, np.array(rows, dtype=float).reshape(len(rows), columns or 0)


def read_trajectory(path: str | Path, robot: Robot) -> tuple[NDArray[np.float64], NDArray[np.float64],
                                                              NDArray[np.float64] | None]:
    """``(t, q, qd)`` from a trajectory file as :func:`write_csv` / :func:`write_npz` write it.

    Parameters
    ----------
    path : str or Path
        CSV with a header ``t,q1..qn[,qd1..qdn,...]`` (without a header the columns are
        ``t, q1 .. qn``), or NPZ with one array per column name.
    robot : Robot
        The arm the file is for: it must have ``robot.n`` joint columns.

    Returns
    -------
    t : (K,) times [s]; q : (K, n) joint values [rad or m]; qd : (K, n) joint rates, or
    ``None`` if the file has no ``qd`` columns.
    """
    path = Path(path)
    if not path.is_file():
        raise InputError(f"trajectory file {str(path)!r} does not exist")
    columns = _npz_columns(path) if path.suffix == ".npz" else _csv_columns(path)
    q_names = [c for c in columns if c.startswith("q") and c[1:].isdigit()]
    if len(q_names) != robot.n:
        raise InputError(f"trajectory file {str(path)!r} has {len(q_names)} joint columns "
                         f"({', '.join(q_names)}); {robot.name} has {robot.n} joints")
    if "t" not in columns:
        raise InputError(f"trajectory file {str(path)!r}: no column 't' (time [s])")
    qd_names = [f"qd{j}" for j in range(1, robot.n + 1)]
    qd = np.column_stack([columns[c] for c in qd_names]) if set(qd_names) <= set(columns) else None
    return columns["t"], np.column_stack([columns[c] for c in q_names]), qd


def _csv_columns(path: Path) -> dict[str, NDArray[np.float64]]:
    header, table = read_csv_rows(path)
    if header is None:
        header = ["t"] + [f"q{j}" for j in range(1, table.shape[1])]
    return {name: table[:, k] for k, name in enumerate(header)}


def _npz_columns(path: Path) -> dict[str, NDArray[np.float64]]:
    try:
        with np.load(path) as archive:
            return {name: np.asarray(archive[name], dtype=float) for name in archive.files}
    except (OSError, ValueError) as exc:
        raise InputError(f"trajectory file {str(path)!r}: not a readable NPZ archive: {exc}") from exc
