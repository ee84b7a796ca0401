#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include "floorcast/floorplans/io.hpp"
#include "floorcast/floorplans/generate.hpp"
#include "floorcast/scenarios/runner.hpp"
#include "floorcast/scenarios/sampling.hpp"
#include "floorcast/scenarios/units.hpp"
#include "floorcast/core/math.hpp"
#include "../match/match_test_plans.hpp"

namespace floorcast {
namespace {

/// Distance from p to the nearest edge of a polygon's outline.
double distance_to_outline(const std::vector<Vec2>& polygon_m, const Vec2& p) {
  double d = 1e9;
  for (std::size_t k = 0; k < polygon_m.size(); ++k)
    d = std::min(d, point_segment_distance(p, Segment2{polygon_m[k], polygon_m[(k + 1) % polygon_m.size()]}));
  return d;
}

TEST(Sampling, SamplingIsSeededAndClear) {
  const FloorPlan plan = test::asymmetric_floor();
  const auto a = sample_observation_poses(plan, 40, 7, 0, 0.5);
  const auto b = sample_observation_poses(plan, 40, 7, 0, 0.5);
  const auto c = sample_observation_poses(plan, 40, 8, 0, 0.5);
  const auto first10 = sample_observation_poses(plan, 10, 7, 0, 0.5);
  ASSERT_EQ(a.size(), 40u);
  int differ = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].x_m, b[i].x_m);
    EXPECT_EQ(a[i].yaw_rad, b[i].yaw_rad);
    differ += a[i].x_m != c[i].x_m;
    if (i < 10) {
      EXPECT_EQ(a[i].y_m, first10[i].y_m);  // point i does not depend on N
    }
  }
  EXPECT_GT(differ, 30);
  // Clearance from every wall surface.
  const auto outline = blocking_outline(plan, BlockingOptions{});
  for (const Pose2& p : a) {
    double d = 1e9;
    for (const auto& l : outline) {
      const Vec2 e = l.segment_m.b_m - l.segment_m.a_m;
      const double t = std::clamp((p.position_m() - l.segment_m.a_m).dot(e) / e.squaredNorm(), 0.0, 1.0);
      d = std::min(d, (l.segment_m.a_m + t * e - p.position_m()).norm());
    }
    EXPECT_GE(d, 0.5);
    EXPECT_GE(p.yaw_rad, 0.0);
    EXPECT_LT(p.yaw_rad, 2.0 * kPi);
  }
  EXPECT_THROW(sample_observation_poses(plan, 5, 1, 0, 50.0), InputError);
}

TEST(Sampling, SamplingKeepsClearOfFurniture) {
  // The shipped apartment is furnished (beds, sofas, tables: all lower than the 1.5 m cut of the
  // default rasters). No observer stands inside or within the clearance of any of them.
  const FloorPlan plan = load_floor_plan(std::string(FLOORCAST_SOURCE_DIR) + "/floorplans/buildings/apartment.json");
  ASSERT_GT(plan.obstacles.size(), 5u);
  BlockingOptions ground;
  ground.obstacles_block = true;
  ground.cut_height_m = 0.01;
  std::vector<Footprint> furniture;
  for (const Footprint& f : blocking_footprints(plan, ground))
    if (f.label == SurfaceLabel::kObstacle) furniture.push_back(f);
  ASSERT_EQ(furniture.size(), plan.obstacles.size());
  const double clearance_m = 0.3;
  for (const Pose2& p : sample_observation_poses(plan, 300, 3, 0, clearance_m)) {
    for (const Footprint& f : furniture) {
      ASSERT_FALSE(point_in_polygon(f.polygon_m, p.position_m())) << "pose inside obstacle " << f.source_index;
      const double d = distance_to_outline(f.polygon_m, p.position_m());
      EXPECT_GE(d, clearance_m) << "obstacle " << f.source_index;
    }
  }
}

