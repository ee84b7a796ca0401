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

    def at(self, x, y, **tags):
        """The node at (x, y), shared by every way that passes there (tagged nodes are never shared)."""
        if tags:
            return self.node(x, y, **tags)
        cache = self.__dict__.setdefault("_at", {})
        if (x, y) not in cache:
            cache[(x, y)] = self.node(x, y)
        return cache[(x, y)]

    def relation(self, members, **tags):
        """members: (type, ref, role) triples."""
        rels = self.__dict__.setdefault("relations", [])
        rid = 5000 + len(rels)
        rels.append((rid, members, tags))
        return rid

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
        for rid, members, tags in self.__dict__.get("relations", []):
            out.append('  <relation id="%d">\n' % rid)
            out.extend('    <member type="%s" ref="%d" role="%s"/>\n' % m for m in members)
            out.append(tag_xml(tags))
            out.append("  </relation>\n")
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


# ---- Imports that must say what the source says (issue 23) ------------------------------------
def box(o, x0, y0, x1, y1, doors=(), **tags):
    """A closed rectangular way through shared corner nodes; `doors` are (x, y) door nodes on its
    outline, inserted on the edge they lie on."""
    corners = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
    refs = []
    for k, (ax, ay) in enumerate(corners):
        bx, by = corners[(k + 1) % 4]
        refs.append(o.at(ax, ay))
        on_edge = [(dx, dy) for dx, dy in doors
                   if abs((bx - ax) * (dy - ay) - (by - ay) * (dx - ax)) < 1e-9
                   and min(ax, bx) <= dx <= max(ax, bx) and min(ay, by) <= dy <= max(ay, by)]
        on_edge.sort(key=lambda d: (d[0] - ax) ** 2 + (d[1] - ay) ** 2)
        refs.extend(o.node(dx, dy, door="hinged") for dx, dy in on_edge)
    return o.closed(refs, **tags)


def make_osm_corridors_open():
    """A ground floor whose circulation is mapped but not walled toward the outside: a foyer
    (indoor=area [0,4]x[0,13], the entrance door on its west side) opens onto a corridor split in
    two pieces ([4,12]x[5,8] and [12,20]x[5,8]); rooms R1-R4 south of it ([4,20]x[0,5], 4 m
    wide), R5 [4,12]x[8,13] and R6 [12,16]x[8,13] north of it; nothing is mapped north of the
    corridor at x 16-20 or around the building. Mapped: rooms 140, corridor 48, foyer 52 = 240 m^2.
    Before issue 23 the foyer's outline drew no wall, the outside flooded in through it and the
    whole corridor network lay outside the free space."""
    o = Osm()
    for k, x in enumerate([4, 8, 12, 16]):
        box(o, x, 0, x + 4, 5, doors=[(x + 2, 5)], indoor="room", level="0", name="R%d" % (k + 1))
    box(o, 4, 5, 12, 8, indoor="corridor", level="0", name="C1")
    box(o, 12, 5, 20, 8, indoor="corridor", level="0", name="C2")
    box(o, 4, 8, 12, 13, doors=[(8, 8)], indoor="room", level="0", name="R5")
    box(o, 12, 8, 16, 13, doors=[(14, 8)], indoor="room", level="0", name="R6")
    box(o, 0, 0, 4, 13, doors=[(0, 6.5)], indoor="area", level="0", name="foyer")
    write("osm/corridors_open.osm", o.xml())


COURTYARD_ROOMS = [  # (x0, y0, x1, y1, door)
    (4, 0, 12, 4, (8, 4)), (12, 0, 20, 4, (16, 4)), (4, 14, 12, 18, (8, 14)), (12, 14, 20, 18, (16, 14)),
    (0, 0, 4, 9, (4, 5)), (0, 9, 4, 18, (4, 13)), (20, 0, 24, 9, (20, 5)), (20, 9, 24, 18, (20, 13))]
COURTYARD_CORRIDORS = [(4, 4, 20, 6), (4, 12, 20, 14), (4, 6, 6, 12), (18, 6, 20, 12)]


def make_osm_courtyard():
    """A 24 x 18 m block: a corridor ring (four pieces, 2 m wide, 88 m^2) around an unmapped
    courtyard [6,18]x[6,12] (72 m^2), eight rooms around the ring (272 m^2) with a door each.
    The courtyard is enclosed by the corridor's walls, but no space covers it: not floor."""
    o = Osm()
    for k, (x0, y0, x1, y1, door) in enumerate(COURTYARD_ROOMS):
        box(o, x0, y0, x1, y1, doors=[door], indoor="room", level="0", name="R%d" % (k + 1))
    for k, (x0, y0, x1, y1) in enumerate(COURTYARD_CORRIDORS):
        box(o, x0, y0, x1, y1, indoor="corridor", level="0", name="C%d" % (k + 1))
    write("osm/courtyard.osm", o.xml())


