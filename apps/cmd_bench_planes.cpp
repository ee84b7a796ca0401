// `floorcast bench planes`: plane-extraction accuracy on simulated noisy planes (VoxelPlane-Reloc
// Table 2 protocol) for plain PCA, PCL RANSAC and the VoxelPlane extractor (+ ablations).
#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>

#include "cli_common.hpp"
#include "floorcast/bench/plane_accuracy.hpp"

namespace floorcast::cli {
namespace {

nlohmann::ordered_json num(double v) { return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(nullptr); }

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
  cmd->add_option("--planes", o->planes, "Planes per noise model (Table 2: 9)")->capture_default_str()->check(CLI::Range(1, 1000));
  cmd->add_option("--points", o->points, "Points per plane")->capture_default_str()->check(CLI::Range(100, 10000000));
  cmd->add_option("--seed", o->seed, "Seed of the simulated planes")->capture_default_str();
  cmd->add_flag("--json", o->json, "Print JSON");
  cmd->callback([o] {
    PlaneBenchParams bp;
    bp.planes = o->planes;
    bp.points_per_plane = o->points;
    bp.seed = o->seed;
    nlohmann::ordered_json j;
    j["protocol"] = "VoxelPlane-Reloc Table 2: points on a known plane 1-9 m from a camera at the origin, "
                    "Gaussian noise along the normal; alpha = angle between normals (deg), d = offset difference (m)";
    j["planes"] = o->planes;
    j["points_per_plane"] = o->points;
    j["seed"] = o->seed;
    j["ransac"] = {{"distance_m", bp.ransac.distance_m}, {"iterations", bp.ransac.iterations}, {"refit_inliers", bp.ransac.refit_inliers}};
    const VoxelPlaneParams& vp = bp.voxel_plane;
    j["voxelplane"] = {{"voxel_size_m", vp.voxel_size_m},     {"max_subdivisions", vp.max_subdivisions},
                       {"max_thickness_m", vp.max_thickness_m}, {"max_eigen_ratio", vp.max_eigen_ratio},
                       {"weight_alpha", vp.weight_alpha},     {"weight_beta", vp.weight_beta},
                       {"growth_max_normal_deg", vp.growth_max_normal_deg}, {"growth_max_offset_m", vp.growth_max_offset_m}};
    j["models"] = nlohmann::ordered_json::array();
    for (const PlaneNoiseModel& noise : standard_plane_noise_models()) {
      const PlaneAccuracyReport r = run_plane_accuracy(noise, bp);
      nlohmann::ordered_json m;
      m["noise"] = {{"name", noise.name},
                    {"sigma_const_m", noise.sigma_const_m},
                    {"sigma_quadratic_per_m", noise.sigma_quadratic_per_m},
                    {"outlier_fraction", noise.outlier_fraction}};
      for (const PlaneMethodResult& mr : r.methods) {
        nlohmann::ordered_json x;
        x["mean_angle_deg"] = num(mr.mean_angle_deg);
        x["mean_offset_m"] = num(mr.mean_offset_m);
        x["failures"] = mr.failures;
        x["median_time_s"] = mr.median_time_s;
        x["angle_deg"] = nlohmann::ordered_json::array();
        x["offset_m"] = nlohmann::ordered_json::array();
        for (std::size_t k = 0; k < mr.angle_error_deg.size(); ++k) {
          x["angle_deg"].push_back(num(mr.angle_error_deg[k]));
          x["offset_m"].push_back(num(mr.offset_error_m[k]));
        }
        m["methods"][mr.method] = x;
      }
      j["models"].push_back(m);
      if (o->json) continue;
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
    }
    if (o->json) std::cout << j.dump(2) << "\n";
  });
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_bench_planes);
}  // namespace floorcast::cli