// Partitions thinner than a raster cell (5 cm toilet-cubicle walls, as every generated core has)
// keep their clearance too: before box obstacles were painted along their medial segment, such a
// partition was painted only where a row of cell centres fell inside its 5 cm band, and uniform
// sampling stood observers on it. Eight partitions at 0-90 deg and sub-cell offsets in the
// asymmetric floor's largest room; 400 points, clearance 0.3 m.
TEST(Sampling, SamplingKeepsClearOfPartitionsThinnerThanACell) {
  FloorPlan plan = test::asymmetric_floor();
  for (int i = 0; i < 8; ++i) {  // two rows of four in the room x 5-12, y 0-5, 1 m long
    const double x = 6.0 + 1.5 * (i % 4) + 0.013 * i, y = (i < 4 ? 2.5 : 4.0) + 0.021 * i, yaw = kPi / 2.0 * i / 7.0;
    plan.obstacles.push_back(Obstacle{"cubicle" + std::to_string(i), ObstacleKind::kBox, Vec2(x, y), Vec2(1.0, 0.05), yaw, 2.0});
  }
  BlockingOptions ground;
  ground.obstacles_block = true;
  ground.cut_height_m = 0.01;
  const double clearance_m = 0.3;
  int near = 0;
  for (const Pose2& p : sample_observation_poses(plan, 400, 5, 0, clearance_m)) {
    for (const Footprint& f : blocking_footprints(plan, ground)) {
      if (f.label != SurfaceLabel::kObstacle) continue;
      const double d = distance_to_outline(f.polygon_m, p.position_m());
      ASSERT_FALSE(point_in_polygon(f.polygon_m, p.position_m())) << "pose inside partition " << f.source_index;
      EXPECT_GE(d, clearance_m) << "partition " << f.source_index;
      near += d < 1.0;
    }
  }
  EXPECT_GT(near, 20) << "too few points near the partitions: the test would not test anything";
}

TEST(Sampling, SamplingRegions) {
  const std::vector<Vec2> l_shape = {{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 3}, {0, 3}};
  EXPECT_TRUE(point_in_polygon(l_shape, {0.5, 2.5}));
  EXPECT_TRUE(point_in_polygon(l_shape, {3.5, 0.5}));
  EXPECT_FALSE(point_in_polygon(l_shape, {2.5, 2.0}));  // in the notch
  EXPECT_FALSE(point_in_polygon(l_shape, {-0.1, 0.5}));
  // Only the east room (x > 5) of the asymmetric plan.
  const FloorPlan plan = test::asymmetric_floor();
  const std::vector<Room> east = {{"e", "lobby", {{5, 0}, {12, 0}, {12, 5}, {5, 5}}, {}}};
  for (const Pose2& p : sample_observation_poses(plan, 30, 4, 0, 0.3, 0.1, east, {"transitional"})) {
    EXPECT_GT(p.x_m, 5.3);
    EXPECT_LT(p.y_m, 4.7);
  }
  const std::vector<Room> nowhere = {{"n", "lobby", {{20, 20}, {21, 20}, {21, 21}}, {}}};
  EXPECT_THROW(sample_observation_poses(plan, 3, 4, 0, 0.3, 0.1, nowhere, {"lobby"}), InputError);
  // Nested labels: a circulation outline around the whole plan and an office inside it. The
  // office's cells belong to the office (the smallest room), so no transitional point lands there.
  const std::vector<Room> nested = {{"level", "circulation", {{-1, -1}, {20, -1}, {20, 20}, {-1, 20}}, {}},
                                    {"o", "office", {{5, 0}, {12, 0}, {12, 5}, {5, 5}}, {}}};
  int in_office = 0;
  for (const Pose2& p : sample_observation_poses(plan, 60, 4, 0, 0.3, 0.1, nested, {"transitional"})) {
    if (p.x_m > 5.0 && p.x_m < 12.0 && p.y_m > 0.0 && p.y_m < 5.0) ++in_office;
  }
  EXPECT_EQ(in_office, 0);
  // Without kinds every free cell counts, the office included.
  in_office = 0;
  for (const Pose2& p : sample_observation_poses(plan, 60, 4, 0, 0.3, 0.1, nested)) {
    if (p.x_m > 5.0 && p.x_m < 12.0 && p.y_m > 0.0 && p.y_m < 5.0) ++in_office;
  }
  EXPECT_GT(in_office, 0);
}

