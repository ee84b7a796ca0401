#!/usr/bin/env bash
# The sanitizer run (issue 13; part of .ci/run): AddressSanitizer + UndefinedBehaviorSanitizer
# build of the input parsers (core, floorplans: plan JSON, the CSV/OSM/S3D/IMDF/PNG importers,
# observation JSON, scan.json) in build-asan/, which replays every parser input kept in the
# repository (test fixtures, shipped buildings, the adversarial corpus's data) and generated
# hostile inputs (100,000-deep nesting, 100,000-digit numbers, long strings) through the fuzz
# targets (fuzz/NAME.cpp, as NAME_replay). Any sanitizer report, signal or exception other than a
# clear InputError fails it. Small on purpose (~35 source files, a few minutes on 2 cores);
#   FLOORCAST_SANITIZE_ALL=1 bash scripts/sanitize.sh
# also builds the scenario loader (all libraries) and replays the scenario YAML inputs.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh

TARGETS=(fuzz_plan_json fuzz_import_csv fuzz_import_osm fuzz_import_s3d fuzz_import_imdf fuzz_import_png
         fuzz_observation_json fuzz_scan_json)
if [ "${FLOORCAST_SANITIZE_ALL:-0}" = "1" ]; then TARGETS+=(fuzz_scenario_yaml); fi

FLAGS="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer -g -O1"
launcher=()
if command -v ccache >/dev/null 2>&1; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache); fi
cmake -S . -B build-asan -DCMAKE_C_FLAGS="$FLAGS" -DCMAKE_CXX_FLAGS="$FLAGS" \
  -DFLOORCAST_BUILD_FUZZ_REPLAY=ON -DFLOORCAST_BUILD_TESTS=OFF -DFLOORCAST_BUILD_BENCHMARKS=OFF \
  "${launcher[@]}" >/dev/null
replays=()
for t in "${TARGETS[@]}"; do replays+=("${t}_replay"); done
cmake --build build-asan -j"${FLOORCAST_SANITIZE_JOBS:-$(nproc)}" --target "${replays[@]}"

# Generated hostile inputs (not kept in git: large).
GEN=build-asan/sanitize_inputs
rm -rf "$GEN"
mkdir -p "$GEN"/{json,yaml,xml,csv,imdf}
repeat() { local s=$1 n=$2 out=""; out=$(printf "%${n}s" "" | sed "s/ /$s/g"); printf '%s' "$out"; }
deep=$(repeat '[' 100000)
printf '%s' "$deep" > "$GEN/json/deep_array.json"
printf '{"format_version":%s}' "$deep" > "$GEN/json/deep_version.json"
printf '{"format_version":1,"walls":[{"id":"w","a":%s' "$deep" > "$GEN/json/deep_point.json"
printf '{"a":%s}' "$(repeat '{"a":' 50000)" > "$GEN/json/deep_object.json"
printf '{"format_version":1e%s}' "$(repeat 9 100000)" > "$GEN/json/number_huge_exponent.json"
printf '{"format_version":%s}' "$(repeat 9 100000)" > "$GEN/json/number_100k_digits.json"
printf '{"format_version":1,"name":"%s"}' "$(repeat 'ab' 100000)" > "$GEN/json/long_string.json"
printf '<osm>%s' "$(repeat '<a>' 100000)" > "$GEN/xml/deep.osm"
printf 'x0,y0,x1,y1\n%s\n' "$(repeat 9 100000)" > "$GEN/csv/long_number.csv"
printf '%s\n#unit\n%s\n#opening\n[' "$deep" "$deep" > "$GEN/imdf/deep.imdf"
for d in tests/floorplans_import/data/imdf/* tests/adversarial/data/imdf/*; do
  [ -f "$d/unit.geojson" ] || continue
  { cat "$d/level.geojson"; printf '\n#unit\n'; cat "$d/unit.geojson"; printf '\n#opening\n';
    if [ -f "$d/opening.geojson" ]; then cat "$d/opening.geojson"; fi; } > "$GEN/imdf/$(basename "$d").imdf"
done

A=tests/adversarial/data
inputs() {
  case $1 in
    fuzz_plan_json) echo floorplans/buildings $A/plan $A/rooms "$GEN/json" ;;
    fuzz_import_csv) echo tests/floorplans_import/data/csv $A/csv "$GEN/csv" ;;
    fuzz_import_osm) echo tests/floorplans_import/data/osm $A/osm "$GEN/xml" ;;
    fuzz_import_s3d) echo tests/floorplans_import/data/s3d "$GEN/json" ;;
    fuzz_import_imdf) echo "$GEN/imdf" ;;
    fuzz_import_png) echo tests/floorplans_import/data/png $A/scan ;;
    fuzz_observation_json) echo $A/obs "$GEN/json" ;;
    fuzz_scan_json) echo $A/scan "$GEN/json" ;;
    fuzz_scenario_yaml) echo scenarios $A/yaml ;;
  esac
}
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
for t in "${TARGETS[@]}"; do
  # shellcheck disable=SC2046
  printf '%-24s ' "$t"
  build-asan/bin/"${t}_replay" $(inputs "$t")
done
echo "sanitize.sh: ASan + UBSan clean on ${#TARGETS[@]} parser targets"
