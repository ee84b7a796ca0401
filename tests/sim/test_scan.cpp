// The scan renderer and sensor models against analytic answers and their own parameters.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "floorcast/core/random.hpp"
#include "floorcast/sim/scan_sim.hpp"
#include "floorcast/core/math.hpp"
#include "sim_test_util.hpp"

namespace floorcast {
namespace {


ScanParams small_perfect(int views, int w, int h, double hfov, double pitch) {
  ScanParams p = scan_preset("perfect");
  p.geometry.num_views = views;
  p.geometry.view_step_deg = 360.0 / views;
  p.geometry.width_px = w;
  p.geometry.height_px = h;
  p.geometry.hfov_deg = hfov;
  p.geometry.pitch_deg = pitch;
  return p;
}

bool same_bytes(const cv::Mat& a, const cv::Mat& b) {
  if (a.empty() || b.empty()) return a.empty() && b.empty();
  if (a.size() != b.size() || a.type() != b.type()) return false;
  for (int r = 0; r < a.rows; ++r) {
    if (std::memcmp(a.ptr(r), b.ptr(r), a.cols * a.elemSize()) != 0) return false;
  }
  return true;
}

bool same_scan(const SimulatedScan& a, const SimulatedScan& b) {
  if (a.scan.views.size() != b.scan.views.size()) return false;
  for (std::size_t k = 0; k < a.scan.views.size(); ++k) {
    if (!same_bytes(a.scan.views[k].depth_m, b.scan.views[k].depth_m)) return false;
    if (!same_bytes(a.scan.views[k].glass_mask, b.scan.views[k].glass_mask)) return false;
    if (!same_bytes(a.scan.views[k].confidence, b.scan.views[k].confidence)) return false;
    if (!a.scan.views[k].T_scan_camera.isApprox(b.scan.views[k].T_scan_camera, 0.0)) return false;
  }
  return a.truth.view_depth_scale == b.truth.view_depth_scale;
}

TEST(Random, CounterRngIsUniformAndNormal) {
  const CounterRng rng(42, kRngPixelNoise, 3);
  double sum = 0.0, sum2 = 0.0, usum = 0.0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const double z = rng.child(static_cast<std::uint64_t>(i)).normal(0);
    sum += z;
    sum2 += z * z;
    usum += rng.uniform(static_cast<std::uint64_t>(i));
  }
  EXPECT_NEAR(sum / n, 0.0, 0.01);
  EXPECT_NEAR(sum2 / n, 1.0, 0.015);
  EXPECT_NEAR(usum / n, 0.5, 0.003);
  // Documented accuracy: 1e-4 in the body (|z| < 2.5), coarser in the clamped tails.
  for (double u : {0.01, 0.1, 0.3, 0.5, 0.77, 0.99}) {
    EXPECT_NEAR(normal_quantile_fast(u), normal_quantile(u), 1e-4) << u;
    EXPECT_NEAR(0.5 * std::erfc(-normal_quantile(u) / std::sqrt(2.0)), u, 1e-12);
  }
  EXPECT_NEAR(normal_quantile_fast(1e-3), normal_quantile(1e-3), 2e-3);
  EXPECT_NEAR(normal_quantile_fast(1e-4), normal_quantile(1e-4), 0.1);
  EXPECT_GE(normal_quantile_fast(1e-12), -4.01);
}

TEST(ScanGeometry, IntrinsicsAndViewPoses) {
  const ScanParams p = scan_preset("mono");
  const CameraIntrinsics K = view_intrinsics(p.geometry);
  EXPECT_EQ(K.width_px, 640);
  EXPECT_NEAR(2.0 * std::atan(0.5 * 640 / K.fx_px) * 180.0 / kPi, 108.0, 1e-9);
  EXPECT_DOUBLE_EQ(K.cx_px, 319.5);
  // View 1 looks 60 deg counter-clockwise of +x, 15 deg down; camera y points down-ish.
  const Eigen::Isometry3d T = view_pose(p.geometry, 1);
  const Eigen::Vector3d f = T.linear().col(2);
  EXPECT_NEAR(std::atan2(f.y(), f.x()) * 180.0 / kPi, 60.0, 1e-9);
  EXPECT_NEAR(std::asin(f.z()) * 180.0 / kPi, -15.0, 1e-9);
  EXPECT_LT(T.linear().col(1).z(), 0.0);
  EXPECT_NEAR(T.linear().determinant(), 1.0, 1e-12);
  EXPECT_EQ(setting_views(p.geometry, ScanSetting::kPartial, 0), (std::vector<int>{5, 0, 1}));
  EXPECT_EQ(setting_views(p.geometry, ScanSetting::kSingle, 2), (std::vector<int>{2}));
  for (const std::string& name : scan_preset_names()) EXPECT_NO_THROW(validate_scan_params(scan_preset(name)));
  EXPECT_THROW(scan_preset("kinect"), InputError);
}

TEST(ScanRender, BoxRoomDepthsEqualExactDistances) {
  // Room interior [0.1, 5.9] x [0.1, 3.9], floor 0, ceiling 3, camera at 1.5 m.
  const RayScene scene(extrude_plan(test::box_room(6.0, 4.0, 0.2)));
  for (double pitch : {0.0, -15.0, 20.0}) {
    const ScanParams p = small_perfect(5, 48, 36, 90.0, pitch);
    const Pose2 pose{2.3, 1.7, 0.4};
    const SimulatedScan scan = simulate_scan(scene, pose, p);
    ASSERT_EQ(scan.scan.views.size(), 5u);
    const Eigen::Isometry3d T_world_scan = scan_frame_in_world(pose, 1.5);
    int checked = 0;
    for (const DepthView& v : scan.scan.views) {
      const Eigen::Isometry3d T = T_world_scan * v.T_scan_camera;
      for (int r = 0; r < v.intrinsics.height_px; ++r) {
        for (int c = 0; c < v.intrinsics.width_px; ++c) {
          const Eigen::Vector3d dc((c - v.intrinsics.cx_px) / v.intrinsics.fx_px,
                                   (r - v.intrinsics.cy_px) / v.intrinsics.fy_px, 1.0);
          const Eigen::Vector3d d = T.linear() * dc, o = T.translation();
          // Exact: nearest of the six planes, in units of d (= z-depth since dc.z = 1).
          double t = std::numeric_limits<double>::infinity();
          auto plane = [&](int axis, double value) {
            if (std::abs(d[axis]) < 1e-12) return;
            const double s = (value - o[axis]) / d[axis];
            if (s > 0.0) t = std::min(t, s);
          };
          plane(0, 0.1);
          plane(0, 5.9);
          plane(1, 0.1);
          plane(1, 3.9);
          plane(2, 0.0);
          plane(2, 3.0);
          const float got = v.depth_m.at<float>(r, c);
          ASSERT_GT(got, 0.0f);
          EXPECT_NEAR(got, t, 2e-5 * std::max(1.0, t)) << "pitch " << pitch << " pixel " << c << "," << r;
          ++checked;
        }
      }
      EXPECT_EQ(cv::countNonZero(v.glass_mask), 0);
      EXPECT_TRUE(v.confidence.empty());
    }
    EXPECT_EQ(checked, 5 * 48 * 36);
    EXPECT_EQ(scan.truth.view_depth_scale, std::vector<double>(5, 1.0));
  }
}

TEST(ScanRender, CameraRaysAreTheRaysTheRendererCasts) {
  // The benchmark compares the renderer with raw Embree on scan_camera_rays: same work.
  const RayScene scene(extrude_plan(test::feature_plan()));
  ScanParams p = small_perfect(3, 40, 20, 90.0, -10.0);  // 40 x 20: partial 16-pixel tiles
  const Pose2 pose{2.0, 2.0, 0.2};
  const SimulatedScan scan = simulate_scan(scene, pose, p);
  const std::vector<Ray3> rays = scan_camera_rays(pose, p);
  ASSERT_EQ(rays.size(), 3u * 40u * 20u);
  std::vector<RayHit3> hits(rays.size());
  scene.intersect_stream(rays.data(), hits.data(), rays.size());
  // Tile order: views, then 16 x 16 tiles row by row, pixels row-major inside each tile.
  std::size_t i = 0;
  for (int k = 0; k < 3; ++k)
    for (int ty = 0; ty < 2; ++ty)
      for (int tx = 0; tx < 3; ++tx)
        for (int v = ty * 16; v < std::min(20, ty * 16 + 16); ++v)
          for (int u = tx * 16; u < std::min(40, tx * 16 + 16); ++u, ++i) {
            ASSERT_TRUE(hits[i].hit());
            EXPECT_EQ(hits[i].t, scan.scan.views[static_cast<std::size_t>(k)].depth_m.at<float>(v, u));
          }
  EXPECT_EQ(i, rays.size());
}

TEST(ScanRender, RangeLimitsGiveNoReturn) {
  const RayScene scene(extrude_plan(test::box_room(20.0, 4.0, 0.2)));
  ScanParams p = small_perfect(1, 16, 12, 30.0, 0.0);
  p.sensor.max_range_m = 5.0;
  const SimulatedScan scan = simulate_scan(scene, {1.0, 2.0, 0.0}, p);  // facing the far wall 18.9 m away
  const cv::Mat& d = scan.scan.views[0].depth_m;
  EXPECT_EQ(d.at<float>(6, 8), 0.0f);
  p.sensor.max_range_m = 30.0;
  const SimulatedScan far = simulate_scan(scene, {1.0, 2.0, 0.0}, p);
  EXPECT_GT(far.scan.views[0].depth_m.at<float>(6, 8), 18.0f);
}

/// Camera facing the glass wall of test::glass_split_room at x = 5 (faces at 4.99 / 5.01),
/// from (2, 2) looking +x: centre pixel distances: glass 2.99, east wall behind 7.9, and the
/// reflected path back to the west wall (x = 0.1): 2.99 + 4.89 = 7.88.
SimulatedScan glass_scan(double p_see, double p_reflect, bool per_pixel = false) {
  static const RayScene scene(extrude_plan(test::glass_split_room()));
  ScanParams p = small_perfect(1, 9, 9, 20.0, 0.0);
  p.sensor.glass.p_see_through = p_see;
  p.sensor.glass.p_reflect = p_reflect;
  p.sensor.glass.per_pixel = per_pixel;
  return simulate_scan(scene, {2.0, 2.0, 0.0}, p, SimulationOptions{true});
}

TEST(ScanGlass, SeeThroughReturnsGeometryBehind) {
  const SimulatedScan s = glass_scan(1.0, 0.0);
  EXPECT_NEAR(s.scan.views[0].depth_m.at<float>(4, 4), 7.9f, 1e-4f);
  EXPECT_EQ(s.scan.views[0].glass_mask.at<unsigned char>(4, 4), 255);
  EXPECT_NEAR(s.truth.depth_m[0].at<float>(4, 4), 2.99f, 1e-4f);  // first surface = the glass
  EXPECT_EQ(cv::countNonZero(s.scan.views[0].glass_mask), 81);
}

TEST(ScanGlass, GlassReturnAndReflection) {
  const SimulatedScan ret = glass_scan(0.0, 0.0);
  EXPECT_NEAR(ret.scan.views[0].depth_m.at<float>(4, 4), 2.99f, 1e-4f);
  EXPECT_EQ(ret.scan.views[0].glass_mask.at<unsigned char>(4, 4), 255);
  const SimulatedScan refl = glass_scan(0.0, 1.0);
  EXPECT_NEAR(refl.scan.views[0].depth_m.at<float>(4, 4), 2.99f + 4.89f, 2e-4f);
}

TEST(ScanGlass, OutcomeFrequenciesFollowProbabilities) {
  // Per-pixel decisions over many seeds: fractions of see-through / reflect / return.
  int n_see = 0, n_refl = 0, n_ret = 0;
  const RayScene scene(extrude_plan(test::glass_split_room()));
  ScanParams p = small_perfect(1, 9, 9, 20.0, 0.0);
  p.sensor.glass = {0.5, 0.2, true, 4};
  for (std::uint64_t seed = 0; seed < 60; ++seed) {
    p.seed = seed;
    const SimulatedScan s = simulate_scan(scene, {2.0, 2.0, 0.0}, p);
    for (int r = 3; r <= 5; ++r) {
      for (int c = 3; c <= 5; ++c) {
        const float d = s.scan.views[0].depth_m.at<float>(r, c);
        if (std::abs(d - 2.99f) < 2e-3f) {
          ++n_ret;
        } else if (std::abs(d - 7.9f) < 2e-3f) {
          ++n_see;
        } else if (std::abs(d - 7.88f) < 2e-3f) {
          ++n_refl;
        }
      }
    }
  }
  const double n = n_see + n_refl + n_ret;
  ASSERT_EQ(n, 60 * 9);
  EXPECT_NEAR(n_see / n, 0.5, 0.07);
  EXPECT_NEAR(n_refl / n, 0.2, 0.06);
  EXPECT_NEAR(n_ret / n, 0.3, 0.07);
}

TEST(ScanGlass, PerPaneDecisionIsCoherentAcrossTheView) {
  for (std::uint64_t seed = 0; seed < 10; ++seed) {
    const RayScene scene(extrude_plan(test::glass_split_room()));
    ScanParams p = small_perfect(1, 9, 9, 20.0, 0.0);
    p.sensor.glass = {0.5, 0.0, false, 4};
    p.seed = seed;
    const SimulatedScan s = simulate_scan(scene, {2.0, 2.0, 0.0}, p);
    const float centre = s.scan.views[0].depth_m.at<float>(4, 4);
    const bool through = centre > 3.5f;
    for (int c = 0; c < 9; ++c) {
      EXPECT_EQ(s.scan.views[0].depth_m.at<float>(4, c) > 3.5f, through) << "seed " << seed;
    }
  }
}

TEST(SensorMono, ViewScaleErrorMatchesSigma) {
  const RayScene scene(extrude_plan(test::box_room(6.0, 4.0, 0.2)));
  ScanParams p = scan_preset("mono");
  p.sensor.mono = mono_model_preset("per_view_lognormal");  // the components tested here alone
  p.geometry.num_views = 360;
  p.geometry.view_step_deg = 1.0;
  p.geometry.width_px = 8;
  p.geometry.height_px = 6;
  p.sensor.mono.warp_sigma_ln = 0.0;
  p.sensor.mono.flying_pixel_prob = 0.0;
  std::vector<double> logs;
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    p.seed = seed;
    const SimulatedScan s = simulate_scan(scene, {2.5, 1.8, 0.0}, p, SimulationOptions{true});
    for (std::size_t k = 0; k < s.scan.views.size(); ++k) {
      // Empirical scale of the view: median of measured / true depth.
      std::vector<double> ratios;
      for (int r = 0; r < 6; ++r)
        for (int c = 0; c < 8; ++c) {
          const float t = s.truth.depth_m[k].at<float>(r, c);
          if (t > 0.0f) ratios.push_back(s.scan.views[k].depth_m.at<float>(r, c) / t);
        }
      ASSERT_FALSE(ratios.empty());
      std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
      const double empirical = ratios[ratios.size() / 2];
      EXPECT_NEAR(empirical / s.truth.view_depth_scale[k], 1.0, 0.03);
      logs.push_back(std::log(empirical));
    }
  }
  const double n = static_cast<double>(logs.size());
  const double mean = std::accumulate(logs.begin(), logs.end(), 0.0) / n;
  double var = 0.0;
  for (double l : logs) var += (l - mean) * (l - mean);
  const double sd = std::sqrt(var / (n - 1.0));
  // 2160 views: the standard error of the sample sd is ~0.12 / sqrt(2 * 2160) = 0.0018.
  EXPECT_NEAR(sd, 0.12, 0.01);
  EXPECT_NEAR(mean, 0.0, 0.01);
}

