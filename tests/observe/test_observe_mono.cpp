// Monocular-depth path (PALMS+) on analytic synthetic scans.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "floorcast/observe/observation_module.hpp"
#include "floorcast/core/math.hpp"
#include "segment_checks.hpp"
#include "synthetic_scan.hpp"

namespace floorcast {
namespace {


/// An L-shaped room around the observer (not symmetric, so scale errors show).
test::Scene l_room() {
  test::Scene sc;
  sc.add_room({{-2.0, -1.5}, {4.0, -1.5}, {4.0, 1.0}, {1.5, 1.0}, {1.5, 3.5}, {-2.0, 3.5}}, 1.5, 2.8);
  return sc;
}

TEST(ObserveBackProjection, PointsLieOnTheRenderedSurfaces) {
  const test::Scene sc = test::box_room(-2.0, 3.0, -1.5, 2.5);
  const Scan scan = test::render_scan(sc, 6, 108.0, -15.0, 160, 120);
  BackProjectionParams p;
  p.remove_depth_edges = false;
  const BackProjectionResult bp = back_project_scan(scan, p);
  ASSERT_EQ(bp.views.size(), 6u);
  std::size_t n = 0;
  for (const auto& v : bp.views) {
    for (const auto& q : view_points_scan(v, 1.0)) {
      // Every point is on a wall, the floor or the ceiling of the box.
      const double d = std::min({std::abs(q.x() + 2.0), std::abs(q.x() - 3.0), std::abs(q.y() + 1.5),
                                 std::abs(q.y() - 2.5), std::abs(q.z() + 1.5), std::abs(q.z() - 1.3)});
      ASSERT_LT(d, 2e-4) << q.transpose();
      ++n;
    }
  }
  EXPECT_EQ(n, 6u * 160u * 120u);
}

TEST(ObserveBackProjection, DepthEdgesAreRemovedAtDiscontinuities) {
  test::Scene sc = test::box_room(-2.0, 6.0, -3.0, 3.0);
  // A free-standing panel in front of the far wall: a depth jump of 4 m around it.
  sc.add_wall({2.0, -0.5}, {2.0, 0.5}, -1.5, 0.5);
  const Scan scan = test::render_scan(sc, 1, 90.0, 0.0, 200, 150);
  const cv::Mat edges = depth_edge_mask(scan.views[0].depth_m, BackProjectionParams{});
  // The panel's left and right borders (columns where depth jumps) are marked; the middle of the
  // panel and of the far wall are not.
  const CameraIntrinsics& K = scan.views[0].intrinsics;
  const int row = static_cast<int>(K.cy_px);
  const int col_edge = static_cast<int>(std::lround(K.cx_px - K.fx_px * 0.5 / 2.0));  // y = +0.5 at x = 2
  bool marked = false;
  for (int c = col_edge - 2; c <= col_edge + 2; ++c) marked |= edges.at<std::uint8_t>(row, c) != 0;
  EXPECT_TRUE(marked);
  EXPECT_EQ(edges.at<std::uint8_t>(row, static_cast<int>(K.cx_px)), 0);
  EXPECT_EQ(edges.at<std::uint8_t>(row, 5), 0);
}

TEST(ObserveBackProjection, GlassMaskRemovesSeeThroughPoints) {
  // Room whose +x wall has a glass pane from y = -1 to 1; behind it, a courtyard wall at x = 8.
  test::Scene sc;
  sc.add_wall({3.0, -2.0}, {3.0, -1.0}, -1.5, 1.3);
  sc.add_wall({3.0, -1.0}, {3.0, 1.0}, -1.5, 1.3, /*glass=*/true);
  sc.add_wall({3.0, 1.0}, {3.0, 2.0}, -1.5, 1.3);
  sc.add_wall({3.0, 2.0}, {-2.0, 2.0}, -1.5, 1.3);
  sc.add_wall({-2.0, 2.0}, {-2.0, -2.0}, -1.5, 1.3);
  sc.add_wall({-2.0, -2.0}, {3.0, -2.0}, -1.5, 1.3);
  sc.add_wall({8.0, -6.0}, {8.0, 6.0}, -1.5, 1.3);
  sc.add_horizontal(-2.0, 9.0, -6.0, 6.0, -1.5);
  const Scan scan = test::render_scan(sc, 6, 108.0, -15.0, 160, 120);
  auto beyond_glass = [](const ObservationResult& r) {
    int n = 0;
    for (const auto& s : r.observation.segments_m) {
      if (s.a_m.x() > 3.5 || s.b_m.x() > 3.5) ++n;
    }
    return n;
  };
  ObservationParams p;
  p.scale.mode = ScaleAlignment::kNone;
  BackProjectionParams bp = p.back_projection;
  std::size_t seen = 0, seen_masked = 0;
  for (bool mask : {false, true}) {
    bp.mask_glass = mask;
    const BackProjectionResult res = back_project_scan(scan, bp);
    std::size_t n = 0;
    for (const auto& v : res.views)
      for (const auto& q : view_points_scan(v, 1.0)) n += q.x() > 3.2 ? 1 : 0;
    (mask ? seen_masked : seen) = n;
  }
  EXPECT_GT(seen, 1000u);
  EXPECT_EQ(seen_masked, 0u);

  const ObservationResult unmasked = observe_scan(scan, p);
  p.back_projection.mask_glass = true;
  const ObservationResult masked = observe_scan(scan, p);
  EXPECT_GT(beyond_glass(unmasked), 0);
  EXPECT_EQ(beyond_glass(masked), 0);
  EXPECT_GT(masked.diagnostics.pixels_glass_removed, 0u);
}

TEST(ObserveBackProjection, FarViewsAreDropped) {
  // Open on the +x side: the view looking that way sees the far wall at 150 m.
  test::Scene sc;
  sc.add_wall({150.0, -300.0}, {150.0, 300.0}, -100.0, 100.0);
  sc.add_wall({-3.0, -3.0}, {-3.0, 3.0}, -1.5, 1.3);
  sc.add_horizontal(-3.0, 2.0, -3.0, 3.0, -1.5);
  const Scan scan = test::render_scan(sc, 2, 90.0, 0.0, 80, 60);
  const BackProjectionResult r = back_project_scan(scan, BackProjectionParams{});
  ASSERT_EQ(r.dropped_views.size(), 1u);
  EXPECT_EQ(r.dropped_views[0], 0);
  ASSERT_EQ(r.views.size(), 1u);
  EXPECT_EQ(r.views[0].view_index, 1);
}

TEST(ObserveScale, AnalyticGradientMatchesFiniteDifferences) {
  const std::vector<double> injected = {1.0, 0.85, 1.2, 0.95, 1.1, 0.9};
  const Scan scan = test::render_scan(l_room(), 6, 108.0, -15.0, 160, 120, injected);
  const BackProjectionResult bp = back_project_scan(scan, BackProjectionParams{});
  ScaleAlignmentParams sp;
  sp.max_points_per_cloud = 800;
  const RelativeScaleResult rel = estimate_relative_scales(bp.views, sp);
  ASSERT_GE(rel.pairs.size(), 6u);
  const std::vector<double> x = {1.0, 1.07, 0.93, 1.02, 0.97, 1.05};
  std::vector<double> g;
  relative_scale_objective(bp.views, rel.pairs, x, sp, &g);
  int agree = 0;
  for (std::size_t k = 1; k < x.size(); ++k) {
    const double h = 1e-6;
    std::vector<double> xp = x, xm = x;
    xp[k] += h;
    xm[k] -= h;
    const double fd = (relative_scale_objective(bp.views, rel.pairs, xp, sp) -
                       relative_scale_objective(bp.views, rel.pairs, xm, sp)) / (2 * h);
    // Nearest-neighbour switches make the function piecewise smooth; most coordinates agree.
    if (std::abs(fd - g[k]) <= 1e-3 * std::max(1.0, std::abs(fd))) ++agree;
  }
  EXPECT_GE(agree, 4);
}

TEST(ObserveScale, InjectedPerViewScalesAreRecovered) {
  // Perfect depth, each view's depth multiplied by its own factor (0.8 .. 1.25).
  const std::vector<double> injected = {1.0, 0.8, 1.25, 0.9, 1.15, 0.85};
  const Scan scan = test::render_scan(l_room(), 6, 108.0, -15.0, 320, 240, injected);
  ObservationParams p;
  const ObservationResult r = observe_scan(scan, p);
  ASSERT_EQ(r.diagnostics.view_scales.size(), 6u) << r.diagnostics.relative.status;
  for (std::size_t k = 0; k < 6; ++k) {
    // The applied scale undoes the injected one (camera 1.5 m above the floor = canonical).
    EXPECT_NEAR(r.diagnostics.view_scales[k] * injected[k], 1.0, 0.03)
        << "view " << k << " status " << r.diagnostics.relative.status;
  }
  EXPECT_TRUE(r.diagnostics.ground.found);
  EXPECT_NEAR(r.diagnostics.ground_height_after_m, -1.5, 0.02);
}

TEST(ObserveGround, HeightWithinTwoCentimetres) {
  for (double cam_h : {1.2, 1.5, 1.75}) {
    const test::Scene sc = test::box_room(-2.5, 3.5, -2.0, 3.0, cam_h, 2.8);
    const Scan scan = test::render_scan(sc, 6, 108.0, -15.0, 160, 120);
    const BackProjectionResult bp = back_project_scan(scan, BackProjectionParams{});
    PointCloud3f cloud;
    for (const auto& v : bp.views) {
      const PointCloud3f q = view_points_scan(v, 1.0);
      cloud.insert(cloud.end(), q.begin(), q.end());
    }
    const GroundPlaneResult g = detect_ground_plane(cloud, GroundPlaneParams{});
    ASSERT_TRUE(g.found) << g.reason;
    EXPECT_NEAR(g.height_m, -cam_h, 0.02);
    GroundPlaneParams coarse;
    coarse.refine_height = false;  // PALMS+: bin centre, within half a bin
    EXPECT_NEAR(detect_ground_plane(cloud, coarse).height_m, -cam_h, 0.025 + 1e-9);
  }
}

TEST(ObserveMono, BoxRoomGivesItsFourWalls) {
  for (double yaw : {0.0, 17.0, 40.0}) {
    const auto corners = test::rotated_box(-2.3, 3.4, -1.7, 2.6, yaw);
    test::Scene sc;
    sc.add_room(corners, 1.5, 2.8);
    const Scan scan = test::render_scan(sc);
    const ObservationResult r = observe_scan(scan, ObservationParams{});
    const auto walls = test::polygon_walls(corners);
    const test::WallMatch m = test::match_walls(r.observation.segments_m, walls, 0.05, 1.0);
    EXPECT_TRUE(m.stray.empty()) << "yaw " << yaw << ": " << m.stray.size() << " stray, first: "
                                 << (m.stray.empty() ? "" : m.stray[0]);
    for (std::size_t w = 0; w < walls.size(); ++w) {
      EXPECT_GT(m.coverage[w], 0.8) << "yaw " << yaw << " wall " << w;
    }
    EXPECT_NEAR(r.diagnostics.ground_height_after_m, -1.5, 0.02);
  }
}

TEST(ObserveMono, ScaleAblationSettings) {
  const std::vector<double> injected = {1.0, 1.2, 0.9, 1.1, 0.95, 1.15};
  const Scan scan = test::render_scan(l_room(), 6, 108.0, -15.0, 160, 120, injected);
  ObservationParams p;
  p.scale.mode = ScaleAlignment::kNone;
  const ObservationResult none = observe_scan(scan, p);
  for (double s : none.diagnostics.view_scales) EXPECT_EQ(s, 1.0);
  p.scale.mode = ScaleAlignment::kGround;
  const ObservationResult ground = observe_scan(scan, p);
  ASSERT_EQ(ground.diagnostics.view_scales.size(), 6u);
  for (std::size_t k = 0; k < 6; ++k) {
    // Each view sees the floor: its own ground plane fixes its scale.
    EXPECT_NEAR(ground.diagnostics.view_scales[k] * injected[k], 1.0, 0.03) << k;
  }
}

TEST(ObserveMono, SameOutputAtOneAndTwoThreads) {
  const std::vector<double> injected = {1.0, 0.9, 1.1, 1.05, 0.95, 1.2};
  const Scan scan = test::render_scan(l_room(), 6, 108.0, -15.0, 160, 120, injected, 0.01);
  auto run = [&](int threads) {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, threads);
    const ObservationResult r = observe_scan(scan, ObservationParams{});
    nlohmann::ordered_json j;
    j["diag"] = to_json(r.diagnostics);
    for (const auto& s : r.observation.segments_m) j["seg"].push_back({s.a_m.x(), s.a_m.y(), s.b_m.x(), s.b_m.y()});
    j["rays"] = r.observation.ray_ranges_m;
    return j.dump();
  };
  EXPECT_EQ(run(1), run(2));
}

TEST(ObserveParams, JsonRoundTripAndUnknownKeys) {
  ObservationParams p;
  p.scale.mode = ScaleAlignment::kGround;
  p.slice.band_half_heights_m = {0.1, 0.3};
  ObservationParams q;
  apply_overrides(q, to_json(p));
  EXPECT_EQ(to_json(q).dump(), to_json(p).dump());
  EXPECT_THROW(apply_overrides(q, nlohmann::json{{"scale", {{"bogus", 1}}}}), InputError);
  EXPECT_THROW(apply_overrides(q, nlohmann::json{{"scale", {{"mode", "half"}}}}), InputError);
  EXPECT_THROW(apply_overrides(q, nlohmann::json{{"slice", {{"max_range_m", "far"}}}}), InputError);
}

}  // namespace
}  // namespace floorcast

