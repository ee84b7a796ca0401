// Scan folders: the on-disk form of a sensor-only Scan (core/scan.hpp), written by the simulator,
// a phone app or any script, read by `floorcast observe`. Format (documented in docs/formats.md):
//
//   DIR/scan.json               format, version, sensor, depth unit, one entry per view:
//                               intrinsics, T_scan_camera (4x4), image file names
//   DIR/view_000_depth.png      16-bit depth in depth units (default millimetres), 0 = no return
//   DIR/view_000_glass.png      optional 8-bit mask, 255 = value affected by glass
//   DIR/view_000_confidence.png optional 8-bit confidence 0..2
//   DIR/view_000_rgb.png        optional 8-bit colour image (what a depth network would look at)
//   DIR/view_000_semantics.json optional column semantics (DepthView::column_semantics): format
//                               "floorcast-column-semantics" 1, "columns": one array per image
//                               column of [class, range_m] pairs, nearest first
//   DIR/view_000_bev.npy        optional BEV of the view (DepthView::bev), float32 (W, D, C); the
//                               scan-level "bev" block {classes, min_depth_m, max_depth_m} gives
//                               its class set and log-spaced depth range
//
// Only views, intrinsics and poses are required: a folder of colour images whose depth comes from
// elsewhere (a depth network run offline, `floorcast observe --depth-dir`) has no "depth" entries.
//
// A simulator may put more files beside these (sim writes simulation.json with the ground truth);
// this reader never needs them. Depth is quantised to the depth unit on save (round to nearest;
// depths beyond 65535 units are written as no return), so load(save(scan)) equals the scan up to
// half a unit per pixel; poses round-trip exactly (shortest round-trip decimal numbers).
#pragma once

#include <string>
#include <vector>

#include "floorcast/core/scan.hpp"

namespace floorcast {

/// Current scan.json format version. Version 1 folders (wave 1: simulator fields inside
/// scan.json) are still read; their simulator keys are left to sim's reader.
constexpr int kScanFormatVersion = 2;

/// Writes a scan into `dir` (created if missing). Throws InputError on failure.
void save_scan(const std::string& dir, const Scan& scan);

struct ScanLoadOptions {
  /// Every view must have a depth image (false: views without one get an empty depth_m, to be
  /// filled from elsewhere, e.g. load_depth_directory).
  bool require_depth = true;
  /// Decode the colour images into DepthView::rgb (otherwise only their presence is checked).
  bool load_rgb = false;
};

/// Reads and validates a scan folder. Only views, intrinsics and poses are required. Throws
/// InputError naming the file, the element and the reason (missing or malformed files and
/// fields, unknown keys, image sizes or types that do not match the intrinsics, non-finite or
/// absurd numbers, non-rigid poses).
Scan load_scan(const std::string& dir, const ScanLoadOptions& options = {});

/// File name of view k's image of `kind` ("depth", "glass", "confidence", "rgb"):
/// "view_000_depth.png", ...
std::string scan_view_file(std::size_t k, const std::string& kind);

/// scan.json as parsed and validated, before any image is read: the views without their images
/// and, per view, the image file names (plain names inside the folder; empty = none).
struct ScanDescription {
  Scan scan;                      ///< views with intrinsics, view_index and T_scan_camera only
  double depth_unit_m = 0.001;
  struct Files {
    std::string depth, rgb, glass_mask, confidence, semantics, bev;
  };
  std::vector<Files> files;       ///< one per view
  /// The scan-level "bev" block (when some view has a BEV file).
  BevClasses bev_classes = BevClasses::kSemantic;
  double bev_min_depth_m = 0.0;
  double bev_max_depth_m = 0.0;
};

/// Parses scan.json text (`source` names it in errors): everything load_scan checks except the
/// images themselves. `require_depth` as in ScanLoadOptions. Throws InputError.
ScanDescription parse_scan_description(const std::string& json_text, const std::string& source,
                                       bool require_depth = true);

/// The scan.json text of a scan (what save_scan writes next to the images).
std::string scan_json_text(const Scan& scan);

/// A view's column semantics file (format "floorcast-column-semantics" 1), and back: one entry
/// per image column (width_px), hits nearest first, nothing after a wall; ranges written to 0.1
/// mm. Throws InputError naming `source` and the element.
std::string column_semantics_json_text(const std::vector<std::vector<SemanticHit>>& columns);
std::vector<std::vector<SemanticHit>> parse_column_semantics(const std::string& text, const std::string& source,
                                                             int width_px);

/// A view's BEV from a .npy of shape (W, D, C), float32 or float64 (a network's softmax output):
/// C must be the class count of `classes` (4: wall, window, door, empty; 2: occupied, empty),
/// every value finite in [0, 1], every (column, bin) summing to 1 within 1e-2 (renormalised
/// exactly; a larger deviation is refused: logits need a softmax over the class axis first).
/// Columns are spread over the image width (DepthView::bev); depth bins log-spaced in
/// [min_depth_m, max_depth_m). Throws InputError naming the file.
BevPrediction read_view_bev(const std::string& path, const CameraIntrinsics& intrinsics, BevClasses classes,
                            double min_depth_m, double max_depth_m);

}  // namespace floorcast
