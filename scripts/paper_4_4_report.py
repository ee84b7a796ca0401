#!/usr/bin/env python3
"""Tables of the PALMS+ sec. 4.4 ingredient study (results/paper_4_4.md) from the run directories
scripts/paper_4_4.py writes. Prints Markdown.

Every paired number comes from floorcast's eval (eval/paired.hpp: McNemar's exact test on
success @1 m 30 deg, paired bootstrap 95% interval of the difference in recall), never from this
script:
  - ingredient vs its base in the same run: the run's summary.json (`paired`, every pair of matchers
    of a cell). A run summarised by an older floorcast has no `paired` block: the run is re-summarised
    from its units by `floorcast merge RUN -o OUT/summaries/NAME` (no unit is recomputed);
  - the protocol's range cells (runs of their own) against the ingredient run on the same points:
    `floorcast compare-runs CELL BASE --json OUT/summaries/NAME.json`.

The twin table asks of every miss whether the building itself hides the answer: floorcast's
perfect observer (Python bindings) renders the view from the estimated pose and from the truth
(360 rays, the scenario's range, doors closed); a miss is a *twin* when at least 90% of the rays
agree within 0.3 m (best of the estimated yaw +-5 deg, so the matchers' 10 deg / 0.1 m grids do
not count as differences). A twin cannot be told from the truth by any matcher given this
observation.

Usage: PYTHONPATH=build/python /usr/bin/python3 scripts/paper_4_4_report.py [--out out/paper_4_4]
       [--bin build/bin/floorcast]
"""
import argparse
import csv
import glob
import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CRIT = "recall_1m_30deg"
TOP5 = "top5_recall_1m"

# What each ingredient label follows (the matchers' READMEs document every parameter).
FOLLOWS = {
    "kernel_alpha1": "alpha 1 (PALMS paper text; code and default: 10)",
    "kernel_blur_palms": "blur 7 px, sigma 3 (PALMS)",
    "kernel_blur_s3d": "blur 7 px, sigma 1 (PALMS+ Structured3D)",
    "kernel_centreline": "wall centre lines instead of faces",
    "kernel_orient_palms": "PALMS orientation candidates (principal + k 90 deg)",
    "kernel_bresenham": "Bresenham plan lines (authors' code)",
    "kernel_ellipse": "CES eroded by an ellipse (authors' code)",
    "kernel_alpha_shape": "valid area = alpha shape of the walls (authors' code)",
    "kernel_corner": "pose reported at the cell corner (authors' code)",
    "kernel_reflect": "map border reflected, no margin (authors' code)",
    "kernel_tilt": "plan rotated to its principal orientation (authors' code)",
    "kernel_ces_doors": "CES stops at doorways (PALMS as published)",
    "kernel_code": "kernels and heatmap shift as CES.py builds them",
    "kernel_authors": "all of the authors' code together",
    "ray180": "180 rays (PALMS+ sec. 4.4, '+~3 points')",
    "ray_corner": "desdf cast from the cell corner (F3Loc code)",
    "ray_raster": "desdf marched on a 0.01 m occupancy image (F3Loc code)",
    "ray_all_cells": "every cell scored, walls and outside too (F3Loc code)",
    "ray_doors_open": "desdf with doors open (observation: doors closed)",
    "ray_fov100": "F3Loc's 11 rays over +-50 deg instead of 360 deg",
    "ray_one_bin_off": "heading one 10 deg bin off (a re-implementation slip)",
    "ray_mirrored": "ray order mirrored (a re-implementation slip)",
    "ray_heading_ray0": "heading at ray 0 instead of V//2 (a re-implementation slip)",
    "ray_f3loc_code": "F3Loc's code together (raster, corner, all cells, its localize(), rays unclipped)",
}


def floorcast(binary, args, ok_codes=(0,)):
    r = subprocess.run([binary] + args, cwd=ROOT, capture_output=True, text=True)
    if r.returncode not in ok_codes:
        sys.exit("floorcast %s failed (%d):\n%s%s" % (" ".join(args), r.returncode, r.stdout, r.stderr))


def summary(out, name, binary):
    """summary.json of run `name`, re-summarised by this floorcast if it has no paired block."""
    run = os.path.join(out, name)
    path = os.path.join(run, "summary.json")
    if not os.path.exists(path):
        return None
    s = json.load(open(path))
    if all("paired" in c for c in s["cells"]):
        return s
    again = os.path.join(out, "summaries", name)
    if not os.path.exists(os.path.join(again, "summary.json")):
        floorcast(binary, ["merge", run, "-o", again])
    return json.load(open(os.path.join(again, "summary.json")))


