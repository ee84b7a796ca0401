#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "floorcast/floorplans/extrusion.hpp"
#include "floorcast/floorplans/generate.hpp"
#include "floorcast/floorplans/geometry.hpp"
#include "floorcast/core/math.hpp"
#include "test_plans.hpp"

namespace floorcast {
namespace {

double total_length(const std::vector<LabeledSegment>& segs) {
  double s = 0.0;
  for (const auto& l : segs) s += l.segment_m.length_m();
  return s;
}

/// Exact free-space side check: a point just left of each outline segment is free, a point just
/// right of it is blocked.
void expect_outline_sides(const std::vector<Footprint>& fps, const std::vector<LabeledSegment>& outline) {
  auto blocked = [&](const Vec2& p) {
    for (const auto& f : fps)
      if (point_in_convex_polygon(f.polygon_m, p)) return true;
    return false;
  };
  for (const auto& l : outline) {
    const Vec2 d = (l.segment_m.b_m - l.segment_m.a_m).normalized();
    const Vec2 left(-d.y(), d.x());
    for (double t : {0.25, 0.5, 0.75}) {
      const Vec2 p = l.segment_m.a_m + t * (l.segment_m.b_m - l.segment_m.a_m);
      EXPECT_FALSE(blocked(p + 1e-4 * left)) << "free side blocked at " << p.transpose();
      EXPECT_TRUE(blocked(p - 1e-4 * left)) << "blocked side free at " << p.transpose();
    }
  }
}

TEST(Outline, ClosedBoxRoomHasInnerAndOuterRectangles) {
  const FloorPlan p = test::box_room(5.0, 4.0, 0.2);
  const auto fps = blocking_footprints(p, {});
  ASSERT_EQ(fps.size(), 4u);
  const auto outline = footprint_outline(fps);
  // Inner rectangle 4.8 x 3.8 and outer 5.2 x 4.2, each side one merged segment.
  EXPECT_EQ(outline.size(), 8u);
  EXPECT_NEAR(total_length(outline), 2 * (4.8 + 3.8) + 2 * (5.2 + 4.2), 1e-9);
  expect_outline_sides(fps, outline);
}

TEST(Outline, OpenDoorCutsTheWallAndShowsJambs) {
  FloorPlan p = test::box_room(5.0, 4.0, 0.2);
  p.doors.push_back({"d", "south", {2.5, 0.0}, 1.0, false});
  const auto outline = blocking_outline(p, {});
  // The 1 m opening removes 1 m from both faces of the south wall and adds two 0.2 m jambs.
  EXPECT_NEAR(total_length(outline), 2 * (4.8 + 3.8) + 2 * (5.2 + 4.2) - 2.0 + 0.4, 1e-9);
  BlockingOptions closed;
  closed.open_doors_block = true;
  const auto closed_outline = blocking_outline(p, closed);
  EXPECT_NEAR(total_length(closed_outline), 2 * (4.8 + 3.8) + 2 * (5.2 + 4.2), 1e-9);
  int door_segments = 0;
  for (const auto& l : closed_outline) door_segments += l.label == SurfaceLabel::kDoorClosed;
  EXPECT_EQ(door_segments, 2);  // inner and outer face of the closed leaf
}

TEST(Outline, WindowIsGlassOnlyWithinItsBand) {
  FloorPlan p = test::furnished_room();
  BlockingOptions at_1_5;  // cuts the west window (0.9 .. 2.1) and the glass east wall
  int glass = 0;
  for (const auto& l : blocking_outline(p, at_1_5)) glass += l.label == SurfaceLabel::kGlass;
  EXPECT_GT(glass, 0);
  BlockingOptions low;
  low.cut_height_m = 0.05;  // below the window sill and below the glass wall's sill (0.1)
  for (const auto& l : blocking_outline(p, low)) EXPECT_NE(l.label, SurfaceLabel::kGlass);
  BlockingOptions see_through;
  see_through.glass_blocks = false;
  for (const auto& l : blocking_outline(p, see_through)) EXPECT_NE(l.label, SurfaceLabel::kGlass);
}

TEST(Outline, RandomOverlappingFootprintsAgreeWithPointTests) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 10.0), ang(0.0, 6.283), th(0.05, 0.6), len(0.5, 6.0);
  FloorPlan p;
  for (int i = 0; i < 25; ++i) {
    const Vec2 a(u(rng), u(rng));
    const double t = ang(rng);
    p.walls.push_back({"w" + std::to_string(i), a, a + len(rng) * Vec2(std::cos(t), std::sin(t)), th(rng),
                       WallMaterial::kSolid, 0.0, {}});
  }
  const auto fps = blocking_footprints(p, {});
  const auto outline = footprint_outline(fps);
  ASSERT_FALSE(outline.empty());
  expect_outline_sides(fps, outline);

