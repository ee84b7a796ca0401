// `floorcast bench planes`: plane-extraction accuracy on simulated noisy planes (VoxelPlane-Reloc
// Table 2 protocol) for plain PCA, PCL RANSAC and the VoxelPlane extractor (+ ablations).
#include <iomanip>
#include <iostream>
#include <memory>

#include "cli_common.hpp"
#include "floorcast/bench/plane_accuracy.hpp"

namespace floorcast::cli {
namespace {

void register_bench_planes(CLI::App& root) {
  CLI::App& bench = group(root, "bench", "Benchmarks (medians over repeats, same-run ratios)");
  struct Options {
    int planes = 9;
    int points = 20000;
    std::uint64_t seed = 7;
    bool json = false;
  };
  auto o = std::make_shared<Options>();
  auto* cmd = bench.add_subcommand("planes", "Plane accuracy (angle, offset) on simulated noisy planes: PCA, PCL RANSAC, VoxelPlane");
  cmd->add_option("--planes", o->planes, "Planes per noise model (Table 2: 9)")->capture_default_str()->check(in_range(1, 1000));
  cmd->add_option("--points", o->points, "Points per plane")->capture_default_str()->check(in_range(100, 10000000));
  cmd->add_option("--seed", o->seed, "Seed of the simulated planes")->capture_default_str();
  cmd->add_flag("--json", o->json, "Print JSON");
  cmd->callback([o] {
    PlaneBenchParams bp;
    bp.planes = o->planes;
    bp.points_per_plane = o->points;
    bp.seed = o->seed;
    auto print = [&](const PlaneAccuracyReport& r) {
      if (o->json) return;
      const PlaneNoiseModel& noise = r.noise;
      std::cout << std::defaultfloat << "noise " << noise.name << " (sigma " << noise.sigma_const_m << " m + " << noise.sigma_quadratic_per_m
                << " r^2, outliers " << noise.outlier_fraction * 100.0 << "%), " << r.planes << " planes x "
                << r.points_per_plane << " points\n";
      std::cout << "  " << std::left << std::setw(24) << "method" << std::right << std::setw(12) << "alpha [deg]"
                << std::setw(10) << "d [m]" << std::setw(10) << "failed" << std::setw(12) << "time [ms]" << "\n";
      for (const PlaneMethodResult& mr : r.methods) {
        std::cout << "  " << std::left << std::setw(24) << mr.method << std::right << std::fixed << std::setprecision(3)
                  << std::setw(12) << mr.mean_angle_deg << std::setprecision(4) << std::setw(10) << mr.mean_offset_m
                  << std::setw(10) << mr.failures << std::setprecision(2) << std::setw(12) << mr.median_time_s * 1e3 << "\n";
      }
    };
    const PlaneBenchReport report = run_plane_bench(bp, print);
    if (o->json) std::cout << to_json(report).dump(2) << "\n";
  });
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_bench_planes);
}  // namespace floorcast::cli
