"""examples/armkit_tour.ipynb runs top to bottom in a real Jupyter kernel (nbclient, ipykernel), and what
its cells show is what armkit computes: the IK table, the pictures, the viewer's live page in an iframe."""

from __future__ import annotations

import re
import urllib.request
from pathlib import Path

import pytest
from conftest import WAIT_S

nbformat = pytest.importorskip("nbformat")
nbclient = pytest.importorskip("nbclient")
pytest.importorskip("ipykernel")
pytest.importorskip("viser")

#: A kernel, armkit, matplotlib and viser starting in a fresh process: not in `make test-fast`.
pytestmark = pytest.mark.slow

NOTEBOOK = Path(__file__).parent.parent / "examples" / "armkit_tour.ipynb"


def _text(cell) -> str:
    return "".join(output.get("text", "") for output in cell.outputs if output.output_type == "stream")


def _has_png(cell) -> bool:
    return any("image/png" in output.get("data", {}) for output in cell.outputs)


def test_the_tour_notebook_runs_and_its_viewer_cell_serves_the_live_page(tmp_path):
    import numpy as np

    import armkit

    notebook = nbformat.read(NOTEBOOK, as_version=4)
    client = nbclient.NotebookClient(notebook, timeout=int(WAIT_S), kernel_name="python3",
                                     resources={"metadata": {"path": str(tmp_path)}})
    served = None
    with client.setup_kernel():
        for index, cell in enumerate(notebook.cells):
            client.execute_cell(cell, index)  # raises CellExecutionError on any error in a cell
            html = "".join(output.get("data", {}).get("text/html", "") for output in cell.get("outputs", []))
            if "data-armkit=\"viewer\"" in html:  # the page must be live while the kernel runs
                url = re.search(r'<iframe src="(http://127\.0\.0\.1:\d+)"', html).group(1)
                with urllib.request.urlopen(url, timeout=WAIT_S) as response:
                    served = (response.status, response.read())
    assert served is not None, "no cell showed the viewer"
    assert served[0] == 200 and b"<html" in served[1].lower()
    code = [cell for cell in notebook.cells if cell.cell_type == "code"]
    robot = armkit.load("puma560")
    T = robot.fk(np.radians([20, -40, -60, 10, 45, 30]))
    solutions = armkit.ik_solutions(robot, T)
    table = _text(code[2])
    assert f"{len(solutions.q)} solutions ({int(solutions.within_limits.sum())} inside the limits)" in table
    rows = [line for line in table.splitlines() if re.match(r"\s+\d+\s+-?\d", line)]
    assert len(rows) == len(solutions.q)
    for row, q_k in zip(rows, solutions.q, strict=True):
        np.testing.assert_allclose([float(v) for v in row.split()[1:7]], np.degrees(q_k), atol=0.006)
    assert _has_png(code[3]) and _has_png(code[4])  # robot.plot and the P-V-A figure
    assert "s through 3 waypoints" in _text(code[4])
