// PALMS+ ground plane: lowest points, near-vertical normals, RANSAC plane, mode of inlier heights.
#include <algorithm>
#include <cmath>
#include <map>

#include "floorcast/observe/observation_module.hpp"
#include "floorcast/core/math.hpp"
#include "observe_pcl.hpp"

namespace floorcast {

GroundPlaneResult detect_ground_plane(const PointCloud3f& points_scan, const GroundPlaneParams& params) {
  GroundPlaneResult res;
  const PointCloud3f cloud = voxel_downsample(points_scan, params.voxel_m);
  res.points = cloud.size();
  if (cloud.size() < 10) {
    res.reason = "fewer than 10 points";
    return res;
  }
  // The lowest fraction of points by height.
  std::vector<float> z(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) z[i] = cloud[i].z();
  const std::size_t k = std::clamp<std::size_t>(
      static_cast<std::size_t>(std::ceil(params.lowest_fraction * cloud.size())), 3, cloud.size());
  std::nth_element(z.begin(), z.begin() + static_cast<std::ptrdiff_t>(k - 1), z.end());
  const float z_cut = z[k - 1];
  PointCloud3f low;
  for (const auto& p : cloud) {
    if (p.z() <= z_cut) low.push_back(p);
  }
  // Keep those whose normal (k nearest neighbours among the low points) is near vertical.
  const std::vector<Eigen::Vector3f> normals = detail::estimate_normals(low, params.normal_k);
  const double cos_tilt = std::cos(params.max_normal_tilt_deg * kPi / 180.0);
  PointCloud3f candidates;
  for (std::size_t i = 0; i < low.size(); ++i) {
    const float nz = normals[i].z();
    if (std::isfinite(nz) && std::abs(nz) >= cos_tilt) candidates.push_back(low[i]);
  }
  res.candidates = candidates.size();
  if (candidates.size() < 3) {
    res.reason = "no low points with near-vertical normals";
    return res;
  }
  const detail::RansacPlane ransac =
      detail::ransac_plane(candidates, params.ransac_distance_m, params.ransac_iterations);
  const std::vector<int>& inliers = ransac.inliers;
  res.inliers = inliers.size();
  if (ransac.coefficients.size() == 4) {
    Eigen::Vector4d plane(ransac.coefficients[0], ransac.coefficients[1], ransac.coefficients[2],
                          ransac.coefficients[3]);
    plane /= plane.head<3>().norm();
    if (plane[2] < 0) plane = -plane;
    res.plane = plane;
  }
  if (static_cast<double>(res.inliers) < params.min_inlier_fraction * static_cast<double>(cloud.size()) ||
      res.inliers < 3) {
    res.reason = "RANSAC plane has " + std::to_string(res.inliers) + " inliers, fewer than " +
                 std::to_string(params.min_inlier_fraction * 100.0) + "% of " +
                 std::to_string(cloud.size()) + " points";
    return res;
  }
  // Mode of the inlier heights in fixed bins (ties: the lowest bin).
  std::map<long, int> bins;
  for (int i : inliers) {
    ++bins[static_cast<long>(std::floor(candidates[i].z() / params.height_bin_m))];
  }
  long mode_bin = bins.begin()->first;
  int mode_count = 0;
  for (const auto& [bin, count] : bins) {
    if (count > mode_count) {
      mode_bin = bin;
      mode_count = count;
    }
  }
  const double centre = (mode_bin + 0.5) * params.height_bin_m;
  res.height_m = centre;
  if (params.refine_height) {
    double sum = 0.0;
    int n = 0;
    for (int i : inliers) {
      const double zi = candidates[i].z();
      if (std::abs(zi - centre) <= params.height_bin_m) {
        sum += zi;
        ++n;
      }
    }
    if (n > 0) res.height_m = sum / n;
  }
  res.found = true;
  return res;
}

}  // namespace floorcast
