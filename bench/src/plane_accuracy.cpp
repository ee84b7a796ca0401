// Simulated noisy planes (VoxelPlane-Reloc Table 2 protocol) and the plane-accuracy comparison.
#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>

#include "floorcast/bench/plane_accuracy.hpp"
#include "floorcast/core/fields.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/core/random.hpp"
#include "floorcast/observe/observation_module.hpp"

namespace floorcast {
namespace {


/// Small portable generator (splitmix64 stream): same numbers on every platform.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    const std::uint64_t z = mix64(state_);
    state_ += 0x9e3779b97f4a7c15ULL;
    return z;
  }
  double uniform() { return (next() >> 11) * (1.0 / 9007199254740992.0); }  // [0, 1)
  double uniform(double a, double b) { return a + (b - a) * uniform(); }
  double gaussian() {  // Box-Muller
    const double u1 = std::max(uniform(), 1e-300), u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
  }
  Eigen::Vector3d unit_vector() {
    const double z = uniform(-1.0, 1.0), a = uniform(0.0, 2.0 * kPi), r = std::sqrt(1.0 - z * z);
    return {r * std::cos(a), r * std::sin(a), z};
  }

 private:
  std::uint64_t state_;
};

/// A unit vector within max_angle of axis, uniform over the spherical cap.
Eigen::Vector3d in_cone(Rng& rng, const Eigen::Vector3d& axis, double max_angle_rad) {
  const double cos_max = std::cos(max_angle_rad);
  const double c = rng.uniform(cos_max, 1.0), a = rng.uniform(0.0, 2.0 * kPi), s = std::sqrt(1.0 - c * c);
  Eigen::Vector3d e1 = axis.unitOrthogonal(), e2 = axis.cross(e1);
  return (c * axis + s * std::cos(a) * e1 + s * std::sin(a) * e2).normalized();
}

}  // namespace

std::vector<PlaneNoiseModel> standard_plane_noise_models() {
  PlaneNoiseModel gaussian;
  gaussian.name = "gaussian";
  gaussian.sigma_const_m = 0.02;
  gaussian.sigma_quadratic_per_m = 0.0;
  PlaneNoiseModel gaussian_outliers = gaussian;
  gaussian_outliers.name = "gaussian+outliers";
  gaussian_outliers.outlier_fraction = 0.05;
  PlaneNoiseModel depth;
  depth.name = "depth";
  PlaneNoiseModel depth_outliers = depth;
  depth_outliers.name = "depth+outliers";
  depth_outliers.outlier_fraction = 0.05;
  return {gaussian, gaussian_outliers, depth, depth_outliers};
}

PlaneCase make_plane_case(int index, const PlaneNoiseModel& noise, int num_points, std::uint64_t seed) {
  Rng rng(seed * 0x100000001b3ULL + static_cast<std::uint64_t>(index) * 0x9e3779b97f4a7c15ULL + 1);
  const Eigen::Vector3d view = in_cone(rng, Eigen::Vector3d::UnitZ(), 30.0 * kPi / 180.0);
  const Eigen::Vector3d centre = 5.0 * view;
  PlaneCase pc;
  pc.normal = in_cone(rng, -view, 70.0 * kPi / 180.0);
  pc.offset_m = pc.normal.dot(centre);
  if (pc.offset_m > 0.0) {
    pc.normal = -pc.normal;
    pc.offset_m = -pc.offset_m;
  }
  const Eigen::Vector3d e1 = pc.normal.unitOrthogonal(), e2 = pc.normal.cross(e1);
  pc.points.reserve(num_points);
  for (int tries = 0; static_cast<int>(pc.points.size()) < num_points && tries < 100 * num_points; ++tries) {
    const Eigen::Vector3d p = centre + rng.uniform(-8.0, 8.0) * e1 + rng.uniform(-8.0, 8.0) * e2;
    const double range = p.norm();
    if (range < 1.0 || range > 9.0 || p.z() <= 0.0) continue;  // 1-9 m, in front of the camera
    const double sigma = noise.sigma_const_m + noise.sigma_quadratic_per_m * range * range;
    pc.points.push_back((p + sigma * rng.gaussian() * pc.normal).cast<float>());
  }
  if (noise.outlier_fraction > 0.0 && !pc.points.empty()) {
    Eigen::Vector3f lo = pc.points[0], hi = pc.points[0];
    for (const auto& p : pc.points) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    lo.array() -= static_cast<float>(noise.outlier_margin_m);
    hi.array() += static_cast<float>(noise.outlier_margin_m);
    for (auto& p : pc.points) {
      if (rng.uniform() >= noise.outlier_fraction) continue;
      for (int a = 0; a < 3; ++a) p[a] = static_cast<float>(rng.uniform(lo[a], hi[a]));
    }
  }
  return pc;
}

