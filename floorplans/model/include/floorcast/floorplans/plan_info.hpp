// What `floorcast plan info` reports about a plan: area, bounding box, element counts.
#pragma once

#include <array>
#include <nlohmann/json.hpp>
#include <string>

#include "floorcast/core/fields.hpp"
#include "floorcast/floorplans/floor_plan.hpp"

namespace floorcast {

struct PlanInfo {
  std::string name;
  int level = 0;
  double area_m2 = 0.0;                 ///< free floor area (doors open), rounded to 0.01 m^2
  std::array<double, 4> bbox_m{};       ///< min x, min y, max x, max y
  PlanCounts counts;
};

PlanInfo plan_info(const FloorPlan& plan);

/// Its fields: name, level, area_m2, bbox_m, walls, glass_walls, doors, doors_closed, windows,
/// obstacles.
const FieldList<PlanInfo>& plan_info_fields();

}  // namespace floorcast
