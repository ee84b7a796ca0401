// `floorcast compare-matchers PLAN...`: the perfect-observation comparison of PALMS+ sec. 4.4 —
// kernel vs ray vs plane (VoxelPlane-Reloc, on perfect 3-D planes) matchers on seeded
// observation points, scored automatically, with negative samples from the other plans if asked. A thin front on the
// scenario engine: the options become a scenario (validated, resolved and run like any other),
// and the output folder is an ordinary run directory (summary.md/json, observations.csv, plots,
// resolved_config.json; resumable).
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

#include "cli_common.hpp"
#include "floorcast/core/json_text.hpp"
#include "floorcast/scenarios/scenario.hpp"

namespace floorcast::cli {
namespace {

using OJson = nlohmann::ordered_json;

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

std::vector<std::string> split_commas(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  std::string k;
  while (std::getline(ss, k, ',')) {
    if (!k.empty()) out.push_back(k);
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
    bool no_planes = false;
    int negatives = 0;
    std::string room_kinds;
    bool uniform = false;
    int jobs = 0;
    bool quiet = false;
    std::string out;
  };
  auto o = std::make_shared<Options>();
  auto* cmd = root.add_subcommand(
      "compare-matchers",
      "Kernel vs ray vs plane matchers on perfect observations (PALMS+ sec. 4.4; perfect 3-D planes for the plane "
      "matcher): a scenario run into a run directory");
  cmd->add_option("PLANS", o->plans, "Floor-plan JSON files")->required();
  cmd->add_option("--points", o->points, "Observation points per plan")->capture_default_str()->check(in_range(1, 100000));
  cmd->add_option("--seed", o->seed, "Seed of the points and headings")->capture_default_str();
  cmd->add_option("--rays", o->rays, "Ray counts of the ray matchers (36 -> \"ray\", N -> \"rayN\")")->capture_default_str();
  cmd->add_option("--clearance", o->clearance_m, "Minimum distance of a point from walls, metres")
      ->capture_default_str()
      ->check(in_range(0.0, 100.0));
  cmd->add_option("--range", o->range_m, "Observation and matching range, metres (PALMS+ 4.4: 10)")
      ->capture_default_str()
      ->check(in_range(0.5, 60.0));
  cmd->add_option("--orientations", o->orientations, "Kernel matcher orientation candidates")
      ->capture_default_str()
      ->check(CLI::IsMember({"palms", "palms+", "dense"}));
  cmd->add_option("--rooms", o->rooms,
                  "Rooms files (`plan generate --rooms`), one per plan in order, for plans without \"rooms\" labels");
  cmd->add_option("--room-kinds", o->room_kinds,
                  "Sample only in rooms of these kinds (comma-separated; default: the transitional kinds)");
  cmd->add_flag("--uniform", o->uniform,
                "Points anywhere in the free space (default: transitional spaces of labelled plans, PALMS+ 4.4)");
  cmd->add_flag("--doors-open", o->doors_open,
                "Open doors stay open in the observations and the matchers' plans (default: all closed, PALMS+ 4.4)");
  cmd->add_flag("--no-planes", o->no_planes, "Leave out the plane matcher (VoxelPlane-Reloc, \"planes\")");
  cmd->add_option("--negatives", o->negatives,
                  "Negative samples per plan: observations made in the other plans, which a matcher should reject "
                  "(scored with precision and recall; needs two or more plans)")
      ->check(CLI::Range(0, 100000));
  cmd->add_option("--matcher", o->specs,
                  "Extra matcher LABEL=NAME[:JSON overrides], e.g. 'kernel_s1=kernel:{\"scales\":[1]}' (repeatable)");
  cmd->add_option("--jobs", o->jobs, "Concurrent work units (default: all cores)")->check(in_range(0, 4096));
  cmd->add_flag("--quiet", o->quiet, "No progress output");
  cmd->add_option("-o,--output", o->out, "Output run directory")->required();
  cmd->callback([o] {
    if (!o->rooms.empty() && o->rooms.size() != o->plans.size()) {
      throw InputError("--rooms: " + std::to_string(o->rooms.size()) + " rooms files for " +
                       std::to_string(o->plans.size()) + " plans (give one per plan, in order)");
    }
    OJson doc;
    doc["name"] = "compare-matchers";
    doc["description"] = "Perfect-observation comparison of layout matchers (PALMS+ sec. 4.4), from the command line";
    OJson buildings = OJson::array();
    for (std::size_t i = 0; i < o->plans.size(); ++i) {
      OJson b;
      b["file"] = std::filesystem::absolute(o->plans[i]).string();
      // Two files with one stem: keep them apart.
      std::string label = std::filesystem::path(o->plans[i]).stem().string();
      for (std::size_t k = 0; k < i; ++k) {
        if (std::filesystem::path(o->plans[k]).stem().string() == label) label += "_" + std::to_string(i);
      }
      b["label"] = label;
      if (!o->rooms.empty()) b["rooms"] = std::filesystem::absolute(o->rooms[i]).string();
      buildings.push_back(b);
    }
    doc["buildings"] = buildings;
    doc["sampling"] = {{"count", o->points}, {"seed", o->seed}, {"clearance_m", o->clearance_m}};
    if (o->negatives > 0) doc["sampling"]["negatives"] = o->negatives;
    if (o->uniform && !o->room_kinds.empty()) throw InputError("--uniform and --room-kinds exclude each other");
    if (o->uniform) doc["sampling"]["region"] = "uniform";
    if (!o->room_kinds.empty()) doc["sampling"]["region_kinds"] = split_commas(o->room_kinds);
    doc["shared"] = {{"range_m", o->range_m}, {"doors_closed", !o->doors_open}};
    doc["observation"] = {{"source", "perfect"}, {"rays", 36}};
    OJson matchers;
    matchers["kernel"] = {{"matcher", "kernel"}, {"orientations", o->orientations}};
    for (int n : parse_ray_counts(o->rays)) {
      matchers[n == 36 ? std::string("ray") : "ray" + std::to_string(n)] = {{"matcher", "ray"}, {"num_directions", n}};
    }
    if (!o->no_planes) matchers["planes"] = {{"matcher", "planes"}};
    for (const std::string& text : o->specs) {
      const auto eq = text.find('=');
      if (eq == std::string::npos || eq == 0) throw InputError("--matcher \"" + text + "\": expected LABEL=NAME[:JSON]");
      const std::string label = text.substr(0, eq);
      const std::string rest = text.substr(eq + 1);
      const auto colon = rest.find(':');
      OJson spec = OJson::object();
      if (colon != std::string::npos) {
        spec = parse_ordered_json_text(rest.substr(colon + 1), "--matcher " + label);
        if (!spec.is_object()) {
          throw InputError("--matcher \"" + text + "\": the overrides are not a JSON object");
        }
      }
      spec["matcher"] = rest.substr(0, colon);
      if (matchers.contains(label)) throw InputError("--matcher \"" + text + "\": label \"" + label + "\" used twice");
      matchers[label] = spec;
    }
    doc["matchers"] = matchers;
    doc["output"] = {{"heatmaps", 0}};
    const Scenario scenario = parse_scenario(doc.dump(2), "compare-matchers (command line)",
                                             std::filesystem::current_path().string(), data_dir());
    run_scenario(scenario, o->out, o->jobs, "0/1", o->quiet);
  });
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_compare_matchers);
}  // namespace floorcast::cli
