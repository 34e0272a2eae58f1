"""Verification tables: computed vs simulated poses in the user's convention."""

from __future__ import annotations

import numpy as np
import pytest

import armkit
from armkit.errors import InputError
from armkit.sim import Simulation, compare_poses
from armkit.spatial.rotations import matrix_from_euler
from armkit.spatial.transforms import transform_from


def test_zju_report_row_in_xyz_euler_degrees():
    robot = armkit.load("zju-i")
    q = np.full((1, 6), np.pi / 12)
    table = compare_poses(robot.fk(q), Simulation(robot).tool_pose(q), convention="xyz-euler", degrees=True)
    # report 003, computed: [0.226, 0.107, 0.552, -148.00, 36.35, -107.00]
    np.testing.assert_allclose(table.computed[0], [0.226, 0.107, 0.552, -148.00, 36.35, -107.00], atol=6e-3)
    assert table.columns == ["x [m]", "y [m]", "z [m]", "a1 (x) [deg]", "a2 (y) [deg]", "a3 (z) [deg]"]
    assert table.max_errors()[0] < 1e-12 and table.max_errors()[1] < 1e-7


def test_per_axis_errors_wrap_and_match_a_known_offset():
    R = matrix_from_euler([[179.9, 10, 20]], "xyz-fixed", degrees=True)
    R_moved = matrix_from_euler([[-179.9, 10, 20]], "xyz-fixed", degrees=True)
    table = compare_poses(transform_from(R, [[0.1, 0.2, 0.3]]), transform_from(R_moved, [[0.1, 0.2, 0.3005]]),
                          degrees=True, length_unit="mm", labels=["a"])
    np.testing.assert_allclose(table.error[0], [0, 0, 0.5, 0.2, 0, 0], atol=1e-9)
    np.testing.assert_allclose(table.orientation_error, np.radians(0.2), rtol=1e-9)
    np.testing.assert_allclose(table.position_error, 5e-4, rtol=1e-9)


def test_bad_input():
    T = np.eye(4)[None]
    with pytest.raises(InputError, match="expected 1 poses"):
        compare_poses(T, np.stack([np.eye(4)] * 2))
    with pytest.raises(InputError, match="length_unit 'cm'"):
        compare_poses(T, T, length_unit="cm")
    with pytest.raises(InputError, match="unknown angle convention"):
        compare_poses(T, T, convention="abc")
    with pytest.raises(InputError, match="labels: expected 1"):
        compare_poses(T, T, labels=["a", "b"])
