// Plane extraction from 3D point clouds for the observation module's LiDAR path and the plane
// accuracy benchmark: plain PCA, PCL RANSAC, PCL normals + region growing, and the
// VoxelPlane-Reloc extractor (Suo et al. 2024: PCA plane per voxel refined with the adaptive
// weight function W_i of eq. 2-3, voxel-growth merging over the 26-neighbourhood, under-grown
// plane merging).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

namespace floorcast {

using PointCloud3f = std::vector<Eigen::Vector3f>;

/// A plane n . p = offset_m with |n| = 1, and the points supporting it.
struct Plane3 {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset_m = 0.0;
  Eigen::Vector3d centroid_m = Eigen::Vector3d::Zero();
  std::vector<int> point_indices;  ///< into the cloud it was extracted from, ascending
  double rms_m = 0.0;              ///< RMS point-to-plane distance of its points
  int voxels = 0;                  ///< voxel planes merged into it (VoxelPlane only)
};

enum class PlaneExtractorKind { kPclRegionGrowing, kVoxelPlane };
std::string to_string(PlaneExtractorKind kind);                 ///< "pcl" | "voxelplane"
PlaneExtractorKind parse_plane_extractor(const std::string& s);  ///< throws InputError

/// Angle between two planes' normals in degrees, in [0, 90] (normals are sign-free).
double plane_angle_error_deg(const Eigen::Vector3d& n_a, const Eigen::Vector3d& n_b);
/// Offset difference |d_a - d_b| after orienting n_b like n_a (the Table 2 "d").
double plane_offset_error_m(const Eigen::Vector3d& n_a, double d_a, const Eigen::Vector3d& n_b,
                            double d_b);

/// Least-squares plane (PCA on all given points; indices empty = all points).
Plane3 fit_plane_pca(const PointCloud3f& points, const std::vector<int>& indices = {});

/// Weighted least-squares plane: minimises sum (w_i (n . p_i - d))^2.
Plane3 fit_plane_weighted(const PointCloud3f& points, const std::vector<int>& indices,
                          const std::vector<double>& weights);

struct RansacPlaneParams {
  double distance_m = 0.05;
  int iterations = 1000;
  bool refit_inliers = true;  ///< least-squares refit on the inliers (PCL optimizeCoefficients)
};
/// Single dominant plane with PCL's RANSAC (SACMODEL_PLANE); deterministic (PCL's fixed seed).
/// Returns a plane with no points when none is found.
Plane3 fit_plane_ransac_pcl(const PointCloud3f& points, const RansacPlaneParams& params = {});

/// PCL normals + region growing segmentation; one least-squares plane per region.
struct PclRegionGrowingParams {
  int normal_k = 30;             ///< neighbours for the normals
  int neighbours_k = 30;         ///< neighbours for growing
  double smoothness_deg = 5.0;   ///< max normal difference between neighbours
  double curvature_threshold = 0.1;
  int min_cluster_points = 50;
};
std::vector<Plane3> extract_planes_region_growing(const PointCloud3f& points,
                                                  const PclRegionGrowingParams& params);

/// VoxelPlane-Reloc parameters. The paper gives the structure but no values; these defaults are
/// ours (documented in localization/observe/README.md).
struct VoxelPlaneParams {
  double voxel_size_m = 0.5;       ///< cube edge of the voxel grid
  int min_points_per_voxel = 10;
  /// A voxel whose points are not planar is split into its 8 children, up to this many times
  /// (VoxelMap's octree, on which the paper builds); 0 = the paper's uniform grid.
  int max_subdivisions = 1;
  /// A voxel holds a plane when the point spread along its PCA normal is small: standard
  /// deviation <= max_thickness_m and smallest/middle eigenvalue <= max_eigen_ratio.
  double max_thickness_m = 0.05;
  double max_eigen_ratio = 0.1;
  /// Eq. 2: W_i = 1 - alpha rho^2 for rho <= 1, exp(-beta rho^2) for rho > 1, with rho = r_i /
  /// sigma, r_i the distance of point i to the PCA centre and sigma half the largest such
  /// distance (the paper's boundary). The paper's r is in metres; normalising by sigma makes the
  /// weights independent of the voxel size. alpha = 0.5, beta = ln 2 make W continuous at rho = 1.
  bool adaptive_weights = true;
  double weight_alpha = 0.5;
  double weight_beta = 0.6931471805599453;
  /// Voxel growth over the 26-neighbourhood: a neighbour voxel's plane joins the region when
  /// its normal is within growth_max_normal_deg of the region plane's and its centre lies within
  /// growth_max_offset_m of the region plane.
  double growth_max_normal_deg = 10.0;
  double growth_max_offset_m = 0.1;
  /// Under-grown plane merging: a plane merges into a larger one when (1) normals are within
  /// merge_max_normal_deg, (2) the line between the centroids is within merge_depth_tol_deg of
  /// perpendicular to the larger plane's normal (same depth), (3) the centroids are closer than
  /// merge_radius_factor x the larger plane's radius (proximity).
  bool merge_undergrown = true;
  double merge_max_normal_deg = 10.0;
  double merge_depth_tol_deg = 5.0;
  double merge_radius_factor = 1.5;
  int min_plane_points = 30;  ///< planes with fewer points are not reported
};

struct VoxelPlaneResult {
  std::vector<Plane3> planes;  ///< largest first
  int voxels = 0;              ///< occupied voxels with >= min points
  int planar_voxels = 0;
  int planes_after_growth = 0;
  int planes_after_merge = 0;
};
VoxelPlaneResult extract_planes_voxel(const PointCloud3f& points, const VoxelPlaneParams& params);

/// The adaptive weight of eq. 2 for a normalised radius rho = r / sigma.
double voxel_plane_weight(double rho, const VoxelPlaneParams& params);

}  // namespace floorcast
