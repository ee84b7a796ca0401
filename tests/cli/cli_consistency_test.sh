#!/usr/bin/env bash
# Consistency a user trips over (issue 12 part 4), end to end through the CLI:
#   exit_codes:  --help 0, usage error 2 (one code, not CLI11's many), bad input 2, no pose 3;
#   output_flag: every command that writes takes -o/--output (run and merge too);
#   swapped:     `localize OBS PLAN` says the arguments are swapped;
#   plan_hash:   an observation made on another plan gets a warning naming both hashes;
#   doors:       `sim scan --sensor perfect` and `sim perfect` see the same doors by default;
#   preview:     `sim scan --rgb` then `sim preview` writes a contact sheet;
#   progress:    a long command reports progress on stderr (`run` without --quiet).
#   grammar:     docs/cli.md's table against every command's --help; old spellings accepted with a
#                note, refused together with the new one; --pose random seeded.
set -uo pipefail
fc=$1
work=$2
what=$3
src=$(cd "$(dirname "$0")/../.." && pwd)
plan=$src/floorplans/buildings/two_rooms.json
apartment=$src/floorplans/buildings/apartment.json
rm -rf "$work"
mkdir -p "$work"
fail() { echo "FAILED: $*"; exit 1; }
status_of() { "$@" > "$work/out.txt" 2> "$work/err.txt"; echo $?; }

case "$what" in
  exit_codes)
    [ "$(status_of "$fc" --help)" = 0 ] || fail "--help"
    [ "$(status_of "$fc" localize --help)" = 0 ] || fail "localize --help"
    [ "$(status_of "$fc" localize)" = 2 ] || fail "missing arguments should be 2"
    [ "$(status_of "$fc" sim scan "$plan" --pose 2,2,0 --sensor nonsense -o "$work/x")" = 2 ] || fail "bad option value should be 2"
    [ "$(status_of "$fc" no-such-command)" = 2 ] || fail "unknown command should be 2"
    [ "$(status_of "$fc" sim perfect "$plan" --pose 20,2,0 -o "$work/x")" = 2 ] || fail "bad input should be 2"
    grep -q "outside the building" "$work/err.txt" || fail "bad input message"
    ;;
  output_flag)
    for cmd in "run" "merge" "localize" "observe" "sim scan" "sim perfect" "sim walk" "sim extrude" "sim preview" \
               "track" "report" "export" "plan generate" "plan render" "plan import" "compare-matchers"; do
      # shellcheck disable=SC2086
      "$fc" $cmd --help > "$work/help.txt" 2>&1 || fail "$cmd --help"
      grep -q -- "-o,--output" "$work/help.txt" || fail "$cmd has no -o,--output"
      if grep -q -- "--out " "$work/help.txt"; then fail "$cmd still spells --out"; fi
    done
    ;;
  swapped)
    "$fc" sim perfect "$plan" --pose 2,2,0 -o "$work/obs" > /dev/null || fail "sim perfect"
    [ "$(status_of "$fc" localize "$work/obs/observation.json" "$plan" -o "$work/loc")" = 2 ] || fail "swapped status"
    grep -q "did you swap them" "$work/err.txt" || { cat "$work/err.txt"; fail "swapped message"; }
    [ "$(status_of "$fc" localize "$work/obs" "$plan" -o "$work/loc")" = 2 ] || fail "swapped folder status"
    grep -q "did you swap them" "$work/err.txt" || { cat "$work/err.txt"; fail "swapped folder message"; }
    ;;
  plan_hash)
    "$fc" sim perfect "$plan" --pose 2,2,0 -o "$work/obs" > /dev/null || fail "sim perfect"
    [ "$(status_of "$fc" localize "$plan" "$work/obs" -o "$work/same")" = 0 ] || fail "same plan"
    if grep -q "plan with hash" "$work/err.txt"; then fail "warning on the same plan"; fi
    "$fc" localize "$apartment" "$work/obs" -o "$work/other" > /dev/null 2> "$work/err.txt"
    grep -q "was made on a plan with hash" "$work/err.txt" || { cat "$work/err.txt"; fail "no plan-hash warning"; }
    ;;
  doors)
    # two_rooms has an open door at (5, 1.5): from (3.5, 1.5) facing +x it is in view.
    "$fc" sim perfect "$plan" --pose 3.5,1.5,0 --rays 0 -o "$work/perfect" > /dev/null || fail "sim perfect"
    "$fc" sim scan "$plan" --pose 3.5,1.5,0 --sensor perfect -o "$work/scan" > /dev/null || fail "sim scan"
    "$fc" observe "$work/scan" --scale-alignment none -o "$work/scan_obs" > /dev/null || fail "observe"
    "$fc" sim perfect "$plan" --pose 3.5,1.5,0 --rays 0 --doors-open -o "$work/perfect_open" > /dev/null || fail "sim perfect open"
    "$fc" sim scan "$plan" --pose 3.5,1.5,0 --sensor perfect --doors-open -o "$work/scan_open" > /dev/null || fail "sim scan open"
    /usr/bin/python3 - "$work" <<'PY' || fail "door defaults differ"
