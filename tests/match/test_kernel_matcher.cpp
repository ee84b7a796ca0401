#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>

#include "floorcast/match/kernel_matcher.hpp"
#include "floorcast/match/plan_raster.hpp"
#include "floorcast/sim/perfect_observation.hpp"
#include "floorcast/core/math.hpp"
#include "match_test_plans.hpp"

namespace floorcast {
namespace {


TEST(KernelMatcher, KernelsFollowPalms) {
  const FloorPlan plan = test::asymmetric_floor();
  const PerfectObserver observer(plan);
  const Observation2D obs = observer.observe({3.2, 1.6, 0.3});
  KernelMatcherParams p;
  const int R = kernel_radius_px(p);
  EXPECT_EQ(R, 110 + 7 + 1);  // 10 m * 1.1 at 0.1 m, plus half the 15 px blur, plus one
  const LayoutKernels k = make_layout_kernels(p, obs.segments_m, 0.3, 1.0, R);
  ASSERT_EQ(k.p.rows, 2 * R + 1);
  double mn = 0.0, mx = 0.0;
  cv::minMaxLoc(k.p, &mn, &mx);
  EXPECT_GE(mn, 0.0);
  EXPECT_NEAR(cv::sum(k.p)[0], 1.0, 1e-4);
  // CES: 0/1, contains the observer (an enclosed observer sees all around), and stays off the
  // observed wall lines thanks to the shrink.
  EXPECT_EQ(k.ces.at<float>(R, R), 1.0f);
  cv::Mat lines = cv::Mat::zeros(2 * R + 1, 2 * R + 1, CV_8U);
  std::vector<Segment2> rotated;
  for (const Segment2& s : obs.segments_m) {
    const Pose2 rot{0.0, 0.0, 0.3};
    rotated.push_back({rot.transform(s.a_m), rot.transform(s.b_m)});
  }
  draw_segment_lines(lines, rotated, {-(R + 0.5) * 0.1, -(R + 0.5) * 0.1}, 0.1);
  for (int r = 0; r < lines.rows; ++r) {
    for (int c = 0; c < lines.cols; ++c) {
      if (lines.at<std::uint8_t>(r, c)) {
        EXPECT_EQ(k.ces.at<float>(r, c), 0.0f) << r << "," << c;
      }
    }
  }
  // The CES area is about shrink^2 of the visible area (eroded by a pixel).
  const double ces_area = cv::sum(k.ces)[0] * 0.01;
  EXPECT_GT(ces_area, 0.3 * 0.49 * 15.0);
  // No segments: all-zero kernels.
  const LayoutKernels empty = make_layout_kernels(p, {}, 0.0, 1.0, R);
  EXPECT_EQ(cv::countNonZero(empty.p), 0);
  EXPECT_EQ(cv::countNonZero(empty.ces), 0);
}

// Known answers for the score's ingredients as PALMS' code builds them (CES.py: blur (15, 3) px,
// Gaussian distance weight of sigma 10 m that favours NEAR walls, shrink 0.7 about the observer,
// one-pixel erosion). Two long walls, one 3.5 m in front of the observer and one 8.5 m behind,
// placed so every edge falls mid-pixel.
TEST(KernelMatcher, KernelIngredientsKnownAnswers) {
  const KernelMatcherParams p;  // defaults = the paper's values
  const int R = kernel_radius_px(p);
  // Free space on each segment's left, as observations are oriented.
  const std::vector<Segment2> obs = {{Vec2(3.5, -4.0), Vec2(3.5, 4.0)}, {Vec2(-8.5, 4.0), Vec2(-8.5, -4.0)}};
  const LayoutKernels k = make_layout_kernels(p, obs, 0.0, 1.0, R);
  const auto P = [&](int dx_px) { return static_cast<double>(k.p.at<float>(R, R + dx_px)); };
  // Across a long straight line the blurred profile is the 1-D Gaussian of sigma 3 px, times the
  // distance weight exp(-d^2 / (2 * 10^2)): one pixel outwards costs exp(-1/18) and the weight
  // of 3.6 m vs 3.5 m.
  const double w_step = std::exp(-(3.6 * 3.6 - 3.5 * 3.5) / 200.0);
  EXPECT_NEAR(P(36) / P(35), std::exp(-1.0 / 18.0) * w_step, 1e-4);
  EXPECT_NEAR(P(34) / P(35), std::exp(-1.0 / 18.0) / std::exp(-(3.5 * 3.5 - 3.4 * 3.4) / 200.0), 1e-4);
  // Near walls weigh more than far ones (PALMS: "weight segments closer to the observation point
  // more"): same blur, weight ratio exp(-(8.5^2 - 3.5^2) / 200).
  EXPECT_NEAR(P(-85) / P(35), std::exp(-(8.5 * 8.5 - 3.5 * 3.5) / 200.0), 1e-4);
  // P is a distribution: min-max scaled, then divided by its sum.
  EXPECT_NEAR(cv::sum(k.p)[0], 1.0, 1e-4);
  // The 15 px blur reaches 7 px from the line and no farther.
  EXPECT_GT(P(35 + 7), 0.0);
  EXPECT_EQ(P(35 + 8), 0.0);
  // CES along the x axis: shrunk to 0.7 * 3.5 = 2.45 m and 0.7 * 8.5 = 5.95 m, so it holds the
  // pixel centres up to 2.4 m and down to -5.9 m; eroded by one pixel: 2.3 m and -5.8 m.
  EXPECT_EQ(k.ces.at<float>(R, R + 23), 1.0f);
  EXPECT_EQ(k.ces.at<float>(R, R + 24), 0.0f);
  EXPECT_EQ(k.ces.at<float>(R, R - 58), 1.0f);
  EXPECT_EQ(k.ces.at<float>(R, R - 59), 0.0f);
  // alpha: every alpha >= 1 correlates the same clipped score; PALMS' 10 is one of them.
  EXPECT_EQ(p.alpha, 10.0);
  EXPECT_GE(correlation_alpha(p.alpha), 1.0);
}

TEST(KernelMatcher, PosteriorEqualsDirectCorrelation) {
  // A small room and a short range so the direct correlation is cheap.
  FloorPlan plan;
  plan.walls = {test::wall("a", 0, 0, 4, 0), test::wall("b", 4, 0, 4, 3), test::wall("c", 4, 3, 0, 3),
                test::wall("d", 0, 3, 0, 0), test::wall("e", 2.5, 0, 2.5, 1.2)};
  KernelMatcherParams p;
  p.max_range_m = 3.0;
  p.ces_window_m = 3.0;
  p.scales = {1.0};
  const KernelMatcher m(plan, p);
  PerfectObservationParams pp;
  pp.max_range_m = 3.0;
  pp.num_rays = 0;
  const PerfectObserver observer(plan, pp);
  const Observation2D obs = observer.observe({1.3, 1.9, 0.2});
  const MatchResult r = m.match_yaws(obs, {0.2});
  const int R = kernel_radius_px(p);
  const LayoutKernels k = make_layout_kernels(p, obs.segments_m, 0.2, 1.0, R);
  const cv::Mat kernel = k.p - p.alpha * k.ces;  // the PALMS kernel itself (alpha = 10)
  const cv::Mat& F = m.plan_raster();
  const GridSpec& g = m.grid();
  // Single-precision FFT round-off of this kernel stays below tol; values near the zero_below
  // cut may land on either side of it.
  const double tol = 2e-5;
  int positives = 0, bad = 0;
  double worst = 0.0;
  for (int row = 0; row < g.height_px; ++row)
    for (int col = 0; col < g.width_px; ++col) {
      double s = 0.0;
      for (int dr = -R; dr <= R; ++dr)
        for (int dc = -R; dc <= R; ++dc) {
          const int rr = row + dr, cc = col + dc;
          if (rr < 0 || cc < 0 || rr >= g.height_px || cc >= g.width_px || !F.at<std::uint8_t>(rr, cc)) continue;
          s += kernel.at<float>(R + dr, R + dc);
        }
      if (!m.valid_mask().at<std::uint8_t>(row, col)) s = -1.0;
      const double got = r.posterior.scores[0].at<float>(row, col);
      if (s > p.zero_below + tol) {
        ++positives;
        worst = std::max(worst, std::abs(got - s));
        bad += std::abs(got - s) > tol;
      } else if (s < p.zero_below - tol) {
        bad += got != 0.0;
      } else {
        bad += got != 0.0 && std::abs(got - s) > tol;
      }
    }
  EXPECT_GT(positives, 20);
  EXPECT_EQ(bad, 0) << "worst " << worst;
}

void expect_argmax_at_truth(const KernelMatcher& m, const PerfectObserver& observer, const Pose2& truth,
                            double yaw_tol_rad) {
  const MatchResult r = m.match(observer.observe(truth));
  const PoseHypothesis h = r.posterior.argmax();
  // Within one cell of the true position, one orientation step of the true yaw.
  EXPECT_LE(std::abs(h.x_m - truth.x_m), 0.1 + 1e-9) << truth.x_m << "," << truth.y_m << " got " << h.x_m << "," << h.y_m;
  EXPECT_LE(std::abs(h.y_m - truth.y_m), 0.1 + 1e-9) << truth.x_m << "," << truth.y_m << " got " << h.x_m << "," << h.y_m;
  EXPECT_LE(angle_distance_rad(h.yaw_rad, truth.yaw_rad), yaw_tol_rad) << truth.yaw_rad << " got " << h.yaw_rad;
  EXPECT_GT(h.score, 0.0);
}

TEST(KernelMatcher, PerfectObservationArgmaxIsTruePose) {
  const FloorPlan plan = test::asymmetric_floor();
  const PerfectObserver observer(plan);
  const KernelMatcher palms_plus(plan);
  KernelMatcherParams palms_p;
  palms_p.orientation.mode = OrientationMode::kPalms;
  const KernelMatcher palms(plan, palms_p);
  KernelMatcherParams dense_p;
  dense_p.orientation.mode = OrientationMode::kDense;
  const KernelMatcher dense(plan, dense_p);
  const std::vector<Pose2> spots = {{3.23, 1.61, 0.31}, {2.18, 5.44, 2.5}, {10.31, 3.07, 4.4}, {6.72, 6.83, 5.9}};
  for (const Pose2& t : spots) {
    expect_argmax_at_truth(palms_plus, observer, t, 0.5 * kPi / 180.0 + 1e-9);  // one 0.5 deg bin
    expect_argmax_at_truth(palms, observer, t, 0.5 * kPi / 180.0 + 1e-9);
  }
  // Dense candidates: the true yaw on the 10 deg grid.
  expect_argmax_at_truth(dense, observer, {3.23, 1.61, 40.0 * kPi / 180.0}, 1e-9);
  expect_argmax_at_truth(dense, observer, {10.31, 3.07, 250.0 * kPi / 180.0}, 1e-9);
}

/// Posterior b equals posterior a moved by `map` (world a -> world b), slice s of a matching
/// slice `slice_map(s)` of b: every cell of a that maps into b's grid agrees up to single-precision
/// FFT round-off (the two grids have different transform sizes). Cells where the two plans'
/// valid-area masks differ (floorplans' rasteriser) are skipped.
template <typename Map, typename SliceMap>
void expect_moved_posterior(const KernelMatcher& a, const MatchResult& ra, const KernelMatcher& b,
                            const MatchResult& rb, Map map, SliceMap slice_map) {
  int compared = 0, positive = 0, bad = 0;
  for (int s = 0; s < ra.posterior.num_slices(); ++s) {
    const cv::Mat& A = ra.posterior.scores[static_cast<std::size_t>(s)];
    const cv::Mat& B = rb.posterior.scores[static_cast<std::size_t>(slice_map(s))];
    for (int r = 0; r < A.rows; ++r)
      for (int c = 0; c < A.cols; ++c) {
        int rr, cc;
        if (!b.grid().world_to_cell(map(a.grid().cell_center_m(r, c)), rr, cc)) continue;
        if ((a.valid_mask().at<std::uint8_t>(r, c) != 0) != (b.valid_mask().at<std::uint8_t>(rr, cc) != 0)) continue;
        ++compared;
        const float x = A.at<float>(r, c), y = B.at<float>(rr, cc);
        positive += x > 0.0f;
        bad += std::abs(x - y) > 5e-5f + 1e-4f * std::max(x, y);
      }
  }
  EXPECT_GT(compared, a.grid().width_px * a.grid().height_px);
  EXPECT_GT(positive, 200);
  EXPECT_EQ(bad, 0);
  const PoseHypothesis ha = ra.posterior.argmax(), hb = rb.posterior.argmax();
  const Vec2 moved = map(Vec2(ha.x_m, ha.y_m));
  EXPECT_NEAR(hb.x_m, moved.x(), 1e-6);
  EXPECT_NEAR(hb.y_m, moved.y(), 1e-6);
}

TEST(KernelMatcher, TranslatedPlanMovesPosterior) {
  const FloorPlan plan = test::asymmetric_floor();
  const FloorPlan moved = test::transformed(plan, 0.0, 3.0, -2.0);
  const KernelMatcher a(plan), b(moved);
  const Observation2D obs = PerfectObserver(plan).observe({3.23, 1.61, 0.31});
  const MatchResult ra = a.match(obs), rb = b.match(obs);
  ASSERT_EQ(ra.posterior.yaw_rad, rb.posterior.yaw_rad);
  expect_moved_posterior(a, ra, b, rb, [](const Vec2& p) { return Vec2(p.x() + 3.0, p.y() - 2.0); },
                         [](int s) { return s; });
}

TEST(KernelMatcher, RotatedPlanRotatesPosterior) {
  // A quarter turn maps cells onto cells and the rasters are symmetric, so the posterior turns
  // with the plan: (x, y, yaw) -> (-y + 20, x + 5, yaw + 90 deg).
  const FloorPlan plan = test::asymmetric_floor();
  const FloorPlan rotated = test::transformed(plan, 0.5 * kPi, 20.0, 5.0);
  const KernelMatcher a(plan), b(rotated);
  const Observation2D obs = PerfectObserver(plan).observe({3.23, 1.61, 0.31});
  const MatchResult ra = a.match(obs), rb = b.match(obs);
  ASSERT_EQ(ra.posterior.num_slices(), rb.posterior.num_slices());
  auto slice_map = [&](int s) {
    for (int t = 0; t < rb.posterior.num_slices(); ++t) {
      if (angle_distance_rad(rb.posterior.yaw_rad[static_cast<std::size_t>(t)],
                             ra.posterior.yaw_rad[static_cast<std::size_t>(s)] + 0.5 * kPi) < 1e-9) {
        return t;
      }
    }
    ADD_FAILURE() << "no rotated slice for yaw " << ra.posterior.yaw_rad[static_cast<std::size_t>(s)];
    return 0;
  };
  expect_moved_posterior(a, ra, b, rb, [](const Vec2& p) { return Vec2(-p.y() + 20.0, p.x() + 5.0); }, slice_map);
}

// A scan that sees through an open door: the map draws every door closed (it cannot know which
// stand open), but doorways do not collide with the certainly-empty space, so the true pose
// survives. With one raster for both parts (ces_through_doorways false) the CES through the
// doorway hits the drawn door and zeroes the true pose.
TEST(KernelMatcher, OpenDoorDoesNotEraseTheTruePose) {
  const FloorPlan plan = test::asymmetric_floor();
  PerfectObservationParams see_through;
  see_through.blocking.open_doors_block = false;
  const Pose2 truth{3.6, 2.1, 0.2};  // in front of door d1 (x = 5, y = 2), looking through it
  const Observation2D obs = PerfectObserver(plan, see_through).observe(truth);
  const KernelMatcher m(plan);
  ASSERT_NE(cv::countNonZero(m.ces_raster() != m.plan_raster()), 0);
  const PoseHypothesis best = m.match(obs).posterior.argmax();
  EXPECT_LE(std::hypot(best.x_m - truth.x_m, best.y_m - truth.y_m), 0.15);
  EXPECT_LE(angle_distance_rad(best.yaw_rad, truth.yaw_rad), 0.02);
  KernelMatcherParams one_raster;
  one_raster.ces_through_doorways = false;
  const KernelMatcher old(plan, one_raster);
  const MatchResult r = old.match_yaws(obs, {truth.yaw_rad});
  int row = 0, col = 0;
  ASSERT_TRUE(old.grid().world_to_cell(truth.position_m(), row, col));
  EXPECT_EQ(r.posterior.scores[0].at<float>(row, col), 0.0f);
}

// The centre-line raster is 1 px wide even where the wall axis runs on a pixel boundary (the grid
// origin is a multiple of the resolution, so an axis at y = 0 is one): the closed line rule drew
// 2 px there, doubling every wall of a generated plan.
TEST(KernelMatcher, CentrelineRasterIsOnePixelWide) {
  FloorPlan plan;
  plan.walls = {test::wall("a", 0, 0, 6, 0), test::wall("b", 6, 0, 6, 4), test::wall("c", 6, 4, 0, 4),
                test::wall("d", 0, 4, 0, 0)};
  KernelMatcherParams p;
  p.plan_raster = PlanRasterKind::kCentreline;
  const KernelMatcher m(plan, p);
  int row = 0, col = 0;
  ASSERT_TRUE(m.grid().world_to_cell({3.0, 0.0}, row, col));
  for (double x = 1.0; x <= 5.0; x += 0.1) {
    ASSERT_TRUE(m.grid().world_to_cell({x, 2.0}, row, col));
    int lit = 0;
    for (int r = 0; r < m.plan_raster().rows; ++r) {
      const double y = m.grid().cell_center_m(r, col).y();
      if (std::abs(y) < 0.5) lit += m.plan_raster().at<std::uint8_t>(r, col) ? 1 : 0;  // the wall at y = 0
    }
    EXPECT_EQ(lit, 1) << "x " << x;
  }
}

TEST(KernelMatcher, IdenticalAcrossThreadCounts) {
  const FloorPlan plan = test::asymmetric_floor();
  const Observation2D obs = PerfectObserver(plan).observe({10.31, 3.07, 4.4});
  auto run = [&](int threads) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    const KernelMatcher m(plan);
    return m.match(obs);
  };
  const MatchResult one = run(1), two = run(2);
  ASSERT_EQ(one.posterior.scores.size(), two.posterior.scores.size());
  EXPECT_EQ(one.posterior.yaw_rad, two.posterior.yaw_rad);
  for (std::size_t s = 0; s < one.posterior.scores.size(); ++s) {
    const cv::Mat& x = one.posterior.scores[s];
    const cv::Mat& y = two.posterior.scores[s];
    ASSERT_TRUE(x.isContinuous() && y.isContinuous());
    EXPECT_EQ(std::memcmp(x.data, y.data, x.total() * x.elemSize()), 0) << "slice " << s;
  }
}

TEST(KernelMatcher, ParametersAndRegistry) {
  const FloorPlan plan = test::asymmetric_floor();
  const auto m = make_matcher("kernel", plan, {{"orientations", "dense"}, {"scales", {1.0}}, {"alpha", 5}});
  EXPECT_EQ(m->name(), "kernel");
  const auto j = m->parameters();
  EXPECT_EQ(j["orientations"], "dense");
  EXPECT_EQ(j["alpha"], 5.0);
  EXPECT_EQ(j["scales"].size(), 1u);
  EXPECT_GT(m->precompute_bytes(), 0u);
  const MatchResult r = m->match(PerfectObserver(plan).observe({3.2, 1.6, 0.0}));
  EXPECT_EQ(r.posterior.num_slices(), 36);
  EXPECT_NO_THROW(r.posterior.check());
  EXPECT_GT(r.stage_s.count("fft_inverse"), 0u);
  EXPECT_THROW(make_matcher("kernel", plan, {{"alpha_typo", 5}}), InputError);
  EXPECT_THROW(make_matcher("kernel", plan, {{"alpha", "five"}}), InputError);
  EXPECT_THROW(make_matcher("kernel", plan, {{"orientations", "sparse"}}), InputError);
  EXPECT_THROW(make_matcher("kernel", plan, {{"blur_size_px", 4}}), InputError);
  EXPECT_THROW(make_matcher("nope", plan), InputError);
  EXPECT_EQ(builtin_matcher_names(), (std::vector<std::string>{"bev", "external", "kernel", "planes", "ray"}));
}

}  // namespace
}  // namespace floorcast
