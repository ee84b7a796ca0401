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
import math
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
ARCHETYPES = ["office", "office_repetitive", "angled", "angled_repetitive", "apartment", "campus",
              "campus_orthogonal_halls", "campus_plain_halls", "campus_no_furniture", "campus_import_walls",
              "campus_blocks", "campus_repetitive"]
# Generated sets that are an archetype with a generator option: the calibrated campus's blocks layout (the
# calibrated campus before it took the spine layout), its halls before they took chamfered corners and before they
# took the real halls' outlines and doors, and the calibrated campus drawn like the imported real plans: with its
# obstacles left out (their sources map none) and with every wall 0.1 m thick (their sources map no thickness; the
# importers draw 0.1 m).
GENERATE = {"campus_blocks": ["--archetype", "campus", "--campus-layout", "blocks"],
            "campus_orthogonal_halls": ["--archetype", "campus", "--campus-halls", "orthogonal"],
            "campus_plain_halls": ["--archetype", "campus", "--campus-halls", "plain"],
            "campus_no_furniture": ["--archetype", "campus", "--no-furniture"],
            "campus_import_walls": ["--archetype", "campus", "--wall-thickness", "0.1"]}


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


def convex_hull(points):
    pts = sorted(set(map(tuple, points)))
    if len(pts) < 3:
        return pts

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    lower, upper = [], []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return lower[:-1] + upper[:-1]


def min_area_rectangle(ring):
    """(area, side along u, side across, unit u, u offset, across offset) of the minimum-area rectangle."""
    hull = convex_hull(ring)
    best = None
    for i in range(len(hull)):
        (ax, ay), (bx, by) = hull[i], hull[(i + 1) % len(hull)]
        length = ((bx - ax) ** 2 + (by - ay) ** 2) ** 0.5
        if length < 1e-9:
            continue
        ux, uy = (bx - ax) / length, (by - ay) / length
        s = [p[0] * ux + p[1] * uy for p in hull]
        t = [-p[0] * uy + p[1] * ux for p in hull]
        a = (max(s) - min(s)) * (max(t) - min(t))
        if best is None or a < best[0]:
            best = (a, max(s) - min(s), max(t) - min(t), (ux, uy), min(s), min(t))
    return best


def simplified_ring(ring, angle_deg=10.0, min_edge_m=0.3):
    """The outline without vertices on a straight run (turn under angle_deg) or on edges under min_edge_m."""
    r = [tuple(p) for p in ring]
    if len(r) > 1 and r[0] == r[-1]:
        r = r[:-1]
    changed = True
    while changed and len(r) > 3:
        changed = False
        for i in range(len(r)):
            a, b, c = r[i - 1], r[i], r[(i + 1) % len(r)]
            e1, e2 = (b[0] - a[0], b[1] - a[1]), (c[0] - b[0], c[1] - b[1])
            l1, l2 = (e1[0] ** 2 + e1[1] ** 2) ** 0.5, (e2[0] ** 2 + e2[1] ** 2) ** 0.5
            if l1 < min_edge_m or l2 < 1e-9 or (e1[0] * e2[0] + e1[1] * e2[1]) / (l1 * l2) > math.cos(
                    math.radians(angle_deg)):
                del r[i]
                changed = True
                break
    return r


def segment_distance(p, a, b):
    dx, dy = b[0] - a[0], b[1] - a[1]
    l2 = dx * dx + dy * dy
    t = 0.0 if l2 == 0 else max(0.0, min(1.0, ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2))
    return ((p[0] - a[0] - t * dx) ** 2 + (p[1] - a[1] - t * dy) ** 2) ** 0.5


def main_axis_deg(walls):
    """The plan's main wall direction modulo 90 deg: the 1-degree bin (with its two neighbours) holding the most
    wall length."""
    bins = [0.0] * 90
    for w in walls:
        dx, dy = w["b"][0] - w["a"][0], w["b"][1] - w["a"][1]
        bins[int(math.degrees(math.atan2(dy, dx)) % 90.0) % 90] += (dx * dx + dy * dy) ** 0.5
    smooth = [bins[k - 1] + bins[k] + bins[(k + 1) % 90] for k in range(90)]
    return smooth.index(max(smooth)) + 0.5


