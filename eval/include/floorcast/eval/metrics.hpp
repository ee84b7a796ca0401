// Scoring: metrics over records of localization outcomes, with bootstrap confidence intervals.
//
// A metric is a named function of a sample of records. Single-shot records (one pose estimate
// per observation) come with the PALMS/PALMS+ metric set; sequential records (tracks) plug in
// the same way with their own record type and metric set (RMSE, success, convergence).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "floorcast/core/math.hpp"
#include "floorcast/core/random.hpp"

namespace floorcast {

/// Outcome of one single-shot localization (one observation, one method).
struct SingleShotRecord {
  double position_error_m = 0.0;  ///< |estimate - truth| in the plane
  double yaw_error_deg = 0.0;     ///< absolute heading error in [0, 180]
  /// Position / yaw errors of the top-K modes in rank order (the first equals the estimate).
  std::vector<double> top_k_position_error_m;
  std::vector<double> top_k_yaw_error_deg;
  double time_s = 0.0;  ///< matching time for this observation
};

/// A per-record yes/no outcome (e.g. "within 1 m and 30 deg"): the recall metrics are the share of
/// records where it holds, and paired tests (paired.hpp) compare two methods on it unit by unit.
template <class Record>
struct SuccessCriterion {
  std::string name;  ///< the recall metric's name, e.g. recall_1m_30deg
  std::function<bool(const Record&)> success;
};

template <class Record>
struct Metric {
  std::string name;
  std::function<double(const std::vector<const Record*>&)> compute;
  /// Whether bootstrap intervals make sense (not for e.g. counts).
  bool bootstrap = true;
};

struct ScoringParams {
  /// Position thresholds for recall (PALMS+ Table 1: 0.1 / 0.5 / 1 / 2 / 5 m).
  std::vector<double> recall_thresholds_m = {0.1, 0.5, 1.0, 2.0, 5.0};
  /// Combined position/orientation recall (PALMS+: @1 m, 30 deg).
  double combined_threshold_m = 1.0;
  double combined_threshold_deg = 30.0;
  /// Top-K recall at combined_threshold_m (best of the first K modes).
  int top_k = 5;
  /// Bootstrap resamples for 95% intervals; 0 disables them.
  int bootstrap_resamples = 1000;
  std::uint64_t bootstrap_seed = 0x5eed;
};

/// The single-shot success criteria in metric order: recall_<t>m per threshold, the combined
/// recall_<m>m_<d>deg and top<K>_recall_<m>m.
std::vector<SuccessCriterion<SingleShotRecord>> single_shot_success_criteria(const ScoringParams& params);

/// The single-shot metric set, keyed as in summary.json: recall_<t>m, recall_1m_30deg,
/// top5_recall_1m, median_position_error_m, mean_position_error_m, median_yaw_error_deg,
/// mean_yaw_error_deg, mean_time_s, median_time_s. Recalls are fractions in [0, 1].
std::vector<Metric<SingleShotRecord>> single_shot_metrics(const ScoringParams& params);

/// Formats a threshold as used in metric names: 0.1 -> "0.1m", 1 -> "1m".
std::string threshold_name(double metres);

struct MetricValue {
  double value = 0.0;
  double ci_low = 0.0;   ///< 2.5th percentile of the bootstrap distribution
  double ci_high = 0.0;  ///< 97.5th percentile
  bool has_ci = false;
};

struct Summary {
  int count = 0;
  std::vector<std::string> order;            ///< metric names in definition order
  std::map<std::string, MetricValue> values;
};

/// Index of draw i of bootstrap resample b over n records: the one counter-based stream every
/// bootstrap in eval uses, so per-method and paired intervals resample the same units.
inline std::size_t bootstrap_index(std::uint64_t seed, int resample, std::uint64_t i, std::uint64_t n) {
  const std::uint64_t h = mix64(seed ^ mix64((static_cast<std::uint64_t>(resample) << 32) ^ i));
  return static_cast<std::size_t>(h % n);
}

/// Evaluates every metric on all records, and bootstrap percentile intervals from resamples
/// drawn with a counter-based generator seeded by params.bootstrap_seed (deterministic).
template <class Record>
Summary summarize(const std::vector<Record>& records, const std::vector<Metric<Record>>& metrics,
                  int bootstrap_resamples, std::uint64_t seed);

Summary summarize_single_shot(const std::vector<SingleShotRecord>& records, const ScoringParams& params = {});

/// One sample scored with rejection (VoxelPlane-Reloc's TP/TN/FP/FN): a positive is observed in
/// the building it is matched against, a negative in another building or level.
struct RejectionRecord {
  bool positive = true;
  bool localized = false;  ///< the method gave a pose (did not abstain: "not localized")
  bool correct = false;    ///< positive, localized, and within the combined threshold (1 m, 30 deg)
  double time_s = 0.0;     ///< relocalization (matching) time
};

/// The rejection metric set, keyed as in summary.json ("rejection": {...}): tp (positives
/// localized correctly), fp_wrong_pose (positives localized elsewhere), fn (positives not
/// localized), tn (negatives not localized), fp_negative (negatives localized), fp (= both
/// false claims), precision = tp / (tp + fp), recall = tp / positives, f1, the paper's
/// precision_negatives_only = tp / (tp + fp_negative) (its tables count false positives on
/// negatives), abstain_rate (share of all samples not localized), mean_time_s (all samples).
/// Ratios with an empty denominator are NaN (written as null, "n/a").
std::vector<Metric<RejectionRecord>> rejection_metrics();
Summary summarize_rejection(const std::vector<RejectionRecord>& records, const ScoringParams& params = {});



template <class Record>
inline Summary summarize(const std::vector<Record>& records, const std::vector<Metric<Record>>& metrics,
                  int bootstrap_resamples, std::uint64_t seed) {
  Summary out;
  out.count = static_cast<int>(records.size());
  std::vector<const Record*> all;
  all.reserve(records.size());
  for (const Record& r : records) all.push_back(&r);
  for (const Metric<Record>& m : metrics) {
    out.order.push_back(m.name);
    out.values[m.name].value = m.compute(all);
  }
  if (bootstrap_resamples <= 0 || records.empty()) return out;

  // Percentile bootstrap: resample indices with a counter-based stream (resample b, draw i).
  std::map<std::string, std::vector<double>> draws;
  std::vector<const Record*> sample(records.size());
  const std::uint64_t n = records.size();
  for (int b = 0; b < bootstrap_resamples; ++b) {
    for (std::uint64_t i = 0; i < n; ++i) sample[i] = all[bootstrap_index(seed, b, i, n)];
    for (const Metric<Record>& m : metrics) {
      if (m.bootstrap) draws[m.name].push_back(m.compute(sample));
    }
  }
  // A draw is NaN where the metric is undefined on that resample (e.g. the median error of the
  // localized observations when none is): the interval is over the draws where it is defined, and
  // there is none when it is defined on no resample.
  for (auto& [name, v] : draws) {
    v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return std::isnan(x); }), v.end());
    if (v.empty()) continue;
    MetricValue& mv = out.values[name];
    mv.ci_low = quantile(v, 0.025);
    mv.ci_high = quantile(v, 0.975);
    mv.has_ci = true;
  }
  return out;
}


}  // namespace floorcast
