#!/usr/bin/env python3
"""Writes the importer test fixtures in this folder (plain Python 3, no packages).

The fixtures are committed; run this only to regenerate them after changing the designs below.
Every design is given in local metres; geographic fixtures are placed around a WGS84 origin with
the meridional / prime-vertical radii of curvature at the origin (exact to well below 1 mm over
the few tens of metres used here).
"""
import json
import math
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))

# ---- geographic helpers -----------------------------------------------------------------------
A = 6378137.0
F = 1.0 / 298.257223563
E2 = F * (2.0 - F)
LAT0, LON0 = 47.3769, 8.5417


def radii(lat_deg):
    s = math.sin(math.radians(lat_deg))
    m = A * (1.0 - E2) / (1.0 - E2 * s * s) ** 1.5
    n = A / math.sqrt(1.0 - E2 * s * s)
    return m, n


M0, N0 = radii(LAT0)


def lonlat(x, y):
    """Local metres (east, north) about (LAT0, LON0) -> [lon, lat]."""
    lat = LAT0 + math.degrees(y / M0)
    lon = LON0 + math.degrees(x / (N0 * math.cos(math.radians(LAT0))))
    return [round(lon, 10), round(lat, 10)]


def write(path, text):
    full = os.path.join(HERE, path)
    os.makedirs(os.path.dirname(full), exist_ok=True)
    with open(full, "w") as f:
        f.write(text)


# ---- Structured3D -------------------------------------------------------------------------------
class S3dScene:
    def __init__(self):
        self.junctions, self.lines, self.planes, self.semantics = [], [], [], []
        self.plane_lines = []   # per plane: set of line indices
        self.line_juncs = []    # per line: (j0, j1)

    def junction(self, x, y, z):
        self.junctions.append([float(x), float(y), float(z)])
        return len(self.junctions) - 1

    def line(self, j0, j1):
        p0, p1 = self.junctions[j0], self.junctions[j1]
        d = [p1[k] - p0[k] for k in range(3)]
        n = math.sqrt(sum(v * v for v in d))
        self.lines.append({"ID": len(self.lines), "point": p0, "direction": [v / n for v in d]})
        self.line_juncs.append((j0, j1))
        return len(self.lines) - 1

    def plane(self, kind, normal, point, lines):
        offset = -sum(normal[k] * point[k] for k in range(3))
        self.planes.append({"ID": len(self.planes), "type": kind, "normal": [float(v) for v in normal],
                            "offset": offset})
        self.plane_lines.append(set(lines))
        return len(self.planes) - 1

    def semantic(self, kind, planes):
        self.semantics.append({"ID": len(self.semantics), "type": kind, "planeID": planes})

    def box_room(self, kind, x0, y0, x1, y1, h, holes=None, exterior=False):
        """A room (normals inside) or, with exterior=True, an outwall shell (normals outside).
        holes: {wall side: [list of hole line indices]} added to that wall plane."""
        holes = holes or {}
        c = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
        fj = [self.junction(x, y, 0) for x, y in c]
        cj = [self.junction(x, y, h) for x, y in c]
        fl = [self.line(fj[k], fj[(k + 1) % 4]) for k in range(4)]
        cl = [self.line(cj[k], cj[(k + 1) % 4]) for k in range(4)]
        vl = [self.line(fj[k], cj[k]) for k in range(4)]
        planes = []
        if not exterior:
            planes.append(self.plane("floor", [0, 0, 1], [x0, y0, 0], fl))
            planes.append(self.plane("ceiling", [0, 0, -1], [x0, y0, h], cl))
        sides = ["south", "east", "north", "west"]
        inward = {"south": [0, 1, 0], "east": [-1, 0, 0], "north": [0, -1, 0], "west": [1, 0, 0]}
        for k, side in enumerate(sides):
            n = inward[side] if not exterior else [-v for v in inward[side]]
            lines = [fl[k], cl[k], vl[k], vl[(k + 1) % 4]] + holes.get(side, [])
            planes.append(self.plane("wall", n, [c[k][0], c[k][1], 0], lines))
        self.semantic(kind, planes)
        return planes

    def hole_x(self, x, y0, y1, z0, z1):
        """Rectangular hole in a plane x = const; returns its 4 lines."""
        j = [self.junction(x, y0, z0), self.junction(x, y1, z0), self.junction(x, y1, z1), self.junction(x, y0, z1)]
        return [self.line(j[k], j[(k + 1) % 4]) for k in range(4)]

    def hole_y(self, y, x0, x1, z0, z1):
        j = [self.junction(x0, y, z0), self.junction(x1, y, z0), self.junction(x1, y, z1), self.junction(x0, y, z1)]
        return [self.line(j[k], j[(k + 1) % 4]) for k in range(4)]

    def to_json(self):
        plm = [[1 if l in self.plane_lines[p] else 0 for l in range(len(self.lines))] for p in range(len(self.planes))]
        ljm = [[1 if j in self.line_juncs[l] else 0 for j in range(len(self.junctions))] for l in range(len(self.lines))]
        return {
            "junctions": [{"ID": i, "coordinate": c} for i, c in enumerate(self.junctions)],
            "lines": self.lines,
            "planes": self.planes,
            "semantics": self.semantics,
            "planeLineMatrix": plm,
            "lineJunctionMatrix": ljm,
            "cuboids": [],
            "manhattan": [],
        }


