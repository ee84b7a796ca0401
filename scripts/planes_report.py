#!/usr/bin/env python3
"""The tables of results/planes.md from the runs of scripts/planes_results.sh.

Reads OUT/{planes,planes_realplans,planes_ablation}/summary.json (the numbers eval wrote; nothing
is recomputed here), OUT/bench_reloc*.json and prints Markdown: scoring with rejection per
observation source and matcher, @1m 30 deg per building for the plane matcher, the ablations
beside the paper's Tables 3, 6 and 7, and the relocalization time.
Usage: scripts/planes_report.py OUT
"""
import json
import os
import sys

SOURCES = {
    ("perfect", "lidar", "mono"): "perfect (2-D walls, 3-D planes, 10 m)",
    ("scan", "lidar", "lidar"): "LiDAR scan (5 m)",
    ("scan", "depth_camera", "lidar"): "depth camera scan (10 m)",
}
ABLATIONS = ["ours", "VR-NE", "VR-NM", "VR-NI", "VR-NG", "VR-NP", "VR-NO", "VR-NS"]
# VoxelPlane-Reloc Tables 3 (ICL-NUIM), 6 (mToF), 7 (L515): TP, TN, FP, FN, P %, R %, avg_time s.
PAPER = {
    "Table 3": {"ours": (99, 39, 1, 22, 99.00, 81.82, 1.47), "VR-NE": (88, 35, 5, 33, 94.62, 72.73, 2.21),
                "VR-NM": (96, 32, 8, 25, 92.31, 79.34, 8.32), "VR-NI": (93, 35, 5, 28, 94.90, 76.86, 4.70),
                "VR-NG": (86, 33, 7, 35, 92.47, 71.07, 14.83), "VR-NP": (77, 30, 10, 44, 88.51, 63.64, 1.68),
                "VR-NO": (69, 28, 12, 52, 85.19, 57.02, 1.23), "VR-NS": (54, 25, 15, 67, 78.26, 44.63, 1.18)},
    "Table 6": {"ours": (66, 49, 0, 6, 100.00, 91.67, 1.45), "VR-NE": (57, 41, 8, 15, 87.69, 79.17, 1.68),
                "VR-NM": (63, 35, 14, 9, 81.82, 87.50, 9.37), "VR-NI": (62, 43, 6, 10, 91.18, 86.11, 5.02),
                "VR-NG": (55, 38, 11, 17, 83.33, 76.39, 14.68), "VR-NP": (47, 34, 15, 25, 75.81, 65.28, 1.49),
                "VR-NO": (43, 32, 17, 29, 71.67, 59.72, 1.38), "VR-NS": (38, 27, 22, 34, 63.33, 52.78, 1.27)},
    "Table 7": {"ours": (63, 45, 4, 6, 94.03, 91.30, 1.52), "VR-NE": (52, 40, 9, 17, 85.25, 75.36, 1.74),
                "VR-NM": (58, 36, 13, 11, 81.69, 84.06, 9.76), "VR-NI": (59, 42, 7, 10, 89.39, 85.51, 4.36),
                "VR-NG": (54, 39, 10, 15, 84.38, 78.26, 15.10), "VR-NP": (42, 32, 17, 27, 71.19, 60.87, 1.97),
                "VR-NO": (37, 28, 21, 32, 63.79, 53.62, 1.34), "VR-NS": (34, 22, 27, 35, 55.74, 49.28, 1.86)},
}


def pct(v):
    return "n/a" if v is None or v != v else f"{100 * v:.1f}"


def ci(r, key):
    lo, hi = r["ci95"][key]
    return f"{pct(r[key])} [{pct(lo)}, {pct(hi)}]"


def load(path):
    with open(path) as f:
        return json.load(f)


def source(cell):
    a = cell["axes"]
    return SOURCES.get((a.get("observation.source"), a.get("observation.sensor"), a.get("observation.path")), str(a))


