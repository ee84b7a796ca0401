#!/usr/bin/env bash
# The README's main command: installs dependencies, builds, and runs the main job on the
# built-in buildings: generates one building of every archetype (the seeds of the shipped files in
# floorplans/buildings/), renders each to PNG, and prints its summary.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
bash scripts/build.sh
out=${1:-out/quickstart}
mkdir -p "$out"
cli=build/bin/floorcast
for spec in apartment:1 office:4 campus:5 angled:2; do
  archetype=${spec%%:*}
  seed=${spec##*:}
  echo "== $archetype (seed $seed)"
  "$cli" plan generate --archetype "$archetype" --seed "$seed" -o "$out/$archetype.json" \
    --rooms "$out/$archetype.rooms.json"
  "$cli" plan render "$out/$archetype.json" -o "$out/$archetype.png"
  "$cli" plan info "$out/$archetype.json"
done
echo "== outputs in $out/: <archetype>.json (plan), <archetype>.rooms.json (rooms), <archetype>.png (drawing)"