  // Every boundary point of every footprint that is not inside another is on the outline.
  std::uniform_int_distribution<std::size_t> pick(0, fps.size() - 1);
  std::uniform_real_distribution<double> t01(0.0, 1.0);
  int checked = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const auto& f = fps[pick(rng)];
    const std::size_t k = std::uniform_int_distribution<std::size_t>(0, f.polygon_m.size() - 1)(rng);
    const Vec2 a = f.polygon_m[k], b = f.polygon_m[(k + 1) % f.polygon_m.size()];
    const Vec2 q = a + t01(rng) * (b - a);
    const Vec2 d = (b - a).normalized();
    const Vec2 outward(d.y(), -d.x());
    bool covered = false;
    for (const auto& g : fps)
      if (&g != &f && point_in_convex_polygon(g.polygon_m, q + 1e-5 * outward)) covered = true;
    if (covered) continue;
    double best = 1e9;
    for (const auto& l : outline) {
      const Vec2 e = l.segment_m.b_m - l.segment_m.a_m;
      const double s = std::clamp((q - l.segment_m.a_m).dot(e) / e.squaredNorm(), 0.0, 1.0);
      best = std::min(best, (l.segment_m.a_m + s * e - q).norm());
    }
    EXPECT_LT(best, 1e-7);
    ++checked;
  }
  EXPECT_GT(checked, 200);
}

// The R-tree neighbourhood (WallJoins, issue 28) against the obvious scan over every wall, at
// every wall end of generated buildings (corners, T-junctions, door jambs, thin and thick walls)
// and of the same walls cut into short collinear pieces.
TEST(WallJoins, EndJoinsEqualAScanOverEveryWall) {
  auto scan_joined = [](const FloorPlan& plan, std::size_t self, const Vec2& p) {
    for (std::size_t j = 0; j < plan.walls.size(); ++j) {
      if (j == self) continue;
      const Wall& w = plan.walls[j];
      const Vec2 d = w.b_m - w.a_m;
      const double len2 = d.squaredNorm();
      if (len2 <= 0.0) continue;
      const double t = std::clamp((p - w.a_m).dot(d) / len2, 0.0, 1.0);
      const double tol = 0.5 * std::max(w.thickness_m, plan.walls[self].thickness_m) + 0.01;
      if ((w.a_m + t * d - p).norm() <= tol) return true;
    }
    return false;
  };
  int checked = 0, joined = 0;
  for (const Archetype a : {Archetype::kOffice, Archetype::kCampus, Archetype::kAngled}) {
    FloorPlan plan = generate_building(a, 3).plan;
    // Every fifth wall cut into three pieces: many ends meeting collinear neighbours.
    const std::size_t n = plan.walls.size();
    for (std::size_t i = 0; i < n; i += 5) {
      Wall w = plan.walls[i];
      const Vec2 a0 = w.a_m, b0 = w.b_m;
      plan.walls[i].b_m = a0 + (b0 - a0) / 3.0;
      w.id += "_cut";
      w.a_m = plan.walls[i].b_m;
      plan.walls.push_back(w);
    }
    // A free-standing wall (a screen): ends that join nothing, and one within the tolerance.
    Wall screen = plan.walls.front();
    screen.id = "screen";
    screen.a_m = Vec2(500.0, 500.0);
    screen.b_m = Vec2(502.0, 500.0);
    plan.walls.push_back(screen);
    screen.id = "screen_near";
    screen.a_m = Vec2(502.0 + 0.5 * screen.thickness_m + 0.005, 500.0);
    screen.b_m = Vec2(504.0, 500.0);
    plan.walls.push_back(screen);
    const WallJoins joins(plan);
    for (std::size_t i = 0; i < plan.walls.size(); ++i) {
      for (const Vec2& p : {plan.walls[i].a_m, plan.walls[i].b_m}) {
        const bool want = scan_joined(plan, i, p);
        EXPECT_EQ(joins.end_joined(i, p), want) << archetype_name(a) << " wall " << plan.walls[i].id;
        ++checked;
        joined += want ? 1 : 0;
      }
    }
  }
  EXPECT_GT(checked, 500);
  EXPECT_GT(joined, checked / 2);  // the test meets both answers
  EXPECT_LT(joined, checked);
}