def oblique_sides(ring, axis_deg, min_angle_deg=5.0, min_length_m=0.5):
    """Lengths of the outline's sides (simplified_ring) more than min_angle_deg off both main axes of the plan."""
    simple = simplified_ring(ring)
    out = []
    for k in range(len(simple)):
        a, b = simple[k], simple[(k + 1) % len(simple)]
        length = ((b[0] - a[0]) ** 2 + (b[1] - a[1]) ** 2) ** 0.5
        off = abs((math.degrees(math.atan2(b[1] - a[1], b[0] - a[0])) - axis_deg + 45.0) % 90.0 - 45.0)
        if length >= min_length_m and off > min_angle_deg:
            out.append(length)
    return out


def hall_measures(path, min_area_m2=200.0):
    """Every hall (non-transitional room of min_area_m2 or more) of a plan: area, sides and area share of its
    minimum-area rectangle, corners and reflex corners of its outline (simplified_ring), its sides oblique to the
    plan's main axes (oblique_sides), its doors (centre within 0.4 m of the outline): what lies beyond each (a
    transitional room, another room, outside) and how far its centre is from the nearest corner of its side of the
    rectangle (share of the side), and the obstacles inside."""
    with open(path) as fh:
        plan = json.load(fh)
    axis_deg = main_axis_deg(plan["walls"])
    rooms = [r for r in plan["rooms"] if r["kind"] != "unmapped"]
    walls = {w["id"]: w for w in plan["walls"]}
    halls = []
    for i, r in enumerate(rooms):
        ring = r["polygon"]
        area = polygon_area(ring) - sum(polygon_area(h) for h in r.get("holes", []))
        if r["kind"] in TRANSITIONAL or area < min_area_m2:
            continue
        rect_area, side_u, side_t, (ux, uy), u0, t0 = min_area_rectangle(ring)
        simple = simplified_ring(ring)
        ccw = sum(simple[k][0] * simple[(k + 1) % len(simple)][1] - simple[(k + 1) % len(simple)][0] * simple[k][1]
                  for k in range(len(simple))) > 0
        reflex = 0
        for k in range(len(simple)):
            a, b, c = simple[k - 1], simple[k], simple[(k + 1) % len(simple)]
            turn = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0])
            reflex += 1 if (turn < 0) == ccw else 0
        doors = []
        for d in plan["doors"]:
            c = d["center"]
            if min(segment_distance(c, ring[k], ring[(k + 1) % len(ring)]) for k in range(len(ring))) > 0.4:
                continue
            w = walls.get(d["wall"])
            ex, ey = (w["b"][0] - w["a"][0], w["b"][1] - w["a"][1]) if w else (1.0, 0.0)
            n = (ex ** 2 + ey ** 2) ** 0.5
            beyond = "outside"
            for sign in (1.0, -1.0):
                q = (c[0] - sign * 0.6 * ey / n, c[1] + sign * 0.6 * ex / n)
                if point_in_ring(q[0], q[1], ring):
                    continue
                for j, o in enumerate(rooms):
                    if j != i and point_in_ring(q[0], q[1], o["polygon"]):
                        beyond = "transitional" if o["kind"] in TRANSITIONAL else "room"
                        break
            u = c[0] * ux + c[1] * uy - u0
            t = -c[0] * uy + c[1] * ux - t0
            # On a side along u (t near 0 or side_t): the position along u; else along t.
            along = u / side_u if min(t, side_t - t) <= min(u, side_u - u) else t / side_t
            doors.append((beyond, min(along, 1.0 - along)))
        obstacles = sum(1 for o in plan.get("obstacles", []) if point_in_ring(o["center"][0], o["center"][1], ring))
        halls.append({"area": area, "aspect": max(side_u, side_t) / min(side_u, side_t), "rectangularity":
                      area / rect_area, "corners": len(simple), "reflex": reflex, "doors": doors,
                      "obstacles": obstacles, "oblique": oblique_sides(ring, axis_deg)})
    return halls


