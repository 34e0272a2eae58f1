"""Reachability maps against analytic workspaces: a planar 2R arm's annulus, a wrist centre's shell."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import armkit
from armkit import _core
from armkit.errors import InputError
from armkit.workspace import grid_for, reachability
from armkit.workspace.grid import Grid, reach_bound
from armkit.workspace.sampling import SamplePlan, chunk_seed, configurations, joint_box, voxel_hits


def planar_2r(l1: float, l2: float) -> armkit.Robot:
    return armkit.Robot.from_dh([armkit.DHRow(0, l1, 0, 0), armkit.DHRow(0, l2, 0, 0)], "standard",
                                limits=[(-np.pi, np.pi)] * 2)


def wrist_centre_arm() -> armkit.Robot:
    """PROBOT Anno's joints without its tool rows and with full turns: its tool point is the wrist centre."""
    probot = armkit.load("probot-anno")
    return armkit.Robot.from_dh(probot.dh.rows, probot.dh.convention, limits=[(-np.pi, np.pi)] * 6)


@pytest.mark.parametrize("method", ["uniform", "sobol"])
def test_planar_2r_area_is_the_annulus_within_the_stated_error(method):
    l1, l2 = 0.3, 0.2
    area = reachability(planar_2r(l1, l2), resolution=0.01, samples=300_000, method=method,
                        chunk_size=2**15).volume()
    exact = np.pi * ((l1 + l2) ** 2 - (l1 - l2) ** 2)
    assert area.unit == "m^2"
    assert abs(area.value - exact) <= area.error
    assert area.error < 0.05 * exact          # the statement is not empty


def test_wrist_centre_volume_is_the_spherical_shell_within_the_stated_error():
    l2, l3 = 0.225, 0.2289                    # PROBOT Anno's upper arm a3 and forearm d4
    volume = reachability(wrist_centre_arm(), resolution=0.03, samples=400_000, chunk_size=2**16).volume()
    exact = 4 / 3 * np.pi * ((l2 + l3) ** 3 - (l2 - l3) ** 3)
    assert volume.unit == "m^3"
    assert abs(volume.value - exact) <= volume.error
    assert volume.error < 0.2 * exact


def test_more_samples_shrink_the_sampling_error_of_an_undersampled_map():
    arm = planar_2r(0.3, 0.2)
    few = reachability(arm, resolution=0.005, samples=40_000).volume()
    many = reachability(arm, resolution=0.005, samples=640_000).volume()
    assert many.sampling_error < few.sampling_error / 10
    assert many.occupied > few.occupied


def test_no_sample_falls_outside_the_grid_and_counts_add_up():
    robot = armkit.load("ur5")
    result = reachability(robot, resolution=0.05, samples=30_000, chunk_size=7_000)
    assert result.outside == 0 and result.complete
    assert result.hits.sum() == 30_000 == result.samples


def test_reach_bound_holds_every_sampled_tool_position():
    for name in ("probot-anno", "stanford", "puma560"):
        robot = armkit.load(name)
        centre, reach = reach_bound(robot)
        p = robot.fk(robot.random_q(5_000, rng=1))[:, :3, 3]
        assert np.linalg.norm(p - centre, axis=1).max() <= reach + 1e-12


def test_counts_do_not_depend_on_the_number_of_threads():
    robot = armkit.load("probot-anno")
    one = reachability(robot, resolution=0.04, samples=40_000, chunk_size=5_000, engine=1)
    three = reachability(robot, resolution=0.04, samples=40_000, chunk_size=5_000, engine=3)
    np.testing.assert_array_equal(one.hits, three.hits)


def test_a_chunk_is_the_same_whoever_draws_it_and_chunks_differ():
    robot = armkit.load("ur5")
    plan = SamplePlan(1000, chunk_size=100, seed=3, method="sobol")
    np.testing.assert_array_equal(configurations(robot, plan, 4), configurations(robot, plan, 4))
    assert not np.allclose(configurations(robot, plan, 4), configurations(robot, plan, 5))
    q = configurations(robot, plan, 9)
    assert robot.within_limits(q).all()


