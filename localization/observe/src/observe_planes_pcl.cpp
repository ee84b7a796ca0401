// PCL-based plane extraction (RANSAC plane; normals + region growing) through the PCL back-end
// module (pcl_backend_api.hpp): no PCL header or library in the observe library itself.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "floorcast/core/math.hpp"
#include "floorcast/core/module.hpp"
#include "floorcast/observe/observe_planes.hpp"
#include "observe_pcl.hpp"
#include "pcl_backend_api.hpp"

namespace floorcast {
namespace detail {
namespace {

static_assert(sizeof(Eigen::Vector3f) == 3 * sizeof(float), "points are passed to PCL as packed x, y, z floats");

/// The back-end's functions, loaded once per process on first use.
const pcl_api::Functions& pcl_functions() {
  static const pcl_api::Functions* functions = [] {
    void* handle = load_module(pcl_api::kModuleName);
    const auto get = reinterpret_cast<pcl_api::GetFunctionsFn>(
        module_symbol(handle, pcl_api::kModuleName, pcl_api::kFunctionsSymbol));
    const pcl_api::Functions* f = get();
    if (f == nullptr || f->api_version != pcl_api::kApiVersion)
      throw std::runtime_error(std::string("floorcast module ") + pcl_api::kModuleName +
                               " is stale (interface version " + std::to_string(f ? f->api_version : -1) +
                               ", expected " + std::to_string(pcl_api::kApiVersion) + "): rebuild it");
    return f;
  }();
  return *functions;
}

const float* packed(const PointCloud3f& points) { return points.empty() ? nullptr : points.front().data(); }

}  // namespace

std::vector<Eigen::Vector3f> estimate_normals(const PointCloud3f& points, int k) {
  std::vector<Eigen::Vector3f> normals(points.size());
  if (points.empty()) return normals;
  pcl_functions().estimate_normals(packed(points), points.size(), k, normals.front().data());
  return normals;
}

RansacPlane ransac_plane(const PointCloud3f& points, double distance_m, int iterations) {
  RansacPlane out;
  if (points.empty()) return out;
  out.inliers.resize(points.size());
  double coefficients[4] = {0, 0, 0, 0};
  int coefficient_count = 0;
  const std::size_t count = pcl_functions().ransac_plane(packed(points), points.size(), distance_m, iterations,
                                                         out.inliers.data(), coefficients, &coefficient_count);
  out.inliers.resize(count);
  out.coefficients.assign(coefficients, coefficients + coefficient_count);
  return out;
}

}  // namespace detail

Plane3 fit_plane_ransac_pcl(const PointCloud3f& points, const RansacPlaneParams& params) {
  Plane3 plane;
  if (points.size() < 3) return plane;
  const detail::RansacPlane found = detail::ransac_plane(points, params.distance_m, params.iterations);
  if (found.inliers.size() < 3 || found.coefficients.size() != 4) return plane;
  if (params.refit_inliers) return fit_plane_pca(points, found.inliers);
  Eigen::Vector3d n(found.coefficients[0], found.coefficients[1], found.coefficients[2]);
  const double norm = n.norm();
  n /= norm;
  double d = -found.coefficients[3] / norm;
  if (d > 0.0) {
    n = -n;
    d = -d;
  }
  plane = fit_plane_pca(points, found.inliers);  // centroid, rms, indices
  plane.normal = n;
  plane.offset_m = d;
  double sq = 0.0;
  for (int i : plane.point_indices) {
    const double r = n.dot(points[i].cast<double>()) - d;
    sq += r * r;
  }
  plane.rms_m = std::sqrt(sq / plane.point_indices.size());
  return plane;
}

std::vector<Plane3> extract_planes_region_growing(const PointCloud3f& points,
                                                  const PclRegionGrowingParams& params) {
  std::vector<Plane3> planes;
  if (points.size() < 3) return planes;
  std::vector<int> indices(points.size());
  std::vector<int> sizes(points.size());
  const std::size_t clusters = detail::pcl_functions().region_growing(
      detail::packed(points), points.size(), params.normal_k, params.neighbours_k, params.min_cluster_points,
      static_cast<float>(params.smoothness_deg * kPi / 180.0), static_cast<float>(params.curvature_threshold),
      indices.data(), sizes.data());
  std::size_t used = 0;
  for (std::size_t i = 0; i < clusters; ++i) {
    const std::vector<int> c(indices.begin() + static_cast<std::ptrdiff_t>(used),
                             indices.begin() + static_cast<std::ptrdiff_t>(used + static_cast<std::size_t>(sizes[i])));
    used += static_cast<std::size_t>(sizes[i]);
    if (static_cast<int>(c.size()) < params.min_cluster_points) continue;
    planes.push_back(fit_plane_pca(points, c));
  }
  std::stable_sort(planes.begin(), planes.end(), [](const Plane3& a, const Plane3& b) {
    if (a.point_indices.size() != b.point_indices.size())
      return a.point_indices.size() > b.point_indices.size();
    return a.point_indices.front() < b.point_indices.front();
  });
  return planes;
}

}  // namespace floorcast
