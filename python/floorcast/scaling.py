"""Scale a scenario out over a Dask cluster through the Python API (docs/scaling.md).

    from distributed import Client, LocalCluster   # Debian: python3-distributed
    import floorcast.scaling
    with LocalCluster(n_workers=4, threads_per_worker=1) as cluster, Client(cluster) as client:
        summary = floorcast.scaling.run_on_dask(client, "scenarios/full_system.yaml", "runs/full_system", shards=16)

Each shard ("I/N" of the scenario's fixed unit order) runs as one task in a worker process through
``floorcast.run_scenario(..., shard="I/N")`` into OUT/shard_I; ``floorcast.merge_runs`` then
combines them into OUT/merged, whose results equal a single-machine run (units are deterministic,
see docs/scaling.md). A task that fails is retried by Dask (``retries``); a shard that was killed
resumes its finished units. Works with any ``distributed`` client: LocalCluster, SSH, Slurm
(dask-jobqueue), Kubernetes.
"""
import os


def run_shard(scenario, out, shard, jobs=1):
    """One shard in a worker: returns its folder (for the merge)."""
    import floorcast
    floorcast.run_scenario(scenario, out, jobs=jobs, quiet=True, shard=shard)
    return out


def run_on_dask(client, scenario, out_root, shards, jobs_per_shard=1, retries=1):
    """Runs `shards` shards of `scenario` on the client's workers, merges them into
    out_root/merged and returns its summary (a dict of summary.json)."""
    import floorcast
    if shards < 1:
        raise ValueError("shards must be >= 1")
    scenario = os.path.abspath(scenario)
    out_root = os.path.abspath(out_root)
    futures = [client.submit(run_shard, scenario, os.path.join(out_root, "shard_%d" % i), "%d/%d" % (i, shards),
                             jobs_per_shard, pure=False, retries=retries, key="floorcast-shard-%d-of-%d" % (i, shards))
               for i in range(shards)]
    dirs = client.gather(futures)
    return floorcast.merge_runs(dirs, os.path.join(out_root, "merged"))
