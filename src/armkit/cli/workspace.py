"""``armkit workspace``: reachability, dexterity and manipulability maps, design sweeps, IK data sets."""

from __future__ import annotations

import logging
import warnings
from pathlib import Path
from typing import Annotated

import typer
from rich.markup import escape

from armkit._params import thread_count
from armkit.cli.app import (
    BaseOpt,
    LockOpt,
    RobotArg,
    TipOpt,
    app,
    console,
    err_console,
    load_robot,
    print_json,
)
from armkit.cli.scene_option import PackagePathOpt, SceneOpt, load_scene_option
from armkit.errors import InputError

#: Exit code of a run ended by Ctrl-C (128 + SIGINT).
INTERRUPTED = 130

#: ``--dask local``: start a LocalCluster on this machine instead of connecting to a scheduler.
LOCAL_CLUSTER = "local"


def _check_store_name(out: Path) -> None:
    """``--out`` names a folder to be (or a store there): not empty, not an existing file, not a
    file format's name."""
    if not out.name:
        raise InputError(f"--out: expected a folder name for the Zarr store, e.g. maps.zarr "
                         f"(got {str(out)!r})")
    if out.is_file():
        raise InputError(f"--out {out}: a file of that name exists, and a Zarr store is a folder; "
                         f"give another name, e.g. {out.with_name(out.stem + '-maps.zarr')}")
    if out.suffix.lower() in _FILE_SUFFIXES and not out.is_dir():
        raise InputError(f"--out {out}: a Zarr store is a folder, and {out.name!r} names a file; call it "
                         f"e.g. {out.with_name(out.stem.removesuffix('.zarr') + '.zarr')}")


#: Endings of file formats a user may give as --out by mistake (a Zarr store is a folder; other
#: dotted names, such as maps_res0.05, are folder names).
_FILE_SUFFIXES = frozenset({".txt", ".csv", ".json", ".npz", ".npy", ".h5", ".hdf5", ".png", ".svg", ".pdf",
                            ".html", ".zip", ".gif", ".toml", ".yaml", ".yml", ".xml", ".urdf", ".pkl"})


def _count(text: str, option: str, minimum: int = 1) -> int:
    """A count such as ``1e8`` or ``250000`` as an int, at least ``minimum``."""
    try:
        value = float(text)
    except ValueError as exc:
        raise InputError(f"{option}: {text!r} is not a number") from exc
    from armkit.workspace.sampling import MAX_SAMPLES

    if not (minimum <= value <= MAX_SAMPLES and value == int(value)):
        raise InputError(f"{option}: expected a whole number from {minimum} to {MAX_SAMPLES:.4g}, "
                         f"got {text!r}")
    return int(value)


def _optional_count(text: str | None, option: str, minimum: int = 1) -> int | None:
    return None if text is None else _count(text, option, minimum)


def _engine(dask: str | None, threads: int | None):
    """The engine and, for ``--dask local``, the cluster to close afterwards."""
    if dask is None:
        return (None if threads is None else thread_count(threads, "--threads")), None
    if dask == LOCAL_CLUSTER:
        try:
            from distributed import Client, LocalCluster
        except ImportError as exc:
            raise InputError("--dask needs dask.distributed: pip install 'armkit[workspace]'") from exc
        # Worker processes, one thread each; their logs silenced (Ctrl-C reaches them too).
        with warnings.catch_warnings():  # "port 8787 in use" when another cluster runs: not ours
            warnings.filterwarnings("ignore", "Port .* is already in use", UserWarning)
            cluster = LocalCluster(n_workers=threads or 2, threads_per_worker=1, dashboard_address=None,
                                   silence_logs=logging.CRITICAL)
        return Client(cluster), cluster
    from armkit.workspace.engine import connect

    return connect(dask), None


