// Office archetype: an L-shaped slab of two double-loaded corridor wings.
//
//   y
//   ^   wing B (runs north): west row | corridor B | east row
//   |
//   +--------+---------------------------------------------------+
//   | SW     |J| wing A (runs east): north row / corridor A / south row
//   +--------+---------------------------------------------------+
//            ^ entrance vestibule (glass facade) south of the junction J
//
// Corner square [0, D]^2 with D = 2 rd + cw: junction J = [rd, rd+cw]^2, the vestibule south of
// it, a corner office west of the vestibule. Each wing: rows of identical offices, glass-walled
// meeting rooms, a core (stairwell, elevator, toilets) mid-wing, a stairwell and an exit at the
// far end, a lounge niche, and a fire partition with double doors across the corridor.
#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "generate_layout.hpp"

namespace floorcast {

using namespace generate_detail;

GeneratedBuilding generate_office(std::uint64_t seed, const OfficeParams& p) {
  Rng rng(mix_seed(seed, 0x0FF1CEULL));
  const BuildingStyle& st = p.style;
  Layout L(st);

  const double rd = snap(rng.uniform(p.room_depth_min_m, p.room_depth_max_m), 0.1);
  const double cw = snap(rng.uniform(p.corridor_width_min_m, p.corridor_width_max_m), 0.1);
  const double module = snap(rng.uniform(p.module_width_min_m, p.module_width_max_m), 0.05);
  const double target_m2 = rng.uniform(p.target_area_min_m2, p.target_area_max_m2);
  const double share_b = rng.uniform(p.second_wing_share_min, p.second_wing_share_max);

  constexpr double kFreeShare = 0.85;  // free floor area / gross area
  const double D = 2.0 * rd + cw;
  const double wings = (target_m2 / kFreeShare - D * D) / D;
  const double LB = snap(share_b * wings, 0.1);
  const double LA = snap(wings - LB, 0.1);

  const WindowSpec win = standard_windows(st);
  const double sd = st.door_width_m;
  const double fire_door = std::min(st.double_door_width_m, cw - 2.0 * st.door_jamb_m - 0.05);
  const double exit_door = fire_door >= 1.5 ? fire_door : 1.0;

  // Frames: wing A runs along +x (identity); wing B along +y (local x = world y, local y = -world x).
  const Frame FA;
  const Frame FB = rotated_frame(Vec2::Zero(), 90);

  // Circulation.
  const int junction = L.add_rect("junction", "hallway", FA, rd, rd, rd + cw, rd + cw, no_windows());
  const bool varied = p.variety.enabled;
  const bool irregular = varied && p.variety.irregular_cores;
  // Fire partition across corridor A: mid-wing (repetitive) or anywhere in its middle half.
  const double xfA = snap(D + (irregular ? rng.uniform(0.3, 0.7) : 0.5) * LA, 0.1);
  const int corrA1 = L.add_rect("corridorA1", "hallway", FA, rd + cw, rd, xfA, rd + cw, no_windows());
  const int corrA2 = L.add_rect("corridorA2", "hallway", FA, xfA, rd, D + LA, rd + cw, hallway_end_windows(st));
  L.set_solid(corrA1, corrA2);
  L.add_door(corrA1, corrA2, fire_door, rng.bernoulli(0.3), FA.to_world(xfA, rd + 0.5 * cw));
  L.add_door(corrA2, kOutside, exit_door, true, FA.to_world(D + LA, rd + 0.5 * cw));

  // Wing B corridor in its local frame: x in [rd+cw, D+LB], y in [-(rd+cw), -rd].
  const bool fire_b = LB > 35.0;
  const double xfB = snap(D + (irregular ? rng.uniform(0.3, 0.7) : 0.5) * LB, 0.1);
  const int corrB1 = L.add_rect("corridorB1", "hallway", FB, rd + cw, -(rd + cw), fire_b ? xfB : D + LB, -rd,
                                fire_b ? no_windows() : hallway_end_windows(st));
  int corrB2 = corrB1;
  if (fire_b) {
    corrB2 = L.add_rect("corridorB2", "hallway", FB, xfB, -(rd + cw), D + LB, -rd, hallway_end_windows(st));
    L.set_solid(corrB1, corrB2);
    L.add_door(corrB1, corrB2, fire_door, rng.bernoulli(0.3), FB.to_world(xfB, -rd - 0.5 * cw));
  }
  L.add_door(corrB2, kOutside, exit_door, true, FB.to_world(D + LB, -rd - 0.5 * cw));

  // Entrance vestibule south of the junction with a glass facade, and the corner office.
  const int vest = L.add_rect("vestibule", "vestibule", FA, rd, 0.0, rd + cw, rd, no_windows());
  L.set_open(vest, junction);
  L.set_glass(vest, kOutside, 0.0, std::nullopt, Vec2(0.0, -1.0));
  L.add_door(vest, kOutside, std::min(exit_door, cw - 2.0 * st.door_jamb_m - 0.05), true,
             FA.to_world(rd + 0.5 * cw, 0.0));
  {
    const int reception = L.add_rect("reception", "office", FA, 0.0, 0.0, rd, rd + cw, win);
    L.add_door(reception, vest, sd, false, FA.to_world(rd, 0.6 * rd));
    if (st.furniture) {
      L.add_obstacle("reception_desk", ObstacleKind::kBox, FA.to_world(0.5 * rd, 0.5 * rd), Vec2(2.4, 0.8), 0.0, 1.05);
      L.add_obstacle("reception_cabinet", ObstacleKind::kBox, FA.to_world(0.45, rd), Vec2(0.45, 1.6), 0.0, 1.9);
    }
  }

  // Strips (local frames): wing A south/north rows, wing B west/east rows.
  struct StripDef {
    const Frame* frame;
    double x0, x1, y0, y1;
    int facing;
    std::vector<std::pair<double, int>> halls;
    std::string name;
  };
  std::vector<StripDef> defs = {
      {&FA, rd + cw, D + LA, 0.0, rd, +1, {{rd + cw, corrA1}, {xfA, corrA2}}, "A.S"},
      {&FA, D, D + LA, rd + cw, D, -1, {{D, corrA1}, {xfA, corrA2}}, "A.N"},
      {&FB, rd + cw, D + LB, -rd, 0.0, -1, {{rd + cw, corrB1}, {xfB, corrB2}}, "B.W"},
      {&FB, rd + cw, D + LB, -D, -(rd + cw), +1, {{rd + cw, corrB1}, {xfB, corrB2}}, "B.E"},
  };
  if (!fire_b) {
    defs[2].halls.resize(1);
    defs[3].halls.resize(1);
  }
  const double min_gap = 2.0 * st.door_jamb_m + sd + 0.6;
  std::vector<StripReservations> res;
  for (const StripDef& d : defs) {
    res.emplace_back(d.x0, d.x1, min_gap);
    for (std::size_t k = 1; k < d.halls.size(); ++k) res.back().cut(d.halls[k].first);  // fire partitions
  }
  auto hall_at = [](const StripDef& d, double x) {
    std::size_t k = 0;
    while (k + 1 < d.halls.size() && d.halls[k + 1].first <= x) ++k;
    return d.halls[k].second;
  };
  auto special = [&](int strip, double x0, double x1, const std::string& id, const std::string& kind,
                     double door_w, bool closed, const WindowSpec& ws) {
    const StripDef& d = defs[static_cast<std::size_t>(strip)];
    const double xm = 0.5 * (x0 + x1);
    return add_facing_room(L, id, kind, *d.frame, x0, d.y0, x1, d.y1, d.facing, hall_at(d, xm), ws, xm, door_w, closed,
                           rng);
  };

  // End stairwells: south row of wing A, east row of wing B.
  for (int strip : {0, 3}) {
    const StripDef& d = defs[static_cast<std::size_t>(strip)];
    const double w = 3.6;
    res[static_cast<std::size_t>(strip)].reserve(d.x1 - w, d.x1);
    const std::string id = std::string(strip == 0 ? "A" : "B") + ".stair_end";
    special(strip, d.x1 - w, d.x1, id, "stairwell", sd, true, win);
    if (st.furniture) add_stairs(L, id, *d.frame, d.x1 - w, d.y0, d.x1, d.y1);
  }

  // Cores: wing A north row (stair, elevator, 2 toilets) next to the fire partition; wing B west
  // row (2 toilets, a tea kitchen).
  {
    const StripDef& d = defs[1];
    std::array<double, 4> widths = {3.6, 2.4, 2.8, 2.8};
    double x0 = xfA;
    if (irregular) {  // anywhere along the row that is free
      const double span = 3.6 + 2.4 + 2.8 + 2.8;
      const double cand = snap(rng.uniform(d.x0 + 3.0 * module, d.x1 - span - 4.0), 0.1);
      if (res[1].fits(cand, cand + span)) x0 = cand;
    }
    std::array<const char*, 4> kinds = {"stairwell", "elevator", "toilet", "toilet"};
    std::array<const char*, 4> names = {"A.core.stair", "A.core.lift", "A.core.wc1", "A.core.wc2"};
    double total = 0.0;
    for (double w : widths) total += w;
    if (res[1].reserve(x0, x0 + total)) {
      double x = x0;
      for (int k = 0; k < 4; ++k) {
        const double w = widths[static_cast<std::size_t>(k)];
        const std::string kind = kinds[static_cast<std::size_t>(k)];
        const bool closed = kind == "toilet" ? rng.bernoulli(0.7) : true;
        special(1, x, x + w, names[static_cast<std::size_t>(k)], kind, kind == "elevator" ? 1.0 : sd, closed, win);
        if (kind == "stairwell" && st.furniture) add_stairs(L, names[0], *d.frame, x, d.y0, x + w, d.y1);
        x += w;
      }
    }
  }
  {
    const StripDef& d = defs[2];
    double x0 = snap(0.5 * (d.x0 + d.x1), 0.1);
    if (irregular) {
      const double cand = snap(rng.uniform(d.x0 + 1.0, d.x1 - 9.2 - 4.0), 0.1);
      if (res[2].fits(cand, cand + 9.2)) x0 = cand;
    }
    std::array<double, 3> widths = {2.8, 2.8, 3.6};
    std::array<const char*, 3> kinds = {"toilet", "toilet", "kitchen"};
    std::array<const char*, 3> names = {"B.core.wc1", "B.core.wc2", "B.core.kitchen"};
    if (res[2].reserve(x0, x0 + widths[0] + widths[1] + widths[2])) {
      double x = x0;
      for (int k = 0; k < 3; ++k) {
        const double w = widths[static_cast<std::size_t>(k)];
        const std::string kind = kinds[static_cast<std::size_t>(k)];
        special(2, x, x + w, names[static_cast<std::size_t>(k)], kind, sd, kind == "toilet" && rng.bernoulli(0.7), win);
        x += w;
      }
    }
  }

  // A conference room at the inner corner of wing A's north row (glass wall to the corridor).
  {
    const StripDef& d = defs[1];
    const double w = 3.0 * module;
    if (res[1].reserve(d.x0, d.x0 + w)) {
      const int conf = special(1, d.x0, d.x0 + w, "A.conference", "meeting", sd, false, win);
      L.set_glass(conf, corrA1);
    }
  }

  // Lounge niches open to the corridor, one per wing with some probability.
  for (int strip : {0, 3}) {
    if (!rng.bernoulli(p.lounge_probability)) continue;
    const StripDef& d = defs[static_cast<std::size_t>(strip)];
    StripReservations& r = res[static_cast<std::size_t>(strip)];
    const double len = 2.0 * module;
    double x0 = snap(d.x0 + rng.uniform(0.2, 0.6) * (d.x1 - d.x0), module);
    // Never across a fire partition (the niche would bypass its doors).
    for (const auto& piece : d.halls) {
      if (piece.first > x0 && piece.first < x0 + len) x0 = piece.first;
    }
    if (!r.reserve(x0, x0 + len)) continue;
    const std::string id = std::string(strip == 0 ? "A" : "B") + ".lounge";
    const int lounge = L.add_rect(id, "lounge", *d.frame, x0, d.y0, x0 + len, d.y1, win);
    L.set_open(lounge, hall_at(d, x0 + 0.5 * len));
    if (st.furniture) furnish_room(L, id, "lounge", *d.frame, x0, d.y0, x0 + len, d.y1, d.facing, rng);
  }

  // Rows of offices.
  RowFill fill;
  fill.module_m = module;
  fill.p_double = p.meeting_room_probability;
  fill.p_triple = 0.03;
  fill.kind_single = "office";
  fill.kind_double = "office";
  fill.kind_triple = "meeting";
  fill.glass_double_probability = 0.8;
  fill.variety = &p.variety;
  for (std::size_t s = 0; s < defs.size(); ++s) {
    const StripDef& d = defs[s];
    int part = 0;
    for (const Interval1& f : res[s].free_intervals()) {
      RowStrip row;
      row.frame = *d.frame;
      row.x0 = f.x0;
      row.x1 = f.x1;
      row.y0 = d.y0;
      row.y1 = d.y1;
      row.facing = d.facing;
      row.hallway = d.halls.front().second;
      row.hallway_pieces = d.halls;
      row.id_prefix = d.name + (part > 0 ? std::string(1, static_cast<char>('a' + part)) : "");
      row.windows = win;
      row.far_side_is_facade = true;
      if (s == 3) row.facade_from_x = D;  // wing B's east row backs onto wing A's north row up to D
      fill_row(L, row, fill, rng);
      ++part;
    }
  }

  return L.assemble(std::string(varied ? "office calibrated" : "office") + " (seed " + std::to_string(seed) + ")");
}

}  // namespace floorcast