def make_s3d():
    """Three rooms in a row (mm): A [0,4000]x[0,3000], B [4200,8000]x[0,3000] (a 200 mm wall
    between them), C [8000,10000]x[0,3000] (a zero-thickness partition with B, so B's east and C's
    west surfaces coincide: a duplicated edge). Height 2800. Openings:
      door 1 A<->B through the 200 mm wall, y in [1000,1900] (one hole plane per surface);
      door 2 B north, x in [6000,6900] (one plane, on B's surface only);
      door 3 B<->C on the zero-thickness partition, y in [1000,1800] (two coincident planes);
      window on A's south surface, x in [1000,2500], z in [900,2100].
    An outwall shell at 200 mm outside everything."""
    s = S3dScene()
    h = 2800
    # Holes (lines shared by the door/window planes and the wall planes they are cut into).
    d1a = s.hole_x(4000, 1000, 1900, 0, 2100)
    d1b = s.hole_x(4200, 1000, 1900, 0, 2100)
    d2 = s.hole_y(3000, 6000, 6900, 0, 2100)
    d2o = s.hole_y(3200, 6000, 6900, 0, 2100)
    d3 = s.hole_x(8000, 1000, 1800, 0, 2100)
    win = s.hole_y(0, 1000, 2500, 900, 2100)
    wino = s.hole_y(-200, 1000, 2500, 900, 2100)
    s.box_room("living room", 0, 0, 4000, 3000, h, holes={"east": d1a, "south": win})
    s.box_room("bedroom", 4200, 0, 8000, 3000, h, holes={"west": d1b, "north": d2, "east": d3})
    s.box_room("kitchen", 8000, 0, 10000, 3000, h, holes={"west": d3})
    s.box_room("outwall", -200, -200, 10200, 3200, h, holes={"north": d2o, "south": wino}, exterior=True)
    p = s.plane("wall", [-1, 0, 0], [4000, 0, 0], d1a)
    q = s.plane("wall", [1, 0, 0], [4200, 0, 0], d1b)
    s.semantic("door", [p, q])
    p = s.plane("wall", [0, -1, 0], [0, 3000, 0], d2)
    s.semantic("door", [p])
    p = s.plane("wall", [-1, 0, 0], [8000, 0, 0], d3)
    q = s.plane("wall", [1, 0, 0], [8000, 0, 0], d3)
    s.semantic("door", [p, q])
    p = s.plane("wall", [0, 1, 0], [0, 0, 0], win)
    s.semantic("window", [p])
    write("s3d/scene_00000/annotation_3d.json", json.dumps(s.to_json(), separators=(",", ":")) + "\n")


# ---- IMDF ---------------------------------------------------------------------------------------
def polygon(pts):
    ring = [lonlat(x, y) for x, y in pts]
    return {"type": "Polygon", "coordinates": [ring + [ring[0]]]}


def feature(fid, ftype, geometry, props):
    return {"id": fid, "type": "Feature", "feature_type": ftype, "geometry": geometry, "properties": props}


