#!/usr/bin/env python3
"""How a matcher's true pose scored, for the points of a perfect-observation run (results/realplans_vs_generated.md,
"Why the halls fail").

    PYTHONPATH=build/python python3 scripts/truth_scores.py RUN_DIR [--matcher kernel] [--where hall]
        [--params JSON] [--against DIR] [--csv FILE]

RUN_DIR is a `floorcast compare-matchers` (or scenario) output with perfect observations: its resolved_config.json
gives the observation (rays, range, doors) and the matcher's parameters, plans/ the plans, observations.csv the true
poses. For every point (or those standing in a hall / room / transitional space: a hall is a non-transitional room of
200 m^2 or more) the observation is made again at the true pose and matched through the Python bindings, and the
script reports: whether the posterior's argmax is within 1 m and 30 deg of the truth; the truth's score (the best
score within 2 cells and one orientation slice of the true pose) over the posterior's maximum; the floor area where
some orientation scores above the truth; how far the true heading lies from the nearest orientation the matcher
tested (the kernel's PALMS+ candidates: 10 headings from the observation's wall directions; a point whose heading is
more than 2.5 deg from every candidate cannot be localised within one orientation slice); what the scan sees (wall
segments, visible length, the share of it oblique to the plan's main axes, more than 5 deg off); and where the
winner stands. With --against DIR the same poses are
also matched on the plans of the same names in DIR (e.g. the same buildings drawn another way): a paired comparison
on identical poses, which a new run cannot give when the free area changes (uniform sampling draws new points).

The argmax of the full posterior can differ from the run's own estimate where the run searched modes by branch and
bound (ties); the summary counts both.
"""
import argparse
import csv
import json
import math
import os
import statistics
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from realplans_vs_generated import main_axis_deg, room_category  # noqa: E402

try:
    import numpy as np
    import floorcast as fc
except ImportError as e:  # a clear message, not a traceback
    sys.exit("truth_scores.py needs numpy and floorcast's Python module (PYTHONPATH=build/python): %s" % e)


def success(estimate, truth):
    if estimate["status"] != "ok":
        return False
    dyaw = abs((estimate["yaw_deg"] - truth[2] + 180.0) % 360.0 - 180.0)
    return math.hypot(estimate["x_m"] - truth[0], estimate["y_m"] - truth[1]) <= 1.0 and dyaw <= 30.0


def truth_measures(match, truth):
    """(truth / max score, area in m^2 where some orientation scores above the truth); NaN, 0 for an all-zero
    posterior."""
    post = match.posterior
    grid = match.grid
    res = grid["resolution_m"]
    col = int(math.floor((truth[0] - grid["origin_x_m"]) / res))
    row = int(math.floor((truth[1] - grid["origin_y_m"]) / res))
    yaw = np.asarray(grid["yaw_deg"])
    s = int(np.argmin(np.abs((yaw - truth[2] + 180.0) % 360.0 - 180.0)))
    n = post.shape[0]
    r0, c0 = max(row - 2, 0), max(col - 2, 0)
    best_here = max(float(post[(s + d) % n, r0:row + 3, c0:col + 3].max()) for d in (-1, 0, 1))
    top = float(post.max())
    if top <= 0.0:
        return float("nan"), 0.0
    above = float((post.max(axis=0) > best_here).sum()) * res * res
    return best_here / top, above


def scan_measures(obs, yaw_deg, axis_deg):
    seg = np.asarray(obs.segments).reshape(-1, 4)
    if not len(seg):
        return 0, 0.0, 0.0
    lengths = np.hypot(seg[:, 2] - seg[:, 0], seg[:, 3] - seg[:, 1])
    angle = np.degrees(np.arctan2(seg[:, 3] - seg[:, 1], seg[:, 2] - seg[:, 0])) + yaw_deg
    off = np.abs((angle - axis_deg + 45.0) % 90.0 - 45.0)
    total = float(lengths.sum())
    return len(seg), total, float(lengths[off > 5.0].sum() / total) if total > 0 else 0.0


def group_of(label):
    """Levels and seeds of one source pooled: spbstu_main_L0 -> spbstu_main, campus_s3 -> campus."""
    head, _, tail = label.rpartition("_")
    return head if head and (tail[:1] in ("L", "s") and tail[1:].lstrip("-").isdigit()) else label


def mr(values, fmt="{:.2f}"):
    v = [x for x in values if x == x]
    return (fmt.format(statistics.median(v)) + " [" + fmt.format(min(v)) + "-" + fmt.format(max(v)) + "]") if v else "-"


