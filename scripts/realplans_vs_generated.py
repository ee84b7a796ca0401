#!/usr/bin/env python3
"""Real development plans vs each generated archetype (issue 10 item 2).

Runs `floorcast plan stats` and `floorcast compare-matchers` (kernel, ray 36; perfect
observations, 10 m, doors closed) on the real dev set and on every archetype (calibrated and
repetitive, several seeds), in transitional spaces and uniformly, and prints the side-by-side
tables of results/realplans_vs_generated.md. Called by scripts/realplans_vs_generated.sh, which
imports the real plans first. Standard library only.
"""
import argparse
import csv
import json
import os
import re
import subprocess
import sys

REAL_SMALL = ["tum_studitum_L-1", "tum_studitum_L0", "tum_studitum_L1", "tum_studitum_L2", "tum_studitum_L3",
              "tum_studitum_L4", "rwth_plt_L-1", "rwth_plt_L0", "rwth_plt_L1", "rwth_plt_L2", "rwth_plt_L3",
              "spbstu_no3_L1", "spbstu_no3_L2", "spbstu_no3_L3", "spbstu_no3_L4", "spbstu_no3_L5"]
REAL_LARGE = ["spbstu_main_L0", "spbstu_main_L1", "spbstu_main_L2", "grenoble_mall_L-1", "grenoble_mall_L0",
              "grenoble_mall_L1"]
# The six small levels whose localization is measured (the real dev set of the earlier table); the
# large levels are measured as a second set.
REAL_MATCHED = ["tum_studitum_L1", "tum_studitum_L2", "rwth_plt_L0", "rwth_plt_L1", "spbstu_no3_L2", "spbstu_no3_L4"]
ARCHETYPES = ["office", "office_repetitive", "angled", "angled_repetitive", "apartment", "campus", "campus_blocks",
              "campus_repetitive"]
# Generated sets that are an archetype with a generator option: the calibrated campus's blocks layout (the
# calibrated campus before it took the spine layout).
GENERATE = {"campus_blocks": ["--archetype", "campus", "--campus-layout", "blocks"]}


def run(cmd):
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if r.returncode != 0:
        sys.exit("failed: " + " ".join(cmd) + "\n" + r.stdout)
    return r.stdout


def success(row, m):
    """@1 m 30 deg; an empty posterior (ok = 0) is a miss."""
    if row[m + "_ok"] != "1":
        return False
    return float(row[m + "_position_error_m"]) <= 1.0 and float(row[m + "_yaw_error_deg"]) <= 30.0


def near_equivalent(row, m):
    """The truth is among the top-5 modes but another pose scored best: a near-equivalent pose."""
    if row[m + "_ok"] != "1":
        return False
    return float(row[m + "_position_error_m"]) > 1.0 and float(row[m + "_best_top5_error_m"]) <= 1.0


def pct(k, n):
    return 100.0 * (k / n) if n else float("nan")


def rng_text(values, fmt="{:.0f}"):
    values = [v for v in values if v == v]
    if not values:
        return "-"
    lo, hi = min(values), max(values)
    return fmt.format(lo) if fmt.format(lo) == fmt.format(hi) else fmt.format(lo) + "-" + fmt.format(hi)


TRANSITIONAL = {"hallway", "corridor", "walkway", "lobby", "foyer", "entrance", "atrium", "lounge", "hall", "vestibule",
                "circulation"}  # rooms.cpp transitional_room_kinds()


def polygon_area(ring):
    return 0.5 * abs(sum(ring[i][0] * ring[(i + 1) % len(ring)][1] - ring[(i + 1) % len(ring)][0] * ring[i][1]
                         for i in range(len(ring))))


def circulation_share(path):
    """Transitional rooms' share of the labelled room area (polygons less holes; "unmapped" left out)."""
    with open(path) as fh:
        rooms = json.load(fh)["rooms"]
    total = trans = 0.0
    for r in rooms:
        if r["kind"] == "unmapped":
            continue
        a = polygon_area(r["polygon"]) - sum(polygon_area(h) for h in r.get("holes", []))
        total += a
        trans += a if r["kind"] in TRANSITIONAL else 0.0
    return trans / total if total > 0 else float("nan")


