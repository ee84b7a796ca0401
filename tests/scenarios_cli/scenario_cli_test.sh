#!/usr/bin/env bash
# End-to-end checks of `floorcast run / merge / gate / compare-runs`:
#   resume: a run killed with SIGKILL and started again equals an uninterrupted run;
#   shards: shards 0/3, 1/3, 2/3 merged equal one run;
#   gate:   the healthy scenario passes its baseline, a degraded matcher parameter fails it.
set -euo pipefail
fc=$1
data=$2
work=$3
what=$4
rm -rf "$work"
mkdir -p "$work"
run() { "$fc" run "$@" --quiet > /dev/null; }

case "$what" in
  resume)
    run "$data/small.yaml" -o "$work/full" --jobs 2
    test -f "$work/full/summary.json"
    # Start, wait for a few finished units, kill hard, resume.
    "$fc" run "$data/small.yaml" -o "$work/killed" --jobs 1 --quiet > /dev/null 2>&1 &
    pid=$!
    for _ in $(seq 1 600); do
      n=$( (find "$work/killed/units" -name '*.json' 2>/dev/null || true) | wc -l)
      [ "$n" -ge 4 ] && break
      sleep 0.05
    done
    kill -9 "$pid" 2>/dev/null || true
    wait "$pid" 2>/dev/null || true
    n=$(find "$work/killed/units" -name '*.json' | wc -l)
    echo "killed after $n of 32 units"
    if [ "$n" -ge 32 ]; then echo "run finished before it could be killed"; exit 1; fi
    test ! -f "$work/killed/summary.json"
    run "$data/small.yaml" -o "$work/killed" --jobs 2
    "$fc" compare-runs "$work/full" "$work/killed"
    ;;
  shards)
    run "$data/small.yaml" -o "$work/full"
    for i in 0 1 2; do run "$data/small.yaml" -o "$work/shard$i" --shard "$i/3"; done
    test ! -f "$work/shard0/summary.json"
    # Merging a subset must refuse to report.
    if "$fc" merge "$work/shard0" "$work/shard1" -o "$work/partial" > /dev/null 2>&1; then
      echo "merge of 2 of 3 shards claimed success"; exit 1
    fi
    "$fc" merge "$work/shard0" "$work/shard1" "$work/shard2" -o "$work/merged" > /dev/null
    test -f "$work/merged/summary.json"
    "$fc" compare-runs "$work/full" "$work/merged"
    ;;
  gate)
    run "$data/small.yaml" -o "$work/healthy"
    "$fc" gate "$work/healthy/summary.json" --baseline "$data/small_baseline.json"
    run "$data/degraded.yaml" -o "$work/degraded"
    set +e
    "$fc" gate "$work/degraded/summary.json" --baseline "$data/small_baseline.json" > "$work/gate.txt" 2>&1
    status=$?
    set -e
    cat "$work/gate.txt"
    if [ "$status" -ne 1 ]; then echo "degraded run passed the gate (status $status)"; exit 1; fi
    grep -q "accuracy regression" "$work/gate.txt"
    ;;
  *) echo "unknown test $what"; exit 2 ;;
esac
echo "ok: $what"