def collection(features):
    return json.dumps({"type": "FeatureCollection", "features": features}, indent=1) + "\n"


def rect(x0, y0, x1, y1):
    return [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]


def unit(fid, level, category, pts):
    return feature(fid, "unit", polygon(pts), {"category": category, "restriction": None, "accessibility": None,
                                               "name": {"en": fid}, "alt_name": None, "level_id": level,
                                               "display_point": None})


def opening(fid, level, a, b, category="pedestrian"):
    geom = {"type": "LineString", "coordinates": [lonlat(*a), lonlat(*b)]}
    return feature(fid, "opening", geom, {"category": category, "accessibility": None, "access_control": None,
                                          "door": {"type": "hinged", "automatic": False, "material": "wood"},
                                          "name": None, "alt_name": None, "display_point": None, "level_id": level})


def level(fid, ordinal, name, pts, building):
    return feature(fid, "level", polygon(pts), {"category": "unspecified", "restriction": None, "outdoor": False,
                                                "ordinal": ordinal, "name": {"en": name},
                                                "short_name": {"en": str(ordinal)}, "display_point": None,
                                                "address_id": None, "building_ids": [building]})


def make_imdf():
    # simple: one level, the level polygon [-10,10]x[-5,5] centred on the origin.
    L = "11111111-1111-1111-1111-111111111111"
    units = [
        unit("room-a", L, "room", rect(-10, 0, -2, 5)),
        # room B: a collinear extra vertex on its south edge and a corner drawn 5 mm off.
        unit("room-b", L, "room", [(-2.005, 0.004), (4, 0), (10, 0), (10, 5), (-2, 5)]),
        unit("walk-1", L, "walkway", rect(-10, -5, 0, 0)),
        unit("walk-2", L, "walkway", rect(0, -5, 10, 0)),
    ]
    openings = [
        opening("o1", L, (-7, 0), (-6, 0)),
        opening("o2", L, (5, 0), (6.5, 0)),
        opening("o3", L, (-2, 2), (-2, 2.9)),
        opening("o4-open", L, (0, -3), (0, -2)),
    ]
    write("imdf/simple/level.geojson", collection([level(L, 0, "Ground", rect(-10, -5, 10, 5), "b1")]))
    write("imdf/simple/unit.geojson", collection(units))
    write("imdf/simple/opening.geojson", collection(openings))

    # campus: two buildings; ordinal 0 exists in both (ambiguous), ordinal 1 only in building 1.
    b1l0, b1l1, b2l0 = "b1-level-0", "b1-level-1", "b2-level-0"
    levels = [level(b1l0, 0, "B1 Ground", rect(0, 0, 20, 10), "b1"),
              level(b1l1, 1, "B1 First", rect(0, 0, 20, 10), "b1"),
              level(b2l0, 0, "B2 Ground", rect(40, 0, 50, 8), "b2")]
    units = [unit("b1-0-hall", b1l0, "room", rect(0, 0, 20, 10)),
             unit("b1-1-west", b1l1, "room", rect(0, 0, 10, 10)),
             unit("b1-1-east", b1l1, "room", rect(10, 0, 20, 10)),
             unit("b2-0-shop", b2l0, "room", rect(40, 0, 50, 8))]
    openings = [opening("b1-1-door", b1l1, (10, 4), (10, 5))]
    write("imdf/campus/level.geojson", collection(levels))
    write("imdf/campus/unit.geojson", collection(units))
    write("imdf/campus/opening.geojson", collection(openings))