def point_in_ring(x, y, ring):
    inside = False
    for i in range(len(ring)):
        (x1, y1), (x2, y2) = ring[i], ring[(i + 1) % len(ring)]
        if (y1 > y) != (y2 > y) and x < (x2 - x1) * (y - y1) / (y2 - y1) + x1:
            inside = not inside
    return inside


def facade_shares(path):
    """Layout measures from the room polygons: the share of the non-transitional room area in rooms
    with a facade (at least 1 m of boundary whose outside, 0.6 m beyond the edge, lies in no room or
    "unmapped" region), halls (rooms of 200 m^2 or more) on a facade / all halls, and the share of
    the transitional rooms' boundary on a facade (one-sided corridors, glazed lobbies)."""
    with open(path) as fh:
        rooms = json.load(fh)["rooms"]
    boxes = []
    for r in rooms:
        xs, ys = [p[0] for p in r["polygon"]], [p[1] for p in r["polygon"]]
        boxes.append((min(xs), min(ys), max(xs), max(ys)))

    def outside_all(x, y, skip):
        for i, r in enumerate(rooms):
            b = boxes[i]
            if i != skip and b[0] <= x <= b[2] and b[1] <= y <= b[3] and point_in_ring(x, y, r["polygon"]):
                return False
        return True

    def facade_and_perimeter(i):
        ring = rooms[i]["polygon"]
        ccw = sum(ring[k][0] * ring[(k + 1) % len(ring)][1] - ring[(k + 1) % len(ring)][0] * ring[k][1]
                  for k in range(len(ring))) > 0
        facade = perimeter = 0.0
        for k in range(len(ring)):
            (ax, ay), (bx, by) = ring[k], ring[(k + 1) % len(ring)]
            length = ((bx - ax) ** 2 + (by - ay) ** 2) ** 0.5
            if length < 1e-6:
                continue
            nx, ny = (by - ay) / length, -(bx - ax) / length
            if not ccw:
                nx, ny = -nx, -ny
            steps = max(1, int(length / 0.5))
            for j in range(steps):
                t = (j + 0.5) / steps
                if outside_all(ax + t * (bx - ax) + 0.6 * nx, ay + t * (by - ay) + 0.6 * ny, i):
                    facade += length / steps
            perimeter += length
        return facade, perimeter

    room_area = facade_area = boundary = boundary_facade = 0.0
    halls = halls_facade = 0
    for i, r in enumerate(rooms):
        if r["kind"] == "unmapped":
            continue
        f, per = facade_and_perimeter(i)
        if r["kind"] in TRANSITIONAL:
            boundary += per
            boundary_facade += f
            continue
        a = polygon_area(r["polygon"]) - sum(polygon_area(h) for h in r.get("holes", []))
        room_area += a
        facade_area += a if f >= 1.0 else 0.0
        if a >= 200.0:
            halls += 1
            halls_facade += 1 if f >= 1.0 else 0
    nan = float("nan")
    return (facade_area / room_area if room_area > 0 else nan, (halls_facade, halls),
            boundary_facade / boundary if boundary > 0 else nan)


