"""Batch evaluation on real local Ray and Dask clusters (2 CPUs each; slow: cluster startup).

The three executors must give the same DataFrame on the same batch (every column but the
wall times): ``tests/test_batch.py`` checks the local process pool against this process.
"""

import math

import pytest
from test_batch import same_table

import pinograsp as pg

pd = pytest.importorskip("pandas")
pytestmark = pytest.mark.slow

BOX = pg.ObjectSpec("box", size=(0.1462, 0.05, 0.10), xyz=(0.0, 0.0, 0.0678))
SCORE = pg.WorstAxisScore(upper=20, steps=4)


def _batch():
    """Scenes, an auto-closed + auto-preloaded Barrett grasp at sampled poses, and failures."""
    sampled = pg.sample_grasps("barrett_bh8_282", BOX, 3, seed=7, q_open={"bh_j11": math.pi / 2})
    return ["pinch", "wedge", "case1", *sampled, "no_such_scene"]


@pytest.fixture(scope="module")
def reference():
    return pg.evaluate_grasps(_batch(), score=SCORE, workers=1)


@pytest.fixture(scope="module")
def ray_cluster():
    ray = pytest.importorskip("ray")
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    yield ray
    ray.shutdown()


@pytest.fixture(scope="module")
def dask_client():
    distributed = pytest.importorskip("distributed")
    cluster = distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0"
    )
    client = distributed.Client(cluster)
    yield client
    client.close()
    cluster.close()


def test_reference_batch_has_ok_and_error_rows(reference):
    assert (reference["status"] == "ok").sum() >= 4
    assert reference["status"].iloc[-1] == "error"


def test_ray_existing_connection(ray_cluster, reference):
    done = []
    df = pg.evaluate_grasps(_batch(), score=SCORE, executor="ray", progress=lambda d, t: done.append(d))
    same_table(df, reference)
    assert done[-1] == len(reference)
    assert ray_cluster.is_initialized()  # an existing connection is left open


def test_ray_lambda_score(ray_cluster):
    df = pg.evaluate_grasps(["pinch", "wedge"], score=lambda m, c: {"nc": m.nc}, executor="ray", workers=2)
    assert df["nc"].tolist() == [2, 2]


def test_dask_client(dask_client, reference):
    same_table(pg.evaluate_grasps(_batch(), score=SCORE, executor=dask_client), reference)


def test_dask_address(dask_client):
    df = pg.evaluate_grasps(
        ["pinch"],
        score=lambda m, c: {"nc": m.nc},
        executor="dask",
        address=dask_client.cluster.scheduler_address,
    )
    assert df["nc"].tolist() == [2]


def test_three_executors_identical(ray_cluster, dask_client, reference):
    local = pg.evaluate_grasps(_batch(), score=SCORE, executor="local", workers=2)
    ray_df = pg.evaluate_grasps(_batch(), score=SCORE, executor="ray", workers=2)
    dask_df = pg.evaluate_grasps(_batch(), score=SCORE, executor=dask_client)
    for df in (local, ray_df, dask_df):
        same_table(df, reference)


def test_owned_clusters_start_and_stop():
    """executor='dask' / 'ray' without a cluster: a 2-worker local one, closed afterwards."""
    ray = pytest.importorskip("ray")
    pytest.importorskip("distributed")
    if ray.is_initialized():
        ray.shutdown()
    ref = pg.evaluate_grasps(["pinch", "wedge"], score=SCORE, workers=1)
    same_table(pg.evaluate_grasps(["pinch", "wedge"], score=SCORE, executor="dask", workers=2), ref)
    same_table(pg.evaluate_grasps(["pinch", "wedge"], score=SCORE, executor="ray", workers=2), ref)
    assert not ray.is_initialized()
