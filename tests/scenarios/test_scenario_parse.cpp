#include <gtest/gtest.h>

#include "floorcast/core/types.hpp"
#include "floorcast/scenarios/scenario.hpp"

namespace floorcast {
namespace {

const std::string kRoot = FLOORCAST_SOURCE_DIR;

Scenario parse(const std::string& yaml) { return parse_scenario(yaml, "s.yaml", kRoot, kRoot); }

std::string error_of(const std::string& yaml) {
  try {
    (void)parse(yaml);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(accepted)";
}

const char* kMinimal = R"(
name: tiny
buildings: [floorplans/buildings/two_rooms.json]
matchers:
  kernel: {matcher: kernel}
)";

TEST(ScenarioParse, MinimalScenarioGetsEveryDefault) {
  const Scenario s = parse(kMinimal);
  EXPECT_EQ(s.name, "tiny");
  ASSERT_EQ(s.buildings.size(), 1u);
  EXPECT_EQ(s.buildings[0].label, "two_rooms");
  ASSERT_EQ(s.cells.size(), 1u);
  EXPECT_EQ(s.cells[0].id, "c000");
  EXPECT_EQ(s.cells[0].observation.source, ObservationSource::kPerfect);
  EXPECT_DOUBLE_EQ(s.cells[0].observation.perfect.max_range_m, 10.0);
  EXPECT_EQ(s.sampling.count, 20);
  const auto& r = s.resolved;
  EXPECT_EQ(r["cells"][0]["observation"]["rays"], 36);
  EXPECT_EQ(r["scoring"]["top_k"], 5);
  EXPECT_EQ(s.hash.size(), 16u);
  EXPECT_EQ(parse(kMinimal).hash, s.hash);
}

TEST(ScenarioParse, SweepFormsACartesianProductWithZippedAxes) {
  const Scenario s = parse(R"(
buildings:
  - floorplans/buildings/two_rooms.json
  - {generate: office, seed: 3}
observation: {source: scan}
matchers:
  kernel: {matcher: kernel, orientations: palms+}
  ray: {matcher: ray}
sweep:
  - observation.setting: [full, partial, single]
  - {observation.sensor: [lidar, mono], observation.path: [lidar, mono]}
  - matchers.kernel.alpha: [1, 10]
)");
  ASSERT_EQ(s.cells.size(), 12u);
  EXPECT_EQ(s.buildings[1].label, "office_3");
  // First axis slowest, last fastest.
  EXPECT_EQ(s.cells[0].observation.scan.setting, ScanSetting::kFull);
  EXPECT_EQ(s.cells[0].observation.scan.preset, "lidar");
  EXPECT_EQ(s.cells[0].observation.observe.path, ObservationPath::kLidar);
  EXPECT_EQ(s.cells[1].matchers[0].config->parameters()["alpha"], 10.0);
  EXPECT_EQ(s.cells[2].observation.scan.preset, "mono");
  EXPECT_EQ(s.cells[2].observation.observe.path, ObservationPath::kMono);
  EXPECT_EQ(s.cells[11].observation.scan.setting, ScanSetting::kSingle);
  EXPECT_EQ(s.cells[11].axes["observation.setting"], "single");
  EXPECT_EQ(s.cells[5].matchers[0].config->parameters()["orientations"], "palms+");  // base value kept
  EXPECT_EQ(s.sweep_keys.size(), 4u);
}

TEST(ScenarioParse, ErrorsNameLineAndKey) {
  EXPECT_NE(error_of(std::string(kMinimal) + "matcherz: 1\n").find("s.yaml:6:1: matcherz: unknown key"), std::string::npos)
      << error_of(std::string(kMinimal) + "matcherz: 1\n");
  const std::string bad_type = R"(
buildings: [floorplans/buildings/two_rooms.json]
sampling:
  count: many
matchers: {kernel: {matcher: kernel}}
)";
  EXPECT_NE(error_of(bad_type).find("s.yaml:4:3: sampling.count: "), std::string::npos) << error_of(bad_type);
  EXPECT_NE(error_of(bad_type).find("expected an integer"), std::string::npos) << error_of(bad_type);
  const std::string bad_range = R"(
buildings: [floorplans/buildings/two_rooms.json]
sampling: {count: -3}
matchers: {kernel: {matcher: kernel}}
)";
  EXPECT_NE(error_of(bad_range).find("sampling.count: "), std::string::npos) << error_of(bad_range);
  EXPECT_NE(error_of(bad_range).find("value -3 outside [1, 1000000]"), std::string::npos) << error_of(bad_range);
  const std::string missing_file = R"(
buildings: [floorplans/buildings/nowhere.json]
matchers: {kernel: {matcher: kernel}}
)";
  EXPECT_NE(error_of(missing_file).find("s.yaml:2:13: buildings[0]: plan file \"floorplans/buildings/nowhere.json\" not found"),
            std::string::npos)
      << error_of(missing_file);
  const std::string bad_choice = R"(