def test_planar_arm_gets_one_voxel_layer():
    grid = grid_for(planar_2r(0.3, 0.2), 0.01)
    assert grid.flat == (False, False, True) and grid.shape[2] == 1


@pytest.mark.parametrize(("kwargs", "match"), [
    ({"resolution": -1.0}, "resolution: expected a positive length"),
    ({"resolution": 1e-6}, "choose a coarser one"),
    ({"samples": 0}, "samples: expected a whole number from 1 to 9007199254740992, got 0"),
    ({"method": "halton"}, "sampling method 'halton'"),
])
def test_bad_settings_are_named(kwargs, match):
    with pytest.raises(InputError, match=match):
        reachability(planar_2r(0.3, 0.2), **{"resolution": 0.1, "samples": 10, **kwargs})


def test_outer_boundary_of_the_annulus_lies_on_its_outer_circle():
    result = reachability(planar_2r(0.3, 0.2), resolution=0.01, samples=200_000)
    outer, every = result.outer_boundary, result.boundary
    assert (outer <= every).all() and 0 < outer.sum() < every.sum()
    radius = np.linalg.norm(result.grid.centres(np.flatnonzero(outer))[:, :2], axis=1)
    assert radius.min() > 0.5 - 2 * 0.01 * np.sqrt(2)     # none on the inner circle (r = 0.1)


