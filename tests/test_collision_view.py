"""The viewer with a collision scene: obstacles drawn, the links in contact coloured."""

from __future__ import annotations

import numpy as np
import pytest

import armkit
from armkit.spatial.transforms import transform_from

pytest.importorskip("mujoco")
pytest.importorskip("viser")

from armkit.view import Viewer  # noqa: E402  (after the importorskip)
from armkit.view.obstacles import COLLIDING  # noqa: E402
from armkit.view.scene import Colours  # noqa: E402

UR5 = armkit.load("ur5")


@pytest.fixture(scope="module")
def viewer():
    scene = armkit.Scene(UR5, [armkit.Box([0.2, 0.2, 0.2], transform_from(np.eye(3), [0.5, 0.0, 0.3])),
                               armkit.Sphere(0.1, [-0.4, 0.4, 0.5]),
                               armkit.Cylinder(0.05, 0.5, transform_from(np.eye(3), [0.3, -0.5, 0.3]))],
                         floor=0.0)
    viewer = Viewer(UR5, port=0, scene=scene, q=[0, -1.2, 1.0, 0, 1.5, 0])
    yield viewer
    viewer.close()


def test_the_floor_and_each_obstacle_are_drawn(viewer):
    names = [name for name in viewer._server.scene._handle_from_node_name if name.startswith("/obstacles/")]
    assert sorted(name.split("_", 1)[1] for name in names) == ["box1", "cylinder1", "floor", "sphere1"]


def test_links_in_contact_are_coloured_and_the_others_not(viewer):
    colours = np.asarray(viewer._arm.handle.batched_colors)
    assert not (colours == COLLIDING).all(axis=1).any()  # a free configuration: nothing coloured
    viewer.q = UR5.home  # the wrist (links 5 and 6) in the floor
    colours = np.asarray(viewer._arm.handle.batched_colors)
    joints = colours[-UR5.n:]
    assert (joints[4:] == COLLIDING).all() and (joints[:4] == Colours.JOINT).all()
    assert (colours[:-UR5.n] == COLLIDING).all(axis=1).any()