# ---- OSM ----------------------------------------------------------------------------------------
class Osm:
    def __init__(self):
        self.nodes, self.ways = [], []
        self.next_id = 1

    def node(self, x, y, **tags):
        nid = self.next_id
        self.next_id += 1
        lon, lat = lonlat(x, y)
        self.nodes.append((nid, lat, lon, tags))
        return nid

    def way(self, refs, **tags):
        wid = 1000 + len(self.ways)
        self.ways.append((wid, refs, tags))
        return wid

    def closed(self, refs, **tags):
        return self.way(refs + [refs[0]], **tags)

    def xml(self):
        def tag_xml(tags):
            return "".join('    <tag k="%s" v="%s"/>\n' % (k.replace("_colon_", ":"), v) for k, v in sorted(tags.items()))
        out = ['<?xml version="1.0" encoding="UTF-8"?>\n<osm version="0.6" generator="floorcast fixtures">\n']
        for nid, lat, lon, tags in self.nodes:
            if tags:
                out.append('  <node id="%d" lat="%.10f" lon="%.10f">\n%s  </node>\n' % (nid, lat, lon, tag_xml(tags)))
            else:
                out.append('  <node id="%d" lat="%.10f" lon="%.10f"/>\n' % (nid, lat, lon))
        for wid, refs, tags in self.ways:
            out.append('  <way id="%d">\n' % wid)
            out.extend('    <nd ref="%d"/>\n' % r for r in refs)
            out.append(tag_xml(tags))
            out.append("  </way>\n")
        out.append("</osm>\n")
        return "".join(out)


def make_osm():
    o = Osm()
    n = o.node
    # Level 0 rooms sharing nodes, a split corridor, an open area, a free wall; a staircase on
    # levels 0;1 and a lift shaft on the range -1-1 drawn with their own (duplicate) nodes.
    p00, p30, p60, p120 = n(0, 0), n(2, 0, door="yes"), n(6, 0), n(12, 0)
    p62 = n(6, 2, door="hinged", width="1.2")
    p04, p34, p64, p94, p124 = n(0, 4), n(3, 4, door="hinged", width="0.9"), n(6, 4), n(9, 4, door="yes", width="90 cm"), n(12, 4)
    p124m = n(12.008, 4.003)  # room R2's corner, drawn 8 mm off and not shared
    p06, p65, p66, p126 = n(0, 6), n(6, 5, door="no"), n(6, 6), n(12, 6)
    o.closed([p00, p30, p60, p62, p64, p34, p04], indoor="room", level="0", name="R1")
    o.closed([p60, p120, p124m, p94, p64, p62], indoor="room", level="0", name="R2")
    o.closed([p04, p34, p64, p65, p66, p06], indoor="corridor", level="0", name="C1")
    o.closed([p64, p94, p124, p126, p66, p65], indoor="corridor", level="0", name="C2")
    o.closed([n(12, 0), n(16, 0), n(16, 6), n(12, 6)], indoor="area", level="0", name="hall")
    o.way([n(13, 3), n(15, 3)], indoor="wall", level="0")
    o.closed([n(-3, 0), n(0, 0), n(0, 6), n(-3, 6)], indoor="room", level="0;1", name="stairs")
    o.closed([n(12, 6), n(14, 6), n(14, 8), n(12, 8)], indoor="room", level="-1-1", name="lift")
    # Level 1: one big room with a door on its south wall (the door node carries its own level).
    o.closed([n(0, 0), n(5, 0, door="yes", level="1"), n(12, 0), n(12, 6), n(0, 6)], indoor="room", level="1", name="R3")
    # Level -1: basement.
    o.closed([n(0, 0), n(10, 0), n(10, 6), n(0, 6)], indoor="room", level="-1", name="basement")
    write("osm/building.osm", o.xml())


# ---- PNG ----------------------------------------------------------------------------------------
def write_png(path, rows):
    h, w = len(rows), len(rows[0])
    raw = b"".join(b"\x00" + bytes(r) for r in rows)
    def chunk(kind, data):
        c = struct.pack(">I", len(data)) + kind + data
        return c + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 0, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    full = os.path.join(HERE, path)
    os.makedirs(os.path.dirname(full), exist_ok=True)
    with open(full, "wb") as f:
        f.write(png)


