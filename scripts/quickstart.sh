#!/usr/bin/env bash
# The README's main command: installs dependencies, builds, and runs the main job on the
# built-in buildings.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
bash scripts/build.sh
out=${1:-out/quickstart}
mkdir -p "$out"
for plan in floorplans/buildings/*.json; do
  echo "== $plan"
  build/bin/floorcast plan info "$plan"
done
