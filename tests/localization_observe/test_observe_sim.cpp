// The observation module on scans from the simulator (Embree renderer, sensor models), end to end
// with the kernel matcher.
#include <gtest/gtest.h>

#include <cmath>

#include "floorcast/floorplans/io.hpp"
#include "floorcast/localization/matcher.hpp"
#include "floorcast/localization/observation_module.hpp"
#include "floorcast/sim/mesh.hpp"
#include "floorcast/sim/perfect_observation.hpp"
#include "floorcast/sim/ray_scene.hpp"
#include "floorcast/sim/scan_sim.hpp"
#include "segment_checks.hpp"

namespace floorcast {
namespace {

constexpr double kPi = 3.14159265358979323846;

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
  Scan scan = simulate_scan(*b.scene, {2.4, 2.2, 0.4}, sp);
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
    const Scan scan = simulate_scan(*b.scene, {6.5, 2.6, 1.0}, sp);
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
  const Scan scan = simulate_scan(*b.scene, pose, scan_preset("perfect"));
  const ObservationResult r = observe_scan(scan, ObservationParams{});
  // Everything a horizontal cut at camera height meets: walls, glass, door leaves, the pillar.
  PerfectObservationParams pp;
  pp.doors_closed = false;
  pp.obstacles_block = true;
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

/// Simulate -> observe -> kernel matcher: the argmax lies within 1 m (and 30 deg) of the truth.
void expect_localised(const std::string& preset, ObservationPath path, PlaneExtractorKind extractor) {
  const Building& b = two_rooms();
  // A distinctive spot: the larger room, near the glass partition and the door to the other room.
  const Pose2 truth{3.2, 2.8, 0.6};
  ScanParams sp = scan_preset(preset);
  sp.seed = 11;
  const Scan scan = simulate_scan(*b.scene, truth, sp);
  ObservationParams p;
  p.path = path;
  p.lidar.extractor = extractor;
  const ObservationResult r = observe_scan(scan, p);
  ASSERT_GE(r.observation.segments_m.size(), 3u);
  const auto matcher = make_matcher("kernel", b.plan);
  const PoseHypothesis h = matcher->match(r.observation).posterior.argmax();
  const double err = std::hypot(h.x_m - truth.x_m, h.y_m - truth.y_m);
  EXPECT_LT(err, 1.0) << preset << ": argmax (" << h.x_m << ", " << h.y_m << ") truth (" << truth.x_m << ", "
                      << truth.y_m << ")";
  EXPECT_LT(angle_distance_rad(h.yaw_rad, truth.yaw_rad), 30.0 * kPi / 180.0) << preset;
}

TEST(ObserveSim, MonoScanLocalisesWithTheKernelMatcher) {
  expect_localised("mono", ObservationPath::kMono, PlaneExtractorKind::kPclRegionGrowing);
}

TEST(ObserveSim, LidarScanLocalisesWithTheKernelMatcher) {
  expect_localised("lidar", ObservationPath::kLidar, PlaneExtractorKind::kPclRegionGrowing);
  expect_localised("lidar", ObservationPath::kLidar, PlaneExtractorKind::kVoxelPlane);
}

}  // namespace
}  // namespace floorcast
