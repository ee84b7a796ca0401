// `floorcast compare-matchers PLAN...`: the perfect-observation comparison of PALMS+ sec. 4.4 —
// kernel vs ray matchers on seeded observation points, scored automatically.
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

#include "cli_common.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/localization/compare_matchers.hpp"

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

void register_compare_matchers(CLI::App& root) {
  struct Options {
    std::vector<std::string> plans;
    int points = 50;
    std::uint64_t seed = 1;
    std::string rays = "36,180";
    double clearance_m = 0.5;
    double range_m = 10.0;
    std::string orientations = "palms+";
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
  cmd->add_option("-o,--output", o->out, "Output folder")->required();
  cmd->callback([o] {
    std::vector<NamedPlan> plans;
    for (const std::string& path : o->plans) {
      std::string name = std::filesystem::path(path).stem().string();
      for (const NamedPlan& p : plans) {
        if (p.name == name) name = path;  // two files with one stem: keep them apart
      }
      plans.push_back({name, load_floor_plan(path)});
    }
    ComparisonParams params;
    params.points_per_plan = o->points;
    params.seed = o->seed;
    params.clearance_m = o->clearance_m;
    params.observation.max_range_m = o->range_m;
    params.observation.doors_closed = true;
    params.observation.num_rays = 36;
    std::vector<MatcherSpec> specs = default_comparison_specs(parse_ray_counts(o->rays));
    specs[0].overrides["orientations"] = o->orientations;
    specs[0].overrides["max_range_m"] = o->range_m;
    for (std::size_t i = 1; i < specs.size(); ++i) specs[i].overrides["max_range_m"] = o->range_m;

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
    run["observation"] = {{"max_range_m", o->range_m}, {"doors_closed", true}, {"rays", 36}};
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
