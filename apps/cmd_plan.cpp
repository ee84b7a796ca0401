// `floorcast plan info|validate`.
#include <iomanip>
#include <iostream>
#include <memory>

#include "cli_common.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/floorplans/raster.hpp"

namespace floorcast::cli {
namespace {

nlohmann::ordered_json plan_info_json(const FloorPlan& plan) {
  const PlanCounts counts = plan_counts(plan);
  const Eigen::Vector4d bbox = plan_bbox_m(plan);
  nlohmann::ordered_json j;
  j["name"] = plan.name;
  j["level"] = plan.level;
  j["area_m2"] = std::round(free_floor_area_m2(plan) * 100.0) / 100.0;
  j["bbox_m"] = {bbox[0], bbox[1], bbox[2], bbox[3]};
  j["walls"] = counts.walls;
  j["glass_walls"] = counts.glass_walls;
  j["doors"] = counts.doors;
  j["doors_closed"] = counts.doors_closed;
  j["windows"] = counts.windows;
  j["obstacles"] = counts.obstacles;
  return j;
}

void register_plan_info(CLI::App& root) {
  CLI::App& plan = group(root, "plan", "Floor plans: inspect, validate, import, generate, render");

  auto* info = plan.add_subcommand("info", "Print a plan's area, bounding box and element counts");
  struct InfoOptions {
    std::string file;
    bool json = false;
  };
  auto info_opts = std::make_shared<InfoOptions>();
  info->add_option("FILE", info_opts->file, "Floor-plan JSON")->required();
  info->add_flag("--json", info_opts->json, "Print JSON instead of text");
  info->callback([info_opts] {
    const FloorPlan p = load_floor_plan(info_opts->file);
    const auto j = plan_info_json(p);
    if (info_opts->json) {
      std::cout << j.dump(2) << "\n";
      return;
    }
    std::cout << std::fixed << std::setprecision(2);
    std::cout << "name:         " << p.name << "\n"
              << "level:        " << p.level << "\n"
              << "area_m2:      " << j["area_m2"].get<double>() << "\n"
              << "bbox_m:       [" << j["bbox_m"][0].get<double>() << ", " << j["bbox_m"][1].get<double>()
              << ", " << j["bbox_m"][2].get<double>() << ", " << j["bbox_m"][3].get<double>() << "]\n"
              << "walls:        " << j["walls"] << " (glass " << j["glass_walls"] << ")\n"
              << "doors:        " << j["doors"] << "\n"
              << "doors_closed: " << j["doors_closed"] << "\n"
              << "windows:      " << j["windows"] << "\n"
              << "obstacles:    " << j["obstacles"] << "\n";
  });

  auto* validate = plan.add_subcommand(
      "validate", "Check a plan file (format, geometry, and a room-sized free region to stand in); exit non-zero with "
                  "the reason if invalid");
  auto validate_files = std::make_shared<std::vector<std::string>>();
  validate->add_option("FILES", *validate_files, "Floor-plan JSON files")->required();
  validate->callback([validate_files] {
    for (const std::string& f : *validate_files) {
      const FloorPlan p = load_floor_plan(f);
      require_room_sized_free_region(p, f);
      std::cout << f << ": ok\n";
    }
  });
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_plan_info);
}  // namespace floorcast::cli
