// Sequential (tracking) metrics, PALMS Table I / PALMS+ Table 3 style, over records of one
// tracker on one walk:
//   rmse_m               RMSE of the position error over all steps after the first skip_first (6)
//   rmse_last_m          RMSE over the last last_n (10) steps
//   end_error_m          position error at the last step
//   success_<t>m         every one of the last last_n steps within t metres (1 m, 0.5 m)
//   converged            the tracker reported stage 2 (PALMS: the dominant cluster holds >= 50%)
//   convergence_{time_s,distance_m}[_stage1]   when (time, distance walked) each stage was reached
//   within_1m_after_convergence   share of the steps after convergence within 1 m ("% error < 1 m
//                        after convergence", PALMS Table I)
// A track that could not start (no pose from the first observation) counts as a failure with
// infinite errors. Aggregates are medians over walks (success and convergence as fractions), with
// bootstrap intervals like the single-shot metrics.
#pragma once

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "floorcast/eval/metrics.hpp"

namespace floorcast {

/// One tracker on one walk: per step after the initial observation (index 0 = the start).
struct SequentialRecord {
  std::vector<double> t_s;
  std::vector<double> distance_m;       ///< distance walked since the start
  std::vector<double> position_error_m;
  std::vector<double> yaw_error_deg;
  std::vector<int> stage;
  bool failed = false;                  ///< the tracker could not start
  double time_per_step_s = 0.0;         ///< mean tracker time per step (timing, not scored)
};

struct SequentialScoring {
  int skip_first = 6;        ///< PALMS: RMSE over the steps after the first 6
  int last_n = 10;           ///< PALMS: last 10 steps
  std::vector<double> success_thresholds_m = {1.0, 0.5};
  double within_m = 1.0;     ///< "% error < 1 m after convergence"
  int bootstrap_resamples = 1000;
  std::uint64_t bootstrap_seed = 0x5eed;
};

/// The per-walk outcome of a record.
struct SequentialOutcome {
  double rmse_m = std::numeric_limits<double>::infinity();
  double rmse_last_m = std::numeric_limits<double>::infinity();
  double end_error_m = std::numeric_limits<double>::infinity();
  std::vector<bool> success;  ///< per success threshold
  bool converged = false;
  double convergence_time_s = std::numeric_limits<double>::quiet_NaN();
  double convergence_distance_m = std::numeric_limits<double>::quiet_NaN();
  double stage1_time_s = std::numeric_limits<double>::quiet_NaN();
  double stage1_distance_m = std::numeric_limits<double>::quiet_NaN();
  double within_after_convergence = std::numeric_limits<double>::quiet_NaN();
};

SequentialOutcome score_track(const SequentialRecord& record, const SequentialScoring& scoring);

/// The per-walk success criteria in metric order: success_<t>m per threshold, then converged.
std::vector<SuccessCriterion<SequentialRecord>> sequential_success_criteria(const SequentialScoring& scoring);

/// The metric set, keyed as in summary.json: success_1m, success_0.5m, median_rmse_m,
/// median_rmse_last_m, median_end_error_m, converged, median_convergence_time_s,
/// median_convergence_distance_m, median_stage1_time_s, within_1m_after_convergence,
/// mean_time_per_step_s.
std::vector<Metric<SequentialRecord>> sequential_metrics(const SequentialScoring& scoring);

Summary summarize_sequential(const std::vector<SequentialRecord>& records, const SequentialScoring& scoring);

}  // namespace floorcast
