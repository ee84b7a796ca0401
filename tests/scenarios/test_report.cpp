#include <gtest/gtest.h>

#include "common/scratch_dir.hpp"

#include <algorithm>
#include <filesystem>
#include <set>

#include "floorcast/core/types.hpp"
#include "floorcast/scenarios/run_directory.hpp"

namespace floorcast {
namespace {

const std::string kRoot = FLOORCAST_SOURCE_DIR;

Scenario small_scenario() {
  return parse_scenario(R"(
name: fake
buildings: [floorplans/buildings/two_rooms.json]
sampling: {count: 4}
matchers: {kernel: {matcher: kernel}, ray: {matcher: ray}}
scoring: {bootstrap_resamples: 100}
paper: [{label: "paper kernel", source: "PALMS+ 4.4", values: {recall_1m_30deg: 0.887}}]
sweep: {observation.rays: [36, 180]}
)", "fake.yaml", kRoot, kRoot);
}

/// Fake results: kernel errors 0.2 m except point 3 (5 m); ray fails on point 0.
std::vector<UnitResult> fake_units(const Scenario& s) {
  std::vector<UnitResult> out;
  for (const WorkUnit& w : enumerate_units(s)) {
    UnitResult r;
    r.unit = w;
    r.truth = {1.0 + w.point, 2.0, 0.5};
    r.observation["segments"] = 7;
    r.timings_s["observe"] = 0.01;
    for (const std::string label : {"kernel", "ray"}) {
      MatcherOutcome o;
      o.label = label;
      o.match_s = 0.1;
      if (label == std::string("ray") && w.point == 0) {
        o.ok = false;
        o.failure = "no rays";
      } else {
        o.estimate.position_error_m = (label == std::string("kernel") && w.point != 3) ? 0.2 : 5.0;
        o.estimate.yaw_error_deg = 3.0;
        o.top_k = {o.estimate};
      }
      r.outcomes.push_back(o);
    }
    out.push_back(r);
  }
  return out;
}

TEST(Report, SummaryTablesAndCsvFromUnits) {
  const Scenario s = small_scenario();
  const auto units = fake_units(s);
  ASSERT_EQ(units.size(), 8u);
  const Report rep = build_report(s, units, {{"reference_s", 0.02}});
  const auto& c0 = rep.summary["cells"][0]["groups"]["all"];
  EXPECT_DOUBLE_EQ(c0["kernel"]["recall_1m_30deg"].get<double>(), 0.75);
  EXPECT_DOUBLE_EQ(c0["ray"]["recall_1m_30deg"].get<double>(), 0.0);
  EXPECT_DOUBLE_EQ(c0["ray"]["recall_5m"].get<double>(), 0.75);  // the failed unit counts as a miss
  EXPECT_EQ(c0["kernel"]["count"], 4);
  EXPECT_TRUE(c0["kernel"]["ci95"].contains("recall_1m"));
  EXPECT_EQ(rep.summary["units"], 8);
  EXPECT_EQ(rep.summary["timing"]["reference_s"], 0.02);
  EXPECT_TRUE(rep.summary["complete"].get<bool>());
  // One CSV row per unit plus the header.
  EXPECT_EQ(std::count(rep.observations_csv.begin(), rep.observations_csv.end(), '\n'), 9);
  EXPECT_NE(rep.summary_md.find("| kernel |"), std::string::npos);
  EXPECT_NE(rep.summary_md.find("*paper kernel*"), std::string::npos);
  EXPECT_NE(rep.summary_md.find("88.7"), std::string::npos);
  EXPECT_NE(rep.summary_md.find("Sweep overview"), std::string::npos);
  // A CDF per cell and an accuracy-vs-axis plot.
  ASSERT_EQ(rep.plots.size(), 3u);
  EXPECT_EQ(rep.plots[2].first, "accuracy_vs_observation.rays.png");
}

TEST(Report, PairedComparisonsOfEveryPairOnTheSameUnits) {
  const Scenario s = small_scenario();
  const auto units = fake_units(s);
  const Report rep = build_report(s, units, {});
  // Per cell of 4 points: kernel within 1 m on points 0-2, ray on none (3 discordant units, all
  // kernel's: McNemar p = 2 / 2^3); medians 0.2 m vs 5 m.
  const auto& p = rep.summary["cells"][0]["paired"]["all"]["kernel vs ray"];
  EXPECT_EQ(p["a"], "kernel");
  EXPECT_EQ(p["count"], 4);
  EXPECT_EQ(p["recall_1m_30deg"]["only_a"], 3);
  EXPECT_EQ(p["recall_1m_30deg"]["only_b"], 0);
  EXPECT_EQ(p["recall_1m_30deg"]["both"], 0);
  EXPECT_DOUBLE_EQ(p["recall_1m_30deg"]["p_value"].get<double>(), 0.25);
  EXPECT_DOUBLE_EQ(p["recall_1m_30deg"]["difference"].get<double>(), 0.75);
  EXPECT_EQ(p["recall_1m_30deg"]["ci95"].size(), 2u);
  EXPECT_DOUBLE_EQ(p["median_position_error_m"]["difference"].get<double>(), 0.2 - 5.0);
  EXPECT_TRUE(p["median_position_error_m"]["lower_is_better"].get<bool>());
  EXPECT_TRUE(rep.summary["cells"][1]["paired"].contains("two_rooms"));  // per building too
  EXPECT_NE(rep.summary_md.find("| kernel vs ray | 75.0 / 0.0 | 3 | 0 | 0.25 | +75.0 ["), std::string::npos) << rep.summary_md;
  EXPECT_NE(rep.summary_md.find("no significant difference |"), std::string::npos);

  // Two runs compared on their shared units: B's ray is kernel's results under another name.
  std::vector<UnitResult> b = units;
  for (UnitResult& u : b) {
    u.outcomes[1] = u.outcomes[0];
    u.outcomes[1].label = "ray";
  }
  b.pop_back();  // B lacks one unit: 7 shared
  b[2].truth.x_m += 1.0;  // another point under the same id: not shared
  const std::vector<CrossRunComparison> c = compare_runs_paired(s, units, "A", s, b, "B");
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c[0].shared_units + c[1].shared_units, 6);
  ASSERT_EQ(c[0].matchers.size(), 4u);  // A:kernel, A:ray x B:kernel, B:ray
  EXPECT_EQ(c[0].matchers[0].a, "A:kernel");
  EXPECT_EQ(c[0].matchers[1].b, "B:ray");
  for (const PairedCriterion& x : c[0].matchers[1].criteria) EXPECT_DOUBLE_EQ(x.test.p_value, 1.0);  // identical
  EXPECT_NE(cross_run_comparisons_md(c, s).find("| A:ray vs B:ray |"), std::string::npos);
}

TEST(Report, RefusesPartialResults) {
  const Scenario s = small_scenario();
  auto units = fake_units(s);
  units.pop_back();
  try {
    (void)build_report(s, units, {});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("1 of 8 work units have no result"), std::string::npos) << e.what();
  }
}

