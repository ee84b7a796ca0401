// `floorcast bench sim`: the front of bench_sim (bench/sim_bench.hpp).
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>

#include "cli_common.hpp"
#include "floorcast/bench/sim_bench.hpp"
#include "floorcast/floorplans/io.hpp"

namespace floorcast::cli {
namespace {

void register_bench_sim(CLI::App& root) {
  CLI::App& bench = group(root, "bench", "Benchmarks (medians over repeats, same-run ratios)");
  struct Options {
    std::string plan;
    int repeats = 9;
    bool json = false;
  };
  auto o = std::make_shared<Options>();
  auto* cmd = bench.add_subcommand("sim", "Scan renderer vs raw Embree stream throughput; default mono scan time");
  cmd->add_option("--plan", o->plan, "Floor plan (default: floorplans/buildings/campus.json)");
  cmd->add_option("--repeats", o->repeats, "Repeats per measurement (median reported)")
      ->capture_default_str()
      ->check(in_range(1, 1000));
  cmd->add_flag("--json", o->json, "Print JSON");
  cmd->callback([o] {
    std::string plan_path = o->plan;
    if (plan_path.empty()) plan_path = data_dir() + "/floorplans/buildings/campus.json";
    SimBenchParams params;
    params.repeats = o->repeats;
    const SimBenchResult r =
        bench_sim(load_floor_plan(plan_path), std::filesystem::path(plan_path).filename().string(), params);
    if (o->json) {
      std::cout << to_json(r).dump(2) << "\n";
      return;
    }
    std::cout << std::fixed << std::setprecision(2) << "plan:                  " << plan_path << " (" << r.triangles
              << " triangles, scene built in " << r.scene_build_ms << " ms)\n"
              << "pose:                  " << r.pose.x_m << ", " << r.pose.y_m << " (most open interior point)\n"
              << "threads:               " << r.threads << "\n"
              << "rays per mono scan:    " << r.rays_per_scan << " (6 x 640x480), " << 100.0 * r.hit_fraction << "% hit\n"
              << "renderer:              " << r.renderer_mrays_per_s << " Mrays/s (median of " << o->repeats << ")\n"
              << "raw Embree stream:     " << r.embree_raw_mrays_per_s << " Mrays/s (rtcIntersect1M, 256-ray chunks)\n"
              << "ratio:                 " << r.ratio << " (target >= 0.60)\n"
              << "mono scan (default):   " << r.scan_ms << " ms (target < 100); CPU time " << r.scan_cpu_ms
              << " ms (all threads)\n"
              << "load average (1 min):  " << r.load_average_1min << " (other processes compete for the cores)\n"
              << "lidar scan (default):  " << r.lidar_scan_ms << " ms\n"
              << "phone scan (default):  " << r.phone_scan_ms << " ms\n"
              << "OSMesa depth, 6 views: " << r.osmesa_6_views_ms << " ms (llvmpipe rasteriser, reference)\n"
              << "RGB views, 640x480:    " << r.rgb_frames_per_s_640x480 << " frames/s (colour + depth + labels; 6 views in "
              << r.rgb_6_views_ms << " ms)\n"
              << "OpenGL first use:      " << r.gl_first_use_ms << " ms (module load, context, shaders, mesh upload; "
              << r.gl_renderer << ")\n";
  });
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_bench_sim);
}  // namespace floorcast::cli
