#!/usr/bin/env python3
"""Writes the small hand-made inputs of the adversarial corpus into data/ (run once; the output
is committed). Large inputs (deep nesting, huge counts) are generated at test time by runner.cpp.
Usage: python3 tests/adversarial/make_data.py"""
import json
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "data")


def put(rel, content):
    path = os.path.join(DATA, rel)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    mode = "wb" if isinstance(content, bytes) else "w"
    with open(path, mode) as f:
        f.write(content)


BOX = [
    {"id": "s", "a": [0, 0], "b": [8, 0], "thickness_m": 0.2},
    {"id": "e", "a": [8, 0], "b": [8, 5], "thickness_m": 0.2},
    {"id": "n", "a": [8, 5], "b": [0, 5], "thickness_m": 0.2},
    {"id": "w", "a": [0, 5], "b": [0, 0], "thickness_m": 0.2},
]


def plan(**over):
    p = {"format_version": 1, "name": "box", "walls": [dict(w) for w in BOX]}
    p.update(over)
    return json.dumps(p)


def wall(**over):
    w = dict(BOX[0])
    w.update(over)
    return plan(walls=[w] + [dict(x) for x in BOX[1:]])


# ---- plan JSON ------------------------------------------------------------------------------
P = "plan/"
put(P + "valid.json", plan())
put(P + "empty.json", "")
put(P + "whitespace.json", " \n\t \n")
put(P + "null.json", "null")
put(P + "array.json", "[]")
put(P + "string.json", '"plan"')
put(P + "number.json", "1")
put(P + "truncated.json", plan()[:-7])
put(P + "trailing_garbage.json", plan() + " }")
put(P + "two_documents.json", plan() + "\n" + plan())
put(P + "bom.json", b"\xef\xbb\xbf" + plan().encode())
put(P + "comment.json", "// a plan\n" + plan())
put(P + "nan_literal.json", plan().replace('"thickness_m": 0.2', '"thickness_m": NaN', 1))
put(P + "infinity_literal.json", plan().replace('"thickness_m": 0.2', '"thickness_m": Infinity', 1))
put(P + "number_1e999.json", plan().replace('[8, 0]', '[1e999, 0]', 1))
put(P + "number_neg_1e999.json", plan().replace('[8, 0]', '[-1e999, 0]', 1))
put(P + "number_1e400_thickness.json", plan().replace('"thickness_m": 0.2', '"thickness_m": 1e400', 1))
put(P + "int_huge.json", plan(format_version=10**30))
put(P + "int_negative_huge.json", plan(format_version=-(10**30)))
put(P + "version_float.json", plan(format_version=1.5))
put(P + "version_string.json", plan(format_version="1"))
put(P + "version_2.json", plan(format_version=2))
put(P + "version_missing.json", json.dumps({"walls": BOX}))
put(P + "walls_missing.json", json.dumps({"format_version": 1}))
put(P + "walls_empty.json", plan(walls=[]))
put(P + "walls_object.json", plan(walls={"a": 1}))
put(P + "walls_null.json", plan(walls=None))
put(P + "wall_not_object.json", plan(walls=[1, 2]))
put(P + "wall_no_id.json", plan(walls=[{"a": [0, 0], "b": [1, 0]}]))
put(P + "wall_id_number.json", wall(id=7))
put(P + "wall_id_empty.json", wall(id=""))
put(P + "wall_duplicate_id.json", plan(walls=BOX + [dict(BOX[0])]))
put(P + "wall_unknown_key.json", wall(colour="red"))
put(P + "wall_point_short.json", wall(a=[0]))
put(P + "wall_point_long.json", wall(a=[0, 0, 0]))
put(P + "wall_point_string.json", wall(a=["0", "0"]))
put(P + "wall_point_null.json", wall(a=None))
put(P + "wall_point_object.json", wall(a={"x": 0, "y": 0}))
put(P + "wall_zero_length.json", wall(b=[0, 0]))
put(P + "wall_tiny.json", wall(b=[1e-9, 0]))
put(P + "wall_far.json", wall(a=[1e9, 0]))
put(P + "wall_too_long.json", wall(b=[20000, 0]))
put(P + "wall_thickness_zero.json", wall(thickness_m=0))
put(P + "wall_thickness_negative.json", wall(thickness_m=-0.2))
put(P + "wall_thickness_huge.json", wall(thickness_m=50))
put(P + "wall_thickness_string.json", wall(thickness_m="0.2"))
put(P + "wall_material_bad.json", wall(material="wood"))
put(P + "wall_material_number.json", wall(material=1))
put(P + "wall_glass_fields_solid.json", wall(glass_sill_m=0.5))
put(P + "wall_glass_head_below_sill.json", wall(material="glass", glass_sill_m=1.0, glass_head_m=0.5))
put(P + "wall_glass_sill_negative.json", wall(material="glass", glass_sill_m=-1.0))
put(P + "wall_glass_head_huge.json", wall(material="glass", glass_head_m=1e6))
put(P + "name_invalid_utf8.json", plan().replace('"box"', '"b\\u00e9x"').encode().replace(b"\\u00e9", b"\xff\xfe"))
put(P + "id_invalid_utf8.json", plan().encode().replace(b'"id": "s"', b'"id": "s\xc3"'))
put(P + "id_overlong_utf8.json", plan().encode().replace(b'"id": "s"', b'"id": "\xc0\xaf"'))
put(P + "id_surrogate_utf8.json", plan().encode().replace(b'"id": "s"', b'"id": "\xed\xa0\x80"'))
put(P + "name_lone_surrogate_escape.json", plan(name="x").replace('"x"', '"\\ud800"'))
put(P + "name_control_chars.json", plan(name="a\u0000b\u0007c"))
put(P + "name_number.json", plan(name=5))
put(P + "level_huge.json", plan(level=10**12))
put(P + "level_float.json", plan(level=0.5))
put(P + "unknown_top_key.json", plan(roomz=[]))
put(P + "binary_garbage.bin", bytes(range(256)) * 4)
put(P + "nul_bytes.json", b"\x00" * 1000)
put(P + "utf16.json", plan().encode("utf-16"))

