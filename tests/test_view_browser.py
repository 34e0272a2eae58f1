"""armkit view in a real browser: Debian's chromium, headless, driven by Playwright.

The page is viser's web client talking to a :class:`armkit.view.Viewer` in this process; the
tests read the read-outs from the page's DOM (their ``data-armkit`` attributes), drive its
sliders, buttons and lists, and keep the screenshots they take in ``ARMKIT_VIEW_ARTIFACTS``
(default ``tests/artifacts/``). Without chromium or Playwright they skip, unless
``ARMKIT_REQUIRE_BROWSER=1`` (CI) makes that a failure.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from conftest import WAIT_S, wait_until

from armkit.lab import published
from armkit.spatial.rotations import matrix_from_quaternion_wxyz, rotation_angle_between
from armkit.spatial.transforms import transform_from_pose
from armkit.trajectory import read_waypoints

pytestmark = pytest.mark.browser

CHROMIUM = "/usr/bin/chromium"
ARGS = ["--headless=new", "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--no-sandbox",
        "--disable-background-networking", "--disable-component-update", "--no-first-run", "--disable-sync"]
#: The page renders in software on a shared machine: every wait for the page is for an event,
#: bounded generously [ms].
WAIT_MS = int(WAIT_S * 1000)
ARTIFACTS = Path(os.environ.get("ARMKIT_VIEW_ARTIFACTS", Path(__file__).parent / "artifacts"))


def _require_browser():
    missing = []
    if not Path(CHROMIUM).exists():
        missing.append(f"chromium ({CHROMIUM}; apt-get install chromium)")
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        missing.append("playwright (pip install playwright)")
        sync_playwright = None
    if missing:
        message = "browser tests need " + " and ".join(missing)
        if os.environ.get("ARMKIT_REQUIRE_BROWSER") == "1":
            pytest.fail(message + " (ARMKIT_REQUIRE_BROWSER=1)")
        pytest.skip(message)
    return sync_playwright


@pytest.fixture(scope="module")
def browser():
    sync_playwright = _require_browser()
    pytest.importorskip("viser")
    with sync_playwright() as playwright:
        launched = playwright.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        yield launched
        launched.close()


@pytest.fixture(scope="module")
def session(browser, tmp_path_factory):
    """One viewer of the PROBOT Anno and one page on it, shared by the tests in order."""
    from armkit.view import Viewer

    viewer = Viewer("probot-anno", port=0)
    page = browser.new_page(viewport={"width": 1100, "height": 700})
    page.set_default_timeout(WAIT_MS)
    page.goto(viewer.url)
    page.wait_for_selector("[data-armkit=pose-matrix]")
    ARTIFACTS.mkdir(parents=True, exist_ok=True)
    yield viewer, page, tmp_path_factory.mktemp("view")
    page.close()
    viewer.close()


def _matrix(page) -> np.ndarray:
    text = page.inner_text("[data-armkit=pose-matrix]")
    return np.array([[float(v) for v in line.split()] for line in text.strip().splitlines()])


def _wait_for_matrix(page, T: np.ndarray) -> np.ndarray:
    """The page's matrix once it shows ``T`` to its six printed decimals."""
    wait_until(lambda: np.abs(_matrix(page) - T).max() <= 1.5e-6, "the page's pose matrix to show the FK")
    return _matrix(page)


def _slider_number_input(page, handle):
    return page.locator(f'[id="{handle._impl.uuid}"]').locator("xpath=following-sibling::div//input")


def _type_joint(page, viewer, j: int, degrees: float) -> None:
    """Type a joint value [deg] into the box beside its slider; wait until the viewer has it."""
    box = _slider_number_input(page, viewer._joints.sliders[j])
    box.fill(str(degrees))
    box.press("Enter")
    box.blur()
    wait_until(lambda: abs(viewer.q[j] - np.radians(degrees)) <= 1e-9, f"joint {j + 1} at {degrees} deg")


def _button(page, handle):
    return page.locator(f'[id="{handle._impl.uuid}"]')


