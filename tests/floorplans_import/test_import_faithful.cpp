// Imports that exit 0 give what the source says (issue 23): free space is the union of the mapped
// spaces (corridors and halls unwalled toward unmapped space are walled there; enclosed regions no
// space covers are "unmapped", not floor), every import reports the faithfulness check, a level
// without spaces and a plan without a room-sized free region are refused. Fixtures written by
// data/make_fixtures.py for each defect.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "floorcast/floorplans/faithfulness.hpp"
#include "floorcast/floorplans/import.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/floorplans/raster.hpp"
#include "floorcast/floorplans/rooms.hpp"
#include "import_test_util.hpp"

namespace floorcast {
namespace {

using test::data_path;
using test::expect_input_error;

ImportResult import_osm(const std::string& file, const std::string& level = "0", ImportOptions o = {}) {
  o.level = level;
  return import_floor_plan(data_path("osm/" + file), ImportFormat::kOsm, o);
}

/// Shift of the imported plan's frame to the fixture's design frame, whose walls' lowest x and y
/// are `design_min`.
Vec2 design_shift(const FloorPlan& p, Vec2 design_min) {
  Vec2 mn(1e9, 1e9);
  for (const Wall& w : p.walls) mn = mn.cwiseMin(w.a_m).cwiseMin(w.b_m);
  return design_min - mn;
}

/// Is design point q free floor of the plan (valid area on a 5 cm grid)?
struct FloorProbe {
  FloorProbe(const FloorPlan& plan, Vec2 design_min) : shift(design_shift(plan, design_min)) {
    grid = grid_for_plan(plan, 0.05, 1.0);
    valid = valid_area_mask(plan, grid);
  }
  bool floor(Vec2 q) const {
    int r = 0, c = 0;
    return grid.world_to_cell(q - shift, r, c) && valid.at<std::uint8_t>(r, c) != 0;
  }
  Vec2 shift;
  GridSpec grid;
  cv::Mat valid;
};

const KindFaithfulness* kind(const FaithfulnessReport& f, const std::string& name) {
  for (const KindFaithfulness& k : f.kinds) {
    if (k.kind == name) return &k;
  }
  return nullptr;
}

bool has_note(const ImportResult& r, std::initializer_list<std::string> fragments) {
  for (const std::string& n : r.notes) {
    bool ok = true;
    for (const std::string& f : fragments) ok = ok && n.find(f) != std::string::npos;
    if (ok) return true;
  }
  return false;
}

int repair(const ImportResult& r, const std::string& name) {
  for (const auto& [what, n] : r.repairs) {
    if (what == name) return n;
  }
  return 0;
}

double unmapped_area(const FloorPlan& p) {
  double a = 0.0;
  for (const Room& r : p.rooms) a += is_unmapped_kind(r.kind) ? room_area_m2(r) : 0.0;
  return a;
}

/// The fixture's free floor against its mapped spaces: the union's area less the wall bodies
/// lying in it (every wall 0.10 m thick; an outline wall has half its body inside).
void expect_free_area_near(const ImportResult& r, double mapped_m2) {
  const FaithfulnessReport& f = r.faithfulness;
  ASSERT_TRUE(f.applicable);
  EXPECT_NEAR(f.mapped_area_m2, mapped_m2, 0.02 * mapped_m2);
  EXPECT_GE(f.free_share, 0.95) << faithfulness_summary(f);
  // Independently of the report: free floor (5 cm) within 5% of the mapped area less walls.
  const double free = free_floor_area_m2(r.plan);
  EXPECT_NEAR(free, f.mapped_area_m2 - f.wall_area_m2, 0.05 * mapped_m2) << faithfulness_summary(f);
  EXPECT_LT(f.free_outside_mapped_m2, 0.01 * mapped_m2);
}

// A foyer (indoor=area) at the building edge and a split corridor bounded by rooms on one side:
// before issue 23 the outside flooded in through the foyer's unwalled outline and took the whole
// corridor network with it. Now the foyer and the corridors are free floor.
TEST(ImportFaithful, CorridorsAndFoyerUnwalledTowardNothingAreFreeFloor) {
  const ImportResult r = import_osm("corridors_open.osm");
  expect_free_area_near(r, 240.0);
  const FloorProbe probe(r.plan, {0, 0});
  EXPECT_TRUE(probe.floor({2, 6.5}));    // foyer
  EXPECT_TRUE(probe.floor({8, 6.5}));    // corridor C1
  EXPECT_TRUE(probe.floor({18, 6.5}));   // corridor C2
  EXPECT_TRUE(probe.floor({6, 2.5}));    // room R1
  EXPECT_FALSE(probe.floor({18, 10}));   // unmapped, outside
  EXPECT_FALSE(probe.floor({-1, 6.5}));  // outside
  for (const char* k : {"corridor", "area", "room"}) {
    ASSERT_NE(kind(r.faithfulness, k), nullptr) << k;
    EXPECT_GE(kind(r.faithfulness, k)->free_share, 0.95) << k;
  }
  // The foyer's outline toward the outside is a wall now, with the entrance door in it.
  EXPECT_LT(test::distance_to_walls(r.plan, Vec2(0, 3) - probe.shift), 0.01);
  bool entrance = false;
  for (const Door& d : r.plan.doors) entrance = entrance || (d.center_m + probe.shift - Vec2(0, 6.5)).norm() < 0.05;
  EXPECT_TRUE(entrance);
  // Corridor pieces and the foyer stay open to each other.
  EXPECT_GT(test::distance_to_walls(r.plan, Vec2(4, 6.5) - probe.shift), 0.5);
  EXPECT_GT(test::distance_to_walls(r.plan, Vec2(12, 6.5) - probe.shift), 0.5);
  EXPECT_TRUE(r.warnings.empty());
  EXPECT_EQ(r.faithfulness.sealed_spaces, 0);
  EXPECT_EQ(r.faithfulness.unreachable_spaces, 0);
}

// A courtyard enclosed by a corridor ring, mapped as no space: not floor, labelled "unmapped"; the
// --unmapped-as-floor flag keeps the former behaviour, and the report says how much it adds.
TEST(ImportFaithful, UnmappedCourtyardIsNotFloor) {
  const ImportResult r = import_osm("courtyard.osm");
  expect_free_area_near(r, 360.0);
  const FloorProbe probe(r.plan, {0, 0});
  EXPECT_FALSE(probe.floor({12, 9}));  // courtyard
  EXPECT_TRUE(probe.floor({12, 5}));   // corridor ring
  EXPECT_TRUE(probe.floor({2, 4}));    // a room
  // The courtyard (12 x 6 m) is one "unmapped" region reaching into the walls around it.
  EXPECT_EQ(r.faithfulness.unmapped_regions, 1);
  EXPECT_NEAR(unmapped_area(r.plan), 72.0, 3.0);
  EXPECT_NEAR(r.faithfulness.unmapped_area_m2, 72.0, 3.0);
  EXPECT_TRUE(r.warnings.empty());
  // The same plan through save/load keeps it.
  const FloorPlan reloaded = parse_floor_plan_json(floor_plan_to_json(r.plan), "courtyard");
  EXPECT_NEAR(free_floor_area_m2(reloaded), free_floor_area_m2(r.plan), 1e-9);

  ImportOptions o;
  o.unmapped_is_floor = true;
  const ImportResult floor = import_osm("courtyard.osm", "0", o);
  const FloorProbe probe_floor(floor.plan, {0, 0});
  EXPECT_TRUE(probe_floor.floor({12, 9}));
  EXPECT_NEAR(floor.faithfulness.free_outside_mapped_m2, 72.0 - 0.05 * 36.0, 2.0);
  ASSERT_EQ(floor.warnings.size(), 1u);  // 16% of the free floor lies in no space
  EXPECT_NE(floor.warnings[0].find("no mapped space"), std::string::npos) << floor.warnings[0];
  o.strict = true;
  expect_input_error([&] { import_osm("courtyard.osm", "0", o); }, {"--strict", "no mapped space"});
}

// IMDF: the same courtyard ringed by walkway units is unmapped there too.
TEST(ImportFaithful, ImdfCourtyardIsNotFloor) {
  const ImportResult r = import_floor_plan(data_path("imdf/courtyard"), ImportFormat::kImdf);
  expect_free_area_near(r, 360.0);
  EXPECT_EQ(r.faithfulness.unmapped_regions, 1);
  EXPECT_NEAR(r.faithfulness.unmapped_area_m2, 72.0, 3.0);
  EXPECT_EQ(r.plan.doors.size(), 8u);
  EXPECT_EQ(r.faithfulness.sealed_spaces, 0);
}

// IMDF one floor up: the courtyard is an atrium mapped as an opentobelow unit (a void, not floor)
// and opening.geojson is empty. A note says every room is sealed in the data (and the check warns:
// 75% of the mapped area sealed); --infer-openings puts one door per room on the longest stretch
// of wall it shares with the walkway ring, counted.
TEST(ImportFaithful, MissingOpeningsAreNotedAndInferredOnRequest) {
  const std::string dir = data_path("imdf/atrium_no_openings");
  const ImportResult r = import_floor_plan(dir, ImportFormat::kImdf);
  EXPECT_TRUE(r.plan.doors.empty());
  EXPECT_TRUE(has_note(r, {"no openings", "8 of 8 rooms have no opening", "--infer-openings"}));
  for (const Room& room : r.plan.rooms) EXPECT_NE(room.kind, "opentobelow");
  EXPECT_EQ(r.faithfulness.unmapped_regions, 1);
  EXPECT_NEAR(r.faithfulness.unmapped_area_m2, 72.0, 3.0);
  expect_free_area_near(r, 360.0);
  EXPECT_EQ(r.faithfulness.sealed_spaces, 8);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("sealed"), std::string::npos);

