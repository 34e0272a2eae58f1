"""Numbers in tables: significant digits for quantities that span orders of magnitude."""

from __future__ import annotations

import math

__all__ = ["NOISE", "fmt_significant"]

#: Below this fraction of its column's largest magnitude, a value in :func:`fmt_significant` is
#: rounding noise (a -6.97e-18 N m beside 12 N m) and shows as 0.
NOISE = 1e-12


def fmt_significant(value: float, scale: float = 0.0, digits: int = 4) -> str:
    """``value`` with ``digits`` significant digits, for quantities that span orders of magnitude
    (torques: ``5e-05`` is not ``0.0000``); below :data:`NOISE` times ``scale`` (the largest
    magnitude beside it) it is ``0``; non-finite values print as ``inf``, ``-inf`` or ``nan``.

    >>> fmt_significant(5.04e-5), fmt_significant(123.456), fmt_significant(-6.97e-18, scale=12.0)
    ('5.04e-05', '123.5', '0')
    """
    if math.isnan(value) or math.isinf(value):
        return f"{value}"
    if abs(value) <= NOISE * scale or value == 0:
        return "0"
    return f"{value:.{digits}g}"
