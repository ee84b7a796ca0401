// Plane extraction (PCA, PCL RANSAC and region growing, VoxelPlane) and the LiDAR path.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>

#include "floorcast/observe/observation_module.hpp"
#include "floorcast/bench/plane_accuracy.hpp"
#include "segment_checks.hpp"
#include "synthetic_scan.hpp"

namespace floorcast {
namespace {

TEST(ObservePlanes, PcaRecoversAnExactPlane) {
  const Eigen::Vector3d n = Eigen::Vector3d(1.0, 2.0, -0.5).normalized();
  const Eigen::Vector3d e1 = n.unitOrthogonal(), e2 = n.cross(e1);
  PointCloud3f pts;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j) pts.push_back((-3.0 * n + 0.1 * i * e1 + 0.13 * j * e2).cast<float>());
  const Plane3 p = fit_plane_pca(pts);
  EXPECT_LT(plane_angle_error_deg(p.normal, n), 1e-3);
  EXPECT_LT(plane_offset_error_m(n, -3.0, p.normal, p.offset_m), 1e-5);
  EXPECT_LE(p.offset_m, 0.0);  // oriented towards the origin
  EXPECT_LT(p.rms_m, 1e-5);
  EXPECT_EQ(p.point_indices.size(), pts.size());
}

TEST(ObservePlanes, AdaptiveWeightIsContinuousAndDecreasing) {
  const VoxelPlaneParams vp;
  EXPECT_DOUBLE_EQ(voxel_plane_weight(0.0, vp), 1.0);
  EXPECT_NEAR(voxel_plane_weight(1.0 - 1e-9, vp), voxel_plane_weight(1.0 + 1e-9, vp), 1e-6);
  double prev = 2.0;
  for (double rho = 0.0; rho <= 2.0; rho += 0.05) {
    const double w = voxel_plane_weight(rho, vp);
    EXPECT_LT(w, prev);
    EXPECT_GT(w, 0.0);
    prev = w;
  }
}

TEST(ObservePlanes, MetricsAreSignFree) {
  const Eigen::Vector3d n(0, 0, 1);
  EXPECT_NEAR(plane_angle_error_deg(n, -n), 0.0, 1e-9);
  EXPECT_NEAR(plane_offset_error_m(n, 2.0, -n, -2.1), 0.1, 1e-12);
  EXPECT_NEAR(plane_angle_error_deg(n, Eigen::Vector3d(1, 0, 1)), 45.0, 1e-9);
}

TEST(ObservePlanes, VoxelPlaneBeatsPlainPcaOnNoisyPlanesWithOutliers) {
  // Table 2 protocol: points 1-9 m away, Gaussian noise along the normal (1 cm + 0.1 cm x r^2),
  // and 5% outliers (flying pixels). Plain PCA has no defence against the outliers.
  PlaneNoiseModel noise;
  noise.name = "test";
  noise.sigma_const_m = 0.01;
  noise.sigma_quadratic_per_m = 0.001;
  noise.outlier_fraction = 0.05;
  PlaneBenchParams bp;
  bp.points_per_plane = 8000;
  const PlaneAccuracyReport r = run_plane_accuracy(noise, bp);
  const PlaneMethodResult* pca = nullptr;
  const PlaneMethodResult* vox = nullptr;
  for (const auto& m : r.methods) {
    if (m.method == "pca") pca = &m;
    if (m.method == "voxelplane") vox = &m;
  }
  ASSERT_TRUE(pca && vox);
  EXPECT_EQ(vox->failures, 0);
  EXPECT_LT(vox->mean_angle_deg, 0.5 * pca->mean_angle_deg)
      << "voxelplane " << vox->mean_angle_deg << " deg, pca " << pca->mean_angle_deg << " deg";
  int better = 0;
  for (int k = 0; k < r.planes; ++k) better += vox->angle_error_deg[k] < pca->angle_error_deg[k] ? 1 : 0;
  EXPECT_GE(better, 8);
  EXPECT_LT(vox->mean_offset_m, pca->mean_offset_m);
}

TEST(ObservePlanes, VoxelPlaneSeparatesTheSurfacesOfARoom) {
  const test::Scene sc = test::box_room(-2.0, 3.0, -1.5, 2.5);
  const Scan scan = test::render_scan(sc, 6, 108.0, -15.0, 160, 120, {}, 0.003);
  const BackProjectionResult bp = back_project_scan(scan, lidar_back_projection_defaults());
  PointCloud3f cloud;
  for (const auto& v : bp.views) {
    const PointCloud3f q = view_points_scan(v, 1.0);
    cloud.insert(cloud.end(), q.begin(), q.end());
  }
  cloud = voxel_downsample(cloud, 0.05);
  const VoxelPlaneResult r = extract_planes_voxel(cloud, VoxelPlaneParams{});
  // The six largest planes are the 4 walls, floor and ceiling, each within 1 deg and 3 cm.
  ASSERT_GE(r.planes.size(), 6u);
  const std::vector<std::pair<Eigen::Vector3d, double>> truth = {
      {{1, 0, 0}, -2.0}, {{1, 0, 0}, 3.0}, {{0, 1, 0}, -1.5}, {{0, 1, 0}, 2.5}, {{0, 0, 1}, -1.5}, {{0, 0, 1}, 1.3}};
  std::vector<bool> found(truth.size(), false);
  for (std::size_t k = 0; k < 6; ++k) {
    const Plane3& p = r.planes[k];
    for (std::size_t t = 0; t < truth.size(); ++t) {
      if (plane_angle_error_deg(p.normal, truth[t].first) < 1.0 &&
          plane_offset_error_m(truth[t].first, truth[t].second, p.normal, p.offset_m) < 0.03) {
        found[t] = true;
      }
    }
  }
  for (std::size_t t = 0; t < truth.size(); ++t) EXPECT_TRUE(found[t]) << "surface " << t;
  EXPECT_LT(r.planes_after_merge, r.planar_voxels);
}

TEST(ObserveLidar, BoxRoomGivesItsFourWallsWithEitherExtractor) {
  const auto corners = test::rotated_box(-2.3, 3.4, -1.7, 2.6, 23.0);
  test::Scene sc;
  sc.add_room(corners, 1.5, 2.8);
  // LiDAR-like: 0.5% depth noise per pixel.
  const Scan scan = test::render_scan(sc, 6, 108.0, -15.0, 256, 192, {}, 0.005);
  for (const PlaneExtractorKind kind : {PlaneExtractorKind::kPclRegionGrowing, PlaneExtractorKind::kVoxelPlane}) {
    ObservationParams p;
    p.path = ObservationPath::kLidar;
    p.lidar.extractor = kind;
    const ObservationResult r = observe_scan(scan, p);
    const auto walls = test::polygon_walls(corners);
    const test::WallMatch m = test::match_walls(r.observation.segments_m, walls, 0.05, 1.0);
    EXPECT_TRUE(m.stray.empty()) << to_string(kind) << ": " << m.stray.size() << " stray, first: "
                                 << (m.stray.empty() ? "" : m.stray[0]);
    for (std::size_t w = 0; w < walls.size(); ++w) {
      EXPECT_GT(m.coverage[w], 0.8) << to_string(kind) << " wall " << w;
    }
    EXPECT_EQ(r.diagnostics.wall_planes, r.observation.segments_m.size());
    EXPECT_EQ(r.observation.ray_ranges_m.size(), 36u);
  }
}

TEST(ObserveLidar, SameOutputAtOneAndTwoThreads) {
  const test::Scene sc = test::box_room(-2.0, 3.0, -1.5, 2.5);
  const Scan scan = test::render_scan(sc, 6, 108.0, -15.0, 160, 120, {}, 0.005);
  for (const PlaneExtractorKind kind : {PlaneExtractorKind::kPclRegionGrowing, PlaneExtractorKind::kVoxelPlane}) {
    auto run = [&](int threads) {
      tbb::global_control c(tbb::global_control::max_allowed_parallelism, threads);
      ObservationParams p;
      p.path = ObservationPath::kLidar;
      p.lidar.extractor = kind;
      const ObservationResult r = observe_scan(scan, p);
      nlohmann::ordered_json j = to_json(r.diagnostics);
      for (const auto& s : r.observation.segments_m) j["seg"].push_back({s.a_m.x(), s.a_m.y(), s.b_m.x(), s.b_m.y()});
      return j.dump();
    };
    EXPECT_EQ(run(1), run(2)) << to_string(kind);
  }
}

}  // namespace
}  // namespace floorcast
