#!/usr/bin/env bash
# Fuzzes one input entry point with libFuzzer:  bash scripts/fuzz.sh TARGET SECONDS
#   TARGET   fuzz_plan_json | fuzz_import_csv | fuzz_import_osm | fuzz_import_s3d | fuzz_import_imdf |
#            fuzz_import_png | fuzz_scenario_yaml | fuzz_observation_json | fuzz_scan_json | list
#   SECONDS  fuzzing time (wall clock)
# Builds the target with clang, ASan and UBSan (and libFuzzer's coverage instrumentation on every
# floorcast library) in build-fuzz/, seeds it from the test fixtures, the adversarial corpus and
# /work/shared/realplans (../shared/realplans next to the checkout), and fuzzes into
# out/fuzz/TARGET/ (the corpus it grows, crash-*/timeout-*/oom-* artifacts, fuzz.log). Prints the
# executions and findings; exits 1 when there is a finding.
#
# Environment: FLOORCAST_FUZZ_BUILD_JOBS (compile jobs, default 2), FLOORCAST_REALPLANS (seed
#   plans folder), FLOORCAST_FUZZ_NO_BUILD=1 (fuzz the binary already in build-fuzz/bin, e.g.
#   while a build of the other targets runs in build-fuzz), FLOORCAST_FUZZ_TIMEOUT (seconds of wall
#   clock after which an input is a hang, default 10; raise it on a loaded machine, where a niced
#   fuzzer waits for the CPU, and check every timeout's CPU time when it is reproduced). One fuzzing process (the machines are shared): run several targets at once
#   for more.
# Every finding gets a regression case in tests/adversarial/cases/ (see results/fuzz.md).
set -euo pipefail
cd "$(dirname "$0")/.."

TARGETS=(fuzz_plan_json fuzz_import_csv fuzz_import_osm fuzz_import_s3d fuzz_import_imdf fuzz_import_png
         fuzz_scenario_yaml fuzz_observation_json fuzz_scan_json)
if [ $# -ge 1 ] && [ "$1" = "list" ]; then printf '%s\n' "${TARGETS[@]}"; exit 0; fi
if [ $# -ne 2 ]; then
  echo "usage: bash scripts/fuzz.sh TARGET SECONDS   (targets: bash scripts/fuzz.sh list)" >&2
  exit 2
fi
TARGET=$1
SECONDS_TO_RUN=$2
if [[ ! " ${TARGETS[*]} " =~ " ${TARGET} " ]]; then
  echo "fuzz.sh: unknown target $TARGET (known: ${TARGETS[*]})" >&2
  exit 2
fi

# clang and the libFuzzer runtime (Debian 12: clang, libclang-rt-14-dev), installed only when missing.
bash scripts/install_deps.sh
need=()
command -v clang++ >/dev/null 2>&1 || need+=(clang)
if ! dpkg-query -W -f='${Status}' libclang-rt-14-dev 2>/dev/null | grep -q "install ok installed"; then
  need+=(libclang-rt-14-dev)
fi
if [ ${#need[@]} -gt 0 ]; then
  SUDO=(); [ "$(id -u)" -eq 0 ] || SUDO=(sudo)
  echo "fuzz.sh: installing ${need[*]}"
  "${SUDO[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${SUDO[@]}" apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null
fi

if [ "${FLOORCAST_FUZZ_NO_BUILD:-0}" = 1 ]; then
  if [ ! -x build-fuzz/bin/"$TARGET" ]; then
    echo "fuzz.sh: FLOORCAST_FUZZ_NO_BUILD=1 but build-fuzz/bin/$TARGET is not built" >&2
    exit 2
  fi
else
  FLAGS="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer -g -O1"
  launcher=()
  if command -v ccache >/dev/null 2>&1; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache); fi
  cmake -S . -B build-fuzz -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
    -DCMAKE_C_FLAGS="$FLAGS" -DCMAKE_CXX_FLAGS="$FLAGS" \
    -DFLOORCAST_BUILD_FUZZERS=ON -DFLOORCAST_BUILD_TESTS=OFF -DFLOORCAST_BUILD_BENCHMARKS=OFF "${launcher[@]}" >/dev/null
  cmake --build build-fuzz -j"${FLOORCAST_FUZZ_BUILD_JOBS:-2}" --target "$TARGET"
fi

# Seed corpus: every fixture of the matching kind.
REALPLANS=${FLOORCAST_REALPLANS:-}
if [ -z "$REALPLANS" ]; then
  for d in /work/shared/realplans ../shared/realplans ../../shared/realplans; do
    if [ -d "$d" ]; then REALPLANS=$d; break; fi
  done
fi
SEEDS=build-fuzz/seeds/$TARGET
rm -rf "$SEEDS"
mkdir -p "$SEEDS"
seed() { for f in "$@"; do [ -f "$f" ] && cp "$f" "$SEEDS/$(echo "$f" | tr '/' '_')"; done; return 0; }
A=tests/adversarial/data
case $TARGET in
  fuzz_plan_json) seed floorplans/buildings/*.json $A/plan/*.json tests/floorplans/data/*.json ;;
  fuzz_import_csv) seed tests/floorplans_import/data/csv/*.csv $A/csv/*.csv ;;
  fuzz_import_osm) seed tests/floorplans_import/data/osm/*.osm $A/osm/*.osm ${REALPLANS:+$REALPLANS/*/*.osm} ;;
  fuzz_import_s3d) seed tests/floorplans_import/data/s3d/*/annotation_3d.json $A/s3d/*.json ;;
  fuzz_import_imdf)
    for d in tests/floorplans_import/data/imdf/* ${REALPLANS:+$REALPLANS/spbstu_polytech}; do
      [ -f "$d/unit.geojson" ] || continue
      { cat "$d/level.geojson"; printf '\n#unit\n'; cat "$d/unit.geojson"; printf '\n#opening\n';
        [ -f "$d/opening.geojson" ] && cat "$d/opening.geojson"; } > "$SEEDS/$(echo "$d" | tr '/' '_').imdf"
    done ;;
  fuzz_import_png) seed tests/floorplans_import/data/png/*.png $A/png/*.png ;;
  fuzz_scenario_yaml) seed scenarios/*.yaml tests/scenarios_cli/data/*.yaml $A/yaml/*.yaml ;;
  fuzz_observation_json) seed $A/obs/*.json ;;
  fuzz_scan_json) seed $A/scan/*/scan.json ;;
