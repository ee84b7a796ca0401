// The observation module on scans from the simulator (Embree renderer, sensor models), end to end
// with the kernel matcher.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "floorcast/floorplans/io.hpp"
#include "floorcast/scenarios/sampling.hpp"
#include "floorcast/match/matcher.hpp"
#include "floorcast/eval/observation_accuracy.hpp"
#include "floorcast/observe/observation_module.hpp"
#include "floorcast/sim/mesh.hpp"
#include "floorcast/sim/perfect_observation.hpp"
#include "floorcast/sim/ray_scene.hpp"
#include "floorcast/sim/scan_sim.hpp"
#include "floorcast/core/math.hpp"
#include "segment_checks.hpp"

namespace floorcast {
namespace {


struct Building {
  FloorPlan plan;
  std::unique_ptr<RayScene> scene;
};

const Building& two_rooms() {
  static const Building b = [] {
    Building x;
    x.plan = load_floor_plan(std::string(FLOORCAST_SOURCE_DIR) + "/floorplans/buildings/two_rooms.json");
    x.scene = std::make_unique<RayScene>(extrude_plan(x.plan));
    return x;
  }();
  return b;
}

TEST(ObserveSim, InjectedScalesRecoveredOnAPerfectDepthScan) {
  const Building& b = two_rooms();
  ScanParams sp = scan_preset("perfect");
  sp.seed = 5;
  Scan scan = simulate_scan(*b.scene, {2.4, 2.2, 0.4}, sp).scan;
  const std::vector<double> injected = {1.0, 0.8, 1.25, 0.9, 1.15, 0.85};
  for (std::size_t k = 0; k < scan.views.size(); ++k) scan.views[k].depth_m *= injected[k];
  for (const bool ray_init : {true, false}) {
    ObservationParams p;
    p.scale.ray_ratio_init = ray_init;  // false: PALMS+ (start at 1)
    const ObservationResult r = observe_scan(scan, p);
    ASSERT_EQ(r.diagnostics.view_scales.size(), 6u);
    for (std::size_t k = 0; k < 6; ++k) {
      EXPECT_NEAR(r.diagnostics.view_scales[k] * injected[k], 1.0, 0.03)
          << "view " << k << (ray_init ? " (ray init)" : " (start at 1)") << ": " << r.diagnostics.relative.status;
    }
    EXPECT_NEAR(r.diagnostics.ground_height_after_m, -1.5, 0.02);
  }
}

TEST(ObserveSim, GroundHeightWithinTwoCentimetres) {
  const Building& b = two_rooms();
  for (const double cam_h : {1.3, 1.5, 1.7}) {
    ScanParams sp = scan_preset("perfect");
    sp.geometry.camera_height_m = cam_h;
    const Scan scan = simulate_scan(*b.scene, {6.5, 2.6, 1.0}, sp).scan;
    ObservationParams p;
    p.scale.mode = ScaleAlignment::kNone;
    const ObservationResult r = observe_scan(scan, p);
    ASSERT_TRUE(r.diagnostics.ground.found) << r.diagnostics.ground.reason;
    EXPECT_NEAR(r.diagnostics.ground.height_m, -cam_h, 0.02);
  }
}

TEST(ObserveSim, PerfectScanSegmentsLieOnVisibleWalls) {
  const Building& b = two_rooms();
  const Pose2 pose{2.4, 2.2, 0.4};
  const Scan scan = simulate_scan(*b.scene, pose, scan_preset("perfect")).scan;
  const ObservationResult r = observe_scan(scan, ObservationParams{});
  // Everything a horizontal cut at camera height meets: walls, glass, door leaves, the pillar.
  PerfectObservationParams pp;
  pp.blocking.open_doors_block = false;
  pp.blocking.obstacles_block = true;
  pp.max_range_m = 30.0;
  const std::vector<Segment2> truth = test::join_collinear(PerfectObserver(b.plan, pp).observe(pose).segments_m);
  const test::WallMatch m = test::match_walls(r.observation.segments_m, truth, 0.05, 1.0);
  EXPECT_TRUE(m.stray.empty()) << m.stray.size() << " stray, first: " << (m.stray.empty() ? "" : m.stray[0]);
  // The long walls of the room the observer stands in are covered.
  double covered = 0.0, total = 0.0;
  for (std::size_t w = 0; w < truth.size(); ++w) {
    if (truth[w].length_m() < 1.0) continue;
    covered += m.coverage[w] * truth[w].length_m();
    total += truth[w].length_m();
  }
  EXPECT_GT(covered / total, 0.8);
}

const Building& apartment() {
  static const Building b = [] {
    Building x;
    x.plan = load_floor_plan(std::string(FLOORCAST_SOURCE_DIR) + "/floorplans/buildings/apartment.json");
    x.scene = std::make_unique<RayScene>(extrude_plan(x.plan));
    return x;
  }();
  return b;
}

/// Simulate -> observe -> kernel matcher at a distinctive spot of the shipped apartment (a room
/// off the main living area, door and corners in view). Returns the position error, or a large
/// value when the yaw is off by more than 30 deg.
double localisation_error(const Scan& scan, const Pose2& truth, const ObservationParams& p) {
  const ObservationResult r = observe_scan(scan, p);
  if (r.observation.segments_m.size() < 3) return 1e9;
  static const auto matcher = make_matcher("kernel", apartment().plan);
  const PoseHypothesis h = matcher->match(r.observation).posterior.argmax();
  if (angle_distance_rad(h.yaw_rad, truth.yaw_rad) > 30.0 * kPi / 180.0) return 1e9;
  return std::hypot(h.x_m - truth.x_m, h.y_m - truth.y_m);
}

const std::vector<Pose2>& distinctive_poses() {
  static const std::vector<Pose2> poses = {{5.25, 8.75, 0.0}, {5.25, 8.75, 2.4}, {5.0, 8.5, 1.8}};
  return poses;
}

TEST(ObserveSim, MonoScanLocalisesWithTheKernelMatcher) {
  // Realistic monocular depth (per-view scale, warp, noise, flying pixels, glass): PALMS+ itself
  // is right about a third of the time on its campus data; here at least 2 of 3 scans of the
  // spot (different headings and noise seeds) must localise within 1 m and 30 deg. The
  // measured rate over 12 headings/seeds at this spot is 9/12 (localization/observe/README.md).
  int ok = 0;
  for (std::size_t k = 0; k < distinctive_poses().size(); ++k) {
    const Pose2& truth = distinctive_poses()[k];
    ScanParams sp = scan_preset("mono");
    sp.seed = 30 + k;
    const double err = localisation_error(simulate_scan(*apartment().scene, truth, sp).scan, truth, ObservationParams{});
    ok += err < 1.0 ? 1 : 0;
  }
  EXPECT_GE(ok, 2);
}

TEST(ObserveSim, LidarScanLocalisesWithTheKernelMatcher) {
  for (std::size_t k = 0; k < 2; ++k) {
    const Pose2& truth = distinctive_poses()[k];
    ScanParams sp = scan_preset("lidar");
    sp.seed = 40 + k;
    const Scan scan = simulate_scan(*apartment().scene, truth, sp).scan;
    for (const PlaneExtractorKind kind : {PlaneExtractorKind::kPclRegionGrowing, PlaneExtractorKind::kVoxelPlane}) {
      ObservationParams p;
      p.path = ObservationPath::kLidar;
      p.lidar.extractor = kind;
      EXPECT_LT(localisation_error(scan, truth, p), 1.0) << to_string(kind) << " pose " << k;
    }
  }
}

/// Simulated iPhone-LiDAR scans (5 m range, 18 views) at the CI gate's six first apartment poses,
/// observed with the LiDAR path, against the walls visible within 5 m (doors as in the plan):
/// overall and without glass (which the LiDAR mostly does not return).
struct LidarWallScores {
  SegmentAccuracy all, opaque;
};
LidarWallScores lidar_wall_scores(const LidarPathParams& lidar) {
  const Building& b = apartment();
  PerfectObservationParams pp;
  pp.max_range_m = 5.0;
  pp.blocking.open_doors_block = false;
  pp.num_rays = 0;
  const PerfectObserver observer(b.plan, pp);
  LidarWallScores out;
  const std::vector<Pose2> poses = sample_observation_poses(b.plan, 6, 21, 0, 0.5);
  for (std::size_t k = 0; k < poses.size(); ++k) {
    ScanParams sp = scan_preset("lidar");
    sp.seed = 21 + k;
    const Scan scan = simulate_scan(*b.scene, poses[k], sp).scan;
    ObservationParams p;
    p.path = ObservationPath::kLidar;
    p.lidar = lidar;
    const std::vector<Segment2> observed = observe_scan(scan, p).observation.segments_m;
    std::vector<Segment2> truth, opaque;
    for (const LabeledSegment& s : observer.visible_world_segments(poses[k].position_m())) {
      const Segment2 local{poses[k].inverse_transform(s.segment_m.a_m), poses[k].inverse_transform(s.segment_m.b_m)};
      truth.push_back(local);
      if (s.label != SurfaceLabel::kGlass) opaque.push_back(local);
    }
    out.all.add(segment_accuracy(observed, truth));
    out.opaque.add(segment_accuracy(observed, opaque));
  }
  return out;
}

TEST(ObserveSim, LidarScansRecoverMostOfTheVisibleWallLength) {
  // Default LiDAR path (VoxelPlane): measured recall 0.71 (0.82 without glass), precision 0.88,
  // median angle error 0.3 deg. The former default (PCL region growing) recovers 0.54 (0.64
  // without glass) here and fails the recall checks.
  const LidarWallScores s = lidar_wall_scores(LidarPathParams{});
  EXPECT_GE(s.all.recall(), 0.68);
  EXPECT_GE(s.opaque.recall(), 0.78);
  EXPECT_GE(s.all.precision(), 0.80);
  std::vector<double> ang = s.all.angle_errors_deg, off = s.all.offset_errors_m;
  ASSERT_FALSE(ang.empty());
  std::sort(ang.begin(), ang.end());
  std::sort(off.begin(), off.end());
  EXPECT_LT(ang[ang.size() / 2], 1.0);
  EXPECT_LT(off[off.size() / 2], 0.02);
}

TEST(SegmentAccuracy, KnownAnswers) {
  // Truth: a 4 m wall along x at y = 2 and a 2 m wall along y at x = 3.
  const std::vector<Segment2> truth = {{{-1.0, 2.0}, {3.0, 2.0}}, {{3.0, 2.0}, {3.0, 0.0}}};
  // Observed: the first 2 m of the first wall 5 cm off, the second wall rotated by 3 deg about
  // its middle, and a 1 m segment where there is no wall.
  const double t = std::tan(3.0 * kPi / 180.0);
  const std::vector<Segment2> observed = {
      {{-1.0, 2.05}, {1.0, 2.05}}, {{3.0 - t, 2.0}, {3.0 + t, 0.0}}, {{-1.0, -1.0}, {0.0, -1.0}}};
  const SegmentAccuracy a = segment_accuracy(observed, truth);
  EXPECT_NEAR(a.truth_length_m, 6.0, 1e-9);
  // 2 m of the first wall plus the ~0.19 m past the observed end within 0.2 m of it, all of the
  // second.
  EXPECT_NEAR(a.recovered_length_m, 4.19, 0.03);
  EXPECT_NEAR(a.recall(), 4.19 / 6.0, 0.005);
  EXPECT_NEAR(a.observed_length_m, 2.0 + 2.0 / std::cos(3.0 * kPi / 180.0) + 1.0, 1e-9);
  EXPECT_NEAR(a.precision(), (a.observed_length_m - 1.0) / a.observed_length_m, 0.01);
  EXPECT_EQ(a.segments, 3);
  EXPECT_EQ(a.spurious_segments, 1);
  ASSERT_EQ(a.angle_errors_deg.size(), 2u);
  EXPECT_NEAR(a.angle_errors_deg[0], 0.0, 1e-9);
  EXPECT_NEAR(a.angle_errors_deg[1], 3.0, 1e-6);
  EXPECT_NEAR(a.offset_errors_m[0], 0.05, 1e-9);
  // A segment 10 deg or more off, or 0.2 m or more away, is not on the wall.
  const SegmentAccuracy far = segment_accuracy({{{-1.0, 2.3}, {3.0, 2.3}}}, truth);
  EXPECT_EQ(far.spurious_segments, 1);
  EXPECT_NEAR(far.recall(), 0.0, 0.02);
  // Points along the first wall, 5 cm off it.
  std::vector<Eigen::Vector2d> pts;
  for (double x = -1.0; x <= 3.0; x += 0.05) pts.emplace_back(x, 1.95);
  EXPECT_NEAR(point_coverage(pts, truth, 0.1), 4.15 / 6.0, 0.01);  // + 0.15 m of the second wall at the corner
}

}  // namespace
}  // namespace floorcast