namespace floorcast {
namespace {

PointCloud3f random_cloud(std::size_t n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> xy(-12.0f, 12.0f), z(-1.6f, 1.4f);
  PointCloud3f c(n);
  for (auto& p : c) p = Eigen::Vector3f(xy(rng), xy(rng), z(rng));
  return c;
}

TEST(ObserveVoxels, OneSortTwoLevelGridEqualsTwoPasses) {
  const PointCloud3f c = random_cloud(200000, 3);
  std::size_t fine = 0;
  const PointCloud3f fast = voxel_downsample_two_level(c, 0.01, 0.1, &fine);
  const PointCloud3f f1 = voxel_downsample(c, 0.01);
  const PointCloud3f slow = voxel_downsample(f1, 0.1);
  EXPECT_EQ(fine, f1.size());
  ASSERT_EQ(fast.size(), slow.size());
  // Same voxels in the same (sorted) order, same centroids up to float rounding.
  for (std::size_t i = 0; i < fast.size(); ++i) ASSERT_LT((fast[i] - slow[i]).norm(), 1e-5f) << i;
  // Centroids: every output point is the mean of its voxel's points (brute force on a few).
  const PointCloud3f coarse = voxel_downsample(c, 0.5);
  for (std::size_t i = 0; i < coarse.size(); i += coarse.size() / 7 + 1) {
    const Eigen::Vector3f cell = (coarse[i] / 0.5f).array().floor();
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int n = 0;
    for (const auto& p : c) {
      if (((p / 0.5f).array().floor() == cell.array()).all()) {
        sum += p.cast<double>();
        ++n;
      }
    }
    ASSERT_GT(n, 0);
    EXPECT_LT((sum / n - coarse[i].cast<double>()).norm(), 1e-5);
  }
}

TEST(ObserveVoxels, SlabThenVoxelsGivesTheSameSliceAsVoxelsThenSlice) {
  const PointCloud3f c = random_cloud(300000, 4);
  for (const double half : {0.2, 0.5, 2.0}) {
    const auto all = slice_points(voxel_downsample_two_level(c, 0.01, 0.1), half, 10.0);
    const auto slab = slice_points(voxel_downsample_two_level(slice_slab(c, half, 0.1, 10.0), 0.01, 0.1), half, 10.0);
    ASSERT_EQ(all.size(), slab.size()) << half;
    auto key = [](const Eigen::Vector2d& p) { return std::make_pair(p.x(), p.y()); };
    std::vector<std::pair<double, double>> a, b;
    for (const auto& p : all) a.push_back(key(p));
    for (const auto& p : slab) b.push_back(key(p));
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    EXPECT_EQ(a, b) << half;
  }
}

}  // namespace
}  // namespace floorcast
