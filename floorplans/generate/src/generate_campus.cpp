// Campus archetype: a large teaching building.
//
// Layout (x east, y north), all bands in metres:
//   y: outer row S (rd) | hallway H0 (cw) | inner block 1 (2 rd) | H1 | inner block 2 (2 rd) | H2 |
//      outer row N (rd)      (rd: one row depth, or one per row when depth_per_row)
//   x: end rooms (rd) | cross hallway V0 (cw) | segment 0 | V1 | segment 1 | ... | V_n | end rooms
// H0..H2 run the full length (exits or end windows at the facades); cross hallways V_k cross the
// inner blocks (all of them, or with inner_crossing_probability < 1 at least one per block, the
// rows running on where one is left out) and reach the facade through the outer rows (exits) or
// stop at a stairwell. Each segment's strips are rows of module rooms (or, calibrated, rooms of
// the real area distribution) facing a hallway, except the reserved special rooms: lobby + atrium
// + cafeteria in the middle segment, great and lecture halls, cores (stairwell, elevator, toilets)
// and lounge niches.
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <string>

#include "floorcast/floorplans/geometry.hpp"
#include "generate_layout.hpp"

namespace floorcast {

using namespace generate_detail;

namespace {

enum Strip { kS = 0, kI1b, kI1t, kI2b, kI2t, kN, kStripCount };

std::string seg_name(int j) { return "seg" + std::to_string(j); }

// How the campus cuts its rows: offices, two-module classrooms, three-module labs.
RowFill campus_row_fill(double module_m, const RoomVariety& variety) {
  RowFill fill;
  fill.module_m = module_m;
  fill.p_double = 0.25;
  fill.p_triple = 0.1;
  fill.kind_single = "office";
  fill.kind_double = "classroom";
  fill.kind_triple = "lab";
  fill.glass_double_probability = 0.1;
  fill.min_room_m = 2.4;  // narrower leftovers widen the last room instead of becoming closets
  fill.variety = &variety;
  return fill;
}

// A core: stairwell, elevator and two toilets side by side along x in [x0, x0 + kCoreLength] of a
// row [y0, y1] facing `hallway`, ordered from the end the core sits at inward.
constexpr double kCoreLength = 3.6 + 2.6 + 2.0 * 3.0;

void add_core(Layout& L, const std::string& pre, const Frame& F, double x0, bool at_start, double y0, double y1,
              int facing, int hallway, const WindowSpec& windows, Rng& rng) {
  const BuildingStyle& st = L.style();
  const std::array<double, 4> widths = {3.6, 2.6, 3.0, 3.0};
  const std::array<const char*, 4> kinds = {"stairwell", "elevator", "toilet", "toilet"};
  const std::array<const char*, 4> names = {".stair", ".lift", ".wc1", ".wc2"};
  double x = at_start ? x0 : x0 + kCoreLength;
  for (int k = 0; k < 4; ++k) {
    const double w = widths[static_cast<std::size_t>(k)];
    const double a = at_start ? x : x - w, b = at_start ? x + w : x;
    x = at_start ? b : a;
    const std::string id = pre + names[static_cast<std::size_t>(k)];
    const std::string kind = kinds[static_cast<std::size_t>(k)];
    const bool closed = kind == "toilet" ? rng.bernoulli(0.7) : true;
    const double dw = kind == "elevator" ? 1.0 : st.door_width_m;
    add_facing_room(L, id, kind, F, a, y0, b, y1, facing, hallway, windows, 0.5 * (a + b), dw, closed, rng);
    if (kind == "stairwell" && st.furniture) add_stairs(L, id, F, a, y0, b, y1);
  }
}

// A lecture hall's lectern and seat rows: the lectern at local x = `front`, rows across the hall
// ([y0, y1], aisles at both sides) every 0.95 m from `first_row_m` towards `front + dir * length`.
void furnish_hall(Layout& L, const std::string& id, const Frame& F, double front, double dir, double length,
                  double y0, double y1, double first_row_m = 3.5) {
  L.add_obstacle(id + "_lectern", ObstacleKind::kBox, F.to_world(front + dir * 1.8, 0.5 * (y0 + y1)), Vec2(0.6, 1.2),
                 F.yaw_rad, 1.1);
  const double aisle = 1.2;
  for (double a = first_row_m; a < length - 1.6; a += 0.95) {
    L.add_obstacle(id + "_seats", ObstacleKind::kBox, F.to_world(front + dir * a, 0.5 * (y0 + y1)),
                   Vec2(0.5, (y1 - y0) - 2.0 * aisle - 0.3), F.yaw_rad, 0.8);
  }
}


// ---- Spine layout ------------------------------------------------------------------------------
//
// World frame (x east, y north): the spine corridor [0, Ls] x [0, cw]; the west wing's corridor
// [-cw, 0] x [-aW, LW - aW] (its frame rotated by 90 deg: local x runs north), the east wing's
// [Ls, Ls + cw] x [cw + aE - LE, cw + aE] (rotated by 270 deg: local x runs south). In a wing's
// frame the corridor is [0, Lw] x [0, cw], its inner side (towards the spine) local y < 0, its
// outer side local y > cw, and the spine meets it at local x in [a, a + cw]. Each corridor is cut
// into segments; per segment one side is lined with rooms and the other with
// second_side_loaded_probability (else a facade with windows). Halls project from the spine's
// sides and the wings' outer sides, and close the wing ends.

struct SpinePiece {
  StripReservations res;
  bool loaded;
};

struct SpineSide {
  Frame frame;
  int degrees = 0;  // the frame's rotation
  double y0 = 0.0, y1 = 0.0;  // the row band; the corridor at y1 (facing +1) or y0 (facing -1)
  int facing = 1;
  int hallway = -1;
  bool halls = false;                       // halls may project from this side, away from the corridor
  double hall_x0 = 0.0, hall_x1 = 0.0;      // ... within this local x range
  double facade_x0 = 0.0, facade_x1 = 0.0;  // the row's far side is a facade within this range
  std::string name;
  std::vector<SpinePiece> pieces;
};

struct SpineCorridor {
  Frame frame;
  double length = 0.0;
  int hallway = -1;
  std::vector<double> cuts;           // segment boundaries (local x)
  std::array<SpineSide, 2> side;      // 0: local y < 0 (facing +1), 1: local y > cw (facing -1)
};

// A hall's outline in its own coordinates: u along its corridor side [0, len], v away from the
// corridor [0, depth]. With the hall variety a shaped hall's far side (v = depth) has rectangular
// notches cut from its far corners and / or a bay beyond its middle, and a third of the halls
// chamfered corners (CampusParams::HallVariety);
// `far_cut_m` is how deep the notches reach in from the far side (seat rows start beyond it).
struct HallOutline {
  std::vector<Vec2> uv;
  double far_cut_m = 0.0;
  /// Chamfered corners: (a, corner, b), the cut side from a to b (uv, then world coordinates).
  std::vector<std::array<Vec2, 3>> cuts;
};

// A chamfered corner of a hall (world coordinates): the hall's outline runs a -> b where it ran a ->
// corner -> b.
struct HallCut {
  int room = -1;
  std::array<Vec2, 3> abc;
};

HallOutline to_world(HallOutline o, const std::function<Vec2(const Vec2&)>& world) {
  for (Vec2& q : o.uv) q = world(q);
  for (auto& c : o.cuts)
    for (Vec2& q : c) q = world(q);
  return o;
}

// Gives a chamfered corner back where another room comes within 0.3 m of the sides it cut off (a
// wall there would leave a sliver of outside between it and the cut): halls of one side may touch,
// and a hall's sides run along its row band's rooms. Where every cut of a hall is given back its
// outline is the one it had without chamfers (a great hall's may be deeper: it was deepened to
// hold its area with the cuts).
void restore_blocked_cuts(Layout& L, const std::vector<HallCut>& cuts) {
  for (const HallCut& c : cuts) {
    bool blocked = false;
    for (int r = 0; r < L.room_count() && !blocked; ++r) {
      if (r == c.room) continue;
      const std::vector<Vec2>& poly = L.room(r).polygon_m;
      for (std::size_t k = 0; k < poly.size() && !blocked; ++k) {
        const Segment2 e{poly[k], poly[(k + 1) % poly.size()]};
        for (const Segment2& side : {Segment2{c.abc[0], c.abc[1]}, Segment2{c.abc[1], c.abc[2]}}) {
          // The distance between two segments that do not cross is the least of their ends'
          // distances to the other; no room edge crosses a removed side (rooms do not overlap the
          // hall, whose outline the removed sides were).
          const double d = std::min({point_segment_distance(e.a_m, side), point_segment_distance(e.b_m, side),
                                     point_segment_distance(side.a_m, e), point_segment_distance(side.b_m, e)});
          if (d < 0.3) blocked = true;
        }
      }
    }
    if (!blocked) continue;
    std::vector<Vec2> poly = L.room(c.room).polygon_m;
    for (std::size_t k = 0; k < poly.size(); ++k) {  // stored counter-clockwise: a -> b or b -> a
      const Vec2 &p0 = poly[k], &p1 = poly[(k + 1) % poly.size()];
      const auto same = [](const Vec2& u, const Vec2& v) { return (u - v).norm() < 1e-9; };
      if ((same(p0, c.abc[0]) && same(p1, c.abc[2])) || (same(p0, c.abc[2]) && same(p1, c.abc[0]))) {
        poly[k] = c.abc[1];
        poly.erase(poly.begin() + static_cast<std::ptrdiff_t>((k + 1) % poly.size()));
        break;
      }
    }
    L.set_room_polygon(c.room, std::move(poly));
  }
}

// Cuts convex corners of a hall's outline away from its corridor side (v > 0) by sides at 45
// degrees, all of one length (HallVariety::chamfer_*): each corner where the cut reaches at most
// 0.45 of both sides it shortens, with chamfer_corner_probability, at least two (the length is
// shortened to fit two corners where it fits fewer; no cut under 0.5 m). Seat rows start beyond the
// cuts that reach into the hall from its far side.
void chamfer_corners(HallOutline& o, double depth, const CampusParams::HallVariety& v, Rng& rng) {
  const std::vector<Vec2> p = o.uv;  // counter-clockwise: a left turn is a convex corner
  const std::size_t n = p.size();
  std::vector<double> room(n, 0.0);  // the longest leg a cut at each corner may have
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 e0 = p[i] - p[(i + n - 1) % n], e1 = p[(i + 1) % n] - p[i];
    if (p[i].y() > 1e-9 && e0.x() * e1.y() - e0.y() * e1.x() > 0.0) room[i] = 0.45 * std::min(e0.norm(), e1.norm());
  }
  std::vector<double> sorted = room;
  std::sort(sorted.begin(), sorted.end(), std::greater<double>());
  const double leg = std::floor(std::min(rng.uniform(v.chamfer_length_min_m, v.chamfer_length_max_m) / std::sqrt(2.0),
                                         n > 1 ? sorted[1] : 0.0) * 10.0) / 10.0;  // on the 0.1 m grid
  if (leg < 0.5) return;
  std::vector<std::size_t> eligible;
  for (std::size_t i = 0; i < n; ++i) {
    if (room[i] >= leg) eligible.push_back(i);
  }
  std::vector<bool> cut(n, false);
  std::size_t count = 0;
  for (std::size_t i : eligible) {
    if (rng.bernoulli(v.chamfer_corner_probability)) cut[i] = true, ++count;
  }
  while (count < 2) {
    const std::size_t i = eligible[static_cast<std::size_t>(rng.integer(0, static_cast<int>(eligible.size()) - 1))];
    if (!cut[i]) cut[i] = true, ++count;
  }
  o.uv.clear();
  for (std::size_t i = 0; i < n; ++i) {
    if (!cut[i]) {
      o.uv.push_back(p[i]);
      continue;
    }
    const Vec2 a = p[i] + leg * (p[(i + n - 1) % n] - p[i]).normalized();
    const Vec2 b = p[i] + leg * (p[(i + 1) % n] - p[i]).normalized();
    o.uv.push_back(a);
    o.uv.push_back(b);
    o.cuts.push_back({a, p[i], b});
    if (p[i].y() <= depth + 1e-9) o.far_cut_m = std::max(o.far_cut_m, depth - p[i].y() + leg);
  }
}

HallOutline hall_outline(double len, double depth, const CampusParams::HallVariety& v, Rng& rng) {
  HallOutline o;
  std::array<bool, 2> notch = {false, false};  // at u = 0, at u = len
  bool bay = false;
  if (v.enabled && rng.bernoulli(v.shaped_probability)) {
    notch[0] = rng.bernoulli(v.corner_notch_probability);
    notch[1] = rng.bernoulli(v.corner_notch_probability);
    bay = rng.bernoulli(v.bay_probability);
    if (!notch[0] && !notch[1] && !bay) {  // a shaped hall has at least one feature
      const int k = rng.integer(0, 2);
      if (k < 2) notch[static_cast<std::size_t>(k)] = true;
      else bay = true;
    }
  }
  std::array<double, 2> nw{}, nd{};
  for (std::size_t k = 0; k < 2; ++k) {
    if (!notch[k]) continue;
    nw[k] = snap(rng.uniform(v.notch_width_share_min, v.notch_width_share_max) * len, 0.1);
    nd[k] = snap(rng.uniform(v.notch_depth_share_min, v.notch_depth_share_max) * depth, 0.1);
    o.far_cut_m = std::max(o.far_cut_m, nd[k]);
  }
  o.uv = {Vec2(0.0, 0.0), Vec2(len, 0.0)};
  if (notch[1]) {
    o.uv.insert(o.uv.end(), {Vec2(len, depth - nd[1]), Vec2(len - nw[1], depth - nd[1]), Vec2(len - nw[1], depth)});
  } else {
    o.uv.emplace_back(len, depth);
  }
  if (bay) {
    const double hw = 0.5 * snap(rng.uniform(v.bay_width_share_min, v.bay_width_share_max) * len, 0.2);
    const double bd = snap(rng.uniform(v.bay_depth_min_m, v.bay_depth_max_m), 0.1);
    const double uc = snap(0.5 * len, 0.1);
    o.uv.insert(o.uv.end(), {Vec2(uc + hw, depth), Vec2(uc + hw, depth + bd), Vec2(uc - hw, depth + bd),
                             Vec2(uc - hw, depth)});
  }
  if (notch[0]) {
    o.uv.insert(o.uv.end(), {Vec2(nw[0], depth), Vec2(nw[0], depth - nd[0]), Vec2(0.0, depth - nd[0])});
  } else {
    o.uv.emplace_back(0.0, depth);
  }
  // From a stream of its own: the rest of the building is the same with or without chamfers.
  Rng chamfer_rng = rng.fork(0xC4A3F3EDULL);
  if (v.enabled && v.chamfer_probability > 0.0 && chamfer_rng.bernoulli(v.chamfer_probability)) {
    chamfer_corners(o, depth, v, chamfer_rng);
  }
  return o;
}

// How many doors a hall has on its corridor side (HallVariety::door_count_weights) and where (u
// along the side, each in its own equal part of [0, len], at least door_corner_share_min * len from
// either end).
std::vector<double> hall_door_positions(double len, const CampusParams::HallVariety& v, Rng& rng) {
  double total = 0.0;
  for (double w : v.door_count_weights) total += std::max(0.0, w);
  double pick = rng.uniform(0.0, total);
  int n = 1;
  for (std::size_t k = 0; k < v.door_count_weights.size(); ++k) {
    pick -= std::max(0.0, v.door_count_weights[k]);
    n = static_cast<int>(k) + 1;
    if (pick < 0.0) break;
  }
  const double margin = v.door_corner_share_min * len;
  std::vector<double> u;
  for (int k = 0; k < n; ++k) {
    const double a = std::max(margin, len * k / n), b = std::min(len - margin, len * (k + 1) / n);
    u.push_back(snap(rng.uniform(a, std::max(a, b)), 0.1));
  }
  return u;
}

// A hall [x0, x1] of a side's frame reaching `depth` from the side's corridor, entered from it.
// Without the hall variety: a rectangle with two double doors (one open); with it: the outline of
// hall_outline() and the doors of hall_door_positions(); a hall whose outline holds less than
// `area_m2` (great halls: the drawn area is the outline's) is deepened to hold it. The lectern
// stands at the far wall; seat rows parallel to the corridor.
void add_spine_hall(Layout& L, const std::string& id, const SpineSide& side, double x0, double x1, double depth,
                    double area_m2, const CampusParams::HallVariety& variety, Rng& rng, std::vector<HallCut>& cuts) {
  const BuildingStyle& st = L.style();
  const double len = x1 - x0;
  HallOutline o;
  if (variety.enabled) {
    o = hall_outline(len, depth, variety, rng);
    const double a = std::abs(signed_area(o.uv));
    if (a < area_m2) {
      const double k = area_m2 / a;
      for (Vec2& q : o.uv) q.y() = snap(k * q.y(), 0.1);
      for (auto& c : o.cuts)
        for (Vec2& q : c) q.y() = snap(k * q.y(), 0.1);
      depth = snap(k * depth, 0.1);
      o.far_cut_m *= k;
    }
  }
  const double yc = side.facing > 0 ? side.y1 : side.y0;  // corridor edge
  const double yf = yc - side.facing * depth;              // far wall
  const double y0 = std::min(yc, yf), y1 = std::max(yc, yf);
  double first_row = 3.5;
  int hall = -1;
  if (!variety.enabled) {
    hall = L.add_rect(id, "lecture_hall", side.frame, x0, y0, x1, y1, no_windows());
    L.add_door(hall, side.hallway, st.double_door_width_m, false, side.frame.to_world(x0 + 0.25 * len, yc));
    L.add_door(hall, side.hallway, st.double_door_width_m, rng.bernoulli(0.5),
               side.frame.to_world(x1 - 0.25 * len, yc));
  } else {
    const HallOutline w =
        to_world(o, [&](const Vec2& q) { return side.frame.to_world(x0 + q.x(), yc - side.facing * q.y()); });
    hall = L.add_room(id, "lecture_hall", w.uv, no_windows());
    for (const auto& c : w.cuts) cuts.push_back({hall, c});
    bool first = true;
    for (double u : hall_door_positions(len, variety, rng)) {
      L.add_door(hall, side.hallway, st.double_door_width_m, first ? false : rng.bernoulli(0.5),
                 side.frame.to_world(x0 + u, yc));
      first = false;
    }
    first_row = std::max(first_row, o.far_cut_m + 1.0);
  }
  if (!st.furniture) return;
  // Lectern at the far wall, rows towards the corridor: furnished in a frame whose x runs from the
  // far wall's middle to the corridor.
  const Frame f = rotated_frame(side.frame.to_world(0.5 * (x0 + x1), yf), side.degrees + (side.facing > 0 ? 90 : 270));
  furnish_hall(L, id, f, 0.0, 1.0, depth, -0.5 * len, 0.5 * len, first_row);
}

GeneratedBuilding generate_campus_spine(std::uint64_t seed, const CampusParams& p) {
  Rng rng(mix_seed(seed, 0x5B14E5ULL));
  const BuildingStyle& st = p.style;
  Layout L(st);
  const WindowSpec win = standard_windows(st);
  const double dd = st.double_door_width_m, sd = st.door_width_m;
  const double min_gap = 2.0 * st.door_jamb_m + sd + 0.6;
  auto depth = [&]() { return snap(rng.uniform(p.room_depth_min_m, p.room_depth_max_m), 0.1); };

  const double cw = snap(rng.uniform(p.hallway_width_min_m, p.hallway_width_max_m), 0.1);
  const double module = snap(rng.uniform(p.module_width_min_m, p.module_width_max_m), 0.05);
  const double target_m2 = rng.uniform(p.target_area_min_m2, p.target_area_max_m2);
  const double dS = depth(), dN = depth();    // spine rows south / north
  const double dWi = depth(), dWo = depth();  // west wing inner / outer rows
  const double dEi = depth(), dEo = depth();  // east wing inner / outer rows
  const double ratio_w = rng.uniform(p.wing_length_ratio_min, p.wing_length_ratio_max);
  const double ratio_e = rng.uniform(p.wing_length_ratio_min, p.wing_length_ratio_max);
  const double share_w = rng.uniform(p.wing_junction_share_min, p.wing_junction_share_max);
  const double share_e = rng.uniform(p.wing_junction_share_min, p.wing_junction_share_max);

  // Size: gross area per metre of corridor (rows on one side, the other with the loading
  // probability) plus the halls' area beyond the rows; free floor ~0.78 of the gross (measured on
  // seeds 1-8).
  const double d_mean = (dS + dN + dWi + dWo + dEi + dEo) / 6.0;
  const double per_m = cw + d_mean * (1.0 + p.second_side_loaded_probability);
  const double hall_depth_mean = 0.5 * (p.spine_hall_depth_min_m + p.spine_hall_depth_max_m);
  const double hall_len_mean = 0.5 * (p.spine_hall_length_min_m + p.spine_hall_length_max_m);
  const double lecture_mean = 0.5 * (p.lecture_halls_min + p.lecture_halls_max);
  const double halls_extra =
      p.great_halls * (0.5 * (p.great_hall_area_min_m2 + p.great_hall_area_max_m2) -
                       0.5 * (p.great_hall_width_min_m + p.great_hall_width_max_m) * d_mean) +
      lecture_mean * hall_len_mean * std::max(0.0, hall_depth_mean - d_mean);
  const double gross = std::max(target_m2 / 0.78 - halls_extra, 0.5 * target_m2);
  const double Ls = snap(gross / per_m / (1.0 + ratio_w + ratio_e), 0.1);
  const double LW = snap(ratio_w * Ls, 0.1), LE = snap(ratio_e * Ls, 0.1);
  const double aW = snap(share_w * LW, 0.1), aE = snap(share_e * LE, 0.1);

  const Frame F0;
  const Frame FW = rotated_frame(Vec2(0.0, -aW), 90);
  const Frame FE = rotated_frame(Vec2(Ls, aE + cw), 270);
  const int spine = L.add_rect("spine", "hallway", F0, 0.0, 0.0, Ls, cw, win);
  const int wing_w = L.add_rect("wingW", "hallway", FW, 0.0, 0.0, LW, cw, win);
  const int wing_e = L.add_rect("wingE", "hallway", FE, 0.0, 0.0, LE, cw, win);

  auto corridor = [&](const std::string& name, const Frame& f, int degrees, double len, int hallway, double d0,
                      double d1) {
    SpineCorridor c;
    c.frame = f;
    c.length = len;
    c.hallway = hallway;
    const int n = std::max(1, static_cast<int>(std::lround(len / p.segment_length_m)));
    for (int k = 0; k <= n; ++k) c.cuts.push_back(k == n ? len : snap(len * k / n, 0.1));
    for (int s = 0; s < 2; ++s) {
      SpineSide& side = c.side[static_cast<std::size_t>(s)];
      side.frame = f;
      side.degrees = degrees;
      side.facing = s == 0 ? +1 : -1;
      side.y0 = s == 0 ? -d0 : cw;
      side.y1 = s == 0 ? 0.0 : cw + d1;
      side.hallway = hallway;
      side.name = name + (s == 0 ? ".a" : ".b");
      side.facade_x0 = 0.0;
      side.facade_x1 = len;
    }
    return c;
  };
  // Spine: side 0 south (depth dS), side 1 north (dN). Wings: side 0 inner, side 1 outer.
  std::array<SpineCorridor, 3> C = {corridor("spine", F0, 0, Ls, spine, dS, dN),
                                    corridor("wingW", FW, 90, LW, wing_w, dWi, dWo),
                                    corridor("wingE", FE, 270, LE, wing_e, dEi, dEo)};
  // Halls project from the spine only between the wings' inner rows (where a spine row's far side
  // is a facade, too), and from the wings' outer sides.
  // A gap of kCourtGap between a hall and a wing's inner rows keeps the court between them open
  // (no enclosed unmapped region).
  constexpr double kCourtGap = 3.0;
  for (SpineSide& s : C[0].side) {
    s.halls = true;
    s.facade_x0 = dWi;
    s.facade_x1 = Ls - dEi;
    s.hall_x0 = dWi + kCourtGap;
    s.hall_x1 = Ls - dEi - kCourtGap;
  }
  for (std::size_t c = 1; c < 3; ++c) {
    C[c].side[1].halls = true;
    C[c].side[1].hall_x0 = 0.0;
    C[c].side[1].hall_x1 = C[c].length;
  }
  // Where the spine's rows meet a wing's inner side (local x of the wing).
  const std::array<Interval1, 2> junction = {Interval1{aW - dS, aW + cw + dN}, Interval1{aE - dN, aE + cw + dS}};
  const std::array<double, 2> junction_a = {aW, aE};

  for (std::size_t c = 0; c < 3; ++c) {
    SpineCorridor& cor = C[c];
    for (std::size_t k = 0; k + 1 < cor.cuts.size(); ++k) {
      const double x0 = cor.cuts[k], x1 = cor.cuts[k + 1];
      const int first = rng.integer(0, 1);
      const bool both = rng.bernoulli(p.second_side_loaded_probability);
      for (int s = 0; s < 2; ++s) {
        std::vector<Interval1> parts = {{x0, x1}};
        if (c > 0 && s == 0) parts = {{x0, std::min(x1, junction[c - 1].x0)}, {std::max(x0, junction[c - 1].x1), x1}};
        for (const Interval1& part : parts) {
          if (part.x1 - part.x0 < min_gap) continue;  // a short leftover stays outside
          cor.side[static_cast<std::size_t>(s)].pieces.push_back({StripReservations(part.x0, part.x1, min_gap),
                                                                   first == s || both});
        }
      }
    }
  }
  auto piece_at = [](SpineSide& side, double x0, double x1) -> StripReservations* {
    for (SpinePiece& pc : side.pieces) {
      if (pc.res.fits(x0, x1)) return &pc.res;
    }
    return nullptr;
  };

  // Exits: a stub across each wing's outer row opposite the spine (lined with rooms there).
  for (std::size_t w = 0; w < 2; ++w) {
    SpineSide& outer = C[w + 1].side[1];
    const double x0 = junction_a[w], x1 = x0 + cw;
    StripReservations* r = piece_at(outer, x0, x1);
    if (r == nullptr) continue;
    r->reserve(x0, x1);
    for (SpinePiece& pc : outer.pieces) {
      if (&pc.res == r) pc.loaded = true;
    }
    const int stub = L.add_rect(outer.name + ".exit", "hallway", outer.frame, x0, outer.y0, x1, outer.y1, no_windows());
    L.add_door(stub, kOutside, dd, true, outer.frame.to_world(0.5 * (x0 + x1), outer.y1));
  }

  // Lobby in the middle of the spine (south side, glass facade, entrances, open onto the spine)
  // and the first great hall opposite it.
  const std::size_t jm = (C[0].cuts.size() - 1) / 2;
  const double xc = snap(0.5 * (C[0].cuts[jm] + C[0].cuts[jm + 1]), 0.1);
  {
    const double ll = snap(rng.uniform(p.lobby_length_min_m, p.lobby_length_max_m), 0.1);
    const double x0 = xc - 0.5 * ll, x1 = xc + 0.5 * ll;
    StripReservations* r = piece_at(C[0].side[0], x0, x1);
    if (r != nullptr && r->reserve(x0, x1)) {
      const int lobby = L.add_rect("lobby", "lobby", F0, x0, -dS, x1, 0.0, no_windows());
      L.set_open(lobby, spine);
      L.set_glass(lobby, kOutside, 0.0, std::nullopt, Vec2(0.0, -1.0));
      L.add_door(lobby, kOutside, dd, true, F0.to_world(xc - 0.25 * ll, -dS));
      L.add_door(lobby, kOutside, dd, rng.bernoulli(0.5), F0.to_world(xc + 0.25 * ll, -dS));
      if (st.furniture) {
        L.add_obstacle("lobby_reception", ObstacleKind::kBox, F0.to_world(x0 + 2.5, -0.6 * dS), Vec2(3.0, 0.8), 0.0,
                       1.1);
      }
    }
  }

  // Halls: great halls (the first opposite the lobby), the wing end halls, then lecture halls
  // projecting from a random side of a random segment, at one end of it.
  int placed = 0;
  std::vector<HallCut> hall_cuts;
  auto try_hall = [&](SpineSide& side, double x0, double x1, double hall_depth, const std::string& id,
                      double area_m2 = 0.0) {
    if (!side.halls || x0 < side.hall_x0 - 1e-6 || x1 > side.hall_x1 + 1e-6) return false;
    StripReservations* r = piece_at(side, x0, x1);
    if (r == nullptr || !r->reserve(x0, x1)) return false;
    add_spine_hall(L, id, side, x0, x1, hall_depth, area_m2, p.hall_variety, rng, hall_cuts);
    ++placed;
    return true;
  };
  for (int g = 0; g < p.great_halls; ++g) {
    const double w = snap(rng.uniform(p.great_hall_width_min_m, p.great_hall_width_max_m), 0.1);
    const double hd = snap(rng.uniform(p.great_hall_area_min_m2, p.great_hall_area_max_m2) / w, 0.1);
    const std::string id = "great_hall" + std::to_string(g + 1);
    if (g == 0) {
      try_hall(C[0].side[1], xc - 0.5 * w, xc + 0.5 * w, hd, id, w * hd);
      continue;
    }
    for (int t = 0; t < 6; ++t) {  // a random spine segment side, at one end
      SpineSide& side = C[0].side[static_cast<std::size_t>(rng.integer(0, 1))];
      const std::size_t k = static_cast<std::size_t>(rng.integer(0, static_cast<int>(C[0].cuts.size()) - 2));
      const double x0 = rng.bernoulli(0.5) ? std::max(C[0].cuts[k], side.hall_x0) : std::min(C[0].cuts[k + 1], side.hall_x1) - w;
      if (try_hall(side, x0, x0 + w, hd, id, w * hd)) break;
    }
  }
  const int lecture_count = rng.integer(p.lecture_halls_min, p.lecture_halls_max);
  int lectures = 0;
  // Wing ends: a hall across the wing (inner row + corridor + outer row), entered from the corridor.
  for (std::size_t w = 0; w < 2; ++w) {
    const SpineCorridor& cor = C[w + 1];
    for (int end = 0; end < 2; ++end) {
      const bool hall_here = lectures < lecture_count && rng.bernoulli(p.wing_end_hall_probability);
      const double xe = end == 0 ? 0.0 : cor.length;
      if (!hall_here) {  // the corridor ends at the facade: an exit
        L.add_door(cor.hallway, kOutside, dd, true, cor.frame.to_world(xe, 0.5 * cw));
        continue;
      }
      const double hd = snap(rng.uniform(p.spine_hall_depth_min_m, p.spine_hall_depth_max_m), 0.1);
      const double x0 = end == 0 ? -hd : xe, x1 = end == 0 ? 0.0 : xe + hd;
      const double y0 = cor.side[0].y0, y1 = cor.side[1].y1;
      const std::string id = "lecture" + std::to_string(++lectures);
      double first_row = 3.5;
      int hall = -1;
      if (!p.hall_variety.enabled) {
        hall = L.add_rect(id, "lecture_hall", cor.frame, x0, y0, x1, y1, win);
      } else {  // u across the wing from y0, v from the corridor's end outward
        const HallOutline o = to_world(hall_outline(y1 - y0, hd, p.hall_variety, rng), [&](const Vec2& q) {
          return cor.frame.to_world(end == 0 ? -q.y() : xe + q.y(), y0 + q.x());
        });
        hall = L.add_room(id, "lecture_hall", o.uv, win);
        for (const auto& c : o.cuts) hall_cuts.push_back({hall, c});
        first_row = std::max(first_row, o.far_cut_m + 1.0);
      }
      L.add_door(hall, cor.hallway, dd, false, cor.frame.to_world(xe, 0.5 * cw));
      ++placed;
      if (st.furniture) {
        const double front = end == 0 ? x0 : x1, dir = end == 0 ? 1.0 : -1.0;
        furnish_hall(L, id, cor.frame, front, dir, hd, y0, y1, first_row);
      }
    }
  }
  for (int t = 0; t < 40 && lectures < lecture_count; ++t) {
    SpineCorridor& cor = C[static_cast<std::size_t>(rng.integer(0, 2))];
    SpineSide& side = cor.side[static_cast<std::size_t>(rng.integer(0, 1))];
    const std::size_t k = static_cast<std::size_t>(rng.integer(0, static_cast<int>(cor.cuts.size()) - 2));
    const double len = snap(rng.uniform(p.spine_hall_length_min_m, p.spine_hall_length_max_m), 0.1);
    const double hd = snap(rng.uniform(p.spine_hall_depth_min_m, p.spine_hall_depth_max_m), 0.1);
    const double x0 = rng.bernoulli(0.5) ? std::max(cor.cuts[k], side.hall_x0) : std::min(cor.cuts[k + 1], side.hall_x1) - len;
    if (try_hall(side, x0, x0 + len, hd, "lecture" + std::to_string(lectures + 1))) ++lectures;
  }

  // Cores (stairwell, elevator, toilets) at one end of a lined side of every segment.
  int core_no = 0;
  for (SpineCorridor& cor : C) {
    for (std::size_t k = 0; k + 1 < cor.cuts.size(); ++k) {
      const int first = rng.integer(0, 1);
      const bool at_start = rng.bernoulli(0.5);
      bool done = false;
      for (int t = 0; t < 4 && !done; ++t) {
        SpineSide& side = cor.side[static_cast<std::size_t>((first + t) % 2)];
        const bool start = (t < 2) == at_start;
        for (SpinePiece& pc : side.pieces) {
          if (!pc.loaded || pc.res.x1() <= cor.cuts[k] || pc.res.x0() >= cor.cuts[k + 1]) continue;
          const double x0 = start ? pc.res.x0() : pc.res.x1() - kCoreLength;
          if (!pc.res.reserve(x0, x0 + kCoreLength)) continue;
          add_core(L, "core" + std::to_string(++core_no), side.frame, x0, start, side.y0, side.y1, side.facing,
                   side.hallway, small_windows(st), rng);
          done = true;
          break;
        }
      }
    }
  }

  // Rows of rooms in what is left of the lined pieces; the rest of the corridor is facade.
  const RowFill fill = campus_row_fill(module, p.variety);
  for (SpineCorridor& cor : C) {
    for (SpineSide& side : cor.side) {
      int part = 0;
      for (SpinePiece& pc : side.pieces) {
        if (!pc.loaded) continue;
        for (const Interval1& f : pc.res.free_intervals()) {
          RowStrip row;
          row.frame = side.frame;
          row.x0 = f.x0;
          row.x1 = f.x1;
          row.y0 = side.y0;
          row.y1 = side.y1;
          row.facing = side.facing;
          row.hallway = side.hallway;
          row.id_prefix = side.name + std::to_string(part++);
          row.windows = win;
          row.far_side_is_facade = f.x0 >= side.facade_x0 - 1e-6 && f.x1 <= side.facade_x1 + 1e-6;
          fill_row(L, row, fill, rng);
        }
      }
    }
  }
  restore_blocked_cuts(L, hall_cuts);
  return L.assemble("campus spine (seed " + std::to_string(seed) + ")");
}

}  // namespace

