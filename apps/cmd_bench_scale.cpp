// `floorcast bench scale`: matcher time and peak memory against floor area. For each area a plan
// is generated (bench/scale_bench.hpp: an office below 5,000 m^2, campus buildings side by side
// above) and written to the work directory; then `floorcast bench match` runs on it in child
// processes, once for the kernel matcher and once for the ray matcher, so each matcher's peak
// resident memory (wait4) is its own: plan, precomputation, observations and matches, the
// bench's own side measurements included (the kernel's FFT floor probe, the ray matcher's
// exhaustive search and max-over-yaw map, which run beside the bounded search for the ratio).
// With --walls N,...: plans of N walls on one fixed area (bench/scale_bench.hpp many_walls_plan),
// each through `plan info`, `plan stats`, `plan validate`, `plan render` and the kernel matcher's
// set-up (`bench match`), every one a child process timed with wait4 (issue 28: nothing that pairs
// or searches walls may grow with the square of the wall count).
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>

#include "cli_common.hpp"
#include "floorcast/bench/match_bench.hpp"
#include "floorcast/bench/scale_bench.hpp"
#include "floorcast/core/file_io.hpp"
#include "floorcast/core/json_text.hpp"
#include "floorcast/floorplans/io.hpp"

namespace floorcast::cli {
namespace {

using Json = nlohmann::ordered_json;

/// A child's JSON output, through the one input layer and JSON reader.
Json read_child_json(const std::string& path) { return parse_ordered_json_text(read_text_file(path), path); }

void register_bench_scale(CLI::App& root) {
  struct Options {
    std::vector<double> areas = {2000.0, 10000.0, 40000.0, 100000.0};
    std::vector<double> walls;
    double walls_area = 100000.0;
    int rays = 36;
    int ray_bits = 16;
    int observations = 3;
    int orientations = 10;
    std::uint64_t seed = 1;
    std::string dir = "out/bench_scale";
    std::string old_dir;
    bool json = false;
  };
  auto o = std::make_shared<Options>();
  CLI::App& bench = group(root, "bench", "Benchmarks (medians over repeats, same-run ratios)");
  auto* cmd = bench.add_subcommand("scale", "Matcher time and peak memory vs floor area (child `bench match` per matcher and area)");
  cmd->add_option("--areas", o->areas, "Floor areas, m^2 (the smallest building the office generator makes: 500 m^2)")
      ->capture_default_str()
      ->delimiter(',')
      ->check(in_range(kMinScalePlanAreaM2, 1e6));
  CLI::Option* walls_opt =
      cmd->add_option("--walls", o->walls,
                      "Wall counts: plans of this many walls on --walls-area, timed through plan info/stats/validate/render "
                      "and the kernel matcher's set-up (without --areas, only these rows run)")
          ->delimiter(',')
          ->check(in_range(1.0, 1e6));
  cmd->add_option("--walls-area", o->walls_area, "Floor area of the --walls plans, m^2")
      ->capture_default_str()
      ->check(in_range(5000.0, 1e6));
  CLI::Option* areas_opt = cmd->get_option("--areas");
  cmd->add_option("--rays", o->rays, "Ray matcher directions")->capture_default_str()->check(in_range(4, 3600));
  cmd->add_option("--ray-bits", o->ray_bits, "Ray matcher distance volume bits (8 or 16)")->capture_default_str()->check(CLI::IsMember({8, 16}));
  cmd->add_option("--observations", o->observations, "Perfect observations per plan (medians)")
      ->capture_default_str()
      ->check(in_range(1, 1000));
  cmd->add_option("--orientations", o->orientations, "Kernel orientations (PALMS+ O = 10)")->capture_default_str()->check(in_range(0, 720));
  cmd->add_option("--seed", o->seed, "Seed of the plans and observation points")->capture_default_str();
  cmd->add_option("-o,--output", o->dir,
                                         "Output folder: the table as bench_scale.json, the generated plans and the "
                                         "children's JSON (a path ending in .json: deprecated, the table file)")
                             ->capture_default_str();
  // The old work-folder option (with -o FILE.json for the table, so it does not exclude -o).
  cmd->add_option("--dir", o->old_dir, "Deprecated: the work folder; use -o DIR")->group("")->each([](const std::string&) {
    deprecation_note("bench scale --dir", "bench scale -o DIR");
  });
  cmd->add_flag("--json", o->json, "Print JSON");
  cmd->callback([o, walls_opt, areas_opt] {
    // The old grammar: --dir was the work folder and -o FILE.json the table.
    std::string table_path = o->dir + "/bench_scale.json";
    if (std::filesystem::path(o->dir).extension() == ".json") {
      deprecation_note("bench scale -o FILE.json", "bench scale -o DIR (writes DIR/bench_scale.json)");
      table_path = o->dir;
      o->dir = "out/bench_scale";
    }
    if (!o->old_dir.empty()) o->dir = o->old_dir;
    ensure_directory(o->dir);
    const std::string exe = std::filesystem::read_symlink("/proc/self/exe").string();
    if (walls_opt->count() > 0 && areas_opt->count() == 0) o->areas.clear();
    Json rows = Json::array();
    if (!o->json && !o->areas.empty()) {
      std::cout << "area m^2 | plan | valid cells | kernel: precompute s, estimate+top-5 CPU s, estimate CPU s, peak MB | ray "
                << o->rays << " (" << o->ray_bits << "-bit): precompute s, volume MB, bounded top-5 CPU s, exhaustive CPU s, peak MB\n";
    }
    for (const double area : o->areas) {
      ScalePlanParams sp;
      sp.area_m2 = area;
      sp.seed = o->seed;
      const FloorPlan plan = scale_plan(sp);
      const std::string plan_path = o->dir + "/" + plan.name + ".json";
      save_floor_plan(plan, plan_path);
      const std::string seed = std::to_string(o->seed), obs = std::to_string(o->observations);
      const std::string kernel_out = o->dir + "/" + plan.name + ".kernel.json";
      const ChildCost kc = run_child(exe,
                                     {"bench", "match", "--plan", plan_path, "--observations", obs, "--seed", seed,
                                      "--orientations", std::to_string(o->orientations), "--rays", "0", "--bev-fov", "0", "--no-posteriors", "--json"},
                                     kernel_out, "bench scale (kernel, " + plan.name + ")");
      const std::string ray_out = o->dir + "/" + plan.name + ".ray.json";
      const ChildCost rc = run_child(exe,
                                     {"bench", "match", "--plan", plan_path, "--observations", obs, "--seed", seed,
                                      "--no-kernel", "--rays", std::to_string(o->rays), "--ray-bits", std::to_string(o->ray_bits),
                                      "--bev-fov", "0", "--no-posteriors", "--json"},
                                     ray_out, "bench scale (ray, " + plan.name + ")");
      const MatchBenchResult kb = read_match_bench(read_child_json(kernel_out), kernel_out);
      const MatchBenchResult rb = read_match_bench(read_child_json(ray_out), ray_out);
      if (!kb.kernel_measured || rb.ray.size() != 1 || rb.ray.front().directions != o->rays)
        throw InputError(kernel_out + ", " + ray_out + ": the children's bench match records lack the kernel or the " +
                         std::to_string(o->rays) + "-direction ray measurement");
      const KernelMatchBench& k = kb.kernel;
      const RayMatchBench& r = rb.ray.front();
      Json row;
      row["area_m2"] = area;
      row["plan"] = plan.name;
      row["walls"] = plan.walls.size();
      row["grid_px"] = {kb.grid_width_px, kb.grid_height_px};
      row["valid_cells"] = kb.valid_cells;
      row["kernel_precompute_wall_s"] = k.precompute_wall_s;
      row["kernel_precompute_mb"] = k.precompute_mb;
      row["kernel_modes_cpu_s"] = k.modes.cpu_s;
      row["kernel_argmax_cpu_s"] = k.argmax.cpu_s;
      row["kernel_process_cpu_s"] = kc.cpu_s;
      row["kernel_peak_mb"] = kc.max_rss_mb;
      row["ray_directions"] = o->rays;
      row["ray_volume_bits"] = o->ray_bits;
      row["ray_precompute_s"] = r.precompute_s;
      row["ray_volume_mb"] = r.volume_mb;
      row["ray_modes_cpu_s"] = r.modes.cpu_s;
      row["ray_exhaustive_cpu_s"] = r.modes_exhaustive.cpu_s;
      row["ray_cells_scored_share"] = r.cells_scored_share;
      row["ray_process_cpu_s"] = rc.cpu_s;
      row["ray_peak_mb"] = rc.max_rss_mb;
      rows.push_back(row);
      if (!o->json) {
        std::cout << std::fixed << std::setprecision(0) << area << " | " << plan.name << " | "
                  << row["valid_cells"].get<double>() << " | " << std::setprecision(2) << row["kernel_precompute_wall_s"].get<double>()
                  << ", " << std::setprecision(3) << row["kernel_modes_cpu_s"].get<double>() << ", "
                  << row["kernel_argmax_cpu_s"].get<double>() << ", " << std::setprecision(0) << kc.max_rss_mb << " | "
                  << std::setprecision(2) << row["ray_precompute_s"].get<double>() << ", " << std::setprecision(0)
                  << row["ray_volume_mb"].get<double>() << ", " << std::setprecision(3) << row["ray_modes_cpu_s"].get<double>()
                  << ", " << row["ray_exhaustive_cpu_s"].get<double>() << ", " << std::setprecision(0) << rc.max_rss_mb
                  << std::endl;
      }
    }
    // Wall counts: each command a child process, its wall time, CPU time and peak memory.
    Json wall_rows = Json::array();
    if (!o->json && !o->walls.empty()) {
      std::cout << "walls | area m^2 | info s | stats s | validate s | render s | kernel set-up s (precompute) | peak MB (max)\n";
    }
    for (const double target : o->walls) {
      ScalePlanParams sp;
      sp.area_m2 = o->walls_area;
      sp.seed = o->seed;
      const FloorPlan plan = many_walls_plan(sp, static_cast<std::size_t>(target));
      const std::string plan_path = o->dir + "/" + plan.name + ".json";
      save_floor_plan(plan, plan_path);
      Json row;
      row["walls_requested"] = target;
      row["walls"] = plan.walls.size();
      row["doors"] = plan.doors.size();
      row["area_m2"] = o->walls_area;
      auto timed = [&](const std::string& key, const std::vector<std::string>& args, const std::string& out_file) {
        const ChildCost c = run_child(exe, args, out_file, "bench scale (" + key + ", " + plan.name + ")");
        row[key] = {{"wall_s", c.wall_s}, {"cpu_s", c.cpu_s}, {"peak_mb", c.max_rss_mb}};
        return c;
      };
      timed("info", {"plan", "info", plan_path, "--json"}, "");
      timed("stats", {"plan", "stats", plan_path, "--json"}, "");
      timed("validate", {"plan", "validate", plan_path}, "");
      timed("render", {"plan", "render", plan_path, "-o", o->dir + "/" + plan.name + ".png"}, "");
      const std::string kernel_out = o->dir + "/" + plan.name + ".kernel.json";
      timed("kernel",
            {"bench", "match", "--plan", plan_path, "--observations", "1", "--seed", std::to_string(o->seed), "--orientations",
             std::to_string(o->orientations), "--rays", "0", "--bev-fov", "0", "--no-posteriors", "--json"},
            kernel_out);
      const MatchBenchResult kb = read_match_bench(read_child_json(kernel_out), kernel_out);
      row["kernel"]["precompute_wall_s"] = kb.kernel_measured ? kb.kernel.precompute_wall_s : std::nan("");
      wall_rows.push_back(row);
      if (!o->json) {
        double peak = 0.0;
        for (const char* k : {"info", "stats", "validate", "render", "kernel"}) peak = std::max(peak, row[k]["peak_mb"].get<double>());
        std::cout << std::fixed << std::setprecision(1) << plan.walls.size() << " | " << std::setprecision(0) << o->walls_area
                  << " | " << std::setprecision(2) << row["info"]["wall_s"].get<double>() << " | "
                  << row["stats"]["wall_s"].get<double>() << " | " << row["validate"]["wall_s"].get<double>() << " | "
                  << row["render"]["wall_s"].get<double>() << " | " << row["kernel"]["wall_s"].get<double>() << " ("
                  << row["kernel"]["precompute_wall_s"].get<double>() << ") | " << std::setprecision(0) << peak << std::endl;
      }
    }
    Json out;
    out["observations"] = o->observations;
    out["seed"] = o->seed;
    out["rows"] = rows;
    if (!wall_rows.empty()) out["wall_rows"] = wall_rows;
    write_json(table_path, out);
    if (o->json) std::cout << out.dump(2) << "\n";
  });
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_bench_scale);
}  // namespace floorcast::cli
