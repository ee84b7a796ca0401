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
#include <cmath>
#include <string>
#include <vector>

#include "floorcast/core/bev.hpp"

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
  /// Optional semantic annotation (core/bev.hpp), empty or one entry per image column u =
  /// 0..width_px-1: the elements the column's horizontal ray at camera height meets, nearest
  /// first, through doors, windows and furniture, ending at the first wall (a column without a
  /// wall within the annotation's range ends without one). The column's ray is the
  /// gravity-aligned one (view_column_azimuth_rad). What a simulator knows and a labelled mesh
  /// or a labelling tool can give: the truth a BEV predictor turns into a prediction.
  std::vector<std::vector<SemanticHit>> column_semantics;
  /// Optional BEV brought for this view (a network's output, core/bev.hpp): W columns spread
  /// evenly over the image width (column w at pixel u = (w + 0.5) width / W - 0.5, left to
  /// right); its column_azimuth_rad are relative to the view's heading (view_heading_rad), i.e.
  /// atan((cx - u) / fx). Empty (no columns) when none.
  BevPrediction bev;
};

/// Heading of a view in the scan frame: azimuth of its optical axis projected on the horizontal
/// plane (CCW from the scan's +x), radians.
inline double view_heading_rad(const DepthView& view) {
  const Eigen::Vector3d z = view.T_scan_camera.linear().col(2);
  return std::atan2(z.y(), z.x());
}

/// Scan-frame azimuth of image column u (pixel centres at integers) after gravity alignment (the
/// thesis' sec. 3.3.1): the view's heading plus atan((cx - u) / fx).
inline double view_column_azimuth_rad(const DepthView& view, double u_px) {
  return view_heading_rad(view) + std::atan((view.intrinsics.cx_px - u_px) / view.intrinsics.fx_px);
}

struct Scan {
  /// Free-form sensor description ("lidar", "mono", "iPhone 15 Pro LiDAR", "Depth Pro", ...);
  /// informational only: nothing in the pipeline branches on it.
  std::string sensor;
  std::vector<DepthView> views;
};

}  // namespace floorcast
