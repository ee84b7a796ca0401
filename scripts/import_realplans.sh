#!/usr/bin/env bash
# Imports every level of the real development set (../shared/realplans) into plan JSONs, with each
# import's report (`plan import --json`: faithfulness check, repairs, notes, warnings) in
# OUT/reports/NAME.json.
set -euo pipefail
bin=${FLOORCAST:-build/bin/floorcast}
src=${1:-../shared/realplans}
out=${2:-out/realplans}
mkdir -p "$out/reports"
imp() {  # the last two arguments are -o FILE
  local plan=${*: -1}
  "$bin" plan import "$@" --json > "$out/reports/$(basename "$plan")"
}
for l in 0 1 2; do imp "$src/spbstu_polytech" -f imdf --level $l --building "Main academic building" -o "$out/spbstu_main_L$l.json"; done
for l in 1 2 3 4 5; do imp "$src/spbstu_polytech" -f imdf --level $l --building "Academic building №3" -o "$out/spbstu_no3_L$l.json"; done
for l in -1 0 1 2 3; do imp "$src/rwth_aachen_plt/aachen.osm" -f osm --level $l -o "$out/rwth_plt_L$l.json"; done
for l in -1 0 1; do imp "$src/grenoble_caserne_de_bonne/caserne.osm" -f osm --level $l -o "$out/grenoble_mall_L$l.json"; done
for l in -1 0 1 2 3 4; do imp "$src/tum_garching_studitum/studitum.geojson" -f geojson --level $l -o "$out/tum_studitum_L$l.json"; done