def _distinct_colours(path: Path) -> int:
    """Distinct colours of the 3-D scene (the left 55 % of the page: the panel floats on the right,
    and its text alone would give hundreds of colours on a blank scene)."""
    from PIL import Image

    with Image.open(path) as image:
        scene = image.convert("RGB").crop((0, 0, int(0.55 * image.width), image.height))
        return len(scene.getcolors(maxcolors=1 << 24))


def test_the_page_loads_and_shows_the_fk_of_the_home_configuration(session):
    viewer, page, _ = session
    np.testing.assert_allclose(_matrix(page), viewer.robot.fk(viewer.robot.home), atol=1.5e-6)
    assert page.locator("text=PROBOT Anno").first.is_visible()


def test_typing_a_joint_value_in_the_page_moves_the_arm_to_its_fk(session):
    viewer, page, _ = session
    box = _slider_number_input(page, viewer._joints.sliders[0])
    box.fill("30")
    box.press("Enter")
    expected_q = viewer.robot.home.copy()
    expected_q[0] = np.radians(30)
    shown = _wait_for_matrix(page, viewer.robot.fk(expected_q))
    np.testing.assert_allclose(viewer.q, expected_q, atol=1e-9)
    np.testing.assert_allclose(shown, viewer.robot.fk(expected_q), atol=1.5e-6)


def test_the_slider_thumb_moved_by_keyboard_changes_the_pose_to_the_fk(session):
    viewer, page, _ = session
    thumb = page.locator(f'[id="{viewer._joints.sliders[2]._impl.uuid}"] [role=slider]')
    thumb.focus()
    for _ in range(5):
        thumb.press("ArrowRight")            # 5 steps of 0.1 deg
    wait_until(lambda: abs(np.degrees(viewer.q[2]) - 0.5) <= 1e-9, "joint 3 at 0.5 deg")
    shown = _wait_for_matrix(page, viewer.robot.fk(viewer.q))
    np.testing.assert_allclose(shown, viewer.robot.fk(viewer.q), atol=1.5e-6)


def test_setting_q_from_python_updates_the_page(session):
    viewer, page, _ = session
    q = np.array([0.5, -0.4, 0.3, 0.2, 1.0, -0.6])
    viewer.q = q
    np.testing.assert_allclose(_wait_for_matrix(page, viewer.robot.fk(q)), viewer.robot.fk(q), atol=1.5e-6)
    assert _slider_number_input(page, viewer._joints.sliders[4]).input_value() == f"{np.degrees(1.0):.1f}"


def _pixel(page, client, point: np.ndarray) -> np.ndarray:
    """Where a point [m] of the scene appears on the page: viser's camera is OpenCV-style (z ahead,
    y down), its ``fov`` the vertical field of view [rad]."""
    camera = client.camera
    R = matrix_from_quaternion_wxyz(np.asarray(camera.wxyz))
    p = R.T @ (np.asarray(point) - np.asarray(camera.position))
    size = page.viewport_size
    focal = size["height"] / 2 / np.tan(camera.fov / 2)
    return np.array([size["width"] / 2 + focal * p[0] / p[2], size["height"] / 2 + focal * p[1] / p[2]])


#: A drag on a busy machine can miss the handle (the page's frame lags the pointer): each attempt
#: waits for the target to move, up to DRAG_WAIT_S [s], before it drags again.
DRAG_ATTEMPTS, DRAG_WAIT_S = 5, 60.0


def _drag_handle(page, viewer, client, T0: np.ndarray) -> None:
    """Pull an arrow of the handle 40 px towards the handle's centre, once the page has drawn a
    frame (the pointer hits what the last frame placed): the arrow that looks longest among those
    whose tip is on the scene, left of the panel that floats over the page's right side."""
    page.evaluate("() => new Promise(done => requestAnimationFrame(() => requestAnimationFrame(done)))")
    heading = page.get_by_text(f"{viewer.robot.name}: {viewer.robot.n} joints").first
    panel_left = heading.bounding_box()["x"] - 20                     # [px], the panel's padding off
    centre = _pixel(page, client, T0[:3, 3])
    tips = [_pixel(page, client, T0[:3, 3] + 0.9 * viewer._ik.handle.scale * T0[:3, a]) for a in range(3)]
    free = [tip for tip in tips if 0 < tip[0] < panel_left and 0 < tip[1] < page.viewport_size["height"]]
    grip = max(free, key=lambda px: np.linalg.norm(px - centre))
    direction = (centre - grip) / np.linalg.norm(centre - grip)
    page.mouse.move(*grip)
    page.mouse.down()
    for step in range(1, 11):
        page.mouse.move(*(grip + 4 * step * direction))
    page.mouse.up()


