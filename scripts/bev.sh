#!/usr/bin/env bash
# The semantic BEV matcher's measurements (issue 27; results/bev.md): scenarios/bev.yaml on the
# calibrated buildings, the same cells on the six small real development levels (imported from
# ../shared/realplans, not in the repository), the predictor sweep (bev_sweep.yaml) and the
# sequential protocol (bev_sequential.yaml), then the tables (scripts/bev_tables.py).
# Usage: scripts/bev.sh [REALPLANS_DIR] [OUT_DIR]    env: JOBS (default 2), SKIP (space-separated
#   run names to skip: calibrated realplans sweep sequential)
set -euo pipefail
cd "$(dirname "$0")/.."
src=${1:-}
if [ -z "$src" ]; then  # ../shared/realplans next to the checkout (worktrees: one level further up)
  for d in ../shared/realplans ../../shared/realplans /work/shared/realplans; do [ -d "$d" ] && src=$d && break; done
fi
out=${2:-out/bev}
bin=$(realpath "${FLOORCAST:-build/bin/floorcast}")
jobs=${JOBS:-2}
skip=" ${SKIP:-} "
mkdir -p "$out"
run() {  # name scenario
  case "$skip" in *" $1 "*) return 0 ;; esac
  "$bin" run "$2" -o "$out/$1" --jobs "$jobs" --quiet > "$out/$1.md"
}
run calibrated scenarios/bev.yaml
if [ -n "$src" ] && [ -d "$src" ]; then
  FLOORCAST=$bin bash scripts/import_realplans.sh "$src" "$out/plans"
  # The same scenario on the six small real levels (the real development set of
  # results/realplans_vs_generated.md), sampled uniformly where a level has no labelled
  # transitional space.
  {
    sed -n '/^name:/,/^buildings:/p' scenarios/bev.yaml | sed 's/^name: bev$/name: bev_realplans/'
    for l in tum_studitum_L1 tum_studitum_L2 rwth_plt_L0 rwth_plt_L1 spbstu_no3_L2 spbstu_no3_L4; do
      echo "  - $(realpath "$out/plans/$l.json")"
    done
    sed -n '/^sampling:/,$p' scenarios/bev.yaml | sed 's/^sampling: {count: 12, seed: 27, clearance_m: 0.5}/sampling: {count: 8, seed: 27, clearance_m: 0.5, region: uniform}/'
  } > "$out/bev_realplans.yaml"
  run realplans "$out/bev_realplans.yaml"
else
  echo "real plans not found (pass REALPLANS_DIR): skipping them" >&2
fi
run sweep scenarios/bev_sweep.yaml
run sequential scenarios/bev_sequential.yaml
python3 scripts/bev_tables.py "$out"
