"""Every numeric parameter is checked by one helper per kind (``armkit._params``): a bad value is
one ``InputError`` naming the parameter, the value and the valid range, never a silent failure,
a raw ``TypeError`` from the bindings or a NaN later."""

from __future__ import annotations

import contextlib
import io
import json
import math
import os
import re
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit
from armkit.errors import InputError
from armkit.ik.numeric import NumericIK, numeric_ik
from armkit.trajectory import lspb, min_jerk, plan_trajectory, quintic

PANDA = armkit.load("panda")
PUMA = armkit.load("puma560")
T_PANDA = PANDA.fk([0.1, -0.3, 0.2, -2.0, 0.1, 1.8, 0.5])

BAD_SOLVER_OPTIONS = [
    ("position_tolerance", -1, r"a finite number > 0"),
    ("position_tolerance", math.nan, r"a finite number > 0"),
    ("orientation_tolerance", 0.0, r"a finite number > 0"),
    ("orientation_tolerance", math.inf, r"a finite number > 0"),
    ("damping", math.nan, r"a finite number >= 0"),
    ("damping", math.inf, r"a finite number >= 0"),
    ("damping", -1, r"a finite number >= 0"),
    ("damping_gain", -0.1, r"a finite number >= 0"),
    ("max_iterations", 10**12, r"a whole number from 1 to 2147483647"),
    ("max_iterations", 0, r"a whole number from 1 to 2147483647"),
    ("max_iterations", 30.0, r"a whole number from 1 to 2147483647"),
    ("max_restarts", 2**40, r"a whole number from 0 to 2147483647"),
    ("max_restarts", -1, r"a whole number from 0 to 2147483647"),
    ("time_budget", math.nan, r"a number >= 0 \(inf: no bound\)"),
    ("time_budget", -1.0, r"a number >= 0 \(inf: no bound\)"),
]


@pytest.mark.parametrize(("name", "value", "expected"), BAD_SOLVER_OPTIONS)
def test_numeric_ik_refuses_each_bad_option_naming_it_the_value_and_the_range(name, value, expected):
    message = re.escape(f"{name}: expected ") + expected + re.escape(f", got {value!r}")
    with pytest.raises(InputError, match=message):
        numeric_ik(PANDA, T_PANDA, rng=0, **{name: value})
    with pytest.raises(InputError, match=message):
        NumericIK(PANDA, **{name: value})


def test_numeric_ik_still_solves_with_an_unbounded_time_budget():
    result = numeric_ik(PANDA, T_PANDA, rng=0, time_budget=math.inf, max_restarts=3)
    assert result.success and result.position_error < 1e-9


WAYPOINTS = np.array([[0.0] * 6, [0.3] * 6, [-0.3] * 6])  # inside the PUMA 560's limits


@pytest.mark.parametrize("duration", [1e-300, 1e200, 5e-7, 2e6])
def test_trajectory_durations_outside_the_float_safe_range_are_refused_without_warnings(duration):
    message = re.escape(f"every segment duration must be from 1e-06 s to 1e+06 s, got {duration:g} s "
                        f"for segment 1")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no RuntimeWarning before the refusal
        with pytest.raises(InputError, match="durations: " + message):
            plan_trajectory(PUMA, WAYPOINTS, [duration, 1.0], fit_limits=False)
        with pytest.raises(InputError, match="durations: " + message):
            min_jerk(WAYPOINTS, [duration, 1.0])
        for profile in (quintic, lspb):
            with pytest.raises(InputError, match="duration: " + message):
                profile(0.0, 1.0, duration)


@pytest.mark.parametrize("duration", [1e-6, 1e6])
def test_the_shortest_and_longest_durations_give_finite_trajectories(duration):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        trajectory = plan_trajectory(PUMA, WAYPOINTS, [duration, duration], fit_limits=False)
        q, qd, qdd = trajectory.at_time(np.linspace(0.0, 2 * duration, 7))
    np.testing.assert_allclose(q[[0, 3, 6]], WAYPOINTS, atol=1e-12)
    assert np.isfinite(qd).all() and np.isfinite(qdd).all()


ANY_VALUE = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.integers(-2**70, 2**70),
                      st.booleans(), st.none(), st.text(max_size=3))


@settings(deadline=None)
@given(name=st.sampled_from(sorted({name for name, _, _ in BAD_SOLVER_OPTIONS} | {"threads"})),
       value=ANY_VALUE)
def test_fuzz_numeric_ik_options_solve_or_name_the_option(name, value):
    try:
        if name == "threads":
            result = NumericIK(PANDA, max_restarts=2).solve_batch(T_PANDA[None], rng=0, threads=value)[0]
        else:
            options = {"max_restarts": 2, "time_budget": 0.05} | {name: value}
            result = numeric_ik(PANDA, T_PANDA, rng=0, **options)
    except InputError as exc:
        assert str(exc).startswith(f"{name}: expected ") and str(exc).endswith(f"got {value!r}")
    else:
        assert result.q.shape == (7,) and np.isfinite(result.q).all()


LOCK_KEY = st.one_of(st.integers(-2, 8).map(str),
                     st.sampled_from(["+1", "q1", "q6", "q9", "", " 2", "1.0", "x"]))
LOCK_VALUE = st.one_of(st.sampled_from(["0.1", "-0.2", "1e300", "-1e300", "nan", "inf", "1e-300", "abc", ""]),
                       st.floats(allow_nan=True, allow_infinity=True).map(repr))


#: hypothesis's default 100 CLI runs, fewer in `make test-fast` (ARMKIT_FUZZ_EXAMPLES=30): 18 s there before.
LOCK_FUZZ_EXAMPLES = min(100, int(os.environ.get("ARMKIT_FUZZ_EXAMPLES", "100")))


@settings(deadline=None, max_examples=LOCK_FUZZ_EXAMPLES)
@given(locks=st.lists(st.tuples(LOCK_KEY, LOCK_VALUE), min_size=1, max_size=3))
def test_fuzz_cli_lock_values_lock_the_arm_or_are_one_line(locks):
    from armkit.cli.main import main

    argv = ["show", "puma560", "--json"]
    for key, value in locks:
        argv += ["--lock", f"{key}={value}"]
    err = io.StringIO()
    out = io.StringIO()
    with warnings.catch_warnings(), contextlib.redirect_stderr(err), contextlib.redirect_stdout(out):
        warnings.simplefilter("error")  # no RuntimeWarning on the way
        code = main(argv)
    assert code in (0, 1) and "Traceback" not in err.getvalue()
    if code == 1:
        lines = err.getvalue().strip().splitlines()
        assert len(lines) == 1, lines
        assert re.match(r"error: (--lock '|joint |cannot lock: |locking all )", lines[0]), lines
    else:
        assert json.loads(out.getvalue())["locked"]


@pytest.mark.parametrize("size", [-1, 10**30, 2.5, (2, -1), "3"])
def test_random_q_sizes_are_whole_numbers(size):
    message = re.escape("size: expected a whole number from 0 to 2147483647, got ")
    with pytest.raises(InputError, match=message):
        PUMA.random_q(size)