DOOR = {"id": "d", "wall": "s", "center": [4, 0], "width_m": 1.0}


def doors(*ds):
    return plan(doors=list(ds))


put(P + "door_unknown_wall.json", doors(dict(DOOR, wall="nope")))
put(P + "door_off_wall.json", doors(dict(DOOR, center=[4, 2])))
put(P + "door_beyond_wall_end.json", doors(dict(DOOR, center=[7.9, 0])))
put(P + "door_width_zero.json", doors(dict(DOOR, width_m=0)))
put(P + "door_width_negative.json", doors(dict(DOOR, width_m=-1)))
put(P + "door_width_huge.json", doors(dict(DOOR, width_m=1e6)))
put(P + "door_overlap.json", doors(DOOR, dict(DOOR, id="d2", center=[4.5, 0])))
put(P + "door_closed_string.json", doors(dict(DOOR, closed="yes")))
put(P + "door_same_id_as_wall.json", doors(dict(DOOR, id="s")))
put(P + "doors_not_array.json", plan(doors={"d": DOOR}))
WIN = {"id": "win", "wall": "n", "center": [4, 5], "width_m": 1.0, "sill_m": 0.9, "head_m": 2.1}
put(P + "window_head_below_sill.json", plan(windows=[dict(WIN, sill_m=2.0, head_m=1.0)]))
put(P + "window_in_glass_wall.json",
    plan(walls=[dict(BOX[0]), dict(BOX[1]), dict(BOX[2], material="glass"), dict(BOX[3])], windows=[WIN]))
put(P + "window_sill_negative.json", plan(windows=[dict(WIN, sill_m=-1)]))
put(P + "window_head_huge.json", plan(windows=[dict(WIN, head_m=1e9)]))
OB = {"id": "o", "kind": "box", "center": [2, 2], "size_m": [1, 1], "height_m": 1}
put(P + "obstacle_kind_bad.json", plan(obstacles=[dict(OB, kind="sphere")]))
put(P + "obstacle_size_negative.json", plan(obstacles=[dict(OB, size_m=[-1, 1])]))
put(P + "obstacle_size_zero.json", plan(obstacles=[dict(OB, size_m=[0, 0])]))
put(P + "obstacle_height_zero.json", plan(obstacles=[dict(OB, height_m=0)]))
put(P + "obstacle_far.json", plan(obstacles=[dict(OB, center=[9e4, 9e4])]))
put(P + "obstacle_yaw_string.json", plan(obstacles=[dict(OB, yaw_rad="north")]))
put(P + "obstacle_missing_height.json", plan(obstacles=[{k: v for k, v in OB.items() if k != "height_m"}]))
put(P + "extent_6km.json", plan(walls=[{"id": "a", "a": [0, 0], "b": [6000, 0]}, {"id": "b", "a": [0, 5], "b": [6000, 5]}]))
put(P + "extent_obstacle_far.json", plan(obstacles=[dict(OB, center=[4000, 4000])]))
put(P + "box_400m.json", plan(walls=[{"id": "s", "a": [0, 0], "b": [400, 0]}, {"id": "e", "a": [400, 0], "b": [400, 400]},
                                      {"id": "n", "a": [400, 400], "b": [0, 400]}, {"id": "w", "a": [0, 400], "b": [0, 0]}]))

# ---- observation JSON -------------------------------------------------------------------------
O = "obs/"


def obs(**over):
    o = {"format": "floorcast-observation", "format_version": 1, "frame": "observer", "max_range_m": 10,
         "segments_m": [[1, -1, 1, 1], [-1, 2, 2, 2]]}
    o.update(over)
    return json.dumps(o)


