"""Stills and GIFs: files decode, frames move, bad input is refused."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image, ImageChops

import armkit
from armkit.animation import animate_trajectory, plot_configuration, plot_configurations
from armkit.errors import InputError


def test_still_png_with_link_frames(tmp_path):
    robot = armkit.load("probot-anno")
    path = tmp_path / "anno.png"
    figure = plot_configuration(robot, [0.927, -0.687, -0.396, 0, 1.083, 0.927], path, dpi=60)
    assert len(figure.axes) == 1 and "PROBOT Anno" in figure.axes[0].get_title()
    with Image.open(path) as image:
        assert image.format == "PNG" and image.size == (288, 288)
    with_frames = np.asarray(Image.open(path).convert("RGB"), dtype=int)
    plot_configuration(robot, [0.927, -0.687, -0.396, 0, 1.083, 0.927], tmp_path / "plain.png", dpi=60,
                       frames=False)
    plain = np.asarray(Image.open(tmp_path / "plain.png").convert("RGB"), dtype=int)
    red = (with_frames[..., 0] > 180) & (with_frames[..., 1] < 80) & (with_frames[..., 2] < 80)
    red_plain = (plain[..., 0] > 180) & (plain[..., 1] < 80) & (plain[..., 2] < 80)
    assert red.sum() > red_plain.sum()  # the x axes of the link frames are drawn in red


def test_side_by_side_configurations(tmp_path):
    robot = armkit.load("grb400-scara")
    q = np.array([[0.5, 0.5, 0.0, 0.0], [1.0, 1.2, 0.02, 0.5], [2.0, 0.3, -0.03, -1.0]])
    figure = plot_configurations(robot, q, tmp_path / "three.png", titles=["a", "b", "c"], dpi=40, columns=2)
    assert [ax.get_title() for ax in figure.axes] == ["a", "b", "c"]
    with pytest.raises(InputError, match="titles: expected 3"):
        plot_configurations(robot, q, titles=["a"])


def test_gif_frames_show_the_motion(tmp_path):
    robot = armkit.load("stanford")  # includes a prismatic joint, drawn as a sliding rod
    q = np.linspace(robot.random_q(rng=1), robot.random_q(rng=2), 30)
    path = animate_trajectory(robot, q, tmp_path / "arm.gif", t=np.linspace(0, 3, 30), frames=6, dpi=40)
    with Image.open(path) as image:
        assert image.format == "GIF" and image.n_frames == 6
        image.seek(0)
        first = image.convert("RGB")
        image.seek(5)
        last = image.convert("RGB")
    assert ImageChops.difference(first, last).getbbox() is not None


def test_bad_input():
    robot = armkit.load("grb400-scara")
    with pytest.raises(InputError, match="4 joints"):
        plot_configuration(robot, [0.0, 0.0])
    with pytest.raises(InputError, match=r"expected shape \(samples, 4\)"):
        animate_trajectory(robot, np.zeros(4), "never.gif")
    with pytest.raises(InputError, match="expected 3 times"):
        animate_trajectory(robot, np.zeros((3, 4)), "never.gif", t=[0.0, 1.0])


def test_gif_frames_carry_their_labels_and_axis_numbers(tmp_path):
    robot = armkit.load("grb400-scara")
    q = np.linspace([0, 0, 0, 0], [1.5, 1.2, 0.03, 1.0], 6)
    labels = [f"solution {k // 3 + 1} of 2" for k in range(6)]
    plain = animate_trajectory(robot, q, tmp_path / "plain.gif", frames=6, dpi=40)
    labelled = animate_trajectory(robot, q, tmp_path / "labelled.gif", frames=6, dpi=40, labels=labels)
    with Image.open(plain) as a, Image.open(labelled) as b:
        a.seek(0)
        b.seek(0)
        top_a = np.asarray(a.convert("L"))[:30, :80]
        top_b = np.asarray(b.convert("L"))[:30, :80]
        assert (top_a != top_b).any()  # the label is drawn in the top left corner
    with pytest.raises(InputError, match="labels: expected 6"):
        animate_trajectory(robot, q, tmp_path / "never.gif", labels=["one"])


def test_small_multiples_keep_few_ticks_so_their_labels_do_not_overlap():
    from armkit.animation import TICKS, plot_configurations

    robot = armkit.load("ur5")
    T = robot.fk([0.9, -0.7, -0.4, 0.3, 1.1, 0.9])
    figure = plot_configurations(robot, robot.ik(T, all_solutions=True, turn_copies=False), dpi=40, size=2.0)
    for ax in figure.axes:
        for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
            low, high = sorted(axis.get_view_interval())
            ticks = axis.get_major_locator()()
            assert 2 <= ((ticks >= low - 1e-12) & (ticks <= high + 1e-12)).sum() <= TICKS + 1


def test_obstacle_outlines_lie_on_the_obstacles_surfaces(tmp_path):
    from armkit.animation import _outlines
    from armkit.spatial.rotations import matrix_from_euler
    from armkit.spatial.transforms import transform_from

    T = transform_from(matrix_from_euler([0.3, -0.2, 0.7], "xyz-fixed"), [0.4, -0.1, 0.25])
    tetrahedron = tmp_path / "tetra.obj"
    tetrahedron.write_text("v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nv 0 0 0.1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
    scene = armkit.Scene(armkit.load("ur5"), [armkit.Box([0.5, 0.04, 0.3], T, name="box"),
                                              armkit.Sphere(0.1, [0.5, 0.2, 0.3], name="ball"),
                                              armkit.Cylinder(0.05, 0.8, T, name="post"),
                                              armkit.Mesh(tetrahedron, T, name="tetra")], samples=0)
    shapes = {shape.part: shape for shape in scene.world_shapes()}
    edges = _outlines(shapes["box"])
    assert len(edges) == 12
    local = np.concatenate(edges) @ T[:3, :3] - T[:3, 3] @ T[:3, :3]   # back into the box's frame
    np.testing.assert_allclose(np.abs(local), np.broadcast_to([0.25, 0.02, 0.15], local.shape), atol=1e-9)
    lengths = sorted(float(np.linalg.norm(e[1] - e[0])) for e in edges)
    np.testing.assert_allclose(lengths, [0.04] * 4 + [0.3] * 4 + [0.5] * 4, atol=1e-9)
    circles = np.concatenate(_outlines(shapes["ball"]))
    np.testing.assert_allclose(np.linalg.norm(circles - [0.5, 0.2, 0.3], axis=1), 0.1, atol=1e-9)
    rim = np.concatenate(_outlines(shapes["post"])) @ T[:3, :3] - T[:3, 3] @ T[:3, :3]
    np.testing.assert_allclose(np.hypot(rim[:, 0], rim[:, 1]), 0.05, atol=1e-9)
    np.testing.assert_allclose(np.abs(rim[:, 2]), 0.4, atol=1e-9)
    corners = np.array([[0, 0, 0], [0.1, 0, 0], [0, 0.1, 0], [0, 0, 0.1]]) @ T[:3, :3].T + T[:3, 3]
    edges = _outlines(shapes["tetra"])
    assert len(edges) == 6                                  # each edge of the 4 triangles once
    ends = np.concatenate(edges)
    float32 = 1e-7    # MuJoCo holds mesh vertices in single precision (6e-8 relative)
    assert np.all(np.min(np.linalg.norm(ends[:, None] - corners[None], axis=-1), axis=1) < float32)
    assert _outlines(shapes["floor"]) == []


def test_a_gif_outlines_the_obstacles(tmp_path):
    robot = armkit.load("ur5")
    q = np.linspace([0, -1.2, 1.2, 0, 1.57, 0], [1.57, -1.2, 1.2, 0, 1.57, 0], 5)
    wall = armkit.Box([0.5, 0.04, 0.5], [[1, 0, 0, -0.35], [0, 1, 0, -0.35], [0, 0, 1, 0.25], [0, 0, 0, 1]])
    plain = animate_trajectory(robot, q, tmp_path / "plain.gif", frames=2, trace_tool=False)
    walled = animate_trajectory(robot, q, tmp_path / "wall.gif", frames=2, trace_tool=False,
                                scene=armkit.Scene(robot, [wall], samples=0))
    with Image.open(plain) as a, Image.open(walled) as b:
        assert ImageChops.difference(a.convert("RGB"), b.convert("RGB")).getbbox() is not None
