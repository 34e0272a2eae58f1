"""Shared test helpers: import them as ``from conftest import assert_transform_close``."""

from __future__ import annotations

import os
import signal
import time
from collections.abc import Callable

import numpy as np
import pytest
from hypothesis import settings

from armkit.spatial.rotations import rotation_angle_between

# CI runs the same examples every time (a failure there is reproducible from its log);
# locally hypothesis explores new ones on every run.
settings.register_profile("ci", derandomize=True, print_blob=True)
# `make fuzz` (HYPOTHESIS_PROFILE=fuzz): the fuzz tests with many more examples, no deadline.
settings.register_profile("fuzz", max_examples=400, deadline=None, print_blob=True)
if os.environ.get("HYPOTHESIS_PROFILE") == "fuzz":
    settings.load_profile("fuzz")
elif os.environ.get("CI"):
    settings.load_profile("ci")


#: Upper bound on any wait for an event (a page update, a subprocess's line or exit, a file
#: appearing) [s]. Waits end as soon as the event happens, so the bound only decides how long a
#: broken test hangs; it is generous so that a machine 3-5x slower than a quiet one (a shared CI
#: runner, a 2-core laptop building something) still passes. ``ARMKIT_TEST_WAIT`` overrides it.
WAIT_S = float(os.environ.get("ARMKIT_TEST_WAIT", "600"))


def wait_until(condition: Callable[[], bool], what: str, timeout_s: float = WAIT_S,
               poll_s: float = 0.05) -> None:
    """Poll ``condition`` until it is true; fail the test naming ``what`` after ``timeout_s`` [s]."""
    deadline = time.monotonic() + timeout_s
    while not condition():
        if time.monotonic() > deadline:
            pytest.fail(f"waited {timeout_s:.0f} s for {what}")
        time.sleep(poll_s)


def interruptible() -> None:
    """``preexec_fn`` of a child process the test interrupts with SIGINT: Ctrl-C's default action,
    even when this run ignores SIGINT (a background job of a shell without job control, as CI may
    start it), which the child would inherit."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


@pytest.fixture
def python_handles_sigint():
    """Python's own Ctrl-C handler in this process for the test (``_thread.interrupt_main`` does
    nothing where SIGINT is ignored), the previous one afterwards."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


def core_internals():
    """``armkit._core`` with the internals only the tests call (``rank``, ``verify_candidates``,
    ``project``, ``damped_step``, ``quartic_roots``): bound when the core is built with CMake's
    ``ARMKIT_TEST_BINDINGS``, as ``make test`` / ``make test-fast`` (and so CI) build it. A core built
    without them fails the test saying so, rather than skipping what it cannot check."""
    from armkit import _core

    if not _core.TEST_BINDINGS:
        pytest.fail("armkit's core was built without its test bindings: rebuild it with `make "
                    ".venv/.installed-test`, or pip install -e '.[test]' "
                    "-Ccmake.define.ARMKIT_TEST_BINDINGS=ON")
    return _core


def assert_transform_close(T_actual, T_expected, position_tol: float = 1e-10,
                           angle_tol: float = 1e-10) -> None:
    """Assert two (batches of) 4x4 transforms agree: position [m] and rotation angle [rad]."""
    T_actual = np.asarray(T_actual, dtype=float)
    T_expected = np.asarray(T_expected, dtype=float)
    assert T_actual.shape == T_expected.shape, f"shapes {T_actual.shape} != {T_expected.shape}"
    position_error = np.linalg.norm(T_actual[..., :3, 3] - T_expected[..., :3, 3], axis=-1)
    angle_error = rotation_angle_between(T_actual, T_expected)
    assert np.all(position_error <= position_tol), f"position error {position_error.max():.3g} m"
    assert np.all(angle_error <= angle_tol), f"rotation error {angle_error.max():.3g} rad"
    np.testing.assert_allclose(T_actual[..., 3, :], T_expected[..., 3, :], atol=1e-12)
