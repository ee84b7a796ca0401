// The VoxelPlane-Reloc plane matcher: map planes from the extrusion, the transform solvers
// against independent solutions, known answers on a box room and an L-shaped room (true pose up
// to the room's symmetry, all symmetric poses in the top-K), rejection of a scan from another
// building, and the brute-force all-triplets search against the pruned one.
#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <cmath>

#include "floorcast/core/math.hpp"
#include "floorcast/match/plane_matcher.hpp"
#include "floorcast/sim/perfect_observation.hpp"
#include "match_test_plans.hpp"

namespace floorcast {
namespace {

/// A closed room from a polygon (counter-clockwise corners), walls 0.15 m thick.
FloorPlan room(const std::vector<Vec2>& corners, const char* name) {
  FloorPlan p;
  p.name = name;
  for (std::size_t k = 0; k < corners.size(); ++k) {
    const Vec2& a = corners[k];
    const Vec2& b = corners[(k + 1) % corners.size()];
    p.walls.push_back(test::wall(("w" + std::to_string(k)).c_str(), a.x(), a.y(), b.x(), b.y()));
  }
  return p;
}

FloorPlan box_room() { return room({{0, 0}, {6, 0}, {6, 4}, {0, 4}}, "box"); }
FloorPlan l_room() { return room({{0, 0}, {8, 0}, {8, 3}, {3.5, 3}, {3.5, 6.5}, {0, 6.5}}, "l_room"); }

Observation2D perfect_planes(const FloorPlan& plan, const Pose2& pose) {
  PerfectObservationParams p;
  p.num_rays = 0;
  return PerfectObserver(plan, p).observe(pose);
}

double pose_error_m(const PoseHypothesis& h, const Pose2& t) { return std::hypot(h.x_m - t.x_m, h.y_m - t.y_m); }
double yaw_error_deg(const PoseHypothesis& h, const Pose2& t) { return rad_to_deg(angle_distance_rad(h.yaw_rad, t.yaw_rad)); }

/// The first mode within 0.05 m and 1 deg of `truth`, or -1.
int rank_of(const std::vector<PoseHypothesis>& modes, const Pose2& truth) {
  for (std::size_t i = 0; i < modes.size(); ++i) {
    if (pose_error_m(modes[i], truth) <= 0.05 && yaw_error_deg(modes[i], truth) <= 1.0) return static_cast<int>(i);
  }
  return -1;
}

TEST(PlaneMap, BoxRoomHasItsWallSidesFloorAndCeiling) {
  const PlaneMap map = build_plane_map(box_room(), PlaneMatcherParams{});
  // Four inner and four outer wall sides, the floor and the ceiling.
  ASSERT_EQ(map.planes.size(), 10u);
  ASSERT_EQ(map.floors.size(), 1u);
  EXPECT_EQ(map.walls.size(), 8u);
  int inner = 0;
  for (const MapPlane& p : map.planes) {
    if (p.kind == PlaneKind::kGround) {
      EXPECT_NEAR(p.offset_m, 0.0, 1e-9);
      EXPECT_NEAR(p.normal.z(), 1.0, 1e-9);
    }
    if (p.kind == PlaneKind::kCeiling) {
      EXPECT_NEAR(-p.offset_m, 3.0, 1e-6);
    }
    if (p.kind != PlaneKind::kWall) continue;
    // Inner sides face the room centre and lie 0.075 m inside the wall axis.
    const double side = p.normal.dot(Eigen::Vector3d(3.0, 2.0, 1.5)) - p.offset_m;
    if (side > 0.0) {
      ++inner;
      EXPECT_TRUE(std::abs(side - 2.925) < 1e-6 || std::abs(side - 1.925) < 1e-6) << side;
      // A full-height 3 m side of a 6 m or 4 m wall: 12 rows of 0.25 m cells, 23-24 or 15-16 columns.
      EXPECT_GE(p.cells, 12 * 15);
      EXPECT_NEAR(p.radius_m, 0.5 * std::hypot(std::abs(side - 2.925) < 1e-6 ? 3.85 : 5.85, 3.0), 0.3);
    }
  }
  EXPECT_EQ(inner, 4);
}

TEST(PlaneMap, DoorsOpenOrClosedAsTheBlockingSays) {
  FloorPlan p = box_room();
  p.doors.push_back({"d", "w0", {3.0, 0.0}, 1.0, false});
  PlaneMatcherParams closed;
  PlaneMatcherParams open;
  open.blocking.open_doors_block = false;
  const PlaneMap a = build_plane_map(p, closed), b = build_plane_map(p, open);
  // The inner side of the south wall: full with the door drawn closed, holed (1 m x 2.1 m less)
  // with it open.
  auto south_inner = [](const PlaneMap& m) {
    for (const MapPlane& q : m.planes) {
      if (q.kind == PlaneKind::kWall && q.normal.y() > 0.99 && q.offset_m > 0.0) return q.cells;
    }
    return -1;
  };
  EXPECT_GT(south_inner(a), south_inner(b));
  EXPECT_NEAR((south_inner(a) - south_inner(b)) * 0.0625, 1.0 * 2.1, 0.4);
}

TEST(PlaneSolvers, QuaternionRotationAndLeastSquaresTranslationAgreeWithSvdReferences) {
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.3, -0.5, 0.8).normalized())).toRotationMatrix();
  const Eigen::Vector3d t(1.5, -2.0, 0.4);
  std::vector<Eigen::Vector3d> ns = {Eigen::Vector3d(1, 0.2, 0).normalized(), Eigen::Vector3d(-0.1, 1, 0.3).normalized(),
                                     Eigen::Vector3d(0.2, 0.1, 1).normalized(), Eigen::Vector3d(1, 1, 1).normalized()};
  std::vector<Eigen::Vector3d> nm;
  std::vector<double> ds = {-1.0, -2.5, 0.3, 1.2}, dm;
  for (std::size_t k = 0; k < ns.size(); ++k) {
    nm.push_back(R * ns[k]);
    dm.push_back(ds[k] + nm.back().dot(t));
  }
  EXPECT_LT((rotation_from_normals(ns, nm) - R).norm(), 1e-9);
  EXPECT_LT((translation_from_offsets(nm, dm, ds) - t).norm(), 1e-9);
  // With noise: Horn's quaternion optimum equals the SVD (Kabsch) optimum of the same objective.
  std::vector<Eigen::Vector3d> noisy = nm;
  noisy[0] = (noisy[0] + Eigen::Vector3d(0.02, -0.01, 0.015)).normalized();
  noisy[2] = (noisy[2] + Eigen::Vector3d(-0.01, 0.03, 0.0)).normalized();
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (std::size_t k = 0; k < ns.size(); ++k) H += ns[k] * noisy[k].transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() > 0 ? 1.0 : -1.0;
  const Eigen::Matrix3d kabsch = svd.matrixV() * D * svd.matrixU().transpose();
  EXPECT_LT((rotation_from_normals(ns, noisy) - kabsch).norm(), 1e-9);
}

