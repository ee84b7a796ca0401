// Plane-extraction accuracy on simulated noisy planes, the way VoxelPlane-Reloc's Table 2
// measures it: points on a known plane 1-9 m from a depth camera at the origin, Gaussian noise
// along the plane normal; each extractor's plane is compared with the truth by the angle between
// normals (alpha, deg) and the offset difference (d, m).
#pragma once

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "floorcast/observe/observe_planes.hpp"

namespace floorcast {

/// How the simulated points are perturbed.
struct PlaneNoiseModel {
  std::string name = "depth";
  /// Noise along the normal: sigma = sigma_const_m + sigma_quadratic_per_m * range^2 (a ToF/
  /// structured-light camera's error grows with the square of the range).
  double sigma_const_m = 0.0;
  double sigma_quadratic_per_m = 0.0025;
  /// Fraction of points replaced by outliers uniform in the points' bounding box grown by
  /// outlier_margin_m (flying pixels, clutter).
  double outlier_fraction = 0.0;
  double outlier_margin_m = 1.0;
};

/// The conditions the benchmark reports: "gaussian" (2 cm everywhere: plain PCA is the
/// maximum-likelihood estimate), "gaussian+outliers" (plus 5% outliers), "depth" (0.25 cm x
/// range^2, a structured-light camera: 20 cm at 9 m), "depth+outliers".
std::vector<PlaneNoiseModel> standard_plane_noise_models();

struct PlaneCase {
  Eigen::Vector3d normal;  ///< truth, oriented towards the camera (offset < 0)
  double offset_m = 0.0;
  PointCloud3f points;
};

/// Plane `index` of a benchmark run: a random plane facing the camera (normal within 70 deg of
/// the viewing direction) with `num_points` points at ranges 1-9 m, perturbed per `noise`.
/// Deterministic in (seed, index).
PlaneCase make_plane_case(int index, const PlaneNoiseModel& noise, int num_points, std::uint64_t seed);

struct PlaneMethodResult {
  std::string method;
  std::vector<double> angle_error_deg;  ///< per plane
  std::vector<double> offset_error_m;
  double mean_angle_deg = 0.0;  ///< over planes where the method returned a plane
  double mean_offset_m = 0.0;
  int failures = 0;             ///< planes where it returned none (errors NaN)
  double median_time_s = 0.0;  ///< per plane
};

struct PlaneAccuracyReport {
  PlaneNoiseModel noise;
  int planes = 0;
  int points_per_plane = 0;
  std::vector<PlaneMethodResult> methods;
};

struct PlaneBenchParams {
  int planes = 9;               ///< Table 2 has 9
  int points_per_plane = 20000;
  std::uint64_t seed = 7;
  RansacPlaneParams ransac;     ///< PCL RANSAC baseline
  VoxelPlaneParams voxel_plane;
};

/// Runs every method on `planes` simulated planes: "pca" (plain PCA on all points),
/// "pcl_ransac" (PCL RANSAC + least-squares refit on its inliers), "voxelplane" (the full
/// extractor; its largest plane), "voxelplane_no_weights" (VR-NE ablation: W_i = 1),
/// "voxelplane_no_merge" (VR-NM ablation: no under-grown merging).
PlaneAccuracyReport run_plane_accuracy(const PlaneNoiseModel& noise, const PlaneBenchParams& params);

/// `floorcast bench planes`: every standard noise model (standard_plane_noise_models(), in order)
/// run with the same parameters.
struct PlaneBenchReport {
  PlaneBenchParams params;
  std::vector<PlaneAccuracyReport> models;
};

/// Runs every standard noise model; `on_model` (optional) sees each model's report as it is done.
PlaneBenchReport run_plane_bench(const PlaneBenchParams& params,
                                 const std::function<void(const PlaneAccuracyReport&)>& on_model = {});

/// The result document of `bench planes --json`: the protocol, every parameter (RANSAC and the
/// VoxelPlane extractor in full), per noise model and method the errors of every plane (null where
/// the method found no plane), their means, failures and the median time.
nlohmann::ordered_json to_json(const PlaneBenchReport& report);

}  // namespace floorcast
