#include "floorcast/bench/scale_bench.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>
#include <vector>

#include "floorcast/core/types.hpp"
#include "floorcast/floorplans/generate.hpp"

namespace floorcast {
namespace {

/// Appends `part` to `plan`, shifted by `offset_m`, every id prefixed.
void append_shifted(FloorPlan& plan, const FloorPlan& part, const Vec2& offset_m, const std::string& prefix) {
  for (Wall w : part.walls) {
    w.id = prefix + w.id;
    w.a_m += offset_m;
    w.b_m += offset_m;
    plan.walls.push_back(std::move(w));
  }
  for (Door d : part.doors) {
    d.id = prefix + d.id;
    d.wall_id = prefix + d.wall_id;
    d.center_m += offset_m;
    plan.doors.push_back(std::move(d));
  }
  for (Window w : part.windows) {
    w.id = prefix + w.id;
    w.wall_id = prefix + w.wall_id;
    w.center_m += offset_m;
    plan.windows.push_back(std::move(w));
  }
  for (Obstacle o : part.obstacles) {
    o.id = prefix + o.id;
    o.center_m += offset_m;
    plan.obstacles.push_back(std::move(o));
  }
  for (Room r : part.rooms) {
    r.id = prefix + r.id;
    for (Vec2& p : r.polygon_m) p += offset_m;
    for (auto& hole : r.holes_m)
      for (Vec2& p : hole) p += offset_m;
    plan.rooms.push_back(std::move(r));
  }
}

}  // namespace

FloorPlan scale_plan(const ScalePlanParams& params) {
  if (!(params.area_m2 >= kMinScalePlanAreaM2) || !(params.campus_area_m2 >= kMinScalePlanAreaM2)) {
    throw InputError("scale plan: areas must be at least " + std::to_string(static_cast<int>(kMinScalePlanAreaM2)) +
                     " m^2 (the smallest office the generator makes), got " + std::to_string(params.area_m2) + " and campus " +
                     std::to_string(params.campus_area_m2));
  }
  const std::string name = "scale_" + std::to_string(static_cast<long long>(std::llround(params.area_m2))) + "m2";
  if (params.area_m2 < 5000.0) {
    OfficeParams op = OfficeParams::repetitive();  // the buildings results/bench_scale.md was measured on
    op.target_area_min_m2 = op.target_area_max_m2 = params.area_m2;
    FloorPlan plan = generate_office(params.seed, op).plan;
    plan.name = name;
    return plan;
  }
  const int count = std::max(1, static_cast<int>(std::lround(params.area_m2 / params.campus_area_m2)));
  CampusParams cp = CampusParams::repetitive();
  cp.target_area_min_m2 = cp.target_area_max_m2 = params.area_m2 / count;
  FloorPlan plan;
  plan.name = name;
  double y = 0.0;
  for (int k = 0; k < count; ++k) {
    const FloorPlan part = generate_campus(params.seed + static_cast<std::uint64_t>(k), cp).plan;
    const Eigen::Vector4d box = plan_bbox_m(part);  // min x, min y, max x, max y
    append_shifted(plan, part, Vec2(-box[0], y - box[1]), "b" + std::to_string(k) + "_");
    y += box[3] - box[1] + params.gap_m;
  }
  return plan;
}

FloorPlan many_walls_plan(const ScalePlanParams& params, std::size_t walls) {
  const FloorPlan base = scale_plan(params);
  std::vector<char> holds_opening(base.walls.size(), 0);
  std::unordered_map<std::string, std::size_t> index;
  for (std::size_t i = 0; i < base.walls.size(); ++i) index.emplace(base.walls[i].id, i);
  for (const Door& d : base.doors) holds_opening[index.at(d.wall_id)] = 1;
  for (const Window& w : base.windows) holds_opening[index.at(w.wall_id)] = 1;
  double free_length = 0.0;
  std::size_t fixed = 0;
  for (std::size_t i = 0; i < base.walls.size(); ++i) {
    if (holds_opening[i]) ++fixed;
    else free_length += base.walls[i].length_m();
  }
  if (walls <= base.walls.size() || free_length <= 0.0) {
    FloorPlan plan = base;
    plan.name = "walls_" + std::to_string(plan.walls.size());
    return plan;
  }
  // Pieces of one length everywhere: each free wall in round(length / piece) pieces.
  const double piece = free_length / static_cast<double>(walls - fixed);
  if (piece < 0.02) throw InputError("many-walls plan: " + std::to_string(walls) + " walls need pieces shorter than 2 cm");
  FloorPlan plan = base;
  plan.walls.clear();
  for (std::size_t i = 0; i < base.walls.size(); ++i) {
    const Wall& w = base.walls[i];
    const int k = holds_opening[i] ? 1 : std::max(1, static_cast<int>(std::lround(w.length_m() / piece)));
    for (int j = 0; j < k; ++j) {
      Wall p = w;
      if (k > 1) {
        p.id = w.id + "_" + std::to_string(j);
        p.a_m = w.a_m + (w.b_m - w.a_m) * (static_cast<double>(j) / k);
        p.b_m = w.a_m + (w.b_m - w.a_m) * (static_cast<double>(j + 1) / k);
      }
      plan.walls.push_back(std::move(p));
    }
  }
  plan.name = "walls_" + std::to_string(plan.walls.size());
  return plan;
}

}  // namespace floorcast
