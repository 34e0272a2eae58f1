"""``armkit`` itself: Ctrl-C and system errors in any command are one line, help reads plainly."""

from __future__ import annotations

import pytest
from conftest import WAIT_S, interruptible

from armkit.cli.main import INTERRUPTED, main


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def _raise(exc):
    def raising(*args, **kwargs):
        raise exc
    return raising


@pytest.mark.parametrize("argv", [
    ["move", "probot-anno", "--by", "0.1", "0", "0", "--duration", "900", "--dt", "0.0005"],
    ["rotate", "probot-anno", "--axis", "1", "0", "0", "--angle", "0.5", "--duration", "900",
     "--dt", "0.0005"],
])
def test_ctrl_c_in_a_running_command_is_one_line_and_exit_130(capsys, argv, python_handles_sigint):
    """A real interrupt of the main thread 0.5 s into a motion of 1.8 million control steps."""
    import _thread
    import threading

    timer = threading.Timer(0.5, _thread.interrupt_main)
    timer.start()
    try:
        code, out, err = run(capsys, *argv)
    finally:
        timer.cancel()
    assert code == INTERRUPTED == 130
    assert err.strip() == "interrupted (Ctrl-C)" and "Traceback" not in out + err


def test_a_system_error_is_one_line_naming_the_file(capsys, monkeypatch):
    denied = PermissionError(13, "Permission denied", "/x/arm.toml")
    monkeypatch.setattr("armkit.cli.app.load", _raise(denied))  # what load_robot reads the file with
    code, _, err = run(capsys, "fk", "probot-anno", "0", "0", "0", "0", "0", "0")
    assert code == 1 and err.strip() == "error: file '/x/arm.toml': Permission denied"


@pytest.mark.parametrize("command", ["fk", "ik", "traj", "sim", "lab", "show", "robots", "move", "export"])
def test_help_shows_flags_without_type_tags(capsys, command):
    code, out, _ = run(capsys, command, "--help")
    assert code == 0 and "--help" in out and "<bool>" not in out


@pytest.mark.parametrize("argv", [["fk", "probot-anno", "0", "0", "0", "0", "0", "0", "--typo"],
                                  ["traj", "probot-anno", "--waypoints", "w", "--durations", "1", "--dge"],
                                  ["move", "probot-anno", "--from", "0", "0", "0", "0", "0", "0", "--fast",
                                   "--by", "0", "0", "0.1"]])
def test_an_unknown_option_among_values_is_named_as_such(capsys, argv):
    code, _, err = run(capsys, *argv)
    assert code == 1 and err.startswith("error: no such option: --") and err.count("\n") == 1


def test_show_prints_no_negative_zero(capsys):
    code, out, _ = run(capsys, "show", "probot-anno")
    assert code == 0 and "tool at q = 0: position [0.228900, 0.000000, 0.454000] m" in out


def test_ctrl_c_while_armkit_is_still_importing_is_one_line_and_exit_130():
    """The console script imports armkit inside its own try: a traceback there was item 10's 8 s case."""
    import signal
    import subprocess
    import sys

    # an import finder holds run()'s import of the CLI until the interrupt comes: the signal lands
    # inside the import on a fast machine and on a slow one alike
    started = ("import sys, time\n"
               "class Hold:\n"
               "    def find_spec(self, name, path, target=None):\n"
               "        if name == 'armkit.cli':\n"
               "            print('importing', flush=True)\n"
               "            time.sleep(3600)\n"
               "sys.meta_path.insert(0, Hold())\n"
               "from _armkit_entry import run\n"
               "run()\n")
    process = subprocess.Popen([sys.executable, "-c", started, "robots"], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True,
                               preexec_fn=interruptible)
    try:
        assert process.stdout.readline() == "importing\n"
        process.send_signal(signal.SIGINT)
        out, err = process.communicate(timeout=WAIT_S)
    finally:
        process.kill()
    assert process.returncode == 130 and err == "interrupted (Ctrl-C)\n" and out == ""