TEST(RunDirectory, UnitsRoundTripAndRunsNeverMix) {
  const Scenario s = small_scenario();
  const test::ScratchDir scratch;
  const std::string dir = scratch.file("run");
  const auto units = fake_units(s);
  {
    RunDirectory run(dir);
    run.open(s, s.resolved);
    EXPECT_FALSE(run.has_unit(s, units[3].unit));
    run.write_unit(s, units[3]);
    EXPECT_TRUE(run.has_unit(s, units[3].unit));
    const auto back = run.read_units(s);
    ASSERT_EQ(back.size(), 1u);
    EXPECT_EQ(unit_to_json(back[0]).dump(), unit_to_json(units[3]).dump());
    // While it is held (run.lock), the folder is refused to a second writer.
    EXPECT_THROW(RunDirectory(dir).open(s, s.resolved), InputError);
  }
  // Re-opening with the same configuration resumes; a different one is refused.
  RunDirectory(dir).open(s, s.resolved);
  nlohmann::ordered_json other = s.resolved;
  other["sampling"]["count"] = 5;
  EXPECT_THROW(RunDirectory(dir).open(s, other), InputError);
}

TEST(Units, ShardsPartitionTheUnits) {
  const Scenario s = small_scenario();
  const auto all = enumerate_units(s);
  std::set<std::string> seen;
  for (int i = 0; i < 3; ++i)
    for (const auto& u : select_shard(all, parse_shard(std::to_string(i) + "/3"))) EXPECT_TRUE(seen.insert(u.id).second);
  EXPECT_EQ(seen.size(), all.size());
  EXPECT_THROW(parse_shard("3/3"), InputError);
  EXPECT_THROW(parse_shard("a/b"), InputError);
  EXPECT_EQ(all[0].id, "c000/two_rooms/0000");
}

TEST(Units, TimingsAreSeparableFromResults) {
  const Scenario s = small_scenario();
  auto a = fake_units(s)[1];
  auto b = a;
  b.timings_s["observe"] = 9.0;
  b.outcomes[0].match_s = 3.0;
  EXPECT_NE(unit_to_json(a).dump(), unit_to_json(b).dump());
  EXPECT_EQ(strip_timings(unit_to_json(a)).dump(), strip_timings(unit_to_json(b)).dump());
}

}  // namespace
}  // namespace floorcast
