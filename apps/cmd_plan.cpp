// `floorcast plan info|validate`.
#include <iomanip>
#include <iostream>
#include <memory>

#include "cli_common.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/floorplans/plan_info.hpp"
#include "floorcast/floorplans/raster.hpp"

namespace floorcast::cli {
namespace {

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
    const PlanInfo info = plan_info(load_floor_plan(info_opts->file));
    if (info_opts->json) {
      std::cout << plan_info_fields().write(info).dump(2) << "\n";
      return;
    }
    const PlanCounts& c = info.counts;
    std::cout << std::fixed << std::setprecision(2);
    std::cout << "name:         " << info.name << "\n"
              << "level:        " << info.level << "\n"
              << "area_m2:      " << info.area_m2 << "\n"
              << "bbox_m:       [" << info.bbox_m[0] << ", " << info.bbox_m[1] << ", " << info.bbox_m[2] << ", "
              << info.bbox_m[3] << "]\n"
              << "walls:        " << c.walls << " (glass " << c.glass_walls << ")\n"
              << "doors:        " << c.doors << "\n"
              << "doors_closed: " << c.doors_closed << "\n"
              << "windows:      " << c.windows << "\n"
              << "obstacles:    " << c.obstacles << "\n";
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
