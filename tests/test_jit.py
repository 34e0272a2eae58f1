"""armkit._jit: compiled entry points and the compile notice."""

import numpy as np
from numba import njit

from armkit._jit import announce_compilation, entry_point


def test_entry_point_computes_what_the_dispatcher_does():
    @njit
    def weighted_sum(values, weights):
        return (values * weights).sum()

    values, weights = np.arange(5.0), np.linspace(0.0, 1.0, 5)
    compiled = entry_point(weighted_sum, values, weights)
    assert compiled(values, weights) == weighted_sum(values, weights) == float(values @ weights)


def test_the_notice_comes_once_and_only_when_numba_compiles():
    @njit
    def first(x):
        return x + 1.0

    @njit
    def second(x):
        return first(x) * 2.0

    notices = []
    with announce_compilation(lambda: notices.append("compiling")):
        assert second(1.0) == 4.0  # compiles second, and first inside it
        assert second(2.0) == 6.0  # compiled already
    assert notices == ["compiling"]
    with announce_compilation(lambda: notices.append("again")):
        second(3.0)  # nothing left to compile
    assert notices == ["compiling"]
    first(1)  # an int: a new compilation, but outside any block
    assert notices == ["compiling"]
