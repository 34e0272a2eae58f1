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


def _line(ax, gid: str) -> np.ndarray:
    """The ``(2, 3)`` end points of the one line of ``ax`` with this gid."""
    found = [line for line in ax.lines if line.get_gid() == gid]
    assert len(found) == 1, f"{len(found)} lines named {gid!r}"
    return np.array(found[0].get_data_3d()).T


@pytest.mark.parametrize("name", ["puma560", "stanford", "grb400-scara"])
def test_robot_plot_draws_the_base_and_tool_triads_and_joint_axes_where_fk_puts_them(tmp_path, name):
    robot = armkit.load(name)
    q = robot.random_q(rng=3)
    figure = robot.plot(q, frames=True)
    ax = figure.axes[0]
    frames = robot.link_frames(q)
    for label, T in (("base", frames[0]), ("tool", robot.fk(q)), *((f"link {i}", frames[i])
                                                                     for i in range(1, robot.n + 1))):
        for k, axis in enumerate("xyz"):
            start, end = _line(ax, f"{label} {axis}")
            np.testing.assert_allclose(start, T[:3, 3], atol=1e-12)
            direction = (end - start) / np.linalg.norm(end - start)
            np.testing.assert_allclose(direction, T[:3, k], atol=1e-12)
    T_joints, _ = armkit.kinematics.joint_frames(robot, q)
    for joint, T in zip(robot.joint_names, T_joints, strict=True):
        ends = _line(ax, f"axis {joint}")
        np.testing.assert_allclose(ends.mean(axis=0), T[:3, 3], atol=1e-12)
        direction = (ends[1] - ends[0]) / np.linalg.norm(ends[1] - ends[0])
        np.testing.assert_allclose(direction, T[:3, 2], atol=1e-12)
    origins = next(c for c in ax.collections if c.get_gid() == "joint origins")
    np.testing.assert_allclose(np.array(origins._offsets3d).T, T_joints[:, :3, 3], atol=1e-12)
    spans = np.ptp([ax.get_xlim(), ax.get_ylim(), ax.get_zlim()], axis=1)
    np.testing.assert_allclose(spans, spans[0], rtol=1e-12)  # equal scale in x, y and z
    np.testing.assert_allclose(ax.get_box_aspect() / ax.get_box_aspect()[0], 1.0, rtol=1e-12)
    path = tmp_path / "arm.png"
    figure.savefig(path, dpi=50)
    with Image.open(path) as image:
        assert image.format == "PNG" and image.size == (250, 250)
        assert len(image.convert("RGB").getcolors(1 << 16)) > 20  # drawn, not blank


def test_a_batch_draws_ghosts_and_the_last_configuration_as_the_arm_into_given_axes():
    from matplotlib.figure import Figure

    robot = armkit.load("probot-anno")
    T = robot.fk([0.9, -0.7, -0.4, 0, 1.1, 0.9])
    q = robot.ik(T, all_solutions=True)
    figure = Figure()
    ax = figure.add_subplot(projection="3d")
    ax.plot([5.0], [5.0], [5.0], "k.")  # something already there stays in view
    assert robot.plot(q, ax=ax) is figure
    for k in range(len(q) - 1):
        start, _ = _line(ax, f"ghost {k + 1} tool x")
        np.testing.assert_allclose(start, T[:3, 3], atol=1e-9)
        ghost = next(line for line in ax.lines if line.get_gid() == f"ghost {k + 1} tool x")
        assert ghost.get_alpha() == armkit.animation.GHOST_ALPHA
    np.testing.assert_allclose(_line(ax, "tool x")[0], T[:3, 3], atol=1e-9)
    assert not any((line.get_gid() or "").startswith(f"ghost {len(q)}") for line in ax.lines)
    assert ax.get_xlim()[1] >= 5.0 and ax.get_zlim()[1] >= 5.0
    assert f"and {len(q) - 1} ghosts" in ax.get_title()


def test_robot_plot_refuses_flat_axes_and_wrong_shapes():
    from matplotlib.figure import Figure

    robot = armkit.load("probot-anno")
    with pytest.raises(InputError, match="ax: expected 3-D axes"):
        robot.plot(robot.home, ax=Figure().add_subplot())
    with pytest.raises(InputError, match=r"expected shape \(6,\) or \(N, 6\)"):
        robot.plot(np.zeros((2, 2, 6)))
    with pytest.raises(InputError):
        robot.plot([0.0, 1.0])
