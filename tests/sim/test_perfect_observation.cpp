#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "floorcast/floorplans/io.hpp"
#include "floorcast/sim/perfect_observation.hpp"
#include "floorcast/core/math.hpp"

namespace floorcast {
namespace {


FloorPlan room(double w, double h, double t) {
  FloorPlan p;
  p.walls = {{"s", {0, 0}, {w, 0}, t, WallMaterial::kSolid, 0.0, {}},
             {"e", {w, 0}, {w, h}, t, WallMaterial::kSolid, 0.0, {}},
             {"n", {w, h}, {0, h}, t, WallMaterial::kSolid, 0.0, {}},
             {"w", {0, h}, {0, 0}, t, WallMaterial::kSolid, 0.0, {}}};
  return p;
}

bool segments_touch(const Vec2& p, const Vec2& q, const Vec2& r, const Vec2& s) {
  auto orient = [](const Vec2& a, const Vec2& b, const Vec2& c) {
    return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
  };
  const double d1 = orient(r, s, p), d2 = orient(r, s, q), d3 = orient(p, q, r), d4 = orient(p, q, s);
  // Closed test: proper crossings and touchings count (collinear overlaps are not needed here).
  return ((d1 > 0) != (d2 > 0) || d1 == 0 || d2 == 0) && ((d3 > 0) != (d4 > 0) || d3 == 0 || d4 == 0);
}

/// Brute force: p is visible from o iff within range and the sight line (stopped just short of p)
/// meets no outline segment.
bool visible_brute(const std::vector<LabeledSegment>& outline, const Vec2& o, const Vec2& p, double range) {
  if ((p - o).norm() > range - 1e-7) return false;
  const Vec2 stop = p - 1e-6 * (p - o).normalized();
  for (const auto& l : outline)
    if (segments_touch(o, stop, l.segment_m.a_m, l.segment_m.b_m)) return false;
  return true;
}

double distance_to_set(const std::vector<LabeledSegment>& segs, const Vec2& q) {
  double best = 1e18;
  for (const auto& l : segs) {
    const Vec2 e = l.segment_m.b_m - l.segment_m.a_m;
    const double s = std::clamp((q - l.segment_m.a_m).dot(e) / e.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (l.segment_m.a_m + s * e - q).norm());
  }
  return best;
}

void check_against_brute_force(const FloorPlan& plan, const PerfectObservationParams& params, const Vec2& o) {
  const PerfectObserver observer(plan, params);
  const auto visible = observer.visible_world_segments(o);
  const auto& outline = observer.outline();
  // Soundness: every output point is visible and lies on the outline, free space on its left.
  for (const auto& v : visible) {
    const Vec2 d = (v.segment_m.b_m - v.segment_m.a_m).normalized();
    for (int k = 0; k < 10; ++k) {
      const Vec2 p = v.segment_m.a_m + (k + 0.5) / 10.0 * (v.segment_m.b_m - v.segment_m.a_m);
      EXPECT_TRUE(visible_brute(outline, o, p, params.max_range_m + 1e-6)) << p.transpose();
      EXPECT_LT(distance_to_set(outline, p), 1e-9);
      EXPECT_GT(-d.y() * (o - p).x() + d.x() * (o - p).y(), 0.0) << "observer not on the free side";
    }
  }
  // Completeness: every visible outline point (sampled every 2 cm) is covered by the output.
  int visible_samples = 0;
  for (const auto& l : outline) {
    const double len = l.segment_m.length_m();
    const int n = std::max(1, static_cast<int>(len / 0.02));
    for (int k = 0; k < n; ++k) {
      const Vec2 p = l.segment_m.a_m + (k + 0.5) / n * (l.segment_m.b_m - l.segment_m.a_m);
      if (!visible_brute(outline, o, p, params.max_range_m)) continue;
      ++visible_samples;
      EXPECT_LT(distance_to_set(visible, p), 1e-7) << "missed visible point " << p.transpose();
    }
  }
  EXPECT_GT(visible_samples, 10);
}

TEST(PerfectObservation, BoxRoomCentreSeesFourInnerFacesAndExactRays) {
  const FloorPlan plan = room(6.0, 4.0, 0.2);
  PerfectObservationParams params;
  params.num_rays = 4;
  const PerfectObserver observer(plan, params);
  const Observation2D obs = observer.observe({3.0, 2.0, 0.0});
  ASSERT_EQ(obs.segments_m.size(), 4u);
  double total = 0.0;
  for (const auto& s : obs.segments_m) total += s.length_m();
  EXPECT_NEAR(total, 2 * (5.8 + 3.8), 1e-9);
  ASSERT_EQ(obs.ray_ranges_m.size(), 4u);
  EXPECT_NEAR(obs.ray_ranges_m[0], 2.9, 1e-12);  // +x
  EXPECT_NEAR(obs.ray_ranges_m[1], 1.9, 1e-12);  // +y
  EXPECT_NEAR(obs.ray_ranges_m[2], 2.9, 1e-12);
  EXPECT_NEAR(obs.ray_ranges_m[3], 1.9, 1e-12);
  // Observer-frame output rotates with the heading.
  const Observation2D turned = observer.observe({3.0, 2.0, kPi / 2});
  EXPECT_NEAR(turned.ray_ranges_m[0], 1.9, 1e-12);
}

// Perfect 3-D planes from the centre of a 6 x 4 m box (walls 0.2 m thick, 3 m high, camera at
// 1.5 m): the four inner wall sides, the floor and the ceiling, at their exact distances, with
// their full visible areas (up to the cell grid).
TEST(PerfectObservation, PerfectPlanesOfABoxRoom) {
  const FloorPlan plan = room(6.0, 4.0, 0.2);
  PerfectObservationParams params;
  params.num_rays = 0;
  const PerfectObserver observer(plan, params);
  const Observation2D obs = observer.observe({3.0, 2.0, 0.3});
  ASSERT_EQ(obs.planes.size(), 6u);
  int walls = 0;
  for (const PlanePatch& p : obs.planes) {
    EXPECT_NEAR(p.normal.norm(), 1.0, 1e-12);
    EXPECT_LE(p.offset_m, 0.0);
    const double area = patch_area_m2(p, obs.plane_cell_m);
    if (std::abs(p.normal.z()) > 0.99) {
      // Floor 1.5 m below and ceiling 1.5 m above the camera, 5.8 x 3.8 m of each visible.
      EXPECT_NEAR(p.offset_m, -1.5, 1e-6);
      EXPECT_NEAR(area, 5.8 * 3.8, 3.5);  // cells cut by the boundary count whole
      continue;
    }
    ++walls;
    EXPECT_NEAR(std::abs(p.normal.z()), 0.0, 1e-6);
    // Inner sides 2.9 m (east, west) or 1.9 m (north, south) from the observer; 3 m high.
    const bool long_side = std::abs(p.offset_m + 1.9) < 1e-6;  // faces are stored as floats
    EXPECT_TRUE(long_side || std::abs(p.offset_m + 2.9) < 1e-6) << p.offset_m;
    EXPECT_NEAR(area, (long_side ? 5.8 : 3.8) * 3.0, 2.5);
  }
  EXPECT_EQ(walls, 4);
  // The observer frame turns with the heading: the patch normals are the world normals turned by -yaw.
  const Observation2D turned = observer.observe({3.0, 2.0, 0.3 + kPi / 2});
  ASSERT_EQ(turned.planes.size(), 6u);
  for (std::size_t i = 0; i < obs.planes.size(); ++i) {
    const Eigen::Vector3d n = obs.planes[i].normal;
    bool found = false;
    for (const PlanePatch& q : turned.planes) found |= (q.normal - Eigen::Vector3d(n.y(), -n.x(), n.z())).norm() < 1e-9;
    EXPECT_TRUE(found) << n.transpose();
  }
  // A wall between the observer and a face hides it: in two rooms, only the observer's room.
  FloorPlan two = room(8.0, 4.0, 0.2);
  two.walls.push_back({"m", {4, 0}, {4, 4}, 0.2, WallMaterial::kSolid, 0.0, {}});
  const Observation2D one_room = PerfectObserver(two, params).observe({2.0, 2.0, 0.0});
  for (const PlanePatch& p : one_room.planes) {
    EXPECT_LT(p.centroid_m.x(), 2.0 + 1e-6) << "a plane of the other room is visible";
  }
}

TEST(PerfectObservation, RangeLimitClipsFaces) {
  const FloorPlan plan = room(30.0, 4.0, 0.2);
  PerfectObservationParams params;
  params.max_range_m = 10.0;
  const PerfectObserver observer(plan, params);
  const Vec2 o(15.0, 2.0);
  for (const auto& s : observer.visible_world_segments(o)) {
    EXPECT_LE((s.segment_m.a_m - o).norm(), 10.0 + 1e-9);
    EXPECT_LE((s.segment_m.b_m - o).norm(), 10.0 + 1e-9);
  }
  check_against_brute_force(plan, params, o);
  const Observation2D obs = observer.observe({15.0, 2.0, 0.0});
  EXPECT_DOUBLE_EQ(obs.ray_ranges_m[0], 10.0);  // along the corridor: no return within range
}

TEST(PerfectObservation, DoorsClosedFlag) {
  FloorPlan plan = room(6.0, 4.0, 0.2);
  plan.doors.push_back({"d", "e", {6.0, 2.0}, 1.0, false});
  plan.walls.push_back({"far", {9.0, -3.0}, {9.0, 7.0}, 0.2, WallMaterial::kSolid, 0.0, {}});
  PerfectObservationParams closed;
  closed.num_rays = 36;
  PerfectObservationParams open = closed;
  open.blocking.open_doors_block = false;
  const Observation2D c = PerfectObserver(plan, closed).observe({3.0, 2.0, 0.0});
  const Observation2D o = PerfectObserver(plan, open).observe({3.0, 2.0, 0.0});
  EXPECT_NEAR(c.ray_ranges_m[0], 2.9, 1e-9);   // the closed leaf
  EXPECT_NEAR(o.ray_ranges_m[0], 5.9, 1e-9);   // through the doorway to the far wall
  check_against_brute_force(plan, open, {3.0, 2.0});
  check_against_brute_force(plan, closed, {3.0, 2.0});
}

TEST(PerfectObservation, EqualsBruteForceInClutteredPlans) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(1.0, 19.0), ang(0.0, 2 * kPi), len(0.5, 5.0), th(0.05, 0.3);
  for (int trial = 0; trial < 5; ++trial) {
    FloorPlan plan = room(20.0, 20.0, 0.2);
    for (int i = 0; i < 20; ++i) {
      const Vec2 a(u(rng), u(rng));
      const double t = ang(rng);
      Vec2 b = a + len(rng) * Vec2(std::cos(t), std::sin(t));
      b = b.cwiseMax(Vec2(0.5, 0.5)).cwiseMin(Vec2(19.5, 19.5));
      if ((b - a).norm() < 0.1) continue;
      plan.walls.push_back({"r" + std::to_string(i), a, b, th(rng), WallMaterial::kSolid, 0.0, {}});
    }
    plan.obstacles.push_back({"p", ObstacleKind::kPillar, {u(rng), u(rng)}, {0.6, 0.6}, 0.0, 3.0});
    PerfectObservationParams params;
    params.blocking.obstacles_block = true;
    params.max_range_m = trial % 2 ? 10.0 : 30.0;
    const PerfectObserver observer(plan, params);
    // A free observer position: away from every footprint.
    const auto fps = blocking_footprints(plan, {true, true, true, true, 1.5});
    int placed = 0;
    for (int attempt = 0; attempt < 200 && placed < 3; ++attempt) {
      const Vec2 o(u(rng), u(rng));
      bool free = true;
      for (const auto& f : fps)
        for (double dx : {-0.2, 0.0, 0.2})
          for (double dy : {-0.2, 0.0, 0.2})
            if (point_in_convex_polygon(f.polygon_m, o + Vec2(dx, dy))) free = false;
      if (!free) continue;
      ++placed;
      check_against_brute_force(plan, params, o);
      // Rays agree with the visible segments.
      const auto rays = observer.ray_ranges(o, 0.0, 72);
      const auto vis = observer.visible_world_segments(o);
      for (int i = 0; i < 72; ++i) {
        const double a = 2 * kPi * i / 72;
        double best = params.max_range_m;
        for (const auto& v : vis) {
          const double t = ray_segment_distance(o, {std::cos(a), std::sin(a)}, v.segment_m);
          if (t >= 0) best = std::min(best, t);
        }
        EXPECT_NEAR(rays[static_cast<std::size_t>(i)], best, 1e-7) << "ray " << i;
      }
    }
    EXPECT_EQ(placed, 3);
  }
}

TEST(PerfectObservation, ShippedPlanMatchesBruteForce) {
  const FloorPlan plan = load_floor_plan(std::string(FLOORCAST_SOURCE_DIR) + "/floorplans/buildings/two_rooms.json");
  PerfectObservationParams params;
  check_against_brute_force(plan, params, {2.5, 2.5});
  check_against_brute_force(plan, params, {6.5, 2.5});
  params.blocking.open_doors_block = false;
  params.blocking.glass_blocks = false;
  check_against_brute_force(plan, params, {6.5, 4.2});
}

}  // namespace
}  // namespace floorcast