esac
DICT=()
case $TARGET in
  fuzz_plan_json|fuzz_import_s3d|fuzz_import_imdf|fuzz_observation_json|fuzz_scan_json) DICT=(-dict=fuzz/json.dict) ;;
  fuzz_import_osm) DICT=(-dict=fuzz/xml.dict) ;;
  fuzz_scenario_yaml) DICT=(-dict=fuzz/yaml.dict) ;;
esac

OUT=out/fuzz/$TARGET
mkdir -p "$OUT/corpus"
echo "fuzz.sh: $TARGET for ${SECONDS_TO_RUN}s, $(ls "$SEEDS" | wc -l) seeds, corpus $OUT/corpus"
# -timeout: an input running longer than 10 s (FLOORCAST_FUZZ_TIMEOUT) is a hang; -rss_limit_mb: more than 3 GiB is a
# memory finding; -max_len 1 MiB covers the real-plan seeds.
set +e
build-fuzz/bin/"$TARGET" "$OUT/corpus" "$SEEDS" "${DICT[@]}" -max_total_time="$SECONDS_TO_RUN" -timeout="${FLOORCAST_FUZZ_TIMEOUT:-10}" \
  -rss_limit_mb=3072 -max_len=1048576 -print_final_stats=1 -artifact_prefix="$OUT/" > "$OUT/fuzz.log" 2>&1
status=$?
set -e
execs=$(grep -h "stat::number_of_executed_units" "$OUT/fuzz.log" | awk '{s += $2} END {print s + 0}')
findings=$(ls "$OUT" | grep -cE '^(crash|timeout|oom|leak|slow-unit)-' || true)
echo "fuzz.sh: $TARGET: $execs executions in ${SECONDS_TO_RUN}s, $findings finding(s), libFuzzer status $status (log $OUT/fuzz.log)"
if [ "$findings" -gt 0 ] || [ "$status" -ne 0 ]; then
  ls "$OUT" | grep -E '^(crash|timeout|oom|leak|slow-unit)-' || true
  exit 1
fi