def summary_lines(summary: dict) -> list[str]:
    """The lines ``armkit workspace`` prints for a :meth:`Workspace.summary` (the report shows the same)."""
    lines = []
    if "volume" in summary:
        v = summary["volume"]
        lines += [f"reachable volume: {v['value']:.4g} ± {v['error']:.2g} {v['unit']} (voxelisation "
                  f"± {v['voxelisation_error']:.2g}, sampling ± {v['sampling_error']:.2g})",
                  f"samples: {summary['samples']:,}, voxels: {summary['voxels']:,} "
                  f"({v['occupied_voxels']:,} reached) at {summary['resolution_m']:g} m"]
        if summary.get("colliding_samples_left_out"):
            lines.append(f"left out: {summary['colliding_samples_left_out']:,} samples in collision with the "
                         f"scene")
        if v["error"] > v["value"]:
            lines.append("  the volume's error is larger than the volume: give more --samples (or a coarser "
                         "--resolution)")
    if "dexterity" in summary:
        d = summary["dexterity"]
        block = ("" if d["block_voxels"] == 1 else
                 f", one per block of {d['block_voxels']}³ voxels ({d['block_m']:g} m) to keep to the IK "
                 f"solves asked (--ik-solves)")
        lines.append(f"mean reachability index: {d['mean_reachability_index']:.3f} over the "
                     f"{d['mean_index_voxels']:,} reached voxels ({d['orientations']} orientations at "
                     f"{d['voxels_tested']:,} positions{block}: {d['ik_solves']:,} IK solves)")
    if "manipulability" in summary:
        m = summary["manipulability"]
        lines.append(f"singular voxels: {m['singular_voxels']:,} (s_min < {m['singular_threshold']:g}), "
                     f"from {m['samples']:,} manipulability samples")
    for name, reason in summary.get("maps_skipped", {}).items():
        lines.append(f"{name} map skipped: {reason}")
    return lines


def _print_summary(summary: dict) -> None:
    lines = [f"robot: {summary['robot']}", *summary_lines(summary)]
    for row in summary.get("values", []):
        index = row["mean_reachability_index"]
        lines.append(f"{summary['parameter']} = {row['value']:.4g}: volume {row['reachable_volume']:.4g} ± "
                     f"{row['reachable_volume_error']:.2g} {row['volume_unit']}"
                     + ("" if index is None else f", mean reachability index {index:.3f}"))
    if summary.get("store"):
        lines.append(f"store: {summary['store']}")
    lines.append(f"time: {summary['seconds']:.1f} s")
    console.print("\n".join(lines), highlight=False)


@app.command("workspace")
def workspace_command(
    robot: RobotArg,
    resolution: Annotated[float, typer.Option(help="Voxel edge in metres.")] = 0.02,
    samples: Annotated[str, typer.Option(help="Configurations for the reachability map, e.g. 1e8.")] = "1e6",
    method: Annotated[str, typer.Option(help="Sampling: uniform or sobol.")] = "uniform",
    seed: Annotated[int, typer.Option(help="The same seed gives the same counts on any engine.")] = 0,
    chunk_size: Annotated[int, typer.Option(help="Configurations per task (memory per task).")] = 2**18,
    orientations: Annotated[int, typer.Option(
        help="Tool orientations per voxel for the dexterity map (0: none).")] = 100,
    manipulability_samples: Annotated[str | None, typer.Option(
        help="Configurations for the manipulability map (0: none; default: --samples / 5).",
        show_default=False)] = None,
    ik_solves: Annotated[str | None, typer.Option(
        help="Most IK solves of the dexterity map: beyond that, blocks of voxels share one position "
             "(default: --samples / 4; 100 times fewer for an arm without a closed form).",
        show_default=False)] = None,
    singular_threshold: Annotated[float, typer.Option(
        help="A voxel is singular where a sample's smallest singular value is below this.")] = 1e-3,
    sweep: Annotated[str | None, typer.Option(
        help="Maps over one DH parameter, e.g. a2=0.2:0.4:5 (row 2's a from 0.2 to 0.4 m, 5 values).",
        show_default=False)] = None,
    dataset: Annotated[str | None, typer.Option(
        help="Write an IK data set of this many (q, pose, all solutions) rows instead of maps.",
        show_default=False)] = None,
    out: Annotated[Path | None, typer.Option(help="Zarr store to write (a folder, e.g. maps.zarr).",
                                             show_default=False)] = None,
    resume: Annotated[bool, typer.Option("--resume", help="Continue the run stored in --out.")] = False,
    force: Annotated[bool, typer.Option("--force", help="Replace --out / the report folder.")] = False,
    threads: Annotated[int | None, typer.Option(help="Local threads (default: one per core); with "
                                                     "'--dask local' the number of workers.",
                                                show_default=False)] = None,
    dask: Annotated[str | None, typer.Option(
        help="Run the chunks on a Dask cluster: its scheduler address (tcp://host:8786), or 'local' for "
             "a LocalCluster on this machine.", show_default=False)] = None,
    report: Annotated[bool, typer.Option("--report", help="Write an HTML page with the pictures.")] = False,
    report_dir: Annotated[Path | None, typer.Option(
        help="Folder of the page (default: next to --out, NAME-report; else armkit-workspace-report).",
        show_default=False)] = None,
    json_output: Annotated[bool, typer.Option("--json", help="Print the summary as JSON.")] = False,
    quiet: Annotated[bool, typer.Option("--quiet", help="No progress bars.")] = False,
    base: BaseOpt = None,
    tip: TipOpt = None,
    lock: LockOpt = None,
    scene: SceneOpt = None,
    package_path: PackagePathOpt = None,
) -> None:
    """Where the arm reaches, how well and in how many ways: maps on a voxel grid, in a Zarr store."""
    options = dict(locals())
    from armkit.workspace.engine import InterruptedRun

    try:
        _run(**options)
    except (InterruptedRun, KeyboardInterrupt) as exc:
        text = str(exc) if isinstance(exc, InterruptedRun) else "before the first chunk was done"
        # a store write the interrupt cut short stays pending in zarr's I/O loop, and asyncio
        # would log "Task was destroyed but it is pending!" at exit, or Python warn that the
        # write's coroutine "was never awaited" (an interrupt before it started, seen in CI):
        # the one line says it all
        logging.getLogger("asyncio").setLevel(logging.CRITICAL)
        warnings.filterwarnings("ignore", "coroutine .* was never awaited", RuntimeWarning)
        err_console.print(f"[yellow]interrupted[/yellow] (Ctrl-C): {escape(text)}", highlight=False,
                          soft_wrap=True)
        raise typer.Exit(INTERRUPTED) from None


