// Apartment archetype (x east, y north, metres):
//
//   y = D  +-----------+---------+-----------+----------+
//          | bedroom   |  bath   | bedroom   | bedroom  |   back band (bedrooms, bath)
//          +-----------+---------+-----------+----+-----+
//   entry->|  hall                                |closet|  hall band
//          +--------------+-----------------------+-----+
//          | kitchen      | living room (glazed east facade)|  front band
//   y = 0  +--------------+----------------------------------+
//
// The bath sits first or second in the back band; the kitchen is open to the living room or
// closed with its own door; the living room door is single or double.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "generate_layout.hpp"

namespace floorcast {

using namespace generate_detail;

GeneratedBuilding generate_apartment(std::uint64_t seed, const ApartmentParams& p) {
  Rng rng(mix_seed(seed, 0xA9A27ULL));
  const BuildingStyle& st = p.style;
  Layout L(st);
  const Frame F;

  const double W = snap(rng.uniform(p.width_min_m, p.width_max_m), 0.05);
  const double front = snap(rng.uniform(p.front_depth_min_m, p.front_depth_max_m), 0.05);
  const double hall_w = snap(rng.uniform(p.hall_width_min_m, p.hall_width_max_m), 0.05);
  const double back = snap(rng.uniform(p.back_depth_min_m, p.back_depth_max_m), 0.05);
  const double kw = snap(rng.uniform(p.kitchen_width_min_m, p.kitchen_width_max_m), 0.05);
  const double bw = snap(rng.uniform(p.bath_width_min_m, p.bath_width_max_m), 0.05);
  const bool open_kitchen = rng.bernoulli(p.open_kitchen_probability);
  const double y_hall = front, y_back = front + hall_w, D = front + hall_w + back;
  const double x_closet = W - p.storage_width_m;
  const WindowSpec win = standard_windows(st);
  const double sd = st.door_width_m;

  // Front band.
  const int kitchen = L.add_rect("kitchen", "kitchen", F, 0.0, 0.0, kw, front, win);
  const int living = L.add_rect("living", "living", F, kw, 0.0, W, front, win);
  L.set_glass(living, kOutside, 0.0, std::nullopt, Vec2(1.0, 0.0));  // glazed east facade
  // Hall band.
  const int hall = L.add_rect("hall", "hall", F, 0.0, y_hall, x_closet, y_back, no_windows());
  const int closet = L.add_rect("closet", "storage", F, x_closet, y_hall, W, y_back, no_windows());
  L.add_door(hall, kOutside, 1.0, true, F.to_world(0.0, 0.5 * (y_hall + y_back)));
  L.add_door(closet, hall, 0.8, true, F.to_world(x_closet, 0.5 * (y_hall + y_back)));
  if (open_kitchen) {
    L.set_open(kitchen, living);
  } else {
    L.add_door(kitchen, hall, 0.8 + 0.1 * rng.integer(0, 1), rng.bernoulli(st.room_door_closed_probability),
               F.to_world(kw - 0.8, y_hall));
  }
  const bool double_living = rng.bernoulli(0.5);
  L.add_door(living, hall, double_living ? 1.6 : sd, false, F.to_world(kw + 0.45 * (x_closet - kw), y_hall));

  // Back band: bedrooms and the bath.
  const double rest = W - bw;
  const int beds = rest >= 3.0 * 3.0 ? 3 : 2;
  std::vector<double> weights;
  for (int b = 0; b < beds; ++b) weights.push_back(b == 0 ? rng.uniform(1.15, 1.35) : rng.uniform(0.95, 1.05));
  double wsum = 0.0;
  for (double w : weights) wsum += w;
  std::vector<double> widths;
  std::vector<std::string> kinds;
  for (int b = 0; b < beds; ++b) {
    widths.push_back(snap(rest * weights[static_cast<std::size_t>(b)] / wsum, 0.05));
    kinds.push_back("bedroom");
  }
  const int bath_pos = rng.integer(0, 1);
  widths.insert(widths.begin() + bath_pos, bw);
  kinds.insert(kinds.begin() + bath_pos, "bath");
  // The last room reaches over the closet; give it at least 1.8 m of wall on the hall for its door
  // (taken from its neighbour, a bedroom of at least 2.8 m).
  {
    double before_last = 0.0;
    for (std::size_t i = 0; i + 1 < widths.size(); ++i) before_last += widths[i];
    const double short_by = 1.8 - (x_closet - before_last);
    if (short_by > 0.0) {
      widths[widths.size() - 2] -= short_by;
      widths.back() += short_by;
    }
  }
  double x = 0.0;
  int bed_no = 0;
  for (std::size_t i = 0; i < widths.size(); ++i) {
    const double x0 = x, x1 = i + 1 == widths.size() ? W : x + widths[i];
    x = x1;
    const bool bath = kinds[i] == "bath";
    const std::string id = bath ? "bath" : "bedroom" + std::to_string(++bed_no);
    const int room = L.add_rect(id, kinds[i], F, x0, y_back, x1, D, bath ? small_windows(st) : win);
    // Door towards the hall (the last room reaches over the closet: keep its door left of it).
    const double hall_x1 = std::min(x1, x_closet);
    const double door_x = bath ? 0.5 * (x0 + hall_x1) : (i % 2 == 0 ? x0 + 0.8 : hall_x1 - 0.8);
    const bool closed = bath ? rng.bernoulli(0.8) : rng.bernoulli(st.room_door_closed_probability);
    L.add_door(room, hall, bath ? 0.8 : sd, closed, F.to_world(door_x, y_back));
    if (bath) {
      // Glass shower screen from the back wall, and bathroom fixtures.
      Wall screen;
      screen.a_m = F.to_world(x0 + 0.95, D);
      screen.b_m = F.to_world(x0 + 0.95, D - 1.05);
      screen.thickness_m = st.glass_thickness_m;
      screen.material = WallMaterial::kGlass;
      screen.glass_sill_m = 0.0;
      screen.glass_head_m = 2.0;
      L.add_free_wall("shower_screen", screen);
      if (st.furniture) {
        L.add_obstacle("bath_vanity", ObstacleKind::kBox, F.to_world(x1 - 0.35, D - 0.8), Vec2(0.5, 0.9), 0.0, 0.85);
        L.add_obstacle("bath_wc", ObstacleKind::kBox, F.to_world(x1 - 0.4, y_back + 0.75), Vec2(0.6, 0.4), 0.0, 0.45);
      }
    } else if (st.furniture) {
      const double bed_w = bed_no == 1 ? 1.6 : 0.9;
      const double cx = 0.5 * (x0 + x1) + rng.uniform(-0.2, 0.2);
      L.add_obstacle(id + "_bed", ObstacleKind::kBox, F.to_world(cx, D - 0.15 - 1.05), Vec2(bed_w, 2.0), 0.0, 0.5);
      const bool left = (i % 2) == 1;  // wardrobe on the wall away from the door
      L.add_obstacle(id + "_wardrobe", ObstacleKind::kBox,
                     F.to_world(left ? x0 + 0.4 : x1 - 0.4, y_back + 0.6 + 0.9), Vec2(0.6, 1.8), 0.0, 2.1);
    }
  }

  if (st.furniture) {
    // Kitchen counter along the west wall and a table; living room sofa, coffee table, shelf.
    L.add_obstacle("kitchen_counter", ObstacleKind::kBox, F.to_world(0.45, 0.5 * front), Vec2(0.6, front - 1.4), 0.0,
                   0.9);
    L.add_obstacle("kitchen_table", ObstacleKind::kBox, F.to_world(0.55 * kw + 0.3, 0.4 * front), Vec2(0.8, 1.2), 0.0,
                   0.75);
    const double lx = 0.5 * (kw + W);
    L.add_obstacle("living_sofa", ObstacleKind::kBox, F.to_world(lx, 0.2 + 0.9), Vec2(2.2, 0.9), 0.0, 0.8);
    L.add_obstacle("living_table", ObstacleKind::kBox, F.to_world(lx, 2.4), Vec2(1.1, 0.6), 0.0, 0.45);
    L.add_obstacle("living_shelf", ObstacleKind::kBox, F.to_world(kw + 1.3, front - 0.35), Vec2(1.6, 0.4), 0.0, 2.0);
    L.add_obstacle("closet_shelf", ObstacleKind::kBox, F.to_world(W - 0.35, 0.5 * (y_hall + y_back)),
                   Vec2(0.4, hall_w - 0.5), 0.0, 2.0);
  }

  return L.assemble("apartment (seed " + std::to_string(seed) + ")");
}

}  // namespace floorcast
