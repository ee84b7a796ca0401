#!/usr/bin/env python3
"""Precision / recall of every matcher of a run when it abstains below a score threshold.

Reads RUN/units/**.json and RUN/resolved_config.json, and for each cell and matcher sweeps the
threshold over the recorded best scores (the `min_score` parameter every matcher takes, applied
after the fact: a unit whose best score is below it is "not localized"). Scoring as in the run's
summary: TP = a positive localized within 1 m and 30 deg (the scenario's combined threshold), FP =
a negative localized or a positive localized elsewhere, FN = a positive not localized, TN = a
negative not localized. Prints one Markdown table per cell: the threshold of best F1 per matcher
and the operating points at precision >= 0.9 / 0.95 / 0.99 (highest recall reaching it).
"""
import glob
import json
import os
import sys


def main(run):
    resolved = json.load(open(os.path.join(run, "resolved_config.json")))
    sc = resolved["scoring"]
    cm, cd = sc["combined_threshold_m"], sc["combined_threshold_deg"]
    count = resolved["sampling"]["count"]
    cells = {}
    for f in glob.glob(os.path.join(run, "units", "**", "*.json"), recursive=True):
        u = json.load(open(f))
        cell = u["id"].split("/")[0]
        negative = u["point"] >= count
        for o in u["outcomes"]:
            rec = {"neg": negative, "ok": bool(u["observation_ok"] and o["ok"]), "score": None, "correct": False}
            if rec["ok"]:
                e = o["estimate"]
                rec["score"] = e["score"]
                rec["correct"] = (not negative) and e["position_error_m"] <= cm and e["yaw_error_deg"] <= cd
            cells.setdefault(cell, {}).setdefault(o["label"], []).append(rec)
    print(f"# Abstaining below a score threshold: {os.path.basename(os.path.normpath(run))}\n")
    print("Thresholds are the matchers' own scores (kernel: correlation score; ray: F3Loc score; "
          "planes: pose density); every threshold is one `min_score`.\n")
    for cell in sorted(cells):
        print(f"## {cell}\n")
        print("| matcher | positives | negatives | min_score 0: P / R / F1 | best F1: min_score, P / R / F1 | "
              "P >= 0.90: R | P >= 0.95: R | P >= 0.99: R |")
        print("|---|---|---|---|---|---|---|---|")
        for label in sorted(cells[cell]):
            recs = cells[cell][label]
            pos = sum(1 for r in recs if not r["neg"])
            neg = len(recs) - pos

            def score_at(t):
                tp = sum(1 for r in recs if r["ok"] and r["score"] >= t and r["correct"])
                fp = sum(1 for r in recs if r["ok"] and r["score"] >= t and not r["correct"])
                p = tp / (tp + fp) if tp + fp else float("nan")
                rc = tp / pos if pos else float("nan")
                f1 = 2 * p * rc / (p + rc) if tp else 0.0
                return p, rc, f1

            thresholds = sorted({0.0} | {r["score"] for r in recs if r["ok"]})
            pts = [(t,) + score_at(t) for t in thresholds]
            base = score_at(0.0)
            best = max(pts, key=lambda x: (x[3], -x[0]))

            def at_precision(target):
                ok = [x for x in pts if x[1] == x[1] and x[1] >= target]
                return f"{100 * max(x[2] for x in ok):.1f}" if ok else "–"

            fmt = lambda v: "n/a" if v != v else f"{100 * v:.1f}"
            print(f"| {label} | {pos} | {neg} | {fmt(base[0])} / {fmt(base[1])} / {fmt(base[2])} | "
                  f"{best[0]:.4g}, {fmt(best[1])} / {fmt(best[2])} / {fmt(best[3])} | {at_precision(0.9)} | "
                  f"{at_precision(0.95)} | {at_precision(0.99)} |")
        print()


if __name__ == "__main__":
    main(sys.argv[1])