TEST(SensorMono, WarpIsSmoothAndNoiseMatchesSigma) {
  const RayScene scene(extrude_plan(test::box_room(6.0, 4.0, 0.2)));
  ScanParams p = scan_preset("mono");
  p.sensor.mono = mono_model_preset("per_view_lognormal");  // the components tested here alone
  p.geometry.num_views = 2;
  p.geometry.width_px = 160;
  p.geometry.height_px = 120;
  p.sensor.mono.scale_sigma_ln = 0.0;
  p.sensor.mono.flying_pixel_prob = 0.0;
  p.sensor.mono.warp_sigma_ln = 0.0;
  p.seed = 5;
  const SimulatedScan s = simulate_scan(scene, {2.5, 1.8, 0.3}, p, SimulationOptions{true});
  double sum2 = 0.0;
  int n = 0;
  for (std::size_t k = 0; k < s.scan.views.size(); ++k)
    for (int r = 0; r < 120; ++r)
      for (int c = 0; c < 160; ++c) {
        const float t = s.truth.depth_m[k].at<float>(r, c);
        if (t <= 0.0f) continue;
        const double e = s.scan.views[k].depth_m.at<float>(r, c) / t - 1.0;
        sum2 += e * e;
        ++n;
      }
  EXPECT_NEAR(std::sqrt(sum2 / n), p.sensor.mono.noise_sigma_rel, 0.0005);

  // With a warp and no noise, the ratio field is smooth: neighbouring pixels differ little.
  p.sensor.mono.noise_sigma_rel = 0.0;
  p.sensor.mono.warp_sigma_ln = 0.1;
  const SimulatedScan w = simulate_scan(scene, {2.5, 1.8, 0.3}, p, SimulationOptions{true});
  double max_step = 0.0, lo = 10.0, hi = 0.0;
  for (int r = 0; r < 120; ++r)
    for (int c = 1; c < 160; ++c) {
      const float t0 = w.truth.depth_m[0].at<float>(r, c - 1), t1 = w.truth.depth_m[0].at<float>(r, c);
      if (t0 <= 0.0f || t1 <= 0.0f) continue;
      const double a = w.scan.views[0].depth_m.at<float>(r, c - 1) / t0, b = w.scan.views[0].depth_m.at<float>(r, c) / t1;
      max_step = std::max(max_step, std::abs(a - b));
      lo = std::min(lo, b);
      hi = std::max(hi, b);
    }
  EXPECT_LT(max_step, 0.01);
  EXPECT_GT(hi - lo, 0.02);  // but it does vary across the view
}