// The default is the PALMS+ sec. 4.4 protocol: points in transitional spaces when the plan has
// room labels (generated buildings, shipped plans); a plan without labels is sampled uniformly
// and the resolved configuration says so; sampling.region: uniform asks for the whole free space.
TEST(Sampling, TransitionalByDefault) {
  const std::string yaml = R"(
buildings: [{generate: office, seed: 3}, floorplans/buildings/office.json, floorplans/buildings/two_rooms.json]
sampling: {count: 10, seed: 5}
observation: {source: perfect}
matchers: {kernel: {matcher: kernel}}
)";
  const Scenario s = parse_scenario(yaml, "default.yaml", ".", FLOORCAST_SOURCE_DIR);
  EXPECT_EQ(s.sampling.region, "transitional");
  ASSERT_EQ(s.buildings.size(), 3u);
  EXPECT_EQ(s.buildings[0].sampling_region, "transitional");
  EXPECT_EQ(s.buildings[1].sampling_region, "transitional");
  EXPECT_EQ(s.buildings[2].sampling_region, "uniform_unlabelled");
  EXPECT_EQ(s.resolved["buildings"][2]["sampling_region"], "uniform_unlabelled");
  const ScenarioRunner runner(s);
  const GeneratedBuilding office = generate_building(Archetype::kOffice, 3);
  for (const WorkUnit& u : enumerate_units(s)) {
    if (u.building > 1) continue;
    const Pose2 p = runner.run_unit(u, nullptr).truth;
    const int k = room_at(office.rooms, p.position_m());
    if (u.building == 0) {
      ASSERT_GE(k, 0) << u.id;
      EXPECT_TRUE(is_transitional_kind(office.rooms[static_cast<std::size_t>(k)].kind)) << u.id;
    }
  }
  const std::string uniform = R"(
buildings: [{generate: office, seed: 3}]
sampling: {count: 40, seed: 5, region: uniform}
matchers: {kernel: {matcher: kernel}}
)";
  const Scenario su = parse_scenario(uniform, "uniform.yaml", ".", FLOORCAST_SOURCE_DIR);
  EXPECT_EQ(su.buildings[0].sampling_region, "uniform");
  const ScenarioRunner ru(su);
  int outside_transitional = 0;
  for (const WorkUnit& u : enumerate_units(su)) {
    const int k = room_at(office.rooms, ru.run_unit(u, nullptr).truth.position_m());
    if (k < 0 || !is_transitional_kind(office.rooms[static_cast<std::size_t>(k)].kind)) ++outside_transitional;
  }
  EXPECT_GT(outside_transitional, 10);  // offices are most of an office building's floor
  EXPECT_THROW(parse_scenario("buildings: [{generate: office}]\nsampling: {region: kinds}\nmatchers: {k: {matcher: kernel}}\n",
                              "bad.yaml", ".", FLOORCAST_SOURCE_DIR),
               InputError);
}

// sampling.region_kinds: every observation point of a generated office lies in one of its
// hallways; a plan file without room labels is refused when region kinds are asked for.
TEST(Sampling, RegionKindsInAScenario) {
  const std::string yaml = R"(
buildings: [{generate: office, seed: 3}]
sampling: {count: 12, seed: 5, region_kinds: [hallway]}
observation: {source: perfect}
matchers: {kernel: {matcher: kernel}}
)";
  const Scenario s = parse_scenario(yaml, "regions.yaml", ".", FLOORCAST_SOURCE_DIR);
  ASSERT_EQ(s.sampling.region_kinds, std::vector<std::string>{"hallway"});
  EXPECT_EQ(s.sampling.region, "kinds");
  const GeneratedBuilding office = generate_building(Archetype::kOffice, 3);
  std::vector<std::vector<Vec2>> hallways;
  for (const GeneratedRoom& r : office.rooms)
    if (r.kind == "hallway") hallways.push_back(r.polygon_m);
  ASSERT_FALSE(hallways.empty());
  const ScenarioRunner runner(s);
  for (const WorkUnit& u : enumerate_units(s)) {
    const Pose2 p = runner.run_unit(u, nullptr).truth;
    bool inside = false;
    for (const auto& h : hallways) inside = inside || point_in_polygon(h, p.position_m());
    EXPECT_TRUE(inside) << u.id << " at " << p.x_m << ", " << p.y_m;
  }
  const std::string no_rooms = R"(
