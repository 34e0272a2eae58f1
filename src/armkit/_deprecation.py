"""Old names kept working for a deprecation period, each with a :class:`DeprecationWarning`.

The version story: armkit 0.1.0 is the version these names were renamed in (no release since
has changed ``pyproject.toml``'s version); every old name keeps working through the 0.1 series
and goes in armkit 0.2.0. Every warning says so, ``... is deprecated since armkit 0.1.0 (removed
in 0.2.0): use ...`` (the test suite turns such warnings into errors, so armkit itself never
uses an old name). The renames and why are listed in ``docs/architecture.md`` ("One API
vocabulary").

>>> import warnings
>>> with warnings.catch_warnings(record=True) as caught:
...     warnings.simplefilter("always")
...     renamed_argument("f", "rate", "rate_hz", 50.0, 100.0, 100.0)
50.0
>>> str(caught[0].message)
'f(rate=...) is deprecated since armkit 0.1.0 (removed in 0.2.0): use rate_hz=... instead'
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from typing import Any

from armkit.errors import InputError

__all__ = ["REMOVED_IN", "SINCE", "deprecated_constants", "deprecated_function", "deprecated_method",
           "deprecated_property", "renamed_argument", "warn_deprecated"]

#: The release that renamed the old names, and the one that removes them.
DEPRECATED_IN, REMOVED_IN = "0.1.0", "0.2.0"
#: What every deprecation message says (``pyproject.toml`` makes it an error in the tests).
SINCE = f"is deprecated since armkit {DEPRECATED_IN} (removed in {REMOVED_IN})"


def warn_deprecated(old: str, new: str, stacklevel: int = 3) -> None:
    """Warn that ``old`` is deprecated in favour of ``new``; ``stacklevel`` 3 points at the
    caller of the function that calls this one."""
    warnings.warn(f"{old} {SINCE}: use {new} instead", DeprecationWarning, stacklevel=stacklevel)


def renamed_argument(where: str, old: str, new: str, old_value: Any, new_value: Any, default: Any) -> Any:
    """The value of argument ``new`` of ``where``, given as ``new_value`` or, under its
    deprecated name ``old``, as ``old_value`` (``None``: not given), with a warning.

    Raises
    ------
    InputError
        If both names are given (``new_value`` is not its ``default``).
    """
    if old_value is None:
        return new_value
    warn_deprecated(f"{where}({old}=...)", f"{new}=...", stacklevel=4)
    if new_value is not default and new_value != default:
        raise InputError(f"{where}: got both {old}={old_value!r} and {new}={new_value!r}; give only {new} "
                         f"({old} is its old name)")
    return old_value


def deprecated_property(old: str, new: str) -> property:
    """A read-only property ``old`` that warns and returns attribute ``new``."""

    def getter(self: Any) -> Any:
        warn_deprecated(f"{type(self).__name__}.{old}", f".{new}")
        return getattr(self, new)

    getter.__doc__ = f"Deprecated alias of :attr:`{new}`."
    return property(getter)


def deprecated_method(old: str, new: str) -> Callable[..., Any]:
    """A method ``old`` that warns and calls method ``new`` with the same arguments."""

    def method(self: Any, *args: Any, **kwargs: Any) -> Any:
        warn_deprecated(f"{type(self).__name__}.{old}()", f".{new}()")
        return getattr(self, new)(*args, **kwargs)

    method.__doc__ = f"Deprecated alias of :meth:`{new}`."
    method.__name__ = old
    return method


def deprecated_function(old: str, new: Callable[..., Any]) -> Callable[..., Any]:
    """A function ``old`` that warns and calls ``new`` with the same arguments."""

    def function(*args: Any, **kwargs: Any) -> Any:
        warn_deprecated(f"{old}()", f"{new.__name__}()")
        return new(*args, **kwargs)

    function.__doc__ = f"Deprecated alias of :func:`{new.__name__}`."
    function.__name__ = old
    return function


def deprecated_constants(module: str, names: dict[str, str], values: dict[str, Any]) -> Callable[[str], Any]:
    """A module ``__getattr__`` (PEP 562) for constants renamed ``old -> new``: the old name
    warns and returns ``values[new]``."""

    def __getattr__(name: str) -> Any:
        if name in names:
            warn_deprecated(f"{module}.{name}", f"{module}.{names[name]}")
            return values[names[name]]
        raise AttributeError(f"module {module!r} has no attribute {name!r}")

    return __getattr__