TEST(SensorMono, FlyingPixelsOnlyAtDepthEdges) {
  // A pillar in front of a wall makes depth edges; flying pixels lie between the two depths.
  FloorPlan plan = test::box_room(8.0, 6.0, 0.2);
  plan.obstacles.push_back({"pillar", ObstacleKind::kPillar, {3.0, 3.0}, {0.6, 0.6}, 0.0, 3.0});
  const RayScene scene(extrude_plan(plan));
  ScanParams p = scan_preset("mono");
  p.sensor.mono = mono_model_preset("per_view_lognormal");  // the components tested here alone
  p.geometry.num_views = 1;
  p.geometry.width_px = 200;
  p.geometry.height_px = 150;
  p.geometry.pitch_deg = 0.0;
  p.sensor.mono.scale_sigma_ln = 0.0;
  p.sensor.mono.warp_sigma_ln = 0.0;
  p.sensor.mono.noise_sigma_rel = 0.0;
  p.sensor.mono.flying_pixel_prob = 1.0;
  const SimulatedScan s = simulate_scan(scene, {1.0, 3.0, 0.0}, p, SimulationOptions{true});
  const cv::Mat& t = s.truth.depth_m[0];
  const cv::Mat& d = s.scan.views[0].depth_m;
  int changed = 0, edge_changed = 0;
  for (int r = 0; r < t.rows; ++r)
    for (int c = 1; c + 1 < t.cols; ++c) {
      const float z = t.at<float>(r, c);
      if (std::abs(d.at<float>(r, c) - z) < 1e-5f) continue;
      ++changed;
      const float a = t.at<float>(r, c - 1), b = t.at<float>(r, c + 1);
      const float up = r > 0 ? t.at<float>(r - 1, c) : z, down = r + 1 < t.rows ? t.at<float>(r + 1, c) : z;
      const float lo = std::min({a, b, up, down, z}), hi = std::max({a, b, up, down, z});
      if ((hi - lo) > 0.05f * lo) ++edge_changed;
      EXPECT_GE(d.at<float>(r, c), lo - 1e-4f);
      EXPECT_LE(d.at<float>(r, c), hi + 1e-4f);
    }
  EXPECT_GT(changed, 100);  // both silhouettes of the pillar, and floor/wall creases are not edges
  EXPECT_EQ(edge_changed, changed);
}

