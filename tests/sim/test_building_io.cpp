// glTF round trip, clutter placement, observation files.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "floorcast/core/file_io.hpp"
#include "floorcast/floorplans/geometry.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/sim/clutter.hpp"
#include "floorcast/sim/gltf_io.hpp"
#include "floorcast/core/observation_io.hpp"
#include "floorcast/sim/perfect_observation.hpp"
#include "floorcast/sim/ray_scene.hpp"
#include "sim_test_util.hpp"

namespace floorcast {
namespace {

namespace fs = std::filesystem;

fs::path temp_path(const std::string& name) {
  return fs::temp_directory_path() / ("floorcast_sim_" + std::to_string(::getpid()) + "_" + name);
}

TEST(Gltf, RoundTripKeepsTrianglesLabelsPartsAndGeometry) {
  const Mesh mesh = extrude_plan(test::feature_plan());
  const fs::path path = temp_path("building.glb");
  save_mesh_glb(path.string(), mesh, {{"plan", "features"}, {"seed", 7}, {"wall_height_m", 3.0}, {"clutter", false}});
  nlohmann::json meta;
  const Mesh back = load_mesh_glb(path.string(), &meta);
  const std::string bytes = read_text_file(path.string());
  fs::remove(path);
  ASSERT_EQ(back.num_triangles(), mesh.num_triangles());
  // Metadata keep their types: numbers as numbers, not strings.
  EXPECT_EQ(meta.at("plan"), "features");
  EXPECT_TRUE(meta.at("seed").is_number_integer());
  EXPECT_EQ(meta.at("seed").get<int>(), 7);
  EXPECT_TRUE(meta.at("wall_height_m").is_number());
  EXPECT_DOUBLE_EQ(meta.at("wall_height_m").get<double>(), 3.0);
  EXPECT_EQ(meta.at("clutter"), false);
  // The JSON chunk: a y-up root node (-90 deg about x) over the label nodes, NORMAL attributes.
  const std::uint32_t json_len = static_cast<std::uint8_t>(bytes[12]) | static_cast<std::uint8_t>(bytes[13]) << 8 |
                                 static_cast<std::uint8_t>(bytes[14]) << 16 | static_cast<std::uint32_t>(static_cast<std::uint8_t>(bytes[15])) << 24;
  const nlohmann::json gltf = nlohmann::json::parse(bytes.substr(20, json_len));
  const nlohmann::json& scene = gltf["scenes"][0];
  ASSERT_EQ(scene["nodes"].size(), 1u);
  const nlohmann::json& root = gltf["nodes"][scene["nodes"][0].get<int>()];
  EXPECT_EQ(root["name"], "building");
  EXPECT_NEAR(root["rotation"][0].get<double>(), -std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(root["rotation"][3].get<double>(), std::sqrt(0.5), 1e-12);
  EXPECT_EQ(root["children"].size(), gltf["meshes"].size());
  EXPECT_TRUE(scene["extras"]["seed"].is_number());
  for (const nlohmann::json& m : gltf["meshes"]) {
    const nlohmann::json& attrs = m["primitives"][0]["attributes"];
    ASSERT_TRUE(attrs.contains("NORMAL"));
    const nlohmann::json& acc = gltf["accessors"][attrs["NORMAL"].get<int>()];
    EXPECT_EQ(acc["type"], "VEC3");
    EXPECT_EQ(acc["componentType"], 5126);
    EXPECT_EQ(acc["count"], gltf["accessors"][attrs["POSITION"].get<int>()]["count"]);
  }
  for (int l = 0; l < kNumMeshLabels; ++l) {
    EXPECT_EQ(back.count(static_cast<MeshLabel>(l)), mesh.count(static_cast<MeshLabel>(l)));
  }
  // Triangles are grouped by label on disk; compare the multiset of (label, part, vertices).
  auto key = [](const Mesh& m, std::size_t i) {
    std::vector<float> k{static_cast<float>(m.labels[i]), static_cast<float>(m.part_ids[i])};
    for (int c = 0; c < 3; ++c)
      for (int d = 0; d < 3; ++d) k.push_back(m.vertices_m[static_cast<std::size_t>(m.triangles[i][c])][d]);
    return k;
  };
  std::vector<std::vector<float>> a, b;
  for (std::size_t i = 0; i < mesh.num_triangles(); ++i) a.push_back(key(mesh, i));
  for (std::size_t i = 0; i < back.num_triangles(); ++i) b.push_back(key(back, i));
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  EXPECT_EQ(a, b);
}

TEST(Gltf, BadFilesAreClearErrors) {
  const fs::path path = temp_path("bad.glb");
  EXPECT_THROW(load_mesh_glb(path.string()), InputError);  // missing
  write_text_file_atomic(path.string(), "this is not a glb");
  try {
    load_mesh_glb(path.string());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("not a binary glTF"), std::string::npos) << e.what();
  }
  fs::remove(path);
}

TEST(Clutter, PlacedInFreeInteriorClearOfDoorsAndDeterministic) {
  // A 20 x 16 building: a 2.4 m corridor along y in [4.8, 7.2] between rooms with doors.
  FloorPlan plan = test::box_room(20.0, 16.0, 0.2);
  plan.walls.push_back({"c_s", {0.0, 4.8}, {20.0, 4.8}, 0.15, WallMaterial::kSolid, 0.0, {}});
  plan.walls.push_back({"c_n", {0.0, 7.2}, {20.0, 7.2}, 0.15, WallMaterial::kSolid, 0.0, {}});
  plan.walls.push_back({"r1", {10.0, 0.0}, {10.0, 4.8}, 0.15, WallMaterial::kSolid, 0.0, {}});
  plan.doors.push_back({"d1", "c_s", {5.0, 4.8}, 1.0, false});
  plan.doors.push_back({"d2", "c_s", {15.0, 4.8}, 1.0, false});
  plan.doors.push_back({"d3", "c_n", {10.0, 7.2}, 1.0, true});
  validate_floor_plan(plan, "clutter test");
  ClutterParams p;
  p.density = 1.0;
  p.seed = 5;
  p.keep_clear_m = {Vec2(3.0, 2.0)};
  const std::vector<Obstacle> items = generate_clutter(plan, p);
  ASSERT_GT(items.size(), 10u);
  int pillars = 0;
  for (const Obstacle& o : items) {
    pillars += o.kind == ObstacleKind::kPillar;
    // Inside the building, not in the corridor's middle band, away from doors and the keep-clear point.
    EXPECT_GT(o.center_m.x(), 0.1);
    EXPECT_LT(o.center_m.x(), 19.9);
    EXPECT_GT(o.center_m.y(), 0.1);
    EXPECT_LT(o.center_m.y(), 15.9);
    for (const Door& d : plan.doors) {
      EXPECT_GT((o.center_m - d.center_m).norm(), 0.5 * d.width_m + 0.8) << o.id;
    }
    EXPECT_GT((o.center_m - Vec2(3.0, 2.0)).norm(), 0.6) << o.id;
    if (o.center_m.y() > 4.8 && o.center_m.y() < 7.2) {
      // Corridor half-width 1.125 m: a box must leave 0.6 m to the centre line (y = 6).
      EXPECT_EQ(o.kind, ObstacleKind::kBox);
      EXPECT_LE(std::abs(o.center_m.y() - 6.0) + 0.5 * o.size_m.y(), 1.2) << o.id;
      EXPECT_GE(std::abs(o.center_m.y() - 6.0) - 0.5 * o.size_m.y(), 0.6 - 1e-9) << o.id;
    }
  }
  EXPECT_GT(pillars, 0);
  // The plan with clutter is still valid (no obstacle overlaps a wall etc.), and no two items
  // overlap: every pair of footprints is disjoint.
  FloorPlan cluttered = plan;
  for (const Obstacle& o : items) cluttered.obstacles.push_back(o);
  EXPECT_NO_THROW(validate_floor_plan(cluttered, "cluttered"));
  BlockingOptions all;
  all.obstacles_block = true;
  all.cut_height_m = 0.01;
  std::vector<Footprint> fps;
  for (const Footprint& f : blocking_footprints(cluttered, all)) {
    if (f.label == SurfaceLabel::kObstacle) fps.push_back(f);
  }
  for (std::size_t i = 0; i < fps.size(); ++i)
    for (std::size_t j = i + 1; j < fps.size(); ++j)
      for (const Vec2& v : fps[i].polygon_m) EXPECT_FALSE(point_in_convex_polygon(fps[j].polygon_m, v));
  // Deterministic, seed-dependent, density-monotone in expectation.
  const std::vector<Obstacle> again = generate_clutter(plan, p);
  ASSERT_EQ(again.size(), items.size());
  for (std::size_t i = 0; i < items.size(); ++i) EXPECT_EQ(again[i].center_m, items[i].center_m);
  p.seed = 6;
  const std::vector<Obstacle> other = generate_clutter(plan, p);
  EXPECT_FALSE(other.size() == items.size() && other[0].center_m == items[0].center_m);
  p.density = 0.0;
  EXPECT_TRUE(generate_clutter(plan, p).empty());
  p.density = 1.5;
  EXPECT_THROW(generate_clutter(plan, p), InputError);
}

TEST(ObservationIo, RoundTripOfAPerfectObservation) {
  const FloorPlan plan = test::feature_plan();
  PerfectObservationParams params;
  params.num_rays = 36;
  const PerfectObserver observer(plan, params);
  const Pose2 pose{2.0, 2.0, 0.4};
  ObservationRecord rec;
  rec.observation = observer.observe(pose);
  for (const LabeledSegment& s : observer.visible_world_segments(pose.position_m())) rec.segment_labels.push_back(s.label);
  ASSERT_EQ(rec.segment_labels.size(), rec.observation.segments_m.size());
  rec.source = "perfect";
  rec.T_world_observer = pose;
  rec.metadata["plan"] = "features";
  const std::string text = observation_to_json_text(rec);
  const ObservationRecord back = parse_observation_json(text, "obs.json");
  ASSERT_EQ(back.observation.segments_m.size(), rec.observation.segments_m.size());
  for (std::size_t i = 0; i < back.observation.segments_m.size(); ++i) {
    EXPECT_EQ(back.observation.segments_m[i].a_m, rec.observation.segments_m[i].a_m);
    EXPECT_EQ(back.observation.segments_m[i].b_m, rec.observation.segments_m[i].b_m);
    EXPECT_EQ(back.segment_labels[i], rec.segment_labels[i]);
  }
  EXPECT_EQ(back.observation.ray_ranges_m, rec.observation.ray_ranges_m);
  EXPECT_EQ(back.observation.max_range_m, 10.0);
  ASSERT_TRUE(back.T_world_observer.has_value());
  EXPECT_EQ(back.T_world_observer->yaw_rad, 0.4);
  EXPECT_EQ(back.metadata.at("plan"), "features");
  // The perfect 3-D planes come back as written.
  ASSERT_FALSE(rec.observation.planes.empty());
  ASSERT_EQ(back.observation.planes.size(), rec.observation.planes.size());
  EXPECT_EQ(back.observation.plane_cell_m, rec.observation.plane_cell_m);
  for (std::size_t i = 0; i < back.observation.planes.size(); ++i) {
    const PlanePatch& a = rec.observation.planes[i];
    const PlanePatch& b = back.observation.planes[i];
    EXPECT_EQ(a.normal, b.normal);
    EXPECT_EQ(a.offset_m, b.offset_m);
    EXPECT_EQ(a.centroid_m, b.centroid_m);
    EXPECT_EQ(a.radius_m, b.radius_m);
    EXPECT_EQ(a.cells_m, b.cells_m);
  }
  EXPECT_EQ(observation_to_json_text(back), text);
}

TEST(ObservationIo, ValidationErrors) {
  auto expect = [](const std::string& text, const std::string& fragment) {
    try {
      parse_observation_json(text, "o.json");
      FAIL() << fragment;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  const std::string head = R"({"format": "floorcast-observation", "format_version": 1, "frame": "observer", )";
  expect(head + R"("max_range_m": 10, "segments_m": [[0, 0, 1]]})", "segments_m[0]");
  expect(head + R"("max_range_m": 10, "segments_m": [], "ray_ranges_m": [11, 1, 1, 1]})", "ray_ranges_m[0]");
  expect(head + R"("max_range_m": 10, "segments_m": [[0,0,1,1]], "segment_labels": ["sofa"]})", "segment_labels[0]");
  expect(head + R"("max_range_m": 10, "segments_m": [], "extra": 1})", "extra: unknown key");
  expect(head + R"("max_range_m": -1, "segments_m": []})", "max_range_m");
  expect(head + R"("max_range_m": 10, "segments_m": [], "plane_cell_m": 0.25})", "planes and plane_cell_m come together");
  const std::string plane = R"("plane_cell_m": 0.25, "planes": [{"normal": [0, 0, 1], "offset_m": -1.5, "centroid_m": [0, 0, -1.5], )"
                            R"("radius_m": 1, "support_points": 0, "cells_m": [[0.125, 0.125, -1.5]]}])";
  EXPECT_EQ(parse_observation_json(head + R"("max_range_m": 10, "segments_m": [], )" + plane + "}", "o.json").observation.planes.size(), 1u);
  std::string bad = plane;
  bad.replace(bad.find("[0, 0, 1]"), 9, "[0, 0, 2]");
  expect(head + R"("max_range_m": 10, "segments_m": [], )" + bad + "}", "planes[0].normal: expected a unit vector");
  bad = plane;
  bad.replace(bad.find("-1.5,"), 5, "1.5, ");
  expect(head + R"("max_range_m": 10, "segments_m": [], )" + bad + "}", "planes[0].offset_m");
  expect(R"({"format": "x"})", "format");
  expect("[", "malformed JSON");
}

}  // namespace
}  // namespace floorcast