  ImportOptions o;
  o.infer_openings = true;
  const ImportResult inferred = import_floor_plan(dir, ImportFormat::kImdf, o);
  EXPECT_EQ(repair(inferred, "openings_inferred"), 8);
  ASSERT_EQ(inferred.plan.doors.size(), 8u);
  EXPECT_TRUE(has_note(inferred, {"8 doors inferred"}));
  EXPECT_EQ(inferred.faithfulness.sealed_spaces, 0);
  EXPECT_EQ(inferred.faithfulness.unreachable_spaces, 0);
  EXPECT_TRUE(inferred.warnings.empty());
  // Every door sits on its room's boundary with the walkway ring, at the middle of the longest
  // shared stretch: e.g. the south-west room [0,4]x[0,9] shares x = 4, y 4-9 with two walkway
  // pieces, so its door is at (4, 6.5).
  const Vec2 shift = design_shift(inferred.plan, {0, 0});
  bool south_west = false;
  for (const Door& d : inferred.plan.doors) {
    EXPECT_NEAR(d.width_m, 0.9, 1e-9);
    south_west = south_west || (d.center_m + shift - Vec2(4, 6.5)).norm() < 0.05;
  }
  EXPECT_TRUE(south_west);
}

// A concourse mapped as one unwalled corridor (wall=no, a multipolygon of two ways) with shops
// inside: it was outside the free space (the level imported as four sealed shops); now it is
// free floor, and the shops, which have no door in the data, are reported sealed (39% of the
// mapped area: a warning; --strict refuses).
TEST(ImportFaithful, UnwalledConcourseIsFreeAndSealedShopsAreReported) {
  const ImportResult r = import_osm("concourse.osm");
  expect_free_area_near(r, 824.0);
  const FloorProbe probe(r.plan, {0, 0});
  EXPECT_TRUE(probe.floor({20, 9}));  // concourse between the shops
  EXPECT_TRUE(probe.floor({44, 10})); // exit passage
  EXPECT_TRUE(probe.floor({9, 6}));   // inside a shop
  EXPECT_EQ(r.faithfulness.sealed_spaces, 4);
  EXPECT_NEAR(r.faithfulness.sealed_area_m2, 320.0, 10.0);
  EXPECT_EQ(r.faithfulness.unreachable_spaces, 4);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("4 of 6 spaces"), std::string::npos) << r.warnings[0];
  EXPECT_NE(r.warnings[0].find("sealed"), std::string::npos) << r.warnings[0];
  ImportOptions o;
  o.strict = true;
  expect_input_error([&] { import_osm("concourse.osm", "0", o); }, {"--strict", "sealed"});
}