// The glass-pane index of the extrusion (issue 28) against the obvious scan it replaced: every
// window (its wall found by a scan over the walls), then every glass wall. Points: the midpoints
// of the glass outline segments the extrusion asks about, at every band, and random points in
// and around every pane (both faces, ends, the tolerance band), on generated buildings with
// windows and glass walls, their walls cut into collinear pieces, a window on an unknown wall and
// a zero-length glass wall.
TEST(Extrusion, GlassPartsEqualAScanOverEveryPane) {
  auto scan_part = [](const FloorPlan& plan, const Vec2& p) {
    int best = -1;
    double best_dist = std::numeric_limits<double>::infinity();
    auto consider = [&](int id, const Wall& wall, double t0, double t1) {
      const Vec2 dir = wall.direction();
      const double t = (p - wall.a_m).dot(dir);
      const double off = std::abs((p - wall.a_m).x() * dir.y() - (p - wall.a_m).y() * dir.x());
      const double tol = 1e-6;
      if (t < t0 - tol || t > t1 + tol || off > 0.5 * wall.thickness_m + tol) return;
      if (off < best_dist) {
        best_dist = off;
        best = id;
      }
    };
    for (std::size_t k = 0; k < plan.windows.size(); ++k) {
      const Window& w = plan.windows[k];
      const OpeningSpan s = opening_span(plan, w.wall_id, w.center_m, w.width_m);
      if (s.wall_index < 0) continue;
      consider(static_cast<int>(k), plan.walls[static_cast<std::size_t>(s.wall_index)], s.t0_m, s.t1_m);
    }
    if (best >= 0) return best;
    for (std::size_t k = 0; k < plan.walls.size(); ++k) {
      const Wall& w = plan.walls[k];
      if (w.material != WallMaterial::kGlass) continue;
      const double cap = 0.5 * w.thickness_m;
      consider(static_cast<int>(plan.windows.size() + k), w, -cap, w.length_m() + cap);
    }
    return best;
  };
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  int checked = 0, windows_hit = 0, glass_walls_hit = 0, none = 0;
  for (const Archetype a : {Archetype::kOffice, Archetype::kCampus, Archetype::kAngled}) {
    FloorPlan plan = generate_building(a, 5).plan;
    // Every third glass-free wall without openings cut in two; every seventh wall made glass.
    std::vector<char> opening(plan.walls.size(), 0);
    for (const Door& d : plan.doors) opening[static_cast<std::size_t>(std::max(0, plan.wall_index(d.wall_id)))] = 1;
    for (const Window& w : plan.windows) opening[static_cast<std::size_t>(std::max(0, plan.wall_index(w.wall_id)))] = 1;
    const std::size_t n = plan.walls.size();
    for (std::size_t i = 0; i < n; ++i) {
      if (i % 7 == 0) {
        plan.walls[i].material = WallMaterial::kGlass;
        plan.walls[i].glass_sill_m = 0.2;
      }
      if (i % 3 == 0 && !opening[i]) {
        Wall w = plan.walls[i];
        const Vec2 mid = 0.5 * (w.a_m + w.b_m);
        plan.walls[i].b_m = mid;
        w.id += "_cut";
        w.a_m = mid;
        plan.walls.push_back(w);
      }
    }
    if (!plan.walls.empty()) {
      Window lost = plan.windows.empty() ? Window{} : plan.windows.front();
      lost.id = "lost";
      lost.wall_id = "no_such_wall";
      plan.windows.push_back(lost);
      Wall dot = plan.walls.front();
      dot.id = "dot";
      dot.b_m = dot.a_m;
      dot.material = WallMaterial::kGlass;
      plan.walls.push_back(dot);
    }
    ASSERT_GT(plan.windows.size(), 1u) << archetype_name(a);
    const WallIdIndex ids(plan);
    GlassPaneIndex index(plan, ids);
    std::vector<Vec2> points;
    for (const double z : {0.5, 1.0, 1.5, 2.0, 2.5}) {
      BlockingOptions opt;
      opt.cut_height_m = z;
      for (const LabeledSegment& l : blocking_outline(plan, opt)) {
        if (l.label == SurfaceLabel::kGlass) points.push_back(0.5 * (l.segment_m.a_m + l.segment_m.b_m));
      }
    }
    auto around = [&](const Wall& w, double t0, double t1) {
      if (!(w.length_m() > 0.0)) return;
      const Vec2 dir = w.direction(), nrm(-dir.y(), dir.x());
      const double h = 0.5 * w.thickness_m;
      for (int k = 0; k < 6; ++k) {
        const double t = t0 - 0.05 + (t1 - t0 + 0.1) * u01(rng);
        const double o = (2.0 * u01(rng) - 1.0) * (h + 0.05);
        points.push_back(w.a_m + t * dir + o * nrm);
      }
      for (const double o : {-h, h}) {  // on both faces and just beyond the tolerance
        points.push_back(w.a_m + 0.5 * (t0 + t1) * dir + o * nrm);
        points.push_back(w.a_m + 0.5 * (t0 + t1) * dir + (o + (o > 0 ? 2e-6 : -2e-6)) * nrm);
      }
    };
    for (const Window& w : plan.windows) {
      const OpeningSpan s = opening_span(plan, w.wall_id, w.center_m, w.width_m);
      if (s.wall_index >= 0) around(plan.walls[static_cast<std::size_t>(s.wall_index)], s.t0_m, s.t1_m);
    }
    for (const Wall& w : plan.walls) {
      if (w.material == WallMaterial::kGlass) around(w, -0.5 * w.thickness_m, w.length_m() + 0.5 * w.thickness_m);
    }
    for (const Vec2& p : points) {
      const int want = scan_part(plan, p);
      ASSERT_EQ(index.part_id(p), want) << archetype_name(a) << " at " << p.transpose();
      ++checked;
      if (want < 0) ++none;
      else if (static_cast<std::size_t>(want) < plan.windows.size()) ++windows_hit;
      else ++glass_walls_hit;
    }
  }
  EXPECT_GT(checked, 1000);
  EXPECT_GT(windows_hit, 100);  // the test meets every answer
  EXPECT_GT(glass_walls_hit, 100);
  EXPECT_GT(none, 100);
}