def make_png():
    """F3Loc-style occupancy, 0.05 m/px, 160 x 100 px (8 m x 5 m). Walls 4 px (0.2 m) thick, drawn
    in gray 127 (anything but 255 is occupied): outer box with its outer edge at pixel 10..150 x
    10..90 (image rows, top = row 0), an interior wall at columns 78..81 from the top wall down to
    row 60 (a T-junction and a free end), a door gap of 18 px in the bottom wall at columns
    30..47, and a one-pixel speck (noise)."""
    w, h = 160, 100
    img = [[255] * w for _ in range(h)]
    def fill(c0, r0, c1, r1, v=127):
        for r in range(r0, r1):
            for c in range(c0, c1):
                img[r][c] = v
    fill(10, 10, 150, 14)    # top wall (rows 10..13)
    fill(10, 86, 150, 90)    # bottom wall (rows 86..89)
    fill(10, 10, 14, 90)     # left wall
    fill(146, 10, 150, 90)   # right wall
    fill(78, 14, 82, 60)     # interior wall hanging from the top wall, free end at row 60
    fill(30, 86, 48, 90, 255)  # door gap in the bottom wall
    img[40][120] = 0         # speck
    write_png("png/two_rooms_f3loc.png", img)


# ---- Real-data defects (issue 10) ---------------------------------------------------------------
def chamfered(pts, cut):
    """A polygon whose every corner is cut by a short diagonal edge (`cut` m along each side), the
    way survey/CAD exports leave sub-3-cm pieces at corners."""
    out = []
    n = len(pts)
    for i in range(n):
        px, py = pts[i - 1]
        cx, cy = pts[i]
        nx, ny = pts[(i + 1) % n]
        def toward(ax, ay, bx, by, d):
            L = math.hypot(bx - ax, by - ay)
            return (ax + (bx - ax) * d / L, ay + (by - ay) * d / L)
        out.append(toward(cx, cy, px, py, cut))
        out.append(toward(cx, cy, nx, ny, cut))
    return out


def jogged(pts, every, jog):
    """Inserts, every `every` m along each edge, a 1-cm-long step `jog` m off the edge and back
    (double vertices a few millimetres apart)."""
    out = []
    n = len(pts)
    for i in range(n):
        ax, ay = pts[i]
        bx, by = pts[(i + 1) % n]
        L = math.hypot(bx - ax, by - ay)
        ux, uy = (bx - ax) / L, (by - ay) / L
        out.append((ax, ay))
        t = every
        while t + 0.01 < L - 0.05:
            out.append((ax + ux * t, ay + uy * t))
            out.append((ax + ux * (t + 0.01) - uy * jog, ay + uy * (t + 0.01) + ux * jog))
            out.append((ax + ux * (t + 0.02), ay + uy * (t + 0.02)))
            t += every
    return out


def split(pts, step):
    """Extra collinear vertices every `step` m along each edge (exports split straight walls)."""
    out = []
    n = len(pts)
    for i in range(n):
        ax, ay = pts[i]
        bx, by = pts[(i + 1) % n]
        L = math.hypot(bx - ax, by - ay)
        k = int(L / step)
        out.append((ax, ay))
        for j in range(1, k):
            if L - j * step > 0.5 * step:
                out.append((ax + (bx - ax) * j * step / L, ay + (by - ay) * j * step / L))
    return out


