#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "floorcast/floorplans/io.hpp"
#include "floorcast/scenarios/compare_matchers.hpp"
#include "floorcast/core/math.hpp"
#include "../match/match_test_plans.hpp"

namespace floorcast {
namespace {

TEST(CompareMatchers, SamplingIsSeededAndClear) {
  const FloorPlan plan = test::asymmetric_floor();
  const auto a = sample_observation_poses(plan, 40, 7, 0, 0.5);
  const auto b = sample_observation_poses(plan, 40, 7, 0, 0.5);
  const auto c = sample_observation_poses(plan, 40, 8, 0, 0.5);
  const auto first10 = sample_observation_poses(plan, 10, 7, 0, 0.5);
  ASSERT_EQ(a.size(), 40u);
  int differ = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].x_m, b[i].x_m);
    EXPECT_EQ(a[i].yaw_rad, b[i].yaw_rad);
    differ += a[i].x_m != c[i].x_m;
    if (i < 10) {
      EXPECT_EQ(a[i].y_m, first10[i].y_m);  // point i does not depend on N
    }
  }
  EXPECT_GT(differ, 30);
  // Clearance from every wall surface.
  const auto outline = blocking_outline(plan, BlockingOptions{});
  for (const Pose2& p : a) {
    double d = 1e9;
    for (const auto& l : outline) {
      const Vec2 e = l.segment_m.b_m - l.segment_m.a_m;
      const double t = std::clamp((p.position_m() - l.segment_m.a_m).dot(e) / e.squaredNorm(), 0.0, 1.0);
      d = std::min(d, (l.segment_m.a_m + t * e - p.position_m()).norm());
    }
    EXPECT_GE(d, 0.5);
    EXPECT_GE(p.yaw_rad, 0.0);
    EXPECT_LT(p.yaw_rad, 2.0 * kPi);
  }
  EXPECT_THROW(sample_observation_poses(plan, 5, 1, 0, 50.0), InputError);
}

TEST(CompareMatchers, SamplingKeepsClearOfFurniture) {
  // The shipped apartment is furnished (beds, sofas, tables: all lower than the 1.5 m cut of the
  // default rasters). No observer stands inside or within the clearance of any of them.
  const FloorPlan plan = load_floor_plan(std::string(FLOORCAST_SOURCE_DIR) + "/floorplans/buildings/apartment.json");
  ASSERT_GT(plan.obstacles.size(), 5u);
  BlockingOptions ground;
  ground.obstacles_block = true;
  ground.cut_height_m = 0.01;
  std::vector<Footprint> furniture;
  for (const Footprint& f : blocking_footprints(plan, ground))
    if (f.label == SurfaceLabel::kObstacle) furniture.push_back(f);
  ASSERT_EQ(furniture.size(), plan.obstacles.size());
  const double clearance_m = 0.3;
  for (const Pose2& p : sample_observation_poses(plan, 300, 3, 0, clearance_m)) {
    for (const Footprint& f : furniture) {
      ASSERT_FALSE(point_in_polygon(f.polygon_m, p.position_m())) << "pose inside obstacle " << f.source_index;
      double d = 1e9;
      for (std::size_t k = 0; k < f.polygon_m.size(); ++k) {
        const Vec2 a = f.polygon_m[k], b = f.polygon_m[(k + 1) % f.polygon_m.size()];
        const Vec2 e = b - a;
        const double t = std::clamp((p.position_m() - a).dot(e) / e.squaredNorm(), 0.0, 1.0);
        d = std::min(d, (a + t * e - p.position_m()).norm());
      }
      EXPECT_GE(d, clearance_m) << "obstacle " << f.source_index;
    }
  }
}

