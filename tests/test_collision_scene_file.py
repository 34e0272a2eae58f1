"""Scene files (armkit.load_scene): what a file builds, and one InputError naming the key for bad ones."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import armkit
from armkit.collision import scene_from_dict
from armkit.errors import InputError

pytest.importorskip("mujoco")

UR5 = armkit.load("ur5")
CELL = """
length_unit = "mm"
angle_unit = "deg"
floor = -10

[[box]]
name = "table"
size = [1200, 800, 50]
xyz = [600, 0, -35]
[[sphere]]
radius = 100
xyz = [500, 200, 400]
[[cylinder]]
radius = 50
length = 1000
xyz = [400, -400, 500]
rpy = [90, 0, 0]

[self_collision]
samples = 0
disabled = [["link1", "link3"]]
"""


def test_a_scene_file_builds_its_obstacles_in_si_units(tmp_path):
    path = tmp_path / "cell.toml"
    path.write_text(CELL)
    scene = armkit.load_scene(path, UR5)
    assert scene.floor == pytest.approx(-0.01)
    assert scene.parts[7:] == ("floor", "table", "sphere1", "cylinder1")
    table, sphere, cylinder = scene.obstacles
    assert table.size == pytest.approx((1.2, 0.8, 0.05))
    assert table.pose[:3, 3] == pytest.approx([0.6, 0, -0.035])
    assert sphere.radius == pytest.approx(0.1) and sphere.pose[:3, 3] == pytest.approx([0.5, 0.2, 0.4])
    assert cylinder.pose[:3, 2] == pytest.approx([0, -1, 0])  # rolled 90 deg: its axis along -y
    assert scene.disabled_pairs[("link1", "link3")] == "user"
    assert "never" not in scene.disabled_pairs.values()  # samples = 0: none sampled
    assert armkit.Scene.from_file(path, UR5).disabled_pairs == scene.disabled_pairs
    assert armkit.Scene(UR5, scene.obstacles, floor=-0.01, disabled_pairs=[("link1", "link3")],
                        samples=0).collides(UR5.random_q(200, rng=1)).tolist() == \
        scene.collides(UR5.random_q(200, rng=1)).tolist()


def test_floor_false_means_no_floor_and_a_missing_floor_is_at_zero():
    base = {"length_unit": "m", "angle_unit": "rad", "self_collision": {"samples": 0}}
    assert scene_from_dict({**base, "floor": False}, UR5).floor is None
    assert scene_from_dict(base, UR5).floor == 0.0


def test_a_mesh_path_is_relative_to_the_scene_file(tmp_path):
    (tmp_path / "parts").mkdir()
    (tmp_path / "parts" / "block.obj").write_text(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
    (tmp_path / "cell.toml").write_text('length_unit = "m"\nangle_unit = "rad"\nfloor = false\n'
                                        '[[mesh]]\npath = "parts/block.obj"\n'
                                        'scale = 0.1\nxyz = [0.4, 0, 0.4]\n')
    scene = armkit.load_scene(tmp_path / "cell.toml", UR5)
    assert scene.obstacles[0].path == tmp_path / "parts" / "block.obj"
    assert scene.obstacles[0].scale == (0.1, 0.1, 0.1)


@pytest.mark.parametrize("text, key", [
    ('angle_unit = "deg"', "length_unit"),
    ('length_unit = "cm"\nangle_unit = "deg"', "length_unit"),
    ('length_unit = "m"\nangle_unit = "deg"\nfloor = "low"', "floor"),
    ('length_unit = "m"\nangle_unit = "deg"\nwalls = 3', "walls"),
    ('length_unit = "m"\nangle_unit = "deg"\n[[box]]\nsize = [1, 1]', "size"),
    ('length_unit = "m"\nangle_unit = "deg"\n[[box]]\nsize = [1, 1, -1]', "size"),
    ('length_unit = "m"\nangle_unit = "deg"\n[[box]]\nxyz = [0, 0, 0]', "size"),
    ('length_unit = "m"\nangle_unit = "deg"\n[[sphere]]\nradius = 0', "radius"),
    ('length_unit = "m"\nangle_unit = "deg"\n[[sphere]]\nradius = 1\ncolour = "red"', "colour"),
    ('length_unit = "m"\nangle_unit = "deg"\n[[cylinder]]\nradius = 1\nlength = 1\nrpy = [0, 0]', "rpy"),
    ('length_unit = "m"\nangle_unit = "deg"\n[[mesh]]\npath = "none.stl"', "file not found"),
    ('length_unit = "m"\nangle_unit = "deg"\n[[mesh]]\npath = "x.stl"\nscale = -1', "scale"),
    ('length_unit = "m"\nangle_unit = "deg"\nbox = 3', "box"),
    ('length_unit = "m"\nangle_unit = "deg"\n[self_collision]\nsamples = -1', "samples"),
    ('length_unit = "m"\nangle_unit = "deg"\n[self_collision]\ndisabled = [["link1"]]', "disabled"),
    ('length_unit = "m"\nangle_unit = "deg"\n[self_collision]\nenabled = [["link1", "hand"]]', "hand"),
    ('length_unit = "m"\nangle_unit = "deg"\nlink_radius = [0.1]', "link_radius"),
    ('length_unit = "m"\nangle_unit = "deg"\ngeometry = "spheres"', "geometry"),
    ("length_unit = ", "not valid TOML"),
])
def test_a_bad_scene_file_raises_one_input_error_naming_the_key(tmp_path, text, key):
    path = tmp_path / "bad.toml"
    path.write_text(text + "\n")
    with pytest.raises(InputError, match=key) as info:
        armkit.load_scene(path, UR5)
    assert str(path) in str(info.value)


def test_a_missing_scene_file_is_an_input_error(tmp_path):
    with pytest.raises(InputError, match="cannot read the scene file"):
        armkit.load_scene(tmp_path / "none.toml", UR5)


_VALUES = st.one_of(st.none(), st.booleans(), st.integers(-10, 10), st.floats(allow_nan=True),
                    st.text(max_size=5), st.lists(st.floats(-2, 2), max_size=4),
                    st.lists(st.lists(st.text(max_size=6), max_size=3), max_size=2))
_KEYS = st.sampled_from(["floor", "link_radius", "geometry", "package_paths", "box", "sphere", "cylinder",
                         "mesh", "self_collision", "size", "radius", "length", "xyz", "rpy", "name", "typo"])


@st.composite
def _scene_dicts(draw):
    data = {"length_unit": "m", "angle_unit": "rad", "self_collision": {"samples": 0}}
    for _ in range(draw(st.integers(1, 3))):
        key = draw(_KEYS)
        if key in ("box", "sphere", "cylinder", "mesh") and draw(st.booleans()):
            table = {draw(_KEYS): draw(_VALUES) for _ in range(draw(st.integers(0, 3)))}
            data[key] = [table]
        elif key == "self_collision":
            data[key] = {draw(st.sampled_from(["samples", "disabled", "enabled", "typo"])): draw(_VALUES)}
        else:
            data[key] = draw(_VALUES)
    return data


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(_scene_dicts())
def test_any_scene_description_builds_a_scene_or_raises_an_input_error_naming_a_key(data):
    try:
        scene = scene_from_dict(data, UR5, "cell.toml")
    except InputError as exc:
        message = str(exc)
        assert message.startswith("cell.toml")
        assert any(key in message for key in [*data, *_flat_keys(data)]), message
    else:
        assert isinstance(scene.collides(np.zeros(6)), bool)


def _flat_keys(data: dict) -> list[str]:
    keys = []
    for value in data.values():
        for table in value if isinstance(value, list) else [value]:
            if isinstance(table, dict):
                keys += list(table)
    return keys


def test_the_self_collision_table_a_scene_writes_gives_the_same_pairs_without_sampling(tmp_path):
    scene = armkit.Scene(UR5, floor=0.0)
    path = tmp_path / "cell.toml"
    path.write_text('length_unit = "m"\nangle_unit = "deg"\nfloor = 0\n' + scene.self_collision_toml())
    again = armkit.load_scene(path, UR5)
    assert set(again.disabled_pairs) == set(scene.disabled_pairs)
    q = UR5.random_q(500, rng=3)
    np.testing.assert_array_equal(again.collides(q), scene.collides(q))


def test_an_empty_scene_file_is_named_empty(tmp_path):
    path = tmp_path / "cell.toml"
    path.write_text("\n")
    with pytest.raises(InputError, match="cell.toml: the file is empty; expected a scene file"):
        armkit.load_scene(path, UR5)