def test_import_armkit_and_armkit_workspace_load_no_zarr_dask_or_matplotlib():
    import subprocess
    import sys

    code = ("import sys, armkit, armkit.workspace; heavy = [m for m in ('zarr', 'dask', 'distributed', "
            "'matplotlib') if m in sys.modules]; print(heavy)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"


def test_doubling_gain_counts_the_voxels_only_the_second_half_of_the_samples_reached():
    result = reachability(planar_2r(0.3, 0.2), resolution=0.005, samples=40_000, chunk_size=10_000)
    volume = result.volume()
    first_half_only = result.hits_even > 0
    assert (first_half_only <= result.occupied).all()
    expected = (result.occupied & ~first_half_only).sum() * result.grid.cell_measure
    assert volume.doubling_gain == expected > 0
    assert volume.sampling_error >= volume.doubling_gain
    single = reachability(planar_2r(0.3, 0.2), resolution=0.005, samples=40_000, chunk_size=40_000)
    assert single.volume().doubling_gain == 0.0      # one chunk: no second half to compare


@given(st.tuples(*[st.floats(-0.6, 0.6)] * 3), st.floats(0.005, 0.2))
def test_a_point_lies_in_the_voxel_whose_centre_the_grid_gives_back(point, resolution):
    grid = grid_for(wrist_centre_arm(), resolution)
    p = np.array([point])
    flat = grid.flat_index(p)
    if flat[0] < 0:   # outside: then some coordinate is beyond the grid's faces
        upper = np.add(grid.lower, np.multiply(grid.shape, resolution))
        assert ((p < grid.lower) | (p >= upper)).any()
    else:
        assert np.abs(grid.centres(flat) - p).max() <= resolution / 2 * (1 + 1e-9)


@pytest.mark.parametrize("method", ["uniform", "sobol"])
def test_fused_counts_are_those_of_fk_positions_put_in_the_grid(method):
    robot = armkit.load("probot-anno")
    grid = grid_for(robot, 0.03)
    plan = SamplePlan(25_003, chunk_size=12_001, seed=11, method=method)
    for chunk in range(plan.n_chunks):
        hits, outside = voxel_hits(robot, grid, plan, chunk)
        flat = grid.flat_index(robot.fk(configurations(robot, plan, chunk))[:, :3, 3])
        np.testing.assert_array_equal(hits, np.bincount(flat[flat >= 0], minlength=grid.size))
        assert outside == int((flat < 0).sum()) == 0


def test_uniform_samples_fill_the_joint_box_evenly_and_do_not_depend_on_threads():
    robot = armkit.load("ur5")
    plan = SamplePlan(50_000, seed=5)
    q = configurations(robot, plan, 0)
    box = robot.limits
    unit = (q - box[:, 0]) / (box[:, 1] - box[:, 0])
    assert unit.min() >= 0 and unit.max() < 1
    np.testing.assert_allclose(unit.mean(axis=0), 0.5, atol=0.01)        # sd of a mean: 0.0013
    np.testing.assert_allclose(np.corrcoef(unit.T), np.eye(6), atol=0.02)  # joints independent
    low, high = np.ascontiguousarray(box[:, 0]), np.ascontiguousarray(box[:, 1])
    grid = grid_for(robot, 0.1)
    where = (np.asarray(grid.lower, dtype=float), grid.resolution, *grid.shape)
    counts = []
    for threads in (1, 2, 3):
        again = np.empty_like(q)
        _core.sample_uniform(robot.chain._core, low, high, chunk_seed(plan, 0), 0, again, threads)
        np.testing.assert_array_equal(again, q)
        hits = np.zeros(grid.size, dtype=np.int64)
        seed = chunk_seed(plan, 0)
        _core.reach_uniform(robot.chain._core, low, high, seed, 0, len(q), *where, hits, threads)
        counts.append(hits)
    np.testing.assert_array_equal(counts[0], counts[1])
    np.testing.assert_array_equal(counts[0], counts[2])
    assert counts[0].sum() == len(q)


def test_positions_on_voxel_faces_are_counted_where_plain_fk_and_division_put_them():
    """The kernel multiplies by 1 / resolution and computes positions in another order than FK;
    on a face the two can disagree (0.3 / 0.1 floors to 2, 0.3 * 10 to 3), and such samples must
    take the plain path: a prismatic joint along z puts the tool exactly on faces."""
    robot = armkit.Robot.from_dh([armkit.DHRow(0, 0, 0, 0, "prismatic")], "standard", limits=[(0.0, 4.0)])
    grid = Grid((-0.05, -0.05, 0.0), 0.1, (1, 1, 41), (True, True, False))
    faces = np.arange(41) * 0.1
    z = np.concatenate([faces, np.nextafter(faces, -1), np.nextafter(faces, 5), [0.3, 0.7, 1.1, 2.3]])
    q = np.ascontiguousarray(np.tile(z, 60)[:, None])      # 10,440 samples: enough for 2 threads
    assert (np.floor(z * (1 / 0.1)) != np.floor(z / 0.1)).any()   # the test has such faces
    plain = grid.flat_index(robot.fk(q)[:, :3, 3])
    for threads in (1, 2):
        hits = np.zeros(grid.size, dtype=np.int64)
        outside = _core.reach_given(robot.chain._core, q, np.asarray(grid.lower), grid.resolution,
                                    *grid.shape, hits, threads)
        np.testing.assert_array_equal(hits, np.bincount(plain[plain >= 0], minlength=grid.size))
        assert outside == int((plain < 0).sum()) > 0         # the last face is the grid's edge


@pytest.mark.parametrize("name", ["stanford", "ur5"])
def test_counts_on_two_threads_are_those_of_plain_fk_of_the_same_samples(name):
    robot = armkit.load(name)   # the Stanford arm has a prismatic joint
    grid = grid_for(robot, 0.03)
    box = joint_box(robot)
    low, high = np.ascontiguousarray(box[:, 0]), np.ascontiguousarray(box[:, 1])
    q = np.empty((20_011, robot.n))
    _core.sample_uniform(robot.chain._core, low, high, 9, 0, q, 1)
    flat = grid.flat_index(robot.fk(q)[:, :3, 3])
    hits = np.zeros(grid.size, dtype=np.int64)
    outside = _core.reach_uniform(robot.chain._core, low, high, 9, 0, len(q), np.asarray(grid.lower),
                                  grid.resolution, *grid.shape, hits, 2)
    np.testing.assert_array_equal(hits, np.bincount(flat[flat >= 0], minlength=grid.size))
    assert outside == int((flat < 0).sum()) == 0