TEST(SensorLidar, AxialNoiseMatchesSigmaOfZ) {
  const RayScene scene(extrude_plan(test::box_room(9.0, 9.0, 0.2)));
  ScanParams p = scan_preset("lidar");
  p.sensor.lidar.lateral_sigma_px = 0.0;
  p.sensor.lidar.dropout_prob = 0.0;
  p.sensor.lidar.grazing_dropout_prob = 0.0;
  p.sensor.tracker = {};
  p.sensor.glass = {};
  p.geometry.num_views = 4;
  p.geometry.view_step_deg = 90.0;
  const LidarModel& m = p.sensor.lidar;
  double sum = 0.0, sum2 = 0.0;
  long n = 0;
  for (std::uint64_t seed = 0; seed < 3; ++seed) {
    p.seed = seed;
    const SimulatedScan s = simulate_scan(scene, {3.0, 4.0, 0.2}, p, SimulationOptions{true});
    for (std::size_t k = 0; k < s.scan.views.size(); ++k)
      for (int r = 0; r < s.scan.views[k].depth_m.rows; ++r)
        for (int c = 0; c < s.scan.views[k].depth_m.cols; ++c) {
          const double z = s.truth.depth_m[k].at<float>(r, c);
          const double got = s.scan.views[k].depth_m.at<float>(r, c);
          if (z <= 0.0) continue;
          ASSERT_GT(got, 0.0);
          const double sigma = m.sigma_base_m + m.sigma_quad_per_m * (z - m.sigma_z0_m) * (z - m.sigma_z0_m);
          const double e = (got - z) / sigma;
          sum += e;
          sum2 += e * e;
          ++n;
        }
  }
  ASSERT_GT(n, 50000);
  EXPECT_NEAR(sum / n, 0.0, 0.02);
  EXPECT_NEAR(std::sqrt(sum2 / n), 1.0, 0.02);
}

