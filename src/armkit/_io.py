"""What every writer runs: the check of an output path, and the atomic write of the file."""

from __future__ import annotations

import os
import secrets
import stat
from collections.abc import Iterator
from contextlib import contextmanager, suppress
from pathlib import Path

from armkit.errors import InputError

__all__ = ["atomic_write", "check_output_path"]


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
def atomic_write(path: str | Path) -> Iterator[Path]:
    """Write a file through a temporary file beside ``path``, renamed over ``path`` only when complete.

    The ``with`` body writes to the path it is given (in ``path``'s folder, with ``path``'s
    extension, so writers that choose a format by extension behave alike); when the body
    finishes the file is renamed onto ``path`` in one step (:func:`os.replace`). If the body
    fails (a full disk, a file-size limit, Ctrl-C, any exception), the temporary file is
    removed and the previous file at ``path``, if any, is left as it was. A file that
    replaces another keeps the other's permission bits; a new one gets the usual ones
    (``0o666`` less the umask). An :class:`OSError` becomes one :class:`InputError` naming
    ``path`` and the system's reason: a folder the user may not write to (``/proc``, a
    read-only mount, a full disk) is bad input, not a bug.

    Parameters
    ----------
    path : str or Path
        The file to create or replace.

    Yields
    ------
    Path
        The temporary file to write, ``.<name>-<random>.partial<suffix>`` beside ``path``.

    Raises
    ------
    InputError
        If the temporary file cannot be created, written or renamed.

    Examples
    --------
    >>> import tempfile
    >>> target = Path(tempfile.mkdtemp()) / "a.txt"
    >>> with atomic_write(target) as partial:
    ...     _ = partial.write_text("done")
    >>> target.read_text()
    'done'
    >>> with atomic_write("/proc/armkit-test.csv") as partial:  # doctest: +IGNORE_EXCEPTION_DETAIL
    ...     _ = partial.write_text("t")
    Traceback (most recent call last):
    armkit.errors.InputError: cannot write '/proc/armkit-test.csv': No such file or directory
    """
    path = Path(path)
    partial = path.with_name(f".{path.stem}-{secrets.token_hex(4)}.partial{path.suffix}")
    try:
        os.close(os.open(partial, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o666))
        if path.is_file():
            os.chmod(partial, stat.S_IMODE(path.stat().st_mode))
        yield partial
        os.replace(partial, path)
    except OSError as exc:
        raise InputError(f"cannot write {str(path)!r}: {exc.strerror or exc}") from exc
    finally:
        with suppress(OSError):
            partial.unlink(missing_ok=True)
