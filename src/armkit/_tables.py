"""Reading TOML tables: the values, units, key checks and transforms robot files and scene files share.

Every reader names where a bad value is (``where``: file, table, key) and raises
:class:`~armkit.errors.RobotDefinitionError`.
"""

from __future__ import annotations

import math
import tomllib
from types import MappingProxyType
from typing import Any

import numpy as np
from numpy.typing import NDArray

from armkit.chain import MAX_VALUE
from armkit.errors import ArmkitError, InputError, RobotDefinitionError
from armkit.spatial.rotations import matrix_from_euler
from armkit.spatial.transforms import check_transform, transform_from

__all__ = ["ANGLE_UNITS", "LENGTH_UNITS", "check_table_keys", "shown_value", "table_choice", "table_number",
           "table_quantity", "table_transform", "table_vector", "toml_table"]

#: Units a file may write its lengths and angles in, and their factor to SI.
LENGTH_UNITS = MappingProxyType({"m": 1.0, "mm": 1e-3})
ANGLE_UNITS = MappingProxyType({"rad": 1.0, "deg": math.pi / 180.0})
_TRANSFORM_KEYS = {"xyz", "rpy", "matrix"}


def toml_table(data: bytes, source: str, what: str = "robot file",
               error: type[ArmkitError] = RobotDefinitionError) -> dict[str, Any]:
    """The TOML table of a file's bytes, or one ``error`` naming ``source`` (not UTF-8, not TOML)."""
    try:
        text = data.decode("utf-8-sig")  # a byte order mark (some Windows editors write one) is skipped
    except UnicodeDecodeError as exc:
        raise error(f"{source}: not UTF-8 text (byte {exc.start}); save the {what} as UTF-8") from exc
    if not text.strip():
        raise error(f"{source}: the file is empty; expected a {what}")
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise error(f"{source}: not valid TOML: {exc}") from exc
    except RecursionError as exc:
        raise error(f"{source}: arrays or tables nested too deeply to read") from exc


def table_number(value: Any, where: str) -> float:
    """A finite number (not a bool), or an error naming ``where``."""
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise RobotDefinitionError(f"{where}: expected a finite number, got {shown_value(value)}")
    return float(value)


def table_quantity(value: Any, where: str, unit: float) -> float:
    """A length or angle in SI units, at most :data:`MAX_VALUE` in magnitude."""
    number = table_number(value, where) * unit
    if not abs(number) <= MAX_VALUE:
        raise RobotDefinitionError(f"{where}: {value!r} is {abs(number):.3g} in SI units (m or rad); "
                                   f"expected at most {MAX_VALUE:g}")
    return number


def shown_value(value: Any) -> str:
    """A value as an error message shows it (``repr``, long ones cut)."""
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def table_vector(value: Any, where: str, unit: float, size: int = 3) -> NDArray[np.float64]:
    """A list of ``size`` finite numbers, times ``unit`` (to SI)."""
    if not isinstance(value, list) or len(value) != size:
        raise RobotDefinitionError(f"{where}: expected {size} numbers, got {shown_value(value)}")
    return np.array([table_quantity(v, where, unit) for v in value])


def table_choice(data: dict, key: str, options: dict | tuple, source: str, default: str | None) -> str:
    """``data[key]`` (or ``default``), one of ``options``, or an error naming the key and the options."""
    value = data.get(key, default)
    if value is None:
        raise RobotDefinitionError(f"{source}: missing key {key!r} (one of {', '.join(options)})")
    if not isinstance(value, str) or value not in options:
        raise RobotDefinitionError(
            f"{source}: {key} = {shown_value(value)}; expected one of {', '.join(map(repr, options))}")
    return value


def check_table_keys(table: Any, allowed: set[str], required: set[str], where: str) -> None:
    """``table`` is a TOML table with every ``required`` key and no key outside ``allowed``."""
    if not isinstance(table, dict):
        raise RobotDefinitionError(f"{where}: expected a table, got {shown_value(table)}")
    unknown = sorted(set(table) - allowed)
    if unknown:
        raise RobotDefinitionError(f"{where}: unknown key {unknown[0]!r}; expected keys: "
                                   f"{', '.join(sorted(allowed))}")
    missing = sorted(required - set(table))
    if missing:
        raise RobotDefinitionError(f"{where}: missing key {missing[0]!r}")


def table_transform(table: dict, where: str, length: float, angle: float) -> NDArray[np.float64]:
    """A ``[base]`` / ``[tool]`` table: ``xyz`` + ``rpy`` or ``matrix``, to SI."""
    check_table_keys(table, _TRANSFORM_KEYS, set(), where)
    if "matrix" in table:
        if set(table) != {"matrix"}:
            raise RobotDefinitionError(f"{where}: give either matrix or xyz and rpy, not both")
        rows = table["matrix"]
        if not isinstance(rows, list) or len(rows) != 4 or not all(isinstance(r, list) and len(r) == 4
                                                                   for r in rows):
            raise RobotDefinitionError(f"{where}, key 'matrix': expected 4 rows of 4 numbers")
        T = np.array([[table_number(v, f"{where}, key 'matrix'") for v in row] for row in rows])
        try:
            T = check_transform(T, f"{where}, key 'matrix'")
        except InputError as exc:
            raise RobotDefinitionError(str(exc)) from exc
        T[:3, 3] = table_vector(T[:3, 3].tolist(), f"{where}, key 'matrix' (translation)", length)
        return T
    xyz = table_vector(table.get("xyz", [0, 0, 0]), f"{where}, key 'xyz'", length)
    rpy = table_vector(table.get("rpy", [0, 0, 0]), f"{where}, key 'rpy'", angle)
    return transform_from(matrix_from_euler(rpy, "xyz-fixed"), xyz)
