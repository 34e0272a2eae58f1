"""Every numbered example runs headless and exits cleanly."""

import os
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import WAIT_S

#: One fresh process per example: not in `make test-fast`.
pytestmark = pytest.mark.slow

EXAMPLES = sorted((Path(__file__).parent.parent / "examples").glob("[0-9][0-9]_*.py"))


@pytest.mark.parametrize("script", EXAMPLES, ids=[p.name for p in EXAMPLES])
def test_example_runs(script, tmp_path):
    env = {**os.environ, "MPLBACKEND": "Agg"}
    result = subprocess.run([sys.executable, str(script)], cwd=tmp_path, env=env, capture_output=True,
                            text=True, timeout=WAIT_S)
    assert result.returncode == 0, result.stderr[-2000:]
    assert result.stdout.strip(), "an example should print what it shows"
    assert list(tmp_path.iterdir()) == [], "an example writes into a temporary folder, not where it is run"


def test_make_figures_makes_every_figure_it_names(tmp_path):
    script = Path(__file__).parent.parent / "docs" / "figures.py"
    env = {**os.environ, "MPLBACKEND": "Agg"}
    result = subprocess.run([sys.executable, str(script), "--quick", "--out", str(tmp_path)], env=env,
                            capture_output=True, text=True, timeout=WAIT_S)
    assert result.returncode == 0, result.stderr[-2000:]
    made = sorted(p.name for p in tmp_path.iterdir())
    browser = Path("/usr/bin/chromium").exists()  # the viewer's screenshot needs it (CI installs it)
    assert browser or os.environ.get("ARMKIT_REQUIRE_BROWSER") != "1"
    assert made == ["lab-summary.png", "lab-trajectory.gif", "seed_pva.png", "seed_tool_path.png",
                    *(["view.png"] if browser else []), "workspace-vertical.png"]
    assert "$ armkit lab" in result.stdout     # each command printed as it runs
