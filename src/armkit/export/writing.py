"""Writing exported files without overwriting a user's file by accident."""

from __future__ import annotations

from pathlib import Path

from armkit._io import atomic_write, check_output_path

__all__ = ["write_text"]


def write_text(path: str | Path, text: str, *, overwrite: bool = False) -> Path:
    """Write ``text`` to ``path`` (UTF-8) and return the path.

    Raises
    ------
    InputError
        If ``path`` exists and ``overwrite`` is false, is a folder, its folder is missing,
        or the system refuses the write.
    """
    path = check_output_path(path, overwrite)
    with atomic_write(path) as partial:
        partial.write_text(text, encoding="utf-8")
    return path
