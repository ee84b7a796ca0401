#!/usr/bin/env bash
# Every level of the real development set through a simulated LiDAR scan -> localize (issue 10,
# "done when"; results/realplans_vs_generated.md, "LiDAR scan -> localize"). Imports the levels
# (scripts/import_realplans.sh), then for every level: a seeded free point (the scenario runner's
# sampling: transitional spaces by default, 0.5 m from walls, random heading), one simulated LiDAR
# rotating scan there (`lidar` sensor, PALMS vertical-plane observation path) and the kernel
# matcher, through `floorcast run`; then the same pose once more through the user-facing commands,
# `floorcast sim scan --sensor lidar` and `floorcast localize --path lidar --matcher kernel`.
# Prints one line per level and point (and the sampling region used): ok/failed (within 1 m and
# 30 deg), wall segments observed, position and yaw error of both routes, and the reason of a
# failure. The two routes scan the same pose with different noise: the runner mixes the seed with
# building and point, `sim scan --seed` uses it as given.
# Usage: scripts/realplans_lidar.sh [REALPLANS_DIR] [OUT_DIR]
#   env: POINTS (per level, default 1), SEED (default 1), REGION (transitional|uniform), JOBS (default 1)
set -euo pipefail
cd "$(dirname "$0")/.."
src=${1:-}
if [ -z "$src" ]; then  # ../shared/realplans next to the checkout (worktrees: one level further up)
  for d in ../shared/realplans ../../shared/realplans /work/shared/realplans; do [ -d "$d" ] && src=$d && break; done
fi
[ -d "$src" ] || { echo "real plans not found (pass REALPLANS_DIR)" >&2; exit 2; }
out=${2:-out/realplans_lidar}
bin=$(realpath "${FLOORCAST:-build/bin/floorcast}")
points=${POINTS:-1}; seed=${SEED:-1}; region=${REGION:-transitional}; jobs=${JOBS:-1}
mkdir -p "$out"
FLOORCAST=$bin bash scripts/import_realplans.sh "$src" "$out/plans"

# One run per level, so that one level's failure does not hide the others. A level whose labelled
# transitional spaces have no free cell with the clearance is sampled uniformly (said in the table).
mkdir -p "$out/runs"
: > "$out/regions.txt"
for f in "$out"/plans/*.json; do
  name=$(basename "$f" .json)
  for reg in $region uniform; do
    scenario=$out/runs/${name}_$reg.yaml
    {
      echo "name: realplans_lidar_$name"
      echo "description: one simulated LiDAR scan per level of the real development plans, kernel matcher"
      echo "buildings:"
      echo "  - $(realpath "$f")"
      echo "sampling: {count: $points, seed: $seed, clearance_m: 0.5, region: $reg}"
      echo "observation: {source: scan, sensor: lidar, path: lidar, seed: $seed}"
      echo "matchers:"
      echo "  kernel: {matcher: kernel}"
    } > "$scenario"
    if "$bin" run "$scenario" -o "$out/runs/${name}_$reg" --jobs "$jobs" --quiet > "$out/runs/${name}_$reg.md" 2> "$out/runs/${name}_$reg.err"; then
      echo "$name $reg" >> "$out/regions.txt"; break
    fi
    echo "$name: $reg sampling failed: $(tail -1 "$out/runs/${name}_$reg.err")" >&2
    [ "$reg" = uniform ] && echo "$name failed" >> "$out/regions.txt"
  done
done

# The same poses through sim scan -> localize (the commands a user runs on one scan).
python3 - "$bin" "$out" "$seed" <<'EOF'
import csv, json, math, subprocess, sys
bin_, out, seed = sys.argv[1], sys.argv[2], sys.argv[3]
rows, region_of = [], {}
for line in open(f"{out}/regions.txt"):
    name, reg = line.split()
    region_of[name] = reg
    if reg != "failed":
        rows += list(csv.DictReader(open(f"{out}/runs/{name}_{reg}/observations.csv")))
    else:
        print(f"{name:<22}  failed: see {out}/runs/{name}_uniform.err")
def yaw_err(a, b):
    return abs((a - b + 180.0) % 360.0 - 180.0)
print(f"{'level':<22} {'pt':>2} {'sampling':<12}  {'run':<6} {'segs':>4} {'err_m':>7} {'yaw':>6}  {'cli':<6} {'segs':>4} {'err_m':>7} {'yaw':>6}  reason")
n_ok = [0, 0]
for r in rows:
    name, pt = r["building"], int(r["point"])
    x, y, yaw = float(r["truth_x_m"]), float(r["truth_y_m"]), float(r["truth_yaw_deg"])
    reason = []
    unit = json.load(open(f"{out}/runs/{name}_{region_of[name]}/units/{r['unit']}.json"))
    segs_run = unit["observation"]["segments"] if unit.get("observation") else 0
    if r["observation_ok"] != "1":
        reason.append(f"run: {unit.get('observation_failure', 'observation failed')}")
    if r["kernel_ok"] == "1":
        e_run, y_run = float(r["kernel_position_error_m"]), float(r["kernel_yaw_error_deg"])
        ok_run = e_run <= 1.0 and y_run <= 30.0
    else:
        e_run = y_run = math.nan; ok_run = False
        if r["observation_ok"] == "1": reason.append("run: no pose (empty posterior)")
    scan = f"{out}/cli/{name}_{pt}/scan"; loc = f"{out}/cli/{name}_{pt}/localize"
    plan = f"{out}/plans/{name}.json"
    e_cli = y_cli = math.nan; ok_cli = False; segs_cli = "-"
    p = subprocess.run([bin_, "sim", "scan", plan, "--pose", f"{x},{y},{yaw}", "--sensor", "lidar",
                        "--seed", seed, "-o", scan], capture_output=True, text=True)
    if p.returncode != 0:
        reason.append("sim scan: " + (p.stderr.strip().splitlines()[-1] if p.stderr.strip() else f"exit {p.returncode}"))
    else:
        p = subprocess.run([bin_, "localize", plan, scan, "--path", "lidar", "--matcher", "kernel",
                            "--quiet", "-o", loc], capture_output=True, text=True)
        try:  # exit 3 = "no pose" (estimate.json still written, status says why)
            est = json.load(open(f"{loc}/estimate.json"))
        except OSError:
            est = None
            reason.append("localize: " + (p.stderr.strip().splitlines()[-1] if p.stderr.strip() else f"exit {p.returncode}"))
        if est is not None:
            segs_cli = est.get("observation_segments")
            if est["status"] != "ok":
                reason.append(f"localize: {est['status']}")
            else:
                e_cli = math.hypot(est["x_m"] - x, est["y_m"] - y)
                y_cli = yaw_err(est["yaw_deg"], yaw)
                ok_cli = e_cli <= 1.0 and y_cli <= 30.0
    n_ok[0] += ok_run; n_ok[1] += ok_cli
    f = lambda v: f"{v:7.2f}" if not math.isnan(v) else "      -"
    g = lambda v: f"{v:6.1f}" if not math.isnan(v) else "     -"
    print(f"{name:<22} {pt:>2} {region_of[name]:<12}  {'ok' if ok_run else 'failed':<6} {segs_run:>4} {f(e_run)} {g(y_run)}  "
          f"{'ok' if ok_cli else 'failed':<6} {segs_cli:>4} {f(e_cli)} {g(y_cli)}  {'; '.join(reason)}")
print(f"ok within 1 m 30 deg: run {n_ok[0]}/{len(rows)}, sim scan -> localize {n_ok[1]}/{len(rows)}")
EOF
