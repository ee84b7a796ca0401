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

double r3(double x) { return std::round(x * 1000.0) / 1000.0; }

nlohmann::ordered_json distribution_json(const Distribution& d) {
  nlohmann::ordered_json j;
  j["count"] = d.count;
  j["min"] = r3(d.min);
  j["q1"] = r3(d.q1);
  j["median"] = r3(d.median);
  j["q3"] = r3(d.q3);
  j["max"] = r3(d.max);
  j["mean"] = r3(d.mean);
  j["cv"] = r3(d.cv);
  return j;
}

nlohmann::ordered_json stats_json(const std::string& file, const PlanStats& s, const PlanStatsParams& p) {
  nlohmann::ordered_json j;
  j["file"] = file;
  j["name"] = s.name;
  j["free_area_m2"] = r3(s.free_area_m2);
  j["walls"] = s.walls;
  j["glass_walls"] = s.glass_walls;
  j["wall_length_m"] = r3(s.wall_length_m);
  j["direction_bin_deg"] = p.direction_bin_deg;
  nlohmann::ordered_json dirs = nlohmann::ordered_json::array();
  for (double v : s.direction_share) dirs.push_back(r3(v));
  j["direction_share"] = dirs;
  j["directions_used"] = s.directions_used;
  nlohmann::ordered_json th = nlohmann::ordered_json::array();
  for (const ThicknessClass& t : s.thickness_classes) {
    th.push_back({{"thickness_m", t.thickness_m}, {"walls", t.walls}, {"length_share", r3(t.length_share)}});
  }
  j["thickness_classes"] = th;
  j["doors"] = s.doors;
  j["doors_per_10m_wall"] = r3(s.doors_per_10m_wall);
  j["pillars"] = s.pillars;
  j["rooms"] = s.rooms;
  j["transitional_rooms"] = s.transitional_rooms;
  j["room_area_m2"] = distribution_json(s.room_area_m2);
  j["room_width_m"] = distribution_json(s.room_width_m);
  j["repeated_width_share"] = r3(s.repeated_width_share);
  j["corridor_width_m"] = distribution_json(s.corridor_width_m);
  return j;
}

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
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--neighbour-gap", opts->params.neighbour_gap_m,
                  "Rooms whose outlines come this close (m) are neighbours")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 10.0));
  cmd->callback([opts] {
    nlohmann::ordered_json all = nlohmann::ordered_json::array();
    for (const std::string& f : opts->files) {
      const FloorPlan p = load_floor_plan(f);
      const PlanStats s = plan_stats(p, opts->params);
      if (opts->json) {
        all.push_back(stats_json(f, s, opts->params));
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
