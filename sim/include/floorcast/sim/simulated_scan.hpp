// A simulated rotating scan: the sensor data (core/scan.hpp, exactly what a real phone would
// deliver) plus what only a simulator knows: the ground truth and every setting it was simulated
// with. Localization code receives `scan` alone.
//
// Frames: world = floor-plan metres, x right, y up, z up from the floor; scan and camera frames as
// in core/scan.hpp. T_world_scan is the ground-truth pose (x, y, yaw) plus the camera height.
#pragma once

#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "floorcast/core/scan.hpp"
#include "floorcast/core/types.hpp"
#include "floorcast/sim/scan_params.hpp"

namespace floorcast {

/// Ground truth kept next to a scan (never read by localization).
struct ScanTruth {
  Pose2 T_world_scan;            ///< observer position and heading in the world
  double camera_height_m = 1.5;  ///< camera centre above the floor
  /// True camera poses in the scan frame (without tracker noise), one per view.
  std::vector<Eigen::Isometry3d> T_scan_camera_true;
  /// Multiplicative depth scale applied to each view: the scan-shared scale times the view's own
  /// (monocular sensor model; 1 otherwise).
  std::vector<double> view_depth_scale;
  double scan_depth_scale = 1.0;  ///< the scan-shared part of view_depth_scale (mono; 1 otherwise)
  std::vector<double> view_depth_shift_m;  ///< additive depth shift of each view (mono; 0 otherwise)
  /// Views whose floor pixels were given no depth (mono: no usable ground plane).
  std::vector<bool> view_floor_masked;
  /// Optional (only when the simulation was asked to keep it; never written to files): per view,
  /// CV_32F z-depth of the first surface each ray met (glass counts as a surface), before any
  /// sensor effect; 0 = nothing within range.
  std::vector<cv::Mat> depth_m;
  /// hex64(plan_hash(plan)) of the plan as given to the simulator (before clutter or door
  /// changes), so a localizer can tell when it is handed another plan; "" when unknown.
  std::string plan_hash;
};

struct SimulatedScan {
  /// The sensor data (scan.sensor = the preset name).
  Scan scan;
  ScanTruth truth;
  /// Everything the scan was simulated with (geometry, sensor model, setting, seed).
  ScanParams params;
};

}  // namespace floorcast
