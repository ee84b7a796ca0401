// Observation-module options shared by `floorcast observe` and `floorcast localize` (a scan folder
// as the observation).
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <string>

#include "floorcast/observe/observation_module.hpp"
#include "floorcast/core/observation_io.hpp"

namespace floorcast::cli {

struct ObserveCliOptions {
  std::string path;             ///< "" = from the scan's sensor (lidar -> lidar, else mono)
  std::string scale_alignment;  ///< "" = default (full)
  std::string extractor;        ///< "" = default (voxelplane)
  bool mask_glass = false;
  std::string params_file;
  /// Bring your own depth: depth maps made elsewhere replace the scan's (core/depth_io.hpp).
  std::string depth_dir;
  std::string depth_kind = "z";
  double depth_unit_m = 0.001;  ///< unit of 16-bit depth files
  /// "" = the params file decides (default off); else enable the BEV predictor with this preset.
  std::string bev;
};

void add_observation_options(CLI::App& cmd, ObserveCliOptions& options);

/// Loads a scan folder for the observation module: with --depth-dir its depth comes from there
/// (the folder then needs no depth images of its own); repairs are printed to stderr.
Scan load_scan_for_observation(const std::string& scan_dir, const ObserveCliOptions& options);

/// Parameters from the options (overrides file first, then flags). `scan` (may be null) picks the
/// default path from its sensor when neither --path nor a params file says.
ObservationParams observation_params_from_cli(const ObserveCliOptions& options, const Scan* scan);

/// The observation as a record of the shared observation schema (ground truth from the scan,
/// key diagnostics as metadata).
ObservationRecord observation_record(const Scan& scan, const std::string& scan_dir, const ObservationResult& result);

/// The module's clouds as PLY files in `dir`: back_projected.ply (every view at scale 1, coloured
/// by view), scaled.ply (kept views at their final scale), slice.ply (the band used, at z = 0);
/// scan frame, metres, voxelised at 2 cm (1 cm for the slice).
void write_observation_clouds(const std::string& dir, const Scan& scan, const ObservationParams& params,
                              const ObservationResult& result);

/// Diagnostics, stage timings and every parameter.
nlohmann::ordered_json observation_diagnostics_json(const ObservationParams& params, const ObservationResult& result);

}  // namespace floorcast::cli
