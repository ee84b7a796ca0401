// What `floorcast localize` writes (estimate.json, posterior_grid.json): the match's result as
// records with one field list each (core/fields.hpp), so their keys are declared once.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "floorcast/core/fields.hpp"
#include "floorcast/core/types.hpp"
#include "floorcast/match/posterior.hpp"

namespace floorcast {

/// A pose hypothesis as written: position in metres, heading in degrees.
struct HypothesisRecord {
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_deg = 0.0;
  double score = 0.0;
};
HypothesisRecord hypothesis_record(const PoseHypothesis& h);

/// estimate.json.
struct EstimateRecord {
  std::string status;                    ///< "ok" or "not localized (no pose): <why>"
  std::optional<HypothesisRecord> best;  ///< x_m, y_m, yaw_deg (null without a pose), score
  double score = 0.0;
  std::vector<HypothesisRecord> top_k;
  std::optional<HypothesisRecord> ground_truth;  ///< when the observation knows it (score unused)
  std::optional<double> position_error_m;        ///< with a pose and a ground truth
  std::optional<double> yaw_error_deg;
  std::map<std::string, double> counters;  ///< the matcher's counters (MatchResult::counters)
  double precompute_s = 0.0;
  double match_s = 0.0;
  std::map<std::string, double> stages_s;
  std::string matcher;
  nlohmann::ordered_json parameters = nlohmann::ordered_json::object();
  double precompute_mb = 0.0;
  std::string plan;
  std::string observation;
  std::string observation_input;
  std::size_t observation_segments = 0;
  std::size_t observation_planes = 0;  ///< 3D plane patches of the observation
  std::vector<std::string> notes;
  GridSpec grid;
  std::optional<int> slices;       ///< orientation slices of the full posterior (null: none computed)
  std::string posterior_output;    ///< what was written of the volume: none, npy, npz-f16, top-k
};
const FieldList<EstimateRecord>& estimate_record_fields();

/// posterior_grid.json: how to read posterior.npy.
struct PosteriorGridRecord {
  std::string file = "posterior.npy";
  int slices = 0;
  GridSpec grid;
  std::string dtype = "float32";
  std::string top_k;  ///< with a top-k file: what its arrays hold (empty otherwise)
  std::vector<double> yaw_deg;
  std::string matcher;
};
PosteriorGridRecord posterior_grid_record(const Posterior& posterior, const std::string& matcher);
const FieldList<PosteriorGridRecord>& posterior_grid_record_fields();

}  // namespace floorcast
