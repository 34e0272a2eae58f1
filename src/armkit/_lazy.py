"""Packages whose public names are imported on first use (PEP 562).

``import armkit`` (or ``armkit.trajectory``) then costs what the names a program uses
cost: a command that only needs FK never loads SciPy's interpolation or optimisation
code. ``from armkit.trajectory import quintic`` and ``armkit.trajectory.quintic`` work as
with eager imports, and so does a subpackage: after ``import armkit`` alone,
``armkit.export.write_urdf`` imports :mod:`armkit.export` on first use.
"""

from __future__ import annotations

import importlib
import importlib.util
import sys
from collections.abc import Callable
from typing import Any


def lazy_exports(package: str, modules: dict[str, list[str]]) -> tuple[Callable[[str], Any],
                                                                       Callable[[], list[str]], list[str]]:
    """``(__getattr__, __dir__, __all__)`` for ``package``, whose public names live in
    ``modules`` (module name -> names). A name, once imported, is kept in the package; a
    public name that is none of them but a submodule's (``armkit.export``) imports it.

    >>> getattr_, dir_, all_ = lazy_exports("armkit", {"armkit.errors": ["InputError"]})
    >>> getattr_("InputError").__name__, all_
    ('InputError', ['InputError'])
    >>> getattr_("export").__name__
    'armkit.export'
    """
    where = {name: module for module, names in modules.items() for name in names}

    def __getattr__(name: str) -> Any:
        module = where.get(name)
        if module is None:
            submodule = f"{package}.{name}"
            if not name.startswith("_") and importlib.util.find_spec(submodule) is not None:
                return importlib.import_module(submodule)  # which also sets it on the package
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(module), name)
        setattr(sys.modules[package], name, value)
        return value

    def __dir__() -> list[str]:
        return sorted({*vars(sys.modules[package]), *where})

    return __getattr__, __dir__, sorted(where)