def med(values):
    return "{:g}".format(statistics.median(values)) if values else "-"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("run", help="a compare-matchers / scenario output directory with perfect observations")
    ap.add_argument("--matcher", default="kernel", help="the run's matcher label (default kernel)")
    ap.add_argument("--where", choices=["hall", "room", "transitional", "all"], default="hall")
    ap.add_argument("--params", default=None, help="JSON overrides of the matcher's parameters (e.g. a variant)")
    ap.add_argument("--against", default=None, help="a directory of plans of the same names: the same poses on them")
    ap.add_argument("--csv", default=None, help="write one row per point here")
    args = ap.parse_args()

    config = json.load(open(os.path.join(args.run, "resolved_config.json")))
    cell = config["cells"][0]
    observation = cell["observation"]
    if observation.get("source") != "perfect":
        sys.exit("%s: observations are '%s'; this script remakes perfect observations only"
                 % (args.run, observation.get("source")))
    if args.matcher not in cell["matchers"]:
        sys.exit("%s: no matcher labelled %s (the run has %s)" % (args.run, args.matcher, ", ".join(cell["matchers"])))
    params = dict(cell["matchers"][args.matcher])
    name = params.pop("matcher")
    if args.params:
        params.update(json.loads(args.params))
    rays, range_m = int(observation["rays"]), float(observation["max_range_m"])
    doors_open = not observation["doors_closed"]

    rows = list(csv.DictReader(open(os.path.join(args.run, "observations.csv"))))
    out = []
    skipped = []
    plans = {}
    for r in rows:
        b = r["building"]
        if r.get("negative"):
            continue
        if b not in plans:
            path = os.path.join(args.run, "plans", b + ".json")
            with open(path) as fh:
                plan_json = json.load(fh)
            entry = {"rooms": [q for q in plan_json["rooms"] if q["kind"] != "unmapped"],
                     "axis": main_axis_deg(plan_json["walls"])}
            entry["plan"] = fc.load_plan(path)
            entry["matcher"] = fc.Matcher(entry["plan"], name, params)
            if args.against:
                other = fc.load_plan(os.path.join(args.against, b + ".json"))
                entry["other"] = (other, fc.Matcher(other, name, params))
            plans[b] = entry
        e = plans[b]
        truth = (float(r["truth_x_m"]), float(r["truth_y_m"]), float(r["truth_yaw_deg"]))
        where = room_category(e["rooms"], truth[0], truth[1])
        if args.where != "all" and where != args.where:
            continue
        try:
            obs = fc.perfect_observation(e["plan"], truth, rays=rays, range_m=range_m, doors_open=doors_open)
        except fc.InputError as ex:  # e.g. a pose the run sampled inside an obstacle thinner than a raster cell
            skipped.append("%s point %s: %s" % (b, r["point"], str(ex).splitlines()[0]))
            continue
        m = e["matcher"].match(obs)
        ratio, above = truth_measures(m, truth)
        segments, length, oblique = scan_measures(obs, truth[2], e["axis"])
        tested = np.asarray(m.grid["yaw_deg"], dtype=float)
        heading_off = float(np.min(np.abs((tested - truth[2] + 180.0) % 360.0 - 180.0)))
        est = m.estimate
        row = {"building": b, "point": r["point"], "where": where,
               "run_success": r[args.matcher + "_ok"] == "1" and float(r[args.matcher + "_position_error_m"]) <= 1.0
               and float(r[args.matcher + "_yaw_error_deg"]) <= 30.0,
               "success": success(est, truth), "truth_over_best": ratio, "area_above_truth_m2": above,
               "segments": segments, "visible_m": length, "oblique_share": oblique,
               "heading_off_deg": heading_off,
               "winner_in": room_category(e["rooms"], est["x_m"], est["y_m"]) if est["status"] == "ok" else "none"}
        if args.against:
            other, matcher = e["other"]
            try:
                row["success_against"] = success(matcher.match(
                    fc.perfect_observation(other, truth, rays=rays, range_m=range_m, doors_open=doors_open)).estimate,
                    truth)
            except fc.InputError as ex:  # the pose is not free floor on the other plan (e.g. a corner cut off)
                row["success_against"] = None
                row["note"] = str(ex).splitlines()[0]
        out.append(row)

    if args.csv:
        with open(args.csv, "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=sorted({k for o in out for k in o}))
            w.writeheader()
            w.writerows(out)

    print("%s, matcher %s, points %s (%d)" % (args.run, args.matcher, args.where, len(out)))
    for note in skipped:
        print("skipped (the bindings refuse the pose): " + note)
    print()
    print("| set | points | localised (run / argmax) | failed: truth / best score, median [range] | failed: area above "
          "the truth (m^2), median | failed: winner in hall / room / transitional | wall segments seen, localised / "
          "failed (median) | seeing an oblique wall: localised of | not seeing one: localised of | true heading "
          "not among the tested orientations (over 2.5 deg off): points, localised |"
          + (" paired: localised here / against |" if args.against else ""))
    print("|" + "---|" * (11 if args.against else 10))
    for g in sorted({group_of(o["building"]) for o in out}):
        pts = [o for o in out if group_of(o["building"]) == g]
        failed = [o for o in pts if not o["success"]]
        ok = [o for o in pts if o["success"]]
        sees = [o for o in pts if o["oblique_share"] > 0.05]
        line = "| %s | %d | %d / %d | %s | %s | %s | %s / %s | %d of %d | %d of %d |" % (
            g, len(pts), sum(o["run_success"] for o in pts), len(ok), mr([o["truth_over_best"] for o in failed]),
            mr([o["area_above_truth_m2"] for o in failed], "{:.1f}"),
            " / ".join(str(sum(o["winner_in"] == c for o in failed)) for c in ("hall", "room", "transitional")),
            med([o["segments"] for o in ok]), med([o["segments"] for o in failed]),
            sum(o["success"] for o in sees), len(sees), sum(o["success"] for o in pts if o not in sees), len(pts) - len(sees))
        missed = [o for o in pts if o["heading_off_deg"] > 2.5]
        line += " %d, %d |" % (len(missed), sum(o["success"] for o in missed))
        if args.against:
            both = [o for o in pts if o.get("success_against") is not None]
            line += " %d / %d of %d |" % (sum(o["success"] for o in both), sum(o["success_against"] for o in both), len(both))
        print(line)


if __name__ == "__main__":
    main()