TEST(SensorLidar, RangeDropoutsAndConfidence) {
  const RayScene scene(extrude_plan(test::glass_split_room()));
  ScanParams p = scan_preset("lidar");
  p.seed = 3;
  const SimulatedScan s = simulate_scan(scene, {2.0, 2.0, 0.0}, p, SimulationOptions{true});
  ASSERT_EQ(s.scan.views.size(), 18u);
  long returns = 0, truth_returns = 0, high = 0, glass_conf = 0, glass_px = 0;
  for (std::size_t k = 0; k < s.scan.views.size(); ++k) {
    const DepthView& v = s.scan.views[k];
    ASSERT_EQ(v.confidence.type(), CV_8U);
    for (int r = 0; r < v.depth_m.rows; ++r)
      for (int c = 0; c < v.depth_m.cols; ++c) {
        const float d = v.depth_m.at<float>(r, c);
        const double xn = (c - v.intrinsics.cx_px) / v.intrinsics.fx_px, yn = (r - v.intrinsics.cy_px) / v.intrinsics.fy_px;
        EXPECT_LE(d * std::sqrt(xn * xn + yn * yn + 1.0), 5.0 + 0.2);  // range limit (plus noise)
        returns += d > 0.0f;
        truth_returns += s.truth.depth_m[k].at<float>(r, c) > 0.0f;
        const unsigned char conf = v.confidence.at<unsigned char>(r, c);
        EXPECT_LE(conf, 2);
        if (d == 0.0f) {
          EXPECT_EQ(conf, 0);
        }
        high += conf == 2;
        if (v.glass_mask.at<unsigned char>(r, c) && d > 0.0f) {
          ++glass_px;
          glass_conf += conf;
        }
      }
  }
  EXPECT_LT(returns, truth_returns);          // dropouts
  EXPECT_GT(returns, 0.9 * truth_returns);    // but few of them
  EXPECT_GT(high, returns / 3);
  EXPECT_GT(glass_px, 0);
  EXPECT_EQ(glass_conf, 0);  // glass-affected returns have low confidence
}