def cross(out, base, other, binary):
    """compare-runs JSON of run `other` against run `base` on their shared points (or None)."""
    if not all(os.path.exists(os.path.join(out, n, "summary.json")) for n in (base, other)):
        return None
    path = os.path.join(out, "summaries", "%s__vs__%s.json" % (other, base))
    if not os.path.exists(path):
        os.makedirs(os.path.dirname(path), exist_ok=True)
        # Exit 1 = "the runs differ", which they do by construction (other configurations: each run's
        # units are read with its own scenario and compared on the points both hold).
        floorcast(binary, ["compare-runs", os.path.join(out, other), os.path.join(out, base), "--json", path],
                  ok_codes=(0, 1))
    return json.load(open(path))


def rate(s, label, metric=CRIT):
    g = s["cells"][0]["groups"]["all"][label]
    return g[metric], g.get("ci95", {}).get(metric), g["count"]


def pair(s, a, b):
    """Paired comparison a - b (success @1 m 30 deg) from a summary's `paired` block."""
    p = s["cells"][0]["paired"]["all"]
    if a + " vs " + b in p:
        return orient(p[a + " vs " + b][CRIT], False)
    return orient(p[b + " vs " + a][CRIT], True)


def orient(e, swap):
    """(difference, ci, only_a, only_b, p) with A and B swapped when `swap`."""
    d, ci = e["difference"], e["ci95"]
    if swap:  # (+ 0.0: no "-0.0")
        return (-d + 0.0 if d is not None else None, [-ci[1] + 0.0, -ci[0] + 0.0] if ci else None, e["only_b"],
                e["only_a"], e["p_value"])
    return (d, ci, e["only_a"], e["only_b"], e["p_value"])


def md_row(cells):
    return "| " + " | ".join(cells) + " |"


def pct(x):
    return "-" if x is None else "%.1f" % (100.0 * x)


def fmt_p(p):
    return "%.2g" % p if p >= 1e-4 else "<1e-4"


def fmt_pair(t):
    d, ci, oa, ob, p = t
    s = "%+.1f" % (100.0 * d)
    if ci:
        s += " [%+.1f, %+.1f]" % (100.0 * ci[0], 100.0 * ci[1])
    return "%s (%d/%d, p %s)" % (s, oa, ob, fmt_p(p))


def fmt_rate(s, label, metric=CRIT):
    v, ci, n = rate(s, label, metric)
    t = pct(v)
    if ci:
        t += " [%s, %s]" % (pct(ci[0]), pct(ci[1]))
    return t


def sets_of(out, binary):
    """(title, summary) of every building set whose run exists: generated, real small, each large level."""
    named = [("generated (3 calibrated)", "generated"), ("real, 6 small levels", "real_small")]
    for d in sorted(glob.glob(os.path.join(out, "real_large_*"))):
        if os.path.isdir(d):
            named.append(("real, " + os.path.basename(d)[len("real_large_"):], os.path.basename(d)))
    sets = []
    for title, name in named:
        s = summary(out, name, binary)
        if s:
            sets.append(("%s, %d points" % (title, rate(s, labels(s)[0])[2]), s))
    return sets


def labels(s):
    return list(s["cells"][0]["groups"]["all"].keys())


def headline(sets):
    out = ["### Success @1 m 30 deg, % [bootstrap 95% interval]; top-5 @1 m in the second row of each set", "",
           "| building set | kernel | ray (36) | ray (180) | ray180 - ray, points (only 180 / only 36, McNemar p) |",
           "|---|---|---|---|---|",
           "| PALMS+ sec. 4.4, 4 real campus buildings | 88.7 | 11.2 | ~14 | ~+3 |"]
    for title, s in sets:
        out.append("| %s | %s | %s | %s | %s |" % (title, fmt_rate(s, "kernel"), fmt_rate(s, "ray"), fmt_rate(s, "ray180"),
                                                   fmt_pair(pair(s, "ray180", "ray"))))
        out.append("| top-5 @1 m | %s | %s | %s | |" % (fmt_rate(s, "kernel", TOP5), fmt_rate(s, "ray", TOP5),
                                                       fmt_rate(s, "ray180", TOP5)))
    return out


