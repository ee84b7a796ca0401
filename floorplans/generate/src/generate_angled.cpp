// Angled archetype: a non-Manhattan building. A convex, irregular lobby hub whose edges carry
// double-loaded corridor wings in several directions (default 180, 30 and -45 degrees), joined
// by facade edges (the widest one a glass entrance facade). Each wing: rows of identical offices
// and glass meeting rooms facing its corridor, which opens into the hub; a stairwell and an exit
// at the far end; a core in the longest wing.
//
// Wing i has its own frame: origin on the hub edge, local x along the wing direction u_i, local y
// across it. Rotations use exact constants (multiples of 15 degrees), so the geometry is
// bit-for-bit reproducible.
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "generate_layout.hpp"

namespace floorcast {

using namespace generate_detail;

GeneratedBuilding generate_angled(std::uint64_t seed, const AngledParams& p) {
  Rng rng(mix_seed(seed, 0xA4C1EDULL));
  const BuildingStyle& st = p.style;
  Layout L(st);
  if (p.wing_directions_deg.size() < 2) throw std::logic_error("angled: need at least two wings");

  const double rd = snap(rng.uniform(p.room_depth_min_m, p.room_depth_max_m), 0.1);
  const double cw = snap(rng.uniform(p.corridor_width_min_m, p.corridor_width_max_m), 0.1);
  const double module = snap(rng.uniform(p.module_width_min_m, p.module_width_max_m), 0.05);
  const double D = 2.0 * rd + cw;
  const WindowSpec win = standard_windows(st);
  const double sd = st.door_width_m;

  // Wings sorted counter-clockwise by direction.
  std::vector<int> dirs;
  for (int d : p.wing_directions_deg) dirs.push_back(((d % 360) + 360) % 360);
  std::sort(dirs.begin(), dirs.end());
  const std::size_t n = dirs.size();
  std::vector<Frame> unit;  // rotation only
  for (int d : dirs) unit.push_back(rotated_frame(Vec2::Zero(), d));

  // Hub radius: every facade edge between two wings keeps at least `facade_min` metres.
  // Edge lines at distance R with normals u_i, u_j meet R*tan(g/2) from each foot; tan(g/2) =
  // (1 - cos g) / sin g from the exact unit vectors.
  const double facade_min = p.hub_facade_min_m;
  double R = 0.5 * D + 2.0;
  for (std::size_t i = 0; i < n; ++i) {
    const Frame& a = unit[i];
    const Frame& b = unit[(i + 1) % n];
    const double cos_g = a.c * b.c + a.s * b.s;
    const double sin_g = a.c * b.s - a.s * b.c;
    if (sin_g < 0.45) throw std::logic_error("angled: consecutive wing directions must be 30..150 degrees apart");
    const double tan_half = (1.0 - cos_g) / sin_g;
    R = std::max(R, (0.5 * D + facade_min) / tan_half);
  }
  R = std::ceil(R * 10.0) / 10.0;

  // Wing frames and the hub polygon (corners computed through the wing frames so they match the
  // wings' rooms bit for bit).
  std::vector<Frame> frames;
  std::vector<Vec2> hub_poly;
  for (std::size_t i = 0; i < n; ++i) {
    const Frame& u = unit[i];
    frames.push_back(rotated_frame(Vec2(R * u.c, R * u.s), dirs[i]));
    hub_poly.push_back(frames.back().to_world(0.0, -0.5 * D));
    hub_poly.push_back(frames.back().to_world(0.0, 0.5 * D));
  }
  const int hub = L.add_room("lobby", "lobby", hub_poly, win);
  // The longest facade edge becomes a glass entrance facade.
  std::size_t entrance = 0;
  double best_len = -1.0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 a = hub_poly[2 * i + 1], b = hub_poly[(2 * i + 2) % hub_poly.size()];
    if ((b - a).norm() > best_len) {
      best_len = (b - a).norm();
      entrance = i;
    }
  }
  {
    const Vec2 a = hub_poly[2 * entrance + 1], b = hub_poly[(2 * entrance + 2) % hub_poly.size()];
    const Vec2 e = (b - a).normalized();
    const Vec2 outward(e.y(), -e.x());
    L.set_glass(hub, kOutside, 0.0, std::nullopt, outward);
    const double dd = std::min(st.double_door_width_m, 0.5 * (b - a).norm() - 0.6);
    L.add_door(hub, kOutside, dd, true, a + 0.35 * (b - a));
    L.add_door(hub, kOutside, dd, rng.bernoulli(0.5), a + 0.65 * (b - a));
    if (st.furniture) {
      // Pillars and a reception desk in the lobby, placed around the hub centre.
      for (std::size_t i = 0; i < n; ++i) {
        const Frame& u = unit[i];
        const double pr = (p.variety.enabled ? 0.62 : 0.45) * R;
        L.add_obstacle("lobby_pillar", ObstacleKind::kPillar, Vec2(pr * u.c, pr * u.s), Vec2(0.6, 0.6), 0.0,
                       4.0);
      }
      const Vec2 m = 0.5 * (a + b);
      L.add_obstacle("lobby_reception", ObstacleKind::kBox, 0.55 * m, Vec2(0.8, 3.2), frames[entrance].yaw_rad, 1.1);
    }
    if (p.variety.enabled && p.variety.irregular_cores) {
      // A stair core standing in the lobby, open towards one wing (a U of solid walls), set off
      // the hub centre away from the entrance: the lobby is no longer an empty convex hall.
      const Vec2 a = hub_poly[2 * entrance + 1], b = hub_poly[(2 * entrance + 2) % hub_poly.size()];
      const Vec2 to_entrance = (0.5 * (a + b)).normalized();
      const Vec2 c = snap(-0.1 * R, 0.1) * to_entrance;
      const Frame cf = rotated_frame(Vec2(snap(c.x(), 0.1), snap(c.y(), 0.1)), dirs[static_cast<std::size_t>(
                                                                                  rng.integer(0, static_cast<int>(n) - 1))]);
      const double hw = 0.5 * snap(rng.uniform(5.0, 8.0), 0.1), hd = 0.5 * snap(rng.uniform(4.0, 6.0), 0.1);
      const int open_side = rng.integer(0, 3);  // which side of the rectangle stays open
      const std::array<std::array<Vec2, 2>, 4> sides = {{{Vec2(-hw, -hd), Vec2(hw, -hd)},
                                                         {Vec2(hw, -hd), Vec2(hw, hd)},
                                                         {Vec2(hw, hd), Vec2(-hw, hd)},
                                                         {Vec2(-hw, hd), Vec2(-hw, -hd)}}};
      for (int k = 0; k < 4; ++k) {
        if (k == open_side) continue;
        Wall w;
        w.a_m = cf.to_world(sides[static_cast<std::size_t>(k)][0].x(), sides[static_cast<std::size_t>(k)][0].y());
        w.b_m = cf.to_world(sides[static_cast<std::size_t>(k)][1].x(), sides[static_cast<std::size_t>(k)][1].y());
        w.thickness_m = st.corridor_wall_thickness_m;
        L.add_free_wall("core", w);
      }
      if (st.furniture) add_stairs(L, "lobby_core", cf, -hw + 0.2, -hd + 0.2, hw - 0.2, hd - 0.2);
    }
  }

