"""Random argument lists for every command: never a traceback, only exit codes 0, 1 and 2.

Each command gets lists of its own options with random values (numbers of every kind,
robot names and files, good and bad paths), plus stray words, run through ``armkit``'s
entry point inside typer's ``CliRunner`` isolation. A few examples per command in
``make test``; ``make fuzz`` (hypothesis profile ``fuzz``) runs many more.
"""

from __future__ import annotations

import contextlib
import os
import shutil
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

import armkit
from armkit.cli.main import main
from armkit.lab import dynamics as lab_dynamics
from armkit.lab import fk_ik, motion
from armkit.lab.report import Section

EXAMPLE_ARM = str(Path(__file__).parents[1] / "examples" / "data" / "my_arm.toml")
#: Examples per command: few in `make test`, the profile's many under `make fuzz`.
EXAMPLES = {} if os.environ.get("HYPOTHESIS_PROFILE") == "fuzz" else {"max_examples": 12}

ROBOTS = ["probot-anno", "ur5", "stanford", "grb400-scara", "panda", EXAMPLE_ARM, "broken.toml", "nosuch",
          "w.csv", "/proc/x.toml", ""]
NUMBERS = ["0", "-0", "1", "-0.5", "0.3", "2", "90", "-180", "1e308", "-1e308", "1e-300", "nan", "inf",
           "-inf", "1,2,3", "0,0,0,0,0,0", "0.1,-0.2", "abc", "1e5"]
PATHS = ["w.csv", "poses.csv", "t.csv", "t.npz", "out.csv", "out.npz", "fig.png", "fig.svg", "a.urdf",
         "a.xml", "report", "/proc/x.csv", "/proc/x.png", "nosuch/x.csv", "w.csv.txt", "."]
WORDS = ["xyz-fixed", "zyz-euler", "quat", "rpy", "base", "tool", "yes", "--", "-x", "--nosuch"]

#: Options of each command, and what kind of values follow them (an empty kind: a flag).
OPTIONS: dict[str, dict[str, str]] = {
    "fk": {"--deg": "", "--euler": "word", "--strict": "", "--json": ""},
    "jacobian": {"--deg": "", "--frame": "word", "--strict": "", "--json": ""},
    "ik": {"--pose": "numbers", "--matrix": "numbers", "--position": "numbers", "--euler": "word",
           "--deg": "", "--all": "", "--outside": "", "--near": "numbers", "--json": ""},
    "traj": {"--waypoints": "path", "--poses": "", "--euler": "word", "--durations": "numbers",
             "--times": "numbers", "--auto-time": "", "--rate": "number", "--out": "path", "--plot": "path",
             "--plot-path": "path", "--force": "", "--deg": "", "--json": "", "--torques": "",
             "--estimate-inertia": "number"},
    "move": {"--from": "numbers", "--by": "numbers", "--duration": "number", "--frame": "word",
             "--dt": "number", "--deg": "", "--json": ""},
    "rotate": {"--from": "numbers", "--axis": "numbers", "--angle": "number", "--rate": "number",
               "--duration": "number", "--frame": "word", "--dt": "number", "--deg": "", "--json": ""},
    "show": {"--json": ""},
    "robots": {"--json": ""},
    "export": {"--urdf": "path", "--mjcf": "path", "--no-gravity": "", "--force": "", "--json": ""},
    "sim": {"--random": "count", "--seed": "count", "--trajectory": "path", "--no-gravity": "",
            "--no-compensation": "", "--euler": "word", "--deg": "", "--force": "", "--json": ""},
    "lab": {"--robot": "robot", "--out": "path", "--quick": "", "--force": "", "--json": ""},
    "dynamics": {"--qd": "number", "--qdd": "number", "--deg": "", "--payload": "number",
                 "--estimate-inertia": "number", "--json": ""},
    "plan": {"--scene": "scene", "--from": "numbers", "--to": "numbers", "--to-pose": "numbers", "--deg": "",
             "--seed": "count", "--time-budget": "number", "--resolution": "number", "--rate": "number",
             "--out": "path", "--plot": "path", "--force": "", "--json": ""},
}
#: Commands whose first argument is a robot.
WITH_ROBOT = {"fk", "jacobian", "ik", "traj", "move", "rotate", "show", "export", "sim", "dynamics", "plan"}

