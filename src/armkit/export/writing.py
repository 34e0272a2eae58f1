"""Writing exported files without overwriting a user's file by accident."""

from __future__ import annotations

from pathlib import Path

from armkit.errors import InputError

__all__ = ["write_text"]


def write_text(path: str | Path, text: str, *, force: bool = False) -> Path:
    """Write ``text`` to ``path`` (UTF-8) and return the path.

    Raises
    ------
    InputError
        If ``path`` exists and ``force`` is false, is a folder, or its folder is missing.
    """
    path = Path(path)
    if path.is_dir():
        raise InputError(f"output path {str(path)!r} is a folder; expected a file name")
    if path.exists() and not force:
        raise InputError(f"output file {str(path)!r} already exists; pass --force "
                         f"(force=True) to overwrite it")
    if not path.parent.is_dir():
        raise InputError(f"output folder {str(path.parent)!r} does not exist")
    path.write_text(text, encoding="utf-8")
    return path
