// Structured3D importer on a hand-built three-room scene (see data/make_fixtures.py).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "floorcast/floorplans/import.hpp"
#include "floorcast/floorplans/io.hpp"
#include "import_test_util.hpp"

namespace floorcast {
namespace {

using test::data_path;
using test::door_by_id;
using test::expect_input_error;
using test::find_wall;

const double kTol = 1e-9;

TEST(ImportS3d, RoomSurfacesBecomeWallsWithDoorsCutIntoBothSurfaces) {
  const ImportResult r = import_floor_plan(data_path("s3d/scene_00000"), ImportFormat::kS3d);
  const FloorPlan& p = r.plan;
  EXPECT_EQ(p.name, "scene_00000");
  // 3 rooms x 4 surfaces = 12; B|C share the zero-thickness partition (duplicate), and B's and
  // C's south and north surfaces continue each other: 12 - 3 = 9 walls.
  ASSERT_EQ(p.walls.size(), 9u);
  EXPECT_EQ(r.cleanup.walls_merged_away, 3);
  EXPECT_NEAR(r.cleanup.duplicate_length_m, 3.0, 1e-9);
  for (const Wall& w : p.walls) EXPECT_DOUBLE_EQ(w.thickness_m, 0.02);
  EXPECT_NE(find_wall(p, {0, 0}, {4, 0}, kTol), nullptr);       // A south (mm -> m)
  EXPECT_NE(find_wall(p, {4, 0}, {4, 3}, kTol), nullptr);       // A east
  EXPECT_NE(find_wall(p, {4.2, 0}, {4.2, 3}, kTol), nullptr);   // B west, 0.2 m behind A east
  EXPECT_NE(find_wall(p, {8, 0}, {8, 3}, kTol), nullptr);       // B east = C west, one wall
  EXPECT_NE(find_wall(p, {4.2, 0}, {10, 0}, kTol), nullptr);    // B south + C south
  EXPECT_NE(find_wall(p, {4.2, 3}, {10, 3}, kTol), nullptr);    // B north + C north
  EXPECT_NE(find_wall(p, {10, 0}, {10, 3}, kTol), nullptr);     // C east
  EXPECT_EQ(find_wall(p, {-0.2, -0.2}, {10.2, -0.2}, 0.01), nullptr);  // no outwall by default

  // Door 1 (semantics ID 4) through the 0.2 m wall: one opening in each surface.
  ASSERT_EQ(p.doors.size(), 4u);
  const Door* d1a = door_by_id(p, "door4");
  const Door* d1b = door_by_id(p, "door4-2");
  ASSERT_TRUE(d1a && d1b);
  EXPECT_EQ(p.walls[static_cast<std::size_t>(p.wall_index(d1a->wall_id))].a_m.x(), 4.0);
  EXPECT_EQ(p.walls[static_cast<std::size_t>(p.wall_index(d1b->wall_id))].a_m.x(), 4.2);
  for (const Door* d : {d1a, d1b}) {
    EXPECT_NEAR(d->center_m.y(), 1.45, kTol);
    EXPECT_NEAR(d->width_m, 0.9, kTol);
    EXPECT_FALSE(d->closed);
  }
  // Door 2: on B's north surface.
  const Door* d2 = door_by_id(p, "door5");
  ASSERT_TRUE(d2);
  EXPECT_NEAR(d2->center_m.x(), 6.45, kTol);
  EXPECT_NEAR(d2->center_m.y(), 3.0, kTol);
  // Door 3: the two coincident door planes on the merged B|C wall became one door.
  const Door* d3 = door_by_id(p, "door6");
  ASSERT_TRUE(d3);
  EXPECT_EQ(door_by_id(p, "door6-2"), nullptr);
  EXPECT_EQ(r.cleanup.openings_merged, 1);
  EXPECT_NEAR(d3->center_m.x(), 8.0, kTol);
  EXPECT_NEAR(d3->center_m.y(), 1.4, kTol);
  EXPECT_NEAR(d3->width_m, 0.8, kTol);

  ASSERT_EQ(p.windows.size(), 1u);
  const Window& win = p.windows[0];
  EXPECT_EQ(win.id, "window7");
  EXPECT_NEAR(win.center_m.x(), 1.75, kTol);
  EXPECT_NEAR(win.center_m.y(), 0.0, kTol);
  EXPECT_NEAR(win.width_m, 1.5, kTol);
  EXPECT_NEAR(win.sill_m, 0.9, kTol);
  EXPECT_NEAR(win.head_m, 2.1, kTol);
  EXPECT_TRUE(r.notes.empty());
}

TEST(ImportS3d, OutwallOptionAddsExteriorSurfacesAndOpensThem) {
  ImportOptions o;
  o.s3d_include_outwall = true;
  o.doors_closed = true;
  const ImportResult r = import_floor_plan(data_path("s3d/scene_00000/annotation_3d.json"), ImportFormat::kS3d, o);
  const FloorPlan& p = r.plan;
  EXPECT_EQ(p.name, "scene_00000");
  EXPECT_EQ(p.walls.size(), 13u);
  EXPECT_NE(find_wall(p, {-0.2, -0.2}, {10.2, -0.2}, kTol), nullptr);
  // Door 2 now also opens the exterior surface 0.2 m behind B's north surface; the window too.
  const Door* d2o = door_by_id(p, "door5-2");
  ASSERT_TRUE(d2o);
  EXPECT_NEAR(d2o->center_m.y(), 3.2, kTol);
  EXPECT_TRUE(d2o->closed);
  EXPECT_EQ(p.doors.size(), 5u);
  ASSERT_EQ(p.windows.size(), 2u);
  EXPECT_NEAR(p.windows[1].center_m.y(), -0.2, kTol);
}

nlohmann::json fixture() {
  return nlohmann::json::parse(read_text_file(data_path("s3d/scene_00000/annotation_3d.json")));
}

TEST(ImportS3d, MalformedAnnotationsAreRefusedWithTheElement) {
  expect_input_error([] { import_s3d_json("{\"junctions\": [", "a.json"); }, {"a.json", "malformed JSON"});
  expect_input_error([] { import_s3d_json("[]", "a.json"); }, {"a.json", "top level must be a JSON object"});
  {
    auto j = fixture();
    j.erase("planes");
    expect_input_error([&] { import_s3d_json(j.dump(), "a.json"); }, {"a.json", "missing required field \"planes\""});
  }
  {
    auto j = fixture();
    j["junctions"][3]["coordinate"] = {1.0, "x", 2.0};
    expect_input_error([&] { import_s3d_json(j.dump(), "a.json"); }, {"a.json: junctions[3].coordinate[1]", "must be a number"});
  }
  {
    auto j = fixture();
    j["planeLineMatrix"].erase(0);
    expect_input_error([&] { import_s3d_json(j.dump(), "a.json"); }, {"planeLineMatrix", "rows", "one per plane"});
  }
  {
    auto j = fixture();
    j["lineJunctionMatrix"][2].erase(0);
    expect_input_error([&] { import_s3d_json(j.dump(), "a.json"); }, {"lineJunctionMatrix[2]", "one per junction"});
  }
  {
    auto j = fixture();
    j["semantics"][1]["planeID"][0] = 999;
    expect_input_error([&] { import_s3d_json(j.dump(), "a.json"); }, {"semantics[1].planeID[0]", "999"});
  }
  {
    auto j = fixture();
    j["planes"][5]["normal"] = {0.0, 0.0, 0.0};
    expect_input_error([&] { import_s3d_json(j.dump(), "a.json"); }, {"planes[5]", "zero length"});
  }
}

TEST(ImportS3d, SkippedElementsAreReportedNotSilent) {
  auto j = fixture();
  // Tilt one wall plane of room A far from vertical: it is skipped with a note.
  j["planes"][2]["normal"] = {0.0, 0.3, 0.95};
  const ImportResult r = import_s3d_json(j.dump(), "a.json");
  ASSERT_FALSE(r.notes.empty());
  EXPECT_NE(r.notes[0].find("planes[2]"), std::string::npos);
  EXPECT_NE(r.notes[0].find("not vertical"), std::string::npos);
  EXPECT_EQ(r.plan.walls.size(), 8u);
}

}  // namespace
}  // namespace floorcast
