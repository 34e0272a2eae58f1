"""The package's exception classes.

Every error armkit raises on bad input derives from :class:`ArmkitError`, so a caller
can catch them all at once, and the CLI turns them into one-line messages.
"""

from __future__ import annotations

import os
import sys
import warnings

__all__ = [
    "ArmkitError",
    "CollisionError",
    "ConvergenceError",
    "InputError",
    "JointLimitError",
    "NoClosedFormError",
    "PlanningError",
    "RobotDefinitionError",
    "SolutionsLeftOffWarning",
    "UnreachableError",
]


class ArmkitError(Exception):
    """Base class of every error armkit raises on purpose."""


class InputError(ArmkitError, ValueError):
    """An argument has the wrong shape, type or value (NaN, non-rigid matrix, ...).

    Attributes
    ----------
    parameter : str or None
        The argument's name, where the check that raised knows it (every check of
        :mod:`armkit._params` does: ``"threads"``, ``"position_tolerance"``, ...).
    value : object
        The value it refused (None where not given).

    Examples
    --------
    >>> import armkit
    >>> try:
    ...     armkit.load("ur5").fk([0.0] * 6, threads=0)
    ... except InputError as exc:
    ...     exc.parameter, exc.value
    ('threads', 0)
    """

    def __init__(self, message: str, *, parameter: str | None = None, value: object = None) -> None:
        super().__init__(message)
        self.parameter = parameter
        self.value = value


class RobotDefinitionError(ArmkitError, ValueError):
    """A robot description (file or code) is incomplete or inconsistent."""


class JointLimitError(ArmkitError, ValueError):
    """A joint value lies outside the joint's limits.

    The message says it in words; the attributes say it in numbers (SI units, whatever units
    the message uses), so a caller need not parse the message.

    Attributes
    ----------
    q : ndarray or None
        The configuration ``(n,)`` [rad or m] the message is about, where there is one (so
        that a caller can say it again in its own units), else None.
    joint : str or None
        The name of the (first) joint outside its limits, where one is known.
    value : float or None
        That joint's value [rad or m].
    limits : tuple of (float, float) or None
        That joint's ``(lower, upper)`` limits [rad or m].

    Examples
    --------
    >>> import armkit
    >>> robot = armkit.load("panda")
    >>> try:
    ...     robot.check_limits([0, 0, 0, 0.5, 0, 1.0, 0])
    ... except JointLimitError as exc:
    ...     exc.joint, exc.value, exc.limits
    ('q4', 0.5, (-3.0718, -0.0698))
    """

    def __init__(self, message: str, q: object = None, *, joint: str | None = None,
                 value: float | None = None, limits: tuple[float, float] | None = None) -> None:
        super().__init__(message)
        self.q = q
        self.joint = joint
        self.value = value
        self.limits = limits


class UnreachableError(ArmkitError):
    """A target pose cannot be reached; the attributes say how far the closest pose found is.

    Attributes
    ----------
    position_error : float
        Distance [m] between the target and the closest tool position found.
    orientation_error : float
        Angle [rad] between the target and the closest tool orientation found.
    """

    def __init__(self, message: str, position_error: float = float("nan"),
                 orientation_error: float = float("nan")) -> None:
        super().__init__(message)
        self.position_error = position_error
        self.orientation_error = orientation_error


class CollisionError(ArmkitError):
    """Every answer found collides with the scene (:class:`armkit.Scene`): the IK solutions of a pose, say.

    Attributes
    ----------
    q : ndarray or None
        The colliding configuration(s) ``(..., n)`` [rad or m] the message is about, if any.
    contacts : list of (str, str)
        The part pairs in contact at the nearest of them.
    """

    def __init__(self, message: str, q: object = None, contacts: list[tuple[str, str]] | None = None) -> None:
        super().__init__(message)
        self.q = q
        self.contacts = [] if contacts is None else contacts


def pair_text(contacts: list[tuple[str, str]], none: str = "no pair in contact") -> str:
    """A :class:`CollisionError`'s contacts as messages and tables name them, ``'link3-wall, link4-wall'``
    (``none`` if there are none)."""
    return ", ".join(f"{a}-{b}" for a, b in contacts) or none


class ConvergenceError(ArmkitError):
    """An iterative solver did not reach its tolerance within its budget.

    Attributes
    ----------
    rounds : int or None
        The budget spent (iterations or rounds).
    last_change : float
        The solver's last relative change (``nan`` if it has none), what would have had to fall
        below its tolerance.
    """

    def __init__(self, message: str, *, rounds: int | None = None, last_change: float = float("nan")) -> None:
        super().__init__(message)
        self.rounds = rounds
        self.last_change = last_change


class NoClosedFormError(ArmkitError):
    """A closed-form solution was asked of a chain whose geometry has none."""


class PlanningError(ArmkitError):
    """No collision-free motion was found: no path within the time budget, or no timing of the path
    passed the collision check (see :func:`armkit.plan_path`; a colliding start or goal is a
    :class:`CollisionError`).

    Attributes
    ----------
    time_budget : float or None
        The search's budget [s] when no path was found in it, else None.
    segment : int or None
        The path segment (1-based) whose timed motion left the checked path, else None.
    """

    def __init__(self, message: str, *, time_budget: float | None = None, segment: int | None = None) -> None:
        super().__init__(message)
        self.time_budget = time_budget
        self.segment = segment


class SolutionsLeftOffWarning(UserWarning):
    """More solutions exist than are listed (e.g. whole-turn copies of joints whose limits
    span several turns); the nearest ones are listed. Not an error: a warning."""


def missing_extra(extra: str, needs: str) -> ArmkitError:
    """The error for an optional dependency that is not installed: ``needs`` says what needs it
    (``"plots need matplotlib"``), and the message how to install it (armkit's extra ``extra``).

    >>> str(missing_extra("plot", "plots need matplotlib and Pillow"))
    "plots need matplotlib and Pillow, which are not installed: pip install 'armkit[plot]'"
    """
    return ArmkitError(f"{needs}, which are not installed: pip install 'armkit[{extra}]'")


def warn_at_caller(warning: Warning) -> None:
    """Issue ``warning`` attributed to the first caller outside the armkit package (so the
    user's line is named, however deep inside armkit it arose)."""
    package = os.path.dirname(os.path.abspath(__file__))
    frame, level = sys._getframe(1), 2  # stacklevel 2: the function calling this one
    while frame is not None and os.path.abspath(frame.f_code.co_filename).startswith(package + os.sep):
        frame, level = frame.f_back, level + 1
    warnings.warn(warning, stacklevel=level)