import json, math, sys
w = sys.argv[1]
def far_points(path):
    # Ray ranges are off (rays 0); compare the farthest observed wall point along +x.
    segs = json.load(open(path))["segments_m"]
    return max(max(s[0], s[2]) for s in segs) if segs else 0.0
closed_perfect = far_points(w + "/perfect/observation.json")
open_perfect = far_points(w + "/perfect_open/observation.json")
closed_scan = far_points(w + "/scan_obs/observation.json")
print("farthest wall point ahead: perfect %.2f, scan %.2f (doors closed); perfect %.2f with doors open"
      % (closed_perfect, closed_scan, open_perfect))
assert open_perfect > closed_perfect + 1.0, "the open door should show the room behind it"
assert abs(closed_scan - closed_perfect) < 0.5, "sim scan and sim perfect disagree on the doors"
PY
    ;;
  preview)
    "$fc" sim scan "$plan" --pose 2,2,30 --sensor mono --setting partial --rgb -o "$work/scan" > "$work/out.txt" || fail "sim scan --rgb"
    grep -q "colour" "$work/out.txt" || fail "no colour timing"
    for k in 000 001 002; do [ -s "$work/scan/view_${k}_rgb.png" ] || fail "view $k rgb missing"; done
    "$fc" sim preview "$work/scan" -o "$work/sheet.png" > "$work/out.txt" || fail "sim preview"
    grep -q "preview: 3 views" "$work/out.txt" || fail "preview output"
    [ -s "$work/sheet.png" ] || fail "no sheet"
    ;;
  progress)
    "$fc" run "$src/tests/report/axes.yaml" -o "$work/run" --jobs 2 > /dev/null 2> "$work/err.txt" || fail "run"
    grep -q "ETA" "$work/err.txt" || { cat "$work/err.txt"; fail "no progress with ETA"; }
    ;;
  grammar)
    # Every current spelling in the table is in the --help of every command it names; no old
    # spelling is.
    /usr/bin/python3 - "$fc" "$src/docs/cli.md" <<'PY' || fail "docs/cli.md and --help disagree"
import re, subprocess, sys
fc, table = sys.argv[1], sys.argv[2]
rows = [l for l in open(table) if l.startswith("| ") and not l.startswith("| quantity") and not l.startswith("|---")]
assert len(rows) >= 10, "the grammar table is missing"
checked = 0
for row in rows:
    cells = [c.strip() for c in re.split(r"(?<!\\)\|", row)[1:-1]]
    spelling, commands, old = cells[1], cells[2], cells[3]
    flag = re.search(r"`(-o, --output|--[a-z-]+)", spelling).group(1).replace("-o, --output", "-o,--output")
    for cmd in re.findall(r"`([a-z-]+(?: [a-z]+)?)`", commands):
        help_text = subprocess.run([fc, *cmd.split(), "--help"], capture_output=True, text=True).stdout
        assert help_text, "%s --help printed nothing" % cmd
        assert flag in help_text, "%s: %s is not in its --help" % (cmd, flag)
        checked += 1
    for old_cmd, old_flag in re.findall(r"`([a-z]+(?: [a-z]+)?) (--[a-z-]+)", old):
        help_text = subprocess.run([fc, *old_cmd.split(), "--help"], capture_output=True, text=True).stdout
        assert re.search(re.escape(old_flag) + r"\b(?!-)", help_text) is None, "%s --help still lists %s" % (old_cmd, old_flag)
