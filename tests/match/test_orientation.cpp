#include <gtest/gtest.h>

#include <cmath>

#include "floorcast/floorplans/io.hpp"
#include "floorcast/match/kernel_matcher.hpp"
#include "floorcast/match/matcher.hpp"
#include "floorcast/match/orientation.hpp"
#include "floorcast/match/plan_raster.hpp"
#include "floorcast/sim/perfect_observation.hpp"
#include "floorcast/core/math.hpp"
#include "match_test_plans.hpp"

namespace floorcast {
namespace {


double nearest_candidate_error(const std::vector<double>& cands, double yaw) {
  double best = 1e9;
  for (double c : cands) best = std::min(best, angle_distance_rad(c, yaw));
  return best;
}

TEST(Orientation, HistogramAndCorrelation) {
  const std::vector<Segment2> segs = {{{0, 0}, {2, 0}}, {{0, 0}, {0, 3}}, {{1, 1}, {0, 1}}, {{0, 0}, {0, 0}}};
  const auto h = direction_histogram(segs, 360);
  ASSERT_EQ(h.size(), 360u);
  EXPECT_DOUBLE_EQ(h[0], 3.0);    // 0 deg and 180 deg fold together
  EXPECT_DOUBLE_EQ(h[180], 3.0);  // 90 deg
  std::vector<double> shifted(360, 0.0);
  shifted[20] = 3.0;    // 10 deg
  shifted[200] = 3.0;   // 100 deg
  const auto c = circular_correlation(shifted, h);
  const auto peaks = circular_peaks(c, 10, 2);
  ASSERT_EQ(peaks.size(), 2u);
  EXPECT_TRUE((peaks[0] == 20 && peaks[1] == 200) || (peaks[0] == 200 && peaks[1] == 20));
  // NMS: peaks closer than the radius collapse.
  std::vector<double> sig(100, 0.0);
  sig[10] = 5;
  sig[14] = 4;
  sig[99] = 3;  // circularly 11 bins from 10
  sig[50] = 1;
  EXPECT_EQ(circular_peaks(sig, 10, 5), (std::vector<int>{10, 99, 50}));
  sig[0] = 2;  // within 10 bins of 10 and of 99
  EXPECT_EQ(circular_peaks(sig, 10, 5), (std::vector<int>{10, 99, 50}));
  EXPECT_EQ(circular_peaks(sig, 3, 5), (std::vector<int>{10, 14, 99, 50}));
}

TEST(Orientation, CandidatesContainTrueYawForRotatedInputs) {
  const FloorPlan plan = test::asymmetric_floor();
  const PerfectObserver observer(plan);
  OrientationParams pp;  // palms+
  OrientationParams palms;
  palms.mode = OrientationMode::kPalms;
  OrientationParams dense;
  dense.mode = OrientationMode::kDense;
  const auto plan_segs = outline_segments(observer.outline());
  // The plan's walls are axis-aligned except one at 45 deg; the observation at (3.2, 1.6) sees
  // axis-aligned walls only, at (2.2, 5.4) the diagonal too.
  for (const Vec2& pos : {Vec2(3.2, 1.6), Vec2(2.2, 5.4), Vec2(10.3, 3.1), Vec2(6.3, 6.8)}) {
    for (double yaw_deg : {0.0, 17.3, 90.0, 133.7, 200.2, 301.9}) {
      const double yaw = yaw_deg * kPi / 180.0;
      const Observation2D obs = observer.observe({pos.x(), pos.y(), yaw});
      ASSERT_FALSE(obs.segments_m.empty());
      const auto c_pp = orientation_candidates(pp, plan_segs, obs.segments_m);
      // At most O = 10: O/2 peaks with a positive correlation, plus their complements.
      EXPECT_LE(c_pp.size(), 10u);
      EXPECT_GE(c_pp.size(), 2u);
      EXPECT_EQ(c_pp.size() % 2, 0u);
      // One histogram bin is 0.5 deg.
      EXPECT_LE(nearest_candidate_error(c_pp, yaw), 0.5 * kPi / 180.0 + 1e-9) << pos.transpose() << " " << yaw_deg;
      const auto c_palms = orientation_candidates(palms, plan_segs, obs.segments_m);
      ASSERT_EQ(c_palms.size(), 4u);
      EXPECT_LE(nearest_candidate_error(c_palms, yaw), 0.5 * kPi / 180.0 + 1e-9) << pos.transpose() << " " << yaw_deg;
      for (std::size_t i = 1; i < 4; ++i) EXPECT_NEAR(angle_distance_rad(c_palms[i], c_palms[i - 1]), 0.5 * kPi, 1e-9);
      const auto c_dense = orientation_candidates(dense, plan_segs, obs.segments_m);
      ASSERT_EQ(c_dense.size(), 36u);
      EXPECT_LE(nearest_candidate_error(c_dense, yaw), 5.0 * kPi / 180.0 + 1e-9);
    }
  }
}

TEST(Orientation, RotatedPlanRotatesCandidates) {
  // Rotating the plan by 30 deg (a non-Manhattan frame) shifts every candidate by 30 deg.
  const FloorPlan plan = test::asymmetric_floor();
  const FloorPlan rotated = test::transformed(plan, 30.0 * kPi / 180.0, 4.0, -1.0);
  const PerfectObserver obs_a(plan), obs_b(rotated);
  const Observation2D obs = obs_a.observe({3.2, 1.6, 0.4});
  OrientationParams pp;
  const auto a = orientation_candidates(pp, outline_segments(obs_a.outline()), obs.segments_m);
  const auto b = orientation_candidates(pp, outline_segments(obs_b.outline()), obs.segments_m);
  ASSERT_EQ(a.size(), b.size());
  for (double ca : a) EXPECT_LE(nearest_candidate_error(b, ca + 30.0 * kPi / 180.0), 0.5 * kPi / 180.0 + 1e-9);
}

TEST(Orientation, RefinementRecoversExactYaw) {
  const FloorPlan plan = test::asymmetric_floor();
  const PerfectObserver observer(plan);
  const auto cache = make_plan_orientation_cache(OrientationParams{}, outline_segments(observer.outline()));
  for (double yaw_deg : {17.3, 133.71, 301.95}) {
    const double yaw = yaw_deg * kPi / 180.0;
    const Observation2D obs = observer.observe({3.2, 1.6, yaw});
    const double refined = refine_orientation(cache.directions, obs.segments_m, yaw + 0.37 * kPi / 180.0,
                                              kPi / 180.0, 0.5 * kPi / 180.0);
    EXPECT_LE(angle_distance_rad(refined, yaw), 0.006 * kPi / 180.0) << yaw_deg;
  }
  OrientationParams refined;
  refined.refine = true;
  const Observation2D obs = observer.observe({2.2, 5.4, 0.7});
  for (double c : orientation_candidates(refined, cache, obs.segments_m)) {
    // Every candidate sits on an exact alignment (within the 0.01 deg grid) of some wall family.
    double d = 1e9;
    for (double k = 0; k < 4; ++k) d = std::min(d, angle_distance_rad(c, 0.7 + k * 0.5 * kPi));
    if (d < 1.0 * kPi / 180.0) {
      EXPECT_LE(d, 0.006 * kPi / 180.0);
    }
  }
}

// A plan with more main wall directions than PALMS+'s O / 2 alignments: the kernel matcher says so
// (Matcher::notes, written to the run log), and tests them all with enough candidates. The
// shipped calibrated angled building has 8 main directions (0, 15, 30, 45, 90, 120, 135, 158 deg:
// its wings and their corners), the calibrated office 2.
TEST(Orientation, PlansWithMoreMainDirectionsThanCandidatesAreNoted) {
  const std::string dir = std::string(FLOORCAST_SOURCE_DIR) + "/floorplans/buildings/";
  const FloorPlan angled = load_floor_plan(dir + "angled_calibrated.json");
  const FloorPlan office = load_floor_plan(dir + "office_calibrated.json");
  // The main directions of a histogram: peaks at least 10% of the largest, 5 deg apart.
  std::vector<double> h(360, 0.0);
  h[0] = 10.0, h[4] = 9.0, h[60] = 5.0, h[180] = 1.0, h[300] = 0.9;
  const std::vector<double> main = main_wall_directions_deg(h, 10);
  ASSERT_EQ(main.size(), 3u);  // bin 4 is within 10 bins of bin 0; bin 300 under 10% of 10
  EXPECT_DOUBLE_EQ(main[0], 0.25);
  EXPECT_DOUBLE_EQ(main[1], 30.25);
  EXPECT_DOUBLE_EQ(main[2], 90.25);

  const std::vector<std::string> angled_notes = make_matcher("kernel", angled)->notes();
  ASSERT_EQ(angled_notes.size(), 1u);
  EXPECT_NE(angled_notes[0].find("main directions"), std::string::npos) << angled_notes[0];
  EXPECT_NE(angled_notes[0].find("num_orientations 10 tests 5"), std::string::npos) << angled_notes[0];
  EXPECT_TRUE(make_matcher("kernel", office)->notes().empty());
  // Enough candidates, every heading, or PALMS' Manhattan assumption.
  EXPECT_TRUE(make_matcher("kernel", angled, {{"num_orientations", 36}})->notes().empty());
  EXPECT_TRUE(make_matcher("kernel", angled, {{"orientations", "dense"}})->notes().empty());
  EXPECT_EQ(make_matcher("kernel", angled, {{"orientations", "palms"}})->notes().size(), 1u);
  EXPECT_TRUE(make_matcher("kernel", office, {{"orientations", "palms"}})->notes().empty());
  // The abstention wrapper passes them on; matchers without orientation candidates have none.
  EXPECT_EQ(make_matcher("kernel", angled, {{"min_score", 0.1}})->notes().size(), 1u);
  EXPECT_TRUE(make_matcher("ray", angled)->notes().empty());
}

TEST(Orientation, ModeNames) {
  EXPECT_EQ(orientation_mode_name(OrientationMode::kPalms), "palms");
  EXPECT_EQ(orientation_mode_name(OrientationMode::kPalmsPlus), "palms+");
  EXPECT_EQ(orientation_mode_name(OrientationMode::kDense), "dense");
  KernelMatcherParams kp;
  kp.apply_overrides({{"orientations", "palms"}});
  EXPECT_EQ(kp.orientation.mode, OrientationMode::kPalms);
  EXPECT_THROW(kp.apply_overrides({{"orientations", "sparse"}}), InputError);
  // No segments: dense fallback.
  OrientationParams pp;
  EXPECT_EQ(orientation_candidates(pp, {{{0, 0}, {1, 0}}}, {}).size(), 36u);
}

}  // namespace
}  // namespace floorcast
