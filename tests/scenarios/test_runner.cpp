#include <gtest/gtest.h>

#include <map>
#include <mutex>
#include <stdexcept>

#include "floorcast/core/types.hpp"
#include "floorcast/scenarios/report.hpp"
#include "floorcast/scenarios/runner.hpp"

namespace floorcast {
namespace {

const std::string kRoot = FLOORCAST_SOURCE_DIR;

/// In-memory sink; optionally "crashes" (throws) after a number of writes, like a killed run.
class MemorySink : public UnitSink {
 public:
  explicit MemorySink(int crash_after = -1) : crash_after_(crash_after) {}
  bool has_unit(const WorkUnit& u) const override { return units.count(u.id) > 0; }
  void write_unit(const UnitResult& r) override {
    if (crash_after_ >= 0 && static_cast<int>(units.size()) >= crash_after_) throw std::runtime_error("killed");
    units[r.unit.id] = strip_timings(unit_to_json(r)).dump();
  }
  void write_image(const std::string& p, const cv::Mat&) override { images.push_back(p); }
  std::map<std::string, std::string> units;
  std::vector<std::string> images;

 private:
  int crash_after_;
};

Scenario perfect_scenario() {
  return parse_scenario(R"(
name: runner-test
buildings: [floorplans/buildings/two_rooms.json, floorplans/buildings/apartment.json]
sampling: {count: 3, seed: 4, clearance_m: 0.4}
output: {heatmaps: 1}
matchers:
  kernel: {matcher: kernel}
  ray: {matcher: ray}
sweep: {observation.max_range_m: [6, 10]}
)", "runner.yaml", kRoot, kRoot);
}

TEST(Runner, SameResultsAtAnyJobCount) {
  const Scenario s = perfect_scenario();
  const ScenarioRunner runner(s);
  MemorySink one, two;
  RunOptions o1;
  o1.jobs = 1;
  RunOptions o2;
  o2.jobs = 2;
  const RunOutcome a = runner.run(one, o1);
  runner.run(two, o2);
  EXPECT_EQ(a.executed, 12u);
  EXPECT_EQ(one.units, two.units);
  EXPECT_EQ(one.images.size(), 2u * 2u * 2u);  // 1 point x 2 buildings x 2 cells x 2 matchers
  // The resolved configuration carries every matcher's parameters with their defaults.
  const auto& params = runner.resolved_full()["cells"][0]["matchers"];
  EXPECT_TRUE(params["kernel"].contains("alpha"));
  EXPECT_TRUE(params["ray"].contains("num_directions"));
}

TEST(Runner, InterruptedRunResumesToTheSameResults) {
  const Scenario s = perfect_scenario();
  const ScenarioRunner runner(s);
  MemorySink full;
  runner.run(full, {});
  MemorySink interrupted(5);
  RunOptions o;
  o.jobs = 2;
  EXPECT_THROW(runner.run(interrupted, o), std::runtime_error);
  const std::size_t done_before = interrupted.units.size();
  EXPECT_EQ(done_before, 5u);
  MemorySink resumed;
  resumed.units = interrupted.units;
  const RunOutcome out = runner.run(resumed, o);
  EXPECT_EQ(out.skipped, done_before);
  EXPECT_EQ(out.executed, 12u - done_before);
  EXPECT_EQ(resumed.units, full.units);
}

TEST(Runner, ShardsTogetherEqualOneRun) {
  const Scenario s = perfect_scenario();
  const ScenarioRunner runner(s);
  MemorySink full, sharded;
  runner.run(full, {});
  for (int i = 0; i < 3; ++i) {
    RunOptions o;
    o.shard = {i, 3};
    const RunOutcome out = runner.run(sharded, o);
    EXPECT_EQ(out.units_in_shard, 4u);
  }
  EXPECT_EQ(sharded.units, full.units);
}

TEST(Runner, PerfectObservationsLocaliseInTheApartment) {
  // (two_rooms.json is a poor choice: its left room is almost square, so a 90 deg turn fits too.)
  const Scenario s = parse_scenario(R"(
buildings: [floorplans/buildings/apartment.json]
sampling: {count: 6, seed: 2, clearance_m: 0.5}
matchers: {kernel: {matcher: kernel}}
)", "t.yaml", kRoot, kRoot);
  const ScenarioRunner runner(s);
  int good = 0;
  for (const WorkUnit& u : enumerate_units(s)) {
    const UnitResult r = runner.run_unit(u, nullptr);
    ASSERT_EQ(r.outcomes.size(), 1u);
    ASSERT_TRUE(r.outcomes[0].ok);
    good += r.outcomes[0].estimate.position_error_m < 1.0 && r.outcomes[0].estimate.yaw_error_deg < 30.0;
  }
  EXPECT_GE(good, 4);
}

TEST(Runner, ScanCellsSimulateAndObserve) {
  const Scenario s = parse_scenario(R"(
buildings: [floorplans/buildings/two_rooms.json]
sampling: {count: 1, seed: 2, clearance_m: 0.6}
observation: {source: scan, sensor: lidar, path: lidar, seed: 3}
matchers: {kernel: {matcher: kernel}}
sweep: {observation.sensor_params.sensor.lidar.dropout_prob: [0.0, 0.05]}
)", "t.yaml", kRoot, kRoot);
  const ScenarioRunner runner(s);
  const auto units = enumerate_units(s);
  const UnitResult a = runner.run_unit(units[0], nullptr);
  EXPECT_TRUE(a.observation_ok) << a.observation_failure;
  EXPECT_GT(a.observation["segments"].get<int>(), 0);
  EXPECT_GT(a.timings_s.at("simulate"), 0.0);
  EXPECT_TRUE(a.observation.contains("diagnostics"));
  // The sweep value reaches the simulator.
  EXPECT_EQ(runner.resolved_full()["cells"][1]["parameters"]["sensor"]["sensor"]["lidar"]["dropout_prob"], 0.05);
  // Same unit, same bytes.
  EXPECT_EQ(strip_timings(unit_to_json(runner.run_unit(units[0], nullptr))).dump(), strip_timings(unit_to_json(a)).dump());
}

// Negative samples: observed at the other building's points, matched against this building; the
// plane matcher rejects them, and the report scores every method with rejection.
TEST(Runner, NegativeSamplesComeFromTheOtherBuildingsAndAreScoredWithRejection) {
  const Scenario s = parse_scenario(R"(
buildings: [floorplans/buildings/two_rooms.json, floorplans/buildings/apartment.json]
sampling: {count: 2, seed: 3, clearance_m: 0.5, negatives: 3}
matchers: {kernel: {matcher: kernel}, planes: {matcher: planes}}
)", "t.yaml", kRoot, kRoot);
  const std::vector<WorkUnit> units = enumerate_units(s);
  ASSERT_EQ(units.size(), 10u);
  const ScenarioRunner runner(s);
  std::vector<UnitResult> results;
  int negatives = 0, planes_rejected = 0;
  for (const WorkUnit& u : units) {
    const UnitResult r = runner.run_unit(u, nullptr);
    if (u.negative()) {
      ++negatives;
      EXPECT_NE(u.source_building, u.building);
      EXPECT_EQ(u.id.substr(u.id.size() - 5, 1), "n");
      const Pose2& src = runner.building_points(u.source_building).at(static_cast<std::size_t>(u.source_point));
      EXPECT_EQ(r.truth.x_m, src.x_m);
      EXPECT_EQ(r.truth.y_m, src.y_m);
      planes_rejected += r.outcomes.at(1).ok ? 0 : 1;
    }
    // The unit JSON keeps where a negative was observed.
    EXPECT_EQ(unit_from_json(unit_to_json(r), "u.json").unit.source_building, u.source_building);
    results.push_back(r);
  }
  EXPECT_EQ(negatives, 6);
  EXPECT_GE(planes_rejected, 1) << "the plane matcher localized every negative";
  const Report rep = build_report(s, results, nlohmann::ordered_json::object());
  const auto& all = rep.summary["cells"][0]["groups"]["all"];
  for (const char* m : {"kernel", "planes"}) {
    const auto& rj = all[m]["rejection"];
    EXPECT_EQ(rj["tp"].get<double>() + rj["fp"].get<double>() + rj["tn"].get<double>() + rj["fn"].get<double>(), 10.0) << m;
    EXPECT_EQ(rj["tn"].get<double>() + rj["fp_negative"].get<double>(), 6.0) << m;
  }
  // The kernel matcher never abstains: every negative is a false positive.
  EXPECT_EQ(all["kernel"]["rejection"]["fp_negative"].get<double>(), 6.0);
  EXPECT_NE(rep.summary_md.find("Scoring with rejection (4 positive, 6 negative samples"), std::string::npos);
  // Recalls count the positives only.
  EXPECT_EQ(all["kernel"]["count"].get<int>(), 4);
  // Negatives need another building.
  EXPECT_THROW(parse_scenario("buildings: [floorplans/buildings/apartment.json]\nsampling: {count: 2, negatives: 1}\n"
                              "matchers: {kernel: {matcher: kernel}}\n", "n.yaml", kRoot, kRoot),
               InputError);
}

TEST(Runner, BadMatcherParameterFailsWhenTheScenarioLoads) {
  try {
    (void)parse_scenario(R"(
buildings: [floorplans/buildings/two_rooms.json]
sampling: {count: 1}
matchers: {kern: {matcher: kernel, alpah: 3}}
)", "bad.yaml", kRoot, kRoot);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.yaml:4:36: matchers.kern.alpah"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace floorcast