// A level of column outlines only: no space, nothing is floor: refused, naming the levels that
// have spaces. The level with spaces lists it as a level without spaces.
TEST(ImportFaithful, LevelWithoutSpacesIsRefused) {
  expect_input_error([] { import_osm("pillars.osm", "1"); }, {"level 1 maps no space", "levels with spaces: 0"});
  const ImportResult r = import_osm("pillars.osm", "0");
  ASSERT_EQ(r.faithfulness.levels_without_spaces.size(), 1u);
  EXPECT_NE(r.faithfulness.levels_without_spaces[0].find("level 1"), std::string::npos);
}

// `plan validate` and every importer refuse a plan with nowhere to stand.
TEST(ImportFaithful, PlanWithoutRoomSizedFreeRegionIsRefused) {
  FloorPlan pillars;
  pillars.name = "pillars";
  for (int k = 0; k < 6; ++k) {
    const double x = 1.0 + 4.0 * (k % 3), y = 2.0 + 4.0 * (k / 3);
    const Vec2 c[4] = {{x, y}, {x + 0.6, y}, {x + 0.6, y + 0.6}, {x, y + 0.6}};
    for (int e = 0; e < 4; ++e) {
      Wall w;
      w.id = "p" + std::to_string(k) + "-" + std::to_string(e);
      w.a_m = c[e];
      w.b_m = c[(e + 1) % 4];
      w.thickness_m = 0.1;
      pillars.walls.push_back(w);
    }
  }
  validate_floor_plan(pillars, "pillars");  // well-formed ...
  const FreeRegionSummary s = free_region_summary(pillars);
  EXPECT_EQ(s.room_sized_regions, 0);
  EXPECT_LT(s.largest_region_m2, 0.5);
  expect_input_error([&] { require_room_sized_free_region(pillars, "pillars.json"); },
                     {"pillars.json", "no room-sized free region"});  // ... but nowhere to stand
  FloorPlan box = pillars;
  box.walls.clear();
  const Vec2 c[4] = {{0, 0}, {3, 0}, {3, 2}, {0, 2}};
  for (int e = 0; e < 4; ++e) {
    Wall w;
    w.id = "b" + std::to_string(e);
    w.a_m = c[e];
    w.b_m = c[(e + 1) % 4];
    w.thickness_m = 0.1;
    box.walls.push_back(w);
  }
  EXPECT_NO_THROW(require_room_sized_free_region(box, "box"));  // 2.9 x 1.9 m: a room
}

}  // namespace
}  // namespace floorcast
