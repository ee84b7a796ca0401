// Small hand-built plans for the matcher tests.
#pragma once

#include <cmath>

#include "floorcast/floorplans/floor_plan.hpp"

namespace floorcast::test {

inline Wall wall(const char* id, double ax, double ay, double bx, double by, double t = 0.15) {
  Wall w;
  w.id = id;
  w.a_m = {ax, ay};
  w.b_m = {bx, by};
  w.thickness_m = t;
  return w;
}

/// An asymmetric 12 x 8 m floor: four rooms of different sizes, doors, one angled wall, a short
/// stub wall. No two spots look alike, so a perfect observation has one clear best pose.
inline FloorPlan asymmetric_floor() {
  FloorPlan p;
  p.name = "asymmetric";
  p.walls = {
      wall("s", 0, 0, 12, 0, 0.2),   wall("e", 12, 0, 12, 8, 0.2), wall("n", 12, 8, 0, 8, 0.2),
      wall("w", 0, 8, 0, 0, 0.2),    wall("m1", 5, 0, 5, 5),       wall("m2", 5, 5, 12, 5),
      wall("m3", 8.5, 5, 8.5, 8),    wall("r1", 0, 3, 3, 3),       wall("diag", 1.0, 5.0, 3.0, 7.0, 0.1),
      wall("stub", 9.5, 0, 9.5, 1.8),
  };
  p.doors = {
      {"d1", "m1", {5.0, 2.0}, 0.9, false},
      {"d2", "m2", {7.0, 5.0}, 1.0, false},
      {"d3", "m3", {8.5, 6.5}, 0.9, true},
      {"d4", "r1", {2.0, 3.0}, 0.9, false},
  };
  return p;
}

/// Every wall endpoint and door centre rotated by yaw about the origin, then translated. Quarter
/// turns are exact (cos/sin rounded to 0 and +-1) so axis-aligned walls stay axis-aligned.
inline FloorPlan transformed(const FloorPlan& in, double yaw, double tx, double ty) {
  FloorPlan p = in;
  double c = std::cos(yaw), s = std::sin(yaw);
  if (std::abs(c) < 1e-12) c = 0.0;
  if (std::abs(s) < 1e-12) s = 0.0;
  auto T = [&](const Vec2& v) { return Vec2(c * v.x() - s * v.y() + tx, s * v.x() + c * v.y() + ty); };
  for (Wall& w : p.walls) {
    w.a_m = T(w.a_m);
    w.b_m = T(w.b_m);
  }
  for (Door& d : p.doors) d.center_m = T(d.center_m);
  for (Window& w : p.windows) w.center_m = T(w.center_m);
  return p;
}

}  // namespace floorcast::test
