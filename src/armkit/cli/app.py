"""The Typer application shared by every command module, and its small helpers.

Command modules (``robots.py``, ``kinematics.py``, ...) import :data:`app` and register
their commands with ``@app.command()``; :mod:`armkit.cli.main` imports them all.
Errors derived from :class:`~armkit.errors.ArmkitError` become one red line on stderr
and exit code 1 (see :func:`armkit.cli.main.main`).
"""

from __future__ import annotations

import json
import math
import re
import sys
from collections.abc import Sequence
from typing import Annotated, Any

import numpy as np
import typer
from rich.console import Console
from rich.markup import escape

from armkit.errors import InputError
from armkit.robot import Robot
from armkit.robot_file import load

__all__ = ["ALLOW_NEGATIVE", "BaseOpt", "LockOpt", "QUATERNION_NAMES", "RobotArg", "TipOpt", "app", "console",
           "err_console", "fmt_number", "fmt_numbers", "load_robot", "option_values", "print_json",
           "reject_unknown_options", "to_si", "warn"]

app = typer.Typer(
    name="armkit",
    help="From a robot arm's DH table or URDF to a verified motion. ROBOT is a built-in name "
         "(see 'armkit robots'), a robot TOML file, a URDF file or an MJCF file (--base/--tip choose its "
         "chain).",
    no_args_is_help=True,
    rich_markup_mode=None,  # plain help: no "<bool>" type tags after flags
    pretty_exceptions_enable=False,
    add_completion=False,
)
#: Piped output gets wide lines rather than tables cut to 80 columns.
console = Console(width=None if sys.stdout.isatty() else 160)
err_console = Console(stderr=True)

#: Command settings that let joint values such as ``-0.687`` be read as numbers.
ALLOW_NEGATIVE = {"ignore_unknown_options": True}

#: ``--euler`` names that ask for a unit quaternion ``w x y z`` instead of three angles.
QUATERNION_NAMES = ("quat", "quaternion", "wxyz")


#: The robot argument and the options that shape it, shared by every command taking ROBOT.
RobotArg = Annotated[str, typer.Argument(help="Built-in name (see 'armkit robots'), robot TOML file, URDF "
                                              "or MJCF file (--base/--tip choose its chain).")]
BaseOpt = Annotated[str | None, typer.Option(
    "--base", metavar="LINK", help="URDF: the link the chain starts at (default: the root link); MJCF: "
                                  "the body (default: the world).",
    show_default=False)]
TipOpt = Annotated[str | None, typer.Option(
    "--tip", metavar="LINK", help="URDF: the link the chain ends at, the tool (default: the only leaf); "
                                 "MJCF: the body or site.",
    show_default=False)]
LockOpt = Annotated[list[str] | None, typer.Option(
    "--lock", metavar="JOINT=VALUE", help="Lock a joint (name or number 1..n) at VALUE in rad or m; "
                                          "repeat for more. The robot then has the other joints.",
    show_default=False)]


def load_robot(name_or_path: str, base: str | None = None, tip: str | None = None,
               lock: Sequence[str] | None = None) -> Robot:
    """The robot named on the command line, with its ``--base``/``--tip`` and ``--lock`` options."""
    robot = load(name_or_path, base=base, tip=tip)
    if not lock:
        return robot
    values: dict[int, float] = {}
    given: dict[int, str] = {}  # the --lock word that locked each joint, for the "twice" message
    for word in lock:
        index, value = _lock_word(robot, word)
        if index in given:
            raise InputError(f"--lock {word!r}: joint {robot.joint_names[index]} is already locked by "
                             f"--lock {given[index]!r}; lock each joint once")
        values[index], given[index] = value, word
    return robot.lock(values)


def _lock_word(robot: Robot, word: str) -> tuple[int, float]:
    """The 0-based joint and the value of one ``--lock JOINT=VALUE`` word."""
    key, sep, value = word.partition("=")
    if not sep or not key.strip():
        raise InputError(f"--lock {word!r}: expected JOINT=VALUE, e.g. --lock {robot.joint_names[-1]}=0.3")
    return joint_option(robot, key, f"--lock {word!r}"), parse_floats([value], f"--lock {word!r}")[0]


def joint_option(robot: Robot, word: str, option: str) -> int:
    """The 0-based index of a joint named on the command line: its name, or its number from 1
    as ``armkit show`` counts (``option`` names where it was typed in an error)."""
    key = word.strip()
    if key in robot.joint_names:
        return robot.joint_names.index(key)
    if re.fullmatch(r"[+-]?[0-9]+", key):  # ASCII digits only: "³" is not a joint number
        if not 1 <= int(key) <= robot.n:
            raise InputError(f"{option}: joint number {key}; expected 1 to {robot.n}")
        return int(key) - 1
    raise InputError(f"{option}: no joint {key!r}; expected a joint number 1 to {robot.n} "
                     f"or a name ({', '.join(robot.joint_names)})")


