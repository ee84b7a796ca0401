// Coordinate systems through PROJ and the IndoorOSM schema (issue 23 item 4): a projected-CRS
// GeoJSON fixture and an IndoorOSM fixture import to the same plans as their WGS84 / Simple Indoor
// Tagging twins (data/make_fixtures.py), walls within 1 cm.
#include <gtest/gtest.h>

#include "floorcast/floorplans/import.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/floorplans/raster.hpp"
#include "import_test_util.hpp"

namespace floorcast {
namespace {

using test::data_path;
using test::expect_input_error;

/// Every wall of `a` has a wall of `b` with both ends within tol (either order) and the same
/// thickness and material, and the counts agree; likewise doors (centre, width) and rooms (count,
/// outer rings vertex by vertex).
void expect_same_plan(const FloorPlan& a, const FloorPlan& b, double tol) {
  ASSERT_EQ(a.walls.size(), b.walls.size());
  for (const Wall& w : a.walls) {
    const Wall* m = test::find_wall(b, w.a_m, w.b_m, tol);
    ASSERT_NE(m, nullptr) << "wall " << w.id << " (" << w.a_m.transpose() << ") - (" << w.b_m.transpose() << ") has no twin";
    EXPECT_NEAR(m->thickness_m, w.thickness_m, 1e-9);
    EXPECT_EQ(m->material, w.material);
  }
  ASSERT_EQ(a.doors.size(), b.doors.size());
  for (const Door& d : a.doors) {
    bool found = false;
    for (const Door& e : b.doors) found = found || ((e.center_m - d.center_m).norm() <= tol && std::abs(e.width_m - d.width_m) <= tol);
    EXPECT_TRUE(found) << "door " << d.id << " at " << d.center_m.transpose() << " has no twin";
  }
  ASSERT_EQ(a.rooms.size(), b.rooms.size());
  for (std::size_t i = 0; i < a.rooms.size(); ++i) {
    bool found = false;
    for (const Room& r : b.rooms) {
      if (r.polygon_m.size() != a.rooms[i].polygon_m.size()) continue;
      bool same = true;
      for (std::size_t k = 0; k < r.polygon_m.size() && same; ++k) same = (r.polygon_m[k] - a.rooms[i].polygon_m[k]).norm() <= tol;
      found = found || same;
    }
    EXPECT_TRUE(found) << "room " << a.rooms[i].id << " has no twin";
  }
}

// The office in WGS84 longitude/latitude and in UTM zone 32N (a crs member naming EPSG:32632,
// coordinates in metres, grid north 0.34 deg off true north, scale 0.9996): the same plan. Both
// are taken to longitude/latitude and onto the local plane about the same origin, so the UTM
// grid's scale and convergence do not show.
TEST(ImportTwins, ProjectedCrsGeojsonImportsLikeItsWgs84Twin) {
  ImportOptions o;
  o.level = "0";
  const ImportResult wgs = import_floor_plan(data_path("geojson/office_wgs84.geojson"), ImportFormat::kGeojson, o);
  const ImportResult utm = import_floor_plan(data_path("geojson/office_utm32n.geojson"), ImportFormat::kGeojson, o);
  EXPECT_NE(utm.level_description.find("UTM zone 32N"), std::string::npos) << utm.level_description;
  expect_same_plan(wgs.plan, utm.plan, 0.01);
  EXPECT_NEAR(free_floor_area_m2(wgs.plan), free_floor_area_m2(utm.plan), 0.05);
  // The design is 15 x 11 m, to the millimetre in both (the corridor's outer wall x = 0..15).
  EXPECT_NEAR(test::wall_lengths(utm.plan).back(), 15.0, 0.002);
  // --crs overrides the declaration (and says so); without either, metres are refused with the fix.
  o.crs = "EPSG:32632";
  const ImportResult given = import_floor_plan(data_path("geojson/office_utm32n.geojson"), ImportFormat::kGeojson, o);
  expect_same_plan(utm.plan, given.plan, 1e-6);
  o.crs = "EPSG:25832";  // ETRS89 / UTM 32N: same projection on GRS80, declared differently
  const ImportResult etrs = import_floor_plan(data_path("geojson/office_utm32n.geojson"), ImportFormat::kGeojson, o);
  expect_same_plan(utm.plan, etrs.plan, 0.01);
  bool noted = false;
  for (const std::string& n : etrs.notes) noted = noted || n.find("--crs \"EPSG:25832\" used instead") != std::string::npos;
  EXPECT_TRUE(noted);
  o.crs.reset();
  const std::string text = test::read_text(data_path("geojson/office_utm32n.geojson"));
  std::string undeclared = text;
  undeclared.replace(undeclared.find("\"crs\""), 5, "\"x\"");  // hide the member
  expect_input_error([&] { import_geojson_text(undeclared, "office.geojson", o); },
                     {"office.geojson", "look like metres", "--crs EPSG:NNNN"});
}

// IndoorOSM (buildingpart ways in type=level relations with shells, under a building relation)
// and its Simple Indoor Tagging twin: the same walls, doors and rooms on both levels. Level 1's
// hall is an indoor=area in the twin; only its kind differs ("hall" vs "area").
TEST(ImportTwins, IndoorOsmImportsLikeItsSimpleIndoorTaggingTwin) {
  for (const char* level : {"0", "1"}) {
    SCOPED_TRACE(level);
    ImportOptions o;
    o.level = level;
    const ImportResult ios = import_floor_plan(data_path("osm/indoorosm.osm"), ImportFormat::kOsm, o);
    const ImportResult sit = import_floor_plan(data_path("osm/indoorosm_sit_twin.osm"), ImportFormat::kOsm, o);
    expect_same_plan(sit.plan, ios.plan, 0.01);
    int stairs = 0, halls = 0, circulation = 0;
    for (const Room& r : ios.plan.rooms) {
      stairs += r.kind == "stairs";
      halls += r.kind == "hall";
      circulation += r.kind == "circulation";
    }
    EXPECT_EQ(stairs, 1);
    EXPECT_EQ(halls, std::string(level) == "1" ? 1 : 0);
    EXPECT_EQ(circulation, 1);  // the shell
    EXPECT_TRUE(ios.warnings.empty());
  }
  // Levels come from the relations: without --level the importer lists them.
  expect_input_error([] { import_floor_plan(data_path("osm/indoorosm.osm"), ImportFormat::kOsm); },
                     {"available levels: 0, 1"});
}

// A file in neither schema is refused with the tags it does carry.
TEST(ImportTwins, UnknownSchemaIsNamed) {
  const std::string xml =
      "<osm version=\"0.6\"><node id=\"1\" lat=\"47\" lon=\"8\"/><node id=\"2\" lat=\"47.0001\" lon=\"8\"/>"
      "<node id=\"3\" lat=\"47.0001\" lon=\"8.0001\"/><way id=\"5\"><nd ref=\"1\"/><nd ref=\"2\"/><nd ref=\"3\"/><nd ref=\"1\"/>"
      "<tag k=\"building:part\" v=\"yes\"/><tag k=\"building:levels\" v=\"3\"/></way></osm>";
  expect_input_error([&] { import_osm_xml(xml, "parts.osm"); },
                     {"parts.osm", "neither Simple Indoor Tagging", "nor IndoorOSM", "building:part=* (1)"});
}


// Walls drawn as polygons with their thickness, doors and windows as lines (no OSM tags): the
// rectangles become walls along their long axes as thick as they are, the T-shaped partition is
// traced into its two arms with measured thickness, and the openings land on their walls.
TEST(ImportTwins, WallPolygonsAndDoorLines) {
  const ImportResult r = import_floor_plan(data_path("geojson/wall_polygons.geojson"), ImportFormat::kGeojson);
  const FloorPlan& p = r.plan;
  Vec2 mn(1e9, 1e9);
  for (const Wall& w : p.walls) mn = mn.cwiseMin(w.a_m).cwiseMin(w.b_m);
  const Vec2 shift = Vec2(-0.15, 0.0) - mn;  // the design's lowest wall end: the south wall's (-0.15, 0)
  auto find = [&](Vec2 a, Vec2 b, double tol) { return test::find_wall(p, a - shift, b - shift, tol); };
  for (const auto& [a, b] : std::vector<std::pair<Vec2, Vec2>>{{{-0.15, 0}, {10.15, 0}}, {{-0.15, 5}, {10.15, 5}},
                                                                {{0, 0.15}, {0, 4.85}}, {{10, 0.15}, {10, 4.85}}}) {
    const Wall* w = find(a, b, 0.01);
    ASSERT_NE(w, nullptr) << a.transpose() << " - " << b.transpose();
    EXPECT_NEAR(w->thickness_m, 0.30, 1e-3);
  }
  // The traced partition: an arm along x = 6 and a return along y = 2.5, 0.15 m thick (within
  // 1.5 cells of the 2 cm raster: the short return's cross-sections near the junction read 3 cm
  // wide), its axis within 2 cm.
  int arms = 0;
  for (const Wall& w : p.walls) {
    if (w.id.rfind("wallpolygon-", 0) != 0 || std::abs(w.thickness_m - 0.30) < 1e-3) continue;
    const Vec2 a = w.a_m + shift, b = w.b_m + shift;
    EXPECT_NEAR(w.thickness_m, 0.15, 0.031) << w.id;
    const bool along_x6 = std::abs(a.x() - 6.0) < 0.02 && std::abs(b.x() - 6.0) < 0.02;
    const bool along_y25 = std::abs(a.y() - 2.5) < 0.02 && std::abs(b.y() - 2.5) < 0.02;
    EXPECT_TRUE(along_x6 || along_y25) << w.id << ": " << a.transpose() << " - " << b.transpose();
    ++arms;
  }
  EXPECT_GE(arms, 2);
  ASSERT_EQ(p.doors.size(), 2u);
  for (const Door& d : p.doors) EXPECT_NEAR(d.width_m, 0.9, 0.01);
  ASSERT_EQ(p.windows.size(), 1u);
  EXPECT_NEAR(p.windows[0].width_m, 1.5, 0.01);
  EXPECT_NEAR((p.windows[0].center_m + shift - Vec2(8.25, 5.0)).norm(), 0.0, 0.02);
  // Free floor: A and B inside the walls' faces, less the partition's return.
  EXPECT_NEAR(free_floor_area_m2(p), 5.775 * 4.7 + 3.775 * 4.7 - 1.425 * 0.15, 0.6);
  EXPECT_FALSE(r.faithfulness.applicable);  // no spaces mapped
}

}  // namespace
}  // namespace floorcast