def make_imdf_courtyard():
    """The courtyard block of osm/courtyard.osm as IMDF units (walkways, offices) and openings."""
    L = "lvl-0"
    units = [unit("room-%d" % (k + 1), L, "office", rect(x0, y0, x1, y1))
             for k, (x0, y0, x1, y1, _) in enumerate(COURTYARD_ROOMS)]
    units += [unit("walk-%d" % (k + 1), L, "walkway", rect(*c)) for k, c in enumerate(COURTYARD_CORRIDORS)]
    openings = []
    for k, (x0, y0, x1, y1, (dx, dy)) in enumerate(COURTYARD_ROOMS):
        horizontal = dy in (y0, y1)
        a, b = ((dx - 0.45, dy), (dx + 0.45, dy)) if horizontal else ((dx, dy - 0.45), (dx, dy + 0.45))
        openings.append(opening("door-%d" % (k + 1), L, a, b))
    write("imdf/courtyard/level.geojson", collection([level(L, 0, "Ground", rect(0, 0, 24, 18), "b1")]))
    write("imdf/courtyard/unit.geojson", collection(units))
    write("imdf/courtyard/opening.geojson", collection(openings))
    # The same block one floor up: the courtyard is an atrium, mapped as a unit of category
    # opentobelow (a hole in the floor); the openings file is empty (every room sealed in the data).
    units.append(unit("atrium-void", L, "opentobelow", rect(6, 6, 18, 12)))
    write("imdf/atrium_no_openings/level.geojson", collection([level(L, 1, "First", rect(0, 0, 24, 18), "b1")]))
    write("imdf/atrium_no_openings/unit.geojson", collection(units))
    write("imdf/atrium_no_openings/opening.geojson", collection([]))