TEST(ScanDeterminism, SameSeedSameBytesAtAnyThreadCount) {
  const RayScene scene(extrude_plan(test::feature_plan()));
  for (const char* preset : {"mono", "lidar", "phone"}) {
    ScanParams p = scan_preset(preset);
    p.geometry.width_px /= 4;
    p.geometry.height_px /= 4;
    p.seed = 99;
    SimulatedScan one, two;
    {
      tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
      one = simulate_scan(scene, {3.0, 2.0, 0.3}, p);
    }
    {
      tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
      two = simulate_scan(scene, {3.0, 2.0, 0.3}, p);
    }
    EXPECT_TRUE(same_scan(one, two)) << preset;
    const SimulatedScan again = simulate_scan(scene, {3.0, 2.0, 0.3}, p);
    EXPECT_TRUE(same_scan(one, again)) << preset;
    p.seed = 100;
    const SimulatedScan other = simulate_scan(scene, {3.0, 2.0, 0.3}, p);
    EXPECT_FALSE(same_scan(one, other)) << preset;
  }
}

TEST(ScanTracker, ReportedPosesCarryJitterTruthDoesNot) {
  const RayScene scene(extrude_plan(test::box_room()));
  ScanParams p = scan_preset("phone");
  p.geometry.width_px = 12;
  p.geometry.height_px = 16;
  p.sensor.tracker = {1.0, 0.02};
  const SimulatedScan s = simulate_scan(scene, {3.0, 2.0, 0.0}, p);
  double rot = 0.0, trans = 0.0;
  for (std::size_t k = 0; k < s.scan.views.size(); ++k) {
    const Eigen::Isometry3d& T_true = s.truth.T_scan_camera_true[k];
    EXPECT_TRUE(T_true.isApprox(view_pose(p.geometry, s.scan.views[k].view_index), 1e-12));
    const Eigen::Isometry3d delta = T_true.inverse() * s.scan.views[k].T_scan_camera;
    rot += Eigen::AngleAxisd(delta.linear()).angle();
    trans += (s.scan.views[k].T_scan_camera.translation() - T_true.translation()).norm();
  }
  rot /= static_cast<double>(s.scan.views.size());
  trans /= static_cast<double>(s.scan.views.size());
  // Mean norm of a 3D isotropic Gaussian = sigma * 1.596.
  EXPECT_NEAR(rot * 180.0 / kPi, 1.596, 0.5);
  EXPECT_NEAR(trans, 0.02 * 1.596, 0.01);
}

