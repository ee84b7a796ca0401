// The OpenGL renderer (module floorcast_gl.so, loaded on first use): an independent cross-check of
// the Embree depth, and colour views that are neither blank nor alike.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <set>

#include "floorcast/sim/gl_renderer.hpp"
#include "floorcast/sim/scan_sim.hpp"
#include "sim_test_util.hpp"

namespace floorcast {
namespace {

struct Compared {
  long total = 0, both = 0, close = 0;
  double median_diff = 0.0;
};

/// Pixels where both depths exist, and how many agree within 1 mm per metre; `skip` (CV_8U, may
/// be empty) excludes pixels.
Compared compare_depths(const cv::Mat& embree, const cv::Mat& gl, const cv::Mat& skip) {
  Compared out;
  std::vector<double> diffs;
  for (int r = 0; r < gl.rows; ++r)
    for (int c = 0; c < gl.cols; ++c) {
      if (!skip.empty() && skip.at<std::uint8_t>(r, c)) continue;
      const double a = embree.at<float>(r, c), b = gl.at<float>(r, c);
      ++out.total;
      if (a > 0.0 && b > 0.0) {
        ++out.both;
        diffs.push_back(std::abs(a - b));
        out.close += std::abs(a - b) < 1e-3 * std::max(1.0, a);
      }
    }
  std::nth_element(diffs.begin(), diffs.begin() + diffs.size() / 2, diffs.end());
  out.median_diff = diffs.empty() ? INFINITY : diffs[diffs.size() / 2];
  return out;
}

TEST(GlRenderer, DepthAgreesWithEmbreeDepth) {
  FloorPlan plan = test::feature_plan();
  const Mesh mesh = extrude_plan(plan);
  const RayScene scene(mesh);
  ScanParams p = scan_preset("perfect");
  p.geometry.width_px = 160;
  p.geometry.height_px = 120;
  p.geometry.num_views = 6;
  const Pose2 pose{2.2, 2.1, 0.3};
  const Scan scan = simulate_scan(scene, pose, p).scan;
  GlRenderer gl(mesh, 160, 120);
  const Eigen::Isometry3d T_world_scan = scan_frame_in_world(pose, p.geometry.camera_height_m);
  Compared all;
  for (const DepthView& v : scan.views) {
    const cv::Mat g = gl.render_depth(T_world_scan * v.T_scan_camera, v.intrinsics, 0.01, 100.0);
    ASSERT_EQ(g.type(), CV_32F);
    const Compared c = compare_depths(v.depth_m, g, {});
    all.total += c.total;
    all.both += c.both;
    all.close += c.close;
    EXPECT_LT(c.median_diff, 1e-4);
  }
  // Pixel centres are sampled by both; only silhouette pixels may disagree.
  EXPECT_EQ(all.both, all.total);  // a closed building: every pixel sees a surface in both renderers
  EXPECT_GT(static_cast<double>(all.close) / static_cast<double>(all.both), 0.999);
}

TEST(GlRenderer, ColourRenderDepthEqualsEmbreeOnNonGlassPixelsAndViewsDiffer) {
  FloorPlan plan = test::feature_plan();
  const Mesh mesh = extrude_plan(plan);
  const RayScene scene(mesh);
  ScanParams p = scan_preset("perfect");  // exact depth; glass always returns and is masked
  p.geometry.width_px = 160;
  p.geometry.height_px = 120;
  const Pose2 pose{6.0, 2.6, 1.2};  // sees the glass wall, the pillar and the inner door
  const Scan scan = simulate_scan(scene, pose, p).scan;
  GlRenderer gl(mesh, 160, 120);
  const Eigen::Isometry3d T_world_scan = scan_frame_in_world(pose, p.geometry.camera_height_m);
  std::vector<cv::Mat> images;
  long glass_pixels = 0, glass_labelled = 0;
  for (const DepthView& v : scan.views) {
    const GlFrame f = gl.render(T_world_scan * v.T_scan_camera, v.intrinsics, 0.01, 100.0);
    ASSERT_EQ(f.bgr.type(), CV_8UC3);
    ASSERT_EQ(f.label.type(), CV_8U);
    // Depth of the colour render equals Embree's on the pixels glass did not touch.
    const Compared c = compare_depths(v.depth_m, f.depth_m, v.glass_mask);
    ASSERT_GT(c.total, 0);
    EXPECT_EQ(c.both, c.total);
    EXPECT_GT(static_cast<double>(c.close) / static_cast<double>(c.both), 0.995);
    EXPECT_LT(c.median_diff, 1e-4);
    // Labels: glass where Embree met glass first.
    for (int r = 0; r < f.label.rows; ++r)
      for (int col = 0; col < f.label.cols; ++col)
        if (v.glass_mask.at<std::uint8_t>(r, col)) {
          ++glass_pixels;
          glass_labelled += f.label.at<std::uint8_t>(r, col) == static_cast<int>(MeshLabel::kGlass);
        }
    // Not blank: brightness varies and many colours appear.
    cv::Mat grey;
    cv::cvtColor(f.bgr, grey, cv::COLOR_BGR2GRAY);
    cv::Scalar mean, sd;
    cv::meanStdDev(grey, mean, sd);
    EXPECT_GT(mean[0], 40.0);
    EXPECT_LT(mean[0], 230.0);
    EXPECT_GT(sd[0], 12.0);
    std::set<int> colours;
    for (int r = 0; r < f.bgr.rows; ++r)
      for (int col = 0; col < f.bgr.cols; ++col) {
        const cv::Vec3b b = f.bgr.at<cv::Vec3b>(r, col);
        colours.insert((b[0] >> 3) << 10 | (b[1] >> 3) << 5 | (b[2] >> 3));
      }
    EXPECT_GT(colours.size(), 40u);  // 160x120 views of plain walls show ~90 (5-bit bins); a flat fill shows a few
    images.push_back(f.bgr);
  }
  EXPECT_GT(glass_pixels, 500);  // the pose sees the glass wall
  EXPECT_GT(static_cast<double>(glass_labelled) / static_cast<double>(glass_pixels), 0.99);
  // Views differ from one another.
  for (std::size_t i = 0; i < images.size(); ++i)
    for (std::size_t j = i + 1; j < images.size(); ++j) {
      cv::Mat d;
      cv::absdiff(images[i], images[j], d);
      EXPECT_GT(cv::mean(d)[0] + cv::mean(d)[1] + cv::mean(d)[2], 15.0) << "views " << i << " and " << j;
    }
}

TEST(GlRenderer, SameViewSameBytes) {
  const Mesh mesh = extrude_plan(test::feature_plan());
  GlRenderer a(mesh, 64, 48), b(mesh, 64, 48);
  ScanParams p = scan_preset("perfect");
  p.geometry.width_px = 64;
  p.geometry.height_px = 48;
  const CameraIntrinsics K = view_intrinsics(p.geometry);
  const Eigen::Isometry3d T = scan_frame_in_world({2.0, 2.0, 0.4}, 1.5) * view_pose(p.geometry, 1);
  const GlFrame fa = a.render(T, K), fb = b.render(T, K), fa2 = a.render(T, K);
  EXPECT_EQ(cv::norm(fa.bgr, fb.bgr, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(fa.bgr, fa2.bgr, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(fa.depth_m, fb.depth_m, cv::NORM_INF), 0.0);
}

TEST(GlRenderer, SizeMismatchIsAnError) {
  GlRenderer gl(extrude_plan(test::box_room()), 32, 24);
  CameraIntrinsics K;
  K.width_px = 64;
  K.height_px = 48;
  K.fx_px = K.fy_px = 50.0;
  EXPECT_THROW(gl.render_depth(Eigen::Isometry3d::Identity(), K), InputError);
  EXPECT_THROW(gl.render(Eigen::Isometry3d::Identity(), K), InputError);
}

TEST(GlRenderer, ModuleIsFoundBesideTheBuild) {
  std::string why;
  EXPECT_TRUE(gl_renderer_available(&why)) << why;
  EXPECT_NE(gl_module_path().find("floorcast_gl.so"), std::string::npos);
}

}  // namespace
}  // namespace floorcast
