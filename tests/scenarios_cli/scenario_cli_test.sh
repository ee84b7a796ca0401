#!/usr/bin/env bash
# End-to-end checks of `floorcast run / merge / gate / compare-runs`:
#   resume: a run killed with SIGKILL and started again equals an uninterrupted run;
#   shards: shards 0/3, 1/3, 2/3 merged equal one run;
#   gate:   the healthy scenario passes its baseline, a degraded matcher parameter fails it; a
#           baseline with a scenario_hash refuses a summary of another configuration;
#   axes:   a merged run lists the sweep axes in the scenario's order and draws the same plots.
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
    "$fc" merge "$work/shard0" "$work/shard1" "$work/shard2" -o "$work/merged" --html > /dev/null 2> "$work/merge_err.txt"
    test -f "$work/merged/summary.json"
    # --html: the page `floorcast report` writes, beside the summary; the plans came along.
    grep -q "<table>" "$work/merged/report.html"
    test -f "$work/merged/plans/apartment.json"
    "$fc" merge --help | grep -q "summary.md" || { echo "merge --help does not say what it writes"; exit 1; }
    "$fc" compare-runs "$work/full" "$work/merged"
    # Merging again into the merged folder, and merging the merged folder itself, are no-ops
    # (units on disk may list their keys in another order: the values are compared).
    "$fc" merge "$work/shard0" "$work/shard1" "$work/shard2" -o "$work/merged" > /dev/null
    "$fc" merge "$work/merged" "$work/shard1" -o "$work/merged" > /dev/null
    "$fc" merge "$work/merged" -o "$work/merged2" > /dev/null
    "$fc" compare-runs "$work/full" "$work/merged2"
    ;;
  axes)
    # A merged report lists the sweep axes in the scenario's order, like a single run.
    axes=$(dirname "$data")/../report/axes.yaml
    run "$axes" -o "$work/full"
    for i in 0 1; do run "$axes" -o "$work/shard$i" --shard "$i/2"; done
    "$fc" merge "$work/shard0" "$work/shard1" -o "$work/merged" > /dev/null
    grep '^## c0' "$work/full/summary.md" > "$work/full_headings.txt"
    grep '^## c0' "$work/merged/summary.md" > "$work/merged_headings.txt"
    diff "$work/full_headings.txt" "$work/merged_headings.txt"
    head -1 "$work/full_headings.txt" | grep -q "observation.max_range_m = 8, observation.rays = 36, observation.doors_closed = true"
    ls "$work/full/plots" > "$work/full_plots.txt"
    ls "$work/merged/plots" > "$work/merged_plots.txt"
    diff "$work/full_plots.txt" "$work/merged_plots.txt"
    # One accuracy plot per axis (the zipped range/rays axis is one plot).
    test "$(grep -c '^accuracy_vs_' "$work/full_plots.txt")" -eq 2
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
    # A baseline measured on one configuration refuses a summary of another (scenario hash).
    hash=$(/usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['hash'])" "$work/healthy/summary.json")
    /usr/bin/python3 -c "import json,sys; b=json.load(open(sys.argv[1])); b['scenario_hash']=sys.argv[2]; json.dump(b, open(sys.argv[3],'w'))" \
      "$data/small_baseline.json" "$hash" "$work/hashed_baseline.json"
    "$fc" gate "$work/healthy/summary.json" --baseline "$work/hashed_baseline.json" > /dev/null
    set +e
    "$fc" gate "$work/degraded/summary.json" --baseline "$work/hashed_baseline.json" > "$work/gate_hash.txt" 2>&1
    status=$?
    set -e
    cat "$work/gate_hash.txt"
    if [ "$status" -ne 2 ]; then echo "a summary of another configuration was not refused (status $status)"; exit 1; fi
    grep -q "differs from the hash" "$work/gate_hash.txt"
    ;;
  *) echo "unknown test $what"; exit 2 ;;
esac
echo "ok: $what"