TEST(ScanSettings, PartialAndSingleKeepTheirViews) {
  const RayScene scene(extrude_plan(test::box_room()));
  ScanParams p = small_perfect(6, 16, 12, 90.0, 0.0);
  p.setting = ScanSetting::kPartial;
  p.center_view = 2;
  SimulatedScan s = simulate_scan(scene, {3.0, 2.0, 0.0}, p);
  ASSERT_EQ(s.scan.views.size(), 3u);
  EXPECT_EQ(s.scan.views[0].view_index, 1);
  EXPECT_EQ(s.scan.views[2].view_index, 3);
  EXPECT_EQ(s.params.setting, ScanSetting::kPartial);
  p.setting = ScanSetting::kSingle;
  s = simulate_scan(scene, {3.0, 2.0, 0.0}, p);
  ASSERT_EQ(s.scan.views.size(), 1u);
  EXPECT_EQ(s.scan.views[0].view_index, 2);
}

TEST(ObserverPose, InsideWallOutsideAndValid) {
  const FloorPlan plan = test::feature_plan();
  EXPECT_NO_THROW(check_observer_pose(plan, {2.0, 2.0, 0.0}, "plan"));
  EXPECT_NO_THROW(check_observer_pose(plan, {5.0, 1.5, 0.0}, "plan"));   // in the open doorway
  EXPECT_NO_THROW(check_observer_pose(plan, {5.04, 1.2, 0.0}, "plan"));  // near its jamb
  try {
    check_observer_pose(plan, {2.0, 0.0, 0.0}, "plan");
    FAIL() << "inside the closed front door";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("closed door in wall \"s\""), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(check_observer_pose(plan, {0.15, 2.0, 0.0}, "plan"));  // 5 cm from a wall
  try {
    check_observer_pose(plan, {5.02, 4.0, 0.0}, "plan");
    FAIL() << "inside the mid wall";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("inside wall \"mid\""), std::string::npos) << e.what();
  }
  try {
    check_observer_pose(plan, {6.5, 1.5, 0.0}, "plan");
    FAIL() << "inside the pillar";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("obstacle \"column\""), std::string::npos) << e.what();
  }
  try {
    check_observer_pose(plan, {-0.3, 2.0, 0.0}, "plan");
    FAIL() << "outside";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("outside the building"), std::string::npos) << e.what();
  }
  EXPECT_THROW(check_observer_pose(plan, {20.0, 2.0, 0.0}, "plan"), InputError);
  EXPECT_THROW(check_observer_pose(plan, {2.0, 5.0, 0.0}, "plan"), InputError);  // in the window's wall
}

TEST(ScanParamsValidation, RejectsAbsurdValues) {
  ScanParams p = scan_preset("mono");
  p.geometry.hfov_deg = 200.0;
  EXPECT_THROW(validate_scan_params(p), InputError);
  p = scan_preset("mono");
  p.sensor.glass.p_see_through = 0.8;
  p.sensor.glass.p_reflect = 0.5;
  EXPECT_THROW(validate_scan_params(p), InputError);
  p = scan_preset("mono");
  p.sensor.max_range_m = 100.0;
  EXPECT_THROW(validate_scan_params(p), InputError);
  p = scan_preset("mono");
  p.center_view = 6;
  EXPECT_THROW(validate_scan_params(p), InputError);
}

}  // namespace
}  // namespace floorcast
