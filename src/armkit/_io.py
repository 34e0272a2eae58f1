"""The one check every writer runs before creating an output file."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from armkit.errors import InputError

__all__ = ["check_output_path", "writing"]


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


@contextmanager
def writing(path: str | Path) -> Iterator[Path]:
    """Turn an :class:`OSError` while writing ``path`` into one :class:`InputError` naming it.

    A folder the user may not write to (``/proc``, a read-only mount, a full disk) is bad
    input, not a bug: the message names the file and the system's reason.

    >>> with writing("/proc/armkit-test.csv") as path:  # doctest: +IGNORE_EXCEPTION_DETAIL
    ...     path.write_text("t")
    Traceback (most recent call last):
    armkit.errors.InputError: cannot write '/proc/armkit-test.csv': No such file or directory
    """
    path = Path(path)
    try:
        yield path
    except OSError as exc:
        raise InputError(f"cannot write {str(path)!r}: {exc.strerror or exc}") from exc
