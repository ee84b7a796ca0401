// plan_stats: known answers on small hand-built plans.
#include <gtest/gtest.h>

#include <cmath>

#include "floorcast/core/math.hpp"
#include "floorcast/floorplans/stats.hpp"
#include "test_plans.hpp"

namespace floorcast {
namespace {

Room rect_room(const std::string& id, const std::string& kind, double x0, double y0, double x1, double y1) {
  return {id, kind, {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}, {}};
}

/// A 2 m corridor (y in [5, 7], x in [0, 16]) between a south row of four identical 4 x 5 m rooms
/// and a north row of three rooms 3, 5 and 8 m wide (5 m deep). Walls: the 16 x 12 outline, the
/// two corridor walls, the partitions; one door per room.
FloorPlan corridor_plan() {
  FloorPlan p;
  p.name = "corridor";
  auto wall = [&p](const std::string& id, Vec2 a, Vec2 b, double t) {
    p.walls.push_back({id, a, b, t, WallMaterial::kSolid, 0.0, {}});
  };
  wall("s", {0, 0}, {16, 0}, 0.3);
  wall("e", {16, 0}, {16, 12}, 0.3);
  wall("n", {16, 12}, {0, 12}, 0.3);
  wall("w", {0, 12}, {0, 0}, 0.3);
  wall("cs", {0, 5}, {16, 5}, 0.15);
  wall("cn", {0, 7}, {16, 7}, 0.15);
  for (int k = 1; k < 4; ++k) wall("ps" + std::to_string(k), {4.0 * k, 0}, {4.0 * k, 5}, 0.1);
  wall("pn1", {3, 7}, {3, 12}, 0.1);
  wall("pn2", {8, 7}, {8, 12}, 0.1);
  for (int k = 0; k < 4; ++k) p.doors.push_back({"ds" + std::to_string(k), "cs", {4.0 * k + 2.0, 5.0}, 0.9, false});
  p.doors.push_back({"dn0", "cn", {1.5, 7.0}, 0.9, false});
  p.doors.push_back({"dn1", "cn", {5.5, 7.0}, 0.9, false});
  p.doors.push_back({"dn2", "cn", {12.0, 7.0}, 0.9, false});
  p.obstacles.push_back({"col", ObstacleKind::kPillar, {8.0, 6.0}, {0.3, 0.3}, 0.0, 3.0});
  for (int k = 0; k < 4; ++k) p.rooms.push_back(rect_room("s" + std::to_string(k), "office", 4.0 * k, 0, 4.0 * k + 4.0, 5));
  p.rooms.push_back(rect_room("n0", "office", 0, 7, 3, 12));
  p.rooms.push_back(rect_room("n1", "office", 3, 7, 8, 12));
  p.rooms.push_back(rect_room("n2", "office", 8, 7, 16, 12));
  p.rooms.push_back(rect_room("hall", "corridor", 0, 5, 16, 7));
  return p;
}

TEST(PlanStats, DescribeGivesQuartilesAndCoefficientOfVariation) {
  const Distribution d = describe({4.0, 1.0, 3.0, 2.0, 5.0});
  EXPECT_EQ(d.count, 5);
  EXPECT_DOUBLE_EQ(d.min, 1.0);
  EXPECT_DOUBLE_EQ(d.q1, 2.0);
  EXPECT_DOUBLE_EQ(d.median, 3.0);
  EXPECT_DOUBLE_EQ(d.q3, 4.0);
  EXPECT_DOUBLE_EQ(d.max, 5.0);
  EXPECT_DOUBLE_EQ(d.mean, 3.0);
  EXPECT_NEAR(d.cv, std::sqrt(2.0) / 3.0, 1e-12);
  EXPECT_EQ(describe({}).count, 0);
  EXPECT_DOUBLE_EQ(describe({2.0, 4.0}).median, 3.0);
}

TEST(PlanStats, MinAreaRectOfARotatedRectangleGivesItsSides) {
  const double c = std::cos(0.5236), s = std::sin(0.5236);
  std::vector<Vec2> pts;
  for (const Vec2& q : {Vec2(0, 0), Vec2(7, 0), Vec2(7, 3), Vec2(0, 3)}) {
    pts.emplace_back(100.0 + c * q.x() - s * q.y(), 50.0 + s * q.x() + c * q.y());
  }
  const auto [w, l] = min_area_rect_sides_m(pts);
  EXPECT_NEAR(w, 3.0, 1e-3);
  EXPECT_NEAR(l, 7.0, 1e-3);
}

TEST(PlanStats, WallsDoorsAndDirectionsOfACorridorPlan) {
  const PlanStats s = plan_stats(corridor_plan());
  EXPECT_EQ(s.walls, 11);
  const double length = 2 * 16 + 2 * 12 + 2 * 16 + 3 * 5 + 2 * 5;  // 113 m
  EXPECT_NEAR(s.wall_length_m, length, 1e-9);
  EXPECT_EQ(s.doors, 7);
  EXPECT_NEAR(s.doors_per_10m_wall, 70.0 / length, 1e-9);
  EXPECT_EQ(s.pillars, 1);
  ASSERT_EQ(s.direction_share.size(), 12u);
  EXPECT_EQ(s.directions_used, 2);
  EXPECT_NEAR(s.direction_share[0], 64.0 / length, 1e-9);   // east-west
  EXPECT_NEAR(s.direction_share[6], 49.0 / length, 1e-9);   // north-south (both orientations fold to 90)
  ASSERT_EQ(s.thickness_classes.size(), 3u);
  EXPECT_DOUBLE_EQ(s.thickness_classes[0].thickness_m, 0.1);
  EXPECT_EQ(s.thickness_classes[0].walls, 5);
  EXPECT_NEAR(s.thickness_classes[2].length_share, 56.0 / length, 1e-9);
  // Free area: 16 x 12 minus wall footprints, roughly.
  EXPECT_GT(s.free_area_m2, 160.0);
  EXPECT_LT(s.free_area_m2, 192.0);
}

TEST(PlanStats, RoomsRepetitionAndCorridorWidth) {
  const PlanStats s = plan_stats(corridor_plan());
  EXPECT_EQ(s.rooms, 8);
  EXPECT_EQ(s.transitional_rooms, 1);
  ASSERT_EQ(s.room_area_m2.count, 7);
  EXPECT_NEAR(s.room_area_m2.median, 20.0, 1e-9);  // 15, 20, 20, 20, 20, 25, 40
  EXPECT_NEAR(s.room_area_m2.min, 15.0, 1e-9);
  EXPECT_NEAR(s.room_area_m2.max, 40.0, 1e-9);
  ASSERT_EQ(s.room_width_m.count, 7);
  EXPECT_NEAR(s.room_width_m.min, 3.0, 1e-3);  // the 8 x 5 room's width is 5
  EXPECT_NEAR(s.room_width_m.max, 5.0, 1e-3);
  // The four identical south rooms repeat each other; 5 m (north, 5 x 5 and 8 x 5) repeat too:
  // widths 4,4,4,4 | 3,5,5 -> the 5 x 5 and 8 x 5 rooms are neighbours with width 5.
  EXPECT_NEAR(s.repeated_width_share, 6.0 / 7.0, 1e-9);
  ASSERT_GT(s.corridor_width_m.count, 100);  // ridge pixels along the 16 m corridor
  EXPECT_NEAR(s.corridor_width_m.median, 2.0, 0.15);
}

TEST(PlanStats, VariedRoomsDoNotRepeatAndATighterToleranceCountsFewer) {
  FloorPlan p = corridor_plan();
  // Make the south rooms 3, 4, 4.4, 4.6 m wide: 4.4 and 4.6 are within 5% (4.3%), 4 and 4.4 are not (9%).
  p.rooms[0] = rect_room("s0", "office", 0, 0, 3, 5);
  p.rooms[1] = rect_room("s1", "office", 3, 0, 7, 5);
  p.rooms[2] = rect_room("s2", "office", 7, 0, 11.4, 5);
  p.rooms[3] = rect_room("s3", "office", 11.4, 0, 16, 5);
  PlanStats s = plan_stats(p);
  // Repeated: s2, s3 (4.4 ~ 4.6); n1, n2 (5, 5); s0 (3) and n0 (3) are 2 m apart (not neighbours).
  EXPECT_NEAR(s.repeated_width_share, 4.0 / 7.0, 1e-9);
  PlanStatsParams tight;
  tight.repeat_tolerance = 0.01;
  s = plan_stats(p, tight);
  EXPECT_NEAR(s.repeated_width_share, 2.0 / 7.0, 1e-9);
  PlanStatsParams far;
  far.neighbour_gap_m = 2.5;  // s0 and n0 (both 3 m wide) become neighbours across the corridor
  s = plan_stats(p, far);
  EXPECT_NEAR(s.repeated_width_share, 6.0 / 7.0, 1e-9);
}

TEST(PlanStats, APlanWithoutRoomsHasEmptyRoomMeasures) {
  const PlanStats s = plan_stats(test::furnished_room());
  EXPECT_EQ(s.rooms, 0);
  EXPECT_EQ(s.room_area_m2.count, 0);
  EXPECT_EQ(s.corridor_width_m.count, 0);
  EXPECT_DOUBLE_EQ(s.repeated_width_share, 0.0);
  EXPECT_EQ(s.walls, 4);
  EXPECT_EQ(s.glass_walls, 1);
  EXPECT_EQ(s.doors, 2);
}

}  // namespace
}  // namespace floorcast