  // Wings.
  std::size_t longest = 0;
  std::vector<double> lengths;
  for (std::size_t i = 0; i < n; ++i) {
    lengths.push_back(snap(rng.uniform(p.wing_length_min_m, p.wing_length_max_m), 0.1));
    if (lengths[i] > lengths[longest]) longest = i;
  }
  RowFill fill;
  fill.module_m = module;
  fill.p_double = p.meeting_room_probability;
  fill.p_triple = 0.04;
  fill.kind_single = "office";
  fill.kind_double = "office";
  fill.kind_triple = "meeting";
  fill.glass_double_probability = 0.8;
  fill.variety = &p.variety;
  const double min_gap = 2.0 * st.door_jamb_m + sd + 0.6;
  for (std::size_t i = 0; i < n; ++i) {
    const Frame& F = frames[i];
    const double len = lengths[i];
    const std::string w = "wing" + std::to_string(dirs[i]);
    const int corridor = L.add_rect(w + ".corridor", "hallway", F, 0.0, -0.5 * cw, len, 0.5 * cw, hallway_end_windows(st));
    L.set_open(corridor, hub);
    const double exit_w = std::min(st.double_door_width_m, cw - 2.0 * st.door_jamb_m - 0.05);
    L.add_door(corridor, kOutside, exit_w >= 1.5 ? exit_w : 1.0, true, F.to_world(len, 0.0));

    struct Side {
      double y0, y1;
      int facing;
      const char* name;
    };
    const std::array<Side, 2> sides = {{{-0.5 * D, -0.5 * cw, +1, ".R"}, {0.5 * cw, 0.5 * D, -1, ".L"}}};
    for (std::size_t sidx = 0; sidx < 2; ++sidx) {
      const Side& s = sides[sidx];
      StripReservations res(0.0, len, min_gap);
      if (sidx == 0) {  // stairwell at the far end of the right-hand row
        res.reserve(len - 3.6, len);
        const std::string id = w + ".stair";
        add_facing_room(L, id, "stairwell", F, len - 3.6, s.y0, len, s.y1, s.facing, corridor, win, len - 1.8, sd, true,
                        rng);
        if (st.furniture) add_stairs(L, id, F, len - 3.6, s.y0, len, s.y1);
      }
      if (i == longest && sidx == 1) {  // core: elevator and two toilets mid-wing
        double x0 = snap(0.5 * len - 4.0, 0.1);
        if (p.variety.enabled && p.variety.irregular_cores) {
          const double cand = snap(rng.uniform(2.0, len - 8.2 - 2.0), 0.1);
          if (res.fits(cand, cand + 8.2)) x0 = cand;
        }
        if (res.reserve(x0, x0 + 8.2)) {
          add_facing_room(L, w + ".lift", "elevator", F, x0, s.y0, x0 + 2.4, s.y1, s.facing, corridor, no_windows(),
                          x0 + 1.2, 1.0, true, rng);
          add_facing_room(L, w + ".wc1", "toilet", F, x0 + 2.4, s.y0, x0 + 5.3, s.y1, s.facing, corridor, win, x0 + 3.85,
                          sd, rng.bernoulli(0.7), rng);
          add_facing_room(L, w + ".wc2", "toilet", F, x0 + 5.3, s.y0, x0 + 8.2, s.y1, s.facing, corridor, win, x0 + 6.75,
                          sd, rng.bernoulli(0.7), rng);
        }
      }
      int part = 0;
      for (const Interval1& f : res.free_intervals()) {
        RowStrip row;
        row.frame = F;
        row.x0 = f.x0;
        row.x1 = f.x1;
        row.y0 = s.y0;
        row.y1 = s.y1;
        row.facing = s.facing;
        row.hallway = corridor;
        row.id_prefix = w + s.name + (part > 0 ? std::string(1, static_cast<char>('a' + part)) : "");
        row.windows = win;
        row.far_side_is_facade = true;
        fill_row(L, row, fill, rng);
        ++part;
      }
    }
  }

  return L.assemble(std::string(p.variety.enabled ? "angled calibrated" : "angled") + " (seed " +
                    std::to_string(seed) + ")");
}

}  // namespace floorcast
