"""--scene on the command line: armkit ik marks the colliding solutions."""

from __future__ import annotations

import json

import numpy as np
import pytest

import armkit
from armkit.cli.main import main

pytest.importorskip("mujoco")

POSE = ["--pose", "0.3", "0.2", "0.3", "180", "0", "0", "--deg"]
CELL = 'length_unit = "m"\nangle_unit = "deg"\nfloor = 0.0\n[self_collision]\nsamples = 500\n'


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_ik_all_with_a_scene_marks_exactly_the_solutions_scene_collides_flags(tmp_path, capsys):
    cell = tmp_path / "cell.toml"
    cell.write_text(CELL)
    code, out, _ = run(capsys, "ik", "ur5", *POSE, "--all", "--json", "--scene", str(cell))
    assert code == 0
    data = json.loads(out)
    scene = armkit.load_scene(cell, armkit.load("ur5"))
    q = np.array(data["solutions"])
    assert data["collides"] == scene.collides(q).tolist()
    assert 0 < sum(data["collides"]) < len(q)
    assert [[tuple(pair) for pair in c] for c in data["contacts"]] == [scene.contacts(qi) for qi in q]
    code, out, _ = run(capsys, "ik", "ur5", *POSE, "--all", "--scene", str(cell))
    assert code == 0 and "link2-floor" in out and "free" in out


def test_ik_with_a_scene_gives_the_nearest_free_solution(tmp_path, capsys):
    cell = tmp_path / "cell.toml"
    cell.write_text(CELL)
    near = ["0", "143.2", "0", "0", "0", "0"]  # deg: its nearest solution has the upper arm in the floor
    code, out, _ = run(capsys, "ik", "ur5", *POSE, "--json", "--near", *near)
    plain = np.array(json.loads(out)["solutions"])
    code, out, _ = run(capsys, "ik", "ur5", *POSE, "--json", "--scene", str(cell), "--near", *near)
    assert code == 0
    data = json.loads(out)
    scene = armkit.load_scene(cell, armkit.load("ur5"))
    assert scene.collides(plain).tolist() == [True] and data["collides"] == [False]
    robot = armkit.load("ur5")
    listed = robot.ik(robot.fk(plain[0]), all_solutions=True, near=np.radians([0, 143.2, 0, 0, 0, 0]))
    np.testing.assert_allclose(data["solutions"][0], listed[~scene.collides(listed)][0], atol=1e-12)


def test_a_bad_scene_file_is_one_error_line(tmp_path, capsys):
    cell = tmp_path / "cell.toml"
    cell.write_text('length_unit = "m"\nangle_unit = "deg"\n[[box]]\nsize = [1, 1]\n')
    code, _, err = run(capsys, "ik", "ur5", *POSE, "--scene", str(cell))
    assert code == 1 and "size" in err and "Traceback" not in err
