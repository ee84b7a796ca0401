// OSM Simple Indoor Tagging importer on a three-level building (see data/make_fixtures.py).
#include <gtest/gtest.h>

#include "floorcast/floorplans/import.hpp"
#include "floorcast/floorplans/io.hpp"
#include "import_test_util.hpp"

namespace floorcast {
namespace {

using test::data_path;
using test::expect_input_error;

constexpr double kGeoTol = 0.002;

ImportResult import_level(const std::string& level) {
  ImportOptions o;
  o.level = level;
  return import_floor_plan(data_path("osm/building.osm"), ImportFormat::kOsm, o);
}

/// The importer centres the plan on its nodes' mean; the fixture's design frame has its
/// south-west corner at (-3, 0) (levels 0 and 1) - shift walls back into it.
FloorPlan in_design_frame(FloorPlan p, Vec2 design_min) {
  Vec2 mn(1e9, 1e9);
  for (const Wall& w : p.walls) mn = mn.cwiseMin(w.a_m).cwiseMin(w.b_m);
  const Vec2 shift = design_min - mn;
  for (Wall& w : p.walls) {
    w.a_m += shift;
    w.b_m += shift;
  }
  for (Door& d : p.doors) d.center_m += shift;
  return p;
}

TEST(ImportOsm, GroundLevelFollowsSimpleIndoorTagging) {
  const ImportResult r = import_level("0");
  EXPECT_EQ(r.plan.level, 0);
  EXPECT_EQ(r.level_description, "level 0");
  EXPECT_EQ(r.plan.name, "building level 0");
  const FloorPlan p = in_design_frame(r.plan, {-3, 0});
  // Rooms and corridors are walled, the corridor split and the corridor/area border are open,
  // the area's outline is a wall only where it borders unmapped space (free space is the union of
  // the spaces: its east side and its south and north sides beyond the lift), the indoor=wall way
  // and the lift (level range -1-1) are walls.
  ASSERT_EQ(p.walls.size(), 12u);
  const std::vector<double> lengths = test::wall_lengths(p);
  const std::vector<double> want = {2, 2, 2, 2, 4, 4, 6, 6, 6, 12, 19, 19};
  for (std::size_t i = 0; i < want.size(); ++i) EXPECT_NEAR(lengths[i], want[i], 0.01) << i;
  // R2's corner drawn 8 mm off tilts the merged x = 12 line by a few millimetres: 1 cm.
  auto wall_at = [&](Vec2 q) { return test::distance_to_walls(p, q) < 0.01; };
  EXPECT_TRUE(wall_at({-3, 3}));     // stairs (level 0;1)
  EXPECT_TRUE(wall_at({6, 1}));      // R1 | R2, drawn by both rooms
  EXPECT_FALSE(wall_at({6, 5.5}));   // C1 | C2: corridor split, open
  EXPECT_TRUE(wall_at({12, 2}));     // R2 east (its corner drawn 8 mm off)
  EXPECT_FALSE(wall_at({12, 5}));    // C2 | hall (indoor=area): open
  EXPECT_TRUE(wall_at({16, 3}));     // hall outline toward unmapped space: a wall
  EXPECT_TRUE(wall_at({14, 0}));
  EXPECT_TRUE(wall_at({15, 6}));
  EXPECT_TRUE(wall_at({14, 3}));     // indoor=wall way inside the hall
  EXPECT_TRUE(wall_at({12, 7}));     // lift on level range -1-1
  EXPECT_TRUE(wall_at({13, 6}));     // lift south = hall north: a wall (the lift is a room)
  const Wall* south = test::find_wall(p, {-3, 0}, {16, 0}, 0.01);
  ASSERT_NE(south, nullptr);
  EXPECT_NEAR(south->length_m(), 19.0, kGeoTol);  // projection accuracy

  ASSERT_EQ(p.doors.size(), 4u);
  auto door = [&](long long node) { return test::door_by_id(p, "node" + std::to_string(node)); };
  // Node ids as written by make_fixtures.py: 2 (2,0) door=yes; 5 (6,2) width=1.2;
  // 7 (3,4) width=0.9; 9 (9,4) width="90 cm"; 13 (6,5) door=no on the corridor split.
  ASSERT_TRUE(door(2) && door(5) && door(7) && door(9));
  EXPECT_NEAR((door(2)->center_m - Vec2(2, 0)).norm(), 0.0, kGeoTol);
  EXPECT_NEAR(door(2)->width_m, 0.9, 1e-12);  // default width
  EXPECT_NEAR(door(5)->width_m, 1.2, 1e-12);
  EXPECT_NEAR(door(9)->width_m, 0.9, 1e-12);
  EXPECT_NEAR((door(7)->center_m - Vec2(3, 4)).norm(), 0.0, kGeoTol);
  EXPECT_FALSE(door(7)->closed);
  // Notes: the stairs and the lift have no door in the source; the hall's outline was walled
  // toward unmapped space; the door=no node on the corridor split is on no wall.
  ASSERT_EQ(r.notes.size(), 3u);
  EXPECT_NE(r.notes[0].find("2 of 4 rooms have no opening"), std::string::npos) << r.notes[0];
  EXPECT_NE(r.notes[1].find("borders unmapped space"), std::string::npos) << r.notes[1];
  EXPECT_NE(r.notes[2].find("node 13"), std::string::npos);
  EXPECT_NE(r.notes[2].find("open boundary"), std::string::npos);
}

TEST(ImportOsm, OtherLevels) {
  const ImportResult first = import_level("1");
  EXPECT_EQ(first.plan.level, 1);
  const FloorPlan p1 = in_design_frame(first.plan, {-3, 0});
  // Stairs (0;1), R3, lift (-1-1): x=-3, y=0, y=6, x=0, x=12 (R3 east + lift west), x=14, y=8.
  EXPECT_EQ(p1.walls.size(), 7u);
  ASSERT_EQ(p1.doors.size(), 1u);
  EXPECT_NEAR((p1.doors[0].center_m - Vec2(5, 0)).norm(), 0.0, kGeoTol);

  const ImportResult basement = import_level("-1");
  EXPECT_EQ(basement.plan.level, -1);
  EXPECT_EQ(basement.plan.walls.size(), 8u);  // basement room + lift
  EXPECT_TRUE(basement.plan.doors.empty());
}

TEST(ImportOsm, LevelSelectionIsExplicit) {
  expect_input_error([] { import_floor_plan(data_path("osm/building.osm"), ImportFormat::kOsm); },
                     {"building.osm", "3 levels", "--level", "available levels: -1, 0, 1"});
  expect_input_error([] { import_level("2"); }, {"no indoor features on level 2", "-1, 0, 1"});
  // A range includes the levels between its ends: only the lift (-1-1) is on level 0.5.
  const ImportResult half = import_level("0.5");
  EXPECT_EQ(half.plan.walls.size(), 4u);
  EXPECT_EQ(half.plan.level, 0);
  bool noted = false;
  for (const std::string& n : half.notes) noted = noted || n.find("not an integer") != std::string::npos;
  EXPECT_TRUE(noted);
  expect_input_error([] { import_level("ground"); }, {"--level \"ground\"", "one level value"});
  expect_input_error([] { import_level("0;1"); }, {"one level value"});
}

const char* kHead = "<?xml version='1.0'?><osm version='0.6'>";

TEST(ImportOsm, SingleLevelFilesNeedNoLevelAndUntaggedMeansZero) {
  const std::string xml = std::string(kHead) +
                          "<node id='1' lat='47.0' lon='8.0'/><node id='2' lat='47.0' lon='8.0001'/>"
                          "<node id='3' lat='47.0001' lon='8.0001'/><node id='4' lat='47.0001' lon='8.0'/>"
                          "<way id='10'><nd ref='1'/><nd ref='2'/><nd ref='3'/><nd ref='4'/><nd ref='1'/>"
                          "<tag k='indoor' v='room'/></way></osm>";
  const ImportResult r = import_osm_xml(xml, "one.osm");
  EXPECT_EQ(r.plan.level, 0);
  EXPECT_EQ(r.plan.walls.size(), 4u);
  // 0.0001 deg at 47 deg: N cos(phi) dlambda = 7.6056 m east-west, M dphi = 11.1171 m north-south.
  const std::vector<double> lengths = test::wall_lengths(r.plan);
  EXPECT_NEAR(lengths[0], 7.6056, 0.002);
  EXPECT_NEAR(lengths[3], 11.1171, 0.002);
}

TEST(ImportOsm, BrokenInputIsRefusedWithTheElement) {
  expect_input_error([] { import_osm_xml("<osm><node id='1'", "b.osm"); }, {"b.osm", "malformed XML"});
  expect_input_error([] { import_osm_xml("<html/>", "b.osm"); }, {"b.osm", "no <osm> root"});
  expect_input_error([] { import_osm_xml(std::string(kHead) + "<node id='1' lat='99' lon='8'/></osm>", "b.osm"); },
                     {"node 1", "lat/lon"});
  expect_input_error([] { import_osm_xml(std::string(kHead) + "<node id='1' lat='47' lon='8'/></osm>", "b.osm"); },
                     {"b.osm", "neither Simple Indoor Tagging", "nor IndoorOSM"});
  const std::string missing = std::string(kHead) +
                              "<node id='1' lat='47' lon='8'/><node id='2' lat='47' lon='8.0001'/>"
                              "<way id='7'><nd ref='1'/><nd ref='2'/><nd ref='3'/><nd ref='1'/><tag k='indoor' v='room'/></way></osm>";
  expect_input_error([&] { import_osm_xml(missing, "b.osm"); }, {"way 7", "node 3", "not in the file"});
  const std::string open_room = std::string(kHead) +
                                "<node id='1' lat='47' lon='8'/><node id='2' lat='47' lon='8.0001'/><node id='3' lat='47.0001' lon='8'/>"
                                "<way id='8'><nd ref='1'/><nd ref='2'/><nd ref='3'/><tag k='indoor' v='room'/></way></osm>";
  // An unclosed room is skipped with a note; with nothing else on the level, that is the error.
  expect_input_error([&] { import_osm_xml(open_room, "b.osm"); }, {"no usable indoor features", "way 8", "not closed"});
  const std::string bad_level = std::string(kHead) +
                                "<node id='1' lat='47' lon='8'/><node id='2' lat='47' lon='8.0001'/>"
                                "<way id='9'><nd ref='1'/><nd ref='2'/><tag k='indoor' v='wall'/><tag k='level' v='first'/></way></osm>";
  expect_input_error([&] { import_osm_xml(bad_level, "b.osm"); }, {"way 9", "level=\"first\""});
  // Deleted elements (JOSM action="delete") are ignored.
  const std::string deleted = std::string(kHead) +
                              "<node id='1' lat='47' lon='8'/><node id='2' lat='47' lon='8.0001'/>"
                              "<node id='3' lat='47.0001' lon='8.0001'/><node id='4' lat='47.0001' lon='8'/>"
                              "<way id='9'><nd ref='1'/><nd ref='2'/><nd ref='3'/><nd ref='4'/><nd ref='1'/><tag k='indoor' v='room'/></way>"
                              "<way id='11' action='delete'><nd ref='1'/><nd ref='5'/><tag k='indoor' v='wall'/></way></osm>";
  EXPECT_EQ(import_osm_xml(deleted, "b.osm").plan.walls.size(), 4u);
}

TEST(ImportOsm, MultipolygonRoomsWithHoles) {
  // A 10 x 10 m room (outer) with a 2 x 2 m column hole (inner), as a multipolygon relation.
  auto node = [](int id, double x, double y) {
    const double lat = 47.0 + y / 111195.0, lon = 8.0 + x / 75820.0;
    return "<node id='" + std::to_string(id) + "' lat='" + std::to_string(lat) + "' lon='" + std::to_string(lon) + "'/>";
  };
  std::string xml = kHead;
  xml += node(1, 0, 0) + node(2, 10, 0) + node(3, 10, 10) + node(4, 0, 10);
  xml += node(5, 4, 4) + node(6, 6, 4) + node(7, 6, 6) + node(8, 4, 6);
  xml += "<way id='20'><nd ref='1'/><nd ref='2'/><nd ref='3'/><nd ref='4'/><nd ref='1'/></way>";
  xml += "<way id='21'><nd ref='5'/><nd ref='6'/><nd ref='7'/><nd ref='8'/><nd ref='5'/></way>";
  xml += "<relation id='30'><member type='way' ref='20' role='outer'/><member type='way' ref='21' role='inner'/>"
         "<tag k='type' v='multipolygon'/><tag k='indoor' v='room'/><tag k='level' v='2'/></relation></osm>";
  const ImportResult r = import_osm_xml(xml, "mp.osm");
  EXPECT_EQ(r.plan.level, 2);
  EXPECT_EQ(r.plan.walls.size(), 8u);
}

}  // namespace
}  // namespace floorcast