def faithfulness_table(plans_dir):
    """The import report (`plan import --json`, saved by scripts/import_realplans.sh) of every real
    level: is the imported plan what the source says?"""
    print("## Faithfulness of the imports (`floorcast plan import`; floorplans/README.md, \"Faithfulness check\")\n")
    print("| level | spaces | mapped (m^2) | free share of mapped less walls | free outside every space (m^2) "
          "| unmapped, not floor (m^2, regions) | sealed spaces (m^2) | not reachable from the largest free region "
          "(m^2) | unwalled outlines walled at unmapped space | rooms without an opening in the source | warnings |")
    print("|" + "---|" * 11)
    for name in REAL_SMALL + REAL_LARGE:
        path = os.path.join(plans_dir, "reports", name + ".json")
        if not os.path.exists(path):
            continue
        with open(path) as fh:
            r = json.load(fh)
        f = r["faithfulness"]
        rooms_without = "0"
        for n in r["notes"]:
            m = re.search(r"(\d+) of (\d+) rooms have no opening", n)
            if m:
                rooms_without = "%s of %s" % (m.group(1), m.group(2))
        walled = r["repairs"].get("open_outlines_walled_at_unmapped", 0)
        print("| %s | %d | %s | %.1f%% | %.1f | %.0f (%d) | %d (%.0f) | %d (%.0f) | %d | %s | %s |" % (
            name, f["spaces"], "{:,.0f}".format(f["mapped_area_m2"]), 100.0 * f["free_share"],
            f["free_outside_mapped_m2"], f["unmapped_area_m2"], f["unmapped_regions"], f["sealed_spaces"],
            f["sealed_area_m2"], f["unreachable_spaces"], f["unreachable_area_m2"], walled, rooms_without,
            "; ".join(r["warnings"]) if r["warnings"] else "none"))
    print()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", default="build/bin/floorcast")
    ap.add_argument("--plans", required=True, help="directory of imported real plans")
    ap.add_argument("--out", required=True)
    ap.add_argument("--points", type=int, default=40, help="observation points per plan")
    ap.add_argument("--seeds", default="1,2,3", help="generator seeds per archetype")
    ap.add_argument("--campus-seeds", default="1,2,3,4", help="campus seeds (large buildings)")
    args = ap.parse_args()
    os.makedirs(os.path.join(args.out, "gen"), exist_ok=True)

    sets = {"real": [os.path.join(args.plans, n + ".json") for n in REAL_MATCHED],
            "real_large": [os.path.join(args.plans, n + ".json") for n in REAL_LARGE]}
    for a in ARCHETYPES:
        seeds = args.campus_seeds if a.startswith("campus") else args.seeds
        files = []
        for s in seeds.split(","):
            f = os.path.join(args.out, "gen", "%s_%s.json" % (a, s))
            run([args.bin, "plan", "generate"] + GENERATE.get(a, ["--archetype", a]) + ["--seed", s, "-o", f])
            files.append(f)
        sets[a] = files

    faithfulness_table(args.plans)

    # Structure.
    real_small = [os.path.join(args.plans, n + ".json") for n in REAL_SMALL]
    real_large = [os.path.join(args.plans, n + ".json") for n in REAL_LARGE]
    all_files = real_small + real_large + [f for a in ARCHETYPES for f in sets[a]]
    stats = {s["file"]: s for s in json.loads(run([args.bin, "plan", "stats", "--json"] + all_files))}
    with open(os.path.join(args.out, "stats.json"), "w") as fh:
        json.dump(list(stats.values()), fh, indent=1)

    def measures(files):
        rows = [stats[f] for f in files]
        ra = [r["room_area_m2"] for r in rows]
        fs = [facade_shares(f) for f in files]
        return {
            "levels": len(rows),
            "area": rng_text([r["free_area_m2"] for r in rows], "{:,.0f}"),
            "walls": rng_text([r["walls"] for r in rows]),
            "doors": rng_text([r["doors_per_10m_wall"] for r in rows], "{:.2f}"),
            "dirs": rng_text([r["directions_used"] for r in rows]),
            "thick": rng_text([len(r["thickness_classes"]) for r in rows]),
            "area_med": rng_text([a["median"] for a in ra if a["count"]], "{:.1f}"),
            "area_iqr": rng_text([a["q3"] / a["q1"] for a in ra if a["count"] and a["q1"] > 0], "{:.2f}"),
            "area_cv": rng_text([a["cv"] for a in ra if a["count"]], "{:.2f}"),
            "width_cv": rng_text([r["room_width_m"]["cv"] for r in rows if r["room_width_m"]["count"]], "{:.2f}"),
            "rep": rng_text([r["repeated_width_share"] for r in rows if r["room_area_m2"]["count"]], "{:.2f}"),
            "corr": rng_text([r["corridor_width_m"]["median"] for r in rows if r["corridor_width_m"]["count"]],
                             "{:.1f}"),
            "circ": rng_text([circulation_share(f) for f in files], "{:.2f}"),
            "facade": rng_text([v[0] for v in fs], "{:.2f}"),
            "halls": ", ".join("%d/%d" % v[1] for v in fs),
            "corr_facade": rng_text([v[2] for v in fs], "{:.2f}"),
        }

    print("## Structure (`floorcast plan stats`; ranges over levels / seeds)\n")
    print("| set | levels | free area (m^2) | walls | doors per 10 m of wall | wall directions (15 deg bins) "
          "| thickness classes | median room (m^2) | room area q3/q1 | room area cv | room width cv "
          "| repeated widths (share of rooms) | median corridor width (m) | circulation share of the room area "
          "| room area on a facade | halls (200 m^2 or more) on a facade, per level | transitional boundary on a facade |")
    print("|" + "---|" * 17)
    struct_sets = [("real, small (TUM, RWTH, SPbSTU No. 3)", real_small), ("real, large (SPbSTU main, Grenoble mall)",
                                                                            real_large),
                   ("real, the six matched levels", sets["real"])] + [(a, sets[a]) for a in ARCHETYPES]
    for name, files in struct_sets:
        m = measures(files)
        print("| %s | %d | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
            name, m["levels"], m["area"], m["walls"], m["doors"], m["dirs"], m["thick"], m["area_med"], m["area_iqr"],
            m["area_cv"], m["width_cv"], m["rep"], m["corr"], m["circ"], m["facade"], m["halls"], m["corr_facade"]))

    # Localization.
    results = {}
    for name, files in sets.items():
        for mode in ("t", "u"):
            out = os.path.join(args.out, "runs", "%s_%s" % (name, mode))
            cmd = [args.bin, "compare-matchers"] + files + ["--points", str(args.points), "--seed", "1", "--rays",
                                                          "36", "--quiet", "-o", out]
            if mode == "u":
                cmd.append("--uniform")
            run(cmd)
            with open(os.path.join(out, "observations.csv")) as fh:
                results[(name, mode)] = list(csv.DictReader(fh))

    def per_plan(rows, m):
        plans = {}
        for r in rows:
            plans.setdefault(r["building"], []).append(success(r, m))
        return {b: pct(sum(v), len(v)) for b, v in plans.items()}

    real_range = {}
    for ref in ("real", "real_large"):
        for mode in ("t", "u"):
            for m in ("kernel", "ray"):
                v = per_plan(results[(ref, mode)], m).values()
                real_range[(ref, mode, m)] = (min(v), max(v))

    print("\n## Perfect-observation success @1 m 30 deg (pooled over plans; [per-plan range])\n")
    print("| set | points per sampling | kernel, transitional | ray 36, transitional | kernel, uniform | ray 36, uniform "
          "| near-equivalent poses kernel / ray (transitional) | no pose kernel / ray | inside the small real levels' "
          "per-plan range (k-t, r-t, k-u, r-u) | inside the large real levels' range |")
    print("|" + "---|" * 10)
    for name in sets:
        cells, inside, inside_large = [], [], []
        for mode in ("t", "u"):
            for m in ("kernel", "ray"):
                rows = results[(name, mode)]
                pooled = pct(sum(success(r, m) for r in rows), len(rows))
                pp = per_plan(rows, m).values()
                cells.append("**%.1f** [%s]" % (pooled, rng_text(list(pp))))
                lo, hi = real_range[("real", mode, m)]
                inside.append("yes" if lo <= pooled <= hi else "no")
                lo, hi = real_range[("real_large", mode, m)]
                inside_large.append("yes" if lo <= pooled <= hi else "no")
        rows_t = results[(name, "t")]
        ne = " / ".join("%.0f%%" % pct(sum(near_equivalent(r, m) for r in rows_t), len(rows_t)) for m in ("kernel",
                                                                                                         "ray"))
        nopose = " / ".join(
            "%d" % sum(r[m + "_ok"] != "1" for mode in ("t", "u") for r in results[(name, mode)]) for m in ("kernel",
                                                                                                         "ray"))
        label = {"real": "real, six small levels", "real_large": "real, large levels (SPbSTU main, Grenoble mall)"}
        print("| %s | %d | %s | %s | %s | %s | %s | %s | %s | %s |" % (
            label.get(name, name), len(rows_t), cells[0], cells[1], cells[2], cells[3], ne, nopose,
            "-" if name.startswith("real") else ", ".join(inside),
            "-" if name.startswith("real") else ", ".join(inside_large)))

    print("\nPer plan (kernel / ray, transitional | uniform):\n")
    print("| plan | transitional | uniform |")
    print("|---|---|---|")
    for name in sets:
        kt, rt = per_plan(results[(name, "t")], "kernel"), per_plan(results[(name, "t")], "ray")
        ku, ru = per_plan(results[(name, "u")], "kernel"), per_plan(results[(name, "u")], "ray")
        for b in kt:
            print("| %s | %.0f / %.0f | %.0f / %.0f |" % (b, kt[b], rt[b], ku.get(b, float("nan")),
                                                          ru.get(b, float("nan"))))


if __name__ == "__main__":
    main()
