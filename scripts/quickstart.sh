#!/usr/bin/env bash
# The README's main command: installs dependencies, builds, and runs the quickstart benchmark
# (scenarios/quickstart.yaml): the PALMS kernel matcher vs the F3Loc ray matcher on perfect
# observations of the four shipped synthetic buildings. Prints the scored table; everything
# (observations.csv, summary.json, summary.md, plots/, heatmaps/, resolved config) lands in
# out/quickstart/ (or the folder given as the first argument). Under 2 minutes on 2 cores after
# the build.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
bash scripts/build.sh
out=${1:-out/quickstart}
rm -rf "$out"
build/bin/floorcast run scenarios/quickstart.yaml -o "$out"
echo
echo "== results in $out/: summary.md (tables above), summary.json, observations.csv, plots/*.png, heatmaps/*.png"
