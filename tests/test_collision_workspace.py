"""armkit workspace with a scene: the samples in collision are left out of the reachability map."""

from __future__ import annotations

import json
import pickle

import numpy as np
import pytest

import armkit
from armkit.cli.main import main
from armkit.workspace.reachability import reachability

pytest.importorskip("mujoco")

ROBOT = armkit.load("probot-anno")


@pytest.fixture(scope="module")
def scene() -> armkit.Scene:
    return armkit.Scene(ROBOT, floor=0.0)


def test_a_scene_pickles_to_the_same_checks(scene):
    again = pickle.loads(pickle.dumps(scene))
    q = ROBOT.random_q(2000, rng=1)
    np.testing.assert_array_equal(again.collides(q), scene.collides(q))
    assert again.disabled_pairs == scene.disabled_pairs


@pytest.mark.parametrize("method", ["sobol", "uniform"])
def test_the_map_with_a_scene_counts_exactly_the_free_samples(scene, method):
    kwargs = {"resolution": 0.05, "samples": 20_000, "chunk_size": 4096, "method": method, "engine": 1}
    plain = reachability(ROBOT, **kwargs)
    free = reachability(ROBOT, scene=scene, **kwargs)
    assert free.colliding > 0 and plain.colliding == 0
    assert int(free.hits.sum()) + free.colliding + free.outside == free.samples
    if method == "sobol":  # the same configurations either way: the free ones are a subset
        assert (free.hits <= plain.hits).all()
        assert int((plain.hits - free.hits).sum()) == free.colliding
    z = free.grid.lower[2] + (np.arange(free.grid.shape[2]) + 1) * free.grid.resolution  # voxel tops
    assert free.hits[..., z < -0.02].sum() == 0 < plain.hits[..., z < -0.02].sum()  # none under the floor


def test_the_workspace_command_reports_the_samples_left_out(tmp_path, capsys):
    cell = tmp_path / "cell.toml"
    cell.write_text('length_unit = "m"\nangle_unit = "deg"\nfloor = 0\n')
    code = main(["workspace", "probot-anno", "--samples", "2e4", "--resolution", "0.05", "--orientations",
                 "0", "--manipulability-samples", "0", "--json", "--scene", str(cell), "--threads", "1"])
    out, _ = capsys.readouterr()
    assert code == 0
    assert json.loads(out)["colliding_samples_left_out"] > 0


def test_a_urdf_robots_scene_pickles_with_its_collision_geometry(tmp_path):
    urdf = tmp_path / "arm.urdf"
    urdf.write_text("""<robot name="arm"><link name="base"/>
  <link name="upper"><collision><origin xyz="0.25 0 0"/><geometry><box size="0.5 0.1 0.1"/></geometry>
    </collision></link>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/><axis xyz="0 1 0"/>
    <limit lower="-3" upper="3" velocity="1" effort="1"/></joint>
  <link name="tip"/><joint name="flange" type="fixed"><parent link="upper"/><child link="tip"/>
    <origin xyz="0.5 0 0"/></joint></robot>""")
    scene = armkit.Scene(armkit.load(urdf), floor=-0.2)
    again = pickle.loads(pickle.dumps(scene))
    assert again.parts == scene.parts == ("base", "upper", "floor")
    q = np.linspace(-3, 3, 61)[:, None]
    np.testing.assert_array_equal(again.clearance(q), scene.clearance(q))
    assert again.collides(q).any() and not again.collides(q).all()
