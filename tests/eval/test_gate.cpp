#include <gtest/gtest.h>

#include "floorcast/eval/gate.hpp"
#include "floorcast/core/types.hpp"

namespace floorcast {
namespace {

using Json = nlohmann::json;

Json summary() {
  return Json::parse(R"({"timing": {"reference_s": 0.02},
    "cells": [{"groups": {"all": {"kernel": {"recall_1m_30deg": 0.85, "median_position_error_m": 0.2, "mean_time_s": 0.3},
                                  "ray": {"recall_1m_30deg": 0.2, "mean_time_s": 0.05}}}}]})");
}

Json baseline() {
  return Json::parse(R"({"checks": [
      {"pointer": "/cells/0/groups/all/kernel/recall_1m_30deg", "min": 0.8},
      {"pointer": "/cells/0/groups/all/kernel/median_position_error_m", "max": 0.5}],
    "timing_ratios": [{"name": "kernel / reference", "numerator": "/cells/0/groups/all/kernel/mean_time_s",
                       "denominator": "/timing/reference_s", "baseline": 12.0, "tolerance": 0.5}]})");
}

TEST(Gate, PassesOnAHealthyRun) {
  const GateOutcome g = evaluate_gate(summary(), baseline(), "b.json");
  EXPECT_TRUE(g.passed);
  EXPECT_EQ(g.passes.size(), 3u);
  EXPECT_TRUE(g.failures.empty());
}

TEST(Gate, FailsOnAccuracyBelowFloor) {
  Json s = summary();
  s["cells"][0]["groups"]["all"]["kernel"]["recall_1m_30deg"] = 0.5;
  const GateOutcome g = evaluate_gate(s, baseline(), "b.json");
  EXPECT_FALSE(g.passed);
  ASSERT_EQ(g.failures.size(), 1u);
  EXPECT_NE(g.failures[0].find("below its floor 0.8"), std::string::npos) << g.failures[0];
}

TEST(Gate, FailsOnTimingRatioNotOnAbsoluteSeconds) {
  // Both times 10x slower (a slow machine): the ratio is unchanged, the gate passes.
  Json slow = summary();
  slow["timing"]["reference_s"] = 0.2;
  slow["cells"][0]["groups"]["all"]["kernel"]["mean_time_s"] = 3.0;
  EXPECT_TRUE(evaluate_gate(slow, baseline(), "b.json").passed);
  // The method alone 2x slower: ratio 30 > 12 * 1.5.
  Json regressed = summary();
  regressed["cells"][0]["groups"]["all"]["kernel"]["mean_time_s"] = 0.6;
  const GateOutcome g = evaluate_gate(regressed, baseline(), "b.json");
  EXPECT_FALSE(g.passed);
  EXPECT_NE(g.failures[0].find("timing regression"), std::string::npos);
}

TEST(Gate, MissingMetricIsAFailureNotASkip) {
  Json s = summary();
  s["cells"][0]["groups"]["all"].erase("kernel");
  const GateOutcome g = evaluate_gate(s, baseline(), "b.json");
  EXPECT_FALSE(g.passed);
  EXPECT_NE(g.failures[0].find("missing"), std::string::npos);
}

TEST(Gate, MalformedBaselineIsAnInputError) {
  EXPECT_THROW(evaluate_gate(summary(), Json::parse(R"({"checks": [{"pointer": "/x"}]})"), "b.json"), InputError);
  EXPECT_THROW(evaluate_gate(summary(), Json::parse(R"({"chekcs": []})"), "b.json"), InputError);
  EXPECT_THROW(evaluate_gate(summary(), Json::parse(R"({"timing_ratios": [{"numerator": "/a", "denominator": "/b"}]})"), "b.json"),
               InputError);
}

}  // namespace
}  // namespace floorcast

