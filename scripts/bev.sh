#!/usr/bin/env bash
# The semantic BEV matcher's measurements (issue 27; results/bev.md): scenarios/bev.yaml on the
# calibrated buildings, the same cells on the six small real development levels (imported from
# ../shared/realplans, not in the repository), the predictor sweep (bev_sweep.yaml) and the
# sequential protocol (bev_sequential.yaml), then the tables (scripts/bev_tables.py).
# Usage: scripts/bev.sh [REALPLANS_DIR] [OUT_DIR]    env: JOBS (default 2), SKIP (space-separated
#   run names to skip: calibrated realplans sweep sequential), PROFILE (full, the default: the
#   scenarios as written, ~2-3 h of CPU; shared: the reduced counts results/bev.md was measured
#   with on a shared 2-core machine, ~1 h wall: the single-shot runs (calibrated 12 points per
#   building, real levels 8) on five of the ten cells, single x {perfect, structured3d_good,
#   structured3d_bad} and full x {perfect, structured3d_good}; sweep 6 points per building;
#   sequential 4 walks per building)
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
profile=${PROFILE:-full}
case "$profile" in full | shared) ;; *) echo "PROFILE must be full or shared" >&2; exit 2 ;; esac
mkdir -p "$out"
run() {  # name scenario
  case "$skip" in *" $1 "*) return 0 ;; esac
  "$bin" run "$2" -o "$out/$1" --jobs "$jobs" --quiet > "$out/$1.md"
}
# The scenario as run: as written (full) or with the shared profile's counts and cells, written
# next to the results (the run directory's resolved_config.json states it too).
profiled() {  # name scenario points-per-building -> path of the scenario to run
  if [ "$profile" = full ]; then echo "$2"; return; fi
  local f="$out/$1_shared.yaml"
  sed -E "s/^sampling: \{count: [0-9]+,/sampling: {count: $3,/" "$2" > "$f"
  if [ "$1" = calibrated ]; then  # one sweep axis of five (setting, preset) cells
    python3 - "$f" <<'PY'
import re, sys
p = sys.argv[1]
s = open(p).read()
cells = ("sweep:\n  - observation.setting: [single, single, single, full, full]\n"
         "    observation.observe_params.bev.preset: [perfect, structured3d_good, structured3d_bad, perfect, structured3d_good]\n")
s = re.sub(r"^sweep:\n(?:  .*\n)+", cells, s, flags=re.M)
open(p, "w").write(s)
PY
  fi
  echo "$f"
}
run calibrated "$(profiled calibrated scenarios/bev.yaml 12)"
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
    sed -n '/^sampling:/,$p' "$(profiled calibrated scenarios/bev.yaml 12)" |
      sed -E "s/^sampling: \{count: [0-9]+, seed: 27, clearance_m: 0.5\}/sampling: {count: 8, seed: 27, clearance_m: 0.5, region: uniform}/"
  } > "$out/bev_realplans.yaml"
  run realplans "$out/bev_realplans.yaml"
else
  echo "real plans not found (pass REALPLANS_DIR): skipping them" >&2
fi
run sweep "$(profiled sweep scenarios/bev_sweep.yaml 6)"
run sequential "$(profiled sequential scenarios/bev_sequential.yaml 4)"
python3 scripts/bev_tables.py "$out"