buildings: [floorplans/buildings/two_rooms.json]
sampling: {count: 2, region_kinds: [hallway]}
matchers: {kernel: {matcher: kernel}}
)";
  const Scenario bad = parse_scenario(no_rooms, "regions.yaml", ".", FLOORCAST_SOURCE_DIR);
  try {
    const ScenarioRunner r(bad);
    FAIL() << "expected a refusal";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("needs room labels"), std::string::npos) << e.what();
  }
}


// Sampling says what it sampled and, when it cannot, why: one message per cause (issue 23).
TEST(Sampling, RefusalsNameTheirCause) {
  const FloorPlan plan = test::asymmetric_floor();
  auto refusal = [&](const std::vector<Room>& rooms, double clearance_m) {
    try {
      (void)sample_observation_points(plan, 5, 1, 0, clearance_m, 0.1, rooms, {"transitional"});
    } catch (const SamplingError& e) {
      return std::make_pair(e.cause(), std::string(e.what()));
    }
    return std::make_pair(SamplingRefusal::kNoClearance, std::string("no refusal"));
  };
  // No room of the sampled kinds: the message lists the kinds the plan has.
  const auto none = refusal({{"o", "office", {{5, 0}, {12, 0}, {12, 5}, {5, 5}}, {}}}, 0.3);
  EXPECT_EQ(none.first, SamplingRefusal::kNoRoomOfKinds);
  EXPECT_NE(none.second.find("no room of the sampled kinds"), std::string::npos) << none.second;
  EXPECT_NE(none.second.find("office 1"), std::string::npos) << none.second;
  // Corridors labelled but outside the free space (an import that left them out).
  const auto outside = refusal({{"c", "corridor", {{20, 0}, {40, 0}, {40, 3}, {20, 3}}, {}}}, 0.3);
  EXPECT_EQ(outside.first, SamplingRefusal::kKindsOutsideFreeSpace);
  EXPECT_NE(outside.second.find("outside the plan's free space"), std::string::npos) << outside.second;
  EXPECT_NE(outside.second.find("60.0 m^2"), std::string::npos) << outside.second;
  // Corridors free but too narrow for the clearance.
  const auto narrow = refusal({{"c", "corridor", {{5, 0}, {12, 0}, {12, 5}, {5, 5}}, {}}}, 3.0);
  EXPECT_EQ(narrow.first, SamplingRefusal::kKindsTooNarrow);
  EXPECT_NE(narrow.second.find("nowhere more than"), std::string::npos) << narrow.second;
  EXPECT_NE(narrow.second.find("3.00 m clearance"), std::string::npos) << narrow.second;
  // Uniform: no free cell with the clearance.
  try {
    (void)sample_observation_points(plan, 5, 1, 0, 50.0);
    FAIL() << "expected a refusal";
  } catch (const SamplingError& e) {
    EXPECT_EQ(e.cause(), SamplingRefusal::kNoClearance);
  }
}

