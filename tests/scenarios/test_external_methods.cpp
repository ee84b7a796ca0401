// External methods in scenario runs: a misbehaving program's errors stay with its units (every
// other method's results are complete and unchanged), the report counts them, and a resumed run
// runs exactly those units again.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "floorcast/scenarios/report.hpp"
#include "floorcast/scenarios/run_directory.hpp"
#include "floorcast/scenarios/runner.hpp"

namespace floorcast {
namespace {

namespace fs = std::filesystem;
const std::string kRoot = FLOORCAST_SOURCE_DIR;

std::string folder(const std::string& name) {
  const fs::path p = fs::path(FLOORCAST_TEST_OUT) / name;
  fs::remove_all(p);
  fs::create_directories(p);
  return p.string();
}

/// A program that misbehaves on some observations, decided by the observation file's checksum
/// (deterministic per unit): crash, hang, a wrong-shaped posterior, or a pose.
void write_program(const std::string& path, bool fixed) {
  std::ofstream f(path);
  f << "#!/bin/sh\n"
       "out=$(sed -n 's/.*\"output_dir\": \"\\(.*\\)\".*/\\1/p' \"$1\")\n"
       "obs=$(sed -n 's/.*\"observation\": \"\\(.*\\)\".*/\\1/p' \"$1\")\n"
       "mode=$(cksum < \"$obs\" | awk '{print $1 % 4}')\n";
  if (!fixed) {
    f << "if [ $mode = 1 ]; then echo 'weights.pt: cannot open' >&2; exit 3; fi\n"
         "if [ $mode = 2 ]; then sleep 30; fi\n"
         "if [ $mode = 3 ]; then printf '{\"poses\": [{\"x_m\": \"left\"}]}' > $out/top_k.json; exit 0; fi\n";
  }
  f << "printf '{\"poses\": [{\"x_m\": 2.0, \"y_m\": 2.0, \"yaw_deg\": 10, \"score\": 1}]}' > $out/top_k.json\n";
}

Scenario scenario(const std::string& program) {
  return parse_scenario(R"(
name: external-errors
buildings: [floorplans/buildings/two_rooms.json, floorplans/buildings/apartment.json]
sampling: {count: 6, seed: 4, clearance_m: 0.4, region: uniform}
output: {heatmaps: 0}
matchers:
  kernel: {matcher: kernel}
  mine: {matcher: external, command: [sh, )" + program + R"(], timeout_s: 1.5, resolution_m: 0.25}
)", "external.yaml", kRoot, kRoot);
}

class DirSink : public UnitSink {
 public:
  DirSink(const RunDirectory& d, const Scenario& s) : dir(d), sc(s) {}
  bool has_unit(const WorkUnit& u) const override { return dir.has_unit(sc, u); }
  void write_unit(const UnitResult& r) override { dir.write_unit(sc, r); }
  void write_image(const std::string&, const cv::Mat&) override {}
  const RunDirectory& dir;
  const Scenario& sc;
};

TEST(ExternalMethods, ErrorsStayWithTheirUnitsAndRerunOnResume) {
  const std::string work = folder("external_errors");
  const std::string program = work + "/matcher.sh";
  write_program(program, false);
  const Scenario s = scenario(program);
  // The command's script path is part of the configuration (its hash).
  EXPECT_NE(s.resolved.dump().find("matcher.sh"), std::string::npos);
  const ScenarioRunner runner(s);
  RunDirectory dir(work + "/run");
  dir.open(s, runner.resolved_full());
  DirSink sink(dir, s);
  RunOptions o;
  o.jobs = 2;
  const RunOutcome first = runner.run(sink, o);
  EXPECT_EQ(first.executed, 12u);

  std::vector<UnitResult> units = dir.read_units(s);
  ASSERT_EQ(units.size(), 12u);
  int errors = 0, ok = 0;
  std::map<std::string, int> kinds;
  for (const UnitResult& u : units) {
    ASSERT_EQ(u.outcomes.size(), 2u);
    EXPECT_TRUE(u.outcomes[0].ok) << u.unit.id << ": kernel lost";  // nothing else is lost
    const MatcherOutcome& m = u.outcomes[1];
    if (m.ok) {
      ++ok;
      EXPECT_DOUBLE_EQ(m.estimate.x_m, 2.0);
      continue;
    }
    ++errors;
    EXPECT_TRUE(m.error);
    if (m.failure.find("exited with status 3; its standard error ends:\nweights.pt: cannot open") != std::string::npos) ++kinds["crash"];
    else if (m.failure.find("did not finish within 1.5 s and was killed") != std::string::npos) ++kinds["hang"];
    else if (m.failure.find("poses[0]: \"x_m\" must be a number") != std::string::npos) ++kinds["malformed"];
    else ADD_FAILURE() << u.unit.id << ": unexpected failure " << m.failure;
  }
  EXPECT_GT(errors, 0);
  EXPECT_GT(ok, 0);
  EXPECT_GT(kinds.size(), 1u) << "the checksums should pick more than one way to misbehave";

  // The report counts the errors apart and says so.
  const Report rep = build_report(s, units, {});
  const auto& cell = rep.summary["cells"][0];
  EXPECT_EQ(cell["errors"]["mine"]["units"].get<int>(), errors);
  EXPECT_EQ(cell["no_pose"]["mine"].get<int>(), 0);
  EXPECT_NE(rep.summary_md.find("**Errors:** mine misbehaved on " + std::to_string(errors) + " of 12 units"), std::string::npos)
      << rep.summary_md;
  // Errors count as misses: at most the units with a pose can be within any distance.
  EXPECT_LE(cell["groups"]["all"]["mine"]["recall_5m"].get<double>(), ok / 12.0 + 1e-12);

  // The kernel's results equal a run without the misbehaving program.
  const Scenario kernel_only = parse_scenario(R"(
name: kernel-only
buildings: [floorplans/buildings/two_rooms.json, floorplans/buildings/apartment.json]
sampling: {count: 6, seed: 4, clearance_m: 0.4, region: uniform}
output: {heatmaps: 0}
matchers: {kernel: {matcher: kernel}}
)", "k.yaml", kRoot, kRoot);
  const ScenarioRunner kr(kernel_only);
  for (const UnitResult& u : units) {
    const UnitResult k = kr.run_unit(u.unit, nullptr);
    EXPECT_EQ(strip_timings(unit_to_json(k))["outcomes"][0].dump(), strip_timings(unit_to_json(u))["outcomes"][0].dump());
  }

  // Resumed: exactly the units with errors run again (they misbehave again, identically).
  const RunOutcome again = runner.run(sink, o);
  EXPECT_EQ(again.executed, static_cast<std::size_t>(errors));
  EXPECT_EQ(again.skipped, 12u - static_cast<std::size_t>(errors));
  // The program fixed (same path, same configuration): the next resume completes them.
  write_program(program, true);
  const RunOutcome fixed = runner.run(sink, o);
  EXPECT_EQ(fixed.executed, static_cast<std::size_t>(errors));
  units = dir.read_units(s);
  for (const UnitResult& u : units) EXPECT_TRUE(u.outcomes[1].ok) << u.unit.id;
  EXPECT_FALSE(build_report(s, units, {}).summary["cells"][0].contains("errors"));
  EXPECT_EQ(runner.run(sink, o).executed, 0u);
}

TEST(ExternalMethods, ConfigurationHashCountsTheProgramByNameAndVersionNotWhereItLies) {
  const std::string work = folder("external_hash");
  for (const char* sub : {"a", "b"}) {
    fs::create_directories(work + "/" + sub);
    write_program(work + "/" + sub + "/matcher.sh", true);
  }
  const Scenario a = scenario(work + "/a/matcher.sh"), b = scenario(work + "/b/matcher.sh");
  EXPECT_NE(a.resolved.dump(), b.resolved.dump());  // the resolved configuration says where it ran
  EXPECT_EQ(a.hash, b.hash);
  EXPECT_EQ(scenario_hash(nlohmann::json(a.resolved)), a.hash);
  // A new version is another configuration.
  const Scenario v2 = parse_scenario(R"(
name: external-errors
buildings: [floorplans/buildings/two_rooms.json, floorplans/buildings/apartment.json]
sampling: {count: 6, seed: 4, clearance_m: 0.4, region: uniform}
output: {heatmaps: 0}
matchers:
  kernel: {matcher: kernel}
  mine: {matcher: external, command: [sh, )" + work + R"(/a/matcher.sh], timeout_s: 1.5, resolution_m: 0.25, version: "2"}
)", "external.yaml", kRoot, kRoot);
  EXPECT_NE(v2.hash, a.hash);
}

}  // namespace
}  // namespace floorcast
