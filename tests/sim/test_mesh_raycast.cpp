// Extrusion and Embree ray casting against exact references.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "floorcast/floorplans/io.hpp"
#include "floorcast/sim/mesh.hpp"
#include "floorcast/sim/ray_scene.hpp"
#include "sim_test_util.hpp"

namespace floorcast {
namespace {

using test::box_room;
using test::feature_plan;

TEST(Extrusion, BoxRoomHasWallsFloorCeilingWithOutwardNormals) {
  const Mesh mesh = extrude_plan(box_room(6.0, 4.0, 0.2));
  // 4 inner faces + 4 outer faces, one band, 2 triangles each.
  EXPECT_EQ(mesh.count(MeshLabel::kWall), 16u);
  EXPECT_GT(mesh.count(MeshLabel::kFloor), 0u);
  EXPECT_EQ(mesh.count(MeshLabel::kFloor), mesh.count(MeshLabel::kCeiling));
  EXPECT_EQ(mesh.labels.size(), mesh.triangles.size());
  EXPECT_EQ(mesh.part_ids.size(), mesh.triangles.size());
  Eigen::Vector3f lo, hi;
  mesh_bounds(mesh, lo, hi);
  EXPECT_NEAR(lo.z(), 0.0f, 1e-6f);
  EXPECT_NEAR(hi.z(), 3.0f, 1e-6f);
  EXPECT_NEAR(lo.x(), -0.1f, 1e-6f);
  EXPECT_NEAR(hi.x(), 6.1f, 1e-6f);
  // Inner faces face the room centre; floor faces up, ceiling down.
  const Eigen::Vector3f centre(3.0f, 2.0f, 1.5f);
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const Eigen::Vector3f n = mesh.normal(i);
    const Eigen::Vector3f a = mesh.vertices_m[static_cast<std::size_t>(mesh.triangles[i][0])];
    if (mesh.labels[i] == MeshLabel::kFloor) {
      EXPECT_GT(n.z(), 0.99f);
    }
    if (mesh.labels[i] == MeshLabel::kCeiling) {
      EXPECT_LT(n.z(), -0.99f);
    }
    if (mesh.labels[i] == MeshLabel::kWall) {
      const bool any_inner = std::abs(a.x() - 0.1f) < 1e-4f || std::abs(a.x() - 5.9f) < 1e-4f ||
                             std::abs(a.y() - 0.1f) < 1e-4f || std::abs(a.y() - 3.9f) < 1e-4f;
      if (any_inner) {
        EXPECT_GT(n.dot(centre - a), 0.0f) << "inner wall face " << i << " must face the room";
      } else {
        EXPECT_LT(n.dot(centre - a), 0.0f) << "outer wall face " << i << " must face away";
      }
    }
  }
}

TEST(Extrusion, FeaturePlanHasEveryLabelAndRejectsBadParams) {
  const Mesh mesh = extrude_plan(feature_plan());
  for (MeshLabel l : {MeshLabel::kWall, MeshLabel::kDoorClosed, MeshLabel::kGlass, MeshLabel::kClutter,
                      MeshLabel::kFloor, MeshLabel::kCeiling}) {
    EXPECT_GT(mesh.count(l), 0u) << mesh_label_name(l);
  }
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    if (mesh.labels[i] == MeshLabel::kGlass) {
      EXPECT_GE(mesh.part_ids[i], 0);
    } else {
      EXPECT_EQ(mesh.part_ids[i], -1);
    }
  }
  ExtrusionParams bad;
  bad.door_height_m = 3.5;
  EXPECT_THROW(extrude_plan(feature_plan(), bad), InputError);
  bad = {};
  bad.wall_height_m = -1.0;
  EXPECT_THROW(extrude_plan(feature_plan(), bad), InputError);
  MeshLabel l;
  EXPECT_TRUE(mesh_label_from_name("door_closed", l));
  EXPECT_EQ(l, MeshLabel::kDoorClosed);
  EXPECT_FALSE(mesh_label_from_name("sofa", l));
}

