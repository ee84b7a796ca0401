// `floorcast compare-matchers PLAN...`: the perfect-observation comparison of PALMS+ sec. 4.4 —
// kernel vs ray matchers on seeded observation points, scored automatically.
#include <filesystem>
#include <iostream>
#include <memory>
#include <set>
#include <sstream>

#include "cli_common.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/scenarios/compare_matchers.hpp"

namespace floorcast::cli {
namespace {

std::vector<int> parse_ray_counts(const std::string& text) {
  std::vector<int> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    std::size_t used = 0;
    int n = 0;
    try {
      n = std::stoi(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (item.empty() || used != item.size() || n < 4 || n > 3600) {
      throw InputError("--rays \"" + text + "\": \"" + item + "\" is not a ray count in [4, 3600]");
    }
    out.push_back(n);
  }
  return out;
}

/// Room polygons of the given kinds from a generator rooms file (`floorcast plan generate
/// --rooms FILE`: {"rooms": [{"id", "kind", "polygon": [[x, y], ...]}, ...]}).
std::vector<std::vector<Vec2>> load_room_polygons(const std::string& path, const std::set<std::string>& kinds) {
  const nlohmann::json j = nlohmann::json::parse(read_text_file(path), nullptr, false);
  if (j.is_discarded() || !j.is_object() || !j.contains("rooms") || !j["rooms"].is_array()) {
    throw InputError(path + ": not a rooms file (expected an object with a \"rooms\" array)");
  }
  std::vector<std::vector<Vec2>> out;
  std::size_t index = 0;
  for (const auto& room : j["rooms"]) {
    const std::string where = path + ": rooms[" + std::to_string(index++) + "]";
    if (!room.is_object() || !room.contains("kind") || !room["kind"].is_string() || !room.contains("polygon") ||
        !room["polygon"].is_array()) {
      throw InputError(where + ": expected \"kind\" (string) and \"polygon\" (array of [x, y])");
    }
    if (!kinds.count(room["kind"].get<std::string>())) continue;
    std::vector<Vec2> poly;
    for (const auto& p : room["polygon"]) {
      if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number()) {
        throw InputError(where + ": polygon points must be [x, y] numbers");
      }
      poly.emplace_back(p[0].get<double>(), p[1].get<double>());
    }
    if (poly.size() < 3) throw InputError(where + ": polygon with fewer than 3 points");
    out.push_back(std::move(poly));
  }
  return out;
}

void register_compare_matchers(CLI::App& root) {
  struct Options {
    std::vector<std::string> plans;
    int points = 50;
    std::uint64_t seed = 1;
    std::string rays = "36,180";
    double clearance_m = 0.5;
    double range_m = 10.0;
    std::string orientations = "palms+";
    std::vector<std::string> rooms;
    std::vector<std::string> specs;
    bool doors_open = false;
    std::string room_kinds = "hallway,corridor,lobby,atrium,lounge,hall,vestibule";
    std::string out;
  };
  auto o = std::make_shared<Options>();
  auto* cmd = root.add_subcommand(
      "compare-matchers", "Kernel vs ray matchers on perfect observations (PALMS+ sec. 4.4): points.csv, summary.json");
  cmd->add_option("PLANS", o->plans, "Floor-plan JSON files")->required();
  cmd->add_option("--points", o->points, "Observation points per plan")->capture_default_str()->check(CLI::Range(1, 100000));
  cmd->add_option("--seed", o->seed, "Seed of the points and headings")->capture_default_str();
  cmd->add_option("--rays", o->rays, "Ray counts of the ray matchers (36 -> \"ray\", N -> \"rayN\")")->capture_default_str();
  cmd->add_option("--clearance", o->clearance_m, "Minimum distance of a point from walls, metres")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 100.0));
  cmd->add_option("--range", o->range_m, "Observation range, metres (PALMS+ 4.4: 10)")
      ->capture_default_str()
      ->check(CLI::Range(0.5, 60.0));
  cmd->add_option("--orientations", o->orientations, "Kernel matcher orientation candidates")
      ->capture_default_str()
      ->check(CLI::IsMember({"palms", "palms+", "dense"}));
  cmd->add_option("--rooms", o->rooms,
                  "Rooms files (`plan generate --rooms`), one per plan in order: points only in rooms of --room-kinds");
  cmd->add_option("--room-kinds", o->room_kinds, "Room kinds sampled with --rooms (comma-separated)")
      ->capture_default_str();
  cmd->add_flag("--doors-open", o->doors_open,
                "Open doors stay open in the observations and the matchers' plans (default: all closed, PALMS+ 4.4)");
  cmd->add_option("--matcher", o->specs,
                  "Extra matcher LABEL=NAME[:JSON overrides], e.g. 'kernel_s1=kernel:{\"scales\":[1]}' (repeatable)");
  cmd->add_option("-o,--output", o->out, "Output folder")->required();
  cmd->callback([o] {
    if (!o->rooms.empty() && o->rooms.size() != o->plans.size()) {
      throw InputError("--rooms: " + std::to_string(o->rooms.size()) + " rooms files for " +
                       std::to_string(o->plans.size()) + " plans (give one per plan, in order)");
    }
    std::set<std::string> kinds;
    {
      std::stringstream ss(o->room_kinds);
      std::string k;
      while (std::getline(ss, k, ',')) {
        if (!k.empty()) kinds.insert(k);
      }
    }
    std::vector<NamedPlan> plans;
    for (const std::string& path : o->plans) {
      std::string name = std::filesystem::path(path).stem().string();
      for (const NamedPlan& p : plans) {
        if (p.name == name) name = path;  // two files with one stem: keep them apart
      }
      NamedPlan np{name, load_floor_plan(path), {}};
      if (!o->rooms.empty()) {
        const std::string& rooms = o->rooms[plans.size()];
        np.sample_regions = load_room_polygons(rooms, kinds);
        if (np.sample_regions.empty()) throw InputError(rooms + ": no room of the kinds " + o->room_kinds);
      }
      plans.push_back(std::move(np));
    }
    ComparisonParams params;
    params.points_per_plan = o->points;
    params.seed = o->seed;
    params.clearance_m = o->clearance_m;
    params.observation.max_range_m = o->range_m;
    params.observation.doors_closed = !o->doors_open;
    params.observation.num_rays = 36;
    std::vector<MatcherSpec> specs = default_comparison_specs(parse_ray_counts(o->rays));
    specs[0].overrides["orientations"] = o->orientations;
    specs[0].overrides["max_range_m"] = o->range_m;
    for (std::size_t i = 1; i < specs.size(); ++i) specs[i].overrides["max_range_m"] = o->range_m;
    for (MatcherSpec& spec : specs) spec.overrides["doors_closed"] = !o->doors_open;
    for (const std::string& text : o->specs) {
      const auto eq = text.find('=');
      if (eq == std::string::npos || eq == 0) throw InputError("--matcher \"" + text + "\": expected LABEL=NAME[:JSON]");
      MatcherSpec spec;
      spec.label = text.substr(0, eq);
      const std::string rest = text.substr(eq + 1);
      const auto colon = rest.find(':');
      spec.name = rest.substr(0, colon);
      if (colon != std::string::npos) {
        spec.overrides = nlohmann::json::parse(rest.substr(colon + 1), nullptr, false);
        if (spec.overrides.is_discarded() || !spec.overrides.is_object()) {
          throw InputError("--matcher \"" + text + "\": the overrides are not a JSON object");
        }
      }
      if (!spec.overrides.contains("max_range_m")) spec.overrides["max_range_m"] = o->range_m;
      if (!spec.overrides.contains("doors_closed")) spec.overrides["doors_closed"] = !o->doors_open;
      for (const MatcherSpec& s : specs) {
        if (s.label == spec.label) throw InputError("--matcher \"" + text + "\": label \"" + spec.label + "\" used twice");
      }
      specs.push_back(spec);
    }

    const ComparisonResult r =
        compare_matchers(plans, specs, params, [](const std::string& line) { std::cerr << line << "\n"; });

    ensure_directory(o->out);
    write_text_file_atomic(o->out + "/points.csv", comparison_points_csv(r));
    write_json(o->out + "/summary.json", comparison_summary_json(r));
    const std::string md = comparison_markdown(r);
    write_text_file_atomic(o->out + "/summary.md", md);
    nlohmann::ordered_json run;
    run["plans"] = o->plans;
    run["points_per_plan"] = o->points;
    run["seed"] = o->seed;
    run["clearance_m"] = o->clearance_m;
    run["rooms"] = o->rooms;
    if (!o->rooms.empty()) run["room_kinds"] = o->room_kinds;
    run["observation"] = {{"max_range_m", o->range_m}, {"doors_closed", !o->doors_open}, {"rays", 36}};
    nlohmann::ordered_json matchers = nlohmann::ordered_json::array();
    for (const MatcherPrecompute& p : r.precompute) {
      matchers.push_back({{"plan", p.plan}, {"matcher", p.matcher}, {"precompute_s", p.precompute_s},
                          {"precompute_mb", p.precompute_mb}, {"parameters", p.parameters}});
    }
    run["matchers"] = matchers;
    nlohmann::ordered_json per_plan;
    for (const auto& [plan, by_label] : r.per_plan) {
      ComparisonResult one;
      one.labels = r.labels;
      one.summary = by_label;
      per_plan[plan] = comparison_summary_json(one);
    }
    run["per_plan"] = per_plan;
    write_json(o->out + "/run.json", run);
    std::cout << md;
  });
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_compare_matchers);
}  // namespace floorcast::cli
