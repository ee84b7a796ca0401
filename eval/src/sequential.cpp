#include "floorcast/eval/sequential.hpp"

#include <algorithm>

namespace floorcast {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double rmse(const std::vector<double>& e, std::size_t from, std::size_t to) {
  if (from >= to) return std::numeric_limits<double>::infinity();
  double s = 0.0;
  for (std::size_t i = from; i < to; ++i) s += e[i] * e[i];
  return std::sqrt(s / static_cast<double>(to - from));
}

/// Median of the finite values (NaN when none); infinite values count (as the largest).
double median_of_defined(std::vector<double> v) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return std::isnan(x); }), v.end());
  return v.empty() ? kNaN : median(v);
}

}  // namespace

SequentialOutcome score_track(const SequentialRecord& r, const SequentialScoring& sc) {
  SequentialOutcome o;
  o.success.assign(sc.success_thresholds_m.size(), false);
  const std::size_t n = r.position_error_m.size();
  if (r.failed || n == 0) return o;
  o.rmse_m = rmse(r.position_error_m, std::min<std::size_t>(static_cast<std::size_t>(sc.skip_first), n - 1), n);
  const std::size_t last_from = n > static_cast<std::size_t>(sc.last_n) ? n - static_cast<std::size_t>(sc.last_n) : 0;
  o.rmse_last_m = rmse(r.position_error_m, last_from, n);
  o.end_error_m = r.position_error_m.back();
  for (std::size_t k = 0; k < sc.success_thresholds_m.size(); ++k) {
    bool all = true;
    for (std::size_t i = last_from; i < n; ++i) all = all && r.position_error_m[i] <= sc.success_thresholds_m[k];
    o.success[k] = all;
  }
  std::size_t conv = n;
  for (std::size_t i = 0; i < n && i < r.stage.size(); ++i) {
    if (std::isnan(o.stage1_time_s) && r.stage[i] >= 1) {
      o.stage1_time_s = r.t_s[i];
      o.stage1_distance_m = r.distance_m[i];
    }
    if (r.stage[i] >= 2) {
      conv = i;
      break;
    }
  }
  if (conv < n) {
    o.converged = true;
    o.convergence_time_s = r.t_s[conv];
    o.convergence_distance_m = r.distance_m[conv];
    std::size_t within = 0;
    for (std::size_t i = conv; i < n; ++i) within += r.position_error_m[i] <= sc.within_m ? 1 : 0;
    o.within_after_convergence = static_cast<double>(within) / static_cast<double>(n - conv);
  }
  return o;
}

std::vector<SuccessCriterion<SequentialRecord>> sequential_success_criteria(const SequentialScoring& sc) {
  std::vector<SuccessCriterion<SequentialRecord>> c;
  for (std::size_t k = 0; k < sc.success_thresholds_m.size(); ++k)
    c.push_back({"success_" + threshold_name(sc.success_thresholds_m[k]),
                 [sc, k](const SequentialRecord& r) -> bool { return score_track(r, sc).success[k]; }});
  c.push_back({"converged", [sc](const SequentialRecord& r) { return score_track(r, sc).converged; }});
  return c;
}

std::vector<Metric<SequentialRecord>> sequential_metrics(const SequentialScoring& sc) {
  using Sample = std::vector<const SequentialRecord*>;
  auto outcomes = [sc](const Sample& s) {
    std::vector<SequentialOutcome> out;
    out.reserve(s.size());
    for (const SequentialRecord* r : s) out.push_back(score_track(*r, sc));
    return out;
  };
  auto share = [](const std::function<bool(const SequentialRecord&)>& pred) {
    return [pred](const Sample& s) {
      if (s.empty()) return 0.0;
      double hits = 0.0;
      for (const SequentialRecord* r : s) hits += pred(*r) ? 1.0 : 0.0;
      return hits / static_cast<double>(s.size());
    };
  };
  const std::vector<SuccessCriterion<SequentialRecord>> criteria = sequential_success_criteria(sc);
  std::vector<Metric<SequentialRecord>> m;
  for (std::size_t k = 0; k + 1 < criteria.size(); ++k) m.push_back({criteria[k].name, share(criteria[k].success)});
  auto median_of = [outcomes](double SequentialOutcome::*field) {
    return [outcomes, field](const Sample& s) {
      std::vector<double> v;
      for (const auto& o : outcomes(s)) v.push_back(o.*field);
      return median_of_defined(v);
    };
  };
  m.push_back({"median_rmse_m", median_of(&SequentialOutcome::rmse_m)});
  m.push_back({"median_rmse_last_m", median_of(&SequentialOutcome::rmse_last_m)});
  m.push_back({"median_end_error_m", median_of(&SequentialOutcome::end_error_m)});
  m.push_back({criteria.back().name, share(criteria.back().success)});
  m.push_back({"median_convergence_time_s", median_of(&SequentialOutcome::convergence_time_s)});
  m.push_back({"median_convergence_distance_m", median_of(&SequentialOutcome::convergence_distance_m)});
  m.push_back({"median_stage1_time_s", median_of(&SequentialOutcome::stage1_time_s)});
  m.push_back({"within_" + threshold_name(sc.within_m) + "_after_convergence", [outcomes](const Sample& s) {
                 std::vector<double> v;
                 for (const auto& o : outcomes(s))
                   if (!std::isnan(o.within_after_convergence)) v.push_back(o.within_after_convergence);
                 if (v.empty()) return kNaN;
                 double sum = 0.0;
                 for (double x : v) sum += x;
                 return sum / static_cast<double>(v.size());
               }});
  m.push_back({"mean_time_per_step_s",
               [](const Sample& s) {
                 if (s.empty()) return 0.0;
                 double t = 0.0;
                 for (const SequentialRecord* r : s) t += r->time_per_step_s;
                 return t / static_cast<double>(s.size());
               },
               false});
  return m;
}

Summary summarize_sequential(const std::vector<SequentialRecord>& records, const SequentialScoring& sc) {
  return summarize(records, sequential_metrics(sc), sc.bootstrap_resamples, sc.bootstrap_seed);
}

}  // namespace floorcast
