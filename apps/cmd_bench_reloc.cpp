// `floorcast bench reloc`: CPU cost of one plane relocalization (VoxelPlane-Reloc) per simulated
// scan, plane extraction included, map planes precomputed once per plan.
#include <iomanip>
#include <iostream>
#include <memory>

#include "cli_common.hpp"
#include "floorcast/bench/reloc_bench.hpp"
#include "floorcast/core/json_text.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/scenarios/sampling.hpp"
#include "floorcast/sim/mesh.hpp"
#include "floorcast/sim/ray_scene.hpp"
#include "floorcast/sim/scan_params.hpp"
#include "floorcast/sim/scan_sim.hpp"

namespace floorcast::cli {
namespace {

void register_bench_reloc(CLI::App& root) {
  CLI::App& bench = group(root, "bench", "Benchmarks (medians over repeats, same-run ratios)");
  struct Options {
    std::vector<std::string> plans;
    int scans = 10;
    std::uint64_t seed = 1;
    std::string sensor = "lidar";
    int repeats = 3;
    std::vector<std::string> params;
    bool json = false;
  };
  auto o = std::make_shared<Options>();
  auto* cmd = bench.add_subcommand(
      "reloc", "Plane relocalization (planes matcher) CPU per scan, plane extraction included, map planes precomputed "
               "once per plan (default plans: the calibrated office and campus)");
  cmd->add_option("--plan", o->plans, "Floor-plan JSON (repeatable)");
  cmd->add_option("--scans", o->scans, "Simulated scans per plan")->capture_default_str()->check(CLI::Range(1, 10000));
  cmd->add_option("--seed", o->seed, "Pose sampling seed (scan noise seed = seed + scan index)")->capture_default_str();
  cmd->add_option("--sensor", o->sensor, "Scan preset (metric depth: the LiDAR observation path)")
      ->capture_default_str()
      ->check(CLI::IsMember({"lidar", "depth_camera", "perfect"}));
  cmd->add_option("--repeats", o->repeats, "Timed runs per scan (median)")->capture_default_str()->check(CLI::Range(1, 100));
  cmd->add_option("--matcher-param", o->params, "planes matcher parameter KEY=VALUE (repeatable; keys as in its parameters)");
  cmd->add_flag("--json", o->json, "Print JSON");
  cmd->callback([o] {
    if (o->plans.empty()) {
      o->plans = {data_dir() + "/floorplans/buildings/office_calibrated.json",
                  data_dir() + "/floorplans/buildings/campus_calibrated.json"};
    }
    RelocBenchParams bp;
    bp.repeats = o->repeats;
    for (const std::string& p : o->params) add_override(bp.matcher_overrides, p, "--matcher-param");
    const ScanParams preset = scan_preset(o->sensor);
    bp.observe.path = ObservationPath::kLidar;
    bp.observe.lidar.max_range_m = preset.sensor.max_range_m;
    bp.shared.range_m = preset.sensor.max_range_m;
    RelocBenchReport report;
    report.sensor = o->sensor;
    report.seed = o->seed;
    for (std::size_t pi = 0; pi < o->plans.size(); ++pi) {
      const FloorPlan plan = load_floor_plan(o->plans[pi]);
      const RayScene scene(extrude_plan(plan));
      const std::vector<Pose2> poses = sample_observation_poses(plan, o->scans, o->seed, static_cast<int>(pi), 0.5);
      std::vector<RelocBenchScan> scans;
      for (std::size_t k = 0; k < poses.size(); ++k) {
        ScanParams sp = preset;
        sp.seed = o->seed + k;
        scans.push_back({simulate_scan(scene, poses[k], sp).scan, poses[k]});
      }
      RelocBenchResult r = bench_reloc(plan, scans, bp);
      r.plan = o->plans[pi];
      if (!o->json) {
        auto ms = [](const RelocBenchStat& s, bool p90) { return 1e3 * (p90 ? s.p90 : s.median); };
        std::cout << std::fixed << std::setprecision(1) << o->plans[pi] << ": " << scans.size() << " " << o->sensor
                  << " scans, " << r.map_planes << " map planes (precompute " << r.precompute_cpu_s << " s CPU)\n"
                  << "  relocalization (extraction + matching) median " << ms(r.relocalization_cpu_s, false)
                  << " ms CPU, p90 " << ms(r.relocalization_cpu_s, true) << " ms: extraction "
                  << ms(r.extraction_cpu_s, false) << " ms, matching " << ms(r.match_cpu_s, false)
                  << " ms; sensor preprocessing " << ms(r.preprocess_cpu_s, false) << " ms, whole observation module "
                  << ms(r.observe_module_cpu_s, false) << " ms\n  localized " << r.localized << " of " << scans.size()
                  << ", within 1 m 30 deg " << r.within_1m_30deg << "\n";
      }
      report.plans.push_back(std::move(r));
    }
    if (o->json) std::cout << to_json(report).dump(2) << "\n";
  });
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_bench_reloc);
}  // namespace floorcast::cli
