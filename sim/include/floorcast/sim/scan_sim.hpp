// The rotating-scan simulator: renders each view's depth with Embree (camera-coherent ray
// streams, TBB over tiles) and applies the sensor model (sensor models: sim/README.md).
//
// Determinism: every random number is a pure function of (seed, stream, view index, pixel or
// pane), so a scan is identical bytes for any thread count and evaluation order.
#pragma once

#include <Eigen/Geometry>
#include <string>

#include "floorcast/floorplans/floor_plan.hpp"
#include "floorcast/sim/ray_scene.hpp"
#include "floorcast/sim/simulated_scan.hpp"

namespace floorcast {

struct SimulationOptions {
  /// Keep the noise-free first-surface depth of every view in Scan::truth.depth_m.
  bool keep_true_depth = false;
  /// Annotate every view with its column semantics (DepthView::column_semantics, core/bev.hpp):
  /// per image column, the horizontal ray at camera height from the true camera centre along the
  /// gravity-aligned column, cast through everything it enters (window and glass-wall panes,
  /// closed door leaves, furniture taller than the camera) until the first wall face, within the
  /// sensor's max_range_m. The sensor realisation (depth, glass, noise) is unchanged.
  bool column_semantics = false;
  /// Open doorways are not surfaces: a second horizontal ray at this height (above the door
  /// openings, below the ceiling; default between the default door height 2.1 m and wall height
  /// 3.0 m) finds their lintels, and a lintel face the camera-height ray passes under (no element
  /// of its own in that plane: within 5 mm) is an open doorway at that range.
  double lintel_probe_height_m = 2.55;
};

/// The column semantics of one view (SimulationOptions::column_semantics) seen from the camera
/// pose T_world_camera (OpenCV camera frame) with intrinsics K: one hit list per image column.
std::vector<std::vector<SemanticHit>> simulate_column_semantics(const RayScene& scene,
                                                                const Eigen::Isometry3d& T_world_camera,
                                                                const CameraIntrinsics& K, double max_range_m,
                                                                double lintel_probe_height_m);

/// Pinhole intrinsics of a view: square pixels, principal point at the image centre (OpenCV
/// convention: pixel (u, v) has its centre at integer coordinates, so cx = (width - 1) / 2),
/// fx = (width / 2) / tan(hfov / 2).
CameraIntrinsics view_intrinsics(const ScanGeometry& geometry);

/// True pose of view `view_index` in the scan frame (camera frame OpenCV: x right, y down, z
/// forward).
Eigen::Isometry3d view_pose(const ScanGeometry& geometry, int view_index);

/// The scan frame in the world: translation (x, y, camera height), rotation yaw about +z.
Eigen::Isometry3d scan_frame_in_world(const Pose2& T_world_scan, double camera_height_m);

/// The camera rays a scan casts (world frame, t in units of z-depth), view by view in the
/// renderer's tile order (16 x 16 pixel tiles, row-major inside each). For benchmarks and tests.
std::vector<Ray3> scan_camera_rays(const Pose2& T_world_scan, const ScanParams& params);

/// Simulates a scan at T_world_scan. Validates params (InputError). The pose itself is not
/// checked here (see check_observer_pose).
SimulatedScan simulate_scan(const RayScene& scene, const Pose2& T_world_scan, const ScanParams& params,
                   const SimulationOptions& options = {});

/// Throws InputError unless the observer position is inside the building (connected to its
/// interior without crossing a wall, door or window) and not inside a wall, closed door, glass
/// pane or obstacle. `source` names the plan in messages.
void check_observer_pose(const FloorPlan& plan, const Pose2& T_world_observer, const std::string& source);

}  // namespace floorcast