PlaneAccuracyReport run_plane_accuracy(const PlaneNoiseModel& noise, const PlaneBenchParams& params) {
  PlaneAccuracyReport report;
  report.noise = noise;
  report.planes = params.planes;
  report.points_per_plane = params.points_per_plane;
  using Extractor = std::function<bool(const PointCloud3f&, Plane3&)>;
  auto voxel = [](VoxelPlaneParams vp) {
    return Extractor([vp](const PointCloud3f& pts, Plane3& out) {
      const VoxelPlaneResult r = extract_planes_voxel(pts, vp);
      if (r.planes.empty()) return false;
      out = r.planes.front();
      return true;
    });
  };
  VoxelPlaneParams no_weights = params.voxel_plane;
  no_weights.adaptive_weights = false;
  VoxelPlaneParams no_merge = params.voxel_plane;
  no_merge.merge_undergrown = false;
  const RansacPlaneParams ransac = params.ransac;
  const std::vector<std::pair<std::string, Extractor>> methods = {
      {"pca",
       [](const PointCloud3f& pts, Plane3& out) {
         out = fit_plane_pca(pts);
         return true;
       }},
      {"pcl_ransac",
       [ransac](const PointCloud3f& pts, Plane3& out) {
         out = fit_plane_ransac_pcl(pts, ransac);
         return !out.point_indices.empty();
       }},
      {"voxelplane", voxel(params.voxel_plane)},
      {"voxelplane_no_weights", voxel(no_weights)},
      {"voxelplane_no_merge", voxel(no_merge)},
  };
  std::vector<PlaneCase> cases;
  for (int k = 0; k < params.planes; ++k) {
    cases.push_back(make_plane_case(k, noise, params.points_per_plane, params.seed));
  }
  for (const auto& [name, fn] : methods) {
    PlaneMethodResult m;
    m.method = name;
    std::vector<double> times;
    double sum_a = 0.0, sum_d = 0.0;
    for (const PlaneCase& pc : cases) {
      Plane3 plane;
      const auto t0 = std::chrono::steady_clock::now();
      const bool ok = fn(pc.points, plane);
      times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      if (!ok) {
        ++m.failures;
        m.angle_error_deg.push_back(std::numeric_limits<double>::quiet_NaN());
        m.offset_error_m.push_back(std::numeric_limits<double>::quiet_NaN());
        continue;
      }
      m.angle_error_deg.push_back(plane_angle_error_deg(pc.normal, plane.normal));
      m.offset_error_m.push_back(plane_offset_error_m(pc.normal, pc.offset_m, plane.normal, plane.offset_m));
      sum_a += m.angle_error_deg.back();
      sum_d += m.offset_error_m.back();
    }
    const int ok = params.planes - m.failures;
    m.mean_angle_deg = ok > 0 ? sum_a / ok : std::numeric_limits<double>::quiet_NaN();
    m.mean_offset_m = ok > 0 ? sum_d / ok : std::numeric_limits<double>::quiet_NaN();
    m.median_time_s = median(times);
    report.methods.push_back(std::move(m));
  }
  return report;
}

