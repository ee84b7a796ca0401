// PCL-based plane extraction: RANSAC plane and normals + region growing. PCL headers stay here.
#include <pcl/features/normal_3d.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/region_growing.h>
#include <pcl/segmentation/sac_segmentation.h>

#include <algorithm>
#include <cmath>

#include "floorcast/observe/observe_planes.hpp"
#include "floorcast/core/math.hpp"
#include "observe_pcl.hpp"

namespace floorcast {
namespace detail {

pcl::PointCloud<pcl::PointXYZ>::Ptr to_pcl(const PointCloud3f& points) {
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  cloud->points.resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    cloud->points[i].x = points[i].x();
    cloud->points[i].y = points[i].y();
    cloud->points[i].z = points[i].z();
  }
  cloud->width = static_cast<std::uint32_t>(points.size());
  cloud->height = 1;
  cloud->is_dense = true;
  return cloud;
}

pcl::PointCloud<pcl::Normal>::Ptr estimate_normals(const pcl::PointCloud<pcl::PointXYZ>::Ptr& cloud,
                                                   int k) {
  pcl::PointCloud<pcl::Normal>::Ptr normals(new pcl::PointCloud<pcl::Normal>);
  pcl::search::KdTree<pcl::PointXYZ>::Ptr tree(new pcl::search::KdTree<pcl::PointXYZ>);
  pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> ne;
  ne.setInputCloud(cloud);
  ne.setSearchMethod(tree);
  ne.setKSearch(std::max(3, k));
  ne.setViewPoint(0.0f, 0.0f, 0.0f);  // scan origin = sensor
  ne.compute(*normals);
  return normals;
}

}  // namespace detail

Plane3 fit_plane_ransac_pcl(const PointCloud3f& points, const RansacPlaneParams& params) {
  Plane3 plane;
  if (points.size() < 3) return plane;
  auto cloud = detail::to_pcl(points);
  pcl::SACSegmentation<pcl::PointXYZ> seg;
  seg.setModelType(pcl::SACMODEL_PLANE);
  seg.setMethodType(pcl::SAC_RANSAC);
  seg.setDistanceThreshold(params.distance_m);
  seg.setMaxIterations(params.iterations);
  seg.setOptimizeCoefficients(false);
  seg.setInputCloud(cloud);
  pcl::PointIndices inliers;
  pcl::ModelCoefficients coefficients;
  seg.segment(inliers, coefficients);
  if (inliers.indices.size() < 3 || coefficients.values.size() != 4) return plane;
  if (params.refit_inliers) return fit_plane_pca(points, inliers.indices);
  Eigen::Vector3d n(coefficients.values[0], coefficients.values[1], coefficients.values[2]);
  const double norm = n.norm();
  n /= norm;
  double d = -coefficients.values[3] / norm;
  if (d > 0.0) {
    n = -n;
    d = -d;
  }
  plane = fit_plane_pca(points, inliers.indices);  // centroid, rms, indices
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
  auto cloud = detail::to_pcl(points);
  auto normals = detail::estimate_normals(cloud, params.normal_k);
  pcl::search::KdTree<pcl::PointXYZ>::Ptr tree(new pcl::search::KdTree<pcl::PointXYZ>);
  pcl::RegionGrowing<pcl::PointXYZ, pcl::Normal> rg;
  rg.setMinClusterSize(std::max(1, params.min_cluster_points));
  rg.setMaxClusterSize(static_cast<int>(points.size()));
  rg.setSearchMethod(tree);
  rg.setNumberOfNeighbours(params.neighbours_k);
  rg.setInputCloud(cloud);
  rg.setInputNormals(normals);
  rg.setSmoothnessThreshold(static_cast<float>(params.smoothness_deg * kPi / 180.0));
  rg.setCurvatureThreshold(static_cast<float>(params.curvature_threshold));
  std::vector<pcl::PointIndices> clusters;
  rg.extract(clusters);
  for (const auto& c : clusters) {
    if (static_cast<int>(c.indices.size()) < params.min_cluster_points) continue;
    planes.push_back(fit_plane_pca(points, c.indices));
  }
  std::stable_sort(planes.begin(), planes.end(), [](const Plane3& a, const Plane3& b) {
    if (a.point_indices.size() != b.point_indices.size())
      return a.point_indices.size() > b.point_indices.size();
    return a.point_indices.front() < b.point_indices.front();
  });
  return planes;
}

}  // namespace floorcast
