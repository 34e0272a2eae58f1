"""armkit view without a browser: the drawing geometry, the read-outs, and the Viewer's Python API
(a real viser server in this process, no page connected)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import urllib.request

import numpy as np
import pytest
from conftest import WAIT_S, interruptible, wait_until

import armkit
from armkit.errors import InputError, JointLimitError, UnreachableError
from armkit.lab import published
from armkit.spatial.transforms import transform_from, transform_from_pose
from armkit.trajectory import read_waypoints
from armkit.view.geometry import arm_placement, arm_size, ellipsoid_axes, rotations_z_to, unit_cylinder
from armkit.view.playback import Playback
from armkit.view.readout import pose_html
from armkit.view.scene import Colours

viser = pytest.importorskip("viser")

from armkit.view import Viewer  # noqa: E402  (after the importorskip)
from armkit.view.ik_ghosts import LABEL_SPACING  # noqa: E402

ROBOTS = ["probot-anno", "puma560", "ur5", "stanford", "panda", "grb400-scara"]


@pytest.fixture(scope="module")
def probot():
    viewer = Viewer("probot-anno", port=0)
    yield viewer
    viewer.close()


def test_import_armkit_does_not_import_viser():
    code = "import sys, armkit; print('viser' in sys.modules, 'armkit.view' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split() == ["False", "False"]


@pytest.mark.parametrize("name", ROBOTS)
def test_the_drawn_links_run_from_the_floor_through_every_joint_to_the_tool(name):
    robot = armkit.load(name)
    q = robot.random_q(rng=3)
    p = arm_placement(robot, q, 0.01)
    links = slice(0, p.link_count)
    R = armkit.spatial.matrix_from_quaternion_wxyz(p.wxyzs[links])
    half = R[..., :, 2] * p.scales[links, 2:3] / 2
    starts, ends = p.positions[links] - half, p.positions[links] + half
    np.testing.assert_allclose(starts[0], 0.0, atol=1e-12)                   # on the floor origin
    np.testing.assert_allclose(ends[-1], robot.fk(q)[:3, 3], atol=1e-12)    # at the tool
    np.testing.assert_allclose(starts[1:], ends[:-1], atol=1e-12)           # one unbroken path
    corners = np.concatenate([starts, ends])
    assert np.linalg.norm(corners[:, None] - p.joint_origins[None], axis=-1).min(axis=0).max() < 1e-12
    np.testing.assert_allclose(p.joint_axes, armkit.kinematics.joint_frames(robot.chain, q)[0][:, :3, 2])


def test_rotations_z_to_are_rotations_with_the_requested_z_axis():
    d = np.random.default_rng(0).normal(size=(50, 3))
    R = rotations_z_to(d)
    np.testing.assert_allclose(R @ np.swapaxes(R, -1, -2), np.broadcast_to(np.eye(3), R.shape), atol=1e-12)
    np.testing.assert_allclose(np.linalg.det(R), 1.0)
    np.testing.assert_allclose(R[..., 2], d / np.linalg.norm(d, axis=-1, keepdims=True), atol=1e-12)


def test_the_unit_cylinder_is_closed_and_faces_outwards():
    vertices, faces = unit_cylinder(16)
    v = vertices.astype(float)[faces]
    normals = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
    volume = np.einsum("ij,ij->i", v[:, 0], normals).sum() / 6      # divergence theorem
    assert volume == pytest.approx(16 / 2 * np.sin(2 * np.pi / 16), rel=1e-6)   # the 16-gon prism


def test_the_velocity_ellipsoid_semi_axes_bound_the_tool_speed_of_unit_joint_rates():
    robot = armkit.load("puma560")
    q = robot.random_q(rng=1)
    R, semi = ellipsoid_axes(robot, q)
    rates = np.random.default_rng(2).normal(size=(2000, 6))
    rates /= np.linalg.norm(rates, axis=1, keepdims=True)
    v_local = (robot.jacobian(q)[:3] @ rates.T).T @ R                 # in the ellipsoid's axes
    assert np.all(np.sum((v_local / semi) ** 2, axis=1) <= 1 + 1e-9)
    assert np.abs(v_local).max(axis=0) / semi == pytest.approx(np.ones(3), abs=0.15)


def test_the_read_out_shows_the_fk_matrix_and_the_angles_of_the_chosen_convention():
    robot = armkit.load("zju-i")
    q = np.radians([15.0] * 6)
    T = robot.fk(q)
    text = pose_html(robot, q, T, "xyz-euler", degrees=True)
    matrix = text.split("<pre data-armkit='pose-matrix' style='margin:2px 0'>")[1].split("</pre>")[0]
    np.testing.assert_allclose(np.array(matrix.split(), dtype=float).reshape(4, 4), T, atol=1e-6)
    angles = text.split("data-armkit='orientation'>")[1].split("</span>")[0]
    np.testing.assert_allclose(np.array(angles.split(), dtype=float),
                               armkit.spatial.euler_from_matrix(T, "xyz-euler", degrees=True), atol=1e-3)
    quaternion = pose_html(robot, q, T, "wxyz", degrees=True).split("data-armkit='orientation'>")[1]
    np.testing.assert_allclose(np.array(quaternion.split("</span>")[0].split(), dtype=float),
                               armkit.spatial.quaternion_wxyz_from_matrix(T[:3, :3]), atol=1e-6)


def test_setting_q_moves_the_handle_to_the_tool(probot):
    q = np.array([0.2, -0.3, 0.4, 0.1, 0.9, -0.2])
    probot.q = q
    np.testing.assert_array_equal(probot.q, q)
    np.testing.assert_allclose(probot.target, probot.robot.fk(q), atol=1e-15)
    assert probot.solutions is None
    with pytest.raises(InputError, match="6"):
        probot.q = [0.1, 0.2]


def test_report_000s_first_target_has_four_solutions_in_the_limits_and_four_outside(probot):
    T = transform_from_pose(np.array(published.PROBOT_IK[0][0]), "xyz-fixed")
    probot.q = probot.robot.home
    found = probot.show_solutions(T, follow=False)
    assert (len(found.q), int(found.within_limits.sum())) == (8, 4)
    assert [g.visible for g in probot._ik.ghosts] == [True] * 8 + [False] * (len(probot._ik.ghosts) - 8)
    labels = np.array([label.position for label in probot._ik.labels[:8]])
    apart = np.linalg.norm(labels[:, None] - labels[None], axis=-1)[np.triu_indices(8, 1)]
    assert apart.min() >= LABEL_SPACING * probot._radius - 1e-12  # no two labels on one spot
    np.testing.assert_array_equal(probot.q, probot.robot.home)              # follow=False: stays
    q = probot.pick(2)
    np.testing.assert_array_equal(q, found.q[1])
    np.testing.assert_allclose(probot.robot.fk(q), T, atol=1e-12)
    with pytest.raises(InputError, match="8 solutions"):
        probot.pick(9)


def test_an_unreachable_target_says_how_far_the_closest_pose_is(probot):
    T = transform_from(np.eye(3), [2.0, 0.0, 0.3])                         # 2 m out, the arm reaches ~0.6 m
    found = probot.show_solutions(T)
    assert len(found.q) == 0
    assert not any(g.visible for g in probot._ik.ghosts)
    text = probot._ik.status.content
    mm = float(text.split("closest pose found is ")[1].split(" mm")[0])
    with pytest.raises(UnreachableError) as solver:
        probot.robot.ik(T, near=probot.q, within_limits=False)
    assert mm == pytest.approx(solver.value.position_error * 1000, abs=0.05)
    assert mm > 1000 * (2.0 - arm_size(probot.robot))              # at least the gap to the arm's reach


def test_switching_the_angle_unit_rewrites_the_sliders_the_solution_list_and_the_waypoints():
    with Viewer("probot-anno", port=0) as viewer:
        q = np.array([0.9, -0.9, -0.35, 0.96, 2.97, -0.24])
        viewer.q = q
        viewer.teach()
        found = viewer.show_solutions(viewer.robot.fk(q), follow=False)
        joints = viewer._joints
        assert [s.label[-5:] for s in joints.sliders] == ["[deg]"] * 6
        joints.units.value = "rad"                        # the panel's "angles" list
        assert [s.label[-5:] for s in joints.sliders] == ["[rad]"] * 6
        np.testing.assert_allclose([s.value for s in joints.sliders], q, atol=5e-4)   # 3 decimals
        first_row = found.q[0]
        assert " ".join(f"{v:.3f}" for v in first_row) in viewer._ik.status.content
        assert " ".join(f"{v:.3f}" for v in q) in viewer._teach._list.content
        np.testing.assert_array_equal(viewer.q, q)        # the arm stays
        joints.units.value = "deg"
        assert " ".join(f"{np.degrees(v):.1f}°" for v in first_row) in viewer._ik.status.content


def test_a_bad_self_motion_request_leaves_the_target_and_the_ik_ghosts_as_they_were():
    with Viewer("panda", port=0) as viewer:
        T = viewer.robot.fk(viewer.robot.home + 0.1)
        viewer.show_solutions(T, follow=False)
        for free_joint, samples, message in (("elbow", 8, "free_joint 'elbow'"), (2, 1, "samples: expected")):
            with pytest.raises(InputError, match=message):
                viewer.show_self_motion(free_joint, viewer.robot.fk(viewer.robot.home), samples=samples)
            np.testing.assert_array_equal(viewer.target, T)
            assert viewer.solutions is not None and viewer._ik.ghosts[0].visible


def test_numeric_ik_arms_show_the_solution_nearest_the_arm():
    with Viewer("panda", port=0) as viewer:
        q_goal = viewer.robot.home + 0.2
        found = viewer.show_solutions(viewer.robot.fk(q_goal))
        assert len(found.q) == 1 and found.within_limits[0]
        np.testing.assert_allclose(viewer.robot.fk(viewer.q), viewer.robot.fk(q_goal), atol=1e-8)


def test_teach_plan_and_save_waypoints_within_the_limits(probot, tmp_path):
    probot.clear_waypoints()
    with pytest.raises(InputError, match="at least two"):
        probot.plan()
    for q in published.PROBOT_WAYPOINT_JOINTS:
        probot.q = q
        assert probot.teach() == len(probot.waypoints)
    trajectory = probot.plan()
    robot = probot.robot
    assert np.all(trajectory.peak_velocity <= robot.max_velocity * (1 + 1e-9))
    assert np.all(trajectory.peak_acceleration <= robot.max_acceleration * (1 + 1e-9))
    probot.time = trajectory.duration / 2
    np.testing.assert_allclose(probot.q, trajectory.at_time(trajectory.duration / 2)[0], atol=1e-3)
    path = probot.save_waypoints(tmp_path / "w.csv")
    np.testing.assert_array_equal(read_waypoints(path, 6), np.array(published.PROBOT_WAYPOINT_JOINTS))
    with pytest.raises(InputError, match="already exists"):
        probot.save_waypoints(path)
    probot.q = [0.0, 0.0, -1.0, 0.0, 0.0, 0.0]                          # q3 below its -40 deg limit
    with pytest.raises(JointLimitError, match="q3"):
        probot.teach()


def test_a_trajectory_file_from_armkit_traj_plays_on_the_timeline(probot, tmp_path):
    robot = probot.robot
    trajectory = armkit.plan_trajectory(robot, np.array(published.PROBOT_WAYPOINT_JOINTS))
    path = trajectory.to_csv(tmp_path / "traj.csv")
    playback = probot.load(path)
    assert playback.duration == pytest.approx(trajectory.duration, abs=1e-9)
    t = 0.37 * trajectory.duration
    q, qd, qdd = playback.at(t)
    exact = trajectory.at_time(t)
    np.testing.assert_allclose(q, exact[0], atol=1e-4)
    np.testing.assert_allclose(qd, exact[1], atol=1e-3)
    probot.play()
    wait_until(lambda: probot.time > 0.2, "the timeline to move")
    probot.pause()
    probot._timeline.player.join(WAIT_S)           # the player thread ends at the pause: the time stays put
    paused = probot.time
    assert 0.2 < paused < trajectory.duration and not probot._timeline.player.is_alive()
    assert probot.time == paused
    with pytest.raises(InputError, match="joint columns"):
        Playback.from_file(trajectory.to_csv(tmp_path / "t.csv"), armkit.load("grb400-scara"))


def test_closing_the_viewer_while_it_plays_stops_the_timeline_and_sends_nothing_after():
    import warnings

    viewer = Viewer("probot-anno", port=0)
    try:
        trajectory = armkit.plan_trajectory(viewer.robot, np.array(published.PROBOT_WAYPOINT_JOINTS))
        viewer.play(trajectory)
        wait_until(lambda: viewer.time > 0.1, "the timeline to move")
        player = viewer._timeline.player
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            viewer.close()
            closed_at, q = viewer.time, viewer.q
            player.join(WAIT_S)
    finally:
        viewer.close()
    assert not player.is_alive() and not viewer._timeline.playing
    assert viewer.time == closed_at < trajectory.duration
    np.testing.assert_array_equal(viewer.q, q)
    assert not [w for w in caught if "closed connection" in str(w.message)], [str(w.message) for w in caught]


def _serve_and_interrupt(args: list[str], cwd, while_serving=None) -> tuple[str, int, str, str]:
    """Run ``armkit view ARGS --port 0 --no-browser``, call ``while_serving(url)`` once it prints its
    address, then Ctrl-C it; its first line, exit code, the rest of stdout, and stderr."""
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    process = subprocess.Popen([sys.executable, "-m", "armkit.cli.main", "view", *args, "--port", "0",
                                "--no-browser"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                               env=env, cwd=cwd, preexec_fn=interruptible)
    try:
        line = process.stdout.readline()
        if while_serving is not None:
            while_serving(line.split(" at ")[1].split()[0])
            assert process.poll() is None
        process.send_signal(signal.SIGINT)
        out, err = process.communicate(timeout=WAIT_S)
    finally:
        process.kill()
    return line, process.returncode, out, err


def _page_is_served(url: str) -> None:
    with urllib.request.urlopen(url, timeout=WAIT_S) as response:
        assert b"<html" in response.read(2000).lower()


def test_cli_view_serves_the_page_and_ctrl_c_ends_it_with_one_line(tmp_path):
    line, code, out, err = _serve_and_interrupt(["probot-anno"], tmp_path, _page_is_served)
    assert line.startswith("armkit view: PROBOT Anno at http://127.0.0.1:")
    assert code == 130
    assert err.strip() == "armkit view: stopped"
    assert out.strip() == ""


def _page_shows(url: str, text: str) -> None:
    """Open the page's websocket as a browser tab does and read its messages until one holds ``text``
    (viser's frame: the sizes of its MessagePack, 8 bytes each, then the MessagePack zstd-compressed)."""
    import asyncio

    import websockets
    import zstandard

    def messages(frame: bytes) -> bytes:
        size, compressed = int.from_bytes(frame[:8], "little"), int.from_bytes(frame[8:16], "little")
        return zstandard.ZstdDecompressor().decompress(frame[16:16 + compressed], max_output_size=size)

    async def read() -> None:
        protocol = f"viser-v{viser.__version__}"
        async with websockets.connect(url.replace("http", "ws"), subprotocols=[protocol],
                                      max_size=None) as connection:
            async with asyncio.timeout(WAIT_S):
                while text.encode() not in messages(await connection.recv()):
                    pass

    asyncio.run(read())


def test_cli_view_free_joint_serves_a_7_joint_arms_self_motion_and_a_6_joint_arm_is_one_error_line(tmp_path):
    def serves_the_self_motion(url: str) -> None:
        _page_is_served(url)
        # the self-motion panel's text: the branches along q3 (the CLI's 3 is joint q3), the arm on one
        _page_shows(url, "branches along q3; branch ")

    line, code, _, err = _serve_and_interrupt(["panda", "--free-joint", "3"], tmp_path,
                                              serves_the_self_motion)
    assert line.startswith("armkit view: Panda at http://127.0.0.1:")
    assert (code, err.strip()) == (130, "armkit view: stopped")
    result = subprocess.run([sys.executable, "-m", "armkit.cli.main", "view", "ur5", "--free-joint", "3",
                             "--port", "0", "--no-browser"], capture_output=True, text=True, timeout=WAIT_S)
    assert result.returncode == 1
    assert result.stderr.strip().splitlines() == [
        "error: self-motion: needs a 7-joint arm (one joint free, six solved in closed form); UR5 has 6"]


def test_cli_view_of_an_unknown_robot_is_one_error_line():
    result = subprocess.run([sys.executable, "-m", "armkit.cli.main", "view", "no-such-arm", "--no-browser"],
                            capture_output=True, text=True, timeout=WAIT_S)
    assert result.returncode == 1
    assert result.stderr.strip().startswith("error: unknown robot 'no-such-arm'")
    assert len(result.stderr.strip().splitlines()) == 1


def test_a_wrist_singular_target_flags_its_families():
    with Viewer("puma560", port=0) as viewer:
        robot = viewer.robot
        q = np.array([0.3, -0.4, 0.5, 0.2, 0.0, -0.1])                 # q5 = 0: joint axes 4 and 6 align
        found = viewer.show_solutions(robot.fk(q), follow=False)
        assert found.family.any()
        family = int(np.flatnonzero(found.family & found.within_limits)[0])
        assert viewer._ik.ghosts[family].handle.batched_colors[0].tolist() == list(Colours.GHOST_FAMILY)
        assert "singular family" in viewer._ik.status.content
        np.testing.assert_allclose(robot.fk(found.q[family]), robot.fk(q), atol=1e-12)


def _send_messages(url: str, frames: list) -> None:
    """Send each frame to the viewer's websocket as a browser tab would, one connection each
    (a frame the server cannot read ends its connection)."""
    import asyncio

    import websockets

    async def send() -> None:
        for frame in frames:
            protocol = f"viser-v{viser.__version__}"
            async with websockets.connect(url.replace("http", "ws"), subprotocols=[protocol]) as connection:
                await connection.send(frame)
                await asyncio.sleep(0.3)

    asyncio.run(send())


def test_a_zero_quaternion_on_the_ik_handle_is_a_status_line_not_a_traceback(capfd):
    import msgspec

    with Viewer("probot-anno", port=0) as viewer:
        before = viewer.target.copy()
        _send_messages(viewer.url, [msgspec.msgpack.encode(
            {"type": "TransformControlsUpdateMessage", "name": "/target", "wxyz": [0.0, 0.0, 0.0, 0.0],
             "position": [0.2, 0.1, 0.3]})])
        wait_until(lambda: "data-armkit='error'" in viewer._status.content, "the panel's error line")
        assert "quaternion: expected a non-zero quaternion, got norm 0" in viewer._status.content
        np.testing.assert_array_equal(viewer.target, before)
    _, err = capfd.readouterr()
    assert "Traceback" not in err, err


def test_junk_websocket_frames_are_one_line_each_and_the_server_stays_up(tmp_path):
    import msgspec

    frames = [b"\x00\x01junk", "a text frame", b"\x81\xa3", msgspec.msgpack.encode({"type": "NoSuchMessage"}),
              msgspec.msgpack.encode([1, 2, 3]),
              msgspec.msgpack.encode({"type": "TransformControlsUpdateMessage", "name": "/target",
                                      "wxyz": "abc", "position": [0.2, 0.1, 0.3]})]

    def send_junk(url: str) -> None:
        _send_messages(url, frames)
        _page_is_served(url)                                 # still serving

    _, _, _, err = _serve_and_interrupt(["probot-anno"], tmp_path, send_junk)
    lines = err.strip().splitlines()
    assert "Traceback" not in err and lines[-1] == "armkit view: stopped", err
    assert len(lines) == len(frames) + 1, err
    assert all(line.startswith("armkit view: ignored a message it cannot read (") for line in lines[:-1]), err


def test_a_probe_of_the_port_logs_nothing_https_and_bad_http_one_line_each(caplog):
    import socket
    import ssl

    import msgspec

    from armkit.view.server_log import TLS_LINE

    def server_lines() -> list[str]:
        return [r.getMessage() for r in caplog.records if r.name in ("websockets.server", "asyncio")]

    with Viewer("probot-anno", port=0) as viewer:
        port = int(viewer.url.rsplit(":", 1)[1])
        with socket.create_connection(("127.0.0.1", port), timeout=WAIT_S):
            pass                                     # a port check (nc -z), a browser's unused pre-connection
        # https:// typed for the page: a real TLS hello (the server reads it, answers nothing, closes)
        context = ssl.create_default_context()
        context.check_hostname, context.verify_mode = False, ssl.CERT_NONE
        with socket.create_connection(("127.0.0.1", port), timeout=WAIT_S) as raw, \
                pytest.raises((ssl.SSLError, ConnectionError, OSError)):
            context.wrap_socket(raw, server_hostname="127.0.0.1")
        wait_until(lambda: len(server_lines()) == 1, "the https line")
        with socket.create_connection(("127.0.0.1", port), timeout=WAIT_S) as probe:
            probe.sendall(b"\x16\x03\x01\x00\xa5\x01\x00\x00\xa1\x03\x03\r\n\r\n")  # a TLS record, cut
            probe.recv(100)                            # the server answers or closes: it has read it
        wait_until(lambda: len(server_lines()) == 2, "the second https line")
        with socket.create_connection(("127.0.0.1", port), timeout=WAIT_S) as old:
            old.sendall(b"GET / HTTP/1.0\r\n\r\n")   # HTTP the server does not take
            old.recv(100)
        wait_until(lambda: len(server_lines()) == 3, "the bad request's line")
        _send_messages(viewer.url, [msgspec.msgpack.encode({"type": "NoSuchMessage"})])
        wait_until(lambda: len(server_lines()) == 4, "the bad message's line")
    server = server_lines()
    assert server[:2] == [TLS_LINE] * 2, server
    assert "the viewer serves http://, not https://" in TLS_LINE
    assert server[2] == ("armkit view: refused a connection that sent no valid HTTP request (ValueError: "
                         "unsupported protocol; expected HTTP/1.1: GET / HTTP/1.0)"), server
    assert server[3].startswith("armkit view: ignored a message it cannot read ("), server


# ------------------------------------------------------------------ a URDF arm's own look, the panel
SHAPES_URDF = """<robot name="shapes">
  <link name="base"><visual><origin xyz="0 0 0.05"/><geometry><box size="0.2 0.1 0.1"/></geometry>
    </visual></link>
  <link name="upper_arm_link_with_a_long_name">
    <visual><origin xyz="0 0 0.15"/><geometry><cylinder radius="0.03" length="0.3"/></geometry>
    </visual></link>
  <link name="hand"><visual><geometry><sphere radius="0.04"/></geometry></visual>
    <visual><geometry><mesh filename="package://shapes_description/meshes/hand.stl" scale="2 2 2"/></geometry>
    </visual></link>
  <joint name="shoulder_pan_joint_of_the_arm" type="revolute"><parent link="base"/>
    <child link="upper_arm_link_with_a_long_name"/><origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-6.2832" upper="6.2832" velocity="1" effort="1"/></joint>
  <joint name="elbow_joint_of_the_arm" type="revolute"><parent link="upper_arm_link_with_a_long_name"/>
    <child link="hand"/><origin xyz="0 0 0.3" rpy="0.3 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-3.1416" upper="3.1416" velocity="1" effort="1"/></joint>
</robot>"""


def _shapes_arm(tmp_path, with_mesh: bool):
    trimesh = pytest.importorskip("trimesh")
    folder = tmp_path / "shapes_description"
    (folder / "urdf").mkdir(parents=True)
    (folder / "meshes").mkdir()
    if with_mesh:
        trimesh.creation.box(extents=(0.01, 0.02, 0.03)).export(folder / "meshes" / "hand.stl")
    path = folder / "urdf" / "shapes.urdf"
    path.write_text(SHAPES_URDF)
    return armkit.load(path)


def test_a_urdf_arm_is_drawn_with_its_meshes_and_shapes_each_in_its_chain_frame(tmp_path):
    robot = _shapes_arm(tmp_path, with_mesh=True)
    assert [(s.link, s.kind, s.size) for s in robot.urdf.shapes] == [
        ("base", "box", (0.2, 0.1, 0.1)), ("upper_arm_link_with_a_long_name", "cylinder", (0.03, 0.3)),
        ("hand", "sphere", (0.04,))]
    viewer = Viewer(robot, port=0)
    try:
        panel = viewer._arm_panel
        assert panel.meshes is not None and not panel.arm.visible and len(panel.meshes.meshes) == 4
        viewer.q = [0.7, -1.1]
        frames = robot.link_frames(viewer.q)
        for i, node in viewer._arm_panel.meshes._nodes.items():
            np.testing.assert_allclose(node.position, frames[i, :3, 3], atol=1e-12)
            np.testing.assert_allclose(armkit.spatial.matrix_from_quaternion_wxyz(node.wxyz),
                                       frames[i, :3, :3], atol=1e-12)
        viewer._arm_panel.show_meshes.value = False   # the box in the panel: capsules instead
        assert viewer._arm_panel.arm.visible and not viewer._arm_panel.meshes.visible
    finally:
        viewer.close()


def test_a_missing_mesh_draws_capsules_and_says_so_once(tmp_path):
    robot = _shapes_arm(tmp_path, with_mesh=False)
    with pytest.warns(UserWarning, match=r"shapes: drawn as capsules: mesh package://shapes_description/meshes/"
                                         r"hand\.stl of link hand not found") as caught:
        viewer = Viewer(robot, port=0)
    try:
        assert len(caught) == 1 and viewer._arm_panel.meshes is None and viewer._arm_panel.arm.visible
        viewer.q = [0.1, 0.2]  # moving warns no more
    finally:
        viewer.close()


def test_package_meshes_are_found_through_package_paths_and_ros_package_path(tmp_path, monkeypatch):
    from armkit.urdf import find_mesh_file

    (tmp_path / "share" / "arm_pkg" / "meshes").mkdir(parents=True)
    mesh = tmp_path / "share" / "arm_pkg" / "meshes" / "a.stl"
    mesh.write_text("solid a\nendsolid a\n")
    urdf = tmp_path / "elsewhere"  # the URDF's folder
    assert find_mesh_file("package://arm_pkg/meshes/a.stl", urdf) is None
    assert find_mesh_file("package://arm_pkg/meshes/a.stl", urdf, [tmp_path / "share"]) == mesh
    monkeypatch.setenv("ROS_PACKAGE_PATH", f"/nonexistent{os.pathsep}{tmp_path / 'share'}")
    assert find_mesh_file("package://arm_pkg/meshes/a.stl", urdf) == mesh
    assert find_mesh_file(f"file://{mesh}", urdf) == mesh


def test_long_joint_names_get_a_row_of_their_own_and_number_boxes_show_every_digit(tmp_path):
    from armkit.view.readout import BOX_CHARS, box_decimals

    robot = _shapes_arm(tmp_path, with_mesh=True)
    viewer = Viewer(robot, port=0)
    try:
        names = [row.content for row in viewer._joints.name_rows]
        assert len(names) == 2 and "shoulder_pan_joint_of_the_arm [deg]" in names[0]
        assert [slider.label for slider in viewer._joints.sliders] == ["q1 [deg]", "q2 [deg]"]
        viewer.q = [1.234567, -3.0]
        for slider in viewer._joints.sliders:
            assert len(f"{slider.value:.{round(-np.log10(slider.step))}f}") <= BOX_CHARS
        assert viewer._joints.sliders[0].value == round(np.degrees(1.234567), 1)
    finally:
        viewer.close()
    assert (box_decimals(-360.0, 360.0, 1), box_decimals(-0.5, 0.5, 4), box_decimals(0, 2000, 1)) == (1, 3, 1)


def test_ghost_labels_stay_apart_even_when_ghosts_coincide():
    from armkit.view.geometry import label_positions

    rng = np.random.default_rng(0)
    shared = rng.normal(size=(5, 3))
    candidates = [shared] * 6 + [rng.normal(size=(5, 3)) for _ in range(10)]
    positions = label_positions(candidates, 0.3)
    apart = np.linalg.norm(positions[:, None] - positions[None], axis=-1)[np.triu_indices(16, 1)]
    assert len(positions) == 16 and apart.min() >= 0.3 - 1e-12
    for points, position in zip(candidates, positions, strict=True):  # on its ghost, or straight above it
        offsets = position - points
        assert (np.linalg.norm(offsets[:, :2], axis=1) < 1e-12).any()


def test_a_general_6r_arms_ten_solutions_are_all_drawn_as_ghosts_with_labels_apart():
    from armkit.chain import DHRow

    rows = [(1.184148, 0.197951, 0.053701), (-1.426528, 0.285711, 0.251453),
            (0.980476, 0.359932, 0.096213), (-0.763343, 0.318981, -0.172995),
            (0.993825, 0.071951, 0.195293), (-1.006478, 0.181301, -0.109957)]
    robot = armkit.Robot.from_dh([DHRow(alpha=alpha, a=a, d=d, theta=0) for alpha, a, d in rows], "standard",
                                 limits=[(-np.pi, np.pi)] * 6, name="general 6R")
    T = robot.fk([0.575, 1.745, -2.464, -1.59, -2.913, -1.708])
    with Viewer(robot, port=0) as viewer:
        found = viewer.show_solutions(T, follow=False)
        count = len(found.q)
        assert count > 8 and len(viewer._ik.ghosts) >= count  # more than the 8 ghosts the viewer used to keep
        ghosts = viewer._ik.ghosts
        assert [g.visible for g in ghosts] == [True] * count + [False] * (len(ghosts) - count)
        for ghost, q in zip(ghosts, found.q, strict=False):  # each ghost its solution, at the target
            np.testing.assert_allclose(ghost.placement.link_frames[-1], T, atol=1e-9)
            np.testing.assert_allclose(ghost.placement.link_frames, robot.link_frames(q), atol=1e-12)
        labels = np.array([label.position for label in viewer._ik.labels[:count]])
        apart = np.linalg.norm(labels[:, None] - labels[None], axis=-1)[np.triu_indices(count, 1)]
        assert apart.min() >= LABEL_SPACING * viewer._radius - 1e-12


def test_cli_view_of_a_urdf_with_a_missing_mesh_says_so_in_one_warning_line(tmp_path):
    path = tmp_path / "arm.urdf"
    path.write_text('<robot name="m"><link name="a"><visual><geometry><mesh filename="package://nopkg/a.stl"/>'
                    '</geometry></visual></link><link name="b"/><joint name="j" type="continuous">'
                    '<parent link="a"/><child link="b"/><origin xyz="0 0 0.3"/></joint></robot>')
    line, _, _, err = _serve_and_interrupt([str(path)], tmp_path)
    assert line.startswith("armkit view: m at http://127.0.0.1:")
    assert err.strip().splitlines() == ["warning: m: drawn as capsules: mesh package://nopkg/a.stl of link a "
                                        "not found", "armkit view: stopped"]