def test_dragging_the_handle_in_the_page_solves_ik_and_the_arm_follows(session):
    viewer, page, _ = session
    viewer.q = [0.5, -0.4, 0.3, 0.2, 1.0, -0.6]
    client = next(iter(viewer._server.get_clients().values()))
    T0 = viewer.target
    # the page has the new pose (the viewer moves its handle first) before the handle is grabbed
    np.testing.assert_allclose(_wait_for_matrix(page, viewer.robot.fk(viewer.q)), T0, atol=1.5e-6)

    def change(T):
        return max(np.linalg.norm(T[:3, 3] - T0[:3, 3]), rotation_angle_between(T, T0))

    for attempt in range(1, DRAG_ATTEMPTS + 1):
        _drag_handle(page, viewer, client, T0)
        try:        # the target moves within a round trip once the handle is caught
            wait_until(lambda: change(viewer.target) > 5e-3, "the dragged handle to move the target",
                       timeout_s=DRAG_WAIT_S)                                   # m or rad
            break
        except pytest.fail.Exception:
            page.screenshot(path=ARTIFACTS / f"view_drag_missed_{attempt}.png", timeout=WAIT_MS)
            if attempt == DRAG_ATTEMPTS:
                raise
    moved = viewer.target
    np.testing.assert_allclose(viewer.robot.fk(viewer.q), moved, atol=1e-9)   # the arm followed
    shown = _wait_for_matrix(page, viewer.robot.fk(viewer.q))
    np.testing.assert_allclose(shown, moved, atol=1.5e-6)
    page.wait_for_function(f"document.querySelectorAll('[data-armkit=solution]').length == "
                           f"{len(viewer.solutions.q)}")


def test_report_000s_first_target_shows_four_in_limit_and_four_out_of_limit_ghosts(session):
    viewer, page, _ = session
    T = transform_from_pose(np.array(published.PROBOT_IK[0][0]), "xyz-fixed")
    found = viewer.show_solutions(T)
    rows = "document.querySelectorAll('[data-armkit=solution][data-within={}]').length"
    page.wait_for_function(f"{rows.format('true')} == 4 && {rows.format('false')} == 4")
    assert sum(g.visible for g in viewer._ik.ghosts) == 8
    # the report's four in-range solutions are the four in-limit ghosts
    inside = found.q[found.within_limits]
    for q_report in published.PROBOT_IK[0][1]:
        assert np.abs(inside - np.array(q_report)).max(axis=1).min() < 1e-4
    shown = _wait_for_matrix(page, T)              # the arm followed: its tool is on the target
    np.testing.assert_allclose(shown, T, atol=1.5e-6)
    shot = ARTIFACTS / "view_ik_ghosts.png"
    notice = page.locator("#webgl-software-rendering button")     # "software WebGL" notice, if shown
    if notice.count() and notice.first.is_visible():
        notice.first.click()
    page.screenshot(path=shot, timeout=WAIT_MS)
    assert _distinct_colours(shot) > 200


def test_picking_a_solution_in_the_page_moves_the_arm_to_it(session):
    viewer, page, _ = session
    found = viewer.solutions
    k = int(np.flatnonzero(found.within_limits)[2])      # the third in-limit solution
    page.locator(f'[id="{viewer._ik.pick._impl.uuid}"]').click()
    page.get_by_role("option", name=f"{k + 1}: in limits").click()
    wait_until(lambda: np.abs(viewer.q - found.q[k]).max() <= 1e-12, f"the arm at solution {k + 1}")
    page.wait_for_selector(f"[data-armkit=solution]:nth-child({k + 1}) >> text=◀ arm")


