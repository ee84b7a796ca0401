// The simulator's column semantics (SimulationOptions::column_semantics): what each image
// column's horizontal ray meets, through the extruded mesh (doors found by the lintel probe),
// equals the plan's brute-force semantic cast (floorplans/semantic_rays.hpp) at camera height,
// plus the furniture the plan's lines leave out.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "floorcast/core/math.hpp"
#include "floorcast/floorplans/semantic_rays.hpp"
#include "floorcast/sim/mesh.hpp"
#include "floorcast/sim/ray_scene.hpp"
#include "floorcast/sim/scan_params.hpp"
#include "floorcast/sim/scan_sim.hpp"

namespace floorcast {
namespace {

Wall wall(const char* id, double ax, double ay, double bx, double by) {
  Wall w;
  w.id = id;
  w.a_m = {ax, ay};
  w.b_m = {bx, by};
  w.thickness_m = 0.15;
  return w;
}

/// A 12 x 4 m hall split by three cross walls: an open door, a closed door, a window; a cabinet
/// (1.8 m, taller than the camera) and a desk (0.75 m) in the first room.
FloorPlan hall() {
  FloorPlan p;
  p.walls = {wall("s", 0, 0, 12, 0), wall("e", 12, 0, 12, 4), wall("n", 12, 4, 0, 4), wall("w", 0, 4, 0, 0),
             wall("x1", 4, 0, 4, 4),  wall("x2", 7, 0, 7, 4),   wall("x3", 9.5, 0, 9.5, 4)};
  p.doors = {{"open", "x1", {4.0, 2.0}, 1.2, false}, {"closed", "x2", {7.0, 2.0}, 1.2, true}};
  p.windows = {{"glass", "x3", {9.5, 2.0}, 1.6, 0.9, 2.1}};
  Obstacle cabinet;
  cabinet.id = "cabinet";
  cabinet.center_m = {2.0, 3.5};
  cabinet.size_m = {1.0, 0.5};
  cabinet.height_m = 1.8;
  Obstacle desk = cabinet;
  desk.id = "desk";
  desk.center_m = {2.0, 0.6};
  desk.height_m = 0.75;
  p.obstacles = {cabinet, desk};
  return p;
}

TEST(ColumnSemantics, EqualsThePlansSemanticCast) {
  const FloorPlan plan = hall();
  const RayScene scene(extrude_plan(plan));
  const SemanticPlanLines lines = semantic_plan_lines(plan, BevClasses::kSemantic, 1.5);
  ScanParams sp = scan_preset("perfect");
  sp.geometry.pitch_deg = -10.0;  // columns are the gravity-aligned ones whatever the pitch
  const CameraIntrinsics K = view_intrinsics(sp.geometry);
  const Pose2 pose{1.0, 2.1, 0.0};
  int doors_open = 0, doors_closed = 0, windows = 0, furniture = 0;
  std::size_t checked = 0;
  std::vector<std::string> mismatches;
  for (int view = 0; view < sp.geometry.num_views; ++view) {
    const Eigen::Isometry3d T_world_camera = scan_frame_in_world(pose, 1.5) * view_pose(sp.geometry, view);
    const auto columns = simulate_column_semantics(scene, T_world_camera, K, 20.0, 2.55);
    ASSERT_EQ(columns.size(), static_cast<std::size_t>(K.width_px));
    const Eigen::Vector3d axis = T_world_camera.linear().col(2);
    for (int u = 0; u < K.width_px; u += 7) {
      const double az = std::atan2(axis.y(), axis.x()) + std::atan((K.cx_px - u) / K.fx_px);
      const std::vector<SemanticHit> expect = semantic_ray_hits(lines, pose.position_m(), az, 20.0);
      std::vector<SemanticHit> got;
      for (const SemanticHit& h : columns[static_cast<std::size_t>(u)]) {
        if (h.label == SemanticClass::kFurniture) {
          ++furniture;
          // The cabinet (the desk is below the camera): a point of its outline facing the camera.
          const double x = pose.x_m + h.range_m * std::cos(az), y = pose.y_m + h.range_m * std::sin(az);
          const bool on_left = std::abs(x - 1.5) < 0.02 && y > 3.23 && y < 3.77;
          const bool on_bottom = std::abs(y - 3.25) < 0.02 && x > 1.48 && x < 2.52;
          EXPECT_TRUE(on_left || on_bottom) << "view " << view << " column " << u << ": " << x << ", " << y;
          continue;
        }
        got.push_back(h);
      }
      auto text = [](const std::vector<SemanticHit>& hits) {
        std::string t;
        for (const SemanticHit& h : hits) t += std::string(" ") + semantic_class_name(h.label) + "@" + std::to_string(h.range_m);
        return t;
      };
      bool same = got.size() == expect.size();
      for (std::size_t i = 0; same && i < got.size(); ++i) {
        same = got[i].label == expect[i].label && std::abs(got[i].range_m - expect[i].range_m) < 2e-3;
      }
      ++checked;
      if (!same) {
        mismatches.push_back("view " + std::to_string(view) + " column " + std::to_string(u) + " azimuth " +
                             std::to_string(rad_to_deg(az)) + ": got" + text(got) + ", expected" + text(expect));
        continue;
      }
      for (const SemanticHit& h : got) {
        doors_open += h.label == SemanticClass::kDoorOpen;
        doors_closed += h.label == SemanticClass::kDoorClosed;
        windows += h.label == SemanticClass::kWindow;
      }
    }
  }
  // Rays grazing the edge where a pane meets its wall may slip between the mesh's faces (the
  // depth sensor sees the same): at most 1% of the columns.
  EXPECT_LE(mismatches.size(), checked / 100);
  for (const std::string& m : mismatches) std::printf("mismatch: %s\n", m.c_str());
  EXPECT_GT(checked, 500u);
  EXPECT_GT(doors_open, 3);
  EXPECT_GT(doors_closed, 3);
  EXPECT_GT(windows, 3);
  EXPECT_GT(furniture, 3);
}

TEST(ColumnSemantics, SimulatedScansCarryThemOnlyWhenAsked) {
  const RayScene scene(extrude_plan(hall()));
  ScanParams sp = scan_preset("mono");
  sp.seed = 3;
  const SimulatedScan plain = simulate_scan(scene, {1.0, 2.1, 0.3}, sp);
  EXPECT_TRUE(plain.scan.views[0].column_semantics.empty());
  SimulationOptions o;
  o.column_semantics = true;
  const SimulatedScan annotated = simulate_scan(scene, {1.0, 2.1, 0.3}, sp, o);
  ASSERT_EQ(annotated.scan.views.size(), plain.scan.views.size());
  for (std::size_t k = 0; k < plain.scan.views.size(); ++k) {
    EXPECT_EQ(annotated.scan.views[k].column_semantics.size(), static_cast<std::size_t>(sp.geometry.width_px));
    // The sensor realisation is the same.
    EXPECT_EQ(cv::norm(annotated.scan.views[k].depth_m, plain.scan.views[k].depth_m, cv::NORM_INF), 0.0);
  }
}

}  // namespace
}  // namespace floorcast
