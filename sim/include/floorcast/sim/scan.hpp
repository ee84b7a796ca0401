// A simulated rotating scan: what a phone measures when its user stands still and turns around.
//
// Frames
// - world: floor-plan metres, x right, y up, z up from the floor.
// - scan: gravity-aligned, origin at the observer's camera centre (camera_height_m above the
//   floor), +x along the observer's heading (yaw 0 of the scan), +z up. T_world_scan is the
//   ground-truth pose (x, y, yaw) plus the camera height.
// - camera: OpenCV convention, x right, y down, z forward (optical axis).
// Depth images hold z-depth along the optical axis (not range), metres, 0 = no return.
#pragma once

#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "floorcast/floorplans/types.hpp"
#include "floorcast/sim/scan_params.hpp"

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
  /// and single scans keep a subset.
  int view_index = 0;
  /// Camera pose in the scan frame as the phone's pose tracker reports it (tracker noise
  /// included).
  Eigen::Isometry3d T_scan_camera = Eigen::Isometry3d::Identity();
  /// CV_32F z-depth in metres, 0 = no return.
  cv::Mat depth_m;
  /// CV_8U, 255 where the pixel's value was affected by glass (see-through, glass return or
  /// reflection); the "PALMS+*" setting masks these pixels.
  cv::Mat glass_mask;
  /// CV_8U ARKit-style confidence 0 (low) .. 2 (high); empty for sensors without one.
  cv::Mat confidence;
};

/// Ground truth kept next to a scan (never read by localization).
struct ScanTruth {
  Pose2 T_world_scan;            ///< observer position and heading in the world
  double camera_height_m = 1.5;  ///< camera centre above the floor
  /// True camera poses in the scan frame (without tracker noise), one per view.
  std::vector<Eigen::Isometry3d> T_scan_camera_true;
  /// Multiplicative depth scale applied to each view (monocular sensor model; 1 otherwise).
  std::vector<double> view_depth_scale;
  /// Optional (only when the simulation was asked to keep it; never written to files): per view,
  /// CV_32F z-depth of the first surface each ray met (glass counts as a surface), before any
  /// sensor effect; 0 = nothing within range.
  std::vector<cv::Mat> depth_m;
};

struct Scan {
  std::string sensor;   ///< preset name: perfect, lidar, mono, phone
  std::string setting;  ///< full, partial or single
  std::vector<DepthView> views;
  ScanTruth truth;
  /// Everything the scan was simulated with (geometry, sensor model, setting, seed).
  ScanParams params;
};

}  // namespace floorcast
