#!/usr/bin/env bash
# Real-vs-generated perfect-observation comparison (issue 10 item 2; results/realplans_vs_generated.md):
# imports the real development plans (../shared/realplans, not in the repository), then runs the
# same compare-matchers command (kernel, ray 36; 10 m, doors closed; 20 points per plan, seed 1)
# on six small real levels and on the shipped generated buildings, in transitional spaces (the
# default) and uniformly. Usage: scripts/realplans_vs_generated.sh [REALPLANS_DIR] [OUT_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
src=${1:-../shared/realplans}
out=${2:-out/calib}
bin=build/bin/floorcast
bash scripts/import_realplans.sh "$src" "$out/plans"
R=$out/plans
REAL=("$R/tum_studitum_L1.json" "$R/tum_studitum_L2.json" "$R/rwth_plt_L0.json" "$R/rwth_plt_L1.json"
      "$R/spbstu_no3_L2.json" "$R/spbstu_no3_L4.json")
GEN=(floorplans/buildings/apartment.json floorplans/buildings/angled.json floorplans/buildings/office.json)
run() { local name=$1; shift; "$bin" compare-matchers "$@" --points 20 --seed 1 --rays 36 --quiet -o "$out/$name"; }
run real_t "${REAL[@]}"
run gen_t "${GEN[@]}"
run real_u "${REAL[@]}" --uniform
run gen_u "${GEN[@]}" --uniform
for r in real_t gen_t real_u gen_u; do echo "== $r"; sed -n '/^Per building/,/^$/p;/^| method/,/^$/p' "$out/$r/summary.md"; done
