"""Entry point of the ``armkit`` command: registers every command module, maps errors."""

from __future__ import annotations

import sys

from rich.markup import escape

from armkit.cli import ik, kinematics, lab, motion, robots, sim, trajectory  # noqa: F401  (register commands)
from armkit.cli.app import app, err_console
from armkit.errors import ArmkitError

__all__ = ["main"]


def main(argv: list[str] | None = None) -> int:
    """Run the CLI and return its exit code.

    Usage errors are Typer's (exit code 2); an :class:`ArmkitError` from a command becomes
    one red line on stderr and exit code 1, never a traceback.
    """
    try:
        app(args=argv, prog_name="armkit")
    except SystemExit as exc:
        return exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
    except ArmkitError as exc:
        err_console.print(f"[red]error:[/red] {escape(str(exc))}", highlight=False, soft_wrap=True)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
