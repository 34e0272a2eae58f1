"""Ctrl-C in ``armkit workspace``: one line on stderr, exit code 130, and a store ``--resume`` continues."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from conftest import WAIT_S, interruptible, wait_until

pytest.importorskip("zarr")
pytestmark = pytest.mark.slow

COMMAND = [sys.executable, "-m", "armkit.cli.main", "workspace", "probot-anno", "--resolution", "0.05",
           "--orientations", "0", "--manipulability-samples", "0", "--chunk-size", "20000", "--quiet"]


def _start(out: Path, samples: str, *extra: str) -> subprocess.Popen:
    env = {**os.environ, "PYTHONUNBUFFERED": "1", "DASK_DISTRIBUTED__COMM__TIMEOUTS__CONNECT": f"{WAIT_S}s",
           "DASK_DISTRIBUTED__COMM__TIMEOUTS__TCP": f"{WAIT_S}s"}  # --dask local's cluster, on a busy machine
    return subprocess.Popen([*COMMAND, "--samples", samples, "--out", str(out), *extra], env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=interruptible)


def _chunks_done(out: Path) -> int:
    attrs = out / "reachability" / "zarr.json"
    try:
        return int(json.loads(attrs.read_text())["attributes"].get("chunks_done", 0))
    except (OSError, ValueError, KeyError):
        return 0


def _interrupt(process: subprocess.Popen) -> tuple[int, str]:
    process.send_signal(signal.SIGINT)
    _, stderr = process.communicate(timeout=WAIT_S)
    return process.returncode, stderr


def _assert_one_line(code: int, stderr: str) -> None:
    assert code == 130, stderr
    assert "Traceback" not in stderr
    assert len(stderr.strip().splitlines()) == 1, stderr
    assert "interrupted" in stderr


def _wait_for_store(out: Path, process: subprocess.Popen) -> None:
    wait_until(lambda: (out / "zarr.json").is_file() or process.poll() is not None, "the store to be made",
               poll_s=0.01)
    assert process.poll() is None, f"ended before making its store: {process.communicate()[1]}"


def test_ctrl_c_before_the_first_chunk_exits_130_with_one_line(tmp_path):
    out = tmp_path / "maps.zarr"
    process = _start(out, "1e7", "--chunk-size", str(2**22))
    _wait_for_store(out, process)  # the store is made right before the first chunk starts
    _assert_one_line(*_interrupt(process))
    assert _chunks_done(out) == 0


@pytest.mark.parametrize("extra", [(), ("--dask", "local")], ids=["local", "dask"])
def test_ctrl_c_during_the_run_keeps_a_store_resume_continues(tmp_path, extra):
    out = tmp_path / "maps.zarr"
    process = _start(out, "2e8", *extra)  # 10,000 chunks: more than the kernel does in a second (4e7 was not)
    _wait_for_store(out, process)
    time.sleep(1.0)  # let chunks run: any number done by the interrupt (even 0 on a slow machine) is right
    assert process.poll() is None, "finished before it could be interrupted"
    _assert_one_line(*_interrupt(process))
    done = _chunks_done(out)
    resumed = subprocess.run([*COMMAND, "--samples", "2e8", "--out", str(out), "--resume", "--json"],
                             capture_output=True, text=True, timeout=WAIT_S)
    assert resumed.returncode == 0, resumed.stderr
    assert json.loads(resumed.stdout)["samples"] == 200_000_000
    assert _chunks_done(out) == 10_000 > done
