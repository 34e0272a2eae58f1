"""The shared output-path check (names the file and the caller's remedy) and the atomic write
every writer uses: a failed write (a full disk, simulated by ``ulimit -f``) never destroys the
previous file."""

import shlex
import stat
import subprocess
import sys
from pathlib import Path

import pytest

from armkit._io import atomic_write, check_output_path
from armkit.errors import InputError

JOINTS = Path(__file__).parent.parent / "examples" / "data" / "probot_seed_joints.csv"


def test_check_output_path(tmp_path):
    existing = tmp_path / "a.csv"
    existing.write_text("x")
    assert check_output_path(tmp_path / "new.csv", False) == tmp_path / "new.csv"
    assert check_output_path(existing, True) == existing
    with pytest.raises(InputError, match=r"'.*a\.csv' already exists; pass overwrite=True to replace it"):
        check_output_path(existing, False)
    with pytest.raises(InputError, match="already exists; pass --force to replace it"):
        check_output_path(existing, False, remedy="pass --force")
    with pytest.raises(InputError, match="is a folder"):
        check_output_path(tmp_path, True)
    with pytest.raises(InputError, match="folder .* does not exist"):
        check_output_path(tmp_path / "missing" / "a.csv", True)


def test_atomic_write_replaces_the_file_only_when_the_body_completes(tmp_path):
    target = tmp_path / "a.csv"
    target.write_text("previous")
    target.chmod(0o640)
    with pytest.raises(RuntimeError, match="stopped"), atomic_write(target) as partial:
        partial.write_text("half")
        raise RuntimeError("stopped")
    assert target.read_text() == "previous"
    assert sorted(tmp_path.iterdir()) == [target]
    with atomic_write(target) as partial:
        assert partial.parent == tmp_path and partial.suffix == ".csv" and partial != target
        partial.write_text("new")
    assert target.read_text() == "new"
    assert stat.S_IMODE(target.stat().st_mode) == 0o640
    assert sorted(tmp_path.iterdir()) == [target]


_EXPORT = ["export", "probot-anno", "--force"]
_TRAJ = ["traj", "probot-anno", "--waypoints", str(JOINTS), "--durations", "10", "10", "10", "--force"]
_DISK_FULL_RUNS = {
    "traj.csv": [*_TRAJ, "--out", "{}"],
    "traj.npz": [*_TRAJ, "--out", "{}"],
    "pva.png": [*_TRAJ, "--plot", "{}"],
    "arm.urdf": [*_EXPORT, "--urdf", "{}"],
    "arm.xml": [*_EXPORT, "--mjcf", "{}"],
}


@pytest.mark.parametrize("name", sorted(_DISK_FULL_RUNS))
def test_a_full_disk_leaves_the_previous_cli_output_whole(tmp_path, name):
    target = tmp_path / name
    target.write_bytes(b"previous")
    argv = [word.format(target) for word in _DISK_FULL_RUNS[name]]
    code = f"import sys; from armkit.cli.main import main; sys.exit(main({argv!r}))"
    result = _with_file_size_limit(code, tmp_path)
    assert result.returncode == 1, result.stderr
    assert f"cannot write '{target}': File too large" in result.stderr and "Traceback" not in result.stderr
    assert target.read_bytes() == b"previous"
    assert sorted(tmp_path.iterdir()) == [target]


def test_a_full_disk_leaves_the_previous_waypoint_file_whole(tmp_path):
    target = tmp_path / "w.csv"
    target.write_bytes(b"previous")
    code = ("import armkit, numpy as np; from armkit.trajectory.waypoints import write_waypoints\n"
            f"write_waypoints({str(target)!r}, armkit.load('probot-anno'), np.zeros((200, 6)), "
            "overwrite=True)")
    result = _with_file_size_limit(code, tmp_path)
    assert result.returncode == 1 and "InputError: cannot write" in result.stderr
    assert "File too large" in result.stderr
    assert target.read_bytes() == b"previous"
    assert sorted(tmp_path.iterdir()) == [target]


def _with_file_size_limit(code: str, folder: Path) -> subprocess.CompletedProcess:
    """Run Python ``code`` in a shell whose file-size limit is 1 KiB (``ulimit -f 1``): a full disk."""
    script = f"ulimit -f 1 && exec {shlex.quote(sys.executable)} -c {shlex.quote(code)}"
    return subprocess.run(["bash", "-c", script], cwd=folder, capture_output=True, text=True, timeout=300)
