// Work units of a scenario run and their results. A unit is one observation point of one
// building in one sweep cell: simulate -> observe -> match (every matcher) -> errors.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "floorcast/core/types.hpp"
#include "floorcast/eval/sequential.hpp"
#include "floorcast/scenarios/scenario.hpp"

namespace floorcast {

struct WorkUnit {
  int cell = 0;
  int building = 0;  ///< the building whose plan the observation is matched against
  int point = 0;     ///< 0..count-1: positives; count..count+negatives-1: negatives
  /// "<cell id>/<building label>/<point, 4 digits>"; negatives "<cell id>/<building label>/n<k, 4 digits>".
  std::string id;
  /// Negative samples: the building the observation is made in (another one of the scenario)
  /// and its point; -1 for positives.
  int source_building = -1;
  int source_point = -1;
  bool negative() const { return source_building >= 0; }
};

/// All units in their canonical order (cell, building, point).
std::vector<WorkUnit> enumerate_units(const Scenario& scenario);

/// `--shard I/N`: unit k of the canonical order belongs to shard k mod N (I in [0, N)).
struct ShardSpec {
  int index = 0;
  int count = 1;
};
/// Parses "I/N"; throws InputError on anything else.
ShardSpec parse_shard(const std::string& text);
std::vector<WorkUnit> select_shard(const std::vector<WorkUnit>& units, const ShardSpec& shard);

struct PoseEstimate {
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_rad = 0.0;
  double score = 0.0;
  double position_error_m = 0.0;
  double yaw_error_deg = 0.0;
};

/// One matcher's outcome on one unit.
struct MatcherOutcome {
  std::string label;
  bool ok = true;              ///< false: the method produced no estimate (reason in `failure`)
  std::string failure;
  /// The method misbehaved (an external method raised, crashed, hung or answered malformed;
  /// match/external.hpp): scored as a miss, counted apart, and run again when the run resumes.
  bool error = false;
  PoseEstimate estimate;       ///< argmax
  std::vector<PoseEstimate> top_k;
  double match_s = 0.0;        ///< timing (excluded from result comparisons)
};

/// One tracker's outcome on one walk (sequential scenarios).
struct TrackOutcome {
  std::string label;
  bool started = true;          ///< false: no track (reason in `failure`), scored as a failure
  std::string failure;
  /// The tracker or its matcher misbehaved (an external method's error; `failure` says which and
  /// where): scored as a failure, counted apart, run again when the run resumes.
  bool error = false;
  int observations_used = 0;
  /// Per step from the initial observation to the end of the walk (record.time_per_step_s is
  /// timing, kept under "timings" in files).
  SequentialRecord record;
  /// The estimated position per step (as record), for trajectory figures; empty in runs made
  /// before it was kept.
  std::vector<Vec2> estimate_xy_m;
  /// Per step, the position errors of the tracker's modes (TrackEstimate::modes, best first);
  /// empty when the tracker reports none.
  std::vector<std::vector<double>> mode_position_error_m;
};

struct UnitResult {
  WorkUnit unit;
  Pose2 truth;
  /// Observation summary (segment count, ray count, diagnostics of the observation module).
  nlohmann::ordered_json observation = nlohmann::ordered_json::object();
  bool observation_ok = true;
  std::string observation_failure;
  std::vector<MatcherOutcome> outcomes;
  /// Sequential scenarios: the walk's summary (with "truth_xy": the true position per step, for
  /// trajectory figures) and every tracker's outcome.
  nlohmann::ordered_json walk = nlohmann::ordered_json::object();
  std::vector<TrackOutcome> tracks;
  /// Stage timings in seconds: simulate, observe, match (sum over matchers).
  std::map<std::string, double> timings_s;
};

/// JSON form of a unit result. Timings live under "timings" only, so comparing results without
/// timings is `strip_timings(a) == strip_timings(b)`.
nlohmann::ordered_json unit_to_json(const UnitResult& result);
UnitResult unit_from_json(const nlohmann::json& json, const std::string& source);
nlohmann::ordered_json strip_timings(nlohmann::ordered_json unit_json);

/// Whether a unit result holds an error of a method (MatcherOutcome/TrackOutcome::error).
bool unit_has_errors(const UnitResult& result);

}  // namespace floorcast
