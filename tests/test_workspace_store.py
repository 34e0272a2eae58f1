"""The Zarr store: round trip through armkit.workspace.open, refusal to overwrite, Ctrl-C and resume."""

from __future__ import annotations

import importlib
import json

import numpy as np
import pytest

import armkit
from armkit import workspace
from armkit.cli.main import main
from armkit.errors import InputError
from armkit.lab.report import MARKER
from armkit.workspace.maps import store_meta
from armkit.workspace.store import create_store

zarr = pytest.importorskip("zarr")
#: The module (the package attribute of the same name is the function).
reachability_module = importlib.import_module("armkit.workspace.reachability")

SMALL = {"resolution": 0.08, "samples": 20_000, "chunk_size": 4_000, "manipulability_samples": 4_000,
         "orientations": 6}


@pytest.fixture(scope="module")
def puma():
    return armkit.load("puma560")


def test_open_gives_back_every_map_and_the_robot(tmp_path, puma):
    made = workspace.compute(puma, out=tmp_path / "m.zarr", **SMALL)
    back = workspace.open(tmp_path / "m.zarr")
    np.testing.assert_array_equal(back.reachability.hits, made.reachability.hits)
    np.testing.assert_array_equal(back.dexterity.reachable_fraction, made.dexterity.reachable_fraction)
    np.testing.assert_array_equal(back.manipulability.mean_manipulability,
                                  made.manipulability.mean_manipulability)
    assert back.grid == made.grid
    np.testing.assert_allclose(back.robot.fk(np.full(6, 0.3)), puma.fk(np.full(6, 0.3)), atol=1e-12)
    assert back.summary()["reachable_volume"] == made.summary()["reachable_volume"]
    group = zarr.open_group(tmp_path / "m.zarr", mode="r")
    assert group.attrs["armkit"]["units"]["x"] == "m"
    np.testing.assert_allclose(group["x"][...], made.grid.axes[0])
    assert "[[joints]]" in group.attrs["armkit"]["robot_toml"]


def test_an_existing_store_is_not_replaced_without_force(tmp_path, puma):
    workspace.compute(puma, out=tmp_path / "m.zarr", **SMALL)
    with pytest.raises(InputError, match="exists; pass --force"):
        workspace.compute(puma, out=tmp_path / "m.zarr", **SMALL)
    (tmp_path / "notes").mkdir()
    (tmp_path / "notes" / "mine.txt").write_text("keep me")
    with pytest.raises(InputError, match="is not a Zarr store; refusing"):
        workspace.compute(puma, out=tmp_path / "notes", overwrite=True, **SMALL)
    assert (tmp_path / "notes" / "mine.txt").read_text() == "keep me"


def test_ctrl_c_keeps_the_chunks_done_and_resume_gives_the_uninterrupted_counts(tmp_path, puma, monkeypatch):
    grid = workspace.grid_for(puma, 0.08)
    whole = workspace.reachability(puma, grid=grid, samples=40_000, chunk_size=4_000, engine=2)
    store = create_store(tmp_path / "r.zarr", store_meta("maps", puma, grid))
    real_add, calls = reachability_module._Hits.add, []

    def add_then_interrupt(self, result):
        if len(calls) == 3:
            raise KeyboardInterrupt
        calls.append(1)
        real_add(self, result)

    monkeypatch.setattr(reachability_module._Hits, "add", add_then_interrupt)
    with pytest.raises(workspace.InterruptedRun,
                       match="interrupted after 3 of 10 chunks of reachability; the store keeps them"):
        workspace.reachability(puma, grid=grid, samples=40_000, chunk_size=4_000, engine=2, store=store)
    monkeypatch.setattr(reachability_module._Hits, "add", real_add)
    saved = store["reachability"].attrs
    assert saved["chunks_done"] == 3 and saved["writing"] is False
    assert int(store["reachability"]["hits"][...].sum()) == 12_000
    resumed = workspace.reachability(puma, grid=grid, samples=40_000, chunk_size=4_000, engine=1,
                                     store=create_store(tmp_path / "r.zarr", store_meta("maps", puma, grid),
                                                        resume=True), resume=True)
    np.testing.assert_array_equal(resumed.hits, whole.hits)


