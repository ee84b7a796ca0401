// Independent cross-check: OSMesa rasterised depth equals Embree ray-cast depth.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "floorcast/sim/gl_depth.hpp"
#include "floorcast/sim/scan_sim.hpp"
#include "sim_test_util.hpp"

namespace floorcast {
namespace {

TEST(GlDepth, AgreesWithEmbreeDepth) {
  FloorPlan plan = test::feature_plan();
  const Mesh mesh = extrude_plan(plan);
  const RayScene scene(mesh);
  ScanParams p = scan_preset("perfect");
  p.geometry.width_px = 160;
  p.geometry.height_px = 120;
  p.geometry.num_views = 6;
  const Pose2 pose{2.2, 2.1, 0.3};
  const Scan scan = simulate_scan(scene, pose, p).scan;
  GlDepthRenderer gl(mesh, 160, 120);
  const Eigen::Isometry3d T_world_scan = scan_frame_in_world(pose, p.geometry.camera_height_m);
  long total = 0, close = 0, both = 0;
  std::vector<double> diffs;
  for (const DepthView& v : scan.views) {
    const cv::Mat g = gl.render_depth(T_world_scan * v.T_scan_camera, v.intrinsics, 0.01, 100.0);
    ASSERT_EQ(g.type(), CV_32F);
    for (int r = 0; r < g.rows; ++r)
      for (int c = 0; c < g.cols; ++c) {
        const double a = v.depth_m.at<float>(r, c), b = g.at<float>(r, c);
        ++total;
        if (a > 0.0 && b > 0.0) {
          ++both;
          diffs.push_back(std::abs(a - b));
          close += std::abs(a - b) < 1e-3 * std::max(1.0, a);
        }
      }
  }
  // Pixel centres are sampled by both; only silhouette pixels may disagree.
  EXPECT_EQ(both, total);  // a closed building: every pixel sees a surface in both renderers
  EXPECT_GT(static_cast<double>(close) / static_cast<double>(both), 0.999);
  std::nth_element(diffs.begin(), diffs.begin() + diffs.size() / 2, diffs.end());
  EXPECT_LT(diffs[diffs.size() / 2], 1e-4);
}

TEST(GlDepth, SizeMismatchIsAnError) {
  GlDepthRenderer gl(extrude_plan(test::box_room()), 32, 24);
  CameraIntrinsics K;
  K.width_px = 64;
  K.height_px = 48;
  K.fx_px = K.fy_px = 50.0;
  EXPECT_THROW(gl.render_depth(Eigen::Isometry3d::Identity(), K), InputError);
}

}  // namespace
}  // namespace floorcast
