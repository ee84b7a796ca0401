// Private PCL helpers of the observation module (only included by observe_*.cpp files).
#pragma once

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "floorcast/observe/observe_planes.hpp"

namespace floorcast::detail {

pcl::PointCloud<pcl::PointXYZ>::Ptr to_pcl(const PointCloud3f& points);

/// Normals from k nearest neighbours, oriented towards the scan origin (the sensor).
pcl::PointCloud<pcl::Normal>::Ptr estimate_normals(const pcl::PointCloud<pcl::PointXYZ>::Ptr& cloud,
                                                   int k);

}  // namespace floorcast::detail