def make_imdf_messy():
    # office: a 30 x 20 m level, a walkway corridor y in [8.5, 11.5], six rooms of 5 m on each side.
    # Every room corner is chamfered by 1.5 cm, straight edges are split every 0.8 m and the long
    # sides have a 1-cm jog of 4 mm: about a fifth of the edges are shorter than 3 cm.
    L = "office-level-0"
    units = [unit("corridor", L, "walkway", chamfered(rect(0, 8.5, 30, 11.5), 0.015))]
    for k in range(6):
        x0, x1 = 5.0 * k, 5.0 * (k + 1)
        units.append(unit("south-%d" % k, L, "office", split(jogged(chamfered(rect(x0, 0, x1, 8.5), 0.015), 6.0, 0.004), 0.8)))
        units.append(unit("north-%d" % k, L, "office", split(jogged(chamfered(rect(x0, 11.5, x1, 20), 0.015), 6.0, 0.004), 0.8)))
    openings = [opening("door-s%d" % k, L, (5.0 * k + 2.0, 8.5), (5.0 * k + 2.9, 8.5)) for k in range(6)]
    openings += [opening("door-n%d" % k, L, (5.0 * k + 2.0, 11.5), (5.0 * k + 2.9, 11.5)) for k in range(6)]
    write("imdf/short_edges/level.geojson", collection([level(L, 0, "Office", rect(0, 0, 30, 20), "office")]))
    write("imdf/short_edges/unit.geojson", collection(units))
    write("imdf/short_edges/opening.geojson", collection(openings))

    # two buildings sharing ordinal 1 (building.geojson names them), openings as real exports
    # write them: one as a MultiLineString of two touching pieces, one 12 cm off its wall's axis,
    # one overrunning the end of its wall by 0.3 m.
    def building(fid, name):
        return feature(fid, "building", None, {"name": {"en": name, "de": name + " (de)"}, "alt_name": None,
                                               "category": "unspecified", "restriction": None,
                                               "display_point": None, "address_id": None})
    main0, main1, annex1, annex2 = "main-0", "main-1", "annex-1", "annex-2"
    levels = [level(main0, 0, "Main Ground", rect(0, 0, 12, 6), "bld-main"),
              level(main1, 1, "Main First", rect(0, 0, 12, 6), "bld-main"),
              level(annex1, 1, "Annex Ground", rect(30, 0, 40, 6), "bld-annex"),
              level(annex2, 2, "Annex First", rect(30, 0, 40, 6), "bld-annex")]
    units = [unit("m0-all", main0, "room", rect(0, 0, 12, 6)),
             unit("m1-west", main1, "classroom", rect(0, 0, 6, 6)),
             unit("m1-east", main1, "classroom", rect(6, 0, 12, 6)),
             unit("a1-hall", annex1, "walkway", rect(30, 0, 40, 3)),
             unit("a1-room", annex1, "office", rect(30, 3, 40, 6)),
             unit("a2-all", annex2, "room", rect(30, 0, 40, 6))]
    multi = feature("m1-double", "opening",
                    {"type": "MultiLineString", "coordinates": [[lonlat(6, 1), lonlat(6, 1.5)], [lonlat(6, 1.5), lonlat(6, 2)]]},
                    {"category": "pedestrian", "door": None, "name": None, "alt_name": None, "display_point": None,
                     "accessibility": None, "access_control": None, "level_id": main1})
    openings = [multi,
                opening("m1-off-axis", main1, (6.12, 4.0), (6.12, 4.9)),
                opening("a1-overrun", annex1, (39.5, 3.0), (40.3, 3.0))]
    write("imdf/two_buildings/building.geojson", collection([building("bld-main", "Main"), building("bld-annex", "Annex")]))
    write("imdf/two_buildings/level.geojson", collection(levels))
    write("imdf/two_buildings/unit.geojson", collection(units))
    write("imdf/two_buildings/opening.geojson", collection(openings))


def make_osm_messy():
    """Level 0: rooms R1 [0,4]x[0,4] (room=office) and R2 [4,8]x[0,4] (stairs=yes) south of a
    corridor [0,8]x[4,6]; the level outline [0,8]x[0,6]; a door node on the exterior corner (8,0)
    (a wall end: the door must slide inside a wall), a door on the R1/corridor wall; two column
    nodes in the corridor; a glass indoor=wall inside R1; an indoor=room way that does not close."""
    o = Osm()
    n = o.node
    c00, c40, c80 = n(0, 0), n(4, 0), n(8, 0, door="hinged", level="0")
    c04, c24, c44, c84 = n(0, 4), n(2, 4, door="hinged"), n(4, 4), n(8, 4)
    c06, c86 = n(0, 6), n(8, 6)
    o.closed([c00, c40, c44, c24, c04], indoor="room", level="0", room="office", name="R1")
    o.closed([c40, c80, c84, c44], indoor="room", level="0", stairs="yes", name="R2")
    o.closed([c04, c24, c44, c84, c86, c06], indoor="corridor", level="0", name="C")
    o.closed([n(0, 0), n(8, 0), n(8, 6), n(0, 6)], indoor="level", level="0")
    n(2.0, 5.0, indoor="column", level="0")
    n(6.0, 5.0, indoor="column", level="0", width="0.3")
    o.way([n(1, 1), n(1, 3)], indoor="wall", level="0", material="glass")
    o.way([n(10, 0), n(12, 0), n(12, 2), n(10, 2)], indoor="room", level="0", name="broken")
    write("osm/messy.osm", o.xml())


