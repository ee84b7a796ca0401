#include "floorcast/eval/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <numeric>
#include <sstream>

namespace floorcast {



std::string threshold_name(double metres) {
  std::ostringstream os;
  os << std::setprecision(6) << metres << "m";
  return os.str();
}

namespace {

using Sample = std::vector<const SingleShotRecord*>;

double fraction(const Sample& s, const std::function<bool(const SingleShotRecord&)>& pred) {
  if (s.empty()) return 0.0;
  std::size_t hits = 0;
  for (const SingleShotRecord* r : s) hits += pred(*r) ? 1 : 0;
  return static_cast<double>(hits) / static_cast<double>(s.size());
}

template <class F>
std::vector<double> collect(const Sample& s, F f) {
  std::vector<double> v;
  v.reserve(s.size());
  for (const SingleShotRecord* r : s) v.push_back(f(*r));
  return v;
}

double mean_of(const std::vector<double>& v) {
  return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

}  // namespace

std::vector<SuccessCriterion<SingleShotRecord>> single_shot_success_criteria(const ScoringParams& params) {
  std::vector<SuccessCriterion<SingleShotRecord>> c;
  for (double t : params.recall_thresholds_m)
    c.push_back({"recall_" + threshold_name(t), [t](const SingleShotRecord& r) { return r.position_error_m <= t; }});
  const double cm = params.combined_threshold_m, cd = params.combined_threshold_deg;
  std::ostringstream deg;
  deg << std::setprecision(6) << cd;
  c.push_back({"recall_" + threshold_name(cm) + "_" + deg.str() + "deg",
               [cm, cd](const SingleShotRecord& r) { return r.position_error_m <= cm && r.yaw_error_deg <= cd; }});
  const int k = params.top_k;
  c.push_back({"top" + std::to_string(k) + "_recall_" + threshold_name(cm), [k, cm](const SingleShotRecord& r) {
                 const std::size_t n = std::min<std::size_t>(static_cast<std::size_t>(k), r.top_k_position_error_m.size());
                 for (std::size_t i = 0; i < n; ++i)
                   if (r.top_k_position_error_m[i] <= cm) return true;
                 return n == 0 && r.position_error_m <= cm;
               }});
  return c;
}

std::vector<Metric<SingleShotRecord>> single_shot_metrics(const ScoringParams& params) {
  std::vector<Metric<SingleShotRecord>> m;
  for (const SuccessCriterion<SingleShotRecord>& c : single_shot_success_criteria(params)) {
    m.push_back({c.name, [pred = c.success](const Sample& s) { return fraction(s, pred); }});
  }
  m.push_back({"median_position_error_m", [](const Sample& s) {
                 return median(collect(s, [](const SingleShotRecord& r) { return r.position_error_m; }));
               }});
  m.push_back({"mean_position_error_m", [](const Sample& s) {
                 return mean_of(collect(s, [](const SingleShotRecord& r) { return r.position_error_m; }));
               }});
  m.push_back({"median_yaw_error_deg", [](const Sample& s) {
                 return median(collect(s, [](const SingleShotRecord& r) { return r.yaw_error_deg; }));
               }});
  m.push_back({"mean_yaw_error_deg", [](const Sample& s) {
                 return mean_of(collect(s, [](const SingleShotRecord& r) { return r.yaw_error_deg; }));
               }});
  m.push_back({"mean_time_s", [](const Sample& s) {
                 return mean_of(collect(s, [](const SingleShotRecord& r) { return r.time_s; }));
               }});
  m.push_back({"median_time_s", [](const Sample& s) {
                 return median(collect(s, [](const SingleShotRecord& r) { return r.time_s; }));
               }});
  return m;
}

Summary summarize_single_shot(const std::vector<SingleShotRecord>& records, const ScoringParams& params) {
  return summarize(records, single_shot_metrics(params), params.bootstrap_resamples, params.bootstrap_seed);
}

namespace {

using RSample = std::vector<const RejectionRecord*>;

struct Counts {
  double tp = 0, fp_wrong = 0, fn = 0, tn = 0, fp_negative = 0, positives = 0, all = 0;
};
Counts count(const RSample& s) {
  Counts c;
  for (const RejectionRecord* r : s) {
    c.all += 1;
    if (r->positive) {
      c.positives += 1;
      if (!r->localized) c.fn += 1;
      else if (r->correct) c.tp += 1;
      else c.fp_wrong += 1;
    } else {
      if (r->localized) c.fp_negative += 1;
      else c.tn += 1;
    }
  }
  return c;
}
double ratio(double a, double b) { return b > 0.0 ? a / b : std::numeric_limits<double>::quiet_NaN(); }

}  // namespace

std::vector<Metric<RejectionRecord>> rejection_metrics() {
  std::vector<Metric<RejectionRecord>> m;
  m.push_back({"tp", [](const RSample& s) { return count(s).tp; }, false});
  m.push_back({"fp", [](const RSample& s) { const Counts c = count(s); return c.fp_wrong + c.fp_negative; }, false});
  m.push_back({"tn", [](const RSample& s) { return count(s).tn; }, false});
  m.push_back({"fn", [](const RSample& s) { return count(s).fn; }, false});
  m.push_back({"fp_negative", [](const RSample& s) { return count(s).fp_negative; }, false});
  m.push_back({"fp_wrong_pose", [](const RSample& s) { return count(s).fp_wrong; }, false});
  m.push_back({"precision", [](const RSample& s) {
                 const Counts c = count(s);
                 return ratio(c.tp, c.tp + c.fp_wrong + c.fp_negative);
               }});
  m.push_back({"recall", [](const RSample& s) { const Counts c = count(s); return ratio(c.tp, c.positives); }});
  m.push_back({"f1", [](const RSample& s) {
                 const Counts c = count(s);
                 const double p = ratio(c.tp, c.tp + c.fp_wrong + c.fp_negative), r = ratio(c.tp, c.positives);
                 return std::isfinite(p) && std::isfinite(r) ? (p + r > 0.0 ? 2.0 * p * r / (p + r) : 0.0)
                                                             : std::numeric_limits<double>::quiet_NaN();
               }});
  m.push_back({"precision_negatives_only", [](const RSample& s) {
                 const Counts c = count(s);
                 return ratio(c.tp, c.tp + c.fp_negative);
               }});
  m.push_back({"abstain_rate", [](const RSample& s) { const Counts c = count(s); return ratio(c.fn + c.tn, c.all); }});
  m.push_back({"mean_time_s", [](const RSample& s) {
                 double t = 0.0;
                 for (const RejectionRecord* r : s) t += r->time_s;
                 return s.empty() ? 0.0 : t / static_cast<double>(s.size());
               }});
  return m;
}

Summary summarize_rejection(const std::vector<RejectionRecord>& records, const ScoringParams& params) {
  return summarize(records, rejection_metrics(), params.bootstrap_resamples, params.bootstrap_seed);
}

}  // namespace floorcast
