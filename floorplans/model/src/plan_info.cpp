#include "floorcast/floorplans/plan_info.hpp"

#include <cmath>

#include "floorcast/floorplans/raster.hpp"

namespace floorcast {

PlanInfo plan_info(const FloorPlan& plan) {
  PlanInfo info;
  info.name = plan.name;
  info.level = plan.level;
  info.area_m2 = std::round(free_floor_area_m2(plan) * 100.0) / 100.0;
  const Eigen::Vector4d bbox = plan_bbox_m(plan);
  info.bbox_m = {bbox[0], bbox[1], bbox[2], bbox[3]};
  info.counts = plan_counts(plan);
  return info;
}

const FieldList<PlanInfo>& plan_info_fields() {
  static const FieldList<PlanCounts> counts =
      FieldList<PlanCounts>("plan counts")
          .integer("walls", &PlanCounts::walls, 0, 1 << 30, "walls")
          .integer("glass_walls", &PlanCounts::glass_walls, 0, 1 << 30, "glass walls among them")
          .integer("doors", &PlanCounts::doors, 0, 1 << 30, "doors")
          .integer("doors_closed", &PlanCounts::doors_closed, 0, 1 << 30, "closed doors among them")
          .integer("windows", &PlanCounts::windows, 0, 1 << 30, "windows")
          .integer("obstacles", &PlanCounts::obstacles, 0, 1 << 30, "obstacles (furniture, pillars)");
  static const FieldList<PlanInfo> f =
      FieldList<PlanInfo>("plan info")
          .text("name", &PlanInfo::name, "the plan's name")
          .integer("level", &PlanInfo::level, -1000, 1000, "the floor's level")
          .number("area_m2", &PlanInfo::area_m2, 0.0, 1e12, "free floor area (doors open), m^2")
          .custom(
              "bbox_m", [](nlohmann::ordered_json& j, const PlanInfo& p) { j["bbox_m"] = p.bbox_m; },
              [](ParamReader& r, PlanInfo& p) {
                std::vector<double> v;
                r.read("bbox_m", v, -1e12, 1e12);
                if (v.size() != 4) r.fail("bbox_m", "expected 4 numbers");
                p.bbox_m = {v[0], v[1], v[2], v[3]};
              },
              "[min x, min y, max x, max y]", "bounding box of walls and obstacles, m")
          .flatten(&PlanInfo::counts, counts);
  return f;
}

}  // namespace floorcast
