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
