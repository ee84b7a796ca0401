#!/usr/bin/env bash
# Real development plans vs each generated archetype (issue 10 item 2; results/realplans_vs_generated.md):
# imports the real development plans (../shared/realplans, not in the repository), generates every
# archetype (calibrated office/angled/campus, campus_blocks, the *_repetitive hard cases, apartment) for a few
# seeds, and prints side by side: structure measures (`floorcast plan stats`) and perfect-observation
# success of the kernel and ray matchers (`floorcast compare-matchers`: 10 m, doors closed, seed 1)
# in transitional spaces and uniformly, with near-equivalent poses and the real per-plan range.
# Usage: scripts/realplans_vs_generated.sh [REALPLANS_DIR] [OUT_DIR] [extra options of the .py]
set -euo pipefail
cd "$(dirname "$0")/.."
src=${1:-}
if [ -z "$src" ]; then  # ../shared/realplans next to the checkout (worktrees: one level further up)
  for d in ../shared/realplans ../../shared/realplans /work/shared/realplans; do [ -d "$d" ] && src=$d && break; done
fi
[ -d "$src" ] || { echo "real plans not found (pass REALPLANS_DIR)" >&2; exit 2; }
out=${2:-out/calib}
shift $(( $# > 2 ? 2 : $# ))
bin=${FLOORCAST:-build/bin/floorcast}
FLOORCAST=$bin bash scripts/import_realplans.sh "$src" "$out/plans"
python3 scripts/realplans_vs_generated.py --bin "$bin" --plans "$out/plans" --out "$out" "$@"