put(O + "valid.json", obs())
put(O + "rays_empty.json", obs(ray_ranges_m=[]))
put(O + "rays_7.json", obs(ray_ranges_m=[1.0] * 7))
put(O + "rays_3.json", obs(ray_ranges_m=[1.0] * 3))
put(O + "rays_negative.json", obs(ray_ranges_m=[-1.0] * 36))
put(O + "rays_beyond_range.json", obs(ray_ranges_m=[11.0] * 36))
put(O + "rays_string.json", obs(ray_ranges_m=["1"] * 36))
put(O + "rays_null.json", obs(ray_ranges_m=[None] * 36))
put(O + "rays_object.json", obs(ray_ranges_m={"a": 1}))
put(O + "rays_1e999.json", obs().replace('"segments_m"', '"ray_ranges_m": [1e999], "segments_m"'))
put(O + "no_segments_no_rays.json", obs(segments_m=[]))
put(O + "segments_missing.json", json.dumps({k: v for k, v in json.loads(obs()).items() if k != "segments_m"}))
put(O + "segment_short.json", obs(segments_m=[[1, 2, 3]]))
put(O + "segment_string.json", obs(segments_m=[["1", 2, 3, 4]]))
put(O + "segment_huge.json", obs(segments_m=[[1e9, 0, 1, 1]]))
put(O + "segment_not_array.json", obs(segments_m={"a": [1, 2, 3, 4]}))
put(O + "labels_mismatch.json", obs(segment_labels=["wall"]))
put(O + "labels_unknown.json", obs(segment_labels=["wall", "curtain"]))
put(O + "max_range_zero.json", obs(max_range_m=0))
put(O + "max_range_negative.json", obs(max_range_m=-10))
put(O + "max_range_huge.json", obs(max_range_m=1e12))
put(O + "max_range_string.json", obs(max_range_m="10"))
put(O + "format_wrong.json", obs(format="floorcast-scan"))
put(O + "format_version_99.json", obs(format_version=99))
put(O + "frame_world.json", obs(frame="world"))
put(O + "unknown_key.json", obs(colour="red"))
put(O + "ground_truth_huge.json", obs(ground_truth={"x_m": 1e9, "y_m": 0, "yaw_rad": 0}))
put(O + "ground_truth_extra.json", obs(ground_truth={"x_m": 1, "y_m": 0, "yaw_rad": 0, "z_m": 1}))
put(O + "metadata_number.json", obs(metadata={"a": 1}))
put(O + "metadata_invalid_utf8.json", obs(metadata={"a": "x"}).encode().replace(b'"x"', b'"\xfe"'))
put(O + "top_array.json", "[" + obs() + "]")
put(O + "truncated.json", obs()[:-3])

# ---- scan folders -----------------------------------------------------------------------------


def png(width, height, depth=16, rows=None):
    """A grayscale PNG (depth 8 or 16) filled with 1500 (16-bit) or 1 (8-bit)."""
    sig = b"\x89PNG\r\n\x1a\n"

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    px = struct.pack(">H", 1500) if depth == 16 else b"\x01"
    raw = b"".join(b"\x00" + px * width for _ in range(height))
    return sig + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, depth, 0, 0, 0, 0)) + \
        chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")


IDENT = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]
CAM = [[0, 0, 1, 0], [-1, 0, 0, 0], [0, -1, 0, 0], [0, 0, 0, 1]]


def view(**over):
    v = {"intrinsics": {"width_px": 8, "height_px": 6, "fx_px": 4, "fy_px": 4, "cx_px": 4, "cy_px": 3},
         "T_scan_camera": CAM, "depth": "d.png"}
    v.update(over)
    return v


def scan(name, views=None, extra_files=None, **over):
    s = {"format": "floorcast-scan", "format_version": 2, "sensor": "test", "views": views if views is not None else [view()]}
    s.update(over)
    put("scan/" + name + "/scan.json", json.dumps(s))
    put("scan/" + name + "/d.png", png(8, 6))
    for k, v in (extra_files or {}).items():
        put("scan/" + name + "/" + k, v)


