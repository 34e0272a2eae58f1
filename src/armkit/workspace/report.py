"""``--report``: the maps' pictures and numbers as one HTML page, in the style of ``armkit lab``.

The page is written by :func:`armkit.lab.report.write_report` (pictures embedded, a marker
file so a later run replaces only its own files, a foreign folder refused without force).
"""

from __future__ import annotations

from datetime import UTC, datetime
from pathlib import Path

import armkit
from armkit.lab.report import Section, Table, prepare_folder, write_report
from armkit.plots import save_figure
from armkit.workspace.maps import Workspace
from armkit.workspace.sweep import Sweep

__all__ = ["write_workspace_report"]


def _number(value: float | None, digits: int = 4) -> str:
    return "" if value is None else f"{value:.{digits}g}"


def _summary_table(summary: dict) -> Table:
    rows = [["robot", summary["robot"]], ["resolution", f"{summary['resolution_m']:g} m"],
            ["grid", f"{' x '.join(map(str, summary['grid_shape']))} = {summary['voxels']} voxels"]]
    if "samples" in summary:
        rows.append(["samples", f"{summary['samples']:,} ({summary['method']}, seed {summary['seed']})"])
    if "volume" in summary:
        v = summary["volume"]
        rows += [["reachable volume", f"{v['value']:.4g} ± {v['error']:.2g} {v['unit']}"],
                 ["  of which voxelisation / sampling",
                  f"± {v['voxelisation_error']:.2g} / ± {v['sampling_error']:.2g} {v['unit']}"],
                 ["reached voxels (boundary)", f"{v['occupied_voxels']:,} ({v['boundary_voxels']:,})"]]
        if v["error"] > v["value"]:
            rows.append(["  note", "the volume's error is larger than the volume: give more samples (or a "
                                   "coarser resolution)"])
    if "dexterity" in summary:
        dex = summary["dexterity"]
        block = ("" if dex["block_voxels"] == 1 else
                 f", one per block of {dex['block_voxels']}³ voxels ({dex['block_m']:g} m)")
        rows += [["mean reachability index", f"{_number(dex['mean_reachability_index'], 3)} over the "
                  f"{dex['mean_index_voxels']:,} reached voxels ({dex['orientations']} orientations at "
                  f"{dex['voxels_tested']:,} positions{block}: {dex['ik_solves']:,} IK solves)"]]
    if "manipulability" in summary:
        manip = summary["manipulability"]
        rows += [["manipulability (mean over voxels)",
                  f"{_number(manip['mean'])} from {manip['samples']:,} samples"],
                 ["singular voxels", f"{manip['singular_voxels']:,} (smallest singular value < "
                  f"{manip['singular_threshold']:g})"]]
    rows += [[f"{name} map", f"skipped: {reason}"]
             for name, reason in summary.get("maps_skipped", {}).items()]
    rows.append(["time", f"{summary['seconds']:.1f} s"])
    return Table("Summary", ["", "value"], rows, wrap=True)


def _map_figures(ws: Workspace, folder: Path, prefix: str) -> tuple[list[tuple[str, str]], list[str]]:
    from armkit.workspace import plots

    images = [(f"{prefix}vertical.png", "Vertical slice through the base axis (y = 0); white: not reached."),
              (f"{prefix}horizontal.png", "Horizontal slices at the quartiles of the reached heights."),
              (f"{prefix}cloud.png", "Reached voxels in 3-D."),
              (f"{prefix}histograms.png", "Distributions over the reached voxels.")]
    figures = [plots.plot_vertical_slice(ws), plots.plot_horizontal_slices(ws), plots.plot_cloud(ws),
               plots.plot_histograms(ws)]
    for (name, _), figure in zip(images, figures, strict=True):
        save_figure(figure, folder / name, overwrite=True, dpi=110)
    return images, [name for name, _ in images]


_INTRO = ("Configurations drawn inside the joint limits put the tool in the voxels shown (samples per "
          "voxel). "
          "The reachable volume counts the reached voxels, minus half of those on the boundary; its error is "
          "half the boundary voxels (voxelisation) plus the reachable voxels expected to be still unhit "
          "(the larger of Chao1, from the voxels hit once and twice, and what the second half of the samples "
          "added).\n\n"
          "The reachability index of a voxel (Zacharias et al. 2007) is the fraction of a fixed near-uniform "
          "set of tool orientations with an IK solution inside the limits; the inverse condition number "
          "s_min/s_max of the Jacobian is 1 where the arm moves equally well in every direction and 0 at a "
          "singularity.")


def write_workspace_report(result: Workspace | Sweep, folder: str | Path, force: bool = False) -> Path:
    """Write ``folder/index.html`` with the pictures of ``result``; return the page.

    Raises
    ------
    InputError
        If ``folder`` holds files that are not an armkit report and ``force`` is false.
    """
    folder = Path(folder)
    prepare_folder(folder, force)
    sections, files = [], []
    if isinstance(result, Sweep):
        from armkit.workspace import plots

        save_figure(plots.plot_sweep(result), folder / "sweep.png", overwrite=True, dpi=110)
        files.append("sweep.png")
        rows = [[f"{row['value']:.4g}",
                 f"{row['reachable_volume']:.4g} ± {row['reachable_volume_error']:.2g}",
                 _number(row["mean_reachability_index"], 3)] for row in result.table()]
        unit = result.table()[0]["volume_unit"]
        sections.append(Section("sweep", f"Design sweep over {result.parameter}", "", badge=False,
                                tables=[Table(f"per value of {result.parameter} (SI units)",
                                              [result.parameter, f"reachable volume [{unit}]",
                                               "mean reachability index"], rows)],
                                images=[("sweep.png", "Reachable volume with its stated error, and the mean "
                                         "reachability index, per value.")]))
        shown = [(f"{result.parameter} = {v:.4g}", ws, f"value{k}-") for k, (v, ws)
                 in enumerate(zip(result.values, result.maps, strict=True))]
        first = result.maps[0].summary()
        shared = ("resolution_m", "grid_shape", "voxels", "samples", "method", "seed")
        summary = {key: first[key] for key in shared}
        summary |= {"robot": result.robot.name, "seconds": result.seconds, "store": result.path}
    else:
        shown, summary = [(result.robot.name, result, "")], result.summary()
    for k, (title, ws, prefix) in enumerate(shown):
        images, names = _map_figures(ws, folder, prefix)
        files += names
        sections.append(Section(f"maps{k}", f"Maps: {title}", _INTRO if k == 0 else "", badge=False,
                                images=images))
    subtitle = (f"armkit {armkit.__version__}, {datetime.now(UTC):%Y-%m-%d %H:%M} UTC"
                + (f", store {summary['store']}" if summary.get("store") else "") + ".")
    return write_report(folder, f"armkit workspace: {summary['robot']}", subtitle, _summary_table(summary),
                        sections, files, seeds=False, generator="armkit workspace")