def median(values):
    v = sorted(values)
    if not v:
        return float("nan")
    return v[len(v) // 2] if len(v) % 2 else 0.5 * (v[len(v) // 2 - 1] + v[len(v) // 2])


def halls_table(sets):
    """Shape and doors of the halls of each set (pooled over its levels / seeds)."""
    print("## Halls: rooms of 200 m^2 or more (the plans' room polygons and doors; pooled over levels / seeds)\n")
    print("| set | levels | halls | area (m^2), median [range] | aspect (minimum-area rectangle), median [range] "
          "| not rectangles (area under 0.99 of the rectangle) | their area / rectangle, median [range] "
          "| corners, median [range] | reflex corners [range] | halls with 0 / 1 / 2 / 3 or more doors "
          "| halls entered only through another room | door centre from the side's nearest corner "
          "(share of the side), median [range] | doors within 0.02 of 1/4 or 1/2 of their side "
          "| obstacles inside a hall, median | halls with a side oblique to the plan's main axes (over 5 deg) "
          "| oblique sides per such hall, median [range] | oblique side length (m), median [range] |")
    print("|" + "---|" * 17)
    for name, files in sets:
        hs = [h for f in files for h in hall_measures(f)]
        if not hs:
            continue
        shaped = [h["rectangularity"] for h in hs if h["rectangularity"] < 0.99]
        counts = [sum(1 for h in hs if len(h["doors"]) == k) for k in (0, 1, 2)] + [
            sum(1 for h in hs if len(h["doors"]) >= 3)]
        through_room = sum(1 for h in hs if h["doors"] and all(d[0] != "transitional" for d in h["doors"]))
        pos = [d[1] for h in hs for d in h["doors"]]
        at = sum(1 for p in pos if abs(p - 0.25) <= 0.02 or abs(p - 0.5) <= 0.02)

        def mr(values, fmt):
            return (fmt.format(median(values)) + " [" + rng_text(values, fmt) + "]") if values else "-"
        oblique = [h["oblique"] for h in hs if h["oblique"]]
        print("| %s | %d | %d | %s | %s | %d of %d | %s | %s | %s | %s | %d | %s | %s | %s | %d of %d | %s | %s |" % (
            name, len(files), len(hs), mr([h["area"] for h in hs], "{:,.0f}"), mr([h["aspect"] for h in hs], "{:.2f}"),
            len(shaped), len(hs), mr(shaped, "{:.2f}"), mr([h["corners"] for h in hs], "{:.0f}"),
            rng_text([h["reflex"] for h in hs]), " / ".join(str(c) for c in counts), through_room,
            mr(pos, "{:.2f}"), ("%d of %d" % (at, len(pos))) if pos else "-",
            "{:.0f}".format(median([h["obstacles"] for h in hs])), len(oblique), len(hs),
            mr([len(o) for o in oblique], "{:.0f}"), mr([x for o in oblique for x in o], "{:.1f}")))
    print()


def room_category(rooms, x, y):
    """"hall" (a non-transitional room of 200 m^2 or more), "room", "transitional" or "none" at (x, y)."""
    for r in rooms:
        if r["kind"] != "unmapped" and point_in_ring(x, y, r["polygon"]):
            if r["kind"] in TRANSITIONAL:
                return "transitional"
            return "hall" if polygon_area(r["polygon"]) >= 200.0 else "room"
    return "none"


def where_points_table(groups, results):
    """Uniform points by where they stand (halls, smaller rooms, transitional spaces) and the share of each that
    the kernel / ray matcher localises."""
    print("\nWhere the uniform points stand and how often they are localised (kernel / ray, @1 m 30 deg; points "
          "in that kind of space, share of all points):\n")
    print("| set | halls (200 m^2 or more) | rooms under 200 m^2 | transitional spaces |")
    print("|---|---|---|---|")
    for label, name, files in groups:
        rooms = {}
        for f in files:
            with open(f) as fh:
                rooms[os.path.splitext(os.path.basename(f))[0]] = json.load(fh)["rooms"]
        rows = [r for r in results[(name, "u")] if r["building"] in rooms]
        cells = []
        for cat in ("hall", "room", "transitional"):
            sel = [r for r in rows if room_category(rooms[r["building"]], float(r["truth_x_m"]),
                                                    float(r["truth_y_m"])) == cat]
            k = sum(success(r, "kernel") for r in sel)
            y = sum(success(r, "ray") for r in sel)
            cells.append("%d / %d of %d (%.0f%% of the points)" % (k, y, len(sel), pct(len(sel), len(rows))))
        print("| %s | %s | %s | %s |" % (label, cells[0], cells[1], cells[2]))


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

    halls_table([("real, SPbSTU main L0-L2", real_large[:3]), ("real, Grenoble mall L-1..L1", real_large[3:])] +
                [(a, sets[a]) for a in ARCHETYPES if a.startswith("campus")])

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

    where_points_table([("real, SPbSTU main L0-L2", "real_large", real_large[:3])] +
                       [(a, a, sets[a]) for a in ARCHETYPES if a.startswith("campus")], results)

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
