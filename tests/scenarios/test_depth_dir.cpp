// Bring your own depth to a scenario run (observation.depth_dir): depth maps laid out as
// `floorcast export` lays out the scans replace the simulated depth of every unit's scans, the
// single-shot observation and every walk step. Maps holding exactly the simulated depth give
// exactly the simulated depth's units; other maps change them; missing folders are refused.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "floorcast/core/depth_io.hpp"
#include "floorcast/scenarios/dataset_export.hpp"
#include "floorcast/scenarios/runner.hpp"
#include "floorcast/scenarios/units.hpp"

namespace floorcast {
namespace {

namespace fs = std::filesystem;
const std::string kRoot = FLOORCAST_SOURCE_DIR;

fs::path test_dir(const std::string& name) {
  const fs::path d = fs::path(FLOORCAST_TEST_OUT) / ("depth_dir_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

Scenario scenario(const std::string& depth_yaml) {
  return parse_scenario(R"(
name: depth-dir
buildings: [floorplans/buildings/two_rooms.json]
sampling: {count: 3, seed: 2, clearance_m: 0.4, region: uniform}
observation: {source: scan, sensor: mono, setting: partial)" + depth_yaml + R"(}
output: {heatmaps: 0}
matchers: {kernel: {matcher: kernel}}
walk: {steps: 24, seed: 3}
odometry: {model: vio, seed: 4}
schedule: {initial: true, every_steps: 10}
trackers: {pf: {tracker: pf, matcher: kernel}}
)", "depth_dir.yaml", kRoot, kRoot);
}

std::vector<UnitResult> run_all(const Scenario& s) {
  const ScenarioRunner runner(s);
  std::vector<UnitResult> out;
  for (const WorkUnit& u : enumerate_units(s)) out.push_back(runner.run_unit(u, nullptr));
  return out;
}

/// What a depth network standing in writes: for every scan the runner makes (every unit, every
/// observed walk step), one map per view; `scale` 1 writes the simulated depth itself.
void write_depth_maps(const Scenario& s, const fs::path& dir, float scale) {
  const ScenarioRunner runner(s);
  for (const WorkUnit& u : enumerate_units(s)) {
    for (int step : runner.unit_observation_steps(u)) {
      const SimulatedScan sim = runner.unit_scan(u, step);
      const fs::path folder = dir / unit_scan_folder(s, u, step);
      fs::create_directories(folder);
      for (std::size_t k = 0; k < sim.scan.views.size(); ++k) {
        char name[32];
        std::snprintf(name, sizeof name, "view_%03zu.npy", k);
        write_npy((folder / name).string(), cv::Mat(sim.scan.views[k].depth_m * scale));
      }
    }
  }
}

nlohmann::ordered_json without_timings(const UnitResult& u) { return strip_timings(unit_to_json(u)); }

TEST(DepthDir, MapsOfTheSimulatedDepthGiveTheSimulatedUnitsOtherMapsOthers) {
  const fs::path dir = test_dir("same");
  const Scenario plain = scenario("");
  ASSERT_TRUE(plain.cells[0].sequential.has_value());
  const std::vector<UnitResult> simulated = run_all(plain);

  write_depth_maps(plain, dir / "depth", 1.0f);
  const Scenario byo = scenario(", depth_dir: " + (dir / "depth").string());
  EXPECT_EQ(byo.cells[0].observation.depth_dir, fs::weakly_canonical(dir / "depth").string());
  const std::vector<UnitResult> written_back = run_all(byo);
  ASSERT_EQ(written_back.size(), simulated.size());
  int updates = 0;
  for (std::size_t i = 0; i < simulated.size(); ++i) {
    EXPECT_EQ(without_timings(written_back[i]).dump(), without_timings(simulated[i]).dump()) << simulated[i].unit.id;
    ASSERT_EQ(simulated[i].tracks.size(), 1u);
    updates += simulated[i].tracks[0].observations_used;
  }
  EXPECT_GE(updates, 6) << "the walks' later observations are part of the comparison";

  // A network 30 % short everywhere: other observations, other estimates (the matcher sees a
  // shrunken room; scale alignment absorbs only part of it).
  write_depth_maps(plain, dir / "short", 0.7f);
  const std::vector<UnitResult> shrunk = run_all(scenario(", depth_dir: " + (dir / "short").string()));
  int differ = 0;
  for (std::size_t i = 0; i < simulated.size(); ++i)
    differ += without_timings(shrunk[i]).dump() != without_timings(simulated[i]).dump();
  EXPECT_GT(differ, 0);
}

TEST(DepthDir, RecordedAsNamedRefusedWhereItCannotWork) {
  const fs::path dir = test_dir("refused");
  const Scenario plain = scenario("");
  write_depth_maps(plain, dir / "depth", 1.0f);
  const Scenario byo = scenario(", depth_dir: " + (dir / "depth").string() + ", depth_kind: range");
  const nlohmann::ordered_json& obs = byo.resolved["cells"][0]["observation"];
  EXPECT_EQ(obs["depth_dir"], (dir / "depth").string());
  EXPECT_EQ(obs["depth_kind"], "range");
  EXPECT_FALSE(plain.resolved["cells"][0]["observation"].contains("depth_dir"));  // older runs' bytes unchanged
  EXPECT_NE(byo.hash, plain.hash);

  auto error_of = [](const std::function<void()>& f) -> std::string {
    try {
      f();
    } catch (const InputError& e) {
      return e.what();
    }
    return "(no error)";
  };
  // Not a folder; not a scan.
  EXPECT_NE(error_of([&] { (void)scenario(", depth_dir: " + (dir / "nowhere").string()); }).find("not found"), std::string::npos);
  const std::string perfect = error_of([&] {
    (void)parse_scenario("name: p\nbuildings: [floorplans/buildings/two_rooms.json]\nobservation: {depth_dir: " +
                             (dir / "depth").string() + "}\nmatchers: {kernel: {matcher: kernel}}\n",
                         "p.yaml", kRoot, kRoot);
  });
  EXPECT_NE(perfect.find("needs source: scan"), std::string::npos) << perfect;

  // A unit's folder missing: the run refuses before any work and names it.
  fs::remove_all(dir / "depth" / "c000" / "two_rooms" / "scans" / "p0001");
  const ScenarioRunner runner(byo);
  struct NoSink : UnitSink {
    bool has_unit(const WorkUnit&) const override { return false; }
    void write_unit(const UnitResult&) override { ++written; }
    void write_image(const std::string&, const cv::Mat&) override {}
    int written = 0;
  } sink;
  const std::string missing = error_of([&] { (void)runner.run(sink, RunOptions{}); });
  EXPECT_NE(missing.find("no depth maps for 1 of 3 units"), std::string::npos) << missing;
  EXPECT_NE(missing.find("p0001"), std::string::npos) << missing;
  EXPECT_EQ(sink.written, 0);
  // A later walk step's folder missing: the unit that reaches it stops the run, naming the step.
  write_depth_maps(plain, dir / "depth", 1.0f);
  fs::remove_all(dir / "depth" / "c000" / "two_rooms" / "scans" / "p0002" / "step_0010");
  WorkUnit u = enumerate_units(byo)[2];
  const std::string step = error_of([&] { (void)runner.run_unit(u, nullptr); });
  EXPECT_NE(step.find("at walk step 10"), std::string::npos) << step;
}

TEST(DepthDir, ExportWritesTheWalkStepsScansWhereDepthDirLooks) {
  const fs::path dir = test_dir("export");
  const Scenario plain = scenario("");
  DatasetExportOptions options;
  options.rgb = false;  // the layout only (colour views: tests/formats/test_export.cpp)
  const DatasetExportReport report = export_scenario_dataset(plain, (dir / "export").string(), options);
  EXPECT_EQ(report.scans, 3u);
  const ScenarioRunner runner(plain);
  std::size_t later = 0;
  for (const WorkUnit& u : enumerate_units(plain)) {
    for (int step : runner.unit_observation_steps(u)) {
      EXPECT_TRUE(fs::is_regular_file(dir / "export" / unit_scan_folder(plain, u, step) / "scan.json")) << u.id << " " << step;
      later += step > 0;
    }
  }
  EXPECT_EQ(report.walk_scans, later);
  EXPECT_GE(later, 3u);
}

}  // namespace
}  // namespace floorcast