def test_teach_plan_play_and_save_through_the_page(session):
    viewer, page, folder = session
    _button(page, viewer._teach.teach_button).click()      # W1: the picked solution of the target
    taught_deg = [[20, -10, 30, 0, 45, 0], [-25, 15, 40, 30, 70, 20], [0, 0, 0, 0, 0, 0]]
    for q_deg in taught_deg:                          # W2..W4: typed into the joint boxes
        for j, value in enumerate(q_deg):
            _type_joint(page, viewer, j, value)
        _button(page, viewer._teach.teach_button).click()
    page.wait_for_function("document.querySelectorAll('[data-armkit=waypoint]').length == 4")
    np.testing.assert_allclose(viewer.waypoints[1:], np.radians(taught_deg), atol=1e-12)
    _button(page, viewer._teach.plan_button).click()
    wait_until(lambda: viewer.playback is not None, "the planned trajectory on the timeline")
    playback = viewer.playback
    assert np.all(np.abs(playback.qd).max(axis=0) <= viewer.robot.max_velocity * (1 + 1e-6))
    assert np.all(np.abs(playback.qdd).max(axis=0) <= viewer.robot.max_acceleration * (1 + 1e-3))
    _button(page, viewer._timeline.play_button).click()
    page.wait_for_function("Number(document.querySelector('[data-armkit=time]').innerText) > 0.5")
    _button(page, viewer._timeline.play_button).click()       # pause
    # the click reaches the viewer when it does: until then the player moves the time on, so the
    # time is set only once the viewer has paused (a busy machine delays the click by seconds)
    wait_until(lambda: viewer._timeline.play_button.label == "play", "the viewer to pause")
    assert viewer.time < playback.duration, "the trajectory ended before the pause click arrived"
    # an auto-timed trajectory runs some joint at a limit: at that moment the page names the joint
    ratios = {"velocity": np.abs(playback.qd) / viewer.robot.max_velocity,
              "acceleration": np.abs(playback.qdd) / viewer.robot.max_acceleration}
    kind = max(ratios, key=lambda name: ratios[name].max())
    k, j = np.unravel_index(np.argmax(ratios[kind]), ratios[kind].shape)
    assert ratios[kind][k, j] > 0.999
    viewer.time = float(playback.t[k])
    name = viewer.robot.joint_names[j]
    page.wait_for_selector(f"[data-armkit=at-limit] >> text={name} at its {kind} limit")
    shot = ARTIFACTS / "view_trajectory.png"
    page.screenshot(path=shot, timeout=WAIT_MS)
    assert _distinct_colours(shot) > 200
    target = folder / "taught.csv"
    file_box = page.locator(f"input[value='{viewer._saving.file.value}']").element_handle()
    file_box.fill(str(target))
    file_box.press("Enter")
    _button(page, viewer._saving.button).click()
    page.wait_for_selector("[data-armkit=saved] >> text=saved 4 waypoints")
    np.testing.assert_allclose(read_waypoints(target, 6), viewer.waypoints, atol=0)
    # saving again asks before replacing the file
    before = target.read_text()
    viewer.clear_waypoints()
    viewer.q = [0.1] * 6
    viewer.teach()
    viewer.q = [0.2] * 6
    viewer.teach()
    _button(page, viewer._saving.button).click()
    page.get_by_text("Replace the file?").wait_for()
    assert target.read_text() == before
    page.get_by_role("button", name="replace").click()
    page.wait_for_selector("[data-armkit=saved] >> text=saved 2 waypoints")
    np.testing.assert_allclose(read_waypoints(target, 6), [[0.1] * 6, [0.2] * 6], atol=0)