def ingredient_table(sets):
    out = ["| ingredient | follows | " + " | ".join(t for t, _ in sets) + " |",
           "|---|---|" + "---|" * len(sets)]
    for base in ("kernel", "ray"):
        row = ["**%s** (base)" % base, "floorcast's defaults"]
        row += [fmt_rate(s, base) for _, s in sets]
        out.append(md_row(row))
        present = labels(sets[0][1])
        for l in [k for k in FOLLOWS if k in present] + sorted(k for k in present if k not in FOLLOWS):
            if l == base or not l.startswith(base):
                continue
            row = [l, FOLLOWS.get(l, "")]
            for _, s in sets:
                row.append("%s: %s" % (pct(rate(s, l)[0]), fmt_pair(pair(s, l, base))))
            out.append(md_row(row))
    return out


def protocol_table(out_dir, binary):
    rows = ["| label | set | 10 m on both (paper) | 10 m on the observation only, maps to 20 m | "
            "F3Loc's evaluation: maps at 10 m, rays to 20 m |", "|---|---|---|---|---|"]
    for set_title, base in (("generated", "generated"), ("real small", "real_small")):
        bs = summary(out_dir, base, binary)
        cells = {}
        for cell in ("obs_only", "f3loc_eval"):
            cells[cell] = cross(out_dir, base, base + "_protocol_" + cell, binary)
        if bs is None or any(v is None for v in cells.values()):
            continue
        for l in ("kernel", "kernel_authors", "ray", "ray180", "ray_f3loc_code"):
            row = [l, set_title, fmt_rate(bs, l)]
            for cell in ("obs_only", "f3loc_eval"):
                c = cells[cell]["cells"][0]
                e = c["matchers"]["A:%s vs B:%s" % (l, l)]
                n = e["count"]
                ok = e[CRIT]["both"] + e[CRIT]["only_a"]
                row.append("%.1f: %s" % (100.0 * ok / n, fmt_pair(orient(e[CRIT], False))))
            rows.append(md_row(row))
    return rows


def combination_table(out_dir, binary):
    rows = []
    sets = [(t, s) for t, s in (("generated", summary(out_dir, "generated_combinations", binary)),
                                ("real small", summary(out_dir, "real_small_combinations", binary))) if s]
    if not sets:
        return rows
    rows += ["| label | " + " | ".join("%s: rate [95%%]; vs ray (only label / only ray, p)" % t for t, _ in sets) + " |",
             "|---|" + "---|" * len(sets)]
    for l in labels(sets[0][1]):
        row = [l]
        for _, s in sets:
            t = fmt_rate(s, l)
            if l != "ray":
                t += "; " + fmt_pair(pair(s, l, "ray"))
            row.append(t)
        rows.append(md_row(row))
    return rows


def regions_table(out_dir, binary):
    rows = ["| set | sampling | points | kernel | kernel_authors | ray (36) | ray_f3loc_code | ray (180) | ray180 - ray | "
            "kernel - ray |", "|---|---|---|---|---|---|---|---|---|---|"]
    for set_title, base in (("generated", "generated"), ("real small", "real_small")):
        for samp, name in (("transitional, 0.5 m clearance (the study's)", base),
                           ("transitional, 1.0 m clearance", base + "_region_clear1"),
                           ("uniform over the free space", base + "_region_uniform")):
            s = summary(out_dir, name, binary)
            if s is None:
                continue
            rows.append(md_row([set_title, samp, str(rate(s, "kernel")[2]), fmt_rate(s, "kernel"),
                                pct(rate(s, "kernel_authors")[0]), fmt_rate(s, "ray"),
                                pct(rate(s, "ray_f3loc_code")[0]), fmt_rate(s, "ray180"),
                                fmt_pair(pair(s, "ray180", "ray")), fmt_pair(pair(s, "kernel", "ray"))]))
    return rows


TWIN_RAYS = 360
TWIN_TOLERANCE_M = 0.3
TWIN_AGREEING_SHARE = 0.9
TWIN_YAW_SLACK_DEG = 5
STRICT_TOLERANCE_M = 0.1
STRICT_AGREEING_SHARE = 0.95


