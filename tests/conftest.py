"""Shared test helpers: import them as ``from conftest import assert_transform_close``."""

from __future__ import annotations

import os

import numpy as np
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
