"""Scale-out through the Python API on a real Dask cluster (issue 24): a distributed LocalCluster
of worker processes runs three shards of a scenario (floorcast.scaling.run_on_dask ->
floorcast.run_scenario(shard=...)), floorcast.merge_runs combines them, and the merged run holds
exactly the units (timings aside) and the summary of a single-machine run. Prints its wall time.

Run by ctest as python_dask (label `scaling`); Debian python3-distributed.
"""
import glob
import json
import os
import shutil
import time

import floorcast as fc
import floorcast.scaling

OUT = os.environ.get("FLOORCAST_TEST_OUT", "/tmp/floorcast_pytest")
SCENARIO = os.path.join(fc.data_dir(), "tests", "scenarios_cli", "data", "small.yaml")


def units_without_timings(run):
    out = {}
    for path in glob.glob(os.path.join(run, "units", "**", "*.json"), recursive=True):
        with open(path) as f:
            u = json.load(f)
        u.pop("timings", None)
        out[u["id"]] = u
    return out


def _drop_timings(x):
    """Everything but timings (keys naming a time or timing: measured, not results)."""
    if isinstance(x, dict):
        return {k: _drop_timings(v) for k, v in x.items() if "time" not in k and "timing" not in k}
    if isinstance(x, list):
        return [_drop_timings(v) for v in x]
    return x


def summary_without_timing(run):
    with open(os.path.join(run, "summary.json")) as f:
        return _drop_timings(json.load(f))


def test_dask_local_cluster_shards_merge_to_the_single_machine_run():
    import distributed  # Debian python3-distributed (scripts/install_deps.sh)
    root = os.path.join(OUT, "dask")
    shutil.rmtree(root, ignore_errors=True)
    os.makedirs(root)
    t0 = time.monotonic()
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0",
                                  silence_logs=40) as cluster, distributed.Client(cluster) as client:
        t1 = time.monotonic()
        merged = floorcast.scaling.run_on_dask(client, SCENARIO, root, shards=3)
        t2 = time.monotonic()
    assert merged["complete"] is True
    for i in range(3):
        assert os.path.isfile(os.path.join(root, "shard_%d" % i, "run.json"))
        assert not os.path.isfile(os.path.join(root, "shard_%d" % i, "summary.json"))  # a shard is not a run
    single = os.path.join(root, "single")
    fc.run_scenario(SCENARIO, single, jobs=1)
    a, b = units_without_timings(os.path.join(root, "merged")), units_without_timings(single)
    assert len(a) == merged["units"] and a.keys() == b.keys()
    for k in a:
        assert a[k] == b[k], k
    assert summary_without_timing(os.path.join(root, "merged")) == summary_without_timing(single)
    print("dask: cluster start %.1f s, 3 shards + merge %.1f s wall" % (t1 - t0, t2 - t1))
