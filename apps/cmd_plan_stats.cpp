// `floorcast plan stats`: structure measures of plans (floorplans/stats.hpp).
#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

#include "cli_common.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/floorplans/stats.hpp"

namespace floorcast::cli {
namespace {

void register_plan_stats(CLI::App& root) {
  CLI::App& plan = group(root, "plan", "Floor plans: inspect, validate, import, generate, render");
  auto* cmd = plan.add_subcommand(
      "stats",
      "Structure measures of plans: wall length and directions, thickness classes, doors per 10 m of wall, "
      "room areas and widths (non-transitional rooms), repeated room widths, corridor widths");
  struct Options {
    std::vector<std::string> files;
    bool json = false;
    PlanStatsParams params;
  };
  auto opts = std::make_shared<Options>();
  cmd->add_option("PLANS", opts->files, "Floor-plan JSON files (room labels from the plan)")->required();
  cmd->add_flag("--json", opts->json, "Print a JSON array (one object per plan) instead of text");
  cmd->add_option("--repeat-tolerance", opts->params.repeat_tolerance,
                  "Room widths within this share of each other count as repeated")
      ->capture_default_str()
      ->check(in_range(0.0, 1.0));
  cmd->add_option("--neighbour-gap", opts->params.neighbour_gap_m,
                  "Rooms whose outlines come this close (m) are neighbours")
      ->capture_default_str()
      ->check(in_range(0.0, 10.0));
  cmd->callback([opts] {
    nlohmann::ordered_json all = nlohmann::ordered_json::array();
    for (const std::string& f : opts->files) {
      const FloorPlan p = load_floor_plan(f);
      const PlanStats s = plan_stats(p, opts->params);
      if (opts->json) {
        nlohmann::ordered_json j = {{"file", f}};
        j.update(to_json(s));
        all.push_back(std::move(j));
        continue;
      }
      auto dist = [](const Distribution& d) {
        std::ostringstream o;
        o << std::fixed << std::setprecision(1);
        if (d.count == 0) return std::string("-");
        o << "median " << d.median << " [q1 " << d.q1 << ", q3 " << d.q3 << "], range " << d.min << "-" << d.max
          << ", cv " << std::setprecision(2) << d.cv << " (n " << d.count << ")";
        return o.str();
      };
      std::cout << std::fixed << std::setprecision(2);
      std::cout << f << " (" << s.name << ")\n"
                << "  free area m2:        " << s.free_area_m2 << "\n"
                << "  walls:               " << s.walls << " (glass " << s.glass_walls << "), " << s.wall_length_m
                << " m\n"
                << "  directions used:     " << s.directions_used << " of " << s.direction_share.size() << " bins of "
                << opts->params.direction_bin_deg << " deg\n"
                << "  thickness classes:  ";
      for (const ThicknessClass& t : s.thickness_classes) {
        std::cout << " " << t.thickness_m << " m (" << std::setprecision(0) << 100.0 * t.length_share << "%)"
                  << std::setprecision(2);
      }
      std::cout << "\n"
                << "  doors:               " << s.doors << " (" << s.doors_per_10m_wall << " per 10 m of wall)\n"
                << "  pillars:             " << s.pillars << "\n"
                << "  rooms:               " << s.rooms << " (" << s.transitional_rooms << " transitional)\n"
                << "  room area m2:        " << dist(s.room_area_m2) << "\n"
                << "  room width m:        " << dist(s.room_width_m) << "\n"
                << "  repeated widths:     " << std::setprecision(0) << 100.0 * s.repeated_width_share
                << "% of rooms\n"
                << std::setprecision(2) << "  corridor width m:    " << dist(s.corridor_width_m) << "\n";
    }
    if (opts->json) std::cout << all.dump(2) << "\n";
  });
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_plan_stats);
}  // namespace floorcast::cli
