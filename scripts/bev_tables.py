#!/usr/bin/env python3
"""The tables of results/bev.md from the run directories of scripts/bev.sh.

Single shot (scenarios/bev.yaml on the calibrated buildings and on the real development levels):
recall @1 m, @1 m 30 deg, @0.5 m, @0.2 m (the thesis' Table 4.3 columns) and top-5 @1 m per
matcher, setting and BEV predictor preset. Sweep (bev_sweep.yaml): recall @1 m 30 deg of bev vs
bev_nosem per depth spread and class confusion. Sequential (bev_sequential.yaml): the thesis'
Table 4.6 protocol, mean recall per frame over the first N frames of every walk (a trajectory of
length N: the filter is causal, so the first N frames of a longer walk are that trajectory), and
top-K recall over the frames when the units carry the belief's modes. Standard library only.
"""
import glob
import json
import math
import os
import sys

THESIS_43 = [  # seed paper 004, Table 4.3 (Structured3D perspective): 1 m, 1 m 30 deg, 0.5 m, 0.2 m
    ("thesis: F3Loc (from its paper)", 22.4, 21.3, 14.6, None),
    ("thesis: LASER", 6.1, 3.7, 2.7, 0.4),
    ("thesis: ours, no semantics", 12.0, 9.5, 4.9, 1.3),
    ("thesis: ours, semantics", 36.1, 31.7, 19.2, 4.5),
]
THESIS_46 = {  # Table 4.6: trajectory length -> mean recall per frame @2 m, 1 m, 1 m 30 deg, 0.5 m
    2: (14.4, 8.4, 8.2, 3.2), 5: (13.5, 8.2, 7.6, 3.5), 10: (15.9, 10.9, 10.4, 5.2),
    20: (15.1, 9.9, 9.5, 4.9), 50: (17.3, 10.7, 10.1, 4.5), 100: (14.2, 9.3, 8.7, 3.8),
}


def pct(x):
    return "n/a" if x is None or (isinstance(x, float) and math.isnan(x)) else f"{100.0 * x:.1f}"


def load(path):
    with open(path) as f:
        return json.load(f)


def setting_and_preset(cell):
    axes = cell["axes"]
    return axes.get("observation.setting", ""), axes.get("observation.observe_params.bev.preset", "")


