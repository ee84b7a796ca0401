// The interface between the observe library and its PCL back-end module floorcast_pcl.so
// (localization/observe/pcl/pcl_backend.cpp), loaded with dlopen on first use (core/module.hpp) so that a
// process which never extracts a ground plane or planes never maps PCL (and with it FLANN, Boost,
// OpenMP, LAPACK/BLAS/gfortran). Private to floorcast: both sides are built from the same tree, so
// plain C types cross the boundary; kApiVersion guards against a stale module. Points are packed
// x, y, z floats. Errors inside the module are thrown as std::runtime_error.
#pragma once

#include <cstddef>

namespace floorcast::pcl_api {

constexpr int kApiVersion = 1;
constexpr const char* kModuleName = "floorcast_pcl";
constexpr const char* kFunctionsSymbol = "floorcast_pcl_functions";

struct Functions {
  int api_version = 0;
  /// Unit normals from the k nearest neighbours (pcl::NormalEstimation over a kd-tree), oriented
  /// towards the origin (the sensor); NaN where PCL leaves the normal undefined. Writes 3n floats.
  void (*estimate_normals)(const float* xyz, std::size_t n, int k, float* normals_xyz) = nullptr;
  /// RANSAC plane (pcl::SACSegmentation, SACMODEL_PLANE, no coefficient optimisation): writes the
  /// inlier indices (capacity n) and returns their count; `coefficients` gets a, b, c, d and
  /// `coefficient_count` how many PCL produced (4 when a plane was found, else 0).
  std::size_t (*ransac_plane)(const float* xyz, std::size_t n, double distance_m, int iterations, int* inliers,
                              double* coefficients, int* coefficient_count) = nullptr;
  /// Region growing over k-NN normals (pcl::RegionGrowing): clusters in PCL's order, their point
  /// indices in PCL's order, packed into `indices` (capacity n) with `cluster_sizes` (capacity n);
  /// returns the number of clusters.
  std::size_t (*region_growing)(const float* xyz, std::size_t n, int normal_k, int neighbours_k,
                                int min_cluster_points, float smoothness_rad, float curvature_threshold,
                                int* indices, int* cluster_sizes) = nullptr;
};

/// The module's one entry point (extern "C", symbol kFunctionsSymbol).
using GetFunctionsFn = const Functions* (*)();

}  // namespace floorcast::pcl_api