TEST(Geometry, RaySegmentDistance) {
  const Segment2 s{{2.0, -3.0}, {2.0, 3.0}};
  EXPECT_NEAR(ray_segment_distance({0, 0}, {1, 0}, s), 2.0, 1e-12);
  EXPECT_LT(ray_segment_distance({0, 0}, {-1, 0}, s), 0.0);
  EXPECT_LT(ray_segment_distance({0, 0}, {0, 1}, s), 0.0);
  const Vec2 d = Vec2(1, 1).normalized();
  EXPECT_NEAR(ray_segment_distance({0, 0}, d, s), 2.0 * std::sqrt(2.0), 1e-12);
  EXPECT_LT(ray_segment_distance({0, 0}, Vec2(1, 2).normalized(), s), 0.0);  // passes above b
}

TEST(Geometry, PoseTransformsInvertEachOther) {
  const Pose2 pose{3.0, -2.0, 0.7};
  const Vec2 p(1.5, 4.0);
  EXPECT_LT((pose.inverse_transform(pose.transform(p)) - p).norm(), 1e-12);
  EXPECT_NEAR(wrap_angle_rad(3.5 * kPi), -0.5 * kPi, 1e-12);
  EXPECT_NEAR(angle_distance_rad(0.1, 2 * kPi - 0.1), 0.2, 1e-12);
}

}  // namespace
}  // namespace floorcast

