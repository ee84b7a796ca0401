// IMDF importer: a one-level venue with messy units, and a two-building venue for level selection.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "floorcast/floorplans/import.hpp"
#include "floorcast/floorplans/io.hpp"
#include "import_test_util.hpp"

namespace floorcast {
namespace {

using test::data_path;
using test::distance_to_walls;
using test::door_by_id;
using test::expect_input_error;
using test::find_wall;

// The fixtures are laid out in local metres about the level centroid (make_fixtures.py), so the
// projected plan must reproduce those coordinates; 2 mm covers the 10-decimal degree rounding
// and the fixture writer's first-order inverse projection.
constexpr double kGeoTol = 0.002;

TEST(ImportImdf, UnitBoundariesBecomeWallsAndOpeningsDoors) {
  const ImportResult r = import_floor_plan(data_path("imdf/simple"), ImportFormat::kImdf);
  const FloorPlan& p = r.plan;
  EXPECT_EQ(p.name, "simple Ground");
  EXPECT_EQ(p.level, 0);
  EXPECT_NE(r.level_description.find("\"Ground\""), std::string::npos);
  ASSERT_EQ(p.walls.size(), 6u);
  EXPECT_NE(find_wall(p, {-10, 5}, {10, 5}, kGeoTol), nullptr);    // rooms' north edges, touching
  EXPECT_NE(find_wall(p, {-10, -5}, {10, -5}, kGeoTol), nullptr);  // walkways' south edges
  EXPECT_NE(find_wall(p, {-10, -5}, {-10, 5}, kGeoTol), nullptr);
  EXPECT_NE(find_wall(p, {10, -5}, {10, 5}, kGeoTol), nullptr);
  EXPECT_NE(find_wall(p, {-10, 0}, {10, 0}, kGeoTol), nullptr);    // rooms | walkways, drawn twice
  // Room A | room B, drawn twice, once with its corner 5 mm off: the merged wall lies between.
  EXPECT_NE(find_wall(p, {-2, 0}, {-2, 5}, 0.005), nullptr);
  // The two walkway units' shared boundary is open.
  EXPECT_GT(distance_to_walls(p, {0, -2.5}), 2.0);
  // Room B's corner was drawn 5 mm off: the y = 0 wall is still straight.
  const Wall* y0 = find_wall(p, {-10, 0}, {10, 0}, kGeoTol);
  ASSERT_TRUE(y0);
  EXPECT_NEAR(y0->a_m.y(), 0.0, kGeoTol);
  EXPECT_NEAR(y0->b_m.y(), 0.0, kGeoTol);
  // Projection accuracy: the 20 m edges measure 20 m.
  EXPECT_NEAR(find_wall(p, {-10, 5}, {10, 5}, kGeoTol)->length_m(), 20.0, kGeoTol);

  ASSERT_EQ(p.doors.size(), 3u);
  const Door* o1 = door_by_id(p, "opening-o1");
  const Door* o2 = door_by_id(p, "opening-o2");
  const Door* o3 = door_by_id(p, "opening-o3");
  ASSERT_TRUE(o1 && o2 && o3);
  EXPECT_EQ(o1->wall_id, y0->id);
  EXPECT_EQ(o2->wall_id, y0->id);
  EXPECT_EQ(o3->wall_id, find_wall(p, {-2, 0}, {-2, 5}, 0.005)->id);
  EXPECT_NEAR((o1->center_m - Vec2(-6.5, 0)).norm(), 0.0, kGeoTol);
  EXPECT_NEAR(o1->width_m, 1.0, kGeoTol);
  EXPECT_NEAR(o2->width_m, 1.5, kGeoTol);
  EXPECT_NEAR((o3->center_m - Vec2(-2, 2.45)).norm(), 0.0, 0.005);
  EXPECT_NEAR(o3->width_m, 0.9, kGeoTol);
  // The opening on the open walkway boundary is reported, not silently lost.
  ASSERT_EQ(r.notes.size(), 1u);
  EXPECT_NE(r.notes[0].find("\"o4-open\""), std::string::npos);
  EXPECT_NE(r.notes[0].find("open boundary"), std::string::npos);
}

TEST(ImportImdf, OpenCategoriesAreConfigurable) {
  ImportOptions o;
  o.imdf_open_unit_categories.clear();  // every unit boundary is a wall
  const ImportResult r = import_floor_plan(data_path("imdf/simple"), ImportFormat::kImdf, o);
  EXPECT_EQ(r.plan.walls.size(), 7u);
  EXPECT_LT(distance_to_walls(r.plan, {0, -2.5}), kGeoTol);
  EXPECT_EQ(r.plan.doors.size(), 4u);
}

TEST(ImportImdf, LevelSelectionByOrdinalOrIdAndClearRefusals) {
  const std::string campus = data_path("imdf/campus");
  expect_input_error([&] { import_floor_plan(campus, ImportFormat::kImdf); },
                     {"3 levels", "--level", "ordinal 0 (id \"b1-level-0\", \"B1 Ground\", building \"b1\")",
                      "ordinal 0 (id \"b2-level-0\", \"B2 Ground\", building \"b2\")",
                      "ordinal 1 (id \"b1-level-1\", \"B1 First\", building \"b1\")"});
  ImportOptions o;
  o.level = "0";
  expect_input_error([&] { import_floor_plan(campus, ImportFormat::kImdf, o); },
                     {"ordinal 0 is ambiguous", "b1-level-0", "b2-level-0", "pass --building NAME_OR_ID or --level LEVEL_ID"});
  o.level = "7";
  expect_input_error([&] { import_floor_plan(campus, ImportFormat::kImdf, o); }, {"no level with ordinal 7", "available levels"});
  o.level = "ground";
  expect_input_error([&] { import_floor_plan(campus, ImportFormat::kImdf, o); }, {"neither a level ordinal", "b1-level-1"});

  o.level = "1";
  const ImportResult first = import_floor_plan(campus, ImportFormat::kImdf, o);
  EXPECT_EQ(first.plan.level, 1);
  EXPECT_EQ(first.plan.walls.size(), 5u);
  ASSERT_EQ(first.plan.doors.size(), 1u);
  // Lengths are metric whatever the origin: the building is 20 x 10 m, the partition 10 m.
  const std::vector<double> lengths = test::wall_lengths(first.plan);
  const std::vector<double> want = {10, 10, 10, 20, 20};
  for (std::size_t i = 0; i < want.size(); ++i) EXPECT_NEAR(lengths[i], want[i], kGeoTol);

  o.level = "b2-level-0";
  const ImportResult shop = import_floor_plan(campus, ImportFormat::kImdf, o);
  EXPECT_EQ(shop.plan.level, 0);
  EXPECT_EQ(shop.plan.walls.size(), 4u);
  EXPECT_NE(shop.level_description.find("b2-level-0"), std::string::npos);
  // Origin = this level's centroid: the 10 x 8 m shop is centred on (0, 0).
  EXPECT_NE(find_wall(shop.plan, {-5, -4}, {5, -4}, kGeoTol), nullptr);
}

nlohmann::json read_json(const std::string& rel) { return nlohmann::json::parse(read_text_file(data_path(rel))); }

TEST(ImportImdf, BadFeaturesAreNamedByFileIndexAndId) {
  const std::string level = read_text_file(data_path("imdf/simple/level.geojson"));
  const std::string unit = read_text_file(data_path("imdf/simple/unit.geojson"));
  const std::string opening = read_text_file(data_path("imdf/simple/opening.geojson"));
  {
    auto u = read_json("imdf/simple/unit.geojson");
    u["features"][1]["properties"].erase("level_id");
    expect_input_error([&] { import_imdf_texts(level, u.dump(), opening, "venue"); },
                       {"venue/unit.geojson: features[1] (id \"room-b\")", "missing properties.level_id"});
  }
  {
    auto u = read_json("imdf/simple/unit.geojson");
    u["features"][2]["geometry"]["coordinates"][0][1][1] = 95.0;
    expect_input_error([&] { import_imdf_texts(level, u.dump(), opening, "venue"); },
                       {"features[2] (id \"walk-1\")", ", 95]", "not a longitude/latitude of WGS 84"});
  }
  {
    auto u = read_json("imdf/simple/unit.geojson");
    u["features"][0]["geometry"]["type"] = "Point";
    expect_input_error([&] { import_imdf_texts(level, u.dump(), opening, "venue"); },
                       {"features[0] (id \"room-a\")", "Polygon or MultiPolygon"});
  }
  {
    auto op = read_json("imdf/simple/opening.geojson");
    op["features"][0]["geometry"]["coordinates"] = nlohmann::json::array({op["features"][0]["geometry"]["coordinates"][0]});
    expect_input_error([&] { import_imdf_texts(level, unit, op.dump(), "venue"); },
                       {"venue/opening.geojson: features[0] (id \"o1\")", "at least 2 positions"});
  }
  {
    auto l = read_json("imdf/simple/level.geojson");
    l["features"][0]["properties"]["ordinal"] = "zero";
    expect_input_error([&] { import_imdf_texts(l.dump(), unit, opening, "venue"); },
                       {"venue/level.geojson: features[0]", "ordinal must be an integer"});
  }
  expect_input_error([&] { import_imdf_texts(level, "{\"type\": \"Feature\"}", opening, "venue"); },
                     {"venue/unit.geojson", "FeatureCollection"});
  expect_input_error([&] { import_imdf_texts(level, "{", opening, "venue"); }, {"venue/unit.geojson", "malformed JSON"});
  expect_input_error([&] { import_floor_plan(data_path("imdf/simple/unit.geojson"), ImportFormat::kImdf); },
                     {"expects a folder"});
  // Without opening.geojson: no doors, and a note says so.
  const ImportResult r = import_imdf_texts(level, unit, "", "venue");
  EXPECT_TRUE(r.plan.doors.empty());
}

}  // namespace
}  // namespace floorcast