LONG_NAMES_URDF = """<robot name="long names">
  <link name="base"><visual><geometry><box size="0.2 0.2 0.1"/></geometry></visual></link>
  <link name="upper"><visual><origin xyz="0 0 0.2"/>
    <geometry><cylinder radius="0.04" length="0.4"/></geometry></visual></link>
  <link name="hand"><visual><geometry><sphere radius="0.06"/></geometry></visual></link>
  <joint name="shoulder_pan_joint_of_the_left_arm" type="revolute"><parent link="base"/><child link="upper"/>
    <origin xyz="0 0 0.05"/><axis xyz="0 0 1"/><limit lower="-6.2832" upper="6.2832" velocity="1" effort="1"/>
  </joint>
  <joint name="elbow_joint_of_the_left_arm" type="revolute"><parent link="upper"/><child link="hand"/>
    <origin xyz="0 0 0.4"/><axis xyz="0 1 0"/><limit lower="-3.1416" upper="3.1416" velocity="1" effort="1"/>
  </joint>
</robot>"""


def test_a_urdf_arm_shows_its_shapes_long_joint_names_whole_and_every_digit_in_its_boxes(browser, tmp_path):
    pytest.importorskip("trimesh")
    import armkit
    from armkit.view import Viewer

    path = tmp_path / "long.urdf"
    path.write_text(LONG_NAMES_URDF)
    viewer = Viewer(armkit.load(path), port=0)
    page = browser.new_page(viewport={"width": 1100, "height": 700})
    page.set_default_timeout(WAIT_MS)
    try:
        page.goto(viewer.url)
        page.wait_for_selector("[data-armkit=joint-name]")
        names = page.locator("[data-armkit=joint-name]").all_inner_texts()
        assert names == ["q1: shoulder_pan_joint_of_the_left_arm [deg]",
                         "q2: elbow_joint_of_the_left_arm [deg]"]
        viewer.q = [np.radians(-123.456789), np.radians(-170.14)]
        for j, shown in enumerate(("-123.5", "-170.1")):
            box = _slider_number_input(page, viewer._joints.sliders[j])
            wait_until(lambda box=box, shown=shown: box.input_value() == shown,
                       f"box {j + 1} to show {shown}")
            assert box.evaluate("input => input.scrollWidth <= input.clientWidth"), f"box {j + 1} cuts digits"
        shot = ARTIFACTS / "view_urdf_shapes.png"
        page.screenshot(path=shot, timeout=WAIT_MS)
        assert _distinct_colours(shot) > 200
    finally:
        page.close()
        viewer.close()


def test_a_7_joint_arms_self_motion_ghosts_are_drawn_and_the_pages_slider_moves_the_arm_along_them(browser):
    from armkit.view import Viewer

    viewer = Viewer("panda", port=0, q=[0.3, -0.4, 0.2, -2.0, 0.1, 1.8, 0.6])
    page = browser.new_page(viewport={"width": 1100, "height": 700})
    page.set_default_timeout(WAIT_MS)
    try:
        T = viewer.target
        motion = viewer.show_self_motion(2, samples=17)
        part = viewer._self_motion
        existing = np.flatnonzero(np.isfinite(motion.q[part.branch]).all(axis=-1))
        viewer.move_along_self_motion(motion.values[existing[-1]])
        page.goto(viewer.url)
        page.wait_for_selector(f"[data-armkit=self-motion][data-branches='{len(motion.q)}']")
        box = _slider_number_input(page, part.slider)
        box.fill(f"{np.degrees(motion.values[existing[0]]):.4f}")
        box.press("Enter")
        box.blur()
        wait_until(lambda: np.array_equal(viewer.q, motion.q[part.branch, existing[0]]),
                   "the arm at the branch's first sample")
        assert box.input_value() == f"{np.degrees(motion.values[existing[0]]):.1f}"   # 0.1 deg shown
        np.testing.assert_allclose(_wait_for_matrix(page, viewer.robot.fk(viewer.q)), T, atol=1.5e-6)
        viewer._joints.units.value = "rad"                   # the panel's "angles": the box in rad
        wait_until(lambda: box.input_value() == f"{motion.values[existing[0]]:.3f}", "the box in rad")
        viewer._joints.units.value = "deg"
        shot = ARTIFACTS / "view_self_motion.png"
        notice = page.locator("#webgl-software-rendering button")
        if notice.count() and notice.first.is_visible():
            notice.first.click()
        page.screenshot(path=shot, timeout=WAIT_MS)
        assert _distinct_colours(shot) > 200
    finally:
        page.close()
        viewer.close()
