// A rotating scan as a sensor delivers it: what a phone measures when its user stands still and
// turns around. Sensor data only (depth views, intrinsics, camera poses, optional masks): a scan
// recorded by a phone app or produced by an external depth network is a Scan; the simulator's
// ground truth and settings live beside it (sim/simulated_scan.hpp), never inside.
//
// Frames
// - scan: gravity-aligned, origin at the observer's camera centre, +x along the observer's
//   heading (yaw 0 of the scan), +z up; the floor is at z = -camera height.
// - camera: OpenCV convention, x right, y down, z forward (optical axis).
// Depth images hold z-depth along the optical axis (not range), metres, 0 = no return.
#pragma once

#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace floorcast {

struct CameraIntrinsics {
  int width_px = 640;
  int height_px = 480;
  double fx_px = 0.0;
  double fy_px = 0.0;
  double cx_px = 0.0;
  double cy_px = 0.0;
};

struct DepthView {
  CameraIntrinsics intrinsics;
  /// Index of this view in the full rotation (view k looks at yaw k * view_step_deg); partial
  /// and single scans keep a subset. Informational for recorded scans.
  int view_index = 0;
  /// Camera pose in the scan frame as the phone's pose tracker reports it.
  Eigen::Isometry3d T_scan_camera = Eigen::Isometry3d::Identity();
  /// CV_32F z-depth in metres, 0 = no return.
  cv::Mat depth_m;
  /// Optional CV_8U, 255 where the pixel's value is unreliable because of glass (see-through,
  /// glass return or reflection); the "PALMS+*" setting drops these pixels. Empty = none marked.
  cv::Mat glass_mask;
  /// Optional CV_8U ARKit-style confidence 0 (low) .. 2 (high); empty for sensors without one.
  cv::Mat confidence;
  /// Optional CV_8UC3 colour image (BGR, OpenCV's order) of the same camera and size; localization
  /// never needs it (depth networks run on it offline). Empty when absent or not loaded.
  cv::Mat rgb;
  /// Name of the colour image inside its scan folder when the scan was read from one ("" else).
  std::string rgb_file;
};

struct Scan {
  /// Free-form sensor description ("lidar", "mono", "iPhone 15 Pro LiDAR", "Depth Pro", ...);
  /// informational only: nothing in the pipeline branches on it.
  std::string sensor;
  std::vector<DepthView> views;
};

}  // namespace floorcast