TEST(RayScene, MatchesBruteForceOnRandomRays) {
  const FloorPlan plan = feature_plan();
  const RayScene scene(extrude_plan(plan));
  const Mesh& mesh = scene.mesh();
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> ux(0.2, 7.8), uy(0.2, 4.8), uz(0.1, 2.9), ua(-1.0, 1.0);
  std::vector<Ray3> rays;
  std::vector<Eigen::Vector3d> os, ds;
  for (int i = 0; i < 3000; ++i) {
    const Eigen::Vector3d o(ux(rng), uy(rng), uz(rng));
    Eigen::Vector3d d(ua(rng), ua(rng), ua(rng));
    if (d.norm() < 1e-3) continue;
    d *= 0.3 + std::abs(ua(rng));  // non-unit directions on purpose
    os.push_back(o);
    ds.push_back(d);
    rays.push_back({o.cast<float>(), d.cast<float>(), 0.0f, std::numeric_limits<float>::infinity()});
  }
  std::vector<RayHit3> hits(rays.size());
  scene.intersect_stream(rays.data(), hits.data(), rays.size(), false);
  int compared = 0, label_checked = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    int tri = -1;
    double second = 0.0;
    const double t = test::brute_force_hit(mesh, os[i], ds[i], tri, &second);
    const RayHit3 single = scene.intersect(rays[i]);
    EXPECT_EQ(single.triangle, hits[i].triangle);
    ASSERT_EQ(std::isfinite(t), hits[i].hit()) << "ray " << i;
    if (!hits[i].hit()) continue;
    const double range = t * ds[i].norm();
    EXPECT_NEAR(hits[i].t * ds[i].norm(), range, 2e-5 * std::max(1.0, range)) << "ray " << i;
    ++compared;
    if ((second - t) * ds[i].norm() > 1e-4) {
      EXPECT_EQ(mesh.labels[static_cast<std::size_t>(hits[i].triangle)], mesh.labels[static_cast<std::size_t>(tri)]);
      ++label_checked;
    }
  }
  EXPECT_GT(compared, 2500);
  EXPECT_GT(label_checked, 2000);
}

TEST(RayScene, ClosedBuildingIsWatertight) {
  // Every ray from inside the closed feature plan (front door closed, glass solid) hits a surface.
  const RayScene scene(extrude_plan(feature_plan()));
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> ux(0.3, 4.7), uy(0.3, 3.2), uz(0.8, 2.9), ua(-1.0, 1.0);
  std::vector<Ray3> rays;
  for (int i = 0; i < 20000; ++i) {
    Eigen::Vector3d o(ux(rng), uy(rng), uz(rng));
    if ((o.head<2>() - Eigen::Vector2d(2.0, 3.8)).norm() < 1.0) continue;  // desk
    Eigen::Vector3d d(ua(rng), ua(rng), ua(rng));
    if (d.norm() < 1e-3) continue;
    rays.push_back({o.cast<float>(), d.normalized().cast<float>(), 0.0f, std::numeric_limits<float>::infinity()});
  }
  std::vector<RayHit3> hits(rays.size());
  scene.intersect_stream(rays.data(), hits.data(), rays.size(), false);
  int escaped = 0;
  for (const RayHit3& h : hits) escaped += !h.hit();
  EXPECT_EQ(escaped, 0);
}

TEST(RayScene, OpenDoorHasLintelAtDoorHeight) {
  const RayScene scene(extrude_plan(feature_plan()));
  // Looking through the open inner door (wall mid at x = 5, door centred at y = 1.5, width 0.9)
  // from x = 3: below the door height the ray passes into the east room; above it, the lintel.
  const Ray3 low{{3.0f, 1.5f, 1.0f}, {1.0f, 0.0f, 0.0f}, 0.0f, 100.0f};
  const RayHit3 h_low = scene.intersect(low);
  ASSERT_TRUE(h_low.hit());
  EXPECT_GT(h_low.t, 3.2f);  // beyond the wall at x = 4.95
  const Ray3 high{{3.0f, 1.5f, 2.5f}, {1.0f, 0.0f, 0.0f}, 0.0f, 100.0f};
  const RayHit3 h_high = scene.intersect(high);
  ASSERT_TRUE(h_high.hit());
  EXPECT_NEAR(h_high.t, 1.95f, 1e-5f);
  EXPECT_EQ(scene.mesh().labels[static_cast<std::size_t>(h_high.triangle)], MeshLabel::kWall);
  // Soffit: looking up inside the doorway.
  const Ray3 up{{5.0f, 1.5f, 1.0f}, {0.0f, 0.0f, 1.0f}, 0.0f, 100.0f};
  const RayHit3 h_up = scene.intersect(up);
  ASSERT_TRUE(h_up.hit());
  EXPECT_NEAR(h_up.t, 1.1f, 1e-5f);
  // Window: glass between sill 0.9 and head 2.1 in the north wall (inner face y = 4.9).
  for (const auto& [z, label] : std::vector<std::pair<float, MeshLabel>>{
           {0.85f, MeshLabel::kWall}, {1.5f, MeshLabel::kGlass}, {2.5f, MeshLabel::kWall}}) {
    const RayHit3 h = scene.intersect({{2.5f, 3.0f, z}, {0.0f, 1.0f, 0.0f}, 0.0f, 100.0f});
    ASSERT_TRUE(h.hit());
    EXPECT_NEAR(h.t, 1.9f, 1e-5f);
    EXPECT_EQ(scene.mesh().labels[static_cast<std::size_t>(h.triangle)], label) << "z = " << z;
  }
}

TEST(RayScene, EmptyMeshIsAnError) { EXPECT_THROW(RayScene(Mesh{}), InputError); }

}  // namespace
}  // namespace floorcast