buildings: [floorplans/buildings/two_rooms.json]
observation: {setting: half}
matchers: {kernel: {matcher: kernel}}
)";
  EXPECT_NE(error_of(bad_choice).find("observation.setting: "), std::string::npos) << error_of(bad_choice);
  EXPECT_NE(error_of(bad_choice).find("expected one of full, partial, single"), std::string::npos) << error_of(bad_choice);
  const std::string bad_sweep = R"(
buildings: [floorplans/buildings/two_rooms.json]
matchers: {kernel: {matcher: kernel}}
sweep:
  observation.setting: [full, sideways]
)";
  EXPECT_NE(error_of(bad_sweep).find("(sweep cell c001)"), std::string::npos) << error_of(bad_sweep);
  const std::string sweep_unknown_matcher = R"(
buildings: [floorplans/buildings/two_rooms.json]
matchers: {kernel: {matcher: kernel}}
sweep:
  matchers.kernal.alpha: [1, 2]
)";
  EXPECT_NE(error_of(sweep_unknown_matcher).find("no matcher labelled \"kernal\""), std::string::npos);
  const std::string zipped_mismatch = R"(
buildings: [floorplans/buildings/two_rooms.json]
matchers: {kernel: {matcher: kernel}}
sweep:
  - {observation.sensor: [lidar, mono], observation.path: [lidar]}
)";
  EXPECT_NE(error_of(zipped_mismatch).find("same number of values"), std::string::npos);
  EXPECT_NE(error_of("buildings: [a, b\n").find("malformed YAML"), std::string::npos);
  const std::string dup_label = R"(
buildings: [floorplans/buildings/two_rooms.json, floorplans/buildings/two_rooms.json]
matchers: {kernel: {matcher: kernel}}
)";
  EXPECT_NE(error_of(dup_label).find("duplicate building label"), std::string::npos);
  EXPECT_NE(error_of("buildings: [floorplans/buildings/two_rooms.json]\n").find("matchers: missing required key"),
            std::string::npos);
}

TEST(ScenarioParse, QuotedScalarsStayStrings) {
  const Scenario s = parse(R"(
name: "123"
buildings: [floorplans/buildings/two_rooms.json]
matchers: {kernel: {matcher: kernel}}
)");
  EXPECT_EQ(s.name, "123");
  const std::string quoted_number = R"(
buildings: [floorplans/buildings/two_rooms.json]
matchers: {kernel: {matcher: kernel, alpha: "10"}}
)";
  EXPECT_NE(error_of(quoted_number).find("s.yaml:3:38: matchers.kernel.alpha: matcher kernel: parameter \"alpha\": expected a number"),
            std::string::npos)
      << error_of(quoted_number);
}

// Stage parameters are parsed when the scenario is loaded: a misspelt or out-of-range key of a
// matcher, the sensor or the observation module fails there, naming file:line:column and key.
TEST(ScenarioParse, StageParameterErrorsFailAtLoadWithTheirPosition) {
  const std::string misspelt = R"(
buildings: [floorplans/buildings/two_rooms.json]
matchers:
  kernel: {matcher: kernel, alpah: 5}
)";
  EXPECT_NE(error_of(misspelt).find("s.yaml:4:29: matchers.kernel.alpah: matcher kernel: unknown parameter \"alpah\""),
            std::string::npos)
      << error_of(misspelt);
  const std::string out_of_range = R"(
buildings: [floorplans/buildings/two_rooms.json]
matchers:
  ray:
    matcher: ray
    num_directions: 2
)";
  EXPECT_NE(error_of(out_of_range).find("s.yaml:6:5: matchers.ray.num_directions:"), std::string::npos)
      << error_of(out_of_range);
  const std::string unknown_matcher = R"(
buildings: [floorplans/buildings/two_rooms.json]
matchers: {best: {matcher: oracle}}
)";
  EXPECT_NE(error_of(unknown_matcher).find("matchers.best.matcher: unknown matcher \"oracle\" (known: bev, external, kernel, planes, ray; and no module floorcast_matcher_oracle.so in"),
            std::string::npos)
      << error_of(unknown_matcher);
  const std::string observe_key = R"(
buildings: [floorplans/buildings/two_rooms.json]
observation:
  source: scan
  observe_params:
    scale: {bogus: 1}
matchers: {kernel: {matcher: kernel}}
)";
  EXPECT_NE(error_of(observe_key).find("s.yaml:6:13: observation.observe_params.scale.bogus: "), std::string::npos)
      << error_of(observe_key);
  const std::string sensor_value = R"(