def test_resume_refuses_other_settings_and_half_written_groups(tmp_path, puma):
    workspace.compute(puma, out=tmp_path / "m.zarr", **SMALL)
    with pytest.raises(InputError, match="samples 20000 there, 30000 now"):
        workspace.compute(puma, out=tmp_path / "m.zarr", resume=True, **(SMALL | {"samples": 30_000}))
    with pytest.raises(InputError, match="made for another grid"):
        workspace.compute(puma, out=tmp_path / "m.zarr", resume=True, **(SMALL | {"resolution": 0.1}))
    zarr.open_group(tmp_path / "m.zarr", mode="r+")["reachability"].attrs["writing"] = True
    with pytest.raises(InputError, match="cut off while being written"):
        workspace.compute(puma, out=tmp_path / "m.zarr", resume=True, **SMALL)


def test_a_finished_run_resumed_does_no_work_and_keeps_its_maps(tmp_path, puma):
    first = workspace.compute(puma, out=tmp_path / "m.zarr", **SMALL)
    again = workspace.compute(puma, out=tmp_path / "m.zarr", resume=True, **SMALL)
    np.testing.assert_array_equal(again.reachability.hits, first.reachability.hits)
    np.testing.assert_array_equal(again.dexterity.max_solutions, first.dexterity.max_solutions)


def test_open_names_a_folder_that_is_not_a_store(tmp_path):
    with pytest.raises(InputError, match="is not a Zarr store"):
        workspace.open(tmp_path)


@pytest.mark.slow
def test_cli_json_summary_and_report(tmp_path, capsys):
    out = tmp_path / "anno.zarr"
    code = main(["workspace", "probot-anno", "--resolution", "0.08", "--samples", "2e4",
                 "--chunk-size", "5000", "--orientations", "4", "--manipulability-samples", "2000",
                 "--out", str(out), "--json",
                 "--report"])
    assert code == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["samples"] == 20_000 and summary["volume_unit"] == "m^3"
    assert 0 < summary["reachable_volume_error"] < summary["reachable_volume"]
    assert summary["dexterity"]["ik_solves"] == 4 * summary["dexterity"]["voxels_tested"]
    page = (tmp_path / "anno-report" / "index.html").read_text()
    assert "reachable volume" in page and page.count("data:image/png;base64") == 4
    assert json.loads((tmp_path / "anno-report" / MARKER).read_text())["generator"] == "armkit workspace"
    assert workspace.open(out).reachability.samples == 20_000


def test_a_dotted_folder_name_is_a_store_and_an_existing_file_is_not(tmp_path, capsys):
    store = tmp_path / "maps_res0.05"
    assert main(["workspace", "puma560", "--resolution", "0.2", "--samples", "100", "--quiet", "--out",
                 str(store)]) == 0
    assert store.is_dir()
    (tmp_path / "notes").write_text("mine")
    assert main(["workspace", "puma560", "--resolution", "0.2", "--samples", "100", "--quiet", "--out",
                 str(tmp_path / "notes")]) == 1
    assert "--out " + str(tmp_path / "notes") + ": a file of that name exists" in capsys.readouterr().err
    assert (tmp_path / "notes").read_text() == "mine"


