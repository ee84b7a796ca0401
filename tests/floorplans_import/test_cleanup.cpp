// cleanup_floor_plan: known answers for each stage, plus a brute-force check on random wall soups.
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <set>

#include "floorcast/floorplans/cleanup.hpp"
#include "floorcast/floorplans/io.hpp"
#include "import_test_util.hpp"

namespace floorcast {
namespace {

using test::expect_input_error;
using test::find_wall;

Wall wall(const std::string& id, Vec2 a, Vec2 b, double t = 0.1) {
  Wall w;
  w.id = id;
  w.a_m = a;
  w.b_m = b;
  w.thickness_m = t;
  return w;
}

FloorPlan plan_of(std::vector<Wall> walls) {
  FloorPlan p;
  p.walls = std::move(walls);
  return p;
}

TEST(Cleanup, DuplicateAndReversedEdgesBecomeOneWall) {
  FloorPlan p = plan_of({wall("a", {0, 0}, {5, 0}), wall("b", {0, 0}, {5, 0}), wall("c", {5, 0}, {0, 0})});
  const CleanupReport r = cleanup_floor_plan(p, {}, "test");
  ASSERT_EQ(p.walls.size(), 1u);
  EXPECT_EQ(p.walls[0].id, "a");
  EXPECT_NEAR(p.walls[0].length_m(), 5.0, 1e-12);
  EXPECT_NEAR(r.duplicate_length_m, 10.0, 1e-9);
  EXPECT_EQ(r.walls_merged_away, 2);
  EXPECT_EQ(r.collinear_groups_merged, 1);
  EXPECT_EQ(r.input_walls, 3);
  EXPECT_EQ(r.output_walls, 1);
}

TEST(Cleanup, CollinearTouchingAndOverlappingPiecesMerge) {
  FloorPlan p = plan_of({wall("a", {0, 0}, {2, 0}), wall("b", {2, 0}, {5, 0}), wall("c", {4, 0}, {7, 0})});
  const CleanupReport r = cleanup_floor_plan(p, {}, "test");
  ASSERT_EQ(p.walls.size(), 1u);
  EXPECT_NE(find_wall(p, {0, 0}, {7, 0}, 1e-9), nullptr);
  EXPECT_NEAR(r.duplicate_length_m, 1.0, 1e-9);
}

TEST(Cleanup, TinyGapsCloseLargeGapsStay) {
  FloorPlan small = plan_of({wall("a", {0, 0}, {2, 0}), wall("b", {2.015, 0}, {5, 0})});
  const CleanupReport r = cleanup_floor_plan(small, {}, "test");
  ASSERT_EQ(small.walls.size(), 1u);
  EXPECT_EQ(r.gaps_closed + r.snapped_endpoints > 0, true);
  EXPECT_NEAR(small.walls[0].length_m(), 5.0, 1e-9);

  FloorPlan door_gap = plan_of({wall("a", {0, 0}, {2, 0}), wall("b", {2.9, 0}, {5, 0})});
  cleanup_floor_plan(door_gap, {}, "test");
  EXPECT_EQ(door_gap.walls.size(), 2u);
}

TEST(Cleanup, GapBetweenCollinearPiecesIsBridgedAlongTheLine) {
  // Endpoints 1.5 cm apart but each also near other points would cluster; keep them isolated by
  // making the gap only along the line: snap tolerance 2 cm closes it.
  CleanupOptions o;
  o.snap_tolerance_m = 0.02;
  FloorPlan p = plan_of({wall("a", {0, 0}, {3, 0}), wall("b", {3.019, 0}, {6, 0})});
  const CleanupReport r = cleanup_floor_plan(p, o, "test");
  ASSERT_EQ(p.walls.size(), 1u);
  EXPECT_NEAR(p.walls[0].length_m(), 6.0, 1e-9);
  EXPECT_GE(r.snapped_endpoints + r.gaps_closed, 1);
}

TEST(Cleanup, NearCoincidentCornerSnapsToTheLinesIntersection) {
  FloorPlan p = plan_of({wall("h", {0, 0}, {5, 0}), wall("v", {5.008, 0.006}, {5.008, 4})});
  const CleanupReport r = cleanup_floor_plan(p, {}, "test");
  ASSERT_EQ(p.walls.size(), 2u);
  const Wall& h = p.walls[0];
  const Wall& v = p.walls[1];
  // Corner = intersection of y = 0 and x = 5.008, shared exactly.
  EXPECT_NEAR(h.b_m.x(), 5.008, 1e-9);
  EXPECT_NEAR(h.b_m.y(), 0.0, 1e-9);
  EXPECT_EQ(h.b_m, v.a_m);
  EXPECT_EQ(r.snapped_endpoints, 2);
}

TEST(Cleanup, TJunctionGapClosesOntoTheThroughWall) {
  FloorPlan p = plan_of({wall("through", {0, 0}, {10, 0}), wall("stem", {5, 0.015}, {5, 4})});
  const CleanupReport r = cleanup_floor_plan(p, {}, "test");
  ASSERT_EQ(p.walls.size(), 2u);
  EXPECT_NEAR(p.walls[1].a_m.y(), 0.0, 1e-12);
  EXPECT_NEAR(p.walls[1].a_m.x(), 5.0, 1e-12);
  EXPECT_EQ(r.endpoints_snapped_to_walls, 1);
  EXPECT_NE(find_wall(p, {0, 0}, {10, 0}, 1e-12), nullptr);  // the through wall did not move
}

TEST(Cleanup, DegeneratePiecesAreDropped) {
  FloorPlan p = plan_of({wall("a", {0, 0}, {5, 0}), wall("dot", {1, 1}, {1.005, 1}), wall("zero", {2, 2}, {2, 2})});
  const CleanupReport r = cleanup_floor_plan(p, {}, "test");
  EXPECT_EQ(p.walls.size(), 1u);
  EXPECT_EQ(r.dropped_degenerate_walls, 2);
}

TEST(Cleanup, OverlapsKeepTheThickerAndSolidWall) {
  Wall thick = wall("b", {4, 0}, {6, 0}, 0.3);
  Wall glass = wall("g", {6, 0}, {8, 0}, 0.3);
  glass.material = WallMaterial::kGlass;
  FloorPlan p = plan_of({wall("a", {0, 0}, {10, 0}, 0.1), thick, glass});
  cleanup_floor_plan(p, {}, "test");
  ASSERT_EQ(p.walls.size(), 3u);
  // a keeps its id on its first piece, b defines the thick piece, the rest of a gets a suffix;
  // the glass piece loses to the solid wall underneath (solid beats glass).
  const Wall* a0 = find_wall(p, {0, 0}, {4, 0}, 1e-9);
  const Wall* b = find_wall(p, {4, 0}, {6, 0}, 1e-9);
  const Wall* a1 = find_wall(p, {6, 0}, {10, 0}, 1e-9);
  ASSERT_TRUE(a0 && b && a1);
  EXPECT_EQ(a0->id, "a");
  EXPECT_EQ(b->id, "b");
  EXPECT_EQ(a1->id, "a-2");
  EXPECT_DOUBLE_EQ(b->thickness_m, 0.3);
  EXPECT_DOUBLE_EQ(a1->thickness_m, 0.1);
  EXPECT_EQ(a1->material, WallMaterial::kSolid);
}

TEST(Cleanup, OpeningsFollowTheirWallIntoTheMergedWall) {
  FloorPlan p = plan_of({wall("w1", {0, 0}, {2, 0}), wall("w2", {2, 0}, {5, 0}), wall("w3", {5, 0}, {5, 4})});
  p.doors.push_back({"d", "w2", {3.0, 0.0}, 0.9, true});
  p.windows.push_back({"win", "w3", {5.0, 2.0}, 1.2, 0.9, 2.1});
  const CleanupReport r = cleanup_floor_plan(p, {}, "test");
  ASSERT_EQ(p.walls.size(), 2u);
  ASSERT_EQ(p.doors.size(), 1u);
  EXPECT_EQ(p.doors[0].wall_id, "w1");
  EXPECT_TRUE(p.doors[0].closed);
  EXPECT_NEAR(p.doors[0].center_m.x(), 3.0, 1e-12);
  EXPECT_NEAR(p.doors[0].width_m, 0.9, 1e-12);
  EXPECT_EQ(p.windows[0].wall_id, "w3");
  EXPECT_EQ(r.openings_reattached, 1);
  validate_floor_plan(p, "test");
}

TEST(Cleanup, DuplicateDoorsMergeIntoOneSpanningBoth) {
  FloorPlan p = plan_of({wall("w", {0, 0}, {6, 0})});
  p.doors.push_back({"d1", "w", {3.0, 0.0}, 0.9, false});
  p.doors.push_back({"d2", "w", {3.1, 0.02}, 0.9, true});
  p.doors.push_back({"d3", "w", {5.0, 0.0}, 0.8, false});  // separate door
  const CleanupReport r = cleanup_floor_plan(p, {}, "test");
  ASSERT_EQ(p.doors.size(), 2u);
  EXPECT_EQ(r.openings_merged, 1);
  EXPECT_EQ(p.doors[0].id, "d1");
  EXPECT_NEAR(p.doors[0].center_m.x(), 3.05, 1e-9);
  EXPECT_NEAR(p.doors[0].width_m, 1.0, 1e-9);
  EXPECT_TRUE(p.doors[0].closed);  // closed if either was
  validate_floor_plan(p, "test");
}

TEST(Cleanup, FloatingOpeningsAttachToTheNearestWallOrFailClearly) {
  FloorPlan p = plan_of({wall("south", {0, 0}, {6, 0}), wall("north", {0, 4}, {6, 4})});
  p.doors.push_back({"near-north", "", {2.0, 3.97}, 0.9, false});
  cleanup_floor_plan(p, {}, "test");
  EXPECT_EQ(p.doors[0].wall_id, "north");

  FloorPlan far = plan_of({wall("south", {0, 0}, {6, 0})});
  far.doors.push_back({"lost", "", {2.0, 1.0}, 0.9, false});
  FloorPlan far_copy = far;
  expect_input_error([&] { cleanup_floor_plan(far, {}, "plan.src"); },
                     {"plan.src", "doors[0] (id \"lost\")", "does not lie on any wall", "\"south\" is 1 m away"});
  CleanupOptions drop;
  drop.drop_unattachable_openings = true;
  const CleanupReport r = cleanup_floor_plan(far_copy, drop, "plan.src");
  EXPECT_TRUE(far_copy.doors.empty());
  EXPECT_EQ(r.openings_dropped, 1);
  ASSERT_EQ(r.notes.size(), 1u);
  EXPECT_NE(r.notes[0].find("lost"), std::string::npos);
}

TEST(Cleanup, SpansOvershootingAWallEndAreTrimmedOnlyWithinTolerance) {
  FloorPlan p = plan_of({wall("w", {0, 0}, {3, 0})});
  p.doors.push_back({"d", "w", {2.555, 0.0}, 0.9, false});  // span [2.105, 3.005]
  const CleanupReport r = cleanup_floor_plan(p, {}, "test");
  EXPECT_EQ(r.openings_trimmed, 1);
  EXPECT_NEAR(p.doors[0].width_m, 0.895, 1e-9);
  EXPECT_NEAR(p.doors[0].center_m.x(), 2.5525, 1e-9);
  validate_floor_plan(p, "test");

  // Overrunning the end by more than the tolerance: the span slides inside the wall (noted).
  FloorPlan slid = plan_of({wall("w", {0, 0}, {3, 0})});
  slid.doors.push_back({"d", "w", {2.8, 0.0}, 0.9, false});
  const CleanupReport rs = cleanup_floor_plan(slid, {}, "t");
  EXPECT_EQ(rs.openings_slid, 1);
  EXPECT_EQ(rs.openings_trimmed, 0);
  EXPECT_NEAR(slid.doors[0].center_m.x(), 2.55, 1e-9);
  EXPECT_NEAR(slid.doors[0].width_m, 0.9, 1e-12);
  ASSERT_EQ(rs.notes.size(), 1u);
  EXPECT_NE(rs.notes[0].find("slid 0.25 m along wall \"w\""), std::string::npos) << rs.notes[0];
  validate_floor_plan(slid, "t");

  // A centre beyond the wall's end by more than half the width lies on no wall.
  FloorPlan bad = plan_of({wall("w", {0, 0}, {3, 0})});
  bad.doors.push_back({"d", "w", {3.6, 0.0}, 0.9, false});
  expect_input_error([&] { cleanup_floor_plan(bad, {}, "t"); },
                     {"doors[0] (id \"d\")", "does not lie on any wall", "\"w\" is 0.6 m away"});
  // A narrow opening just beyond the end, within reach of the wall: its span does not reach it.
  FloorPlan beyond = plan_of({wall("w", {0, 0}, {3, 0})});
  beyond.doors.push_back({"d", "w", {3.1, 0.0}, 0.1, false});
  expect_input_error([&] { cleanup_floor_plan(beyond, {}, "t"); }, {"doors[0] (id \"d\")", "does not reach wall \"w\""});
}

// A door node on a wall end (OSM draws doors as vertices of room outlines; at a corner the door's
// centre is both walls' end): it slides into the wall it fits, centred as close as it can be.
TEST(Cleanup, DoorOnAWallEndSlidesInsideTheWall) {
  FloorPlan p = plan_of({wall("south", {0, 0}, {8, 0}), wall("east", {8, 0}, {8, 4})});
  p.doors.push_back({"corner", "", {8.0, 0.0}, 0.9, false});
  const CleanupReport r = cleanup_floor_plan(p, {}, "t");
  EXPECT_EQ(r.openings_slid, 1);
  ASSERT_EQ(p.doors.size(), 1u);
  validate_floor_plan(p, "t");
  const Door& d = p.doors[0];
  const Wall& w = p.walls[static_cast<std::size_t>(p.wall_index(d.wall_id))];
  const double along = (d.center_m - w.a_m).dot(w.direction());
  EXPECT_NEAR(std::min(along, w.length_m() - along), 0.45, 1e-9);  // flush with the corner
}

TEST(Cleanup, OpeningWiderThanItsWallIsNarrowedToIt) {
  FloorPlan p = plan_of({wall("stub", {0, 0}, {0.6, 0}), wall("long", {0.6, 0}, {0.6, 5})});
  p.doors.push_back({"wide", "stub", {0.3, 0.0}, 0.9, false});
  const CleanupReport r = cleanup_floor_plan(p, {}, "t");
  EXPECT_EQ(r.openings_narrowed, 1);
  EXPECT_EQ(p.doors[0].wall_id, "stub");
  EXPECT_NEAR(p.doors[0].width_m, 0.6, 1e-12);
  validate_floor_plan(p, "t");
}

// Real exports put doors a few centimetres off the wall's axis (IMDF openings drawn on a unit's
// outline next to the wall): within the attach tolerance they move onto the axis, counted, with a
// note beyond 5 cm (where validation would have refused them), so --drop-bad-openings is not needed.
TEST(Cleanup, OpeningsOffTheAxisMoveOntoIt) {
  FloorPlan p = plan_of({wall("w", {0, 0}, {6, 0}, 0.1)});
  p.doors.push_back({"near", "", {2.0, 0.02}, 0.9, false});
  p.doors.push_back({"off", "", {4.0, -0.12}, 0.9, false});
  const CleanupReport r = cleanup_floor_plan(p, {}, "t");
  EXPECT_EQ(r.openings_moved_to_axis, 2);
  ASSERT_EQ(r.notes.size(), 1u);
  EXPECT_NE(r.notes[0].find("doors[1] (id \"off\") moved 0.12 m onto the axis of wall \"w\""), std::string::npos)
      << r.notes[0];
  for (const Door& d : p.doors) EXPECT_NEAR(d.center_m.y(), 0.0, 1e-12);
  validate_floor_plan(p, "t");
}

// Collinearity is judged by direction and offset, never by shortness: a 1.5 cm chamfer at a corner
// lies within the snap tolerance of both walls' lines but is collinear with neither, so the walls
// stay two walls meeting at the corner (the old rule chained them into one fitted diagonal).
TEST(Cleanup, ShortPiecesNeverChainWallsOfAnotherDirection) {
  FloorPlan p = plan_of({wall("south", {0, 0}, {5.985, 0}), wall("chamfer", {5.985, 0}, {6.0, 0.015}),
                         wall("east", {6.0, 0.015}, {6, 4})});
  cleanup_floor_plan(p, {}, "t");
  // The chamfer (2.1 cm, longer than the snap tolerance) stays a wall of its own.
  ASSERT_EQ(p.walls.size(), 3u);
  const Wall* south = find_wall(p, {0, 0}, {5.985, 0}, 1e-9);
  const Wall* east = find_wall(p, {6, 0.015}, {6, 4}, 1e-9);
  ASSERT_TRUE(south && east);
  EXPECT_EQ(south->a_m.y(), 0.0);
  EXPECT_EQ(south->b_m.y(), 0.0);
  EXPECT_EQ(east->a_m.x(), 6.0);
  EXPECT_EQ(east->b_m.x(), 6.0);
  // And pairwise: a short piece across a line is not collinear with it.
  const std::vector<Segment2> segs = {{{0, 0}, {10, 0}}, {{4, -0.01}, {4.005, 0.01}}, {{6, 0.001}, {6.02, 0.0012}}};
  const std::vector<int> g = collinear_groups(segs, 0.02, 0.0175);
  EXPECT_NE(g[0], g[1]);
  EXPECT_EQ(g[0], g[2]);
}

TEST(Cleanup, WindowsNeverGoIntoGlassWalls) {
  Wall g = wall("glass", {0, 0}, {6, 0}, 0.05);
  g.material = WallMaterial::kGlass;
  FloorPlan p = plan_of({g});
  p.windows.push_back({"win", "", {3.0, 0.0}, 1.2, 0.9, 2.1});
  expect_input_error([&] { cleanup_floor_plan(p, {}, "t"); }, {"windows[0]", "glass wall \"glass\""});
}

TEST(Cleanup, IsIdempotentAndDeterministic) {
  FloorPlan p = plan_of({wall("a", {0, 0}, {5, 0}), wall("b", {5.01, 0.01}, {5, 4}), wall("c", {5, 4}, {0, 4}),
                         wall("d", {0, 4}, {0, 0}), wall("e", {2, 0}, {4, 0}), wall("f", {2.5, 0.012}, {2.5, 4})});
  p.doors.push_back({"door", "e", {3.2, 0.0}, 0.8, false});
  FloorPlan once = p;
  cleanup_floor_plan(once, {}, "t");
  FloorPlan again = p;
  cleanup_floor_plan(again, {}, "t");
  EXPECT_EQ(floor_plan_to_json(once), floor_plan_to_json(again));
  FloorPlan twice = once;
  const CleanupReport r2 = cleanup_floor_plan(twice, {}, "t");
  EXPECT_EQ(floor_plan_to_json(once), floor_plan_to_json(twice));
  EXPECT_EQ(r2.walls_merged_away, 0);
  EXPECT_EQ(r2.snapped_endpoints, 0);
}

TEST(Cleanup, RefusesBadTolerances) {
  FloorPlan p = plan_of({wall("a", {0, 0}, {5, 0})});
  CleanupOptions o;
  o.snap_tolerance_m = -1.0;
  expect_input_error([&] { cleanup_floor_plan(p, o, "t"); }, {"t: cleanup", "tolerances"});
}

TEST(Cleanup, OffsetWallsThatMeetEndToEndStaySeparate) {
  // Two parallel walls 0.4 m apart meeting end to end along y (a jog), like a corridor wall
  // stepping back: not collinear, must not merge.
  FloorPlan p = plan_of({wall("a", {0, 0}, {0, 7.7}), wall("b", {0.4, 7.7}, {0.4, 15.4})});
  cleanup_floor_plan(p, {}, "t");
  ASSERT_EQ(p.walls.size(), 2u);
  EXPECT_EQ(p.walls[0].a_m.x(), 0.0);
  EXPECT_EQ(p.walls[1].a_m.x(), 0.4);
}

/// A messy block: a room whose walls are split into jittered pieces, some drawn twice, and a jog.
std::vector<Wall> messy_block(std::mt19937& rng, const Vec2& offset, int& next_id) {
  std::uniform_real_distribution<double> jitter(-0.003, 0.003);
  std::uniform_int_distribution<int> coin(0, 1);
  const std::vector<std::pair<Vec2, Vec2>> base = {{{0, 0}, {12, 0}},   {{12, 0}, {12, 15.4}}, {{12, 15.4}, {0.4, 15.4}},
                                                  {{0.4, 15.4}, {0.4, 7.7}}, {{0, 7.7}, {0, 0}},   {{0, 7.7}, {0.4, 7.7}},
                                                  {{6, 0}, {6, 9}}};
  std::vector<Wall> out;
  for (const auto& [a, b] : base) {
    // Pieces of at least 2.5 m: 3 mm of jitter tilts them by at most 0.14 degrees, within the
    // 1-degree tolerance (shorter jittered pieces may point off their line by more, and are then
    // not collinear with it: direction decides, never shortness).
    const int n = (b - a).norm() >= 7.5 ? 3 : 1;
    for (int k = 0; k < n; ++k) {
      Vec2 p0 = a + (b - a) * (k / double(n)) + offset, p1 = a + (b - a) * ((k + 1) / double(n)) + offset;
      p0 += Vec2(jitter(rng), jitter(rng));
      p1 += Vec2(jitter(rng), jitter(rng));
      out.push_back(wall("w" + std::to_string(next_id++), p0, p1));
      if (coin(rng)) out.push_back(wall("w" + std::to_string(next_id++), p1, p0));
    }
  }
  return out;
}

TEST(Cleanup, ResultDoesNotDependOnFarAwayWallsOnTheSameLines) {
  // 5 x 4 copies 300 m apart: their walls share lines with each other across the whole plan. Each
  // copy must clean up exactly like a copy on its own (same wall count, same geometry up to the
  // jitter), i.e. far-apart walls neither join nor tilt each other.
  std::mt19937 rng(11);
  int next = 0;
  FloorPlan single;
  single.walls = messy_block(rng, {0, 0}, next);
  cleanup_floor_plan(single, {}, "single");
  ASSERT_EQ(single.walls.size(), 7u);  // south, east, north, west in two parts, the jog, the partition

  FloorPlan tiled;
  for (int tx = 0; tx < 5; ++tx) {
    for (int ty = 0; ty < 4; ++ty) {
      for (Wall& w : messy_block(rng, {300.0 * tx, 300.0 * ty}, next)) tiled.walls.push_back(w);
    }
  }
  cleanup_floor_plan(tiled, {}, "tiled");
  EXPECT_EQ(tiled.walls.size(), 20u * single.walls.size());
  for (const Wall& w : tiled.walls) {
    const Vec2 tile(300.0 * std::floor(w.a_m.x() / 300.0 + 0.01), 300.0 * std::floor(w.a_m.y() / 300.0 + 0.01));
    EXPECT_NE(find_wall(single, w.a_m - tile, w.b_m - tile, 0.01), nullptr) << w.id;
  }
}

// ---- brute-force checks -------------------------------------------------------------------------

/// Slow obvious collinearity (same rule as the library, written independently).
bool slow_collinear(const Segment2& s, const Segment2& t, double tol, double angle_tol) {
  auto angle = [](const Segment2& q) {
    double a = std::atan2(q.b_m.y() - q.a_m.y(), q.b_m.x() - q.a_m.x());
    while (a < 0) a += M_PI;
    while (a >= M_PI) a -= M_PI;
    return a;
  };
  double da = std::abs(angle(s) - angle(t));
  da = std::min(da, M_PI - da);
  if (da > angle_tol) return false;
  const Segment2& L = s.length_m() >= t.length_m() ? s : t;
  const Segment2& S = s.length_m() >= t.length_m() ? t : s;
  const Vec2 u = (L.b_m - L.a_m).normalized();
  auto off = [&](const Vec2& p) { return std::abs(u.x() * (p - L.a_m).y() - u.y() * (p - L.a_m).x()); };
  return off(S.a_m) <= tol && off(S.b_m) <= tol;
}

TEST(Cleanup, CollinearGroupsMatchTransitiveClosureOfPairwiseTest) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(-20.0, 20.0), jitter(-0.01, 0.01), ang(0.0, M_PI);
  std::vector<Segment2> segs;
  // Lines with several jittered pieces each, plus random clutter.
  for (int line = 0; line < 12; ++line) {
    const Vec2 o(coord(rng), coord(rng));
    const double a = line % 3 == 0 ? 0.0 : (line % 3 == 1 ? M_PI / 2 : ang(rng));
    const Vec2 u(std::cos(a), std::sin(a)), n(-u.y(), u.x());
    for (int k = 0; k < 5; ++k) {
      const double t0 = coord(rng) * 0.5, len = 0.5 + std::abs(coord(rng)) * 0.2;
      segs.push_back({o + t0 * u + jitter(rng) * n, o + (t0 + len) * u + jitter(rng) * n});
    }
  }
  for (int k = 0; k < 60; ++k) segs.push_back({{coord(rng), coord(rng)}, {coord(rng), coord(rng)}});
  const double tol = 0.02, angle_tol = 0.0175;
  const std::vector<int> fast = collinear_groups(segs, tol, angle_tol);
  // Slow: transitive closure by repeated relaxation.
  std::vector<int> slow(segs.size());
  for (std::size_t i = 0; i < segs.size(); ++i) slow[i] = static_cast<int>(i);
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t i = 0; i < segs.size(); ++i) {
      for (std::size_t j = 0; j < segs.size(); ++j) {
        if (slow[i] != slow[j] && slow_collinear(segs[i], segs[j], tol, angle_tol)) {
          const int m = std::min(slow[i], slow[j]);
          slow[i] = slow[j] = m;
          changed = true;
        }
      }
    }
  }
  for (std::size_t i = 0; i < segs.size(); ++i) {
    for (std::size_t j = i + 1; j < segs.size(); ++j) {
      EXPECT_EQ(fast[i] == fast[j], slow[i] == slow[j]) << i << " " << j;
    }
  }
}

