#!/usr/bin/env bash
# Scale-out on a real Slurm cluster (issue 24): a single-node cluster on localhost
# (slurm_cluster.sh), docs/floorcast_array.sbatch submitted as a job array of 3 shards, the merge
# submitted as a job that depends on the array, and the merged run compared with a
# single-machine run of the same scenario (`floorcast compare-runs`: identical, timings aside).
#
#   slurm_test.sh FLOORCAST_EXE SCENARIO.yaml WORK_DIR
#
# Prints the wall time of the cluster part; "ok: slurm" on success.
set -euo pipefail
fc=$(readlink -f "$1")
scenario=$(readlink -f "$2")
work=$3
src=$(cd "$(dirname "$0")/../.." && pwd)
rm -rf "$work"
mkdir -p "$work"
work=$(cd "$work" && pwd)
cluster="$work/cluster"
trap 'bash "$src/tests/scaling/slurm_cluster.sh" stop "$cluster"' EXIT
eval "export $(bash "$src/tests/scaling/slurm_cluster.sh" start "$cluster")"
export FLOORCAST="$fc"
t0=$(date +%s.%N)
cd "$work"
shards=3
# The sbatch file asks for 4 cores and 8 GB per task (a real cluster); the test node is smaller.
array=$(sbatch --parsable --array=0-$((shards - 1)) --cpus-per-task=1 --mem=1G --time=00:20:00 \
  -o "$work/slurm-%A_%a.out" "$src/docs/floorcast_array.sbatch" "$scenario" "$work/runs")
merge=$(sbatch --parsable --dependency=afterok:"$array" --cpus-per-task=1 --mem=1G -o "$work/slurm-merge-%j.out" \
  --wrap "\"$fc\" merge $work/runs/shard_* -o $work/runs/merged")
echo "submitted array job $array ($shards tasks) and merge job $merge (afterok:$array)"
for _ in $(seq 1200); do
  if [ -z "$(squeue -h -j "$array,$merge" 2>/dev/null)" ]; then break; fi
  sleep 0.5
done
if [ -n "$(squeue -h -j "$array,$merge" 2>/dev/null)" ]; then
  squeue; echo "FAILED: jobs still queued or running after 10 minutes"; exit 1
fi
t1=$(date +%s.%N)
for i in $(seq 0 $((shards - 1))); do
  [ -f "$work/runs/shard_$i/run.json" ] || { cat "$work"/slurm-*.out; echo "FAILED: shard $i did not run"; exit 1; }
done
[ -f "$work/runs/merged/summary.json" ] || { cat "$work"/slurm-*.out; echo "FAILED: the merge job wrote no report"; exit 1; }
"$fc" run "$scenario" -o "$work/single" --quiet > /dev/null
"$fc" compare-runs "$work/runs/merged" "$work/single"
awk -v n="$shards" -v a="$t0" -v b="$t1" 'BEGIN { printf "slurm: %d shards + dependent merge in %.1f s wall (submission to merged report)\n", n, b - a }'
echo "ok: slurm"
