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
    colours = np.asarray(viewer._arm_panel.arm.handle.batched_colors)
    assert not (colours == COLLIDING).all(axis=1).any()  # a free configuration: nothing coloured
    viewer.q = UR5.home  # the wrist (links 5 and 6) in the floor
    colours = np.asarray(viewer._arm_panel.arm.handle.batched_colors)
    joints = colours[-UR5.n:]
    assert (joints[4:] == COLLIDING).all() and (joints[:4] == Colours.JOINT).all()
    assert (colours[:-UR5.n] == COLLIDING).all(axis=1).any()


BUMPER_URDF = """<robot name="bumper">
  <link name="base"><visual><geometry><box size="0.1 0.1 0.1"/></geometry></visual></link>
  <link name="upper"><visual><origin xyz="0 0 0.15"/>
    <geometry><cylinder radius="0.03" length="0.3"/></geometry></visual>
    <collision><origin xyz="0 0 0.15"/><geometry><cylinder radius="0.03" length="0.3"/></geometry></collision>
  </link>
  <link name="fore"><visual><origin xyz="0 0 0.3"/><geometry><box size="0.04 0.04 0.6"/></geometry></visual>
    <collision><origin xyz="0 0 0.3"/><geometry><box size="0.04 0.04 0.6"/></geometry></collision></link>
  <link name="tip"/>
  <joint name="pan" type="revolute"><parent link="base"/><child link="upper"/><origin xyz="0 0 0.05"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" velocity="1" effort="1"/></joint>
  <joint name="lift" type="revolute"><parent link="upper"/><child link="fore"/><origin xyz="0 0 0.3"/>
    <axis xyz="0 1 0"/><limit lower="-2.6" upper="2.6" velocity="1" effort="1"/></joint>
  <joint name="tip" type="fixed"><parent link="fore"/><child link="tip"/><origin xyz="0 0 0.6"/></joint>
</robot>"""


def test_a_urdf_arm_drawn_with_its_meshes_shows_its_links_in_contact_in_the_contact_colour(tmp_path):
    pytest.importorskip("trimesh")
    path = tmp_path / "bumper.urdf"
    path.write_text(BUMPER_URDF)
    robot = armkit.load(path)
    scene = armkit.Scene(robot, floor=0.0)
    down = [0.0, 2.3]                      # the forearm points down past the floor, 0.45 m from the base
    assert ("fore", "floor") in scene.contacts(down) and not scene.contacts([0.0, 0.0])
    with Viewer(robot, port=0, scene=scene, q=[0.0, 0.0]) as viewer:
        meshes = viewer._arm_panel.meshes
        assert meshes is not None and len(meshes.highlights) == len(meshes.meshes) == 3
        fore = meshes.frames == scene.parts.index("fore")
        assert fore.sum() == 1

        def copies() -> list[str]:  # the contact-coloured copies sent to the browser
            return [name for name in viewer._server.scene._handle_from_node_name
                    if name.endswith("_highlight")]

        def drawn():
            own = np.array([m.visible for m in meshes.meshes])
            highlighted = np.array([h is not None and h.visible for h in meshes.highlights])
            assert (own != highlighted).all()  # each visual drawn once: in its own colours or the contact one
            return highlighted

        assert not drawn().any()
        assert copies() == [] and meshes.highlights == [None] * 3   # never in contact: no copy sent
        viewer.q = down
        np.testing.assert_array_equal(drawn(), fore)
        assert len(copies()) == 1                                   # a copy of the forearm only
        assert tuple(meshes.highlights[int(np.flatnonzero(fore)[0])].color) == COLLIDING
        viewer.q = [0.0, 0.0]
        assert not drawn().any()
        viewer.q = down                                             # in contact again: the same copy
        np.testing.assert_array_equal(drawn(), fore)
        assert len(copies()) == 1


def test_a_mesh_drawing_without_a_highlight_colour_says_so_when_asked_to_highlight(tmp_path):
    pytest.importorskip("trimesh")
    from armkit.errors import ArmkitError

    path = tmp_path / "bumper.urdf"
    path.write_text(BUMPER_URDF)
    with Viewer(armkit.load(path), port=0) as viewer:              # no collision scene: no highlight colour
        meshes = viewer._arm_panel.meshes
        meshes.highlight(np.zeros(3, dtype=bool))                    # nothing flagged: nothing to do
        with pytest.raises(ArmkitError, match="highlight: this drawing was made without a highlight colour"):
            meshes.highlight(np.ones(3, dtype=bool))
        with pytest.raises(ArmkitError,
                           match=r"highlight: expected 3 flags \(one per visual\), got shape \(2,\)"):
            meshes.highlight(np.ones(2, dtype=bool))
