#!/usr/bin/env bash
# results/planes.md: the plane matcher (VoxelPlane-Reloc) beside the kernel and ray matchers,
# scored with rejection, its ablations, and its relocalization time.
#   1. scenarios/planes.yaml: perfect observations, LiDAR (5 m) and depth-camera (10 m) scans of
#      the shipped calibrated buildings and the apartment, kernel / ray / planes, 24 points and 8
#      negatives per building;
#   2. the same three observation sources on levels of the real development plans
#      (../shared/realplans, imported by scripts/import_realplans.sh), negatives from the other
#      levels and buildings;
#   3. scenarios/planes_ablation.yaml: VR-NE ... VR-NS on depth-camera scans;
#   4. `floorcast bench reloc` on the calibrated office and campus (LiDAR scans);
#   5. precision / recall of the kernel and ray matchers abstaining below a score threshold,
#      swept over their recorded best scores (scripts/planes_pr.py).
# Usage: scripts/planes_results.sh [OUT_DIR]   env: JOBS (default 2), REALPLANS_DIR
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-out/planes_results}
bin=$(realpath "${FLOORCAST:-build/bin/floorcast}")
jobs=${JOBS:-2}
mkdir -p "$out"
# The commit measured at (taken as the run starts).
git rev-parse HEAD > "$out/commit" 2>/dev/null || true
"$bin" run scenarios/planes.yaml -o "$out/planes" --jobs "$jobs" --quiet > "$out/planes.md"
"$bin" run scenarios/planes_ablation.yaml -o "$out/planes_ablation" --jobs "$jobs" --quiet > "$out/planes_ablation.md"

src=${REALPLANS_DIR:-}
if [ -z "$src" ]; then
  for d in ../shared/realplans ../../shared/realplans /work/shared/realplans; do [ -d "$d" ] && src=$d && break; done
fi
if [ -d "$src" ]; then
  FLOORCAST=$bin bash scripts/import_realplans.sh "$src" "$out/realplans"
  {
    echo "name: planes_realplans"
    echo "description: kernel, ray and planes matchers on levels of the real development plans, with negatives from the other levels"
    echo "buildings:"
    for f in rwth_plt_L0 rwth_plt_L1 rwth_plt_L2 tum_studitum_L0 tum_studitum_L1 spbstu_no3_L2 spbstu_no3_L3; do
      echo "  - $(realpath "$out/realplans/$f.json")"
    done
    echo "sampling: {count: 12, seed: 51, clearance_m: 0.5, region: uniform, negatives: 4}"
    echo "observation: {seed: 13}"
    echo "matchers:"
    echo "  kernel: {matcher: kernel}"
    echo "  ray: {matcher: ray}"
    echo "  planes: {matcher: planes}"
    echo "output: {heatmaps: 0}"
    echo "sweep:"
    echo "  - observation.source: [perfect, scan, scan]"
    echo "    observation.sensor: [lidar, lidar, depth_camera]"
    echo "    observation.path: [mono, lidar, lidar]"
  } > "$out/planes_realplans.yaml"
  "$bin" run "$out/planes_realplans.yaml" -o "$out/planes_realplans" --jobs "$jobs" --quiet > "$out/planes_realplans.md"
fi
"$bin" bench reloc --scans 20 --repeats 3 --json > "$out/bench_reloc.json"
"$bin" bench reloc --scans 20 --repeats 3 --sensor depth_camera --json > "$out/bench_reloc_depth_camera.json"
python3 scripts/planes_pr.py "$out/planes" > "$out/pr_planes.md"
[ -d "$out/planes_realplans" ] && python3 scripts/planes_pr.py "$out/planes_realplans" > "$out/pr_realplans.md"
echo "done: $out"