@pytest.mark.parametrize(("args", "message"), [
    (["--resume"], "--resume needs --out"),
    (["--samples", "many"], "--samples: 'many' is not a number"),
    (["--samples", "1.5"], "expected a whole number"),
    (["--sweep", "b2=1:2:3"], "expected PARAMETER ROW=START:STOP:COUNT"),
    (["--sweep", "a3=nan:1:3"], "sweep 'a3=nan:1:3': expected finite START and STOP from -1e+06 to 1e+06"),
    (["--sweep", "a3=0:inf:3"], "(m or rad), got 0 and inf"),
    (["--sweep", "a3=1e308:1e308:2"], "(m or rad), got 1e308 and 1e308"),
    (["--sweep", "a3=0.1:0.2:100000000"], "expected COUNT from 1 to 1000 (each value is a whole"),
    (["--out", ""], "--out: expected a folder name for the Zarr store"),
    (["--dataset", "10"], "--dataset needs --out"),
    (["--out", "maps.txt"], "--out maps.txt: a Zarr store is a folder, and 'maps.txt' names a file; call it "
                            "e.g. maps.zarr"),
])
def test_cli_errors_are_one_line(args, message, capsys):
    assert main(["workspace", "puma560", "--resolution", "0.2", "--samples", "100", "--quiet", *args]) == 1
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err and "Warning" not in err


@pytest.mark.slow
def test_cli_sweep_report_names_the_arm_and_shows_every_value(tmp_path, capsys):
    code = main(["workspace", "probot-anno", "--sweep", "a3=0.15:0.3:2", "--resolution", "0.1",
                 "--samples", "1e4", "--orientations", "2", "--out", str(tmp_path / "s.zarr"), "--report",
                 "--json"])
    assert code == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["robot"] == "PROBOT Anno" and len(summary["values"]) == 2
    page = (tmp_path / "s-report" / "index.html").read_text()
    assert "armkit workspace: PROBOT Anno<" in page and "Maps: a3 = 0.3" in page
    again = workspace.open(tmp_path / "s.zarr")
    assert [round(v, 3) for v in again.values] == [0.15, 0.3]
    assert again.table()[1]["reachable_volume"] == summary["values"][1]["reachable_volume"]


def _interrupt_after(monkeypatch, accumulator: type, chunks: int) -> None:
    """Ctrl-C arrives once ``chunks`` chunks have been added to ``accumulator``."""
    real_add, calls = accumulator.add, []

    def add_then_interrupt(self, result):
        if len(calls) == chunks:
            raise KeyboardInterrupt
        calls.append(1)
        real_add(self, result)

    monkeypatch.setattr(accumulator, "add", add_then_interrupt)


@pytest.mark.parametrize(("module", "accumulator", "unfinished"), [
    ("armkit.workspace.dexterity", "_Counts", "dexterity"),
    ("armkit.workspace.manipulability", "_Stats", "manipulability"),
])
def test_an_interrupted_run_is_never_reported_complete_and_resume_completes_it(
        tmp_path, puma, monkeypatch, module, accumulator, unfinished):
    settings = SMALL | {"resolution": 0.05, "manipulability_samples": 16_000}
    whole = workspace.compute(puma, **settings)
    assert whole.complete and whole.summary()["complete"]
    with monkeypatch.context() as patch:
        _interrupt_after(patch, getattr(importlib.import_module(module), accumulator), 2)
        with pytest.raises(workspace.InterruptedRun, match=f"after 2 of .* chunks of {unfinished}"):
            workspace.compute(puma, out=tmp_path / "m.zarr", **settings)
    cut = workspace.open(tmp_path / "m.zarr")
    summary = cut.summary()
    assert not cut.complete and summary["complete"] is False and summary["reachability_complete"] is True
    assert summary[unfinished]["complete"] is False
    if unfinished == "dexterity":
        assert 0 < summary["dexterity"]["voxels_tested"] < summary["dexterity"]["voxels_to_test"]
    else:
        assert summary["maps_missing"] == ["dexterity"]
        assert 0 < summary["manipulability"]["samples"] < 16_000
    resumed = workspace.compute(puma, out=tmp_path / "m.zarr", resume=True, **settings)
    again = workspace.open(tmp_path / "m.zarr")
    assert resumed.complete and again.complete and "maps_missing" not in again.summary()
    np.testing.assert_array_equal(again.dexterity.reachable_fraction, whole.dexterity.reachable_fraction)
    np.testing.assert_array_equal(again.manipulability.arrays["count"], whole.manipulability.arrays["count"])