def make_osm_pillars():
    """Level 0: a room [0,10]x[0,8] and a corridor [0,8]x[8,10] (the level with spaces); level 1:
    six column outlines (indoor=column, 0.5 m squares) and nothing else: no space, no floor."""
    o = Osm()
    box(o, 0, 0, 10, 8, doors=[(5, 8)], indoor="room", level="0", name="hall room")
    box(o, 0, 8, 10, 10, indoor="corridor", level="0", name="C")
    for k in range(6):
        x, y = 1 + 4 * (k % 3), 2 + 4 * (k // 3)
        o.closed([o.node(x, y), o.node(x + 0.5, y), o.node(x + 0.5, y + 0.5), o.node(x, y + 0.5)],
                 indoor="column", level="1")
    write("osm/pillars.osm", o.xml())


def make_osm_concourse():
    """A station concourse [0,40]x[0,20] mapped as one indoor=corridor with wall=no (an open hall),
    a multipolygon relation whose outer ring is drawn as two ways, with four shops (indoor=room,
    shop=*, 10 x 8 m, no door nodes: sealed in the data) standing inside it, and an exit passage
    (indoor=corridor) [40,8]x[46,12] off its east side. Mapped: 800 + 24 m^2 (the shops lie inside
    the concourse). Before issue 23 the concourse drew no wall and lay outside: the level imported
    as four sealed shops."""
    o = Osm()
    a, b, c, d = o.at(0, 0), o.at(40, 0), o.at(40, 20), o.at(0, 20)
    e1, e2 = o.at(40, 8), o.at(40, 12)
    w1 = o.way([a, b, e1, e2, c])
    w2 = o.way([c, d, a])
    o.relation([("way", w1, "outer"), ("way", w2, "outer")], type="multipolygon", indoor="corridor", wall="no",
               level="0", name="concourse")
    box(o, 40, 8, 46, 12, indoor="corridor", level="0", name="exit passage")
    for k, (x, y) in enumerate([(4, 2), (26, 2), (4, 10), (26, 10)]):
        box(o, x, y, x + 10, y + 8, indoor="room", shop="kiosk", level="0", name="shop %d" % (k + 1))
    write("osm/concourse.osm", o.xml())


# ---- Coordinate systems and schemas (issue 23 item 4) -------------------------------------------
def utm32n(lon, lat):
    """WGS84 longitude/latitude -> UTM zone 32N (EPSG:32632) easting/northing: the transverse
    Mercator projection by Krueger's series to sixth order in n (Karney 2011, eqs. 9-12; exact to
    well below a millimetre in the zone)."""
    a, f, k0, lon0 = A, F, 0.9996, 9.0
    n = f / (2.0 - f)
    big_a = a / (1.0 + n) * (1.0 + n ** 2 / 4.0 + n ** 4 / 64.0 + n ** 6 / 256.0)
    alpha = [
        n / 2 - 2 * n ** 2 / 3 + 5 * n ** 3 / 16 + 41 * n ** 4 / 180 - 127 * n ** 5 / 288 + 7891 * n ** 6 / 37800,
        13 * n ** 2 / 48 - 3 * n ** 3 / 5 + 557 * n ** 4 / 1440 + 281 * n ** 5 / 630 - 1983433 * n ** 6 / 1935360,
        61 * n ** 3 / 240 - 103 * n ** 4 / 140 + 15061 * n ** 5 / 26880 + 167603 * n ** 6 / 181440,
        49561 * n ** 4 / 161280 - 179 * n ** 5 / 168 + 6601661 * n ** 6 / 7257600,
        34729 * n ** 5 / 80640 - 3418889 * n ** 6 / 1995840,
        212378941 * n ** 6 / 319334400,
    ]
    e = 2.0 * math.sqrt(n) / (1.0 + n)
    phi, lam = math.radians(lat), math.radians(lon - lon0)
    t = math.sinh(math.atanh(math.sin(phi)) - e * math.atanh(e * math.sin(phi)))
    xi1 = math.atan2(t, math.cos(lam))
    eta1 = math.atanh(math.sin(lam) / math.sqrt(1.0 + t * t))
    xi = xi1 + sum(al * math.sin(2 * j * xi1) * math.cosh(2 * j * eta1) for j, al in enumerate(alpha, 1))
    eta = eta1 + sum(al * math.cos(2 * j * xi1) * math.sinh(2 * j * eta1) for j, al in enumerate(alpha, 1))
    return [round(500000.0 + k0 * big_a * eta, 4), round(k0 * big_a * xi, 4)]


# One small office, level 0: (kind, rectangle, door points on its outline, extra tags).
TWIN_OFFICE = [
    ("room", (0, 0, 5, 4), [(2.5, 4)], {"name": "R1"}),
    ("room", (5, 0, 10, 4), [(7.5, 4)], {"name": "R2"}),
    ("room", (10, 0, 15, 4), [(12.5, 4)], {"name": "R3"}),
    ("corridor", (0, 4, 15, 6.5), [(0, 5.25)], {"name": "C"}),
    ("room", (0, 6.5, 7, 11), [(3.5, 6.5)], {"name": "R4"}),
    ("room", (7, 6.5, 10, 11), [(8.5, 6.5)], {"name": "stairs", "stairs": "yes"}),
    ("room", (10, 6.5, 15, 11), [(12.5, 6.5)], {"name": "R5"}),
]


def make_geojson_crs_twins():
    """The office of TWIN_OFFICE as OSM-derived GeoJSON twice: in WGS84 longitude/latitude
    (office_wgs84.geojson) and in UTM zone 32N metres with a crs member naming EPSG:32632
    (office_utm32n.geojson). Both must import to the same plan."""
    def f(fid, geom, props):
        return {"type": "Feature", "id": fid, "geometry": geom, "properties": props}
    def build(pos):
        feats = []
        for k, (kind, (x0, y0, x1, y1), doors, extra) in enumerate(TWIN_OFFICE):
            ring = [pos(x, y) for x, y in rect(x0, y0, x1, y1)]
            props = {"indoor": kind, "level": "0"}
            props.update(extra)
            feats.append(f("way/%d" % (100 + k), {"type": "Polygon", "coordinates": [ring + [ring[0]]]}, props))
            for j, (dx, dy) in enumerate(doors):
                feats.append(f("node/%d" % (1000 + 10 * k + j), {"type": "Point", "coordinates": pos(dx, dy)},
                               {"door": "hinged", "level": "0"}))
        feats.append(f("way/200", {"type": "LineString", "coordinates": [pos(2, 8), pos(5, 8)]},
                       {"indoor": "wall", "level": "0"}))
        return feats
    write("geojson/office_wgs84.geojson",
          json.dumps({"type": "FeatureCollection", "features": build(lonlat)}, indent=1) + "\n")
    utm = lambda x, y: utm32n(*lonlat(x, y))
    write("geojson/office_utm32n.geojson",
          json.dumps({"type": "FeatureCollection", "crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::32632"}},
                      "features": build(utm)}, indent=1) + "\n")


# A two-level building for the IndoorOSM twin: (IndoorOSM buildingpart, SIT tags, rectangle,
# doors, levels). Level 1 has a hall where level 0 has room R4; the stairs pass both levels.
TWIN_LEVELS = [
    ("room", {"indoor": "room"}, (0, 0, 5, 4), [(2.5, 4)], [0, 1]),
    ("room", {"indoor": "room"}, (5, 0, 10, 4), [(7.5, 4)], [0, 1]),
    ("room", {"indoor": "room"}, (10, 0, 15, 4), [(12.5, 4)], [0, 1]),
    ("corridor", {"indoor": "corridor"}, (0, 4, 15, 6.5), [], [0, 1]),
    ("room", {"indoor": "room"}, (0, 6.5, 7, 11), [(3.5, 6.5)], [0]),
    ("hall", {"indoor": "area"}, (0, 6.5, 7, 11), [], [1]),
    ("verticalpassage", {"indoor": "room", "stairs": "yes"}, (7, 6.5, 10, 11), [(8.5, 6.5)], [0, 1]),
    ("room", {"indoor": "room"}, (10, 6.5, 15, 11), [(12.5, 6.5)], [0, 1]),
]


