"""Workspace runs are bounded and say so: the memory a run needs is estimated from its arguments
and a run that does not fit is refused naming the option; bad counts and thresholds are refused;
one run at a time writes a store; ``--resume`` needs a store to continue."""

from __future__ import annotations

import importlib
import re

import pytest

import armkit
from armkit import workspace
from armkit.cli.main import main
from armkit.errors import InputError
from armkit.workspace.budget import MemoryEstimate, estimate_memory
from armkit.workspace.grid import Grid
from armkit.workspace.store import store_lock

pytest.importorskip("zarr")
budget = importlib.import_module("armkit.workspace.budget")

GIB = 2**30


@pytest.fixture
def four_gib(monkeypatch):
    """A machine with 4 GiB free, whatever this one has (the refusals do not depend on the test box)."""
    monkeypatch.setattr(budget, "available_memory", lambda: 4 * GIB)


def run(capsys, *argv):
    code = main(["workspace", *map(str, argv)])
    _, err = capsys.readouterr()
    return code, err


@pytest.mark.parametrize(("args", "message"), [
    (["--resolution", "1e-3"], r"resolution 0.001 m \(--resolution\): the run needs about 184 GiB "
                               r"\(1.06e\+09 voxels\), more than the 4 GiB of memory free; choose 0.0037 m "
                               r"or coarser"),
    (["--orientations", "1000000000", "--ik-solves", "1e15"],     # (fewer solves: too few positions, skipped)
     r"orientations 1000000000 \(--orientations\): the run needs about "
                                       r"4.77e\+05 GiB for the dexterity map's tasks, more than the 4 GiB of "
                                       r"memory free; choose \d+ or fewer"),
    (["--chunk-size", str(2**40)], r"chunk_size 1099511627776 \(--chunk-size\): the run needs about "
                                   r"3.93e\+05 GiB for the chunks, more than the 4 GiB of memory free"),
])
def test_a_run_that_does_not_fit_in_memory_is_refused_naming_the_option(capsys, four_gib, args, message):
    code, err = run(capsys, "probot-anno", "--threads", "2", *args)
    assert code == 1 and len(err.strip().splitlines()) == 1, err
    assert re.search(message, " ".join(err.split())), err


def test_the_suggested_value_fits(four_gib):
    robot = armkit.load("probot-anno")
    grid = workspace.grid_for(robot, 0.0037)
    needed = estimate_memory(grid, samples=10**6, chunk_size=2**18, manipulability_samples=200_000,
                             orientations=100, threads=2)
    assert needed.total <= 4 * GIB
    coarser = workspace.grid_for(robot, 0.0036)
    assert estimate_memory(coarser, samples=10**6, chunk_size=2**18, manipulability_samples=200_000,
                           orientations=100, threads=2).total > 4 * GIB


def test_the_estimate_grows_with_voxels_threads_orientations_and_chunks():
    grid = Grid((-0.5, -0.5, -0.5), 0.01, (100, 100, 100))
    base = estimate_memory(grid, samples=10**6, chunk_size=2**18, threads=1)
    assert base == MemoryEstimate(10**6 * (24 + 24), 4 * 128, 0)
    assert estimate_memory(grid, samples=10**6, chunk_size=2**18, threads=2).maps == 10**6 * (24 + 2 * 24)
    with_maps = estimate_memory(grid, samples=10**6, chunk_size=2**18, threads=1, manipulability_samples=1,
                                orientations=10)
    assert with_maps.maps == 10**6 * (24 + 88 + 27 + 24)
    assert with_maps.orientations == 10 * (250 * 1024 + 256)
    assert with_maps.samples == 2**16 * 768 + 5 * 128


def test_a_run_that_fits_is_not_refused(tmp_path, four_gib):
    maps = workspace.compute(armkit.load("puma560"), resolution=0.2, samples=4000, chunk_size=1000,
                             manipulability_samples=1000, orientations=4, out=tmp_path / "m.zarr")
    assert maps.reachability.samples == 4000


@pytest.mark.parametrize(("args", "message"), [
    (["--samples", "1e30"], "--samples: expected a whole number from 1 to 9.007e+15, got '1e30'"),
    (["--samples", "0"], "--samples: expected a whole number from 1 to 9.007e+15, got '0'"),
    (["--threads", "0"], "--threads: expected None (every core) or a whole number of threads from 1"),
    (["--samples", "-5"], "--samples: expected a whole number from 1 to 9.007e+15, got '-5'"),
    (["--manipulability-samples", "1e300"], "--manipulability-samples: expected a whole number from 0 to"),
    (["--singular-threshold", "nan"], "singular_threshold: expected a finite number > 0, got nan"),
    (["--singular-threshold", "-1"], "singular_threshold: expected a finite number > 0, got -1.0"),
    (["--singular-threshold", "0"], "singular_threshold: expected a finite number > 0, got 0.0"),
])
def test_bad_counts_and_thresholds_are_one_line(capsys, args, message):
    code, err = run(capsys, "puma560", "--resolution", "0.2", "--samples", "100", "--quiet", *args)
    assert code == 1 and message in err and "Traceback" not in err, err


def test_a_store_another_run_is_writing_is_refused(tmp_path, capsys):
    out = tmp_path / "m.zarr"
    args = ["puma560", "--resolution", "0.2", "--samples", "2000", "--chunk-size", "1000",
            "--manipulability-samples", "0", "--orientations", "0", "--out", out, "--quiet"]
    assert run(capsys, *args)[0] == 0
    before = workspace.open(out).reachability.hits.copy()
    with store_lock(out):  # the other run
        for extra in (["--force"], ["--resume"]):
            code, err = run(capsys, *args, *extra)
            assert code == 1 and f"'{out}' is being written by another run; wait for it to end" in err, err
    assert (workspace.open(out).reachability.hits == before).all()
    assert run(capsys, *args, "--force")[0] == 0  # free again once the other run ended


def test_resume_of_a_store_that_does_not_exist_is_refused(tmp_path, capsys):
    code, err = run(capsys, "puma560", "--resolution", "0.2", "--samples", "100", "--quiet",
                    "--out", tmp_path / "none.zarr", "--resume")
    assert code == 1 and "cannot resume" in err and "there is no store there; run without --resume" in err
    assert not (tmp_path / "none.zarr").exists()
    with pytest.raises(InputError, match="there is no store there"):
        workspace.ik_dataset(armkit.load("ur5"), 10, tmp_path / "ik.zarr", resume=True)
