"""Dexterity, manipulability, the design sweep and the IK data set, against direct computation."""

from __future__ import annotations

import numpy as np
import pytest

import armkit
from armkit import workspace
from armkit.errors import InputError, JointLimitError, NoClosedFormError, UnreachableError
from armkit.workspace.orientations import super_fibonacci
from armkit.workspace.sampling import SamplePlan, configurations
from armkit.workspace.sweep import robot_with


def planar_2r(l1: float, l2: float) -> armkit.Robot:
    return armkit.Robot.from_dh([armkit.DHRow(0, l1, 0, 0), armkit.DHRow(0, l2, 0, 0)], "standard",
                                limits=[(-np.pi, np.pi)] * 2)


def test_super_fibonacci_rotations_cover_so3_evenly():
    R = super_fibonacci(2000)
    np.testing.assert_allclose(np.linalg.det(R), 1.0, atol=1e-12)
    # Haar measure: E[R] = 0, and the rotation angle has density (1 - cos t) / pi on [0, pi].
    np.testing.assert_allclose(R.mean(axis=0), 0.0, atol=0.02)
    angle = np.arccos(np.clip((np.trace(R, axis1=1, axis2=2) - 1) / 2, -1, 1))
    expected_mean = np.pi / 2 + 2 / np.pi      # integral of t (1 - cos t) / pi over [0, pi]
    assert abs(angle.mean() - expected_mean) < 0.01
    with pytest.raises(InputError, match="orientations: expected a positive whole number"):
        super_fibonacci(0)


def test_dexterity_counts_are_those_of_robot_ik_at_each_voxel_centre():
    robot = armkit.load("probot-anno")
    dex = workspace.dexterity(robot, resolution=0.12, orientations=6, voxels_per_chunk=7)
    tested = np.flatnonzero(np.isfinite(dex.reachable_fraction.ravel()))
    R = super_fibonacci(6)
    rng = np.random.default_rng(0)
    solved = 0
    for voxel in rng.choice(tested, 12, replace=False):
        counts = []
        for Rk in R:
            T = np.eye(4)
            T[:3, :3], T[:3, 3] = Rk, dex.grid.centres(np.array([voxel]))[0]
            try:
                counts.append(len(robot.ik(T, all_solutions=True)))
            except (UnreachableError, JointLimitError):
                counts.append(0)
        assert dex.reachable_fraction.ravel()[voxel] == np.mean(np.array(counts) > 0)
        assert dex.max_solutions.ravel()[voxel] == max(counts)
        assert dex.mean_solutions.ravel()[voxel] == pytest.approx(np.mean(counts))
        solved += sum(counts)
    assert solved > 20                          # the voxels checked are not all out of reach


def test_dexterity_without_closed_form_uses_numeric_ik():
    panda = armkit.load("panda")
    grid = workspace.Grid((0.25, -0.05, 0.35), 0.1, (2, 1, 1))
    dex = workspace.dexterity(panda, grid=grid, orientations=3)
    assert np.isin(dex.max_solutions, [0, 1]).all()
    assert dex.tested == 2


def test_manipulability_of_a_voxel_is_the_mean_over_its_samples():
    robot = armkit.load("puma560")
    stats = workspace.manipulability(robot, resolution=0.15, samples=3000, chunk_size=1000, seed=4)
    q = np.concatenate([configurations(robot, SamplePlan(3000, 1000, 4), c) for c in range(3)])
    flat = stats.grid.flat_index(robot.fk(q)[:, :3, 3])
    voxel = np.bincount(flat).argmax()
    inside = flat == voxel
    w = robot.manipulability(q[inside])
    s = robot.singular_values(q[inside])
    assert stats.arrays["count"].ravel()[voxel] == inside.sum()
    np.testing.assert_allclose(stats.mean_manipulability.ravel()[voxel], w.mean(), rtol=1e-12)
    np.testing.assert_allclose(stats.arrays["manipulability_max"].ravel()[voxel], w.max(), rtol=1e-12)
    np.testing.assert_allclose(stats.arrays["inverse_condition_min"].ravel()[voxel],
                               (s[:, -1] / s[:, 0]).min(), rtol=1e-12)
    assert stats.singular.ravel()[voxel] == (s[:, -1].min() < stats.threshold)


def test_sweep_of_a_planar_arm_follows_the_annulus_area_per_value():
    result = workspace.sweep(planar_2r(0.3, 0.2), "a2=0.1:0.25:3", resolution=0.01, samples=300_000,
                             chunk_size=2**16)
    assert len({m.grid for m in result.maps}) == 1
    for row, value in zip(result.table(), result.values, strict=True):
        exact = 4 * np.pi * 0.3 * value                # pi ((l1 + l2)^2 - (l1 - l2)^2)
        assert abs(row["reachable_volume"] - exact) <= row["reachable_volume_error"]


def test_robot_with_changes_one_dh_entry_and_names_bad_ones():
    robot = armkit.load("probot-anno")
    longer = robot_with(robot, "a", 3, 0.3)
    assert longer.dh.rows[2].a == 0.3 and longer.dh.rows[1] == robot.dh.rows[1]
    np.testing.assert_array_equal(longer.limits, robot.limits)
    with pytest.raises(InputError, match="sweep row 9: PROBOT Anno has joint rows 1 to 6"):
        robot_with(robot, "a", 9, 0.3)


def test_ik_dataset_rows_hold_q_its_pose_and_every_solution(tmp_path):
    robot = armkit.load("ur5")
    data = workspace.ik_dataset(robot, 300, tmp_path / "ik.zarr", chunk_size=128, seed=2)
    q, pose = data["q"][...], data["pose"][...]
    solutions, counts = data["solutions"][...], data["counts"][...]
    np.testing.assert_allclose(robot.fk(q), pose, atol=1e-12)
    assert robot.within_limits(q).all() and (counts >= 1).all()
    np.testing.assert_allclose(solutions[:, 0], q, atol=1e-8)          # nearest to q first: q itself
    for i in range(0, 300, 37):
        found = solutions[i, :counts[i]]
        np.testing.assert_allclose(robot.fk(found), np.broadcast_to(pose[i], (counts[i], 4, 4)), atol=1e-9)
        assert np.isnan(solutions[i, counts[i]:]).all()
    reopened = workspace.open(tmp_path / "ik.zarr")
    assert reopened.complete and reopened.summary()["samples"] == 300


def test_ik_dataset_resumes_only_missing_chunks(tmp_path):
    robot = armkit.load("ur5")
    first = workspace.ik_dataset(robot, 200, tmp_path / "ik.zarr", chunk_size=64)
    q = first["q"][...]
    first.group["chunk_done"][1] = False
    first.group["q"][64:128] = 0.0
    again = workspace.ik_dataset(robot, 200, tmp_path / "ik.zarr", chunk_size=64, resume=True)
    np.testing.assert_array_equal(again["q"][...], q)


def test_ik_dataset_needs_a_closed_form(tmp_path):
    with pytest.raises(NoClosedFormError, match="needs a closed form"):
        workspace.ik_dataset(armkit.load("panda"), 10, tmp_path / "ik.zarr")