def make_osm_indoorosm_twins():
    """The building of TWIN_LEVELS in the IndoorOSM schema (indoorosm.osm: ways tagged
    buildingpart=room|corridor|hall|verticalpassage, grouped by level relations type=level with a
    shell way each, under a building relation type=building with roles level_0, level_1; doors as
    door=yes nodes) and in Simple Indoor Tagging (indoorosm_sit_twin.osm: indoor=room|corridor|area,
    stairs=yes, level=*, indoor=level outlines). Both must import to the same plans."""
    # IndoorOSM: one set of ways; each level relation lists the ways on its level.
    o = Osm()
    members = {0: [], 1: []}
    for part, _sit, (x0, y0, x1, y1), doors, levels in TWIN_LEVELS:
        tags = {"buildingpart": part}
        if part == "verticalpassage":
            tags["buildingpart_colon_verticalpassage"] = "stairway"
        wid = box(o, x0, y0, x1, y1, doors=doors, **tags)
        for lv in levels:
            members[lv].append(("way", wid, "buildingpart"))
    level_rels = {}
    for lv in (0, 1):
        shell = box(o, 0, 0, 15, 11)
        level_rels[lv] = o.relation(members[lv] + [("way", shell, "shell")], type="level", level=str(lv),
                                    name="Level %d" % lv, height="3.5")
    o.relation([("relation", level_rels[lv], "level_%d" % lv) for lv in (0, 1)], type="building", building="university",
               building_colon_min_level="0", building_colon_max_level="1", name="Twin building")
    write("osm/indoorosm.osm", o.xml())
    # The same in Simple Indoor Tagging.
    o = Osm()
    for _part, sit, (x0, y0, x1, y1), doors, levels in TWIN_LEVELS:
        box(o, x0, y0, x1, y1, doors=doors, level=";".join(str(v) for v in levels), **sit)
    box(o, 0, 0, 15, 11, indoor="level", level="0;1")
    write("osm/indoorosm_sit_twin.osm", o.xml())


def make_geojson_wall_polygons():
    """Walls drawn as polygons with their thickness and doors/windows as lines, the way CAD and
    indoor-map exports write them (no OSM tags; the element class under category/layer/type/class):
    rooms A [0,6]x[0,5] and B [6,10]x[0,5]; the outer walls are four 0.30 m rectangles centred on
    the outline (south and north run 10.3 m, west and east 4.7 m between them); the partition at
    x = 6 is one T-shaped 0.15 m polygon with a 1.425 m return along y = 2.5 into B; a 0.9 m door
    line in the south wall of A, a 0.9 m door line in the partition, a 1.5 m window line in the north
    wall of B."""
    def f(fid, geom, props):
        return {"type": "Feature", "id": fid, "geometry": geom, "properties": props}
    def poly(pts):
        ring = [lonlat(x, y) for x, y in pts]
        return {"type": "Polygon", "coordinates": [ring + [ring[0]]]}
    def line(a, b):
        return {"type": "LineString", "coordinates": [lonlat(*a), lonlat(*b)]}
    t = 0.15
    feats = [
        f("south", poly(rect(-t, -t, 10 + t, t)), {"category": "Wall"}),
        f("north", poly(rect(-t, 5 - t, 10 + t, 5 + t)), {"category": "wall"}),
        f("west", poly(rect(-t, t, t, 5 - t)), {"layer": "Walls"}),
        f("east", poly(rect(10 - t, t, 10 + t, 5 - t)), {"layer": "Walls"}),
        f("partition", poly([(5.925, t), (6.075, t), (6.075, 2.425), (7.5, 2.425), (7.5, 2.575), (6.075, 2.575),
                             (6.075, 5 - t), (5.925, 5 - t)]), {"type": "wall"}),
        f("door-a", line((2, 0), (2.9, 0)), {"type": "door"}),
        f("door-ab", line((6, 3.5), (6, 4.4)), {"category": "Door"}),
        f("window-b", line((7.5, 5), (9, 5)), {"class": "window"}),
    ]
    write("geojson/wall_polygons.geojson", json.dumps({"type": "FeatureCollection", "features": feats}, indent=1) + "\n")


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
    make_osm_corridors_open()
    make_osm_courtyard()
    make_imdf_courtyard()
    make_osm_pillars()
    make_osm_concourse()
    make_geojson_crs_twins()
    make_osm_indoorosm_twins()
    make_geojson_wall_polygons()