TEST(CompareMatchers, SamplingRegions) {
  const std::vector<Vec2> l_shape = {{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 3}, {0, 3}};
  EXPECT_TRUE(point_in_polygon(l_shape, {0.5, 2.5}));
  EXPECT_TRUE(point_in_polygon(l_shape, {3.5, 0.5}));
  EXPECT_FALSE(point_in_polygon(l_shape, {2.5, 2.0}));  // in the notch
  EXPECT_FALSE(point_in_polygon(l_shape, {-0.1, 0.5}));
  // Only the east room (x > 5) of the asymmetric plan.
  const FloorPlan plan = test::asymmetric_floor();
  const std::vector<std::vector<Vec2>> east = {{{5, 0}, {12, 0}, {12, 5}, {5, 5}}};
  for (const Pose2& p : sample_observation_poses(plan, 30, 4, 0, 0.3, 0.1, east)) {
    EXPECT_GT(p.x_m, 5.3);
    EXPECT_LT(p.y_m, 4.7);
  }
  const std::vector<std::vector<Vec2>> nowhere = {{{20, 20}, {21, 20}, {21, 21}}};
  EXPECT_THROW(sample_observation_poses(plan, 3, 4, 0, 0.3, 0.1, nowhere), InputError);
}

TEST(CompareMatchers, SummaryOnSmallPlan) {
  std::vector<NamedPlan> plans = {{"asym", test::asymmetric_floor(), {}}};
  ComparisonParams params;
  params.points_per_plan = 6;
  params.seed = 3;
  auto specs = default_comparison_specs({36});
  int lines = 0;
  const ComparisonResult r = compare_matchers(plans, specs, params, [&](const std::string&) { ++lines; });
  EXPECT_GT(lines, 0);
  ASSERT_EQ(r.points.size(), 12u);
  const auto j = comparison_summary_json(r);
  ASSERT_TRUE(j.contains("kernel"));
  ASSERT_TRUE(j.contains("ray"));
  for (const char* key : {"recall_0.5m", "recall_1m", "recall_1m_30deg", "recall_2m", "top5_recall_1m",
                          "median_position_error_m", "median_yaw_error_deg", "mean_time_s"}) {
    EXPECT_TRUE(j["kernel"].contains(key)) << key;
  }
  EXPECT_EQ(j["kernel"].size(), 8u);
  // The kernel matcher with perfect observations on a distinctive plan: all within 1 m, 30 deg.
  EXPECT_EQ(j["kernel"]["recall_1m_30deg"], 1.0);
  for (const auto& [label, s] : r.summary) {
    EXPECT_GE(s.recall_2m, s.recall_1m);
    EXPECT_GE(s.recall_1m, s.recall_1m_30deg);
    EXPECT_GE(s.recall_1m, s.recall_0_5m);
    EXPECT_GE(s.top5_recall_1m, s.recall_1m);
    EXPECT_GT(s.mean_time_s, 0.0);
  }
  const std::string csv = comparison_points_csv(r);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 13);
  EXPECT_NE(comparison_markdown(r).find("| kernel |"), std::string::npos);
  EXPECT_EQ(default_comparison_specs({36, 180})[2].label, "ray180");
}

TEST(CompareMatchers, SummariseKnownAnswer) {
  std::vector<PointOutcome> o(4);
  o[0].position_error_m = 0.3, o[0].yaw_error_deg = 2, o[0].time_s = 1;
  o[1].position_error_m = 0.9, o[1].yaw_error_deg = 45, o[1].time_s = 2;
  o[2].position_error_m = 1.5, o[2].yaw_error_deg = 1, o[2].time_s = 3, o[2].top_k_hit_1m = true;
  o[3].position_error_m = 9.0, o[3].yaw_error_deg = 180, o[3].time_s = 6;
  o[0].top_k_hit_1m = o[1].top_k_hit_1m = true;
  const MatcherSummary s = summarise({&o[0], &o[1], &o[2], &o[3]}, 30.0);
  EXPECT_EQ(s.count, 4);
  EXPECT_DOUBLE_EQ(s.recall_0_5m, 0.25);
  EXPECT_DOUBLE_EQ(s.recall_1m, 0.5);
  EXPECT_DOUBLE_EQ(s.recall_1m_30deg, 0.25);
  EXPECT_DOUBLE_EQ(s.recall_2m, 0.75);
  EXPECT_DOUBLE_EQ(s.top5_recall_1m, 0.75);
  EXPECT_DOUBLE_EQ(s.median_position_error_m, 1.2);
  EXPECT_DOUBLE_EQ(s.median_yaw_error_deg, 23.5);
  EXPECT_DOUBLE_EQ(s.mean_time_s, 3.0);
}

}  // namespace
}  // namespace floorcast