buildings: [floorplans/buildings/two_rooms.json]
observation:
  source: scan
  sensor_params:
    sensor: {mono: {scale_sigma_ln: -1}}
matchers: {kernel: {matcher: kernel}}
)";
  EXPECT_NE(error_of(sensor_value).find("s.yaml:6:21: observation.sensor_params.sensor.mono.scale_sigma_ln: "),
            std::string::npos)
      << error_of(sensor_value);
  const std::string shared_key = R"(
buildings: [floorplans/buildings/two_rooms.json]
shared: {range: 5}
matchers: {kernel: {matcher: kernel}}
)";
  EXPECT_NE(error_of(shared_key).find("s.yaml:3:10: shared.range: "), std::string::npos) << error_of(shared_key);
}

// One range and one set of blocking flags flow to the perfect observer and every matcher, unless
// a stage sets its own explicitly; the resolved configuration lists every stage's every default.
TEST(ScenarioParse, SharedQuantitiesFlowToEveryStageAndResolvedShowsEveryDefault) {
  const Scenario s = parse(R"(
buildings: [floorplans/buildings/two_rooms.json]
shared: {range_m: 8, doors_closed: false}
matchers:
  kernel: {matcher: kernel}
  ray: {matcher: ray}
  ray12: {matcher: ray, max_range_m: 12}
)");
  const CellSpec& c = s.cells.at(0);
  EXPECT_EQ(c.observation.perfect.max_range_m, 8.0);
  EXPECT_FALSE(c.observation.perfect.blocking.open_doors_block);
  EXPECT_EQ(c.matchers[0].config->parameters()["max_range_m"], 8.0);
  EXPECT_EQ(c.matchers[0].config->parameters()["doors_closed"], false);
  EXPECT_EQ(c.matchers[1].config->parameters()["max_range_m"], 8.0);
  EXPECT_EQ(c.matchers[2].config->parameters()["max_range_m"], 12.0);  // explicit wins
  EXPECT_EQ(c.matchers[2].config->parameters()["doors_closed"], false);
  const nlohmann::ordered_json& r = s.resolved;
  EXPECT_EQ(r["shared"]["range_m"], 8.0);
  const nlohmann::ordered_json& kernel = r["cells"][0]["matchers"]["kernel"];
  EXPECT_EQ(kernel["matcher"], "kernel");
  EXPECT_EQ(kernel["blur_size_px"], 15);  // a default nobody wrote
  EXPECT_EQ(kernel["scales"].size(), 3u);
  EXPECT_EQ(r["cells"][0]["parameters"]["perfect_observer"]["num_rays"], 36);
  const Scenario scan = parse(R"(
buildings: [floorplans/buildings/two_rooms.json]
observation: {source: scan, sensor: lidar, path: lidar}
matchers: {kernel: {matcher: kernel}}
)");
  const nlohmann::ordered_json& p = scan.resolved["cells"][0]["parameters"];
  EXPECT_EQ(p["sensor"]["preset"], "lidar");
  EXPECT_TRUE(p["observation_module"]["scale"].contains("max_rounds"));
}

}  // namespace
}  // namespace floorcast

namespace floorcast {
namespace {

TEST(ScenarioParse, ResolvedFormRoundTripsWithTheSameHash) {
  const Scenario s = parse(R"(
buildings: [floorplans/buildings/two_rooms.json, {generate: campus, seed: 9}]
observation: {source: scan, sensor_params: {sensor: {mono: {scale_sigma_ln: 0.2}}}}
matchers: {kernel: {matcher: kernel, alpha: 5}, ray: {matcher: ray}}
paper: [{label: "PALMS+ paper", source: "sec. 4.4", values: {recall_1m_30deg: 0.887}}]
sweep: {observation.setting: [full, single]}
)");
  const nlohmann::json written = nlohmann::json::parse(s.resolved.dump());
  const Scenario back = scenario_from_resolved(written, "resolved.json");
  EXPECT_EQ(back.hash, s.hash);
  ASSERT_EQ(back.cells.size(), 2u);
  EXPECT_EQ(back.cells[1].observation.scan.setting, ScanSetting::kSingle);
  EXPECT_EQ(back.cells[0].observation.scan.sensor.mono.scale_sigma_ln, 0.2);
  EXPECT_EQ(back.cells[0].matchers[0].config->parameters()["alpha"], 5.0);
  EXPECT_EQ(nlohmann::json(back.resolved), nlohmann::json(s.resolved));
  EXPECT_EQ(back.buildings[1].archetype, "campus");
  EXPECT_EQ(back.paper.at(0).values.at("recall_1m_30deg"), 0.887);
  EXPECT_EQ(back.sweep_keys, s.sweep_keys);
}

}  // namespace
}  // namespace floorcast
