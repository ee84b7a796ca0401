// Private PCL calls of the observation module (only included by observe_*.cpp files). PCL itself
// lives in the back-end module floorcast_pcl.so (pcl_backend_api.hpp), loaded on first use.
#pragma once

#include <vector>

#include "floorcast/observe/observe_planes.hpp"

namespace floorcast::detail {

/// Normals from k nearest neighbours, oriented towards the scan origin (the sensor); NaN where
/// undefined (too few distinct neighbours).
std::vector<Eigen::Vector3f> estimate_normals(const PointCloud3f& points, int k);

/// PCL's RANSAC plane: inlier indices and the plane's a, b, c, d (empty when none was found).
struct RansacPlane {
  std::vector<int> inliers;
  std::vector<double> coefficients;
};
RansacPlane ransac_plane(const PointCloud3f& points, double distance_m, int iterations);

}  // namespace floorcast::detail