/// Random rectilinear wall soup on an integer lattice: pieces split, duplicated, reversed and
/// jittered. After cleanup the covered unit edges must be exactly those of the input (brute
/// force over the lattice), each covered once.
TEST(Cleanup, RandomSoupKeepsExactlyTheCoveredLatticeEdgesOnce) {
  for (int seed = 0; seed < 200; ++seed) {
    std::mt19937 rng(static_cast<unsigned>(seed));
    std::uniform_int_distribution<int> cell(0, 12), len(1, 6), coin(0, 3);
    std::uniform_real_distribution<double> jitter(-0.004, 0.004);
    std::set<std::tuple<int, int, int>> expected;  // (horizontal?, x, y) unit edges
    FloorPlan p;
    int next = 0;
    for (int k = 0; k < 25; ++k) {
      const bool horizontal = coin(rng) % 2 == 0;
      const int x0 = cell(rng), y0 = cell(rng), L = len(rng);
      for (int s = 0; s < L; ++s) expected.insert({horizontal ? 1 : 0, horizontal ? x0 + s : x0, horizontal ? y0 : y0 + s});
      // Split into random pieces; some duplicated or reversed; endpoints jittered.
      int t = 0;
      while (t < L) {
        const int piece = std::min(L - t, 1 + coin(rng));
        Vec2 a = horizontal ? Vec2(x0 + t, y0) : Vec2(x0, y0 + t);
        Vec2 b = horizontal ? Vec2(x0 + t + piece, y0) : Vec2(x0, y0 + t + piece);
        a += Vec2(jitter(rng), jitter(rng));
        b += Vec2(jitter(rng), jitter(rng));
        if (coin(rng) == 0) std::swap(a, b);
        p.walls.push_back(wall("w" + std::to_string(next++), a, b));
        if (coin(rng) == 0) p.walls.push_back(wall("w" + std::to_string(next++), b, a));
        t += piece;
      }
    }
    const CleanupReport r = cleanup_floor_plan(p, {}, "soup");
    EXPECT_EQ(r.output_walls, static_cast<int>(p.walls.size()));
    std::map<std::tuple<int, int, int>, int> covered;
    for (const Wall& w : p.walls) {
      const Vec2 d = w.b_m - w.a_m;
      ASSERT_TRUE(std::abs(d.x()) < 0.02 || std::abs(d.y()) < 0.02) << "seed " << seed << " wall " << w.id;
      const bool horizontal = std::abs(d.x()) > std::abs(d.y());
      const double lo = horizontal ? std::min(w.a_m.x(), w.b_m.x()) : std::min(w.a_m.y(), w.b_m.y());
      const double hi = horizontal ? std::max(w.a_m.x(), w.b_m.x()) : std::max(w.a_m.y(), w.b_m.y());
      const int fixed = static_cast<int>(std::lround(horizontal ? w.a_m.y() : w.a_m.x()));
      EXPECT_NEAR(lo, std::round(lo), 0.01) << "seed " << seed;
      EXPECT_NEAR(hi, std::round(hi), 0.01) << "seed " << seed;
      for (int s = static_cast<int>(std::lround(lo)); s < static_cast<int>(std::lround(hi)); ++s) {
        covered[{horizontal ? 1 : 0, horizontal ? s : fixed, horizontal ? fixed : s}] += 1;
      }
    }
    std::set<std::tuple<int, int, int>> got;
    for (const auto& [edge, n] : covered) {
      EXPECT_EQ(n, 1) << "seed " << seed << ": a unit edge is covered twice";
      got.insert(edge);
    }
    EXPECT_EQ(got, expected) << "seed " << seed;
  }
}

}  // namespace
}  // namespace floorcast
