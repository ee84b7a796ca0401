// The perfect-observation comparison of layout matchers (PALMS+ sec. 4.4), scored automatically:
// seeded observation points in free space, exact observations from the plan (10 m, doors
// closed), every matcher's posterior, recalls and errors per matcher.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "floorcast/match/matcher.hpp"
#include "floorcast/scenarios/sampling.hpp"
#include "floorcast/sim/perfect_observation.hpp"

namespace floorcast {

struct ComparisonParams {
  /// Observation points per plan.
  int points_per_plan = 50;
  std::uint64_t seed = 1;
  /// Minimum distance of a point from any blocked cell.
  double clearance_m = 0.5;
  /// Grid used to sample points (cells of the valid area).
  double sample_resolution_m = 0.1;
  /// Perfect observations: PALMS+ sec. 4.4 (10 m, doors closed, 36 rays).
  PerfectObservationParams observation;
  /// Success thresholds.
  double yaw_threshold_deg = 30.0;
  /// Top-K modes (NMS separation in metres and degrees) for top-K recall @1 m.
  int top_k = 5;
  double top_k_separation_m = 1.0;
  double top_k_separation_deg = 30.0;
};

/// A labelled plan, optionally with the regions observation points are drawn from (e.g. the
/// hallways and lobbies of a generated building: PALMS+'s points are in transitional spaces).
struct NamedPlan {
  std::string name;
  FloorPlan plan;
  /// Closed polygons (world metres); empty = the whole valid area.
  std::vector<std::vector<Vec2>> sample_regions;
};

struct PointOutcome {
  std::string plan;
  int point = 0;
  std::string matcher;  ///< spec label
  Pose2 truth;
  PoseHypothesis estimate;
  double position_error_m = 0.0;
  double yaw_error_deg = 0.0;
  bool top_k_hit_1m = false;  ///< some top-K mode within 1 m (and the yaw threshold is not used)
  double time_s = 0.0;
  int num_segments = 0;
  /// Mean of the perfect observation's 36 ray ranges: how open the spot is.
  double mean_range_m = 0.0;
};

struct MatcherSummary {
  int count = 0;
  double recall_0_5m = 0.0;
  double recall_1m = 0.0;
  double recall_1m_30deg = 0.0;
  double recall_2m = 0.0;
  double top5_recall_1m = 0.0;
  double median_position_error_m = 0.0;
  double median_yaw_error_deg = 0.0;
  double mean_time_s = 0.0;
};

struct MatcherPrecompute {
  std::string plan;
  std::string matcher;
  double precompute_s = 0.0;
  double precompute_mb = 0.0;
  nlohmann::ordered_json parameters;
};

struct ComparisonResult {
  std::vector<std::string> labels;  ///< spec labels in order
  std::vector<PointOutcome> points; ///< plan-major, then point, then matcher
  std::map<std::string, MatcherSummary> summary;                           ///< by label
  std::map<std::string, std::map<std::string, MatcherSummary>> per_plan;  ///< plan -> label -> summary
  std::vector<MatcherPrecompute> precompute;
};

/// Summary statistics of a set of outcomes (fractions in [0, 1]).
MatcherSummary summarise(const std::vector<const PointOutcome*>& outcomes, double yaw_threshold_deg);

/// Runs every spec on every plan. `progress` (optional) receives one line per finished step.
ComparisonResult compare_matchers(const std::vector<NamedPlan>& plans, const std::vector<MatcherSpec>& specs,
                                  const ComparisonParams& params,
                                  const std::function<void(const std::string&)>& progress = {});

/// The default specs: "kernel" and one ray matcher per ray count ("ray" for 36, "ray<N>" else).
std::vector<MatcherSpec> default_comparison_specs(const std::vector<int>& ray_counts);

/// {"<label>": {"recall_0.5m", "recall_1m", "recall_1m_30deg", "recall_2m", "top5_recall_1m",
///  "median_position_error_m", "median_yaw_error_deg", "mean_time_s"}, ...}
nlohmann::ordered_json comparison_summary_json(const ComparisonResult& result);
/// One row per point and matcher.
std::string comparison_points_csv(const ComparisonResult& result);
/// Markdown table of the summary (percentages), plus one table per plan when there are several.
std::string comparison_markdown(const ComparisonResult& result);

}  // namespace floorcast
