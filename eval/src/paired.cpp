#include "floorcast/eval/paired.hpp"

#include <cmath>
#include <stdexcept>

namespace floorcast {

double mcnemar_exact_p_value(int only_a, int only_b) {
  if (only_a < 0 || only_b < 0) throw std::invalid_argument("McNemar: negative discordant count");
  const int n = only_a + only_b;
  if (n == 0) return 1.0;
  const int m = std::min(only_a, only_b);
  // P[X <= m] for X ~ Binomial(n, 1/2), summed in log space (0.5^n underflows past n ~ 1074).
  const double log_half_n = -static_cast<double>(n) * std::log(2.0);
  const double lg_n1 = std::lgamma(static_cast<double>(n) + 1.0);
  double tail = 0.0;
  for (int k = 0; k <= m; ++k)
    tail += std::exp(lg_n1 - std::lgamma(k + 1.0) - std::lgamma(static_cast<double>(n - k) + 1.0) + log_half_n);
  return std::min(1.0, 2.0 * tail);
}

McNemarTest mcnemar_exact(const std::vector<bool>& success_a, const std::vector<bool>& success_b) {
  if (success_a.size() != success_b.size())
    throw std::invalid_argument("McNemar: " + std::to_string(success_a.size()) + " outcomes of A but " +
                                std::to_string(success_b.size()) + " of B (pairs need the same units)");
  McNemarTest t;
  for (std::size_t i = 0; i < success_a.size(); ++i) {
    if (success_a[i] && success_b[i]) ++t.both;
    else if (success_a[i]) ++t.only_a;
    else if (success_b[i]) ++t.only_b;
    else ++t.neither;
  }
  t.p_value = mcnemar_exact_p_value(t.only_a, t.only_b);
  return t;
}

PairedComparison compare_single_shot(const std::string& label_a, const std::vector<SingleShotRecord>& a,
                                     const std::string& label_b, const std::vector<SingleShotRecord>& b,
                                     const ScoringParams& params) {
  std::vector<Metric<SingleShotRecord>> metrics;
  for (Metric<SingleShotRecord>& m : single_shot_metrics(params))
    if (m.name == "median_position_error_m") metrics.push_back(std::move(m));
  return compare_paired(label_a, a, label_b, b, single_shot_success_criteria(params), metrics, {false},
                        params.bootstrap_resamples, params.bootstrap_seed);
}

PairedComparison compare_sequential(const std::string& label_a, const std::vector<SequentialRecord>& a,
                                    const std::string& label_b, const std::vector<SequentialRecord>& b,
                                    const SequentialScoring& scoring) {
  std::vector<Metric<SequentialRecord>> metrics;
  for (const char* name : {"median_rmse_m", "median_end_error_m"})
    for (const Metric<SequentialRecord>& m : sequential_metrics(scoring))
      if (m.name == name) metrics.push_back(m);
  return compare_paired(label_a, a, label_b, b, sequential_success_criteria(scoring), metrics, {false, false},
                        scoring.bootstrap_resamples, scoring.bootstrap_seed);
}

}  // namespace floorcast
