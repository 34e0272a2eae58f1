"""Each map's work follows what was asked (issue 20, item 4): the manipulability samples and the
dexterity IK solves scale with ``samples``, blocks of voxels share a position when the solves
would not cover every voxel, maps that do not apply to the arm are skipped and say why, and
the summary gives one count of reached voxels."""

from __future__ import annotations

import json

import numpy as np
import pytest

import armkit
from armkit import workspace
from armkit.cli.main import main
from armkit.workspace.dexterity import MIN_POSITIONS, blocks, candidate_voxels
from armkit.workspace.maps import DEXTERITY_SHARE, MANIPULABILITY_SHARE, NUMERIC_COST, default_sizes
from armkit.workspace.orientations import super_fibonacci
from armkit.workspace.sampling import ik_solution_counts

RRP = """name = "RRP"
convention = "standard"
length_unit = "m"
angle_unit = "deg"
[[joints]]
d = 0.3
a = 0
alpha = 90
theta = 0
limits = [-170, 170]
[[joints]]
d = 0
a = 0
alpha = 90
theta = 90
limits = [-90, 90]
[[joints]]
type = "prismatic"
d = 0
a = 0
alpha = 0
theta = 0
limits = [0.2, 0.6]
"""


def test_the_default_sizes_follow_samples_and_a_numeric_arm_gets_fewer_solves():
    probot, panda = armkit.load("probot-anno"), armkit.load("panda")
    assert default_sizes(probot, 10**6) == (10**6 // MANIPULABILITY_SHARE, 10**6 // DEXTERITY_SHARE)
    assert default_sizes(probot, 10**5) == (10**5 // MANIPULABILITY_SHARE, 10**5 // DEXTERITY_SHARE)
    assert default_sizes(panda, 10**6)[1] == 10**6 // DEXTERITY_SHARE // NUMERIC_COST


def test_ik_solves_bound_the_dexterity_map_and_each_block_takes_its_position_values():
    robot = armkit.load("probot-anno")
    reach = workspace.reachability(robot, resolution=0.05, samples=20_000)
    full = workspace.dexterity(robot, reach=reach, orientations=8)
    small = workspace.dexterity(robot, reach=reach, orientations=8, ik_solves=800)
    assert full.block == 1 and small.block > 1
    assert small.ik_solves <= 800 < full.ik_solves
    positions = blocks(reach.grid, candidate_voxels(reach.grid, robot, reach), 8, 800, reach.occupied)
    assert positions.targets.size == small.candidates
    # every voxel of a block holds the values the IK at its position gives, found here directly
    R = super_fibonacci(8)
    for k in (0, positions.targets.size // 2, positions.targets.size - 1):
        target = positions.targets[k]
        T = np.zeros((8, 4, 4))
        T[:, :3, :3], T[:, :3, 3], T[:, 3, 3] = R, reach.grid.centres(np.array([target]))[0], 1.0
        counts = ik_solution_counts(robot, T)
        members = positions.members[positions.starts[k]:positions.starts[k + 1]]
        assert target in members
        np.testing.assert_array_equal(small.reachable_fraction.ravel()[members], np.mean(counts > 0))
        np.testing.assert_array_equal(small.max_solutions.ravel()[members], counts.max())
        np.testing.assert_array_equal(full.reachable_fraction.ravel()[target], np.mean(counts > 0))
    # the voxels tested are the same; their mean index is an estimate of the full map's
    assert np.array_equal(np.isfinite(small.reachable_fraction), np.isfinite(full.reachable_fraction))
    assert small.mean_index(reach.occupied) == pytest.approx(full.mean_index(reach.occupied), abs=0.1)


def test_a_small_and_a_larger_run_agree_within_their_errors():
    robot = armkit.load("probot-anno")
    small, large = (workspace.compute(robot, resolution=0.05, samples=n, orientations=20)
                    for n in (20_000, 80_000))
    for maps in (small, large):   # the IK solves follow the samples
        assert maps.dexterity.ik_solves <= maps.reachability.plan.samples // DEXTERITY_SHARE
        assert maps.manipulability.samples == maps.reachability.plan.samples // MANIPULABILITY_SHARE
    a, b = small.reachability.volume(), large.reachability.volume()
    assert abs(a.value - b.value) <= a.error + b.error
    assert abs(small.summary()["dexterity"]["mean_reachability_index"]
               - large.summary()["dexterity"]["mean_reachability_index"]) < 0.1


def test_an_arm_of_three_joints_skips_the_dexterity_map_and_says_why(tmp_path, capsys):
    path = tmp_path / "rrp.toml"
    path.write_text(RRP)
    maps = workspace.compute(armkit.load(path), resolution=0.05, samples=20_000)
    assert maps.dexterity is None and "3-joint arm" in maps.skipped["dexterity"]
    assert maps.summary()["maps_skipped"]["dexterity"] == maps.skipped["dexterity"]
    assert main(["workspace", str(path), "--samples", "2e4", "--resolution", "0.05", "--quiet"]) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert ("dexterity map skipped: a 3-joint arm reaches each point in a set of orientations of measure "
            "zero") in out


def test_too_few_solves_for_a_map_skip_it_naming_the_options(capsys):
    maps = workspace.compute(armkit.load("probot-anno"), resolution=0.1, samples=2000, orientations=100)
    assert maps.dexterity is None
    assert maps.skipped["dexterity"] == (f"500 IK solves (--ik-solves) at 100 orientations allow 5 "
                                         f"positions, fewer than {MIN_POSITIONS}: give more --samples or "
                                         f"--ik-solves, or fewer --orientations")


def test_the_cli_prints_one_count_of_reached_voxels_the_sizes_and_a_hint_for_a_large_error(capsys):
    args = ["workspace", "probot-anno", "--samples", "2e4", "--resolution", "0.05", "--orientations", "8",
            "--quiet"]
    assert main([*args, "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    reached = summary["volume"]["occupied_voxels"]
    assert summary["dexterity"]["mean_index_voxels"] == reached
    assert summary["manipulability"]["samples"] == 4000
    assert main(args) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert f"({reached:,} reached)" in out and f"over the {reached:,} reached voxels" in out
    assert "from 4,000 manipulability samples" in out
    volume = summary["volume"]
    assert (volume["error"] > volume["value"]) == ("the volume's error is larger than the volume: give more "
                                                   "--samples" in out)


def test_the_page_says_the_same_counts_and_the_hint(tmp_path, capsys):
    assert main(["workspace", "probot-anno", "--samples", "2e4", "--resolution", "0.05", "--orientations",
                 "8", "--quiet", "--report", "--report-dir", str(tmp_path / "page"), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    page = " ".join((tmp_path / "page" / "index.html").read_text().split())
    reached = summary["volume"]["occupied_voxels"]
    assert f"over the {reached:,} reached voxels" in page and f"{reached:,} (" in page
    volume = summary["volume"]
    assert (volume["error"] > volume["value"]) == ("the volume's error is larger than the volume" in page)
