// Paired comparisons: does method A beat method B on the *same* units (observation points or
// walks)? Per-method bootstrap intervals answer "how sure are we of A's recall"; they overlap long
// after a paired test is decisive, because both methods share every unit's difficulty.
//
//   McNemar's exact test on a yes/no outcome (e.g. within 1 m and 30 deg): only the discordant
//   units count (A right and B wrong: only_a; the reverse: only_b). Under "no difference" each
//   discordant unit is a fair coin, so the two-sided p-value is
//       p = min(1, 2 * P[X <= min(only_a, only_b)]),  X ~ Binomial(only_a + only_b, 1/2).
//   Paired bootstrap: resample units (both methods' records of a unit together) and take the
//   2.5th / 97.5th percentiles of metric(A) - metric(B) over the resamples. The resamples are the
//   ones summarize() draws (bootstrap_index), so they are deterministic for a seed.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "floorcast/eval/metrics.hpp"
#include "floorcast/eval/sequential.hpp"

namespace floorcast {

struct McNemarTest {
  int both = 0;     ///< units where both methods succeed
  int only_a = 0;   ///< A succeeds, B fails
  int only_b = 0;   ///< B succeeds, A fails
  int neither = 0;
  double p_value = 1.0;  ///< two-sided exact (1 when there are no discordant units)
};

/// Two-sided exact McNemar p-value from the discordant counts (see the file comment).
double mcnemar_exact_p_value(int only_a, int only_b);

/// McNemar's exact test on paired outcomes; throws std::invalid_argument for unequal lengths.
McNemarTest mcnemar_exact(const std::vector<bool>& success_a, const std::vector<bool>& success_b);

/// metric(A) - metric(B) on all units, with a paired bootstrap percentile interval.
struct PairedDifference {
  double value = std::numeric_limits<double>::quiet_NaN();  ///< NaN when undefined (inf - inf)
  double ci_low = std::numeric_limits<double>::quiet_NaN();
  double ci_high = std::numeric_limits<double>::quiet_NaN();
  /// False without resamples, without units, or when some resample's difference is undefined
  /// (both medians infinite: more than half of both methods' units failed).
  bool has_ci = false;
};

/// Paired bootstrap of metric(A) - metric(B); a[i] and b[i] are the two methods' records of unit
/// i (throws std::invalid_argument for unequal lengths).
template <class Record>
PairedDifference paired_bootstrap_difference(const std::vector<Record>& a, const std::vector<Record>& b,
                                             const std::function<double(const std::vector<const Record*>&)>& metric,
                                             int resamples, std::uint64_t seed);

/// One yes/no criterion compared on paired units: the McNemar test and the paired interval of
/// the difference in recall (A - B, a fraction).
struct PairedCriterion {
  std::string name;  ///< the recall metric, e.g. recall_1m_30deg
  McNemarTest test;
  PairedDifference difference;
};

/// A continuous metric compared on paired units (e.g. median_position_error_m: A - B).
struct PairedMetric {
  std::string name;
  bool higher_is_better = false;
  PairedDifference difference;
};

struct PairedComparison {
  std::string a, b;  ///< method labels
  int count = 0;     ///< paired units
  std::vector<PairedCriterion> criteria;
  std::vector<PairedMetric> metrics;
};

/// The generic comparison: every criterion (McNemar + paired interval of the recall difference)
/// and every metric (paired interval), from one set of resamples.
template <class Record>
PairedComparison compare_paired(const std::string& label_a, const std::vector<Record>& a, const std::string& label_b,
                                const std::vector<Record>& b, const std::vector<SuccessCriterion<Record>>& criteria,
                                const std::vector<Metric<Record>>& metrics, const std::vector<bool>& higher_is_better,
                                int resamples, std::uint64_t seed);

/// Single-shot: every recall criterion (single_shot_success_criteria) and the median position
/// error, with params' bootstrap resamples and seed.
PairedComparison compare_single_shot(const std::string& label_a, const std::vector<SingleShotRecord>& a,
                                     const std::string& label_b, const std::vector<SingleShotRecord>& b,
                                     const ScoringParams& params);

/// Sequential: success_<t>m and converged (sequential_success_criteria), and the median RMSE and
/// median end error over walks.
PairedComparison compare_sequential(const std::string& label_a, const std::vector<SequentialRecord>& a,
                                    const std::string& label_b, const std::vector<SequentialRecord>& b,
                                    const SequentialScoring& scoring);



template <class Record>
PairedDifference paired_bootstrap_difference(const std::vector<Record>& a, const std::vector<Record>& b,
                                             const std::function<double(const std::vector<const Record*>&)>& metric,
                                             int resamples, std::uint64_t seed) {
  if (a.size() != b.size())
    throw std::invalid_argument("paired bootstrap: " + std::to_string(a.size()) + " records of A but " +
                                std::to_string(b.size()) + " of B (pairs need the same units)");
  auto difference = [](double x, double y) {
    if (std::isinf(x) && std::isinf(y) && (x > 0) == (y > 0)) return std::numeric_limits<double>::quiet_NaN();
    return x - y;
  };
  const std::size_t n = a.size();
  std::vector<const Record*> sa(n), sb(n);
  for (std::size_t i = 0; i < n; ++i) {
    sa[i] = &a[i];
    sb[i] = &b[i];
  }
  PairedDifference out;
  out.value = difference(metric(sa), metric(sb));
  if (resamples <= 0 || n == 0) return out;
  std::vector<double> draws;
  draws.reserve(static_cast<std::size_t>(resamples));
  for (int r = 0; r < resamples; ++r) {
    for (std::uint64_t i = 0; i < n; ++i) {
      const std::size_t k = bootstrap_index(seed, r, i, n);
      sa[i] = &a[k];
      sb[i] = &b[k];
    }
    const double d = difference(metric(sa), metric(sb));
    if (std::isnan(d)) return out;  // undefined in some resample: no interval
    draws.push_back(d);
  }
  out.ci_low = quantile(draws, 0.025);
  out.ci_high = quantile(draws, 0.975);
  out.has_ci = true;
  return out;
}

template <class Record>
PairedComparison compare_paired(const std::string& label_a, const std::vector<Record>& a, const std::string& label_b,
                                const std::vector<Record>& b, const std::vector<SuccessCriterion<Record>>& criteria,
                                const std::vector<Metric<Record>>& metrics, const std::vector<bool>& higher_is_better,
                                int resamples, std::uint64_t seed) {
  if (a.size() != b.size())
    throw std::invalid_argument("paired comparison of " + label_a + " and " + label_b + ": " + std::to_string(a.size()) +
                                " vs " + std::to_string(b.size()) + " records (pairs need the same units)");
  PairedComparison out;
  out.a = label_a;
  out.b = label_b;
  out.count = static_cast<int>(a.size());
  for (const SuccessCriterion<Record>& c : criteria) {
    std::vector<bool> ya(a.size()), yb(b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
      ya[i] = c.success(a[i]);
      yb[i] = c.success(b[i]);
    }
    PairedCriterion pc;
    pc.name = c.name;
    pc.test = mcnemar_exact(ya, yb);
    // The recall difference resampled on the precomputed outcomes (one record = one 0/1).
    std::vector<double> da(a.size()), db(b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
      da[i] = ya[i] ? 1.0 : 0.0;
      db[i] = yb[i] ? 1.0 : 0.0;
    }
    const std::function<double(const std::vector<const double*>&)> share = [](const std::vector<const double*>& s) {
      if (s.empty()) return 0.0;
      double t = 0.0;
      for (const double* x : s) t += *x;
      return t / static_cast<double>(s.size());
    };
    pc.difference = paired_bootstrap_difference(da, db, share, resamples, seed);
    out.criteria.push_back(std::move(pc));
  }
  for (std::size_t k = 0; k < metrics.size(); ++k) {
    PairedMetric pm;
    pm.name = metrics[k].name;
    pm.higher_is_better = k < higher_is_better.size() && higher_is_better[k];
    pm.difference = paired_bootstrap_difference(a, b, metrics[k].compute, resamples, seed);
    out.metrics.push_back(std::move(pm));
  }
  return out;
}

}  // namespace floorcast
