// `floorcast bench observe`: the front of bench_observe (bench/observe_bench.hpp).
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>

#include "cli_common.hpp"
#include "floorcast/bench/observe_bench.hpp"
#include "floorcast/floorplans/io.hpp"

namespace floorcast::cli {
namespace {

std::string default_plan() {
  for (const char* name : {"campus.json", "office.json", "two_rooms.json"}) {
    const std::string p = data_dir() + "/floorplans/buildings/" + name;
    if (std::filesystem::exists(p)) return p;
  }
  throw InputError("bench observe: no shipped building found under floorplans/buildings/ (use --plan)");
}

void register_bench_observe(CLI::App& root) {
  CLI::App& bench = group(root, "bench", "Benchmarks (medians over repeats, same-run ratios)");
  struct Options {
    std::string plan;
    int scans = 5;
    int repeats = 3;
    bool json = false;
  };
  auto o = std::make_shared<Options>();
  auto* cmd = bench.add_subcommand("observe", "Observation module time per scan: mono (PALMS+) and LiDAR (PALMS) paths");
  cmd->add_option("--plan", o->plan, "Floor plan (default: the first shipped of campus, office, two_rooms)");
  cmd->add_option("--scans", o->scans, "Scans (poses) per path")->capture_default_str()->check(in_range(1, 100));
  cmd->add_option("--repeats", o->repeats, "Repeats per scan (median over all)")->capture_default_str()->check(in_range(1, 100));
  cmd->add_flag("--json", o->json, "Print JSON");
  cmd->callback([o] {
    const std::string plan_path = o->plan.empty() ? default_plan() : o->plan;
    ObserveBenchParams params;
    params.scans = o->scans;
    params.repeats = o->repeats;
    const ObserveBenchResult r = bench_observe(load_floor_plan(plan_path), plan_path, params);
    if (o->json) {
      std::cout << to_json(r).dump(2) << "\n";
      return;
    }
    std::cout << std::fixed << std::setprecision(3) << "bench observe: " << plan_path << ", " << o->scans << " scans x "
              << o->repeats << " repeats, " << r.threads << " threads, load average " << r.load_average_1min.value_or(0.0)
              << "\n";
    for (const ObserveBenchPath& d : r.paths) {
      std::cout << "  " << std::left << std::setw(6) << d.name << std::right << d.preset << " " << d.views << " views "
                << d.resolution << ": median " << d.median_s << " s wall (max " << d.max_s << " s), " << d.median_cpu_s
                << " s CPU, " << d.median_segments << " segments\n    stages:";
      for (const auto& [stage, v] : d.stage_median_s) std::cout << " " << stage << " " << v;
      std::cout << "\n";
    }
    std::cout << "  PALMS+ reports 20.4 s for point cloud reconstruction + scale alignment (Apple M2, Python); "
                 "target here <= 0.5 s per default mono scan on 2 cores\n";
  });
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_bench_observe);
}  // namespace floorcast::cli
