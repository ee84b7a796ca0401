// Walk folders (`floorcast sim walk ... -o DIR`), read by `floorcast track`:
//
//   DIR/walk.json          format, parameters (walk, odometry, schedule) in full, plan name and
//                          hash, summary, the list of observations, and the odometry's stated
//                          error (odometry_uncertainty: what trackers assume; a recording states
//                          its sensor's, a simulated walk its odometry model's)
//   DIR/truth.tum          true trajectory (TUM: evo reads it unchanged)
//   DIR/odometry.tum       odometry trajectory in its own frame (first pose = identity), as a
//                          real odometry source reports it (evo: align or compare relative poses)
//   DIR/steps.csv          one row per sample: truth, odometry pose and increment, flags
//   DIR/observations/step_NNNN/   one per scheduled observation: observation.json (perfect) or a
//                                 simulated scan folder (scan.json + views + simulation.json)
//
// Increments are stored in steps.csv at full precision, so the tracker reads exactly what the
// odometry model produced.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "floorcast/core/fields.hpp"
#include "floorcast/sim/odometry.hpp"
#include "floorcast/sim/walk.hpp"

namespace floorcast {

/// One scheduled observation of a walk folder.
struct WalkObservation {
  int step = 0;
  std::string kind;  ///< "perfect" (observation.json) or "scan" (a scan folder)
  std::string path;  ///< relative to the walk folder
};

struct WalkRecord {
  Walk walk;
  OdometryParams odometry_params;
  OdometryTrack odometry;
  /// The odometry's error as trackers should assume it (walk.json "odometry_uncertainty"; when
  /// absent, derived from odometry_params: odometry_uncertainty()).
  OdometryUncertainty odometry_uncertainty;
  ObservationSchedule schedule;
  std::vector<WalkObservation> observations;
  std::string plan_name;
  std::string plan_hash;  ///< hex FNV-1a of the plan's canonical JSON
  /// Observation settings (sensor preset, perfect-observer parameters, ...), kept for reference.
  nlohmann::ordered_json observation_settings = nlohmann::ordered_json::object();
};

/// Writes walk.json, truth.tum, odometry.tum and steps.csv into `dir` (created if missing). The
/// observations themselves are written by the caller into their `path`s.
void save_walk(const std::string& dir, const WalkRecord& record);

/// walk.json's "summary" (length_m, duration_s, speed_mps, ...).
const FieldList<WalkSummary>& walk_summary_fields();

/// Reads a walk folder (strict; errors name the file, element and reason).
WalkRecord load_walk(const std::string& dir);

}  // namespace floorcast
