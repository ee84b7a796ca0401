// Scan folders (format documented in sim/README.md):
//
//   DIR/scan.json               intrinsics, view poses, sensor parameters, setting, seed, truth
//   DIR/view_000_depth.png      16-bit depth in millimetres, 0 = no return (one per view)
//   DIR/view_000_glass.png      8-bit glass mask, 255 = value affected by glass
//   DIR/view_000_confidence.png 8-bit confidence 0..2 (sensors that have one: lidar)
//
// Depth is quantised to millimetres on save (round to nearest; depths >= 65.5355 m are written
// as no return), so load(save(scan)) equals the scan up to 0.5 mm per pixel. Everything else
// round-trips exactly (poses and parameters as shortest round-trip decimal numbers).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "floorcast/sim/scan.hpp"
#include "floorcast/sim/scan_params.hpp"

namespace floorcast {

/// Writes a scan into `dir` (created if missing). Throws InputError on failure.
void save_scan(const std::string& dir, const Scan& scan);

/// Reads and validates a scan folder. Throws InputError naming the file, the element and the
/// reason (missing or malformed files and fields, unknown keys, image sizes or types that do not
/// match the intrinsics, non-finite or absurd numbers, non-rigid poses).
Scan load_scan(const std::string& dir);

/// The scan.json text of a scan (what save_scan writes next to the images).
std::string scan_json_text(const Scan& scan);

/// Every scan parameter with its value (the "params" object of scan.json).
nlohmann::ordered_json scan_params_to_json(const ScanParams& params);

/// Reads parameters written by scan_params_to_json; strict (unknown or missing keys, values out
/// of range throw InputError naming `source` and the key).
ScanParams scan_params_from_json(const nlohmann::json& json, const std::string& source);

/// Overrides some parameters with a JSON object of the same shape (nested objects for geometry,
/// sensor, sensor.glass/lidar/mono/tracker), e.g. {"sensor": {"mono": {"scale_sigma_ln": 0.2}}}.
/// Unknown keys and bad values throw InputError naming `source` and the key.
void apply_scan_overrides(ScanParams& params, const nlohmann::json& overrides, const std::string& source);

}  // namespace floorcast
