// The experiment driver (scenarios/driver.hpp) and the configuration hash: the same scenario in
// two folders (two checkouts, an installation) hashes the same, and shards run in two checkouts
// merge into the run one checkout makes alone.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "floorcast/core/file_io.hpp"
#include "floorcast/scenarios/driver.hpp"
#include "floorcast/scenarios/run_directory.hpp"

namespace floorcast {
namespace {

namespace fs = std::filesystem;
const std::string kRoot = FLOORCAST_SOURCE_DIR;

const char* kScenario = R"(name: driver-test
buildings:
  - floorplans/buildings/two_rooms.json
  - {file: floorplans/buildings/apartment.json, label: flat}
sampling: {count: 3, seed: 4, clearance_m: 0.4}
output: {heatmaps: 0}
matchers:
  kernel: {matcher: kernel}
sweep: {observation.max_range_m: [6, 10]}
)";

/// A folder of its own for this test (parallel ctest).
fs::path test_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("floorcast_test_driver_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// A copy of the scenario and the plans it names laid out like a checkout (`layout` "checkout":
/// ROOT/scenarios/s.yaml beside ROOT/floorplans/buildings/) or an installation ("install":
/// ROOT/share/floorcast/...); returns the scenario file and the data folder.
std::pair<std::string, std::string> copy_tree(const fs::path& root, const std::string& layout) {
  const fs::path data = layout == "install" ? root / "share" / "floorcast" : root;
  fs::create_directories(data / "scenarios");
  fs::create_directories(data / "floorplans" / "buildings");
  for (const char* plan : {"two_rooms.json", "apartment.json"}) {
    fs::copy_file(fs::path(kRoot) / "floorplans" / "buildings" / plan, data / "floorplans" / "buildings" / plan);
  }
  const std::string yaml = (data / "scenarios" / "s.yaml").string();
  write_text_file_atomic(yaml, kScenario);
  return {yaml, data.string()};
}

TEST(ConfigurationHash, SameScenarioSameHashInAnyFolder) {
  const fs::path dir = test_dir("hash");
  const auto [yaml_a, data_a] = copy_tree(dir / "checkout_a", "checkout");
  const auto [yaml_b, data_b] = copy_tree(dir / "somewhere" / "else" / "checkout_b", "checkout");
  const auto [yaml_i, data_i] = copy_tree(dir / "prefix", "install");
  const Scenario a = load_scenario(yaml_a, data_a);
  const Scenario b = load_scenario(yaml_b, data_b);
  const Scenario i = load_scenario(yaml_i, data_i);
  EXPECT_NE(a.buildings[0].file, b.buildings[0].file);  // two places ...
  EXPECT_EQ(a.hash, b.hash);                            // ... one configuration
  EXPECT_EQ(a.hash, i.hash);
  // The plan's path from the data folder (a scenario outside the data tree) hashes the same too.
  const Scenario from_source = parse_scenario(kScenario, "elsewhere.yaml", (dir / "nowhere").string(), kRoot);
  EXPECT_EQ(from_source.hash, a.hash);
  // The stored configuration holds no absolute path and the content hash of each plan.
  const std::string stored = a.resolved.dump();
  EXPECT_EQ(stored.find(dir.string()), std::string::npos) << stored.substr(0, 400);
  EXPECT_TRUE(a.resolved["buildings"][0].contains("file_hash"));
  fs::remove_all(dir);
}

TEST(ConfigurationHash, ChangesWithThePlansContent) {
  const fs::path dir = test_dir("content");
  const auto [yaml_a, data_a] = copy_tree(dir / "a", "checkout");
  const auto [yaml_b, data_b] = copy_tree(dir / "b", "checkout");
  const fs::path plan_b = fs::path(data_b) / "floorplans" / "buildings" / "two_rooms.json";
  write_text_file_atomic(plan_b.string(), read_text_file(plan_b.string()) + "\n");  // one byte more
  EXPECT_NE(load_scenario(yaml_a, data_a).hash, load_scenario(yaml_b, data_b).hash);
  fs::remove_all(dir);
}

TEST(Driver, ShardsRunInTwoCheckoutsMergeIntoTheSingleRun) {
  const fs::path dir = test_dir("shards");
  const auto [yaml_a, data_a] = copy_tree(dir / "checkout_a", "checkout");
  const auto [yaml_b, data_b] = copy_tree(dir / "checkout_b", "checkout");
  RunRequest first;
  first.jobs = 2;
  first.shard = "0/2";
  RunRequest second = first;
  second.shard = "1/2";
  const RunSummary s0 = run_scenario(load_scenario(yaml_a, data_a), (dir / "run_a").string(), first);
  const RunSummary s1 = run_scenario(load_scenario(yaml_b, data_b), (dir / "run_b").string(), second);
  EXPECT_FALSE(s0.summary_md);  // a shard alone writes no report
  EXPECT_FALSE(s1.summary_md);
  EXPECT_EQ(s0.outcome.executed + s1.outcome.executed, 12u);
  const MergeSummary m = merge_runs({(dir / "run_a").string(), (dir / "run_b").string()}, (dir / "merged").string());
  EXPECT_EQ(m.copied, 12u);
  EXPECT_NE(m.summary_md.find("driver-test"), std::string::npos);

  RunRequest whole;
  whole.jobs = 2;
  const RunSummary all = run_scenario(load_scenario(yaml_a, data_a), (dir / "whole").string(), whole);
  ASSERT_TRUE(all.summary_md);
  const RunComparison c = compare_runs((dir / "merged").string(), (dir / "whole").string());
  EXPECT_TRUE(c.same_configuration) << c.hash_a << " vs " << c.hash_b;
  EXPECT_TRUE(c.identical_results());
  EXPECT_EQ(c.identical, 12u);
  // Resuming in the other checkout finds the run of the same configuration complete.
  const RunSummary again = run_scenario(load_scenario(yaml_b, data_b), (dir / "whole").string(), whole);
  EXPECT_EQ(again.outcome.executed, 0u);
  EXPECT_EQ(again.outcome.skipped, 12u);
  fs::remove_all(dir);
}

TEST(Driver, RefusesToMergeOtherConfigurations) {
  const fs::path dir = test_dir("refuse");
  const auto [yaml_a, data_a] = copy_tree(dir / "a", "checkout");
  RunRequest r;
  r.jobs = 1;
  r.shard = "0/2";
  run_scenario(load_scenario(yaml_a, data_a), (dir / "run_a").string(), r);
  Scenario other = parse_scenario(std::string(kScenario) + "description: another\n", "other.yaml", data_a, data_a);
  r.shard = "1/2";
  run_scenario(other, (dir / "run_b").string(), r);
  EXPECT_THROW(merge_runs({(dir / "run_a").string(), (dir / "run_b").string()}, (dir / "merged").string()), InputError);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace floorcast
