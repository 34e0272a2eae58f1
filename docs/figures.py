"""Regenerate the README's and docs' figures from the current build: ``make figures``.

Each figure is made by the command a user would run (printed as it goes), in a temporary
folder, then copied over ``docs/img/``:

- ``seed_pva.png``, ``seed_tool_path.png``: ``armkit traj`` on report 000's poses, 10 s per segment.
- ``lab-summary.png``, ``lab-trajectory.gif``: ``armkit lab`` (the seed experiments); the
  summary is its trajectory animation's last frame, its P-V-A figure and its straight-line
  tracking, under the run's own headline numbers.
- ``workspace-vertical.png``: ``armkit workspace probot-anno --samples 1e7 --report``.
- ``view.png``: the browser viewer (``armkit.view.Viewer``) on report 000's first IK target with
  its solutions as ghosts, photographed by headless Debian ``chromium`` through Playwright
  (software WebGL); skipped, with a line saying so, where either is missing.

Run: python docs/figures.py [--quick] [--out DIR]   (--quick: smaller runs, to check the script;
--out: write there instead of docs/img)
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

IMG = Path(__file__).parent / "img"
DATA = Path(__file__).parents[1] / "examples" / "data"
ARMKIT = str(Path(sys.executable).with_name("armkit"))


def run(*args: str, folder: Path) -> str:
    """Run ``armkit ARGS`` in ``folder``, printing the command; its stdout."""
    print("$ armkit", " ".join(args), flush=True)
    return subprocess.run([ARMKIT, *args], cwd=folder, check=True, capture_output=True, text=True).stdout


def trajectory_figures(folder: Path) -> list[Path]:
    run("traj", "probot-anno", "--waypoints", str(DATA / "probot_seed_poses.csv"), "--poses", "--durations",
        "10", "10", "10", "--plot", "seed_pva.png", "--plot-path", "seed_tool_path.png", folder=folder)
    return [folder / "seed_pva.png", folder / "seed_tool_path.png"]


def lab_figures(folder: Path, quick: bool) -> list[Path]:
    from matplotlib.figure import Figure
    from PIL import Image

    report = folder / "lab"
    summary = json.loads(run("lab", "--out", str(report), "--json", *(["--quick"] if quick else []),
                             folder=folder))
    with Image.open(report / "trajectory.gif") as gif:
        gif.seek(gif.n_frames - 1)
        last_frame = gif.convert("RGB")
    figure = Figure(figsize=(12.8, 7.6), dpi=100)
    headlines = {section["key"]: section["headline"] for section in summary["sections"]}
    figure.text(0.012, 0.965, "armkit lab: the seed experiments computed by armkit and simulated in MuJoCo",
                fontsize=17, weight="bold", va="top")
    lines = [f"{name}: {headlines[key]}" for key, name in (("ik", "IK"), ("trajectory", "trajectory"),
                                                           ("line", "straight line")) if headlines.get(key)]
    figure.text(0.012, 0.915, "PROBOT Anno (report 000). " + "; ".join(lines) + ".", fontsize=10, va="top",
                wrap=True)
    panels = ((last_frame, (0.0, 0.02, 0.37, 0.82)),
              (Image.open(report / "trajectory_pva.png"), (0.38, 0.40, 0.62, 0.46)),
              (Image.open(report / "line_tracking.png"), (0.38, 0.0, 0.62, 0.40)))
    for image, box in panels:
        ax = figure.add_axes(box)
        ax.imshow(image)
        ax.set_axis_off()
    summary_png = folder / "lab-summary.png"
    figure.savefig(summary_png, dpi=100)
    with Image.open(summary_png) as full:   # 256 colours: a fifth of the bytes, the same to the eye
        quantized = full.convert("RGB").quantize(256)
    quantized.save(summary_png, optimize=True)
    shutil.copy(report / "trajectory.gif", folder / "lab-trajectory.gif")
    return [summary_png, folder / "lab-trajectory.gif"]


def workspace_figure(folder: Path, quick: bool) -> list[Path]:
    run("workspace", "probot-anno", "--resolution", "0.02", "--samples", "1e5" if quick else "1e7",
        "--report", "--report-dir", "maps", "--quiet", folder=folder)
    shutil.copy(folder / "maps" / "vertical.png", folder / "workspace-vertical.png")
    return [folder / "workspace-vertical.png"]


CHROMIUM = "/usr/bin/chromium"
CHROMIUM_ARGS = ["--headless=new", "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--no-sandbox"]


def viewer_figure(folder: Path) -> list[Path]:
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        print("view.png skipped: playwright is not installed (pip install playwright)")
        return []
    if not Path(CHROMIUM).exists():
        print(f"view.png skipped: no {CHROMIUM} (apt-get install chromium)")
        return []
    from armkit.lab.published import PROBOT_IK
    from armkit.spatial.transforms import transform_from_pose
    from armkit.view import Viewer

    print("$ python -c 'Viewer(\"probot-anno\").show_solutions(<report 000 IK target 1>)'  (+ chromium)")
    path = folder / "view.png"
    with Viewer("probot-anno", port=0) as viewer, sync_playwright() as playwright:
        viewer.show_solutions(transform_from_pose(PROBOT_IK[0][0]))
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        page = browser.new_page(viewport={"width": 1280, "height": 760})
        page.set_default_timeout(600_000)
        page.goto(viewer.url)
        page.wait_for_selector("[data-armkit=pose-matrix]")
        page.wait_for_selector("canvas")
        page.wait_for_timeout(4000)  # the scene's meshes arrive after the panel; software WebGL draws them
        for close in page.locator("[class*=Notification] button").all():  # viser's "software WebGL" notice
            close.click()
        page.wait_for_timeout(1000)
        page.screenshot(path=str(path))
        browser.close()
    return [path]


def main(argv: list[str]) -> int:
    quick = "--quick" in argv
    out = Path(argv[argv.index("--out") + 1]) if "--out" in argv else IMG
    with tempfile.TemporaryDirectory(prefix="armkit-figures-") as tmp:
        folder = Path(tmp)
        made = (trajectory_figures(folder) + lab_figures(folder, quick) + workspace_figure(folder, quick)
                + viewer_figure(folder))
        for path in made:
            shutil.copy(path, out / path.name)
            print(f"wrote {out / path.name}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
