#!/usr/bin/env python3
"""Do walks whose initial single-shot estimate is right stay right? (issue 20), over a sequential run.

Reads a finished `floorcast run` folder of a sequential scenario (units/<cell>/<building>/*.json)
and counts, per cell and tracker, the walks whose single-shot estimate on the initial observation
(the mode of the tracker's matcher: `outcomes[matcher].estimate`) lies within 1 m of the truth,
and of those the walks whose last tracked estimate lies within 1.5 m. Each cell's `trackers` in
resolved_config.json name the tracker's matcher. Trackers that ignore the initial posterior (the uniform
baselines) are listed too; for them the count only says where the walk started. Standard library
only; the numbers of results/sequential.md.

  scripts/run_keeps_right.py RUN_DIR [--start-m 1.0] [--end-m 1.5]
"""
import argparse
import collections
import glob
import json
import os


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run", help="run folder of a sequential scenario")
    ap.add_argument("--start-m", type=float, default=1.0, help="single-shot estimate 'right' within this (m)")
    ap.add_argument("--end-m", type=float, default=1.5, help="last estimate 'still right' within this (m)")
    a = ap.parse_args()
    config = json.load(open(os.path.join(a.run, "resolved_config.json")))
    matcher_of = {}  # (cell, tracker label) -> matcher label
    for cell in config.get("cells", []):
        for label, spec in (cell.get("trackers") or {}).items():
            matcher_of[(cell["id"], label)] = spec.get("matcher")
    counts = collections.defaultdict(lambda: [0, 0, 0])  # (cell, tracker) -> walks, right, kept
    units = sorted(glob.glob(os.path.join(a.run, "units", "*", "*", "*.json")))
    if not units:
        raise SystemExit(f"{a.run}: no units/<cell>/<building>/*.json (not a finished run folder?)")
    for path in units:
        cell = path.split(os.sep)[-3]
        u = json.load(open(path))
        single = {o["label"]: o["estimate"]["position_error_m"] for o in u.get("outcomes", []) if o.get("ok") and "estimate" in o}
        for t in u.get("tracks", []):
            errors = t.get("position_error_m") or []
            if not errors:
                continue
            matcher = matcher_of.get((cell, t["label"]))
            if matcher is None:
                raise SystemExit(f"{path}: tracker {t['label']} has no matcher in resolved_config.json")
            c = counts[(cell, t["label"])]
            c[0] += 1
            if single.get(matcher, float("inf")) < a.start_m:
                c[1] += 1
                if errors[-1] <= a.end_m:
                    c[2] += 1
    print(f"| cell | tracker | walks | single-shot within {a.start_m:g} m | of them within {a.end_m:g} m at the end |")
    print("|---|---|---|---|---|")
    for (cell, label), (walks, right, kept) in sorted(counts.items()):
        share = f"{kept} ({100.0 * kept / right:.0f}%)" if right else "n/a"
        print(f"| {cell} | {label} | {walks} | {right} | {share} |")


if __name__ == "__main__":
    main()