def rejection_table(summary):
    print("| observations | method | TP | FP (wrong pose) | FP (negative) | TN | FN | precision | recall | F1 | "
          "precision on negatives only | top-5 @1m | time / sample (s) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for cell in summary["cells"]:
        for m in summary["matchers"]:
            g = cell["groups"]["all"][m]
            r = g["rejection"]
            print(f"| {source(cell)} | {m} | {r['tp']:.0f} | {r['fp_wrong_pose']:.0f} | {r['fp_negative']:.0f} | "
                  f"{r['tn']:.0f} | {r['fn']:.0f} | {ci(r, 'precision')} | {ci(r, 'recall')} | {pct(r['f1'])} | "
                  f"{pct(r['precision_negatives_only'])} | {pct(g['top5_recall_1m'])} | {r['mean_time_s']:.3f} |")
    print()


def per_building(summary, matcher="planes"):
    buildings = [b for b in summary["cells"][0]["groups"] if b != "all"]
    print("| observations | " + " | ".join(buildings) + " |")
    print("|---" * (len(buildings) + 1) + "|")
    for cell in summary["cells"]:
        row = []
        for b in buildings:
            g = cell["groups"][b]
            row.append(" / ".join(pct(g[m]["recall_1m_30deg"]) for m in summary["matchers"]))
        print(f"| {source(cell)} | " + " | ".join(row) + " |")
    print()


def ablation_table(summary):
    print("| variant | TP | TN | FP (wrong pose + negative) | FN | P [%] | R [%] | F1 [%] | time / sample (s) | "
          "Table 3 (ICL-NUIM) P / R / s | Table 6 (mToF) P / R / s | Table 7 (L515) P / R / s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for k, cell in enumerate(summary["cells"]):
        name = ABLATIONS[k] if k < len(ABLATIONS) else cell["id"]
        r = cell["groups"]["all"]["planes"]["rejection"]
        paper = " | ".join(f"{PAPER[t][name][4]:.1f} / {PAPER[t][name][5]:.1f} / {PAPER[t][name][6]:.2f}" for t in PAPER)
        print(f"| {name} | {r['tp']:.0f} | {r['tn']:.0f} | {r['fp']:.0f} ({r['fp_wrong_pose']:.0f} + {r['fp_negative']:.0f}) | "
              f"{r['fn']:.0f} | {pct(r['precision'])} | {pct(r['recall'])} | {pct(r['f1'])} | {r['mean_time_s']:.3f} | {paper} |")
    print()


def bench_table(out):
    print("| sensor | plan | scans | map planes | precompute (s CPU) | relocalization = extraction + matching: median / p90 / max (ms CPU) | "
          "extraction median (ms) | matching median (ms) | depth -> voxelised cloud median (ms) | submap planes (median) | "
          "triplets evaluated (median) | localized | within 1 m 30° |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for name in ("bench_reloc.json", "bench_reloc_depth_camera.json"):
        path = os.path.join(out, name)
        if not os.path.exists(path):
            continue
        b = load(path)
        for p in b["plans"]:
            r = p["relocalization_cpu_s"]
            print(f"| {b['sensor']} | {os.path.basename(p['plan'])} | {p['scans']} | {p['map_planes']:.0f} | {p['precompute_cpu_s']:.2f} | "
                  f"{1e3 * r['median']:.1f} / {1e3 * r['p90']:.1f} / {1e3 * r['max']:.1f} | {1e3 * p['extraction_cpu_s']['median']:.1f} | "
                  f"{1e3 * p['match_cpu_s']['median']:.1f} | {1e3 * p['preprocess_cpu_s']['median']:.1f} | {p['submap_planes']['median']:.0f} | "
                  f"{p['hypotheses_evaluated']['median']:.0f} | {p['localized']} of {p['scans']} | {p['within_1m_30deg']} |")
    print()


def main(out):
    for run, title in (("planes", "calibrated buildings"), ("planes_realplans", "real development plans")):
        path = os.path.join(out, run, "summary.json")
        if not os.path.exists(path):
            continue
        s = load(path)
        print(f"## Scoring with rejection: {title} ({run}, scenario hash {s['hash']})\n")
        rejection_table(s)
        print(f"@1m 30° per building ({' / '.join(s['matchers'])}):\n")
        per_building(s)
    path = os.path.join(out, "planes_ablation", "summary.json")
    if os.path.exists(path):
        s = load(path)
        print(f"## Ablations (planes_ablation, scenario hash {s['hash']})\n")
        ablation_table(s)
    print("## Relocalization time (bench reloc)\n")
    bench_table(out)


if __name__ == "__main__":
    main(sys.argv[1])
