"""The same chunks on a Dask LocalCluster give the same maps, bit for bit, as the local threads.

The cluster runs its two workers as threads of this process (``processes=False``) to keep
the test quick; ``armkit workspace --dask local`` and a real scheduler use worker
processes, which get the same tasks (they pickle: a function and plain data).
"""

from __future__ import annotations

import importlib
import pickle
from functools import partial

import numpy as np
import pytest
from conftest import WAIT_S

import armkit
from armkit import workspace
from armkit.robot_file import robot_to_toml

dask = pytest.importorskip("dask")
distributed = pytest.importorskip("distributed")
pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def client():
    # Dask's own 30 s connection timeouts are wall-clock guesses too: as generous as the tests' waits
    timeouts = {"distributed.comm.timeouts.connect": f"{WAIT_S}s",
                "distributed.comm.timeouts.tcp": f"{WAIT_S}s"}
    with dask.config.set(timeouts):
        cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                                           dashboard_address=None)
        client = distributed.Client(cluster, timeout=f"{WAIT_S}s")
        yield client
        client.close()
        cluster.close()


def test_dask_gives_identical_counts_and_sums_to_the_local_run(client):
    robot = armkit.load("probot-anno")
    settings = {"resolution": 0.06, "samples": 60_000, "chunk_size": 6_000, "manipulability_samples": 6_000,
                "orientations": 5, "seed": 11}
    local = workspace.compute(robot, engine=2, **settings)
    remote = workspace.compute(robot, engine=client, **settings)
    np.testing.assert_array_equal(remote.reachability.hits, local.reachability.hits)
    for key, values in local.manipulability.arrays.items():
        np.testing.assert_array_equal(remote.manipulability.arrays[key], values, err_msg=key)
    np.testing.assert_array_equal(remote.dexterity.reachable_fraction, local.dexterity.reachable_fraction)
    assert remote.summary()["reachable_volume"] == local.summary()["reachable_volume"]


def test_sobol_chunks_on_dask_match_too(client):
    robot = armkit.load("ur5")
    local = workspace.reachability(robot, resolution=0.1, samples=2**14, chunk_size=2**11, method="sobol")
    remote = workspace.reachability(robot, resolution=0.1, samples=2**14, chunk_size=2**11, method="sobol",
                                    engine=client)
    np.testing.assert_array_equal(remote.hits, local.hits)


def test_tasks_pickle_for_worker_processes():
    robot = armkit.load("puma560")
    grid = workspace.grid_for(robot, 0.2)
    reach = importlib.import_module("armkit.workspace.reachability")
    task = partial(reach._hits_of_chunks, reach._Task(robot_to_toml(robot), grid,
                                                      reach.SamplePlan(1000, chunk_size=100)))
    again = pickle.loads(pickle.dumps(task))
    np.testing.assert_array_equal(again((3, 4))[1], task((3, 4))[1])
