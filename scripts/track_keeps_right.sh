#!/usr/bin/env bash
# Do walks whose initial single-shot estimate is right stay right? (issue 20's check; numbers in
# results/sequential.md). For each seed: `floorcast sim walk PLAN --seed S` (a perfect initial
# scan, then no observation), `floorcast track` with the given filter; a walk "starts right" when
# the tracker's step-0 estimate is within 1 m of the truth (hist: the belief's argmax, i.e. the ray
# matcher's single-shot mode; pf: the mean of all particles, rarely right before convergence), and
# "stays right" when its last estimate is within 1.5 m. Prints one line per walk and the counts.
#
#   scripts/track_keeps_right.sh [-p PLAN] [-s "1 2 ..."] [-n STEPS] [-f hist|pf] [-o OUT] [-- TRACKER_PARAM ...]
#   e.g. scripts/track_keeps_right.sh -- motion_noise=fixed     (the papers' fixed noise)
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${FLOORCAST:-build/bin/floorcast}
plan=floorplans/buildings/office_calibrated.json
seeds="1 2 3 4 5 6 7 8"
steps=120
filter=hist
out=out/track_keeps_right
while getopts "p:s:n:f:o:" opt; do
  case $opt in
    p) plan=$OPTARG ;;
    s) seeds=$OPTARG ;;
    n) steps=$OPTARG ;;
    f) filter=$OPTARG ;;
    o) out=$OPTARG ;;
    *) sed -n 2,10p "$0" >&2; exit 2 ;;
  esac
done
shift $((OPTIND - 1))
params=()
for p in "$@"; do params+=(--tracker-param "$p"); done
mkdir -p "$out"
right=0
stayed=0
for s in $seeds; do
  "$bin" sim walk "$plan" --seed "$s" --steps "$steps" --odometry vio -o "$out/walk_$s" > /dev/null
  "$bin" track "$plan" "$out/walk_$s" --filter "$filter" --quiet "${params[@]}" -o "$out/track_$s" > /dev/null
  # errors.csv: position_error_m is column 10; first data row = step 0, last row = the end.
  read -r first last < <(awk -F, 'NR == 2 {f = $10} END {print f, $10}' "$out/track_$s/errors.csv")
  verdict=$(awk -v f="$first" -v l="$last" 'BEGIN {print (f < 1.0) ? ((l <= 1.5) ? "starts right, stays right" : "starts right, lost") : "starts wrong"}')
  printf 'seed %s: step-0 error %.2f m, end error %.2f m: %s\n' "$s" "$first" "$last" "$verdict"
  case $verdict in
    "starts right, stays right") right=$((right + 1)); stayed=$((stayed + 1)) ;;
    "starts right, lost") right=$((right + 1)) ;;
  esac
done
echo "starts right: $right walks; of them within 1.5 m at the end: $stayed"