print("grammar table: %d command/flag pairs checked" % checked)
assert checked >= 40
PY
    # Old spellings: accepted, same result, a note naming the new spelling; both at once: usage error.
    "$fc" sim perfect "$plan" --pose 3,1.5,0 -o "$work/obs" > /dev/null || fail "sim perfect"
    "$fc" localize "$plan" "$work/obs" --matcher-param alpha=0.7 --posterior npy --quiet -o "$work/new" > /dev/null 2> "$work/err_new.txt" || fail "--matcher-param"
    "$fc" localize "$plan" "$work/obs" --param alpha=0.7 --posterior npy --quiet -o "$work/old" > /dev/null 2> "$work/err_old.txt" || fail "--param"
    grep -q "note: --param is deprecated, use --matcher-param" "$work/err_old.txt" || { cat "$work/err_old.txt"; fail "no note for --param"; }
    if grep -q "deprecated" "$work/err_new.txt"; then fail "a note without an old spelling"; fi
    cmp -s "$work/new/posterior.npy" "$work/old/posterior.npy" || fail "--param and --matcher-param differ"
    [ "$(status_of "$fc" localize "$plan" "$work/obs" --param alpha=1 --matcher-param alpha=1 -o "$work/both")" = 2 ] || fail "old and new together"
    "$fc" sim scan "$plan" --pose 3,1.5,0 --sensor lidar --setting single --max-range 4 -o "$work/scan_old" > /dev/null 2> "$work/err.txt" || fail "--max-range"
    grep -q "note: --max-range is deprecated, use --range" "$work/err.txt" || fail "no note for --max-range"
    "$fc" sim scan "$plan" --pose 3,1.5,0 --sensor lidar --setting single --range 4 -o "$work/scan_new" > /dev/null || fail "--range"
    cmp -s "$work/scan_old/view_000_depth.png" "$work/scan_new/view_000_depth.png" || fail "--max-range and --range differ"
    [ "$(status_of "$fc" sim scan "$plan" --pose 3,1.5,0 --range 4 --max-range 5 -o "$work/x")" = 2 ] || fail "--range with --max-range"
    "$fc" sim walk "$plan" --start 3,1.5,0 --steps 5 --seed 2 -o "$work/walk_old" > /dev/null 2> "$work/err.txt" || fail "--start"
    grep -q "note: --start is deprecated, use --pose" "$work/err.txt" || fail "no note for --start"
    "$fc" track "$plan" "$work/walk_old" --param num_particles=200 --quiet -o "$work/track_old" > /dev/null 2> "$work/err.txt"
    grep -q "note: --param is deprecated, use --tracker-param" "$work/err.txt" || { cat "$work/err.txt"; fail "no note for track --param"; }
    "$fc" observe "$work/scan_new" -o "$work/obs_old.json" > /dev/null 2> "$work/err.txt" || fail "observe -o FILE.json"
    grep -q "deprecated" "$work/err.txt" && [ -s "$work/obs_old.json" ] && [ -s "$work/obs_old.diagnostics.json" ] || fail "observe -o FILE.json"
    "$fc" observe "$work/scan_new" -o "$work/obs_new" > /dev/null 2> "$work/err.txt" || fail "observe -o DIR"
    [ -s "$work/obs_new/observation.json" ] && [ -s "$work/obs_new/observation.diagnostics.json" ] || fail "observe -o DIR files"
    # --pose random: seeded, inside the plan, reported.
    "$fc" sim perfect "$plan" --pose random --seed 7 -o "$work/r1" > "$work/out1.txt" || fail "--pose random"
    "$fc" sim perfect "$plan" --pose random --seed 7 -o "$work/r2" > /dev/null || fail "--pose random again"
    "$fc" sim perfect "$plan" --pose random --seed 8 -o "$work/r3" > /dev/null || fail "--pose random seed 8"
    cmp -s "$work/r1/observation.json" "$work/r2/observation.json" || fail "--pose random is not seeded"
    if cmp -s "$work/r1/observation.json" "$work/r3/observation.json"; then fail "--pose random ignores the seed"; fi
    "$fc" sim scan "$plan" --pose random --seed 7 --sensor lidar --setting single -o "$work/rs" > /dev/null || fail "sim scan --pose random"
    ;;
  *) fail "unknown test $what" ;;
esac
echo "ok: $what"
