#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "floorcast/eval/paired.hpp"

namespace floorcast {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

SingleShotRecord rec(double pos, double yaw = 1.0) {
  SingleShotRecord r;
  r.position_error_m = pos;
  r.yaw_error_deg = yaw;
  r.top_k_position_error_m = {pos};
  r.top_k_yaw_error_deg = {yaw};
  return r;
}

TEST(McNemar, ExactPValuesByHand) {
  // Two-sided p = min(1, 2 * sum_{k <= min(b, c)} C(b + c, k) / 2^(b + c)).
  EXPECT_DOUBLE_EQ(mcnemar_exact_p_value(0, 0), 1.0);
  EXPECT_NEAR(mcnemar_exact_p_value(0, 5), 2.0 / 32.0, 1e-12);                 // 0.0625
  EXPECT_NEAR(mcnemar_exact_p_value(1, 6), 2.0 * (1 + 7) / 128.0, 1e-12);      // 0.125
  EXPECT_NEAR(mcnemar_exact_p_value(12, 2), 2.0 * (1 + 14 + 91) / 16384.0, 1e-12);  // 0.01294
  EXPECT_NEAR(mcnemar_exact_p_value(10, 0), 2.0 / 1024.0, 1e-12);
  EXPECT_DOUBLE_EQ(mcnemar_exact_p_value(5, 5), 1.0);   // 2 * 638 / 1024 > 1, clamped
  EXPECT_NEAR(mcnemar_exact_p_value(3, 4), 1.0, 1e-12);  // 2 * 64 / 128
  EXPECT_DOUBLE_EQ(mcnemar_exact_p_value(4, 9), mcnemar_exact_p_value(9, 4));
  // Large counts (0.5^n underflows beyond n ~ 1074): close to the continuity-corrected
  // chi-square approximation (|b - c| - 1)^2 / (b + c) = 8.91 -> p = 0.00284.
  const double p = mcnemar_exact_p_value(500, 600);
  EXPECT_NEAR(p, std::erfc(std::sqrt(99.0 * 99.0 / 1100.0 / 2.0)), 3e-4);
  EXPECT_DOUBLE_EQ(mcnemar_exact_p_value(1000, 1000), 1.0);
  EXPECT_GE(mcnemar_exact_p_value(0, 1500), 0.0);
  EXPECT_LT(mcnemar_exact_p_value(0, 1500), 1e-300);
  EXPECT_THROW(mcnemar_exact_p_value(-1, 2), std::invalid_argument);
}

TEST(McNemar, CountsTheFourCells) {
  const McNemarTest t = mcnemar_exact({true, true, false, false, true, false}, {true, false, true, false, false, false});
  EXPECT_EQ(t.both, 1);
  EXPECT_EQ(t.only_a, 2);
  EXPECT_EQ(t.only_b, 1);
  EXPECT_EQ(t.neither, 2);
  EXPECT_DOUBLE_EQ(t.p_value, 1.0);
  EXPECT_THROW(mcnemar_exact({true}, {true, false}), std::invalid_argument);
}

// 100 units; B succeeds on 50 of them, A on those and 10 more. Each method's 95% interval is
// about +-10 points wide, so they overlap (A [0.5, 0.7], B [0.4, 0.6]), yet the paired test is
// decisive: 10 discordant units, all for A (p = 2 / 2^10), and the paired interval of the
// difference is 0.10 +- 1.96 * sqrt((0.10 - 0.10^2) / 100) = [0.041, 0.159] by hand.
TEST(Paired, OverlappingIntervalsButDecisivePairedTest) {
  std::vector<SingleShotRecord> a, b;
  for (int i = 0; i < 100; ++i) {
    a.push_back(rec(i < 60 ? 0.2 : 4.0));
    b.push_back(rec(i < 50 ? 0.2 : 4.0));
  }
  ScoringParams p;
  p.bootstrap_resamples = 2000;
  const Summary sa = summarize_single_shot(a, p), sb = summarize_single_shot(b, p);
  const MetricValue& ra = sa.values.at("recall_1m_30deg");
  const MetricValue& rb = sb.values.at("recall_1m_30deg");
  ASSERT_TRUE(ra.has_ci && rb.has_ci);
  EXPECT_LT(ra.ci_low, rb.ci_high) << "the per-method intervals overlap";

  const PairedComparison c = compare_single_shot("A", a, "B", b, p);
  EXPECT_EQ(c.count, 100);
  const PairedCriterion* combined = nullptr;
  for (const PairedCriterion& x : c.criteria)
    if (x.name == "recall_1m_30deg") combined = &x;
  ASSERT_NE(combined, nullptr);
  EXPECT_EQ(combined->test.only_a, 10);
  EXPECT_EQ(combined->test.only_b, 0);
  EXPECT_EQ(combined->test.both, 50);
  EXPECT_EQ(combined->test.neither, 40);
  EXPECT_NEAR(combined->test.p_value, 0.001953125, 1e-12);
  EXPECT_NEAR(combined->difference.value, 0.10, 1e-12);
  ASSERT_TRUE(combined->difference.has_ci);
  EXPECT_GT(combined->difference.ci_low, 0.0) << "the paired interval excludes no difference";
  EXPECT_NEAR(combined->difference.ci_low, 0.041, 0.02);
  EXPECT_NEAR(combined->difference.ci_high, 0.159, 0.02);
  // Below 0.1 m neither succeeds anywhere: no discordant unit, p = 1, difference exactly 0.
  EXPECT_EQ(c.criteria.front().name, "recall_0.1m");
  EXPECT_DOUBLE_EQ(c.criteria.front().test.p_value, 1.0);
  EXPECT_DOUBLE_EQ(c.criteria.front().difference.ci_low, 0.0);
  EXPECT_DOUBLE_EQ(c.criteria.front().difference.ci_high, 0.0);
}

TEST(Paired, CriteriaFollowTheRecallMetricsAndTheirValues) {
  std::vector<SingleShotRecord> a, b;
  for (int i = 0; i < 37; ++i) {
    a.push_back(rec(0.05 * static_cast<double>(mix64(static_cast<std::uint64_t>(i)) % 200), static_cast<double>(i % 50)));
    b.push_back(rec(0.05 * static_cast<double>(mix64(static_cast<std::uint64_t>(i) + 99) % 200), static_cast<double>(i % 40)));
  }
  ScoringParams p;
  p.bootstrap_resamples = 300;
  const PairedComparison c = compare_single_shot("A", a, "B", b, p);
  const Summary sa = summarize_single_shot(a, p), sb = summarize_single_shot(b, p);
  const auto criteria = single_shot_success_criteria(p);
  ASSERT_EQ(c.criteria.size(), criteria.size());
  for (std::size_t k = 0; k < criteria.size(); ++k) {
    EXPECT_EQ(c.criteria[k].name, criteria[k].name);
    EXPECT_NEAR(c.criteria[k].difference.value,
                sa.values.at(criteria[k].name).value - sb.values.at(criteria[k].name).value, 1e-12);
    EXPECT_EQ(c.criteria[k].test.both + c.criteria[k].test.only_a + c.criteria[k].test.only_b + c.criteria[k].test.neither, 37);
  }
  ASSERT_EQ(c.metrics.size(), 1u);
  EXPECT_EQ(c.metrics[0].name, "median_position_error_m");
  EXPECT_FALSE(c.metrics[0].higher_is_better);
  EXPECT_DOUBLE_EQ(c.metrics[0].difference.value,
                   sa.values.at("median_position_error_m").value - sb.values.at("median_position_error_m").value);
}

TEST(Paired, SameResamplesAsTheSummary) {
  // Against a method that never succeeds, the paired difference in every resample is A's own
  // recall in that resample: the paired interval equals A's bootstrap interval exactly.
  std::vector<SingleShotRecord> a, never;
  for (int i = 0; i < 50; ++i) {
    a.push_back(rec(mix64(static_cast<std::uint64_t>(i)) % 3 ? 0.3 : 7.0));
    never.push_back(rec(kInf, 180.0));
  }
  ScoringParams p;
  p.bootstrap_resamples = 500;
  const MetricValue own = summarize_single_shot(a, p).values.at("recall_1m");
  const PairedComparison c = compare_single_shot("A", a, "never", never, p);
  ASSERT_EQ(c.criteria[2].name, "recall_1m");
  EXPECT_DOUBLE_EQ(c.criteria[2].difference.ci_low, own.ci_low);
  EXPECT_DOUBLE_EQ(c.criteria[2].difference.ci_high, own.ci_high);
  // The median error of a method that always fails is infinite: the difference is -inf, and an
  // interval of infinities (defined, not NaN).
  EXPECT_EQ(c.metrics[0].difference.value, -kInf);
}

TEST(Paired, MedianErrorShiftIsExact) {
  // A's error is B's minus 0.5 m on every unit (multiples of 0.25: exact in floating point), so
  // every resample's difference of medians is exactly -0.5.
  std::vector<SingleShotRecord> a, b;
  for (int i = 0; i < 41; ++i) {
    const double e = 0.5 + 0.25 * static_cast<double>(mix64(static_cast<std::uint64_t>(i)) % 40);
    b.push_back(rec(e));
    a.push_back(rec(e - 0.5));
  }
  ScoringParams p;
  p.bootstrap_resamples = 400;
  const PairedComparison c = compare_single_shot("A", a, "B", b, p);
  EXPECT_DOUBLE_EQ(c.metrics[0].difference.value, -0.5);
  ASSERT_TRUE(c.metrics[0].difference.has_ci);
  EXPECT_DOUBLE_EQ(c.metrics[0].difference.ci_low, -0.5);
  EXPECT_DOUBLE_EQ(c.metrics[0].difference.ci_high, -0.5);
}

TEST(Paired, SwapNegatesAndSeedDetermines) {
  std::vector<SingleShotRecord> a, b;
  for (int i = 0; i < 60; ++i) {
    a.push_back(rec(0.1 * static_cast<double>(mix64(static_cast<std::uint64_t>(i)) % 30)));
    b.push_back(rec(0.1 * static_cast<double>(mix64(static_cast<std::uint64_t>(i) + 7) % 30)));
  }
  ScoringParams p;
  p.bootstrap_resamples = 400;
  const PairedComparison ab = compare_single_shot("A", a, "B", b, p);
  const PairedComparison ab2 = compare_single_shot("A", a, "B", b, p);
  const PairedComparison ba = compare_single_shot("B", b, "A", a, p);
  for (std::size_t k = 0; k < ab.criteria.size(); ++k) {
    EXPECT_EQ(ab.criteria[k].difference.ci_low, ab2.criteria[k].difference.ci_low);
    EXPECT_EQ(ab.criteria[k].difference.ci_high, ab2.criteria[k].difference.ci_high);
    EXPECT_NEAR(ab.criteria[k].difference.value, -ba.criteria[k].difference.value, 1e-12);
    EXPECT_NEAR(ab.criteria[k].difference.ci_low, -ba.criteria[k].difference.ci_high, 1e-12);
    EXPECT_EQ(ab.criteria[k].test.only_a, ba.criteria[k].test.only_b);
    EXPECT_DOUBLE_EQ(ab.criteria[k].test.p_value, ba.criteria[k].test.p_value);
  }
  p.bootstrap_seed = 12345;
  const PairedComparison other = compare_single_shot("A", a, "B", b, p);
  bool differs = false;
  for (std::size_t k = 0; k < ab.criteria.size(); ++k)
    differs = differs || other.criteria[k].difference.ci_low != ab.criteria[k].difference.ci_low ||
              other.criteria[k].difference.ci_high != ab.criteria[k].difference.ci_high;
  EXPECT_TRUE(differs) << "another seed draws other resamples";
  EXPECT_THROW(compare_single_shot("A", a, "B", std::vector<SingleShotRecord>(3), p), std::invalid_argument);
}

TEST(Paired, UndefinedDifferenceHasNoInterval) {
  // Both methods fail everywhere: both medians are infinite, their difference is undefined.
  std::vector<SingleShotRecord> a(10, rec(kInf, 180.0)), b(10, rec(kInf, 180.0));
  ScoringParams p;
  p.bootstrap_resamples = 50;
  const PairedComparison c = compare_single_shot("A", a, "B", b, p);
  EXPECT_TRUE(std::isnan(c.metrics[0].difference.value));
  EXPECT_FALSE(c.metrics[0].difference.has_ci);
  p.bootstrap_resamples = 0;
  EXPECT_FALSE(compare_single_shot("A", a, "B", b, p).criteria[0].difference.has_ci);
}

TEST(Paired, SequentialCriteria) {
  // Walks of 20 steps (the last 10 decide success): A ends within 0.3 m on 8 of 10 walks, B on 2 (B's good walks are A's).
  auto walk = [](double err) {
    SequentialRecord r;
    for (int k = 0; k < 20; ++k) {
      r.t_s.push_back(k);
      r.distance_m.push_back(k);
      r.position_error_m.push_back(k < 4 ? 5.0 : err);
      r.stage.push_back(k < 4 ? 0 : 2);
    }
    return r;
  };
  std::vector<SequentialRecord> a, b;
  for (int i = 0; i < 10; ++i) {
    a.push_back(walk(i < 8 ? 0.3 : 3.0));
    b.push_back(walk(i < 2 ? 0.3 : 3.0));
  }
  SequentialScoring sc;
  sc.bootstrap_resamples = 200;
  const PairedComparison c = compare_sequential("A", a, "B", b, sc);
  ASSERT_EQ(c.criteria.size(), 3u);
  EXPECT_EQ(c.criteria[0].name, "success_1m");
  EXPECT_EQ(c.criteria[0].test.only_a, 6);
  EXPECT_EQ(c.criteria[0].test.only_b, 0);
  EXPECT_NEAR(c.criteria[0].test.p_value, 2.0 / 64.0, 1e-12);
  EXPECT_NEAR(c.criteria[0].difference.value, 0.6, 1e-12);
  EXPECT_EQ(c.criteria[2].name, "converged");
  EXPECT_DOUBLE_EQ(c.criteria[2].test.p_value, 1.0);
  ASSERT_EQ(c.metrics.size(), 2u);
  EXPECT_EQ(c.metrics[0].name, "median_rmse_m");
  EXPECT_LT(c.metrics[0].difference.value, 0.0);
}

}  // namespace
}  // namespace floorcast
