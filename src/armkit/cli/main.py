"""Entry point of the ``armkit`` command: registers every command module, maps errors."""

from __future__ import annotations

import sys
import warnings

from rich.markup import escape

from armkit.cli import dynamics, ik, kinematics, lab, motion, robots, sim, trajectory, view  # noqa: F401  (register)
from armkit.cli import plan as _plan  # noqa: F401  (registers armkit plan)
from armkit.cli import workspace as _workspace  # noqa: F401  (registers armkit workspace)
from armkit.cli.app import app, err_console, warn
from armkit.errors import ArmkitError

__all__ = ["main"]


def main(argv: list[str] | None = None) -> int:
    """Run the CLI and return its exit code.

    Usage errors are Typer's (exit code 2); an :class:`ArmkitError` from a command, or a
    file that cannot be read or written (:class:`OSError`), becomes one red line on stderr
    and exit code 1, never a traceback. Ctrl-C (:class:`KeyboardInterrupt`) in any command
    prints one line and returns 130, the shell's code for a run ended by SIGINT.
    """
    try:
        with warnings.catch_warnings():
            warnings.showwarning = _show_warning  # one 'warning:' line, not Python's two with a source line
            app(args=argv, prog_name="armkit")
    except SystemExit as exc:
        if _caused_by_interrupt(exc):  # Typer turns Ctrl-C into a silent exit 130
            return _interrupted()
        return exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
    except ArmkitError as exc:
        return _error(str(exc))
    except OSError as exc:
        return _error(_os_error_text(exc))
    except KeyboardInterrupt:
        return _interrupted()
    return 0


def _show_warning(message: Warning | str, category: type[Warning], filename: str, lineno: int,
                  file: object = None, line: str | None = None) -> None:
    """A Python warning as the CLI's one yellow ``warning:`` line on stderr."""
    warn(str(message))


#: Exit code of a run interrupted by Ctrl-C (128 + SIGINT), as shells report it.
INTERRUPTED = 130


def _caused_by_interrupt(exc: BaseException) -> bool:
    while exc is not None:
        if isinstance(exc, KeyboardInterrupt):
            return True
        if exc.__cause__ is not None:
            exc = exc.__cause__
        else:
            exc = None if exc.__suppress_context__ else exc.__context__
    return False


def _interrupted() -> int:
    err_console.print("[yellow]interrupted[/yellow] (Ctrl-C)", highlight=False, soft_wrap=True)
    return INTERRUPTED


def _error(text: str) -> int:
    err_console.print(f"[red]error:[/red] {escape(text)}", highlight=False, soft_wrap=True)
    return 1


def _os_error_text(exc: OSError) -> str:
    """``file '/proc/x.csv': No such file or directory`` rather than a traceback."""
    where = f" {str(exc.filename)!r}" if exc.filename is not None else ""
    return f"file{where}: {exc.strerror or exc}"


if __name__ == "__main__":
    sys.exit(main())
