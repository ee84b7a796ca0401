// `floorcast export SCENARIO.yaml -o DIR`: a scenario's scans as a dataset other tools read.
//
//   DIR/README.md                       the layout and conventions, written with the data
//   DIR/<cell>/split.yaml               F3Loc: train/val/test scene lists (every building a test scene)
//   DIR/<cell>/<building>/map.png       F3Loc-style occupancy (255 free, 0 blocked; 0.01 m/px by default)
//   DIR/<cell>/<building>/map.yaml      resolution, size, the world <-> map transform
//   DIR/<cell>/<building>/poses.txt     F3Loc: 4 lines per scan (3 sources, the reference), "x y theta"
//                                       (map frame: metres from the map centre, x right, y down,
//                                       theta = -yaw, radians)
//   DIR/<cell>/<building>/depth40.txt, depth160.txt   F3Loc ground truth: per frame 40 / 160
//                                       horizontal depths at camera height along equally spaced
//                                       image columns (from the plan, doors closed)
//   DIR/<cell>/<building>/depth40_sensor.txt   the same columns as the simulated sensor measured
//   DIR/<cell>/<building>/rgb/NNNNN-l.png  F3Loc GridSeqDataset frames (l = 3 the reference);
//                                       rgb/NNNNN.png the same frames by poses.txt line (TrajDataset)
//   DIR/<cell>/<building>/scans.tum     every scan's true pose (TUM; timestamp = point index)
//   DIR/<cell>/<building>/scans/pNNNN/  one scan folder per observation point, which `floorcast
//       observe` reads as is (scan.json, view_NNN_depth.png 16-bit mm, view_NNN_rgb.png,
//       view_NNN_glass.png, view_NNN_confidence.png, simulation.json), plus
//       view_NNN_depth_gt.png (noise-free z-depth, 16-bit mm; with colour only),
//       view_NNN_label.png (8-bit MeshLabel of the first surface: 0 wall, 1 closed door, 2 glass,
//       3 clutter, 4 floor, 5 ceiling, 255 none), intrinsics.json (K per view, depth_scale 1000),
//       rgb.txt / depth.txt (TUM RGB-D association lists), groundtruth.txt (TUM: each view's true
//       camera pose in the world; timestamp = view index) and truth.json (pose, camera height,
//       per-view depth scale, plan hash).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "floorcast/scenarios/scenario.hpp"

namespace floorcast {

struct DatasetExportOptions {
  bool rgb = true;                  ///< render colour views (OpenGL module)
  double map_resolution_m = 0.01;   ///< F3Loc's map scale; coarsened (reported) beyond 16384 px
  std::vector<std::string> cells;   ///< cell ids to export; empty = every cell that simulates scans
  /// "scenario" (or empty): the scenario's camera, with a note where it differs from F3Loc's;
  /// "f3loc": F3Loc's hard-coded camera (focal length / width 3/8, no pitch) for every scan cell.
  std::string camera = "scenario";
};

struct DatasetExportReport {
  std::size_t scans = 0;
  std::size_t walk_scans = 0;  ///< sequential cells: scans at later walk steps (scans/pNNNN/step_SSSS)
  std::size_t images = 0;
  std::vector<std::string> notes;  ///< coarsened maps, cells skipped (perfect observations), ...
};

/// Exports the scans of the scenario's scan cells into `out_dir` (created). `progress` (optional)
/// is called after every scan with (done, total). Throws InputError when no requested cell
/// simulates scans or a requested cell id does not exist.
DatasetExportReport export_scenario_dataset(const Scenario& scenario, const std::string& out_dir,
                                            const DatasetExportOptions& options,
                                            const std::function<void(std::size_t, std::size_t)>& progress = {});

}  // namespace floorcast
