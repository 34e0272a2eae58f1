"""The one check every writer runs before creating an output file."""

from __future__ import annotations

from pathlib import Path

from armkit.errors import InputError

__all__ = ["check_output_path"]


def check_output_path(path: str | Path, overwrite: bool, *, remedy: str = "pass overwrite=True") -> Path:
    """Return ``path`` as a :class:`Path` if a file may be written there.

    Parameters
    ----------
    path : str or Path
        The output file.
    overwrite : bool
        Whether an existing file may be replaced.
    remedy : str
        How the caller allows overwriting, quoted in the error: ``"pass overwrite=True"``
        for the Python API, ``"pass --force"`` for the command line.

    Raises
    ------
    InputError
        If ``path`` is a folder, its folder is missing, or it exists and ``overwrite`` is false.
    """
    path = Path(path)
    if path.is_dir():
        raise InputError(f"output path {str(path)!r} is a folder; expected a file name")
    if path.exists() and not overwrite:
        raise InputError(f"output file {str(path)!r} already exists; {remedy} to replace it")
    if not path.parent.is_dir():
        raise InputError(f"output file {str(path)!r}: folder {str(path.parent)!r} does not exist")
    return path
