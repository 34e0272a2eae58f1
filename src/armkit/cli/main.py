"""Entry point of the ``armkit`` command: registers every command module, maps errors."""

from __future__ import annotations

import sys

from rich.markup import escape

from armkit._jit import announce_compilation
from armkit.cli import ik, kinematics, lab, motion, robots, sim, trajectory, view  # noqa: F401  (register)
from armkit.cli.app import app, err_console
from armkit.errors import ArmkitError

__all__ = ["main"]


def main(argv: list[str] | None = None) -> int:
    """Run the CLI and return its exit code.

    Usage errors are Typer's (exit code 2); an :class:`ArmkitError` from a command becomes
    one red line on stderr and exit code 1, never a traceback.
    """
    try:
        with announce_compilation(_compiling):
            app(args=argv, prog_name="armkit")
    except SystemExit as exc:
        return exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
    except ArmkitError as exc:
        err_console.print(f"[red]error:[/red] {escape(str(exc))}", highlight=False, soft_wrap=True)
        return 1
    return 0


def _compiling() -> None:
    err_console.print("[dim]compiling armkit's kernels for this machine (each kernel once; the IK ones "
                      "take up to a minute), later runs load them from the cache ...[/dim]",
                      highlight=False, soft_wrap=True)


if __name__ == "__main__":
    sys.exit(main())