def make_geojson():
    """OSM-derived GeoJSON as indoor map viewers export it: levels "0~0", "1~1", a stair shaft on
    "0~1"; level 0 has a level outline [0,10]x[0,6] with two rooms along its south side and no
    corridor (the rest is circulation), doors as Points (one on a wall end), an indoor=wall line,
    one feature in the older osmtogeojson layout (tags under properties.tags, id "way/77")."""
    def f(fid, geom, props):
        return {"type": "Feature", "id": fid, "geometry": geom, "properties": props}
    def poly(pts):
        ring = [lonlat(x, y) for x, y in pts]
        return {"type": "Polygon", "coordinates": [ring + [ring[0]]]}
    def point(x, y):
        return {"type": "Point", "coordinates": lonlat(x, y)}
    feats = [
        f(11, poly(rect(0, 0, 10, 6)), {"indoor": "level", "level": "0~0"}),
        f(12, poly(rect(0, 0, 4, 3)), {"indoor": "room", "level": "0~0", "room": "study", "ref": "0.01"}),
        f(13, poly(rect(4, 0, 8, 3)), {"indoor": "room", "level": "0~0", "room": "toilets"}),
        f(14, poly(rect(8, 0, 10, 3)), {"indoor": "room", "level": "0~1", "stairs": "yes"}),
        f(21, point(2, 3), {"door": "hinged", "indoor": "door", "level": "0~0", "width": "1.0"}),
        f(22, point(8, 3), {"door": "hinged", "level": "0~0"}),
        f(23, {"type": "LineString", "coordinates": [lonlat(6, 4.5), lonlat(6, 6)]}, {"indoor": "wall", "level": "0~0"}),
        f("way/77", poly(rect(0, 0, 10, 6)), {"tags": {"indoor": "level", "level": "1~1"}, "id": "way/77"}),
        f(31, poly(rect(0, 3, 8, 6)), {"indoor": "room", "level": "1~1", "room": "class"}),
        f(32, point(4, 3), {"door": "yes", "level": 1}),
        f(40, point(5, 5), {"highway": "elevator", "level": "0~1"}),
    ]
    write("geojson/studihaus.geojson", json.dumps({"type": "FeatureCollection", "features": feats}, indent=1) + "\n")


def make_png_exterior():
    """Occupancy at 0.1 m/px, 200 x 160 px (20 m x 16 m), everything occupied except the building's
    free interior (columns 60..139, rows 50..109: 8 m x 6 m, rooms split by a 2-px wall at columns
    99..100 with a 10-px door gap at rows 70..79) - the F3Loc layout where the exterior is occupied."""
    w, h = 200, 160
    img = [[0] * w for _ in range(h)]
    for r in range(50, 110):
        for c in range(60, 140):
            img[r][c] = 255
    for r in range(50, 110):
        if not (70 <= r < 80):
            img[r][99] = 0
            img[r][100] = 0
    write_png("png/occupied_exterior.png", img)


def make_csv_units():
    """The two-room plan of csv/two_rooms_messy.csv in millimetres and in feet (door gaps 0.9 m)."""
    segs = [(0, 0, 3, 0), (3.9, 0, 10, 0), (10, 0, 10, 8), (10, 8, 0, 8), (0, 8, 0, 0),
            (5, 0, 5, 3), (5, 3.9, 5, 8), (0, 4, 2, 4), (2.9, 4, 5, 4), (5, 4, 7, 4), (7.9, 4, 10, 4)]
    write("csv/millimetres.csv", "# x1,y1,x2,y2 in millimetres\n" +
          "".join("%g,%g,%g,%g\n" % tuple(1000 * v for v in s) for s in segs))
    write("csv/feet.csv", "# x1,y1,x2,y2 in feet\n" +
          "".join("%.4f,%.4f,%.4f,%.4f\n" % tuple(v / 0.3048 for v in s) for s in segs))


if __name__ == "__main__":
    make_s3d()
    make_imdf()
    make_osm()
    make_png()
    make_imdf_messy()
    make_osm_messy()
    make_geojson()
    make_png_exterior()
    make_csv_units()