def single_shot(run, title):
    path = os.path.join(run, "summary.json")
    if not os.path.exists(path):
        return
    s = load(path)
    print(f"\n### {title}\n")
    print("| setting | BEV preset | matcher | n | @1 m | @1 m 30 deg | @0.5 m | @0.2 m | top-5 @1 m | median error m |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for cell in s["cells"]:
        setting, preset = setting_and_preset(cell)
        for label, m in cell["groups"]["all"].items():
            top = next((v for k, v in m.items() if k.startswith("top") and k.endswith("_recall_1m")), None)
            med = m.get("median_position_error_m")
            print(f"| {setting} | {preset} | {label} | {m['count']} | {pct(m.get('recall_1m'))} | "
                  f"{pct(m.get('recall_1m_30deg'))} | {pct(m.get('recall_0.5m'))} | {pct(m.get('recall_0.2m'))} | "
                  f"{pct(top)} | {'n/a' if med is None else f'{med:.2f}'} |")
    # The paired tests the summaries carry (eval/paired.hpp): the same points, matcher against
    # matcher, McNemar's exact test and a paired bootstrap interval of the difference.
    print(f"\nPaired on the same points (recall @1 m 30 deg, percentage points A - B, paired 95% interval; McNemar p):\n")
    print("| setting | BEV preset | A vs B | only A | only B | A - B | 95% interval | p | verdict at 5% |")
    print("|---|---|---|---|---|---|---|---|---|")
    for cell in s["cells"]:
        setting, preset = setting_and_preset(cell)
        for pair, v in cell.get("paired", {}).get("all", {}).items():
            if "bev" not in pair:
                continue
            r = v.get("recall_1m_30deg")
            if not r:
                continue
            lo, hi = r.get("ci95", [None, None]) or [None, None]
            p = r.get("p_value")
            verdict = "no significant difference"
            if p is not None and p < 0.05:
                verdict = (v["a"] if r["difference"] > 0 else v["b"]) + " better"
            ci = "n/a" if lo is None else f"[{100 * lo:+.1f}, {100 * hi:+.1f}]"
            print(f"| {setting} | {preset} | {pair} | {r['only_a']} | {r['only_b']} | {100 * r['difference']:+.1f} | {ci} | "
                  f"{'n/a' if p is None else f'{p:.3g}'} | {verdict} |")
    print("\nThe thesis (Table 4.3, Structured3D perspective images, ~105 m^2 floors):\n")
    print("| method | @1 m | @1 m 30 deg | @0.5 m | @0.2 m |")
    print("|---|---|---|---|---|")
    for name, *v in THESIS_43:
        print(f"| {name} | " + " | ".join("-" if x is None else f"{x:.1f}" for x in v) + " |")


def sweep(run):
    path = os.path.join(run, "summary.json")
    if not os.path.exists(path):
        return
    s = load(path)
    print("\n### Predictor sweep (recall @1 m 30 deg, %; bev with semantics / without)\n")
    print("| setting | depth sigma per m | window->wall, wall->window, door missed | bev | bev_nosem | semantics gain |")
    print("|---|---|---|---|---|---|")
    for cell in s["cells"]:
        a = cell["axes"]
        g = cell["groups"]["all"]
        b, n = g["bev"].get("recall_1m_30deg"), g["bev_nosem"].get("recall_1m_30deg")
        conf = ", ".join(str(a.get("observation.observe_params.bev." + k)) for k in ("window_as_wall", "wall_as_window", "door_missed"))
        gain = "n/a" if b is None or n is None else f"{100.0 * (b - n):+.1f}"
        print(f"| {a.get('observation.setting')} | {a.get('observation.observe_params.bev.depth_sigma_ln_per_m')} | {conf} | "
              f"{pct(b)} | {pct(n)} | {gain} |")


def mcnemar_p(only_a, only_b):
    """Exact two-sided McNemar p (binomial on the discordant pairs)."""
    n = only_a + only_b
    if n == 0:
        return 1.0
    k = min(only_a, only_b)
    tail = sum(math.comb(n, i) for i in range(k + 1)) / 2.0 ** n
    return min(1.0, 2.0 * tail)


def sweep_pooled(run):
    """The sweep's cells pooled over the other axis, paired per point from the units: bev and
    bev_nosem on the same views (success @1 m 30 deg, and the truth among the top-5 @1 m)."""
    units = glob.glob(os.path.join(run, "units", "*", "*", "*.json"))
    if not units:
        return
    s = load(os.path.join(run, "resolved_config.json")) if os.path.exists(os.path.join(run, "resolved_config.json")) else None
    axes_of = {}
    if s:
        for cell in s.get("cells", []):
            axes_of[cell.get("id")] = cell.get("axes", {})
    summary = load(os.path.join(run, "summary.json"))
    for cell in summary["cells"]:
        axes_of[cell["id"]] = cell["axes"]
    rows = {}
    for u in units:
        j = load(u)
        a = axes_of.get(j["cell"] if isinstance(j["cell"], str) else u.split(os.sep)[-3], axes_of.get(u.split(os.sep)[-3], {}))
        out = {o["label"]: o for o in j["outcomes"]}
        if "bev" not in out or "bev_nosem" not in out:
            continue
        def ok(o, top=False):
            if not o.get("ok"):
                return False
            if top:
                return any(m["position_error_m"] <= 1.0 for m in o.get("top_k", [])[:5])
            e = o["estimate"]
            return e["position_error_m"] <= 1.0 and e["yaw_error_deg"] <= 30.0
        conf = a.get("observation.observe_params.bev.window_as_wall")
        sig = a.get("observation.observe_params.bev.depth_sigma_ln_per_m")
        for key in ((a.get("observation.setting"), "depth sigma per m", sig), (a.get("observation.setting"), "window->wall (confusion level)", conf)):
            r = rows.setdefault(key, [0, 0, 0, 0, 0, 0, 0])
            b, n = ok(out["bev"]), ok(out["bev_nosem"])
            r[0] += 1
            r[1] += b
            r[2] += n
            r[3] += b and not n
            r[4] += n and not b
            r[5] += ok(out["bev"], True)
            r[6] += ok(out["bev_nosem"], True)
    print("\n### Predictor sweep pooled over the other axis (paired per view; success @1 m 30 deg and top-5 @1 m, %)\n")
    print("| setting | axis | value | n | bev | bev_nosem | only bev | only nosem | McNemar p | top-5 bev | top-5 nosem |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for (setting, axis, value), r in sorted(rows.items(), key=lambda kv: (str(kv[0][0]), kv[0][1], kv[0][2])):
        n = r[0]
        print(f"| {setting} | {axis} | {value} | {n} | {100 * r[1] / n:.1f} | {100 * r[2] / n:.1f} | {r[3]} | {r[4]} | "
              f"{mcnemar_p(r[3], r[4]):.3g} | {100 * r[5] / n:.1f} | {100 * r[6] / n:.1f} |")


def sequential(run):
    units = sorted(glob.glob(os.path.join(run, "units", "*", "*", "*.json")))
    if not units:
        return
    tracks = {}  # label -> list of (position errors, yaw errors, mode errors)
    for u in units:
        j = load(u)
        for t in j.get("tracks", []):
            if not t["started"]:
                continue
            tracks.setdefault(t["label"], []).append((t["position_error_m"], t["yaw_error_deg"], t.get("mode_position_error_m")))
    print("\n### Sequential: mean recall per frame over the first N frames (%; thesis Table 4.6 protocol)\n")
    print("| tracker | N | walks | @2 m | @1 m | @1 m 30 deg | @0.5 m | thesis @2 / 1 / 1 m 30 / 0.5 m |")
    print("|---|---|---|---|---|---|---|---|")
    for label, runs in sorted(tracks.items()):
        for n in (2, 5, 10, 20, 50, 100):
            rows = [r for r in runs if len(r[0]) >= n]
            if not rows:
                continue
            def mean_recall(ok):
                return sum(sum(ok(p, y) for p, y in zip(r[0][:n], r[1][:n])) / n for r in rows) / len(rows)
            th = THESIS_46[n]
            print(f"| {label} | {n} | {len(rows)} | {pct(mean_recall(lambda p, y: p <= 2.0))} | "
                  f"{pct(mean_recall(lambda p, y: p <= 1.0))} | {pct(mean_recall(lambda p, y: p <= 1.0 and y <= 30.0))} | "
                  f"{pct(mean_recall(lambda p, y: p <= 0.5))} | {th[0]} / {th[1]} / {th[2]} / {th[3]} |")
    have_modes = any(r[2] for runs in tracks.values() for r in runs)
    if not have_modes:
        return
    print("\n### Sequential: top-K recall @1 m of the belief's peaks per frame (%; thesis Fig. 5.7)\n")
    frames = (1, 2, 5, 10, 20, 50, 100)
    print("| tracker | K | " + " | ".join(f"frame {f}" for f in frames) + " |")
    print("|---|---|" + "---|" * len(frames))
    for label, runs in sorted(tracks.items()):
        for k in (1, 3, 5):
            cells = []
            for f in frames:
                rows = [r for r in runs if r[2] and len(r[2]) >= f]
                if not rows:
                    cells.append("-")
                    continue
                hit = sum(any(e <= 1.0 for e in r[2][f - 1][:k]) for r in rows) / len(rows)
                cells.append(pct(hit))
            print(f"| {label} | {k} | " + " | ".join(cells) + " |")


def bench(path, title):
    """Matching cost per view (floorcast bench match --json): CPU s medians of estimate + top-5."""
    if not os.path.exists(path):
        return
    j = load(path)
    if "plan" in j:  # one plan: its record at the top level
        j = {j["plan"]: j}
    views = {p.get("observations") for p in j.values()}
    print(f"\n### {title}, medians of {', '.join(str(v) for v in sorted(views))} perfect views\n")
    print("| plan | matcher | view | estimate + top-5, CPU s | exhaustive, CPU s | full posterior, CPU s | "
          "scored by the bounded search (ray: cells; bev: cell-orientation pairs) | precompute s (wall) | precompute MB |")
    print("|---|---|---|---|---|---|---|---|---|")
    for plan, p in j.items():
        name = plan.replace("_", " ")
        k = p.get("kernel")
        if k:
            print(f"| {name} | kernel (O = {k['orientations']:.0f}) | 360 deg | {k['modes']['cpu_s']:.3f} | - | "
                  f"{k.get('posterior', {}).get('cpu_s', float('nan')):.3f} | - | {k['precompute_wall_s']:.2f} | {k['precompute_mb']:.0f} |")
        for r in ray_records(p):
            print(f"| {name} | ray ({r['directions']} rays) | 360 deg | {r['modes']['cpu_s']:.3f} | {r['modes_exhaustive']['cpu_s']:.3f} | "
                  f"{r['posterior']['cpu_s']:.3f} | {100 * r['cells_scored_share']:.0f}% | "
                  f"{r['precompute_s']:.2f} | {r['volume_mb']:.0f} |")
        for b in bev_records(p):
            cls = "semantic" if b["semantics"] else "occupancy"
            for x in b["views"]:
                print(f"| {name} | bev {cls} ({x['columns']} columns) | {x['fov_deg']:g} deg | {x['modes']['cpu_s']:.3f} | "
                      f"{x['modes_exhaustive']['cpu_s']:.3f} | {x['posterior']['cpu_s']:.3f} | "
                      f"{100 * x['cells_scored_share']:.0f}% | {b['precompute_wall_s']:.2f} | {b['precompute_mb']:.0f} |")


def ray_records(p):
    """The ray measurements of one plan's `bench match` record: a list (this version) or, in files
    written before the record had a field list, an object keyed by the direction count."""
    r = p.get("ray", [])
    if isinstance(r, list):
        return r
    return [dict(v, directions=int(d), cells_scored_share=v["search_counters"]["cells_scored_share"])
            for d, v in sorted(r.items(), key=lambda x: int(x[0]))]


def bev_records(p):
    """The bev measurements, in the same two shapes (older: {"semantic": {"fov_60": ...}})."""
    b = p.get("bev", [])
    if isinstance(b, list):
        return b
    out = []
    for cls, v in b.items():
        views = [dict(x, fov_deg=float(k[4:]), cells_scored_share=x["search_counters"]["cells_scored_share"])
                 for k, x in v.items() if k.startswith("fov_")]
        out.append(dict(v, semantics=(cls == "semantic"), views=views))
    return out

def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "out/bev"
    single_shot(os.path.join(out, "calibrated"), "Single shot, calibrated office, angled and campus (scenarios/bev.yaml)")
    single_shot(os.path.join(out, "realplans"), "Single shot, six real development levels")
    for path in sorted(glob.glob(os.path.join(out, "bench_*.json"))):
        if os.path.getsize(path):
            bench(path, f"Matching cost per view ({os.path.basename(path)}: floorcast bench match --json)")
    sweep(os.path.join(out, "sweep"))
    sweep_pooled(os.path.join(out, "sweep"))
    sequential(os.path.join(out, "sequential"))


if __name__ == "__main__":
    main()
