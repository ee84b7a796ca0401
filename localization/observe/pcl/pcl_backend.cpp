// floorcast_pcl.so: the observation module's PCL calls (normals, RANSAC plane, region growing)
// behind the plain interface of localization/observe/src/pcl_backend_api.hpp, loaded on first use.
#include <pcl/ModelCoefficients.h>
#include <pcl/PointIndices.h>
#include <pcl/features/normal_3d.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/region_growing.h>
#include <pcl/segmentation/sac_segmentation.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "../src/pcl_backend_api.hpp"

namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

Cloud::Ptr to_cloud(const float* xyz, std::size_t n) {
  Cloud::Ptr cloud(new Cloud);
  cloud->points.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    cloud->points[i].x = xyz[3 * i];
    cloud->points[i].y = xyz[3 * i + 1];
    cloud->points[i].z = xyz[3 * i + 2];
  }
  cloud->width = static_cast<std::uint32_t>(n);
  cloud->height = 1;
  cloud->is_dense = true;
  return cloud;
}

pcl::PointCloud<pcl::Normal>::Ptr normals_of(const Cloud::Ptr& cloud, int k) {
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

void estimate_normals(const float* xyz, std::size_t n, int k, float* out) {
  const auto normals = normals_of(to_cloud(xyz, n), k);
  for (std::size_t i = 0; i < n; ++i) {
    out[3 * i] = normals->points[i].normal_x;
    out[3 * i + 1] = normals->points[i].normal_y;
    out[3 * i + 2] = normals->points[i].normal_z;
  }
}

std::size_t ransac_plane(const float* xyz, std::size_t n, double distance_m, int iterations, int* inliers_out,
                         double* coefficients_out, int* coefficient_count) {
  pcl::SACSegmentation<pcl::PointXYZ> seg;
  seg.setModelType(pcl::SACMODEL_PLANE);
  seg.setMethodType(pcl::SAC_RANSAC);
  seg.setDistanceThreshold(distance_m);
  seg.setMaxIterations(iterations);
  seg.setOptimizeCoefficients(false);
  seg.setInputCloud(to_cloud(xyz, n));
  pcl::PointIndices inliers;
  pcl::ModelCoefficients coefficients;
  seg.segment(inliers, coefficients);
  *coefficient_count = static_cast<int>(std::min<std::size_t>(coefficients.values.size(), 4));
  for (int i = 0; i < *coefficient_count; ++i) coefficients_out[i] = coefficients.values[static_cast<std::size_t>(i)];
  const std::size_t count = std::min(inliers.indices.size(), n);
  std::copy_n(inliers.indices.begin(), count, inliers_out);
  return count;
}

std::size_t region_growing(const float* xyz, std::size_t n, int normal_k, int neighbours_k, int min_cluster_points,
                           float smoothness_rad, float curvature_threshold, int* indices_out, int* cluster_sizes) {
  const Cloud::Ptr cloud = to_cloud(xyz, n);
  const auto normals = normals_of(cloud, normal_k);
  pcl::search::KdTree<pcl::PointXYZ>::Ptr tree(new pcl::search::KdTree<pcl::PointXYZ>);
  pcl::RegionGrowing<pcl::PointXYZ, pcl::Normal> rg;
  rg.setMinClusterSize(std::max(1, min_cluster_points));
  rg.setMaxClusterSize(static_cast<int>(n));
  rg.setSearchMethod(tree);
  rg.setNumberOfNeighbours(neighbours_k);
  rg.setInputCloud(cloud);
  rg.setInputNormals(normals);
  rg.setSmoothnessThreshold(smoothness_rad);
  rg.setCurvatureThreshold(curvature_threshold);
  std::vector<pcl::PointIndices> clusters;
  rg.extract(clusters);
  std::size_t used = 0, count = 0;
  for (const auto& c : clusters) {
    if (used + c.indices.size() > n) break;  // clusters are disjoint: cannot happen
    std::copy(c.indices.begin(), c.indices.end(), indices_out + used);
    used += c.indices.size();
    cluster_sizes[count++] = static_cast<int>(c.indices.size());
  }
  return count;
}

const floorcast::pcl_api::Functions kFunctions = [] {
  floorcast::pcl_api::Functions f;
  f.api_version = floorcast::pcl_api::kApiVersion;
  f.estimate_normals = &estimate_normals;
  f.ransac_plane = &ransac_plane;
  f.region_growing = &region_growing;
  return f;
}();

}  // namespace

extern "C" __attribute__((visibility("default"))) const floorcast::pcl_api::Functions* floorcast_pcl_functions() {
  return &kFunctions;
}
