// Bring your own depth: feeding the simulated depth back through --depth-dir (any format)
// reproduces the simulated observation exactly; the example folder in the repository works.
#include <gtest/gtest.h>

#include "common/scratch_dir.hpp"

#include <filesystem>

#include "floorcast/core/depth_io.hpp"
#include "floorcast/core/scan_io.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/observe/observation_module.hpp"
#include "floorcast/sim/mesh.hpp"
#include "floorcast/sim/scan_io.hpp"
#include "floorcast/sim/scan_sim.hpp"

namespace floorcast {
namespace {

namespace fs = std::filesystem;

void expect_same_observation(const Observation2D& a, const Observation2D& b) {
  ASSERT_EQ(a.segments_m.size(), b.segments_m.size());
  for (std::size_t i = 0; i < a.segments_m.size(); ++i) {
    EXPECT_EQ(a.segments_m[i].a_m, b.segments_m[i].a_m);
    EXPECT_EQ(a.segments_m[i].b_m, b.segments_m[i].b_m);
  }
  EXPECT_EQ(a.ray_ranges_m, b.ray_ranges_m);
}

TEST(ByoDepth, SimulatedDepthFedBackReproducesTheObservation) {
  const test::ScratchDir scratch;
  const fs::path dir = scratch.path();
  const FloorPlan plan = load_floor_plan(std::string(FLOORCAST_SOURCE_DIR) + "/floorplans/buildings/apartment.json");
  ScanParams p = scan_preset("mono");
  p.seed = 11;
  const RayScene scene(extrude_plan(plan));
  const Pose2 pose{4.0, 3.0, 0.4};
  check_observer_pose(plan, pose, "apartment");
  save_simulated_scan((dir / "scan").string(), simulate_scan(scene, pose, p));

  // The scan as floorcast observes it from its folder.
  const Scan original = load_scan((dir / "scan").string());
  const ObservationResult a = observe_scan(original);
  ASSERT_GT(a.observation.segments_m.size(), 3u);

  // The same depth maps written by "another tool" in every format, named in every accepted way.
  fs::create_directories(dir / "depth");
  const char* names[] = {"view_000.npy", "view_001.tif", "view_002_depth.exr", "view_003.png", "view_004.tiff",
                         "view_005_depth.npy"};
  ASSERT_EQ(original.views.size(), 6u);
  for (std::size_t k = 0; k < 6; ++k) write_depth_file((dir / "depth" / names[k]).string(), original.views[k].depth_m);
  ScanLoadOptions lo;
  lo.require_depth = false;
  Scan byo = load_scan((dir / "scan").string(), lo);
  for (DepthView& v : byo.views) v.depth_m.release();  // only the depth folder's maps count
  const DepthDirectoryReport rep = load_depth_directory(byo, (dir / "depth").string());
  EXPECT_TRUE(rep.repairs.empty());
  for (std::size_t k = 0; k < 6; ++k) EXPECT_EQ(cv::norm(byo.views[k].depth_m, original.views[k].depth_m, cv::NORM_INF), 0.0) << k;
  const ObservationResult b = observe_scan(byo);
  expect_same_observation(a.observation, b.observation);
  fs::remove_all(dir);
}

TEST(ByoDepth, ExampleFolderInTheRepository) {
  const std::string root = std::string(FLOORCAST_SOURCE_DIR) + "/examples/byo_depth";
  ScanLoadOptions lo;
  lo.require_depth = false;
  lo.load_rgb = true;
  Scan scan = load_scan(root + "/scan", lo);
  ASSERT_EQ(scan.views.size(), 2u);
  for (const DepthView& v : scan.views) {
    EXPECT_TRUE(v.depth_m.empty());  // colour, intrinsics and poses only
    EXPECT_EQ(v.rgb.type(), CV_8UC3);
  }
  EXPECT_THROW(load_scan(root + "/scan"), InputError);  // without depth maps it cannot be observed
  const DepthDirectoryReport rep = load_depth_directory(scan, root + "/depth");
  EXPECT_EQ(rep.files.size(), 2u);
  const ObservationResult r = observe_scan(scan);
  EXPECT_GE(r.observation.segments_m.size(), 3u);
}

}  // namespace
}  // namespace floorcast
