"""The ``armkit`` console script: Ctrl-C while armkit is still being imported is one line too.

Importing armkit (NumPy, rich, Typer and the command modules) takes a moment, and a
KeyboardInterrupt then would print Python's traceback before :func:`armkit.cli.main.main`
can catch anything. This module lives outside the ``armkit`` package so that importing it
imports nothing heavy; it imports the CLI inside the ``try``.
"""

from __future__ import annotations

import sys

#: Exit code of a run interrupted by Ctrl-C (128 + SIGINT), as :mod:`armkit.cli.main` uses.
INTERRUPTED = 130


def run() -> None:
    """Import and run the CLI; exit with its code (130 and one line if Ctrl-C comes first)."""
    try:
        from armkit.cli.main import main
    except KeyboardInterrupt:
        sys.stderr.write("interrupted (Ctrl-C)\n")
        sys.exit(INTERRUPTED)
    sys.exit(main())
