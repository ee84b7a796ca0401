// The kernel matcher's paper-faithful variants (KernelMatcherParams: line_rule bresenham,
// ces_erode_shape, valid_area, report_point, map_border, map_tilt, kernel_construction): defaults
// unchanged, each against a known answer. The PALMS authors' arithmetic end to end:
// test_palms_reference.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include <opencv2/imgproc.hpp>

#include "floorcast/core/hash.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/core/random.hpp"
#include "floorcast/floorplans/geometry.hpp"
#include "floorcast/match/kernel_matcher.hpp"
#include "floorcast/match/orientation.hpp"
#include "floorcast/match/plan_raster.hpp"
#include "floorcast/sim/perfect_observation.hpp"
#include "match_test_plans.hpp"

namespace floorcast {
namespace {

/// Hash of the plan raster, the valid mask and the top-3 modes (cells, slices) of 12 seeded
/// perfect observations, by both output paths.
std::uint64_t kernel_fingerprint(const KernelMatcher& m, const FloorPlan& plan) {
  std::uint64_t h = fnv1a64(std::string(reinterpret_cast<const char*>(m.plan_raster().data), m.plan_raster().total()));
  h = mix64(h ^ fnv1a64(std::string(reinterpret_cast<const char*>(m.valid_mask().data), m.valid_mask().total())));
  const PerfectObserver observer(plan, PerfectObservationParams{});
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> ux(0.5, 11.5), uy(0.5, 7.5), uyaw(0.0, 2 * kPi);
  for (int k = 0; k < 12; ++k) {
    const Observation2D obs = observer.observe({ux(rng), uy(rng), uyaw(rng)});
    for (MatchOutput out : {MatchOutput::kModes, MatchOutput::kPosterior}) {
      MatchRequest rq = MatchRequest::modes(3);
      rq.output = out;
      for (const PoseHypothesis& p : m.match(obs, rq).modes) {
        h = mix64(h ^ ((static_cast<std::uint64_t>(p.row) << 40) ^ (static_cast<std::uint64_t>(p.col) << 24) ^
                       (static_cast<std::uint64_t>(p.slice) << 16)));
      }
    }
  }
  return h;
}

// The new keys at their defaults change nothing, and the defaults are what they were before:
// the fingerprint was computed with the same code linked against main 25bdd7e's libraries, and
// re-pinned when the rasterizer stopped losing walls whose axis fell between two cells' boxes
// (floorplans/model/src/raster.cpp, test Raster.AWallBetweenTwoCellsBoxesIsPainted).
TEST(KernelVariants, DefaultsUnchanged) {
  const FloorPlan plan = test::asymmetric_floor();
  KernelMatcherParams p;
  p.apply_overrides({{"kernel_construction", "floorcast"}, {"map_border", "margin"}, {"map_tilt", false},
                     {"valid_area", "free"}, {"report_point", "centre"}, {"ces_erode_shape", "square"},
                     {"line_rule", "closed"}});
  const KernelMatcher a(plan, KernelMatcherParams{}), b(plan, p);
  EXPECT_EQ(hex64(kernel_fingerprint(a, plan)), "e6d0f6f84bdfa117");
  EXPECT_EQ(hex64(kernel_fingerprint(b, plan)), "e6d0f6f84bdfa117");
  EXPECT_EQ(a.tilt_rad(), 0.0);
  EXPECT_TRUE(a.output_grid() == a.grid());
}

// PALMS' Bresenham, hand-traced: ends floored to pixels (2, 1) and (7, 3); dx = 5 > dy = 2,
// err starts at 2.5; every minor step also marks the pixel at the old x ("enhance the wall").
TEST(KernelVariants, BresenhamKnownAnswer) {
  cv::Mat img = cv::Mat::zeros(6, 10, CV_8U);
  draw_bresenham_line(img, 2.7, 1.2, 7.1, 3.9);
  // x=2,y=1: err 2.5-2=0.5; x=3: err -1.5 -> y=2, err 3.5, mark (3,2); x=4: err 1.5; x=5: err -0.5
  // -> y=3, err 4.5, mark (5,3); x=6: err 2.5; end (7,3).
  const std::vector<cv::Point> expected = {{2, 1}, {3, 1}, {3, 2}, {4, 2}, {5, 2}, {5, 3}, {6, 3}, {7, 3}};
  cv::Mat want = cv::Mat::zeros(6, 10, CV_8U);
  for (const cv::Point& p : expected) want.at<std::uint8_t>(p) = 255;
  EXPECT_EQ(cv::countNonZero(img != want), 0);
  // In world units through draw_segment_lines (origin and resolution applied, then floored).
  cv::Mat w = cv::Mat::zeros(6, 10, CV_8U);
  draw_segment_lines(w, {{{1.27, 2.12}, {1.71, 2.39}}}, {1.0, 2.0}, 0.1, LineRule::kBresenham);
  EXPECT_EQ(cv::countNonZero(w != want), 0);
}

// PALMS' erosion element: cv2 MORPH_ELLIPSE 3 x 3 is a cross; a one-pixel line of CES survives
// nowhere, a 3 x 3 block keeps its centre either way, a plus-shaped blob keeps its centre only
// with the cross.
TEST(KernelVariants, EllipseErosionIsACrossAt3x3) {
  const cv::Mat e = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(3, 3));
  const cv::Mat cross = (cv::Mat_<std::uint8_t>(3, 3) << 0, 1, 0, 1, 1, 1, 0, 1, 0);
  EXPECT_EQ(cv::countNonZero(e != cross), 0);
  const FloorPlan plan = test::asymmetric_floor();
  KernelMatcherParams sq, el;
  el.ces_erode_shape = ErodeShape::kEllipse;
  const Observation2D obs = PerfectObserver(plan, PerfectObservationParams{}).observe({2.5, 5.5, 0.3});
  const int R = kernel_radius_px(sq);
  const LayoutKernels a = make_layout_kernels(sq, obs.segments_m, 0.3, 1.0, R);
  const LayoutKernels b = make_layout_kernels(el, obs.segments_m, 0.3, 1.0, R);
  // The cross erodes less: its CES contains the square's.
  cv::Mat a8, b8;
  a.ces.convertTo(a8, CV_8U);
  b.ces.convertTo(b8, CV_8U);
  EXPECT_EQ(cv::countNonZero(a8 & ~b8), 0);
  EXPECT_GT(cv::countNonZero(b8), cv::countNonZero(a8));
}

// PALMS' alpha shape: the interior of a closed 10 x 6 m room, its walls included, is valid,
// nothing outside; in a 30 x 30 m hall with nothing inside, the triangles across the middle
// have circumradii > 1 / 0.15 m and are dropped: only its corners stay valid (the authors' mask
// leaves the middle of large open halls out).
TEST(KernelVariants, AlphaShapeMask) {
  GridSpec g;
  g.origin_x_m = -2.0;
  g.origin_y_m = -2.0;
  g.resolution_m_per_px = 0.1;
  g.width_px = 360;
  g.height_px = 360;
  const std::vector<Segment2> room = {{{0, 0}, {10, 0}}, {{10, 0}, {10, 6}}, {{10, 6}, {0, 6}}, {{0, 6}, {0, 0}}};
  const cv::Mat m = alpha_shape_mask(room, 0.15, 1.0, g, 0.5);
  EXPECT_EQ(m.at<std::uint8_t>(50, 70), 255);       // (5, 3)
  EXPECT_EQ(m.at<std::uint8_t>(20, 20), 255);       // on the corner (0, 0): edges included
  EXPECT_EQ(m.at<std::uint8_t>(10, 70), 0);         // (5, -1): outside
  EXPECT_NEAR(cv::countNonZero(m), 101 * 61, 200);  // 10 x 6 m in 0.1 m cells, give or take its edge
  const std::vector<Segment2> hall = {{{0, 0}, {30, 0}}, {{30, 0}, {30, 30}}, {{30, 30}, {0, 30}}, {{0, 30}, {0, 0}}};
  const cv::Mat h = alpha_shape_mask(hall, 0.15, 1.0, g, 0.5);
  EXPECT_EQ(h.at<std::uint8_t>(170, 170), 0);    // (15, 15), the middle of the hall
  EXPECT_EQ(h.at<std::uint8_t>(30, 30), 255);    // (1, 1), in a corner
  EXPECT_LT(cv::countNonZero(h), 301 * 301 / 4);
  // An enclosed hole of the union is filled: a ring of rooms around a 20 m courtyard.
  std::vector<Segment2> ring = {{{0, 0}, {30, 0}}, {{30, 0}, {30, 30}}, {{30, 30}, {0, 30}}, {{0, 30}, {0, 0}},
                                {{5, 5}, {25, 5}}, {{25, 5}, {25, 25}}, {{25, 25}, {5, 25}}, {{5, 25}, {5, 5}}};
  const cv::Mat r = alpha_shape_mask(ring, 0.15, 1.0, g, 0.5);
  EXPECT_EQ(r.at<std::uint8_t>(45, 170), 255);   // (15, 2.5), in the ring of rooms
  EXPECT_EQ(r.at<std::uint8_t>(170, 170), 255);  // (15, 15), the courtyard: a hole, filled
}

// Reported at corners: the same cells, poses half a cell lower in x and y.
TEST(KernelVariants, CornerReportPoint) {
  const FloorPlan plan = test::asymmetric_floor();
  KernelMatcherParams p;
  p.report_point = ReportPoint::kCorner;
  const KernelMatcher a(plan, KernelMatcherParams{}), b(plan, p);
  const Observation2D obs = PerfectObserver(plan, PerfectObservationParams{}).observe({6.5, 2.5, 1.0});
  for (MatchOutput out : {MatchOutput::kModes, MatchOutput::kPosterior}) {
    MatchRequest rq = MatchRequest::modes(2);
    rq.output = out;
    const MatchResult ra = a.match(obs, rq), rb = b.match(obs, rq);
    ASSERT_EQ(ra.modes.size(), rb.modes.size());
    for (std::size_t i = 0; i < ra.modes.size(); ++i) {
      EXPECT_EQ(ra.modes[i].row, rb.modes[i].row);
      EXPECT_NEAR(rb.modes[i].x_m, ra.modes[i].x_m - 0.05, 1e-12);
      EXPECT_NEAR(rb.modes[i].y_m, ra.modes[i].y_m - 0.05, 1e-12);
    }
  }
}

// The posterior (FFT) equals the direct sum at sampled cells for the variants that change the
// correlation: the reflected border and the authors' kernels (embedded and shifted).
TEST(KernelVariants, PosteriorEqualsCellScore) {
  const FloorPlan plan = test::asymmetric_floor();
  const Observation2D obs = PerfectObserver(plan, PerfectObservationParams{}).observe({3.3, 1.6, 0.8});
  for (int variant = 0; variant < 3; ++variant) {
    KernelMatcherParams p;
    p.scales = {1.0};
    if (variant != 1) p.map_border = MapBorder::kReflect;
    if (variant != 0) p.kernel_construction = KernelConstruction::kPalmsCode;
    const KernelMatcher m(plan, p);
    const std::vector<double> yaws = {0.8, 2.0};
    const MatchResult r = m.match_yaws(obs, yaws);
    const GridSpec& g = m.grid();
    std::mt19937_64 rng(3);
    int checked = 0;
    for (int k = 0; k < 300; ++k) {
      const int row = static_cast<int>(rng() % static_cast<std::uint64_t>(g.height_px));
      const int col = static_cast<int>(rng() % static_cast<std::uint64_t>(g.width_px));
      if (!m.valid_mask().at<std::uint8_t>(row, col)) continue;
      for (std::size_t o = 0; o < yaws.size(); ++o) {
        const double direct = std::max(0.0, m.cell_score(obs, yaws[o], 1.0, row, col));
        const double fft = r.posterior.scores[o].at<float>(row, col);
        EXPECT_NEAR(fft, direct < 1e-4 ? fft : direct, 3e-5) << "variant " << variant << " cell " << row << "," << col;
        ++checked;
      }
    }
    EXPECT_GT(checked, 100);
    // The authors' kernels, like floorcast's, make a perfect observation's true cell the argmax.
    const MatchResult best = m.match(obs);
    ASSERT_FALSE(best.modes.empty());
    EXPECT_LT(std::hypot(best.modes[0].x_m - 3.3, best.modes[0].y_m - 1.6), 0.3) << "variant " << variant;
  }
}

// map_tilt: a plan turned by 20 deg is turned back onto the raster axes (to PALMS' 0.5 deg
// histogram bins) and an observation in it is found where it was taken; posteriors come back on
// the plan's own grid.
TEST(KernelVariants, MapTilt) {
  const FloorPlan plan = rotate_plan(test::asymmetric_floor(), 20.0 * kPi / 180.0);
  const double t = palms_landscape_rotation_rad(footprint_centrelines(blocking_footprints(plan, closed_door_map())));
  // Back onto an axis (the landscape rule may add a quarter turn), within half a bin.
  const double rem = std::fmod(std::abs(t * 180.0 / kPi + 20.0), 90.0);
  EXPECT_LT(std::min(rem, 90.0 - rem), 0.51) << t * 180.0 / kPi;
  KernelMatcherParams p;
  p.map_tilt = true;
  const KernelMatcher m(plan, p);
  EXPECT_NEAR(m.tilt_rad(), t, 1e-12);
  const double a20 = 20.0 * kPi / 180.0;
  const Pose2 truth{std::cos(a20) * 3.0 - std::sin(a20) * 5.5, std::sin(a20) * 3.0 + std::cos(a20) * 5.5, 1.2};
  const Observation2D obs = PerfectObserver(plan, PerfectObservationParams{}).observe(truth);
  const MatchResult modes = m.match(obs, MatchRequest::modes(1));
  ASSERT_FALSE(modes.modes.empty());
  EXPECT_LT(std::hypot(modes.modes[0].x_m - truth.x_m, modes.modes[0].y_m - truth.y_m), 0.2);
  EXPECT_LT(angle_distance_rad(modes.modes[0].yaw_rad, truth.yaw_rad), 2.0 * kPi / 180.0);
  const MatchResult full = m.match(obs);
  EXPECT_TRUE(full.posterior.grid == m.output_grid());
  EXPECT_TRUE(full.grid == m.output_grid());
  ASSERT_FALSE(full.modes.empty());
  EXPECT_NEAR(full.modes[0].x_m, modes.modes[0].x_m, 1e-9);
  int r = 0, c = 0;
  ASSERT_TRUE(m.output_grid().world_to_cell({truth.x_m, truth.y_m}, r, c));
  EXPECT_GT(full.posterior.max_over_yaw().at<float>(r, c), 0.0f);
}

// Every new key parses, and misspelt values are refused naming the key.
TEST(KernelVariants, Parameters) {
  KernelMatcherParams p;
  p.apply_overrides({{"kernel_construction", "palms_code"}, {"map_border", "reflect"}, {"map_tilt", true},
                     {"valid_area", "alpha_shape"}, {"alpha_shape_alpha", 0.2}, {"report_point", "corner"},
                     {"ces_erode_shape", "ellipse"}, {"line_rule", "bresenham"}});
  const nlohmann::ordered_json j = p.to_json();
  EXPECT_EQ(j["kernel_construction"], "palms_code");
  EXPECT_EQ(j["map_border"], "reflect");
  EXPECT_EQ(j["line_rule"], "bresenham");
  KernelMatcherParams q;
  q.apply_overrides(j);
  EXPECT_EQ(q.to_json(), j);
  EXPECT_THROW(q.apply_overrides({{"map_border", "mirror"}}), ParameterError);
  EXPECT_THROW(q.apply_overrides({{"report_point", 1}}), ParameterError);
}

}  // namespace
}  // namespace floorcast