namespace floorcast {
namespace {

// A summary's paired block as report.cpp writes it (A - B; "ray vs kernel" stored in that order).
nlohmann::json paired_summary(int only_ray, int only_kernel, double p, double lo, double hi) {
  nlohmann::json s;
  s["cells"][0]["paired"]["all"]["ray vs kernel"] = {
      {"a", "ray"}, {"b", "kernel"}, {"count", 100},
      {"recall_1m_30deg", {{"both", 40}, {"only_a", only_ray}, {"only_b", only_kernel}, {"neither", 60 - only_ray - only_kernel},
                           {"p_value", p}, {"difference", (only_ray - only_kernel) / 100.0}, {"ci95", {lo, hi}}}},
      {"median_position_error_m", {{"difference", 0.4}, {"ci95", {0.1, 0.7}}, {"lower_is_better", true}}}};
  return s;
}

nlohmann::json not_worse(const std::string& a, const std::string& b, const std::string& metric, const std::string& extra = "") {
  return nlohmann::json::parse(R"({"paired_checks": [{"a": ")" + a + R"(", "not_worse_than": ")" + b +
                               R"(", "at": "/cells/0/paired/all", "metric": ")" + metric + "\"" + extra + "}]}");
}

TEST(GatePaired, McNemarDecidesEitherOrder) {
  // kernel wins 10 discordant units, ray none (p = 2 / 2^10): "ray not worse than kernel" fails,
  // "kernel not worse than ray" passes, whichever order the pair is stored in.
  const nlohmann::json s = paired_summary(0, 10, 0.001953125, -0.16, -0.04);
  GateOutcome g = evaluate_gate(s, not_worse("ray", "kernel", "recall_1m_30deg"), "b.json");
  EXPECT_FALSE(g.passed);
  ASSERT_EQ(g.failures.size(), 1u);
  EXPECT_NE(g.failures[0].find("kernel beats ray"), std::string::npos) << g.failures[0];
  g = evaluate_gate(s, not_worse("kernel", "ray", "recall_1m_30deg"), "b.json");
  EXPECT_TRUE(g.passed) << (g.failures.empty() ? "" : g.failures[0]);
  // Not significant (3 vs 1, p = 0.625): passes without a margin ...
  const nlohmann::json close = paired_summary(1, 3, 0.625, -0.08, 0.04);
  EXPECT_TRUE(evaluate_gate(close, not_worse("ray", "kernel", "recall_1m_30deg"), "b.json").passed);
  // ... and a margin demands evidence: ray - kernel >= -0.05 is not shown by [-0.08, 0.04].
  EXPECT_FALSE(evaluate_gate(close, not_worse("ray", "kernel", "recall_1m_30deg", R"(, "margin": 0.05)"), "b.json").passed);
  EXPECT_TRUE(evaluate_gate(close, not_worse("ray", "kernel", "recall_1m_30deg", R"(, "margin": 0.1)"), "b.json").passed);
  // Oriented for the reverse order: kernel - ray = [-0.04, 0.08] lies above -0.05.
  EXPECT_TRUE(evaluate_gate(close, not_worse("kernel", "ray", "recall_1m_30deg", R"(, "margin": 0.05)"), "b.json").passed);
  // A stricter alpha lets the 10-vs-0 case through only below its p-value.
  EXPECT_TRUE(evaluate_gate(s, not_worse("ray", "kernel", "recall_1m_30deg", R"(, "alpha": 0.001)"), "b.json").passed);
}

TEST(GatePaired, ContinuousMetricsUseThePairedInterval) {
  const nlohmann::json s = paired_summary(0, 0, 1.0, 0.0, 0.0);
  // ray's median error is larger by [0.1, 0.7] m: ray is worse, kernel is not.
  EXPECT_FALSE(evaluate_gate(s, not_worse("ray", "kernel", "median_position_error_m"), "b.json").passed);
  EXPECT_TRUE(evaluate_gate(s, not_worse("kernel", "ray", "median_position_error_m"), "b.json").passed);
  EXPECT_THROW(evaluate_gate(s, not_worse("kernel", "ray", "median_position_error_m", R"(, "alpha": 0.01)"), "b.json"), InputError);
}

TEST(GatePaired, MissingPairsFailAndBadEntriesAreRefused) {
  const nlohmann::json s = paired_summary(0, 10, 0.002, -0.16, -0.04);
  const GateOutcome g = evaluate_gate(s, not_worse("ray", "mine", "recall_1m_30deg"), "b.json");
  EXPECT_FALSE(g.passed);
  EXPECT_NE(g.failures.at(0).find("no \"ray vs mine\" comparison"), std::string::npos) << g.failures[0];
  EXPECT_THROW(evaluate_gate(s, nlohmann::json::parse(R"({"paired_checks": [{"a": "ray"}]})"), "b.json"), InputError);
  EXPECT_THROW(evaluate_gate(s, not_worse("ray", "kernel", "recall_1m_30deg", R"(, "margn": 0.1)"), "b.json"), InputError);
  EXPECT_THROW(evaluate_gate(s, not_worse("ray", "kernel", "recall_1m_30deg", R"(, "alpha": 2)"), "b.json"), InputError);
}

}  // namespace
}  // namespace floorcast
