// PALMS CSV importer: known answers on a messy fixture, error messages.
#include <gtest/gtest.h>

#include "floorcast/floorplans/import.hpp"
#include "floorcast/floorplans/io.hpp"
#include "import_test_util.hpp"

namespace floorcast {
namespace {

using test::data_path;
using test::expect_input_error;
using test::find_wall;

TEST(ImportCsv, MessyTwoRoomsCleanUpToSixWalls) {
  const ImportResult r = import_floor_plan(data_path("csv/two_rooms_messy.csv"), ImportFormat::kCsv);
  const FloorPlan& p = r.plan;
  EXPECT_EQ(p.name, "two_rooms_messy");
  ASSERT_EQ(p.walls.size(), 6u);
  const double tol = 1e-9;
  EXPECT_NE(find_wall(p, {0, 0}, {8, 0}, tol), nullptr);
  EXPECT_NE(find_wall(p, {8, 0}, {8, 5}, tol), nullptr);  // the 7 mm overshoot snapped away
  EXPECT_NE(find_wall(p, {0, 5}, {8, 5}, tol), nullptr);  // two pieces + a duplicate
  EXPECT_NE(find_wall(p, {0, 0}, {0, 5}, tol), nullptr);
  EXPECT_NE(find_wall(p, {4, 0}, {4, 2}, tol), nullptr);
  EXPECT_NE(find_wall(p, {4, 2.9}, {4, 5}, tol), nullptr);  // the door gap stays a gap
  for (const Wall& w : p.walls) EXPECT_DOUBLE_EQ(w.thickness_m, 0.10);
  // Ids name the first CSV line that drew each wall.
  EXPECT_EQ(find_wall(p, {0, 0}, {8, 0}, tol)->id, "l4");
  EXPECT_EQ(find_wall(p, {4, 2.9}, {4, 5}, tol)->id, "l10");
  EXPECT_EQ(r.cleanup.input_walls, 12);
  EXPECT_EQ(r.cleanup.dropped_degenerate_walls, 1);
  EXPECT_EQ(r.cleanup.walls_merged_away, 5);
  EXPECT_NEAR(r.cleanup.duplicate_length_m, 4.0 + 5.0 + 4.0 + 2.1, 0.02);
  ASSERT_EQ(r.source_counts.size(), 1u);
  EXPECT_EQ(r.source_counts[0], (std::pair<std::string, int>{"segments", 12}));
}

TEST(ImportCsv, OptionsSetThicknessLevelAndName) {
  ImportOptions o;
  o.wall_thickness_m = 0.25;
  o.level = "3";
  o.name = "custom";
  const ImportResult r = import_csv_text("0,0,4,0\n4,0,4,3\n", "mem.csv", o);
  EXPECT_EQ(r.plan.level, 3);
  EXPECT_EQ(r.plan.name, "custom");
  EXPECT_DOUBLE_EQ(r.plan.walls[0].thickness_m, 0.25);
  o.level = "first";
  expect_input_error([&] { import_csv_text("0,0,4,0\n", "mem.csv", o); }, {"mem.csv", "--level \"first\"", "integer"});
  o.level.reset();
  o.wall_thickness_m = -1.0;
  expect_input_error([&] { import_csv_text("0,0,4,0\n", "mem.csv", o); }, {"mem.csv", "thickness"});
}

TEST(ImportCsv, BadLinesNameFileAndLineNumber) {
  expect_input_error([] { import_floor_plan(data_path("csv/bad_line.csv"), ImportFormat::kCsv); },
                     {"bad_line.csv:3:", "y2 is not a finite number", "\"x\""});
  expect_input_error([] { import_csv_text("0,0,1,0\n1,2,3\n", "m.csv"); }, {"m.csv:2:", "expected 4 comma-separated numbers", "got 3"});
  expect_input_error([] { import_csv_text("0,0,1,0,5\n", "m.csv"); }, {"m.csv:1:", "got 5"});
  expect_input_error([] { import_csv_text("0,0,1,\n", "m.csv"); }, {"m.csv:1:", "y2 is not a finite number"});
  expect_input_error([] { import_csv_text("0,nan,1,0\n", "m.csv"); }, {"m.csv:1:", "y1 is not a finite number"});
  expect_input_error([] { import_csv_text("0,0,1e999,0\n", "m.csv"); }, {"m.csv:1:", "x2"});
  expect_input_error([] { import_csv_text("# only comments\n\n", "m.csv"); }, {"m.csv", "no wall segments"});
  expect_input_error([] { import_csv_text("0,0,0,0\n", "m.csv"); }, {"m.csv", "no walls left"});
  // A 200 km wall: the unit check speaks first (millimetres?); with the unit given, validation.
  expect_input_error([] { import_csv_text("0,0,2e5,0\n", "m.csv"); }, {"m.csv", "no building level is that large", "--units"});
  ImportOptions metres;
  metres.units = "m";
  expect_input_error([&] { import_csv_text("0,0,2e5,0\n", "m.csv", metres); }, {"m.csv", "walls[0]", "absurd"});
  expect_input_error([] { import_floor_plan(data_path("csv/missing.csv"), ImportFormat::kCsv); }, {"missing.csv"});
}

TEST(ImportCsv, ToleratesWhitespaceCommentsAndCrLf) {
  const ImportResult r = import_csv_text("  # header\r\n 0 , 0 , 5 , 0 # south\r\n\r\n5,0,5,4\r\n", "m.csv");
  EXPECT_EQ(r.plan.walls.size(), 2u);
  EXPECT_NE(find_wall(r.plan, {0, 0}, {5, 0}, 1e-12), nullptr);
}

}  // namespace
}  // namespace floorcast