GeneratedBuilding generate_campus(std::uint64_t seed, const CampusParams& p) {
  if (p.layout == CampusLayout::kSpine) return generate_campus_spine(seed, p);
  Rng rng(mix_seed(seed, 0xCA3905ULL));
  const BuildingStyle& st = p.style;
  Layout L(st);
  const Frame F;  // the campus is axis aligned

  const double rd = snap(rng.uniform(p.room_depth_min_m, p.room_depth_max_m), 0.1);
  const double cw = snap(rng.uniform(p.hallway_width_min_m, p.hallway_width_max_m), 0.1);
  const double module = snap(rng.uniform(p.module_width_min_m, p.module_width_max_m), 0.05);
  const double target_m2 = rng.uniform(p.target_area_min_m2, p.target_area_max_m2);
  // Depth of each row (S, I1b, I1t, I2b, I2t, N): one for all, or one per row.
  std::array<double, kStripCount> d{};
  for (double& x : d) x = p.depth_per_row ? snap(rng.uniform(p.room_depth_min_m, p.room_depth_max_m), 0.1) : rd;

  // Free floor area is ~0.84 of the gross block area (walls, furniture) with rows of module rooms,
  // ~0.80 with the calibrated rooms and halls (seating rows; measured on seeds 1-4).
  const double kFreeShare = p.variety.enabled ? 0.80 : 0.84;
  const double depth = d[0] + d[1] + d[2] + d[3] + d[4] + d[5] + 3.0 * cw;
  const double length_goal = target_m2 / kFreeShare / depth;
  const int nseg = std::max(
      2, static_cast<int>(std::lround((length_goal - 2.0 * rd - cw) / (p.segment_length_m + cw))));
  const double seg = snap((length_goal - 2.0 * rd - (nseg + 1) * cw) / nseg, 0.1);
  std::vector<double> vx(static_cast<std::size_t>(nseg + 1));  // west x of cross hallway k
  for (int k = 0; k <= nseg; ++k) vx[static_cast<std::size_t>(k)] = rd + k * (cw + seg);
  const double Lx = vx.back() + cw + rd;

  // y bands.
  const std::array<double, 3> yh = {d[0], d[0] + d[1] + d[2] + cw,
                                    d[0] + d[1] + d[2] + d[3] + d[4] + 2.0 * cw};  // south edge of H0..H2
  const double ytop = yh[2] + cw + d[5];
  // Strip extents (y0, y1, facing, hallway index).
  struct StripGeom {
    double y0, y1;
    int facing, hall;
    bool outer;
    const char* name;
  };
  const std::array<StripGeom, kStripCount> strips = {{
      {0.0, yh[0], +1, 0, true, "S"},
      {yh[0] + cw, yh[0] + cw + d[1], -1, 0, false, "I1b"},
      {yh[0] + cw + d[1], yh[1], +1, 1, false, "I1t"},
      {yh[1] + cw, yh[1] + cw + d[3], -1, 1, false, "I2b"},
      {yh[1] + cw + d[3], yh[2], +1, 2, false, "I2t"},
      {yh[2] + cw, ytop, -1, 2, true, "N"},
  }};

  const WindowSpec win = standard_windows(st);
  const double dd = st.double_door_width_m, sd = st.door_width_m;

  // Hallways: three long east-west ones.
  std::array<int, 3> H{};
  for (int k = 0; k < 3; ++k) {
    const double y0 = yh[static_cast<std::size_t>(k)];
    H[static_cast<std::size_t>(k)] =
        L.add_rect("H" + std::to_string(k), "hallway", F, 0.0, y0, Lx, y0 + cw, hallway_end_windows(st));
    if (k != 1) {  // exits at both ends of the outer hallways
      L.add_door(H[static_cast<std::size_t>(k)], kOutside, dd, true, F.to_world(0.0, y0 + 0.5 * cw));
      L.add_door(H[static_cast<std::size_t>(k)], kOutside, dd, true, F.to_world(Lx, y0 + 0.5 * cw));
    }
  }

  // Which cross hallways cross which inner block (0: between H0 and H1, 1: between H1 and H2);
  // every block keeps at least one crossing, so the three long hallways stay connected.
  std::vector<std::array<bool, 2>> crosses(static_cast<std::size_t>(nseg + 1), {true, true});
  if (p.inner_crossing_probability < 1.0) {
    for (int b = 0; b < 2; ++b) {
      const int keep = rng.integer(0, nseg);
      for (int k = 0; k <= nseg; ++k) {
        crosses[static_cast<std::size_t>(k)][static_cast<std::size_t>(b)] =
            rng.bernoulli(p.inner_crossing_probability) || k == keep;
      }
    }
  }
  auto crossed = [&crosses](int k, int block) {
    return crosses[static_cast<std::size_t>(k)][static_cast<std::size_t>(block)];
  };

  // Cross hallways.
  for (int k = 0; k <= nseg; ++k) {
    const double x0 = vx[static_cast<std::size_t>(k)], x1 = x0 + cw;
    const std::string v = "V" + std::to_string(k);
    if (crossed(k, 0)) L.add_rect(v + ".I1", "hallway", F, x0, yh[0] + cw, x1, yh[1], no_windows());
    if (crossed(k, 1)) L.add_rect(v + ".I2", "hallway", F, x0, yh[1] + cw, x1, yh[2], no_windows());
    for (int side = 0; side < 2; ++side) {
      const double y0 = side == 0 ? 0.0 : yh[2] + cw, y1 = side == 0 ? yh[0] : ytop;
      const int hall = H[side == 0 ? 0 : 2];
      const int facing = side == 0 ? +1 : -1;
      const std::string id = v + (side == 0 ? ".S" : ".N");
      if (rng.bernoulli(p.cross_hallway_exit_probability)) {
        const int stub = L.add_rect(id, "hallway", F, x0, y0, x1, y1, no_windows());
        L.add_door(stub, kOutside, dd, true, F.to_world(0.5 * (x0 + x1), side == 0 ? 0.0 : ytop));
      } else {
        const int stair = L.add_rect(id, "stairwell", F, x0, y0, x1, y1, win);
        L.add_door(stair, hall, sd, true, F.to_world(0.5 * (x0 + x1), facing > 0 ? y1 : y0));
        if (st.furniture) add_stairs(L, id, F, x0, y0, x1, y1);
      }
    }
  }

  // End rooms (west and east of V0 / V_n): one per strip, facing its hallway.
  for (int e = 0; e < 2; ++e) {
    const double x0 = e == 0 ? 0.0 : Lx - rd, x1 = e == 0 ? rd : Lx;
    for (int s = 0; s < kStripCount; ++s) {
      const StripGeom& g = strips[static_cast<std::size_t>(s)];
      const std::string id = std::string(e == 0 ? "west." : "east.") + g.name;
      const std::string kind = rng.bernoulli(0.5) ? "classroom" : "lab";
      const double door_x = e == 0 ? x1 - 1.5 : x0 + 1.5;
      add_facing_room(L, id, kind, F, x0, g.y0, x1, g.y1, g.facing, H[static_cast<std::size_t>(g.hall)], win, door_x,
                      sd, rng.bernoulli(st.room_door_closed_probability), rng);
    }
  }

  // Segments: reservations for special rooms, then rows.
  const double min_gap = 2.0 * st.door_jamb_m + sd + 0.6;
  std::vector<std::array<StripReservations, kStripCount>> res;
  for (int j = 0; j < nseg; ++j) {
    const double xa = vx[static_cast<std::size_t>(j)] + cw, xb = vx[static_cast<std::size_t>(j + 1)];
    // Inner strips take the place of a cross hallway that does not cross their block: the first
    // segment from the west end, every segment up to the next segment's start.
    auto inner = [&](int block) {
      const double a = (j == 0 && !crossed(0, block)) ? vx[0] : xa;
      const double b = crossed(j + 1, block) ? xb : xb + cw;
      return StripReservations(a, b, min_gap);
    };
    res.push_back({StripReservations(xa, xb, min_gap), inner(0), inner(0), inner(1), inner(1),
                   StripReservations(xa, xb, min_gap)});
  }
  auto strip_res = [&res](int j, int s) -> StripReservations& {
    return res[static_cast<std::size_t>(j)][static_cast<std::size_t>(s)];
  };

  const int jm = nseg / 2;
  const double xc = snap(0.5 * (strip_res(jm, kS).x0() + strip_res(jm, kS).x1()), 0.1);

  // Lobby (south row, glass facade, open onto H0) with the atrium behind it across H0.
  {
    const double ll = snap(rng.uniform(p.lobby_length_min_m, p.lobby_length_max_m), 0.1);
    const double x0 = xc - 0.5 * ll, x1 = xc + 0.5 * ll;
    strip_res(jm, kS).reserve(x0, x1);
    const double sd0 = d[kS];  // lobby depth: the south row's
    const int lobby = L.add_rect("lobby", "lobby", F, x0, 0.0, x1, sd0, no_windows());
    L.set_open(lobby, H[0]);
    L.set_glass(lobby, kOutside, 0.0, std::nullopt, Vec2(0.0, -1.0));
    L.add_door(lobby, kOutside, dd, true, F.to_world(xc - 0.25 * ll, 0.0));
    L.add_door(lobby, kOutside, dd, rng.bernoulli(0.5), F.to_world(xc + 0.25 * ll, 0.0));
    if (st.furniture) {
      L.add_obstacle("lobby_reception", ObstacleKind::kBox, F.to_world(x0 + 2.5, 0.6 * sd0), Vec2(3.0, 0.8), 0.0, 1.1);
      for (int k = -1; k <= 1; k += 2) {
        L.add_obstacle("lobby_pillar", ObstacleKind::kPillar, F.to_world(xc + k * 0.25 * ll, 0.55 * sd0),
                       Vec2(0.6, 0.6), 0.0, 3.5);
      }
    }

    const double la = snap(rng.uniform(p.atrium_length_min_m, p.atrium_length_max_m), 0.1);
    const double a0 = xc - 0.5 * la, a1 = xc + 0.5 * la;
    strip_res(jm, kI1b).reserve(a0, a1);
    strip_res(jm, kI1t).reserve(a0, a1);
    const double ay0 = yh[0] + cw, ay1 = yh[1];
    const int atrium = L.add_rect("atrium", "atrium", F, a0, ay0, a1, ay1, no_windows());
    L.set_glass(atrium, H[0]);
    L.set_glass(atrium, H[1]);
    L.add_door(atrium, H[0], dd, false, F.to_world(xc - 0.25 * la, ay0));
    L.add_door(atrium, H[0], dd, false, F.to_world(xc + 0.25 * la, ay0));
    L.add_door(atrium, H[1], dd, rng.bernoulli(0.5), F.to_world(xc, ay1));
    if (st.furniture) {
      const int cols = std::max(2, static_cast<int>(std::floor(la / 7.0)));
      for (int c = 1; c < cols; ++c) {
        for (int r = 1; r <= 2; ++r) {
          L.add_obstacle("atrium_pillar", ObstacleKind::kPillar,
                         F.to_world(a0 + c * la / cols, ay0 + r * (ay1 - ay0) / 3.0), Vec2(0.5, 0.5), 0.0, 4.0);
        }
      }
      L.add_obstacle("atrium_bench", ObstacleKind::kBox, F.to_world(xc, 0.5 * (ay0 + ay1)), Vec2(4.0, 0.5), 0.0, 0.45);
    }

    // Cafeteria in the north row of the middle segment.
    const double lc = snap(rng.uniform(16.0, 22.0), 0.1);
    const double c0 = xc - 0.5 * lc, c1 = xc + 0.5 * lc;
    if (strip_res(jm, kN).reserve(c0, c1)) {
      const double cy0 = yh[2] + cw;
      const int caf = L.add_rect("cafeteria", "cafeteria", F, c0, cy0, c1, ytop, win);
      L.add_door(caf, H[2], dd, false, F.to_world(c0 + 0.25 * lc, cy0));
      L.add_door(caf, H[2], dd, rng.bernoulli(0.5), F.to_world(c1 - 0.25 * lc, cy0));
      if (st.furniture) furnish_room(L, "cafeteria", "cafeteria", F, c0, cy0, c1, ytop, -1, rng);
    }
  }

  // Lecture halls: full inner-block depth, at one end of a segment, lectern against the cross
  // hallway, doors to both hallways at the back.
  {
    struct Slot {
      int j, block;  // block 0: inner block 1, 1: inner block 2
    };
    std::vector<Slot> slots;
    for (int j = 0; j < nseg; ++j) {
      for (int b = 0; b < 2; ++b) {
        if (j == jm && b == 0) continue;  // atrium
        slots.push_back({j, b});
      }
    }
    for (std::size_t i = slots.size(); i > 1; --i) {  // Fisher-Yates with our own generator
      const int k = rng.integer(0, static_cast<int>(i) - 1);
      std::swap(slots[i - 1], slots[static_cast<std::size_t>(k)]);
    }
    const int count = p.great_halls + rng.integer(p.lecture_halls_min, p.lecture_halls_max);
    int placed = 0;
    // First pass: one hall per slot at a random end; second pass (only while halls are missing):
    // both ends of every slot.
    for (int pass = 0; pass < 2 && placed < count; ++pass) {
      for (const Slot& slot : slots) {
        for (int end = 0; end < (pass == 0 ? 1 : 2) && placed < count; ++end) {
          const int sb = slot.block == 0 ? kI1b : kI2b, stp = sb + 1;
          StripReservations& rb = strip_res(slot.j, sb);
          StripReservations& rt = strip_res(slot.j, stp);
          // Great halls first (first pass only: one that fits nowhere is left out).
          const bool great = pass == 0 && placed < p.great_halls;
          const double block_depth =
              strips[static_cast<std::size_t>(stp)].y1 - strips[static_cast<std::size_t>(sb)].y0;
          const double lh =
              great ? snap(rng.uniform(p.great_hall_area_min_m2, p.great_hall_area_max_m2) / block_depth, 0.1)
                    : snap(rng.uniform(p.lecture_hall_length_min_m, p.lecture_hall_length_max_m), 0.1);
          const bool at_start = pass == 0 ? rng.bernoulli(0.5) : end == 0;
          const double x0 = at_start ? rb.x0() : rb.x1() - lh, x1 = x0 + lh;
          if (!rb.fits(x0, x1) || !rt.fits(x0, x1)) continue;
          rb.reserve(x0, x1);
          rt.reserve(x0, x1);
          ++placed;
          const double y0 = strips[static_cast<std::size_t>(sb)].y0, y1 = strips[static_cast<std::size_t>(stp)].y1;
          const std::string id = great ? "great_hall" + std::to_string(placed) : "lecture" + std::to_string(placed);
          const int hall = L.add_rect(id, "lecture_hall", F, x0, y0, x1, y1, no_windows());
          const int hall_lo = H[static_cast<std::size_t>(strips[static_cast<std::size_t>(sb)].hall)];
          const int hall_hi = H[static_cast<std::size_t>(strips[static_cast<std::size_t>(stp)].hall)];
          const double front = at_start ? x0 : x1, dir = at_start ? 1.0 : -1.0;  // lectern at `front`
          L.add_door(hall, hall_lo, dd, false, F.to_world(front + dir * 0.75 * lh, y0));
          L.add_door(hall, hall_hi, dd, rng.bernoulli(0.5), F.to_world(front + dir * 0.75 * lh, y1));
          L.add_door(hall, hall_lo, sd, true, F.to_world(front + dir * 1.6, y0));
          if (st.furniture) furnish_hall(L, id, F, front, dir, lh, y0, y1);
        }
      }
    }
  }

  // Cores: stairwell, elevator, two toilets at one end of an inner strip of every segment.
  for (int j = 0; j < nseg; ++j) {
    const double core_len = kCoreLength;
    bool done = false;
    const int first = rng.integer(0, 3);
    for (int t = 0; t < 8 && !done; ++t) {
      const int s = kI1b + (first + t % 4) % 4;
      const bool at_start = (t / 4 == 0) == ((j % 2) == 0);
      StripReservations& r = strip_res(j, s);
      const double x0 = at_start ? r.x0() : r.x1() - core_len;
      if (!r.reserve(x0, x0 + core_len)) continue;
      done = true;
      const StripGeom& g = strips[static_cast<std::size_t>(s)];
      add_core(L, seg_name(j) + ".core", F, x0, at_start, g.y0, g.y1, g.facing, H[static_cast<std::size_t>(g.hall)],
               no_windows(), rng);
    }
  }

  // Lounge niches: open to their hallway, a widening with sofas.
  for (int j = 0; j < nseg; ++j) {
    if (!rng.bernoulli(p.lounge_probability)) continue;
    const int s = kI1b + rng.integer(0, 3);
    StripReservations& r = strip_res(j, s);
    const double len = 2.0 * module;
    for (const Interval1& f : r.free_intervals()) {
      if (f.x1 - f.x0 < len) continue;
      double x0 = f.x0;
      if (!r.reserve(x0, x0 + len)) {
        x0 = f.x1 - len;
        if (!r.reserve(x0, x0 + len)) continue;
      }
      const StripGeom& g = strips[static_cast<std::size_t>(s)];
      const std::string id = seg_name(j) + ".lounge";
      const int lounge = L.add_rect(id, "lounge", F, x0, g.y0, x0 + len, g.y1, no_windows());
      L.set_open(lounge, H[static_cast<std::size_t>(g.hall)]);
      if (st.furniture) furnish_room(L, id, "lounge", F, x0, g.y0, x0 + len, g.y1, g.facing, rng);
      break;
    }
  }

  // Rows of module rooms in what is left.
  const RowFill fill = campus_row_fill(module, p.variety);
  for (int j = 0; j < nseg; ++j) {
    for (int s = 0; s < kStripCount; ++s) {
      const StripGeom& g = strips[static_cast<std::size_t>(s)];
      int part = 0;
      for (const Interval1& f : strip_res(j, s).free_intervals()) {
        RowStrip row;
        row.frame = F;
        row.x0 = f.x0;
        row.x1 = f.x1;
        row.y0 = g.y0;
        row.y1 = g.y1;
        row.facing = g.facing;
        row.hallway = H[static_cast<std::size_t>(g.hall)];
        row.id_prefix = seg_name(j) + "." + g.name + (part > 0 ? std::string(1, static_cast<char>('a' + part)) : "");
        row.windows = g.outer ? win : no_windows();
        fill_row(L, row, fill, rng);
        ++part;
      }
    }
  }

  return L.assemble(std::string(p.variety.enabled ? "campus calibrated" : "campus") + " (seed " +
                    std::to_string(seed) + ")");
}

}  // namespace floorcast