TEST(PlaneSolvers, GravityAlignedTransformFromGroundAndTwoWalls) {
  PlaneMatcherParams params;
  const PlaneMap map = build_plane_map(box_room(), params);
  const Pose2 truth{1.7, 1.1, 0.4};
  const Observation2D obs = perfect_planes(box_room(), truth);
  // Pair every observed plane with the map plane it is (by construction of the truth).
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(truth.yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(truth.x_m, truth.y_m, 1.5);
  std::vector<PlanePatch> s;
  std::vector<const MapPlane*> m;
  for (const PlanePatch& p : obs.planes) {
    const PlanePatch w = transform_patch(p, T);
    for (const MapPlane& q : map.planes) {
      if (q.normal.dot(w.normal) > 0.9999 && std::abs(q.offset_m - w.offset_m) < 1e-6) {
        s.push_back(p);
        m.push_back(&q);
      }
    }
  }
  ASSERT_EQ(s.size(), 6u);  // floor, ceiling, four walls
  const Eigen::Isometry3d est = gravity_aligned_transform(s, m);
  EXPECT_LT((est.translation() - T.translation()).norm(), 1e-9);
  EXPECT_LT((est.linear() - T.linear()).norm(), 1e-9);
}

TEST(PlaneMatcher, BoxRoomFindsBothSymmetricPoses) {
  const FloorPlan plan = box_room();
  const PlaneMatcher m(plan);
  for (const Pose2& truth : {Pose2{1.7, 1.1, 0.4}, Pose2{4.2, 2.9, -2.3}}) {
    const MatchResult r = m.match(perfect_planes(plan, truth), MatchRequest::modes(5));
    ASSERT_TRUE(r.has_pose());
    // A 6 x 4 m box looks the same turned by 180 degrees about its centre.
    const Pose2 twin{6.0 - truth.x_m, 4.0 - truth.y_m, wrap_angle_rad(truth.yaw_rad + kPi)};
    const int a = rank_of(r.modes, truth), b = rank_of(r.modes, twin);
    EXPECT_GE(a, 0) << "true pose not in the top-5";
    EXPECT_GE(b, 0) << "symmetric pose not in the top-5";
    EXPECT_LE(std::max(a, b), 1) << "the two symmetric poses are the two best modes";
    EXPECT_NEAR(r.modes[0].score, r.modes[1].score, 1e-3 * r.modes[0].score);
  }
}

TEST(PlaneMatcher, LShapedRoomFindsTheTruePose) {
  const FloorPlan plan = l_room();
  const PlaneMatcher m(plan);
  for (const Pose2& truth : {Pose2{1.6, 1.4, 0.7}, Pose2{6.5, 1.2, 2.8}, Pose2{1.5, 5.0, -1.2}}) {
    const MatchResult r = m.match(perfect_planes(plan, truth), MatchRequest::modes(3));
    ASSERT_TRUE(r.has_pose()) << truth.x_m << " " << truth.y_m;
    EXPECT_LE(pose_error_m(r.modes[0], truth), 0.05);
    EXPECT_LE(yaw_error_deg(r.modes[0], truth), 1.0);
    EXPECT_GT(r.counters.at("hypotheses_accepted"), 0.0);
  }
}

TEST(PlaneMatcher, ScanOfAnotherBuildingIsRejected) {
  // Observations in the L-shaped room and in a 9 x 2.5 m corridor, matched against the box room:
  // no triplet passes the evaluation, so the answer is "not localized" (no modes).
  const PlaneMatcher box(box_room());
  const FloorPlan corridor = room({{0, 0}, {9, 0}, {9, 2.5}, {0, 2.5}}, "corridor");
  for (const Observation2D& obs : {perfect_planes(l_room(), {1.6, 1.4, 0.7}), perfect_planes(corridor, {4.0, 1.2, 0.3})}) {
    ASSERT_GE(obs.planes.size(), 5u);
    const MatchResult r = box.match(obs);
    EXPECT_FALSE(r.has_pose());
    ASSERT_NO_THROW(r.posterior.check());
    EXPECT_EQ(r.posterior.total(), 0.0);
  }
  // ... and the box room's own observation is not rejected by the L-shaped room either way round.
  const PlaneMatcher l(l_room());
  EXPECT_FALSE(l.match(perfect_planes(box_room(), {1.7, 1.1, 0.4})).has_pose());
}

TEST(PlaneMatcher, BruteForceFindsTheSameBestPose) {
  for (const FloorPlan& plan : {box_room(), l_room()}) {
    const PlaneMatcher m(plan);
    const Observation2D obs = perfect_planes(plan, {1.6, 1.4, 0.7});
    const std::vector<PlaneHypothesis> pruned = m.hypotheses(obs, false);
    const std::vector<PlaneHypothesis> brute = m.hypotheses(obs, true);
    ASSERT_FALSE(pruned.empty());
    ASSERT_GE(brute.size(), pruned.size());
    auto best = [](const std::vector<PlaneHypothesis>& hs) {
      return *std::max_element(hs.begin(), hs.end(), [](const PlaneHypothesis& a, const PlaneHypothesis& b) { return a.density < b.density; });
    };
    // The same best pose up to the room's symmetry: every pruned maximum is a brute-force one.
    const Pose2 a = planar_pose(best(pruned).T_world_observer), b = planar_pose(best(brute).T_world_observer);
    double best_density = best(brute).density, nearest = 1e9;
    for (const PlaneHypothesis& h : brute) {
      if (h.density < best_density * (1.0 - 1e-6)) continue;
      const Pose2 v = planar_pose(h.T_world_observer);
      nearest = std::min(nearest, std::hypot(v.x_m - a.x_m, v.y_m - a.y_m) + angle_distance_rad(v.yaw_rad, a.yaw_rad));
    }
    EXPECT_LT(nearest, 1e-6) << plan.name << ": pruned best " << a.x_m << ", " << a.y_m << "; brute best " << b.x_m << ", " << b.y_m;
  }
}

TEST(PlaneMatcher, NoPlanesNoPose) {
  const PlaneMatcher m(box_room());
  Observation2D empty;
  const MatchResult r = m.match(empty);
  EXPECT_FALSE(r.has_pose());
  EXPECT_EQ(r.posterior.num_slices(), m.params().yaw_bins);
}

}  // namespace
}  // namespace floorcast
