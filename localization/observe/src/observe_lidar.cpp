// PALMS LiDAR path: vertical planes of the scan cloud, each turned into a 2D segment spanning its
// extent.
#include <algorithm>
#include <cmath>

#include "floorcast/observe/observation_module.hpp"
#include "floorcast/core/math.hpp"

namespace floorcast {

WallPlaneResult extract_wall_segments(const PointCloud3f& points_scan, const LidarPathParams& params) {
  WallPlaneResult res;
  if (params.extractor == PlaneExtractorKind::kVoxelPlane) {
    res.planes = extract_planes_voxel(points_scan, params.voxel_plane).planes;
  } else {
    res.planes = extract_planes_region_growing(points_scan, params.pcl);
  }
  const double sin_tilt = std::sin(params.max_wall_tilt_deg * kPi / 180.0);
  for (std::size_t k = 0; k < res.planes.size(); ++k) {
    const Plane3& pl = res.planes[k];
    if (std::abs(pl.normal.z()) > sin_tilt) continue;  // not vertical
    const Vec2 n2 = pl.normal.head<2>().normalized();
    const Vec2 t(-n2.y(), n2.x());
    const double offset = n2.dot(pl.centroid_m.head<2>());
    double a_min = 1e300, a_max = -1e300, z_min = 1e300, z_max = -1e300;
    for (int i : pl.point_indices) {
      const auto& p = points_scan[i];
      const double along = t.x() * p.x() + t.y() * p.y();
      a_min = std::min(a_min, along);
      a_max = std::max(a_max, along);
      z_min = std::min(z_min, static_cast<double>(p.z()));
      z_max = std::max(z_max, static_cast<double>(p.z()));
    }
    if (a_max - a_min < params.min_wall_width_m || z_max - z_min < params.min_wall_height_m) continue;
    if (params.require_camera_height &&
        (z_max < -params.wall_band_half_height_m || z_min > params.wall_band_half_height_m)) {
      continue;
    }
    Segment2 s;
    s.a_m = offset * n2 + a_min * t;
    s.b_m = offset * n2 + a_max * t;
    orient_observer_left(s);
    res.segments_m.push_back(s);
    res.wall_planes.push_back(static_cast<int>(k));
  }
  return res;
}

std::vector<PlanePatch> plane_patches(const PointCloud3f& cloud, const std::vector<Plane3>& planes,
                                      const PlanePatchParams& params) {
  std::vector<PlanePatch> out;
  std::vector<Eigen::Vector3d> pts;
  for (const Plane3& pl : planes) {
    pts.clear();
    for (int i : pl.point_indices) pts.push_back(cloud[static_cast<std::size_t>(i)].cast<double>());
    PlanePatch patch = make_plane_patch(pl.normal, pl.offset_m, pts, params.cell_m, params.min_points_per_cell);
    if (patch_area_m2(patch, params.cell_m) < params.min_area_m2) continue;
    out.push_back(std::move(patch));
  }
  return out;
}

}  // namespace floorcast