def _run(*, robot, resolution, samples, method, seed, chunk_size, orientations, manipulability_samples,
         ik_solves, singular_threshold, sweep, dataset, out, resume, force, threads, dask, report, report_dir,
         json_output, quiet, base, tip, lock, scene, package_path) -> None:
    from armkit import workspace

    arm = load_robot(robot, base, tip, lock)
    world = load_scene_option(arm, scene, package_path)
    if world is not None and (sweep is not None or dataset is not None):
        raise InputError("--scene: with the maps only (not with --sweep or --dataset)")
    if resume and out is None:
        raise InputError("--resume needs --out: the store to continue")
    if out is not None:
        _check_store_name(out)
    engine, cluster = _engine(dask, threads)
    common = {"seed": seed, "method": method, "engine": engine, "resume": resume, "overwrite": force,
              "progress": not quiet and not json_output}
    try:
        if dataset is not None:
            if out is None:
                raise InputError("--dataset needs --out: the Zarr store to write the rows to")
            result = workspace.ik_dataset(arm, _count(dataset, "--dataset"), out, **common)
        elif sweep is not None:
            result = workspace.sweep(arm, sweep, resolution=resolution, samples=_count(samples, "--samples"),
                                     chunk_size=chunk_size, orientations=orientations,
                                     ik_solves=_optional_count(ik_solves, "--ik-solves"), out=out, **common)
        else:
            result = workspace.compute(arm, resolution=resolution, samples=_count(samples, "--samples"),
                                       chunk_size=chunk_size, orientations=orientations,
                                       manipulability_samples=_optional_count(manipulability_samples,
                                                                              "--manipulability-samples", 0),
                                       ik_solves=_optional_count(ik_solves, "--ik-solves"),
                                       singular_threshold=singular_threshold, out=out, scene=world, **common)
    finally:
        if cluster is not None:
            engine.close()
            cluster.close()
    summary = result.summary()
    if report and dataset is None:
        from armkit.workspace.report import write_workspace_report

        default = out.with_name(out.stem + "-report") if out else Path("armkit-workspace-report")
        folder = report_dir or default
        summary["report"] = str(write_workspace_report(result, folder, force=force))
    if json_output:
        print_json(summary, {"resolution_m": "m", "volume": "m^3 (m^2 for a planar arm), as volume_unit",
                             "reachable_volume": "as volume_unit", "seconds": "s", "block_m": "m",
                             "singular_threshold": "m/s and rad/s mixed, per unit joint rate"})
    elif dataset is not None:
        console.print(f"IK data set: {summary['samples']:,} rows, {summary['mean_solutions']:.2f} solutions "
                      f"per pose on average, in {summary['store']}", highlight=False)
    else:
        _print_summary(summary)
        if "report" in summary:
            console.print(f"report: {summary['report']}", highlight=False)
