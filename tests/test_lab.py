"""``armkit lab``: the report has every table, plot and animation it promises; folder safety."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

import armkit
from armkit.animation import animate_trajectory
from armkit.cli.main import main
from armkit.errors import InputError
from armkit.lab import motion, run_lab
from armkit.lab import published as seeds
from armkit.lab.context import LabContext
from armkit.lab.motion import rotation_axes
from armkit.lab.report import _CSS, MARKER, Table, _table_html, prepare_folder
from armkit.spatial.transforms import transform_from_pose
from armkit.trajectory import read_trajectory, read_waypoints

#: The seed reports' experiments end to end, MuJoCo included: not in `make test-fast`.
pytestmark = pytest.mark.slow

PNGS = ["fk_configuration.png", "ik_solutions.png", "line_tracking.png", "trajectory_pva.png",
        "trajectory_tracking.png", "rotation.png", "zju_configuration.png", "scara_configuration.png",
        "dynamics_torques.png", "plan_pva.png"]
EXAMPLE_ARM = Path(__file__).parents[1] / "examples" / "data" / "my_arm.toml"
GIFS = ["ik_solutions.gif", "line.gif", "trajectory.gif", "rotation.gif", "plan.gif"]
DATA = [motion.TRAJECTORY_FILE, motion.WAYPOINTS_FILE]


@pytest.fixture(scope="module")
def seed_report(tmp_path_factory):
    folder = tmp_path_factory.mktemp("lab") / "armkit-report"
    return run_lab(None, folder, quick=True, progress=False)


def test_every_seed_experiment_is_reproduced(seed_report):
    keys = [s.key for s in seed_report.sections]
    assert keys == ["fk", "ik", "line", "trajectory", "rotation", "dynamics", "plan", "zju", "scara", "floor",
                    "dh"]
    problems = [(s.key, s.notes) for s in seed_report.sections if s.status != "ok"]
    assert not problems
    ik = next(s for s in seed_report.sections if s.key == "ik")
    assert ik.headline.startswith("4 + 4 + 4 solutions")
    # report 000 prints four in-limit solutions of target 3 though its text says three
    assert ik.published.startswith("lists 4 + 4 + 4 in-limit solutions (its text says 4 + 4 + 3)")
    assert all(s.badge is False or s.status == "ok" for s in seed_report.sections)
    assert len(next(s for s in seed_report.sections if s.key == "dh").tables) == 3


def test_images_exist_decode_and_are_embedded(seed_report):
    folder = seed_report.index.parent
    for name in PNGS:
        with Image.open(folder / name) as image:
            assert image.format == "PNG" and min(image.size) > 100
    for name in GIFS:
        with Image.open(folder / name) as image:
            assert image.format == "GIF" and image.n_frames >= 4
    page = seed_report.index.read_text()
    assert page.count("data:image/png;base64,") == len(PNGS)
    assert page.count("data:image/gif;base64,") == len(GIFS)
    assert 'src="' not in page.replace('src="data:', "")  # self-contained: no external files


def test_report_tables_show_published_computed_and_simulated_values(seed_report):
    page = seed_report.index.read_text()
    for title in ("Tool pose: published, computed by armkit, simulated in MuJoCo", "Target 3:",
                  "Waypoints: target pose", "Peaks against the joint limits", "Target: the tool along d",
                  "Rotation about", "ZJU-I tool pose", "SCARA tool coordinates", "PROBOT Anno: modified DH"):
        assert title in page
    for published in ("0.150035", "0.199922", "-148.05", "36.31", "141.4214", "370.1666", "0.303826"):
        assert published in page
    assert page.count(">reproduced<") == 2 * 8  # badges and summary
    # the planned motion's and the collision check's (no seed report planned motions or checked collisions)
    assert page.count(">checked<") == 2 * 2
    assert "its text says &quot;3 solutions in range&quot; but it prints 4" in page
    fk_errors = re.findall(r"max \|MuJoCo - armkit\| ([0-9.e+-]+) m", page)
    assert fk_errors and float(fk_errors[0]) < 1e-9


def test_marker_lists_what_was_written(seed_report):
    folder = seed_report.index.parent
    manifest = json.loads((folder / MARKER).read_text())
    assert sorted(manifest["files"]) == sorted([*PNGS, *GIFS, *DATA, "index.html"])


def test_the_trajectory_and_its_waypoints_are_saved_for_the_viewer(seed_report):
    folder = seed_report.index.parent
    robot = armkit.load("probot-anno")
    t, q, qd = read_trajectory(folder / motion.TRAJECTORY_FILE, robot)
    waypoints = read_waypoints(folder / motion.WAYPOINTS_FILE, robot.n)
    T_goal = transform_from_pose(np.array(seeds.PROBOT_WAYPOINT_POSES))       # the report's poses
    np.testing.assert_allclose(robot.fk(waypoints), T_goal, atol=1e-9)
    np.testing.assert_allclose(q[[0, -1]], waypoints[[0, -1]], atol=1e-12)
    assert np.all(np.abs(qd) <= robot.max_velocity * (1 + 1e-9)) and t[-1] > 0
    assert "armkit lab --view" in seed_report.index.read_text()


def test_rerun_replaces_its_own_report_and_keeps_other_files(tmp_path):
    folder = tmp_path / "report"
    folder.mkdir()
    (folder / "old.png").write_bytes(b"x")
    (folder / "mine.txt").write_text("user notes")
    (folder / MARKER).write_text(json.dumps({"files": ["old.png", "index.html", "../escape.txt"]}))
    (tmp_path / "escape.txt").write_text("outside")
    prepare_folder(folder, force=False)
    assert not (folder / "old.png").exists() and not (folder / MARKER).exists()
    assert (folder / "mine.txt").read_text() == "user notes"
    assert (tmp_path / "escape.txt").exists()


def test_refuses_a_folder_that_is_not_a_report(tmp_path, capsys):
    folder = tmp_path / "thesis"
    folder.mkdir()
    (folder / "chapter1.tex").write_text("...")
    with pytest.raises(InputError, match="not an armkit report"):
        prepare_folder(folder, force=False)
    assert main(["lab", "--quick", "--out", str(folder)]) == 1
    assert "not an armkit report" in capsys.readouterr().err
    assert sorted(p.name for p in folder.iterdir()) == ["chapter1.tex"]
    prepare_folder(folder, force=True)
    with pytest.raises(InputError, match="is a file"):
        prepare_folder(folder / "chapter1.tex", force=True)


def test_lab_on_a_users_robot_file(tmp_path, capsys):
    robot_file = tmp_path / "my_arm.toml"
    robot_file.write_text(armkit.robot_to_toml(armkit.load("puma560")))
    out = tmp_path / "out"
    assert main(["lab", "--quick", "--robot", str(robot_file), "--out", str(out)]) == 0
    assert "report:" in capsys.readouterr().out
    page = (out / "index.html").read_text()
    assert "armkit lab: PUMA 560 in MuJoCo" in page
    assert "ZJU-I" not in page and page.count("data:image/gif;base64,") == 5
    assert re.search(r"(\d+) \+ (\d+) \+ (\d+) solutions", page)
    text = re.sub(r"<[^>]+>", " ", re.sub(r'src="data:[^"]+"', "", page))
    for seed_only in ("report", "Gazebo", "reproduced", "pi/2", "printed", "twist"):
        assert seed_only not in text, seed_only  # no empty published columns, no sentences about report 000
    assert page.count(">checked<") >= 2 * 3
    moved = re.search(r"The axis is ([^,]+).*?Joints that moved [^:]*: [^(]*\((\d) of 6\)", text)
    assert moved and int(moved.group(2)) >= 3, "the rotation must exercise more than the last joint"
    target = re.search(r"Target: the tool along d = \[([^\]]+)\] m", text)
    computed = re.search(r"armkit \(computed\)\s+\[[^\]]+\]\s+\[[^\]]+\]\s+\[([^\]]+)\]", text)
    assert target and computed  # the title's displacement is the one the computed run made
    np.testing.assert_allclose(np.array(computed.group(1).split(", "), dtype=float),
                               np.array(target.group(1).split(", "), dtype=float), atol=1e-3)


def test_lab_on_the_readme_3r_arm_says_not_applicable_once_and_exits_0(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["lab", "--quick", "--robot", str(EXAMPLE_ARM), "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert printed.count("Not applicable, because") == 2 and "failed" not in printed
    page = (out / "index.html").read_text()
    text = re.sub(r"<[^>]+>", " ", re.sub(r'src="data:[^"]+"', "", page))
    assert text.count("Not applicable, because") == 2 and "failed" not in text


def test_rotation_axes_of_a_users_arm_are_not_the_last_joint_axis():
    robot = armkit.load("puma560")
    q = robot.random_q(rng=np.random.default_rng(3))
    last = robot.jacobian(q)[3:, -1]
    axes = [axis for axis, _ in rotation_axes(robot, q)]
    assert len(axes) >= 4 and np.allclose([a @ a for a in axes], 1.0)
    assert max(abs(a @ last) for a in axes) < np.cos(np.radians(25.0))
    assert np.allclose(axes[0], [1, 0, 0]) or abs(last[0]) > np.cos(np.radians(25.0))


def test_lab_refuses_a_robot_that_cannot_be_simulated(tmp_path, capsys):
    robot_file = tmp_path / "point.toml"
    robot_file.write_text('convention = "modified"\nlength_unit = "m"\nangle_unit = "rad"\n'
                          '[[joints]]\nalpha = 0\na = 0\nd = 0\ntheta = 0\n')
    out = tmp_path / "out"
    assert main(["lab", "--quick", "--robot", str(robot_file), "--out", str(out)]) == 1
    assert "cannot be simulated" in capsys.readouterr().err
    assert not out.exists()


def test_a_three_joint_arm_is_told_once_why_line_and_rotation_do_not_apply(tmp_path):
    ctx = LabContext(robot=armkit.load(EXAMPLE_ARM), folder=tmp_path, quick=True, seeds=False)
    line, rotation = motion.linear_motion(ctx), motion.fixed_point_rotation(ctx)
    assert line.status == rotation.status == "n/a" and not line.tables and not rotation.tables
    for section in (line, rotation):
        assert len(section.notes) == 1 and section.notes[0].startswith("Not applicable, because ")
    assert "cannot move its tool point without turning the tool" in line.notes[0]
    assert "cannot turn its tool about any of the axes tried" in rotation.notes[0]


def test_twist_possible_follows_the_jacobian_range():
    puma, arm = armkit.load("puma560"), armkit.load(EXAMPLE_ARM)
    q = motion.ready_configuration(puma, np.random.default_rng(0))
    assert motion.twist_possible(puma, q, np.array([0.1, 0, 0, 0, 0, 0]))
    q3 = motion.ready_configuration(arm, np.random.default_rng(0))
    J = arm.jacobian(q3)
    assert motion.twist_possible(arm, q3, J @ np.array([0.2, -0.1, 0.3]))   # any joint motion's twist
    assert not motion.twist_possible(arm, q3, np.array([0, 0, 0, 1.0, 0, 0]))


def _fake_experiments(monkeypatch, failing: str | None = None, interrupt: str | None = None):
    """Replace the seven experiments by instant ones (``failing`` fails, ``interrupt`` raises Ctrl-C)."""
    from armkit.lab import dynamics, fk_ik, planning
    from armkit.lab.report import Section

    for module, name in ((fk_ik, "fk_check"), (fk_ik, "ik_check"), (motion, "linear_motion"),
                         (motion, "trajectory_experiment"), (motion, "fixed_point_rotation"),
                         (dynamics, "dynamics_experiment"), (planning, "planned_motion")):
        def experiment(ctx, name=name):
            if name == interrupt:
                raise KeyboardInterrupt
            picture = ctx.path(f"{name}.png")
            picture.write_bytes(b"new")
            section = Section(name, name, "", headline=f"{name} done")
            if name == failing:
                section.status = "failed"
                section.notes.append(f"{name} missed its target")
            return section
        monkeypatch.setattr(module, name, experiment)


def test_a_failed_experiment_makes_the_run_exit_1(tmp_path, capsys, monkeypatch):
    _fake_experiments(monkeypatch, failing="linear_motion")
    out = tmp_path / "report"
    assert main(["lab", "--robot", "puma560", "--out", str(out)]) == 1
    printed = capsys.readouterr().out
    assert printed.count("linear_motion missed its target") == 1 and "failed" in printed
    assert (out / "index.html").is_file()
    _fake_experiments(monkeypatch)
    assert main(["lab", "--robot", "puma560", "--out", str(out), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    # the fake experiments run no motion: nothing for the collision check ("n/a"), before the DH tables
    assert data["failed"] == 0 and [s["status"] for s in data["sections"]] == ["ok"] * 7 + ["n/a", "ok"]


def test_an_interrupted_run_leaves_the_previous_report_whole(tmp_path, capsys, monkeypatch):
    _fake_experiments(monkeypatch)
    out = tmp_path / "report"
    assert main(["lab", "--robot", "puma560", "--out", str(out)]) == 0
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    _fake_experiments(monkeypatch, interrupt="trajectory_experiment")
    capsys.readouterr()
    assert main(["lab", "--robot", "puma560", "--out", str(out)]) == 130
    assert capsys.readouterr().err.strip() == "interrupted (Ctrl-C)"
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["report"]  # no staging folder left


def test_a_new_report_replaces_the_old_files_and_keeps_the_users(tmp_path, monkeypatch):
    folder = tmp_path / "report"
    folder.mkdir()
    (folder / "old.png").write_bytes(b"x")
    (folder / "mine.txt").write_text("user notes")
    (folder / MARKER).write_text(json.dumps({"files": ["old.png", "index.html"]}))
    _fake_experiments(monkeypatch)
    run_lab("puma560", folder, quick=True, progress=False)
    names = sorted(p.name for p in folder.iterdir())
    assert "old.png" not in names and "mine.txt" in names and "linear_motion.png" in names
    assert (folder / "linear_motion.png").read_bytes() == b"new"
    assert sorted(json.loads((folder / MARKER).read_text())["files"]) == sorted(
        n for n in names if n not in ("mine.txt", MARKER))


def test_tables_drop_empty_columns_and_wide_ones_fit_the_page():
    columns = ["q", "report: computed", *[f"value {k}" for k in range(7)]]
    html = _table_html(Table("t", columns, [["[0, 1]", "", *["1.0"] * 7], ["[1, 0]", "", *["2.0"] * 7]]))
    assert "report: computed" not in html and html.count("<th>") == 8 and html.count("<td>") == 16
    assert html.startswith('<div class="table wide">')  # smaller font, wrapping cells (see _CSS)
    assert ".wide td{white-space:normal}" in _CSS and "th{white-space:normal" in _CSS
    narrow = _table_html(Table("t", ["a", "b"], [["1", "2"]]))
    assert narrow.startswith('<div class="table">')


def test_full_run_animations_are_480_px(tmp_path):
    robot = armkit.load("grb400-scara")
    ctx = LabContext(robot=robot, folder=tmp_path, quick=False, seeds=False)
    q = np.linspace(np.zeros(4), [0.5, 0.5, 0.05, 1.0], 20)
    gif = animate_trajectory(robot, q, tmp_path / "a.gif", frames=3, dpi=ctx.gif_dpi)
    with Image.open(gif) as image:
        assert image.size == (480, 480) and image.n_frames == 3
    assert LabContext(robot=robot, folder=tmp_path, quick=True, seeds=False).gif_dpi < ctx.gif_dpi


def test_lab_view_opens_the_viewer_with_the_trajectory_and_its_waypoints(seed_report, monkeypatch):
    pytest.importorskip("viser")
    import armkit.cli.view
    from armkit.cli.lab import _view

    served = []
    monkeypatch.setattr(armkit.cli.view, "serve", lambda viewer, open_browser: served.append(viewer))
    _view("probot-anno", seed_report.index.parent, 0, open_browser=False)
    viewer = served[0]
    try:
        waypoints = read_waypoints(seed_report.index.parent / motion.WAYPOINTS_FILE, viewer.robot.n)
        np.testing.assert_array_equal(viewer.waypoints, waypoints)
        assert viewer.playback.source == motion.TRAJECTORY_FILE
        t, q, _ = read_trajectory(seed_report.index.parent / motion.TRAJECTORY_FILE, viewer.robot)
        np.testing.assert_array_equal(viewer.playback.q, q)
        assert viewer.playback.duration == t[-1] > 0
    finally:
        viewer.close()


def test_the_dynamics_experiment_finds_armkit_and_mujoco_agree(seed_report):
    section = next(s for s in seed_report.sections if s.key == "dynamics")
    assert section.status == "ok", section.notes
    assert (seed_report.index.parent / "dynamics_torques.png").is_file()
    assert "armkit = MuJoCo to" in section.headline
    assert [row[0] for row in section.tables[0].rows] == armkit.load("probot-anno").joint_names
    assert section.tables[1].columns[2] == "computed-torque feedforward (armkit's)"


def test_a_users_arm_is_timed_to_its_own_limits_and_its_peak_table_has_units(tmp_path):
    robot = armkit.load("ur5")
    ctx = LabContext(robot=robot, folder=tmp_path, quick=True, seeds=False)
    q, poses, report_q, durations = motion.experiment_waypoints(ctx)
    assert durations is None                           # timed by plan_trajectory to the limits
    section = motion.trajectory_experiment(ctx)
    assert any(note.startswith("Timed to the arm's own limits") for note in section.notes)
    table = next(t for t in section.tables if t.title.startswith("Peaks against the joint limits"))
    peaks = np.array([float(row[1].split()[0]) for row in table.rows])
    assert np.isclose(peaks / robot.max_velocity, 1.0, atol=1e-6).any()   # some joint at its limit
    assert all(row[1].endswith(" rad/s") and row[3].endswith(" rad/s²") and row[5].endswith(" rad")
               for row in table.rows)


def test_the_planned_motion_goes_around_a_box_the_straight_motion_hits(tmp_path):
    from armkit.lab import planning

    ctx = LabContext(armkit.load("puma560"), tmp_path, quick=True, seeds=False)
    q, *_ = motion.experiment_waypoints(ctx)
    goal, (scene, grown) = next((goal, found) for goal, _ in planning._goals(ctx, q[0], q[-1])
                                if (found := planning._obstacle(ctx, q[0], goal)) is not None)
    assert scene.path_collides(q[0], goal) and not grown.collides(np.array([q[0], goal])).any()
    assert np.allclose(np.array(grown.obstacles[0].size) - scene.obstacles[0].size, 2 * planning.MARGIN)
    section = planning.planned_motion(ctx)
    assert section.status == "ok", section.notes
    assert "free of collisions" in section.tables[1].note and section.headline.startswith("around a ")


def test_a_panda_whose_tool_stays_near_axis_1_gets_a_far_goal_with_a_blocking_box(tmp_path):
    from armkit.lab import planning

    ctx = LabContext(armkit.load("panda"), tmp_path, quick=True, seeds=False)
    q, *_ = motion.experiment_waypoints(ctx)
    found = [(what, scenes) for goal, what in planning._goals(ctx, q[0], q[-1])
             if (scenes := planning._obstacle(ctx, q[0], goal)) is not None]
    assert found and found[0][0].startswith("of 64 random configurations"), [what for what, _ in found]


def test_without_ompl_the_planned_motion_is_not_applicable_and_says_what_to_install(tmp_path, monkeypatch):
    import importlib.util

    from armkit.lab import planning

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec",
                        lambda name, *args: None if name == "ompl" else real(name, *args))
    ctx = LabContext(armkit.load("puma560"), tmp_path, quick=True, seeds=False)
    section = planning.planned_motion(ctx)
    assert section.status == "n/a" and "pip install 'armkit[plan]'" in section.notes[0]
