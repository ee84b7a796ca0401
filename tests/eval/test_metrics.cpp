#include <gtest/gtest.h>

#include <cmath>

#include "floorcast/eval/metrics.hpp"

namespace floorcast {
namespace {

SingleShotRecord rec(double pos, double yaw, std::vector<double> topk = {}) {
  SingleShotRecord r;
  r.position_error_m = pos;
  r.yaw_error_deg = yaw;
  r.top_k_position_error_m = topk.empty() ? std::vector<double>{pos} : topk;
  r.top_k_yaw_error_deg.assign(r.top_k_position_error_m.size(), yaw);
  r.time_s = 0.5;
  return r;
}

// Scoring with rejection: 4 positives (2 correct, 1 wrong pose, 1 not localized) and 3 negatives
// (1 localized, 2 rejected).
TEST(Metrics, RejectionKnownAnswers) {
  const std::vector<RejectionRecord> r = {{true, true, true, 0.1},   {true, true, true, 0.1},   {true, true, false, 0.1},
                                          {true, false, false, 0.1}, {false, true, false, 0.2}, {false, false, false, 0.2},
                                          {false, false, false, 0.2}};
  ScoringParams p;
  p.bootstrap_resamples = 50;
  const Summary s = summarize_rejection(r, p);
  auto v = [&](const char* k) { return s.values.at(k).value; };
  EXPECT_EQ(v("tp"), 2.0);
  EXPECT_EQ(v("fp"), 2.0);
  EXPECT_EQ(v("fp_wrong_pose"), 1.0);
  EXPECT_EQ(v("fp_negative"), 1.0);
  EXPECT_EQ(v("tn"), 2.0);
  EXPECT_EQ(v("fn"), 1.0);
  EXPECT_DOUBLE_EQ(v("precision"), 0.5);
  EXPECT_DOUBLE_EQ(v("recall"), 0.5);
  EXPECT_DOUBLE_EQ(v("f1"), 0.5);
  EXPECT_DOUBLE_EQ(v("precision_negatives_only"), 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(v("abstain_rate"), 3.0 / 7.0);
  EXPECT_NEAR(v("mean_time_s"), 1.0 / 7.0, 1e-12);
  EXPECT_TRUE(s.values.at("precision").has_ci);
  EXPECT_FALSE(s.values.at("tp").has_ci);
  // A method that never answers has no precision (NaN, "n/a"), recall 0, and no crash in the
  // bootstrap.
  std::vector<RejectionRecord> silent = r;
  for (RejectionRecord& x : silent) x.localized = x.correct = false;
  const Summary q = summarize_rejection(silent, p);
  EXPECT_TRUE(std::isnan(q.values.at("precision").value));
  EXPECT_EQ(q.values.at("recall").value, 0.0);
  EXPECT_FALSE(q.values.at("precision").has_ci);
}

TEST(Metrics, KnownAnswers) {
  // 10 records: errors 0.05, 0.3, 0.8 (yaw 90), 1.5, 3, 10 x5 with one top-5 rescue.
  std::vector<SingleShotRecord> r = {rec(0.05, 1), rec(0.3, 2), rec(0.8, 90), rec(1.5, 3), rec(3.0, 4),
                                     rec(10, 5, {10, 20, 0.7}), rec(10, 5), rec(10, 5), rec(10, 5), rec(10, 5)};
  ScoringParams p;
  p.bootstrap_resamples = 0;
  const Summary s = summarize_single_shot(r, p);
  EXPECT_EQ(s.count, 10);
  EXPECT_DOUBLE_EQ(s.values.at("recall_0.1m").value, 0.1);
  EXPECT_DOUBLE_EQ(s.values.at("recall_0.5m").value, 0.2);
  EXPECT_DOUBLE_EQ(s.values.at("recall_1m").value, 0.3);
  EXPECT_DOUBLE_EQ(s.values.at("recall_1m_30deg").value, 0.2);  // the 0.8 m one is 90 deg off
  EXPECT_DOUBLE_EQ(s.values.at("recall_2m").value, 0.4);
  EXPECT_DOUBLE_EQ(s.values.at("recall_5m").value, 0.5);
  EXPECT_DOUBLE_EQ(s.values.at("top5_recall_1m").value, 0.4);  // + the third mode at 0.7 m
  EXPECT_DOUBLE_EQ(s.values.at("median_position_error_m").value, 0.5 * (3.0 + 10.0));
  EXPECT_DOUBLE_EQ(s.values.at("mean_time_s").value, 0.5);
  EXPECT_FALSE(s.values.at("recall_1m").has_ci);
  ASSERT_EQ(s.order.front(), "recall_0.1m");
}

TEST(Metrics, MedianOddEvenEmpty) {
  EXPECT_DOUBLE_EQ(median({3, 1, 2}), 2.0);
  EXPECT_DOUBLE_EQ(median({4, 1, 3, 2}), 2.5);
  EXPECT_DOUBLE_EQ(median({}), 0.0);
}

TEST(Metrics, BootstrapIntervalsAreDeterministicAndShrinkWithN) {
  auto make = [](int n) {
    std::vector<SingleShotRecord> r;
    for (int i = 0; i < n; ++i) r.push_back(rec(mix64(static_cast<std::uint64_t>(i)) % 2 ? 0.2 : 5.0, 1));
    return r;
  };
  ScoringParams p;
  p.bootstrap_resamples = 400;
  const Summary small = summarize_single_shot(make(20), p);
  const Summary small_again = summarize_single_shot(make(20), p);
  const Summary big = summarize_single_shot(make(400), p);
  const MetricValue& a = small.values.at("recall_1m");
  EXPECT_TRUE(a.has_ci);
  EXPECT_EQ(a.ci_low, small_again.values.at("recall_1m").ci_low);
  EXPECT_EQ(a.ci_high, small_again.values.at("recall_1m").ci_high);
  EXPECT_LE(a.ci_low, a.value);
  EXPECT_GE(a.ci_high, a.value);
  const MetricValue& b = big.values.at("recall_1m");
  EXPECT_LT(b.ci_high - b.ci_low, a.ci_high - a.ci_low);
  // The interval of a proportion with n = 400 around 0.5 is about +-0.05.
  EXPECT_NEAR(b.ci_high - b.ci_low, 2 * 1.96 * std::sqrt(0.25 / 400), 0.03);
}

TEST(Metrics, CustomMetricsPlugIn) {
  // A sequential-style metric on another record type uses the same machinery.
  struct Track { double rmse; };
  std::vector<Track> tracks = {{1.0}, {2.0}, {3.0}};
  std::vector<Metric<Track>> metrics = {{"mean_rmse", [](const std::vector<const Track*>& s) {
                                            double t = 0;
                                            for (auto* x : s) t += x->rmse;
                                            return s.empty() ? 0.0 : t / s.size();
                                          }, true}};
  const Summary s = summarize(tracks, metrics, 50, 1);
  EXPECT_DOUBLE_EQ(s.values.at("mean_rmse").value, 2.0);
  EXPECT_TRUE(s.values.at("mean_rmse").has_ci);
}

}  // namespace
}  // namespace floorcast