number = st.one_of(st.sampled_from(NUMBERS), st.floats(allow_nan=True, allow_infinity=True).map(repr),
                   st.integers(-10**6, 10**6).map(str))
word = st.one_of(st.sampled_from(WORDS), st.text(max_size=6))
VALUES = {
    "": st.just([]),
    "number": number.map(lambda v: [v]),
    "numbers": st.lists(number, min_size=0, max_size=17),
    "word": word.map(lambda v: [v]),
    "path": st.sampled_from(PATHS).map(lambda v: [v]),
    "robot": st.sampled_from(ROBOTS).map(lambda v: [v]),
    "count": st.integers(-2, 3).map(lambda v: [str(v)]),  # small: each configuration is simulated
    "scene": st.sampled_from(["wall.toml", "broken.toml", "w.csv", "nosuch.toml"]).map(lambda v: [v]),
}


@st.composite
def arguments(draw, command: str) -> list[str]:
    argv = [command]
    if command in WITH_ROBOT and draw(st.integers(0, 9)) > 0:
        argv.append(draw(st.sampled_from(ROBOTS)))
    options = OPTIONS[command]
    for _ in range(draw(st.integers(0, 6))):
        if draw(st.integers(0, 9)) == 0:  # a stray word or number
            argv.append(draw(st.one_of(number, word)))
            continue
        name = draw(st.sampled_from(sorted(options)))
        argv += [name, *draw(VALUES[options[name]])]
    return argv


@pytest.fixture(scope="module")
def workdir(tmp_path_factory):
    """A folder with the files the arguments name: waypoints, poses, a trajectory, a broken robot."""
    folder = tmp_path_factory.mktemp("fuzz")
    robot = armkit.load("probot-anno")
    q = robot.random_q(3, rng=np.random.default_rng(0))
    np.savetxt(folder / "w.csv", q, delimiter=",")
    np.savetxt(folder / "poses.csv", robot.pose(q), delimiter=",")
    trajectory = armkit.plan_trajectory(robot, q, [1.0, 1.0])
    trajectory.to_csv(folder / "t.csv")
    (folder / "broken.toml").write_text('convention = "standard"\n[[joints]]\nd = [1\n')
    shutil.copy(Path(__file__).parents[1] / "examples" / "data" / "ur5_wall.toml", folder / "wall.toml")
    return folder


@pytest.fixture(scope="module")
def instant_lab():
    """``armkit lab`` with its experiments replaced by instant ones: the fuzz is about its arguments."""
    def experiment(ctx):
        return Section("fake", "fake experiment", "", headline="done")
    names = [(fk_ik, "fk_check"), (fk_ik, "ik_check"), (motion, "linear_motion"),
             (motion, "trajectory_experiment"), (motion, "fixed_point_rotation"),
             (fk_ik, "fk_table_zju"), (fk_ik, "fk_table_scara"),
             (lab_dynamics, "dynamics_experiment")]
    saved = [(module, name, getattr(module, name)) for module, name in names]
    for module, name in names:
        setattr(module, name, experiment)
    yield
    for module, name, original in saved:
        setattr(module, name, original)


def _run(folder: Path, argv: list[str]) -> tuple[int, str]:
    runner = CliRunner()
    with contextlib.chdir(folder), runner.isolation() as streams:
        code = main(argv)
        output = b"".join(stream.getvalue() for stream in streams if stream is not None)
    return code, output.decode(errors="replace")


@pytest.mark.parametrize("command", sorted(OPTIONS))
def test_random_arguments_never_give_a_traceback(command, workdir, instant_lab):
    @settings(deadline=None, suppress_health_check=[HealthCheck.too_slow], **EXAMPLES)
    @given(argv=arguments(command))
    def check(argv):
        code, output = _run(workdir, argv)
        assert code in (0, 1, 2), (argv, code, output[-2000:])
        assert "Traceback" not in output, (argv, output[-2000:])

    check()