namespace floorcast {
namespace {

TEST(Geometry, ClipSegmentToBoxKnownAnswers) {
  // Crossing the box: clipped to its two sides.
  Vec2 a(-1.0, 0.5), b(3.0, 0.5);
  ASSERT_TRUE(clip_segment_to_box(a, b, 0.0, 0.0, 2.0, 1.0));
  EXPECT_NEAR(a.x(), 0.0, 1e-12);
  EXPECT_NEAR(b.x(), 2.0, 1e-12);
  EXPECT_NEAR(a.y(), 0.5, 1e-12);
  // Diagonal through a corner region: clipped where it enters and leaves.
  a = Vec2(-1.0, -1.0);
  b = Vec2(3.0, 3.0);
  ASSERT_TRUE(clip_segment_to_box(a, b, 0.0, 0.0, 2.0, 1.0));
  EXPECT_NEAR((a - Vec2(0.0, 0.0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((b - Vec2(1.0, 1.0)).norm(), 0.0, 1e-12);
  // Inside: unchanged. Outside, parallel to an edge, and touching a corner (closed box).
  a = Vec2(0.5, 0.5);
  b = Vec2(1.5, 0.25);
  ASSERT_TRUE(clip_segment_to_box(a, b, 0.0, 0.0, 2.0, 1.0));
  EXPECT_EQ(a, Vec2(0.5, 0.5));
  EXPECT_EQ(b, Vec2(1.5, 0.25));
  a = Vec2(-1.0, 2.0);
  b = Vec2(3.0, 2.0);
  EXPECT_FALSE(clip_segment_to_box(a, b, 0.0, 0.0, 2.0, 1.0));
  a = Vec2(2.0, 2.0);
  b = Vec2(3.0, 1.0);
  EXPECT_TRUE(clip_segment_to_box(a, b, 0.0, 0.0, 2.0, 1.0) == false);
  a = Vec2(1.0, 2.0);
  b = Vec2(3.0, 0.0);
  ASSERT_TRUE(clip_segment_to_box(a, b, 0.0, 0.0, 2.0, 1.0));
  EXPECT_NEAR((a - Vec2(2.0, 1.0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((b - Vec2(2.0, 1.0)).norm(), 0.0, 1e-12);
}

// The extrusion's faces grouped into planes: a box room with a door in its south wall is 4 inner
// and 4 outer wall sides (the inner south side with its lintel and the jambs' neighbours joined,
// the door opening a hole below the lintel), the door's jambs and soffit, the floor and the
// ceiling; every face in exactly one plane, the plane's offset that of its faces.
TEST(Extrusion, CoplanarFacesGroupIntoConnectedPlanes) {
  FloorPlan p = test::box_room(6.0, 4.0, 0.2);
  p.doors.push_back({"d", "south", {3.0, 0.0}, 1.0, false});
  const std::vector<ExtrudedFace> faces = extrude_faces(p);
  const std::vector<ExtrudedPlane> planes = group_coplanar_faces(faces);
  std::vector<int> seen(faces.size(), 0);
  int floors = 0, ceilings = 0, inner_south = 0;
  for (const ExtrudedPlane& pl : planes) {
    for (int f : pl.faces) {
      ++seen[static_cast<std::size_t>(f)];
      EXPECT_NEAR(pl.normal.dot(faces[static_cast<std::size_t>(f)].polygon_m[0].cast<double>()), pl.offset_m, 1e-5);
      EXPECT_NEAR((faces[static_cast<std::size_t>(f)].outward.cast<double>() - pl.normal).norm(), 0.0, 1e-6);
    }
    floors += pl.label == MeshLabel::kFloor;
    ceilings += pl.label == MeshLabel::kCeiling;
    // The inner side of the south wall (y = 0.1, facing +y): one plane of three faces (left of
    // the door, right of it, the lintel above it).
    if (pl.label == MeshLabel::kWall && pl.normal.y() > 0.99 && std::abs(pl.offset_m - 0.1) < 1e-6) {
      ++inner_south;
      EXPECT_EQ(pl.faces.size(), 3u);
    }
  }
  for (int n : seen) EXPECT_EQ(n, 1);
  EXPECT_EQ(floors, 1);
  EXPECT_EQ(ceilings, 1);
  EXPECT_EQ(inner_south, 1);
  // Two coplanar but separate faces stay two planes: the outer sides of two rooms in a row.
  FloorPlan two = test::box_room(4.0, 4.0, 0.2);
  FloorPlan other = test::box_room(4.0, 4.0, 0.2);
  for (Wall& w : other.walls) {
    w.a_m.x() += 10.0;
    w.b_m.x() += 10.0;
    w.id += "_b";
    two.walls.push_back(w);
  }
  int outer_south = 0;
  for (const ExtrudedPlane& pl : group_coplanar_faces(extrude_faces(two))) {
    outer_south += pl.label == MeshLabel::kWall && pl.normal.y() < -0.99 && std::abs(pl.offset_m - 0.1) < 1e-6;
  }
  EXPECT_EQ(outer_south, 2);
}

}  // namespace
}  // namespace floorcast