scan("valid")
scan("views_empty", views=[])
scan("views_object", views={"a": view()})
scan("version_99", format_version=99)
scan("format_wrong", format="floorcast-walk")
scan("unknown_key", colour="red")
scan("depth_unit_zero", depth_unit_m=0)
scan("depth_unit_negative", depth_unit_m=-0.001)
scan("intrinsics_zero_size", views=[view(intrinsics={"width_px": 0, "height_px": 6, "fx_px": 4, "fy_px": 4, "cx_px": 4, "cy_px": 3})])
scan("intrinsics_huge_size", views=[view(intrinsics={"width_px": 100000, "height_px": 100000, "fx_px": 4, "fy_px": 4, "cx_px": 4, "cy_px": 3})])
scan("intrinsics_fx_zero", views=[view(intrinsics={"width_px": 8, "height_px": 6, "fx_px": 0, "fy_px": 4, "cx_px": 4, "cy_px": 3})])
scan("intrinsics_fx_negative", views=[view(intrinsics={"width_px": 8, "height_px": 6, "fx_px": -4, "fy_px": 4, "cx_px": 4, "cy_px": 3})])
scan("intrinsics_float_size", views=[view(intrinsics={"width_px": 8.5, "height_px": 6, "fx_px": 4, "fy_px": 4, "cx_px": 4, "cy_px": 3})])
scan("intrinsics_missing", views=[{"T_scan_camera": CAM, "depth": "d.png"}])
scan("pose_not_rigid", views=[view(T_scan_camera=[[2, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])])
scan("pose_shape", views=[view(T_scan_camera=[[1, 0, 0], [0, 1, 0], [0, 0, 1]])])
scan("pose_string", views=[view(T_scan_camera="identity")])
scan("pose_bottom_row", views=[view(T_scan_camera=[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [1, 1, 1, 1]])])
scan("pose_far", views=[view(T_scan_camera=[[1, 0, 0, 1e9], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])])
scan("depth_missing_file", views=[view(depth="nope.png")])
scan("depth_traversal", views=[view(depth="../valid/d.png")])
scan("depth_absolute", views=[view(depth="/etc/passwd")])
scan("depth_empty_name", views=[view(depth="")])
scan("depth_size_mismatch", views=[view(depth="big.png")], extra_files={"big.png": png(16, 12)})
scan("depth_8bit", views=[view(depth="d8.png")], extra_files={"d8.png": png(8, 6, depth=8)})
scan("depth_not_png", views=[view(depth="d.txt")], extra_files={"d.txt": "not an image"})
scan("depth_truncated_png", views=[view(depth="t.png")], extra_files={"t.png": png(8, 6)[:40]})
scan("depth_png_header_huge", views=[view(depth="h.png")], extra_files={"h.png": png(8, 6)[:16] + struct.pack(">II", 60000, 60000) + png(8, 6)[24:]})
scan("confidence_out_of_range", views=[view(confidence="c.png")], extra_files={"c.png": png(8, 6, depth=8).replace(b"", b"")})
scan("view_index_negative", views=[view(view_index=-1)])
scan("view_index_huge", views=[view(view_index=10**12)])
put("scan/no_scan_json/readme.txt", "not a scan")
put("scan/scan_json_is_dir/scan.json/x", "x")
put("scan/scan_json_invalid_utf8/scan.json", b'{"format": "floorcast-scan\xff", "format_version": 2, "views": []}')


# ---- scenario YAML ------------------------------------------------------------------------------
Y = "yaml/"
BASE = ("name: t\nbuildings: [floorplans/buildings/two_rooms.json]\nsampling: {count: 2, seed: 1}\n"
        "matchers: {k: {matcher: kernel}}\n")


def y(name, text):
    put(Y + name + ".yaml", text)


def yb(name, extra, base=BASE):
    y(name, base + extra)


y("tiny", BASE + "observation: {source: perfect}\noutput: {heatmaps: 0}\n")
y("sweep_zip_ok", BASE + "observation: {source: perfect}\nsweep: {observation.seed: [1, 2]}\n")
y("rooms_scenario", "buildings: [{file: floorplans/buildings/two_rooms.json, rooms: ../rooms/square.json}]\n"
  "sampling: {count: 2, seed: 1, region_kinds: [room]}\nmatchers: {k: {matcher: kernel}}\n")
put("rooms/square.json", json.dumps({"rooms": [{"kind": "room", "polygon": [[1, 1], [4, 1], [4, 4], [1, 4]]}]}))
y("tiny_other", BASE.replace("count: 2", "count: 3") + "observation: {source: perfect}\noutput: {heatmaps: 0}\n")
y("empty", "")
y("null_doc", "~\n")
y("scalar_doc", "hello\n")
y("list_doc", "- a\n- b\n")
y("two_docs", BASE + "---\n" + BASE)
# Fuzzing finding (results/fuzz.md): a line starting with a stray comma (a typo splitting a comment)
# made yaml-cpp's LoadAll append empty documents until memory ran out (18 GB in a release build).
y("stray_comma", "# a comment split by a typo: 10\n,m doors closed\n" + BASE)
y("only_comma", ",")
y("tab_indent", "name: t\nbuildings:\n\t- floorplans/buildings/two_rooms.json\n")
y("unclosed_flow", "buildings: [floorplans/buildings/two_rooms.json\nmatchers: {k: {matcher: kernel}}\n")
y("unclosed_quote", 'name: "t\nbuildings: [x]\n')
y("bad_indent", "name: t\n  buildings: [x]\n")
y("recursive_alias", "buildings: &a [*a]\nmatchers: {k: {matcher: kernel}}\n")
y("recursive_alias_map", "matchers: &m {k: *m}\nbuildings: [floorplans/buildings/two_rooms.json]\n")
y("undefined_alias", "buildings: *nope\nmatchers: {k: {matcher: kernel}}\n")
y("alias_reuse_ok", "common: &c {matcher: kernel}\n" + BASE)
y("invalid_utf8_value", BASE.replace("name: t", "name: t\xff").encode("latin-1").decode("latin-1"))
put(Y + "invalid_utf8_value.yaml", BASE.replace("name: t", "name: tX").encode().replace(b"tX", b"t\xff"))
put(Y + "invalid_utf8_key.yaml", (BASE + "kX: 1\n").encode().replace(b"kX", b"k\xc3"))
put(Y + "invalid_utf8_path.yaml", BASE.encode().replace(b"two_rooms.json", b"two_rooms\xfe.json"))
put(Y + "nul_byte.yaml", BASE.encode() + b"\x00\n")
yb("duplicate_key", "sampling: {count: 3}\n")
yb("duplicate_inner_key", "", base=BASE.replace("{count: 2, seed: 1}", "{count: 2, count: 3}"))
yb("complex_key", "? [a, b]\n: 1\n")
yb("unknown_top", "colour: red\n")
yb("unknown_sampling", "", base=BASE.replace("seed: 1}", "seed: 1, sead: 2}"))
y("no_buildings", "matchers: {k: {matcher: kernel}}\n")
y("buildings_empty", "buildings: []\nmatchers: {k: {matcher: kernel}}\n")
y("buildings_string", "buildings: floorplans/buildings/two_rooms.json\nmatchers: {k: {matcher: kernel}}\n")
y("building_missing_file", "buildings: [nope/missing.json]\nmatchers: {k: {matcher: kernel}}\n")
y("building_both", "buildings: [{file: floorplans/buildings/two_rooms.json, generate: office}]\nmatchers: {k: {matcher: kernel}}\n")
y("building_archetype_bad", "buildings: [{generate: castle}]\nmatchers: {k: {matcher: kernel}}\n")
y("building_seed_negative", "buildings: [{generate: office, seed: -1}]\nmatchers: {k: {matcher: kernel}}\n")
y("building_seed_huge", "buildings: [{generate: office, seed: 99999999999999999999}]\nmatchers: {k: {matcher: kernel}}\n")
y("building_seed_float", "buildings: [{generate: office, seed: 1.5}]\nmatchers: {k: {matcher: kernel}}\n")
y("building_label_bad", "buildings: [{file: floorplans/buildings/two_rooms.json, label: 'a b'}]\nmatchers: {k: {matcher: kernel}}\n")
y("building_label_dup", "buildings: [floorplans/buildings/two_rooms.json, floorplans/buildings/two_rooms.json]\nmatchers: {k: {matcher: kernel}}\n")
y("building_plan_deep", "buildings: [../gen_missing/plan_deep.json]\nmatchers: {k: {matcher: kernel}}\n")
y("building_dev_zero", "buildings: [/dev/zero]\nmatchers: {k: {matcher: kernel}}\n")
y("building_directory", "buildings: [floorplans/buildings]\nmatchers: {k: {matcher: kernel}}\n")
yb("count_zero", "", base=BASE.replace("count: 2", "count: 0"))
yb("count_negative", "", base=BASE.replace("count: 2", "count: -5"))
yb("count_float", "", base=BASE.replace("count: 2", "count: 2.5"))
yb("count_string", "", base=BASE.replace("count: 2", "count: many"))
yb("count_huge", "", base=BASE.replace("count: 2", "count: 1000000000000"))
yb("count_units_limit", "sweep: {observation.seed: [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12]}\n",
   base=BASE.replace("count: 2", "count: 1000000"))
yb("count_1e999", "", base=BASE.replace("count: 2", "count: 1e999"))
yb("clearance_1e999", "", base=BASE.replace("seed: 1}", "seed: 1, clearance_m: 1e999}"))
yb("clearance_neg_1e999", "", base=BASE.replace("seed: 1}", "seed: 1, clearance_m: -1e999}"))
yb("clearance_nan", "", base=BASE.replace("seed: 1}", "seed: 1, clearance_m: .nan}"))
yb("clearance_inf", "", base=BASE.replace("seed: 1}", "seed: 1, clearance_m: .inf}"))
yb("clearance_negative", "", base=BASE.replace("seed: 1}", "seed: 1, clearance_m: -1}"))
yb("seed_negative", "", base=BASE.replace("seed: 1}", "seed: -1}"))
yb("seed_int_overflow", "", base=BASE.replace("seed: 1}", "seed: 18446744073709551616}"))
yb("region_kinds_empty", "", base=BASE.replace("seed: 1}", "seed: 1, region_kinds: []}"))
yb("region_kinds_number", "", base=BASE.replace("seed: 1}", "seed: 1, region_kinds: [5]}"))
yb("random_yaw_string", "", base=BASE.replace("seed: 1}", "seed: 1, random_yaw: maybe}"))
yb("shared_range_zero", "shared: {range_m: 0}\n")
yb("shared_range_negative", "shared: {range_m: -10}\n")
yb("shared_range_huge", "shared: {range_m: 1e308}\n")
yb("shared_unknown", "shared: {rang_m: 10}\n")
yb("shared_cut_height_neg", "shared: {cut_height_m: -1}\n")
yb("shared_not_map", "shared: 5\n")
yb("observation_source_bad", "observation: {source: dream}\n")
yb("observation_range_zero", "observation: {max_range_m: 0}\n")
yb("observation_rays_zero", "observation: {rays: 0}\n")
yb("observation_rays_huge", "observation: {rays: 100000}\n")
yb("observation_rays_negative", "observation: {rays: -36}\n")
yb("observation_sensor_bad", "observation: {source: scan, sensor: radar}\n")
yb("observation_setting_bad", "observation: {source: scan, setting: half}\n")
yb("observation_seed_negative", "observation: {seed: -3}\n")
yb("sensor_params_range_negative", "observation: {source: scan, sensor: lidar, sensor_params: {sensor: {max_range_m: -1}}}\n")
yb("sensor_params_unknown", "observation: {source: scan, sensor_params: {warp: 1}}\n")
yb("sensor_params_not_map", "observation: {source: scan, sensor_params: [1, 2]}\n")
yb("sensor_params_views_huge", "observation: {source: scan, sensor_params: {geometry: {num_views: 100000}}}\n")
yb("sensor_params_pixels_huge", "observation: {source: scan, sensor_params: {geometry: {width_px: 100000, height_px: 100000}}}\n")
yb("observe_stride_zero", "observation: {source: scan, observe_params: {back_projection: {pixel_stride: 0}}}\n")
yb("observe_voxel_zero", "observation: {source: scan, observe_params: {ground: {voxel_m: 0}}}\n")
yb("observe_k_zero", "observation: {source: scan, observe_params: {ground: {normal_k: 0}}}\n")
yb("observe_reference_99", "observation: {source: scan, observe_params: {scale: {reference_view: 99}}}\n")
yb("observe_scales_swapped", "observation: {source: scan, observe_params: {scale: {min_scale: 1.2, max_scale: 0.8}}}\n")
yb("observe_theta_zero", "observation: {source: scan, observe_params: {segments: {hough_theta_deg: 0}}}\n")
yb("observe_deep", "observation: {source: scan, observe_params: {scale: " + "{a: " * 200 + "1" + "}" * 200 + "}}\n")
yb("observe_params_list", "observation: {source: scan, observe_params: [1]}\n")
yb("observe_int_overflow", "observation: {source: scan, observe_params: {ground: {ransac_iterations: 99999999999}}}\n")
y("no_matchers", "buildings: [floorplans/buildings/two_rooms.json]\n")
y("matchers_empty", "buildings: [floorplans/buildings/two_rooms.json]\nmatchers: {}\n")
y("matchers_list", "buildings: [floorplans/buildings/two_rooms.json]\nmatchers: [kernel]\n")
y("matcher_unknown", "buildings: [floorplans/buildings/two_rooms.json]\nmatchers: {k: {matcher: oracle}}\n")
y("matcher_missing_name", "buildings: [floorplans/buildings/two_rooms.json]\nmatchers: {k: {alpha: 1}}\n")
y("matcher_label_bad", "buildings: [floorplans/buildings/two_rooms.json]\nmatchers: {'k k': {matcher: kernel}}\n")
y("matcher_param_unknown", "buildings: [floorplans/buildings/two_rooms.json]\nmatchers: {k: {matcher: kernel, alfa: 1}}\n")
y("matcher_resolution_zero", "buildings: [floorplans/buildings/two_rooms.json]\nmatchers: {k: {matcher: kernel, resolution_m: 0}}\n")
y("matcher_resolution_tiny", "buildings: [floorplans/buildings/two_rooms.json]\nmatchers: {k: {matcher: ray, resolution_m: 0.0001}}\n")
y("matcher_directions_huge", "buildings: [floorplans/buildings/two_rooms.json]\nmatchers: {k: {matcher: ray, num_directions: 1000000}}\n")
y("matcher_scales_empty", "buildings: [floorplans/buildings/two_rooms.json]\nmatchers: {k: {matcher: kernel, scales: []}}\n")
y("matcher_scales_negative", "buildings: [floorplans/buildings/two_rooms.json]\nmatchers: {k: {matcher: kernel, scales: [-1]}}\n")
y("matcher_alpha_string", "buildings: [floorplans/buildings/two_rooms.json]\nmatchers: {k: {matcher: kernel, alpha: high}}\n")
y("matcher_blur_even", "buildings: [floorplans/buildings/two_rooms.json]\nmatchers: {k: {matcher: kernel, blur_size_px: 4}}\n")
y("matcher_dense_step_zero", "buildings: [floorplans/buildings/two_rooms.json]\nmatchers: {k: {matcher: kernel, dense_step_deg: 0}}\n")
y("matcher_params_deep", "buildings: [floorplans/buildings/two_rooms.json]\nmatchers: {k: {matcher: kernel, alpha: " + "[" * 300 + "]" * 300 + "}}\n")
yb("sweep_not_map", "sweep: 5\n")
yb("sweep_empty_axis", "sweep: {observation.seed: []}\n")
yb("sweep_unknown_key", "sweep: {colour: [1, 2]}\n")
yb("sweep_matcher_unknown", "sweep: {matchers.q.alpha: [1, 2]}\n")
yb("sweep_matcher_name", "sweep: {matchers.k.matcher: [kernel, ray]}\n")
yb("sweep_zip_mismatch", "sweep:\n  - {observation.seed: [1, 2], matchers.k.alpha: [1, 2, 3]}\n")
yb("sweep_same_key_twice", "sweep:\n  - {observation.seed: [1, 2]}\n  - {observation.seed: [3, 4]}\n")
yb("sweep_cells_limit", "sweep:\n" + "".join("  - {observation.observe_params.x%d: [1, 2, 3, 4, 5, 6, 7, 8, 9, 10]}\n" % i for i in range(6)))
yb("sweep_bad_value", "sweep: {observation.max_range_m: [10, -1]}\n")
yb("sweep_bad_matcher_value", "sweep: {matchers.k.resolution_m: [0.1, 0]}\n")
yb("sweep_observe_value", "sweep: {observation.observe_params.scale.min_scale: [0.5, 5]}\n")
yb("scoring_thresholds_empty", "scoring: {recall_thresholds_m: []}\n")
yb("scoring_thresholds_negative", "scoring: {recall_thresholds_m: [1, -1]}\n")
yb("scoring_thresholds_string", "scoring: {recall_thresholds_m: [a]}\n")
yb("scoring_thresholds_huge", "scoring: {recall_thresholds_m: [1e308]}\n")
yb("scoring_top_k_zero", "scoring: {top_k: 0}\n")
yb("scoring_bootstrap_huge", "scoring: {bootstrap_resamples: 100000000}\n")
yb("scoring_deg_negative", "scoring: {combined_threshold_deg: -1}\n")
yb("output_heatmaps_negative", "output: {heatmaps: -1}\n")
yb("paper_not_list", "paper: {a: 1}\n")
yb("paper_value_string", "paper: [{label: x, values: {recall_1m: high}}]\n")
yb("paper_no_label", "paper: [{values: {recall_1m: 1}}]\n")
yb("walk_steps_zero", "walk: {steps: 0}\ntrackers: {t: {tracker: pf, matcher: k}}\n")
yb("walk_steps_huge", "walk: {steps: 100000000}\ntrackers: {t: {tracker: pf, matcher: k}}\n")
yb("walk_speed_swapped", "walk: {speed_min_mps: 2, speed_max_mps: 1}\ntrackers: {t: {tracker: pf, matcher: k}}\n")
yb("walk_unknown", "walk: {stepz: 10}\ntrackers: {t: {tracker: pf, matcher: k}}\n")
yb("odometry_model_bad", "odometry: {model: teleport}\ntrackers: {t: {tracker: pf, matcher: k}}\n")
yb("schedule_no_initial", "schedule: {initial: false}\ntrackers: {t: {tracker: pf, matcher: k}}\n")
yb("schedule_every_negative", "schedule: {every_steps: -1}\ntrackers: {t: {tracker: pf, matcher: k}}\n")
yb("trackers_missing", "walk: {steps: 10}\n")
yb("tracker_unknown", "trackers: {t: {tracker: kalman, matcher: k}}\n")
yb("tracker_matcher_unknown", "trackers: {t: {tracker: pf, matcher: nope}}\n")
yb("tracker_particles_zero", "trackers: {t: {tracker: pf, matcher: k, num_particles: 0}}\n")
yb("tracker_particles_huge", "trackers: {t: {tracker: pf, matcher: k, num_particles: 1000000000}}\n")
yb("tracker_hist_orientations", "trackers: {t: {tracker: hist, matcher: k, num_orientations: 0}}\n")
yb("number_hex", "", base=BASE.replace("count: 2", "count: 0x10"))
yb("number_underscore", "", base=BASE.replace("count: 2", "count: 1_000"))
yb("bool_yes", "observation: {doors_closed: yes}\n")
yb("tag_binary", "observation: {source: !!binary aGVsbG8=}\n")
yb("anchor_on_key", "&k name: t\n" + BASE.replace("name: t\n", ""))
yb("long_key", "x" * 100000 + ": 1\n")
yb("long_value", "description: " + "y" * 1000000 + "\n")

# ---- gate ---------------------------------------------------------------------------------------
put("gate/summary_incomplete.json", json.dumps({"complete": False}))
put("gate/summary_ok.json", json.dumps({"complete": True, "cells": [{"id": "c000", "recall": 0.5}]}))
put("gate/baseline_huge_index.json", json.dumps({"checks": [{"pointer": "/cells/99999999999999999999/recall", "min": 0.1}]}))
put("gate/baseline_neg_index.json", json.dumps({"checks": [{"pointer": "/cells/-1/recall", "min": 0.1}]}))
put("gate/baseline_bad_pointer.json", json.dumps({"checks": [{"pointer": "cells~9", "min": 0.1}]}))
put("gate/baseline_bad_escape.json", json.dumps({"checks": [{"pointer": "/cells~9/x", "min": 0.1}]}))
put("gate/baseline_min_string.json", json.dumps({"checks": [{"pointer": "/cells/0/recall", "min": "high"}]}))
put("gate/baseline_no_bounds.json", json.dumps({"checks": [{"pointer": "/cells/0/recall"}]}))
put("gate/baseline_unknown_key.json", json.dumps({"checks": [], "floors": []}))
put("gate/baseline_checks_object.json", json.dumps({"checks": {"a": 1}}))
put("gate/baseline_ratio_zero_den.json", json.dumps({"timing_ratios": [{"name": "r", "numerator": "/cells/0/recall", "denominator": "/zero", "baseline": 1, "tolerance": 1.5}]}))
put("gate/baseline_tolerance_string.json", json.dumps({"timing_ratios": [{"name": "r", "numerator": "/cells/0/recall", "denominator": "/cells/0/recall", "baseline": 1, "tolerance": "wide"}]}))
put("gate/baseline_name_number.json", json.dumps({"timing_ratios": [{"name": 5, "numerator": "/cells/0/recall", "denominator": "/cells/0/recall", "baseline": 1}]}))
put("gate/summary_zero.json", json.dumps({"complete": True, "zero": 0, "cells": [{"id": "c000", "recall": 0.5}]}))
put("gate/summary_deep_array.json", "{\"complete\": true, \"x\": " + "[" * 300 + "]" * 300 + "}")

# ---- issue 28: hostile input round two --------------------------------------------------------
# Duplicate keys: JSON keeps the last, so the first "walls" (the real ones) was silently dropped and
# the error blamed an empty plan.
put(P + "duplicate_key_walls.json", plan()[:-1] + ', "walls": []}')
put(P + "duplicate_key_nested.json", plan().replace('"id": "s", ', '"id": "s", "id": "t", ', 1))
put("obs/duplicate_key.json", json.dumps({"format": "floorcast-observation", "format_version": 1, "frame": "observer",
                                          "max_range_m": 10, "segments_m": [[1, -1, 1, 1]]})[:-1] + ', "max_range_m": 1}')
# Gate: a baseline that checks nothing, and one of another scenario.
put("gate/summary_named.json", json.dumps({"complete": True, "scenario": "gate", "cells": [{"id": "c000", "recall": 0.5}]}))
put("gate/baseline_zero_checks.json", json.dumps({"description": "nothing", "checks": []}))
put("gate/baseline_empty_object.json", json.dumps({}))
put("gate/baseline_other_scenario.json", json.dumps({"scenario": "scenarios/gate_sequential.yaml",
                                                     "checks": [{"pointer": "/cells/0/recall", "min": 0.1}]}))
put("gate/baseline_same_scenario.json", json.dumps({"scenario": "scenarios/gate.yaml",
                                                    "checks": [{"pointer": "/cells/0/recall", "min": 0.1}]}))
# YAML merge keys (YAML 1.1 `<<`): yaml-cpp reads "<<" as a key, which the loader called unknown.
RUN_BASE = ("name: t\nbuildings: [floorplans/buildings/two_rooms.json]\nsampling: {count: 2, seed: 1}\n"
            "observation: {source: perfect}\noutput: {heatmaps: 0}\n")
y("merge_key", RUN_BASE + "matchers:\n  k: &k {matcher: kernel, resolution_m: 0.1}\n  k2: {<<: *k, resolution_m: 0.2}\n")
y("merge_key_list", RUN_BASE + "matchers:\n  k: &k {matcher: kernel}\n  r: &r {matcher: ray, max_range_m: 8}\n"
  "  k2: {<<: [*k, *r]}\n")
y("merge_key_scalar", BASE + "observation: {<<: 5}\n")
y("merge_key_unknown_after", RUN_BASE + "matchers:\n  k: &k {matcher: kernel}\n  k2: {<<: *k, colour: red}\n")
# A folder where a plan file is expected ("not found" before).
y("building_is_folder", "buildings: [floorplans/buildings]\nmatchers: {k: {matcher: kernel}}\n")
# CSV from a spreadsheet: a UTF-8 byte-order mark before the first number.
put("csv/bom.csv", b"\xef\xbb\xbf" + b"0,0,8,0\n8,0,8,5\n8,5,0,5\n0,5,0,0\n")
put("csv/bom_crlf.csv", b"\xef\xbb\xbf" + b"0,0,8,0\r\n8,0,8,5\r\n8,5,0,5\r\n0,5,0,0\r\n")
# Fuzzing finding (issue 28's campaign): a wall 255 m long at a slant; rasters painted its whole
# bounding box (6 s under the fuzzer's sanitizers for 359 bytes). A non-UTF-8 byte in the comment.
put("csv/fuzz_diagonal_feet.csv", b"# x1,y1,x2,y2 in\x9c feet\n0.0000,0.0000,9.8425,0.0000\n12.7953,0.0000,32.8084,0.0000\n"
    b"32.8084,0.0000,32.8084,26.2467\n32.8044,862.267,0.0000,26.2467\n0.0000,26.2467,0.0000,0.0000\n"
    b"16.4042,0.0000,16.4042,9.8425\n16.4042,12.7953,16.4042,26.2467\n0.0000,132.134,6.5617,13.1234\n"
    b"9.5144,13.1234,16.4042,13.1234\n16.4042,13.1234,22.9659,13.1234\n25.9186,11.1234,32.8084,13.1234\n")


def gray_png(width, height, value):
    """An 8-bit grayscale PNG of one value."""
    sig = b"\x89PNG\r\n\x1a\n"

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    raw = b"".join(b"\x00" + bytes([value]) * width for _ in range(height))
    return sig + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)) + \
        chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")


# Occupancy images with nothing free (all black) or nothing occupied (all white).
put("png/all_black.png", gray_png(64, 48, 0))
put("png/all_white.png", gray_png(64, 48, 255))
# The shipped two-room plan under another name: another plan hash, the same geometry.
with open(os.path.join(HERE, "..", "..", "floorplans", "buildings", "two_rooms.json")) as f:
    two_rooms = json.load(f)
two_rooms["name"] = "two_rooms_renamed"
put(P + "two_rooms_renamed.json", json.dumps(two_rooms, indent=1))

print("wrote", sum(len(f) for _, _, f in os.walk(DATA)), "files under", DATA)