PlaneBenchReport run_plane_bench(const PlaneBenchParams& params,
                                 const std::function<void(const PlaneAccuracyReport&)>& on_model) {
  PlaneBenchReport report;
  report.params = params;
  for (const PlaneNoiseModel& noise : standard_plane_noise_models()) {
    report.models.push_back(run_plane_accuracy(noise, params));
    if (on_model) on_model(report.models.back());
  }
  return report;
}

nlohmann::ordered_json to_json(const PlaneBenchReport& report) {
  constexpr double kAny = 1e300;
  using RP = RansacPlaneParams;
  static const FieldList<RP> ransac =
      FieldList<RP>("bench planes ransac")
          .number("distance_m", &RP::distance_m, 0.0, kAny, "inlier distance, m")
          .integer("iterations", &RP::iterations, 1, 1 << 30, "RANSAC iterations")
          .flag("refit_inliers", &RP::refit_inliers, "least-squares refit on the inliers (PCL optimizeCoefficients)");
  using P = PlaneBenchParams;
  static const FieldList<P> params =
      FieldList<P>("bench planes")
          .integer("planes", &P::planes, 1, 1 << 30, "planes per noise model (Table 2: 9)")
          .integer("points_per_plane", &P::points_per_plane, 1, 1 << 30, "points per plane")
          .unsigned_integer("seed", &P::seed, "seed of the simulated planes")
          .section("ransac", &P::ransac, ransac)
          .section("voxelplane", &P::voxel_plane, voxel_plane_fields());
  using N = PlaneNoiseModel;
  static const FieldList<N> noise =
      FieldList<N>("noise model")
          .text("name", &N::name, "gaussian | gaussian+outliers | depth | depth+outliers")
          .number("sigma_const_m", &N::sigma_const_m, 0.0, kAny, "noise along the normal, constant part, m")
          .number("sigma_quadratic_per_m", &N::sigma_quadratic_per_m, 0.0, kAny, "noise along the normal per range^2, 1/m")
          .number("outlier_fraction", &N::outlier_fraction, 0.0, 1.0, "points replaced by outliers")
          .number("outlier_margin_m", &N::outlier_margin_m, 0.0, kAny, "outlier box margin, m");
  // Per plane: null where the method found no plane (the JSON form of NaN).
  using M = PlaneMethodResult;
  static const FieldList<M> method =
      FieldList<M>("method")
          .number("mean_angle_deg", &M::mean_angle_deg, 0.0, 180.0, "mean alpha over the planes found, deg")
          .number("mean_offset_m", &M::mean_offset_m, 0.0, kAny, "mean d over the planes found, m")
          .integer("failures", &M::failures, 0, 1 << 30, "planes where the method found none")
          .number("median_time_s", &M::median_time_s, 0.0, kAny, "median time per plane, s")
          .series("angle_deg", &M::angle_error_deg, "alpha per plane, deg")
          .series("offset_m", &M::offset_error_m, "d per plane, m");
  using R = PlaneAccuracyReport;
  static const FieldList<R> model =
      FieldList<R>("noise model result")
          .section("noise", &R::noise, noise)
          .custom(
              "methods",
              [](nlohmann::ordered_json& j, const R& r) {
                nlohmann::ordered_json by_name = nlohmann::ordered_json::object();
                for (const M& m : r.methods) by_name[m.method] = method.write(m);
                j["methods"] = std::move(by_name);
              },
              [](ParamReader& r, R&) { r.fail("methods", "is written, not read"); }, "object",
              "per method (pca, pcl_ransac, voxelplane and its ablations) its errors and time");
  using B = PlaneBenchReport;
  static const FieldList<B> document =
      FieldList<B>("bench planes result")
          .custom(
              "protocol",
              [](nlohmann::ordered_json& j, const B&) {
                j["protocol"] =
                    "VoxelPlane-Reloc Table 2: points on a known plane 1-9 m from a camera at the origin, Gaussian "
                    "noise along the normal; alpha = angle between normals (deg), d = offset difference (m)";
              },
              [](ParamReader& r, B&) { r.fail("protocol", "is written, not read"); }, "text", "what was measured")
          .flatten(&B::params, params)
          .list("models", &B::models, model);
  return document.write(report);
}

}  // namespace floorcast