TEST(Sampling, CoverageCountsKindsAndCellsAndWarns) {
  const FloorPlan plan = test::asymmetric_floor();
  const std::vector<Room> rooms = {{"l", "lobby", {{5, 0}, {12, 0}, {12, 5}, {5, 5}}, {}},
                                   {"o", "office", {{0, 0}, {5, 0}, {5, 5}, {0, 5}}, {}}};
  const SampledPoints all = sample_observation_points(plan, 60, 4, 0, 0.3, 0.1, rooms);
  int total = 0;
  for (const auto& [kind, count] : all.coverage.points_per_kind) total += count;
  EXPECT_EQ(total, 60);
  EXPECT_EQ(all.coverage.points, 60);
  EXPECT_GT(all.coverage.distinct_cells_2m, 8);
  EXPECT_TRUE(all.coverage.warnings.empty());
  // The same points as sample_observation_poses.
  const std::vector<Pose2> same = sample_observation_poses(plan, 60, 4, 0, 0.3, 0.1, rooms);
  for (std::size_t i = 0; i < same.size(); ++i) EXPECT_EQ(same[i].x_m, all.poses[i].x_m);
  // A corridor label mostly outside the walls: the points land in its small free part, and the
  // coverage says the corridors are mostly outside the free space and the points crowd together.
  const std::vector<Room> stray = {{"c", "corridor", {{11, 3.5}, {60, 3.5}, {60, 20}, {11, 20}}, {}}};
  const SampledPoints crowded = sample_observation_points(plan, 40, 4, 0, 0.3, 0.1, stray, {"transitional"});
  ASSERT_EQ(crowded.coverage.points_per_kind.size(), 1u);
  EXPECT_EQ(crowded.coverage.points_per_kind[0].first, "corridor");
  EXPECT_LE(crowded.coverage.distinct_cells_2m, 3);
  ASSERT_EQ(crowded.coverage.warnings.size(), 2u);
  EXPECT_NE(crowded.coverage.warnings[0].find("outside the plan's free space"), std::string::npos);
  EXPECT_NE(crowded.coverage.warnings[1].find("distinct 2 m cells"), std::string::npos);
}

// sampling.region: transitional_or_uniform samples a labelled plan without transitional spaces
// uniformly and says why; the plain transitional region refuses it with the cause.
TEST(Sampling, TransitionalOrUniformFallsBackWithTheReason) {
  const std::string dir = ::testing::TempDir() + "/sampling_fallback";
  std::filesystem::create_directories(dir);
  FloorPlan plan = load_floor_plan(std::string(FLOORCAST_SOURCE_DIR) + "/floorplans/buildings/two_rooms.json");
  Room office;
  office.id = "o";
  office.kind = "office";
  office.polygon_m = {{0, 0}, {8, 0}, {8, 5}, {0, 5}};
  plan.rooms = {office};
  save_floor_plan(plan, dir + "/offices.json");
  const std::string yaml = R"(
buildings: [offices.json]
sampling: {count: 6, seed: 5, region: transitional_or_uniform}
observation: {source: perfect}
matchers: {kernel: {matcher: kernel}}
)";
  const Scenario s = parse_scenario(yaml, "fallback.yaml", dir, FLOORCAST_SOURCE_DIR);
  EXPECT_EQ(s.buildings[0].sampling_region, "transitional_or_uniform");
  std::vector<std::string> log;
  const ScenarioRunner runner(s, [&](const std::string& line) { log.push_back(line); });
  EXPECT_EQ(runner.building_points(0).size(), 6u);
  EXPECT_NE(runner.building_sampling_region(0).find("uniform (fallback: "), std::string::npos);
  EXPECT_NE(runner.building_sampling_region(0).find("no room of the sampled kinds"), std::string::npos);
  bool logged = false;
  for (const std::string& l : log) logged = logged || (l.find("fallback") != std::string::npos && l.find("6 office") != std::string::npos);
  EXPECT_TRUE(logged);
  const Scenario strict = parse_scenario("buildings: [offices.json]\nsampling: {count: 6}\nmatchers: {k: {matcher: kernel}}\n",
                                         "strict.yaml", dir, FLOORCAST_SOURCE_DIR);
  EXPECT_THROW(ScenarioRunner r(strict), SamplingError);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace floorcast
