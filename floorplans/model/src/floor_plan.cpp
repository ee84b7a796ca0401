#include "floorcast/floorplans/floor_plan.hpp"

#include <algorithm>
#include <cmath>

#include "floorcast/core/hash.hpp"
#include "floorcast/floorplans/io.hpp"

namespace floorcast {

int FloorPlan::wall_index(const std::string& wall_id) const {
  for (std::size_t i = 0; i < walls.size(); ++i) {
    if (walls[i].id == wall_id) return static_cast<int>(i);
  }
  return -1;
}

OpeningSpan opening_span(const FloorPlan& plan, const std::string& wall_id, const Vec2& center_m,
                         double width_m) {
  return opening_span(plan, plan.wall_index(wall_id), center_m, width_m);
}

WallIdIndex::WallIdIndex(const FloorPlan& plan) {
  index_.reserve(plan.walls.size());
  for (std::size_t i = 0; i < plan.walls.size(); ++i) index_.emplace(plan.walls[i].id, static_cast<int>(i));
}

int WallIdIndex::find(const std::string& wall_id) const {
  const auto it = index_.find(wall_id);
  return it == index_.end() ? -1 : it->second;
}

OpeningSpan opening_span(const FloorPlan& plan, int wall_index, const Vec2& center_m, double width_m) {
  OpeningSpan span;
  span.wall_index = wall_index;
  if (span.wall_index < 0 || static_cast<std::size_t>(wall_index) >= plan.walls.size()) {
    span.wall_index = -1;
    return span;
  }
  const Wall& wall = plan.walls[static_cast<std::size_t>(span.wall_index)];
  const double t = (center_m - wall.a_m).dot(wall.direction());
  span.t0_m = t - 0.5 * width_m;
  span.t1_m = t + 0.5 * width_m;
  return span;
}

Eigen::Vector4d plan_bbox_m(const FloorPlan& plan) {
  const double inf = std::numeric_limits<double>::infinity();
  Eigen::Vector4d box(inf, inf, -inf, -inf);
  auto add = [&box](const Vec2& p) {
    box[0] = std::min(box[0], p.x());
    box[1] = std::min(box[1], p.y());
    box[2] = std::max(box[2], p.x());
    box[3] = std::max(box[3], p.y());
  };
  for (const Wall& w : plan.walls) {
    const Vec2 d = w.b_m - w.a_m;
    const double len = d.norm();
    if (len <= 0.0) continue;
    const Vec2 n = Vec2(-d.y(), d.x()) / len * (0.5 * w.thickness_m);
    add(w.a_m + n);
    add(w.a_m - n);
    add(w.b_m + n);
    add(w.b_m - n);
  }
  for (const Obstacle& o : plan.obstacles) {
    if (o.kind == ObstacleKind::kPillar) {
      const double r = 0.5 * o.size_m.x();
      add(o.center_m - Vec2(r, r));
      add(o.center_m + Vec2(r, r));
      continue;
    }
    const double c = std::cos(o.yaw_rad), s = std::sin(o.yaw_rad);
    const Vec2 ex = 0.5 * o.size_m.x() * Vec2(c, s);
    const Vec2 ey = 0.5 * o.size_m.y() * Vec2(-s, c);
    for (const Vec2& corner : {Vec2(o.center_m - ex - ey), Vec2(o.center_m + ex - ey), Vec2(o.center_m + ex + ey),
                               Vec2(o.center_m - ex + ey)})
      add(corner);
  }
  if (box[0] > box[2]) box.setZero();
  return box;
}

PlanCounts plan_counts(const FloorPlan& plan) {
  PlanCounts c;
  c.walls = static_cast<int>(plan.walls.size());
  c.glass_walls = static_cast<int>(std::count_if(plan.walls.begin(), plan.walls.end(), [](const Wall& w) {
    return w.material == WallMaterial::kGlass;
  }));
  c.doors = static_cast<int>(plan.doors.size());
  c.doors_closed = static_cast<int>(
      std::count_if(plan.doors.begin(), plan.doors.end(), [](const Door& d) { return d.closed; }));
  c.windows = static_cast<int>(plan.windows.size());
  c.obstacles = static_cast<int>(plan.obstacles.size());
  return c;
}

std::uint64_t plan_hash(const FloorPlan& plan) {
  return fnv1a64(floor_plan_to_json(plan));
}

}  // namespace floorcast
