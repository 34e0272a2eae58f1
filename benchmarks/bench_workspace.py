"""Workspace maps at scale: reachability samples/s, dexterity IK solves/s, Dask overhead vs local threads.

Targets of issue 13 (on this 2-core machine): 1e8
reachability samples of a 6R arm in under 60 s; 1e6 dexterity IK solves (1e4 voxels x 100
orientations) in under 30 s; a 2-worker Dask LocalCluster within 20 % of the local threads.
This prints what the current kernels do; sizes are scaled down by default (``--samples``,
``--voxels`` to change them, ``--quick`` for a smoke run) and the rates extrapolated.

Run: python benchmarks/bench_workspace.py [--quick] [--samples 1e7] [--voxels 1e4] [--repeat 3]
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

import armkit
from armkit import workspace
from armkit.workspace.dexterity import candidate_voxels


def _run(label: str, function, work: float, unit: str, target_work: float,
         target_seconds: float) -> tuple[float, object]:
    start = time.perf_counter()
    result = function()
    seconds = time.perf_counter() - start
    rate = work / seconds
    print(f"{label:<44} {work:>12.3g} {unit:<14} {seconds:8.2f} s {rate:12.3g} {unit}/s   "
          f"-> {target_work:.0e} in ~{target_work / rate:7.1f} s (target {target_seconds:.0f} s)", flush=True)
    return seconds, result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=float, default=1e7, help="reachability samples (default 1e7)")
    parser.add_argument("--voxels", type=float, default=2e3, help="dexterity voxels x 100 orientations")
    parser.add_argument("--repeat", type=lambda text: max(1, int(text)), default=3,
                        help="turns of local and Dask runs (default 3, at least 1)")
    parser.add_argument("--quick", action="store_true", help="small sizes (a smoke run)")
    args = parser.parse_args()
    samples, voxels = (int(2e5), 200) if args.quick else (int(args.samples), int(args.voxels))
    robot = armkit.load("probot-anno")
    cores = os.cpu_count()
    print(f"PROBOT Anno (6R), resolution 0.02 m, {cores} local cores; compiled core, warmed first")
    workspace.compute(robot, resolution=0.1, samples=2000, manipulability_samples=200, orientations=2)

    _, local = _run("reachability, local threads", lambda: workspace.reachability(
        robot, resolution=0.02, samples=samples), samples, "samples", 1e8, 60)

    grid = local.grid
    chosen = np.flatnonzero(local.occupied.ravel())
    chosen = chosen[np.linspace(0, len(chosen) - 1, min(voxels, len(chosen))).astype(int)]
    mask = np.zeros(grid.size, dtype=bool)
    mask[chosen] = True
    # Only the chosen voxels: a reachability map holding them alone (their neighbours are added).
    sparse = workspace.ReachabilityMap(grid, mask.reshape(grid.shape).astype(np.int64), local.plan,
                                       local.chunks_done)
    tested = len(candidate_voxels(grid, robot, sparse))
    _run(f"dexterity, {tested} voxels x 100 orientations", lambda: workspace.dexterity(
        robot, reach=sparse, orientations=100), tested * 100, "IK solves", 1e6, 30)

    try:
        import distributed
    except ImportError:
        print("dask.distributed not installed: no Dask comparison (pip install 'armkit[workspace]')")
        return
    with distributed.LocalCluster(n_workers=cores, threads_per_worker=1, dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        workspace.reachability(robot, resolution=0.1, samples=2000, engine=client)  # workers load kernels
        _compare_engines(robot, samples, args.repeat, client, local.hits)


def _compare_engines(robot, samples: int, repeat: int, client, local_hits) -> None:
    """Dask against local threads, run in turns (local, Dask, local, ...) so that both see the same
    load on a shared machine; prints each pair's ratio, their median and the smallest, and how the
    Dask time grows from a tenth of the samples (linear growth: a ratio near 10)."""
    ratios, same = [], True
    for turn in range(repeat):
        local_seconds, _ = _run("reachability, local threads", lambda: workspace.reachability(
            robot, resolution=0.02, samples=samples), samples, "samples", 1e8, 60)
        dask_seconds, remote = _run(
            f"reachability, Dask LocalCluster ({len(client.nthreads())} processes)",
            lambda: workspace.reachability(robot, resolution=0.02, samples=samples, engine=client),
            samples, "samples", 1e8, 60)
        same &= bool(np.array_equal(remote.hits, local_hits))
        ratios.append(dask_seconds / local_seconds)
        print(f"  turn {turn + 1}: Dask / local time {ratios[-1]:.2f}", flush=True)
    tenth, _ = _run("reachability, Dask, a tenth of the samples", lambda: workspace.reachability(
        robot, resolution=0.02, samples=samples // 10, engine=client), samples // 10, "samples", 1e8, 60)
    print(f"Dask / local time over {repeat} turns: median {np.median(ratios):.2f}, "
          f"smallest {min(ratios):.2f} (target < 1.20); identical counts: {same}; "
          f"Dask time x{dask_seconds / tenth:.1f} for 10x the samples (linear: 10)")

if __name__ == "__main__":
    main()
