// Simulated scan folders: a scan folder (core/scan_io.hpp: scan.json + view images, what any
// sensor would write) plus simulation.json with what only the simulator knows (ground truth,
// setting, seed, every sensor parameter). Format documented in sim/README.md.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "floorcast/sim/simulated_scan.hpp"
#include "floorcast/sim/scan_params.hpp"

namespace floorcast {

/// Writes the scan folder and simulation.json into `dir` (created if missing).
void save_simulated_scan(const std::string& dir, const SimulatedScan& scan);

/// The simulator's side of a scan folder.
struct SimulationRecord {
  ScanTruth truth;
  ScanParams params;
};

/// Reads simulation.json (or the simulator fields of a wave-1 scan.json) of a scan folder with
/// `num_views` views; nullopt when the folder was not written by the simulator (e.g. a phone
/// scan). Throws InputError when the file exists but is invalid.
std::optional<SimulationRecord> load_simulation_record(const std::string& dir, std::size_t num_views);

/// Reads a simulated scan folder (also wave-1 folders, whose scan.json held the simulator's
/// fields). Throws InputError naming the file, the element and the reason.
SimulatedScan load_simulated_scan(const std::string& dir);

/// The simulation.json text of a simulated scan.
std::string simulation_json_text(const SimulatedScan& scan);

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