def twin_table(out_dir, names, matchers=("kernel", "ray", "ray180")):
    """Per building set: each matcher's misses (@1 m 30 deg) and the share of them that are twins."""
    import numpy as np
    import floorcast as fc

    rows = ["| building set | matcher | misses | twins among the misses (90%% of rays within %.1f m) | "
            "strict twins (%.0f%% within %.1f m) | misses that are not twins |" % (
                TWIN_TOLERANCE_M, 100 * STRICT_AGREEING_SHARE, STRICT_TOLERANCE_M),
            "|---|---|---|---|---|---|"]
    for title, name in names:
        run = os.path.join(out_dir, name)
        if not os.path.exists(os.path.join(run, "observations.csv")):
            continue
        config = json.load(open(os.path.join(run, "resolved_config.json")))
        files = {b["label"]: b["file"] for b in config["buildings"]}
        range_m = config["cells"][0]["observation"]["max_range_m"]
        plans, views = {}, {}

        def view(building, x, y, yaw_deg):
            if building not in plans:
                plans[building] = fc.load_plan(os.path.join(ROOT, files[building]))
            try:
                o = fc.perfect_observation(plans[building], (x, y, yaw_deg), rays=TWIN_RAYS, range_m=range_m)
            except Exception:  # the estimate lies in a wall or outside the plan: no view
                return None
            return np.asarray(o.ray_ranges)

        def is_twin(truth, estimate, tolerance_m, share):
            if estimate is None:
                return False
            best = 0.0
            for shift in range(-TWIN_YAW_SLACK_DEG, TWIN_YAW_SLACK_DEG + 1):
                agree = np.mean(np.abs(np.roll(estimate, shift) - truth) <= tolerance_m)
                best = max(best, agree)
            return best >= share

        with open(os.path.join(run, "observations.csv")) as f:
            points = [r for r in csv.DictReader(f) if r["cell"] == "c000"]
        for m in matchers:
            misses = twins = strict = 0
            for r in points:
                ok = r[m + "_ok"] == "1" and float(r[m + "_position_error_m"]) <= 1.0 and \
                    float(r[m + "_yaw_error_deg"]) <= 30.0
                if ok:
                    continue
                misses += 1
                if r[m + "_ok"] != "1":
                    continue
                key = r["unit"]
                if key not in views:
                    views[key] = view(r["building"], float(r["truth_x_m"]), float(r["truth_y_m"]),
                                      float(r["truth_yaw_deg"]))
                estimate = view(r["building"], float(r[m + "_x_m"]), float(r[m + "_y_m"]), float(r[m + "_yaw_deg"]))
                twins += is_twin(views[key], estimate, TWIN_TOLERANCE_M, TWIN_AGREEING_SHARE)
                strict += is_twin(views[key], estimate, STRICT_TOLERANCE_M, STRICT_AGREEING_SHARE)
            rows.append("| %s | %s | %d of %d | %d (%.0f%%) | %d (%.0f%%) | %d |" % (
                title, m, misses, len(points), twins, 100.0 * twins / max(misses, 1), strict,
                100.0 * strict / max(misses, 1), misses - twins))
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default="out/paper_4_4")
    ap.add_argument("--bin", default="build/bin/floorcast")
    a = ap.parse_args()
    out = os.path.abspath(a.out)
    binary = os.path.abspath(a.bin)
    sets = sets_of(out, binary)
    if not sets:
        sys.exit("%s: no finished run (run scripts/paper_4_4.py first)" % out)
    lines = ["## Headline", ""] + headline(sets)
    lines += ["", "## Ingredients, one at a time, paired against their base on the same points", "",
              "Each cell: the variant's success @1 m 30 deg (%); its paired difference from the base in percentage "
              "points [paired bootstrap 95% interval] (points only the variant localizes / only the base, McNemar's "
              "exact p).", ""]
    lines += ingredient_table(sets)
    lines += ["", "## Protocol: where the 10 m range applies (same points, paired against the paper's protocol)", "",
              "Each cell: success @1 m 30 deg (%): difference from the paper's protocol [95%] (only this protocol / "
              "only the paper's, McNemar p).", ""]
    lines += protocol_table(out, binary)
    comb = combination_table(out, binary)
    if comb:
        lines += ["", "## Combinations of the strongest ingredients, paired against the default ray matcher", ""] + comb
    lines += ["", "## Where the points are (different points per row: compare within a row)", ""]
    lines += regions_table(out, binary)
    lines += ["", "## Misses that the building itself hides (twins)", ""]
    lines += twin_table(out, [("generated", "generated"), ("real, 6 small levels", "real_small")] +
                        [("real, " + os.path.basename(d)[len("real_large_"):], os.path.basename(d))
                         for d in sorted(glob.glob(os.path.join(out, "real_large_*")))])
    commits = os.path.join(out, "commit.txt")
    if os.path.exists(commits):
        lines += ["", "Runs and the source commit each was computed at:", "", "```"]
        lines += open(commits).read().strip().splitlines() + ["```"]
    print("\n".join(lines))


if __name__ == "__main__":
    main()