def to_si(robot: Robot, q: Sequence[float | str], degrees: bool, name: str = "joint values") -> np.ndarray:
    """Joint values from the command line in SI units (``--deg`` converts revolute joints only);
    ``name`` says where they were typed (an option such as ``--near``) in an error."""
    reject_unknown_options([str(v) for v in q])
    q = robot.check_q(np.asarray(parse_floats(q, name), dtype=float), name)
    if degrees:
        q = np.where(robot.chain.prismatic, q, np.radians(q))
    return q


def fmt_number(value: float, digits: int = 4) -> str:
    """``value`` with ``digits`` decimals, never ``-0.0000``: the one number format of tables.

    A value that rounds to zero prints as zero (a ``-6.97e-18`` beside 4-decimal values is
    ``0.0000``); non-finite values print as ``inf``, ``-inf`` or ``nan``.

    >>> fmt_number(-6.97e-18), fmt_number(-0.5, 2), fmt_number(float("inf"))
    ('0.0000', '-0.50', 'inf')
    """
    text = f"{value:.{digits}f}"
    return text[1:] if text.startswith("-") and math.isfinite(value) and float(text) == 0 else text


def fmt_numbers(values: Sequence[float], digits: int = 4) -> str:
    """``[a, b, c]`` with :func:`fmt_number` for each."""
    return "[" + ", ".join(fmt_number(float(v), digits) for v in values) + "]"


def option_values(first: str | None, rest: Sequence[str] | None, option: str, what: str) -> list[str] | None:
    """The words of an option with as many values as the robot has joints, or ``None`` if not given.

    Typer options take a fixed number of values, so ``option`` takes the first word and the
    command's trailing arguments collect the rest: ``--near 0 -0.5 0.5`` and the comma list
    ``--near 0,-0.5,0.5`` give the same three words. Trailing values without the option are
    refused, naming ``what`` they would have been.
    """
    reject_unknown_options(rest or [])
    if first is None:
        if rest:
            raise InputError(f"unexpected values {' '.join(rest)}: {what} are given after {option} "
                             f"(e.g. {option} 0 0 0 or {option} 0,0,0)")
        return None
    if first.startswith("--"):  # "--near --json": the option took the next option as its value
        raise InputError(f"{option}: expected {what} after it (e.g. {option} 0 0 0; leave {option} out "
                         f"for the default), got the option {first}")
    return [word for word in first.replace(",", " ").split()] + list(rest or [])


def reject_unknown_options(words: Sequence[str]) -> None:
    """Raise for a word like ``--deg`` among a command's trailing values: an option it does not have.

    Commands that read negative numbers as values let Typer pass unknown options through
    with them; without this check ``--typo`` would be reported as a misplaced value.
    """
    for word in words:
        if word.startswith("--") and len(word) > 2:
            raise InputError(f"no such option: {word} (see the command's --help)")


def warn(message: str) -> None:
    """A yellow warning line on stderr (one line, however long: it may be grepped)."""
    err_console.print(f"[yellow]warning:[/yellow] {escape(message)}", highlight=False, soft_wrap=True)


def check_limits_or_warn(robot: Robot, q: np.ndarray, strict: bool, degrees: bool = False) -> None:
    """Warn about joint values outside their limits, or fail with ``--strict``."""
    violations = robot.limit_violations(q, degrees)
    if violations and strict:
        robot.check_limits(q, degrees)
    for message in violations:
        warn(message)


def _plain(value: Any) -> Any:
    if isinstance(value, np.ndarray):
        return _plain(value.tolist())
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_plain(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, np.generic):
        return _plain(value.item())
    return value


#: The unit of joint values in ``--json`` (always SI, whatever ``--deg`` says).
JOINT_UNITS = "rad (revolute), m (prismatic)"


def print_json(data: dict, units: dict[str, str] | None = None) -> None:
    """Print ``data`` as JSON on stdout (arrays become lists, non-finite numbers null), in SI units,
    with ``units`` (field: unit) as its ``"units"`` object (docs/cli.md, Output)."""
    if units is not None:
        data = {**data, "units": units}
    typer.echo(json.dumps(_plain(data), indent=2))


def parse_floats(values: Sequence[float | str], what: str) -> list[float]:
    """Numbers from command-line words, with an error naming the bad word."""
    out = []
    for word in values:
        try:
            out.append(float(word))
        except ValueError as exc:
            raise InputError(f"{what}: {word!r} is not a number") from exc
    return out
