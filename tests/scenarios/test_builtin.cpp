// The shipped scenarios and the CI gate's baseline must stay loadable and consistent with each
// other: a renamed matcher, a dropped cell or a moved building file fails here, not in CI's gate.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <algorithm>
#include <set>
#include <sstream>

#include "floorcast/eval/gate.hpp"
#include "floorcast/core/types.hpp"
#include "floorcast/scenarios/scenario.hpp"

namespace floorcast {
namespace {

namespace fs = std::filesystem;
const std::string kRoot = FLOORCAST_SOURCE_DIR;

nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  std::stringstream ss;
  ss << in.rdbuf();
  return nlohmann::json::parse(ss.str());
}

std::vector<std::string> split_pointer(const std::string& p) {
  std::vector<std::string> parts;
  std::stringstream ss(p.substr(1));
  std::string t;
  while (std::getline(ss, t, '/')) parts.push_back(t);
  return parts;
}

TEST(BuiltinScenarios, EveryShippedScenarioLoadsAndResolves) {
  const std::set<std::string> expected = {"quickstart", "perfect_observation", "full_system",
                                          "scale_ablation", "sensor_sweep", "gate", "gate_sequential",
                                          "sequential", "paper_4_4", "paper_4_4_protocol", "paper_4_4_combinations"};
  std::set<std::string> found;
  for (const auto& entry : fs::directory_iterator(kRoot + "/scenarios")) {
    if (entry.path().extension() != ".yaml") continue;
    SCOPED_TRACE(entry.path().string());
    Scenario s;
    ASSERT_NO_THROW(s = load_scenario(entry.path().string(), kRoot));
    EXPECT_FALSE(s.cells.empty());
    EXPECT_FALSE(s.buildings.empty());
    EXPECT_EQ(s.hash.size(), 16u);
    found.insert(entry.path().stem().string());
  }
  for (const std::string& name : expected) EXPECT_TRUE(found.count(name)) << name << ".yaml is missing";
}

/// Every check of a gate baseline points at a cell, group and method the scenario produces, and
/// bites: a summary right at every bound passes, one just past every bound fails every check.
void expect_baseline_matches(const std::string& scenario, const std::string& baseline_file) {
  SCOPED_TRACE(baseline_file);
  const Scenario s = load_scenario(kRoot + "/scenarios/" + scenario, kRoot);
  const nlohmann::json baseline = read_json(kRoot + "/results/baselines/" + baseline_file);
  ASSERT_TRUE(baseline.contains("checks"));
  std::set<std::string> groups = {"all"};
  for (const BuildingSpec& b : s.buildings) groups.insert(b.label);
  // A run's summary names its scenario (the gate refuses a baseline of another scenario).
  nlohmann::json good = {{"scenario", s.name}}, bad = good;
  for (const auto& c : baseline["checks"]) {
    const std::string ptr = c["pointer"].get<std::string>();
    const auto parts = split_pointer(ptr);
    ASSERT_EQ(parts.size(), 6u) << ptr;
    EXPECT_EQ(parts[0], "cells");
    const std::size_t cell = std::stoul(parts[1]);
    ASSERT_LT(cell, s.cells.size()) << ptr;
    EXPECT_TRUE(parts[2] == "groups" || parts[2] == "sequential") << ptr;
    EXPECT_TRUE(groups.count(parts[3])) << ptr << ": no building labelled " << parts[3];
    bool has_method = false;
    if (parts[2] == "groups") {
      for (const MatcherSpec& m : s.cells[cell].matchers) has_method |= m.label == parts[4];
    } else {
      ASSERT_TRUE(s.cells[cell].sequential.has_value()) << ptr;
      for (const TrackerSpec& t : s.cells[cell].sequential->trackers) has_method |= t.label == parts[4];
    }
    EXPECT_TRUE(has_method) << ptr << ": no method labelled " << parts[4];
    // A summary right at each bound passes; one just past every bound fails every check.
    const bool is_floor = c.contains("min");
    const double bound = is_floor ? c["min"].get<double>() : c["max"].get<double>();
    good[nlohmann::json::json_pointer(ptr)] = bound;
    bad[nlohmann::json::json_pointer(ptr)] = is_floor ? bound - 0.01 : bound + 0.01;
  }
  for (const auto& r : baseline["timing_ratios"]) {
    const double base = r["baseline"].get<double>();
    good[nlohmann::json::json_pointer(r["numerator"].get<std::string>())] = base;
    good[nlohmann::json::json_pointer(r["denominator"].get<std::string>())] = 1.0;
    bad[nlohmann::json::json_pointer(r["numerator"].get<std::string>())] = 10.0 * base;
    bad[nlohmann::json::json_pointer(r["denominator"].get<std::string>())] = 1.0;
  }
  // Paired checks name two methods of the cell, at the cell's paired comparisons of a group; the
  // good summary has A ahead, the bad one B significantly ahead (or A's error significantly larger).
  const nlohmann::json paired = baseline.value("paired_checks", nlohmann::json::array());
  for (const auto& c : paired) {
    const std::string at = c["at"].get<std::string>();
    const auto parts = split_pointer(at);
    ASSERT_EQ(parts.size(), 4u) << at;
    const std::size_t cell = std::stoul(parts[1]);
    ASSERT_LT(cell, s.cells.size()) << at;
    EXPECT_TRUE(parts[2] == "paired" || parts[2] == "sequential_paired") << at;
    EXPECT_TRUE(groups.count(parts[3])) << at;
    std::vector<std::string> labels;
    if (parts[2] == "paired") {
      for (const MatcherSpec& m : s.cells[cell].matchers) labels.push_back(m.label);
    } else {
      ASSERT_TRUE(s.cells[cell].sequential.has_value()) << at;
      for (const TrackerSpec& t : s.cells[cell].sequential->trackers) labels.push_back(t.label);
    }
    const std::string a = c["a"], b = c["not_worse_than"], metric = c["metric"];
    const auto ia = std::find(labels.begin(), labels.end(), a), ib = std::find(labels.begin(), labels.end(), b);
    ASSERT_TRUE(ia != labels.end() && ib != labels.end()) << a << ", " << b;
    // The report stores each pair once, in label order.
    const bool a_first = ia < ib;
    const std::string key = a_first ? a + " vs " + b : b + " vs " + a;
    const double s_ = a_first ? 1.0 : -1.0;  // sign of A - B in the stored orientation
    auto entry = [&](bool a_ahead) {
      nlohmann::json e;
      if (metric.rfind("median_", 0) == 0) {
        e["lower_is_better"] = true;
        e["difference"] = (a_ahead ? -0.5 : 0.5) * s_;
        e["ci95"] = a_ahead == a_first ? nlohmann::json::array({-0.8, -0.2}) : nlohmann::json::array({0.2, 0.8});
      } else {
        const int ahead = 10, behind = 0;
        const bool first_ahead = a_ahead == a_first;
        e["only_a"] = first_ahead ? ahead : behind;
        e["only_b"] = first_ahead ? behind : ahead;
        e["p_value"] = 0.002;
        e["ci95"] = first_ahead ? nlohmann::json::array({0.05, 0.2}) : nlohmann::json::array({-0.2, -0.05});
      }
      return e;
    };
    good[nlohmann::json::json_pointer(at + "/" + key + "/" + metric)] = entry(true);
    bad[nlohmann::json::json_pointer(at + "/" + key + "/" + metric)] = entry(false);
  }
  const GateOutcome pass = evaluate_gate(good, baseline, "gate.json");
  EXPECT_TRUE(pass.passed);
  EXPECT_TRUE(pass.failures.empty()) << (pass.failures.empty() ? "" : pass.failures.front());
  const GateOutcome fail = evaluate_gate(bad, baseline, "gate.json");
  EXPECT_FALSE(fail.passed);
  EXPECT_EQ(fail.failures.size(), baseline["checks"].size() + baseline["timing_ratios"].size() + paired.size());
}

TEST(BuiltinScenarios, GateBaselinesReferToWhatTheGateScenariosProduce) {
  expect_baseline_matches("gate.yaml", "gate.json");
  expect_baseline_matches("gate_sequential.yaml", "gate_sequential.json");
}

}  // namespace
}  // namespace floorcast
