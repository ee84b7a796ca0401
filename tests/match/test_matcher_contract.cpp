// The matcher contract: every built-in matcher (builtin_matcher_names()) runs over the same known-answer
// cases, so a new matcher is tested by registering it. Matcher-specific behaviour (kernel
// ingredients, ray distance volumes) is tested in the matcher's own test file.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>

#include "floorcast/core/math.hpp"
#include "floorcast/core/params.hpp"
#include "floorcast/match/matcher.hpp"
#include "floorcast/sim/perfect_observation.hpp"
#include "match_test_plans.hpp"

namespace floorcast {
namespace {

class MatcherContract : public ::testing::TestWithParam<std::string> {
 protected:
  static const FloorPlan& plan() {
    static const FloorPlan p = test::asymmetric_floor();
    return p;
  }
  /// Perfect observations with every input a matcher may take: segments, rays and BEVs.
  static Observation2D observe(const FloorPlan& p, const Pose2& pose) {
    PerfectObservationParams params;
    params.bev_columns = 72;
    return PerfectObserver(p, params).observe(pose);
  }
};

bool same_bytes(const Posterior& a, const Posterior& b) {
  if (a.scores.size() != b.scores.size() || a.yaw_rad != b.yaw_rad || !(a.grid == b.grid)) return false;
  for (std::size_t s = 0; s < a.scores.size(); ++s) {
    const cv::Mat x = a.scores[s].clone(), y = b.scores[s].clone();
    if (x.size() != y.size() || x.type() != y.type()) return false;
    if (std::memcmp(x.data, y.data, x.total() * x.elemSize()) != 0) return false;
  }
  return true;
}

// A perfect observation at a distinctive spot: the argmax is the true pose (within a cell
// diagonal and 10 deg: the ray matcher's direction bins are 10 deg wide).
TEST_P(MatcherContract, PerfectObservationFindsTheTruePose) {
  const std::unique_ptr<Matcher> m = make_matcher(GetParam(), plan());
  EXPECT_EQ(m->name(), GetParam());
  for (const Pose2& truth : {Pose2{3.23, 1.61, 0.31}, Pose2{10.31, 3.07, 4.4}}) {
    const MatchResult r = m->match(observe(plan(), truth));
    ASSERT_NO_THROW(r.posterior.check());
    const PoseHypothesis best = r.posterior.argmax();
    EXPECT_GT(best.score, 0.0);
    EXPECT_LE(std::hypot(best.x_m - truth.x_m, best.y_m - truth.y_m), 0.15) << GetParam();
    EXPECT_LE(angle_distance_rad(best.yaw_rad, truth.yaw_rad), deg_to_rad(10.0)) << GetParam();
    EXPECT_GE(r.match_s, 0.0);
  }
  EXPECT_GT(m->precompute_bytes(), 0u);
  EXPECT_GE(m->precompute_s(), 0.0);
}

// The plan moved by a whole number of cells: the estimate moves with it, the yaw stays.
TEST_P(MatcherContract, MovedPlanMovesTheEstimate) {
  const FloorPlan moved = test::transformed(plan(), 0.0, 3.0, -2.0);
  const Pose2 truth{3.23, 1.61, 0.31};
  const Observation2D obs = observe(plan(), truth);
  const PoseHypothesis a = make_matcher(GetParam(), plan())->match(obs).posterior.argmax();
  const PoseHypothesis b = make_matcher(GetParam(), moved)->match(obs).posterior.argmax();
  EXPECT_NEAR(b.x_m, a.x_m + 3.0, 1e-6) << GetParam();
  EXPECT_NEAR(b.y_m, a.y_m - 2.0, 1e-6) << GetParam();
  EXPECT_NEAR(angle_distance_rad(a.yaw_rad, b.yaw_rad), 0.0, 1e-9) << GetParam();
}

// Same input, same bytes: twice, and at 1 and 2 threads.
TEST_P(MatcherContract, DeterministicAtAnyThreadCount) {
  const Observation2D obs = observe(plan(), {6.72, 6.83, 5.9});
  auto run = [&](int threads) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    return make_matcher(GetParam(), plan())->match(obs).posterior;
  };
  const Posterior one = run(1), two = run(2), again = run(2);
  EXPECT_TRUE(same_bytes(one, two)) << GetParam();
  EXPECT_TRUE(same_bytes(two, again)) << GetParam();
}

// Parameters: the resolved set round-trips, and bad keys, types and values are refused with the
// key named (ParameterError), before any plan is involved.
TEST_P(MatcherContract, ParametersRoundTripAndBadOnesAreRefused) {
  const std::shared_ptr<const MatcherConfig> config = make_matcher_config(GetParam());
  const nlohmann::ordered_json params = config->parameters();
  EXPECT_TRUE(params.contains("max_range_m"));
  EXPECT_TRUE(params.contains("doors_closed"));
  EXPECT_EQ(make_matcher_config(GetParam(), params)->parameters(), params);
  EXPECT_EQ(make_matcher(GetParam(), plan())->parameters(), params);
  try {
    (void)make_matcher_config(GetParam(), {{"no_such_parameter", 1}});
    FAIL() << "unknown key accepted by " << GetParam();
  } catch (const ParameterError& e) {
    EXPECT_EQ(e.key(), "no_such_parameter");
  }
  try {
    (void)make_matcher_config(GetParam(), {{"max_range_m", "far"}});
    FAIL() << "string range accepted by " << GetParam();
  } catch (const ParameterError& e) {
    EXPECT_EQ(e.key(), "max_range_m");
  }
  try {
    (void)make_matcher_config(GetParam(), {{"max_range_m", -3.0}});
    FAIL() << "negative range accepted by " << GetParam();
  } catch (const ParameterError& e) {
    EXPECT_EQ(e.key(), "max_range_m");
  }
  EXPECT_THROW((void)make_matcher_config(GetParam(), nlohmann::json::array()), InputError);
}

// The shared range and blocking flags reach the matcher unless it overrides them.
TEST_P(MatcherContract, SharedQuantitiesApplyUnlessOverridden) {
  SharedParams shared;
  shared.range_m = 7.5;
  shared.blocking.open_doors_block = false;
  const auto p = make_matcher_config(GetParam(), nlohmann::json::object(), shared)->parameters();
  EXPECT_EQ(p["max_range_m"], 7.5);
  EXPECT_EQ(p["doors_closed"], false);
  const auto q = make_matcher_config(GetParam(), {{"max_range_m", 9.0}}, shared)->parameters();
  EXPECT_EQ(q["max_range_m"], 9.0);
  const BlockingOptions b = make_matcher_config(GetParam(), nlohmann::json::object(), shared)->build(plan())->blocking();
  EXPECT_FALSE(b.open_doors_block);
}

// An observation without walls is not an error: the posterior is valid (all zero for the kernel
// matcher, whose score needs observed walls), so callers can report "no pose" instead of
// inventing one.
TEST_P(MatcherContract, EmptyObservationGivesAnEmptyPosterior) {
  Observation2D empty;
  empty.max_range_m = 10.0;
  empty.ray_ranges_m.assign(36, 10.0);
  const std::unique_ptr<Matcher> m = make_matcher(GetParam(), plan(), {{"max_range_m", 10.0}});
  MatchResult r;
  ASSERT_NO_THROW(r = m->match(empty)) << GetParam();
  ASSERT_NO_THROW(r.posterior.check());
  EXPECT_GT(r.posterior.num_slices(), 0);
}

// The caller says what it needs and gets exactly that: the modes only (no slices kept), the
// max-over-yaw map (equal to the full posterior's), or the full posterior; the same estimate and
// top-K from each on a distinctive spot.
TEST_P(MatcherContract, OutputsAsRequested) {
  const std::unique_ptr<Matcher> m = make_matcher(GetParam(), plan());
  const Observation2D obs = observe(plan(), {3.23, 1.61, 0.31});
  MatchRequest full;
  full.top_k = 3;
  const MatchResult post = m->match(obs, full);
  ASSERT_GT(post.posterior.num_slices(), 0);
  EXPECT_TRUE(post.grid == post.posterior.grid);
  ASSERT_EQ(post.modes.size(), 3u) << GetParam();
  const std::vector<PoseHypothesis> expect = post.posterior.top_k(3);
  for (std::size_t i = 0; i < expect.size(); ++i) {
    EXPECT_EQ(post.modes[i].slice, expect[i].slice);
    EXPECT_EQ(post.modes[i].row, expect[i].row);
    EXPECT_EQ(post.modes[i].col, expect[i].col);
  }
  MatchRequest yaw_map = full;
  yaw_map.output = MatchOutput::kMaxOverYaw;
  const MatchResult my = m->match(obs, yaw_map);
  EXPECT_TRUE(my.posterior.scores.empty()) << GetParam();
  ASSERT_EQ(my.max_over_yaw.type(), CV_32F);
  EXPECT_EQ(cv::norm(my.max_over_yaw, post.posterior.max_over_yaw(), cv::NORM_INF), 0.0) << GetParam();
  const MatchResult modes = m->match(obs, MatchRequest::modes(3));
  EXPECT_TRUE(modes.posterior.scores.empty()) << GetParam();
  EXPECT_TRUE(modes.max_over_yaw.empty()) << GetParam();
  EXPECT_TRUE(modes.grid == post.grid);
  for (const MatchResult* r : {&my, &modes}) {
    ASSERT_EQ(r->modes.size(), post.modes.size()) << GetParam();
    for (std::size_t i = 0; i < post.modes.size(); ++i) {
      EXPECT_EQ(r->modes[i].slice, post.modes[i].slice) << GetParam() << " mode " << i;
      EXPECT_EQ(r->modes[i].row, post.modes[i].row) << GetParam() << " mode " << i;
      EXPECT_EQ(r->modes[i].col, post.modes[i].col) << GetParam() << " mode " << i;
      EXPECT_NEAR(r->modes[i].score, post.modes[i].score, 2e-4) << GetParam() << " mode " << i;
    }
  }
}

// Point queries (Matcher::query) against the full posterior, the slow obvious version: same grid,
// slices and maximum, and every cell of the estimate's slice and of two others, plus cells of every
// slice, scored as the posterior holds them: bit for bit, except the kernel matcher's direct sums
// against its FFT posterior (round-off, and a value within it of zero_below clipped on one side
// only: 2e-4, the modes' tolerance above). The query scores cells itself (no hidden posterior)
// where the matcher has point queries.
TEST_P(MatcherContract, PointQueriesEqualThePosterior) {
  const std::unique_ptr<Matcher> m = make_matcher(GetParam(), plan());
  const double tolerance = GetParam() == "kernel" ? 2e-4 : 0.0;
  for (const Pose2& truth : {Pose2{3.23, 1.61, 0.31}, Pose2{6.72, 6.83, 5.9}}) {
    const Observation2D obs = observe(plan(), truth);
    const Posterior post = m->match(obs).posterior;
    const PosteriorQuery q = m->query(obs);
    ASSERT_TRUE(q.grid() == post.grid) << GetParam();
    ASSERT_EQ(q.yaw_rad(), post.yaw_rad) << GetParam();
    double post_max = 0.0;
    for (const cv::Mat& s : post.scores) {
      double mx = 0.0;
      cv::minMaxLoc(s, nullptr, &mx);
      post_max = std::max(post_max, mx);
    }
    EXPECT_NEAR(q.max_score(), post_max, tolerance) << GetParam();
    const PoseHypothesis best = post.argmax();
    std::vector<PosteriorCell> cells;
    for (int slice : {best.slice, (best.slice + 1) % post.num_slices(), post.num_slices() / 2})
      for (int r = 0; r < post.grid.height_px; ++r)
        for (int c = 0; c < post.grid.width_px; ++c) cells.push_back({slice, r, c});
    for (int slice = 0; slice < post.num_slices(); ++slice)
      for (int k = 0; k < 50; ++k) cells.push_back({slice, (7 * k + slice) % post.grid.height_px, (13 * k + 3 * slice) % post.grid.width_px});
    std::vector<float> got;
    q.scores(cells, got);
    ASSERT_EQ(got.size(), cells.size());
    double worst = 0.0;
    int nonzero = 0;
    for (std::size_t i = 0; i < cells.size(); ++i) {
      const float want = post.scores[static_cast<std::size_t>(cells[i].slice)].at<float>(cells[i].row, cells[i].col);
      worst = std::max(worst, std::abs(static_cast<double>(got[i]) - want));
      nonzero += want > 0.0f;
    }
    EXPECT_LE(worst, tolerance) << GetParam();
    EXPECT_GT(nonzero, 0) << GetParam();  // the comparison saw scores, not only zeros
    if (GetParam() == "kernel" || GetParam() == "ray") {
      EXPECT_EQ(q.cells_scored(), static_cast<std::int64_t>(cells.size())) << GetParam();
      EXPECT_FALSE(q.has_full()) << GetParam();
    }
    // The full posterior on request is match()'s.
    EXPECT_TRUE(same_bytes(q.full(), post)) << GetParam();
  }
}

// Every built-in matcher except "external": that one is an adapter whose answers are its program's
// (its protocol, checks and errors are tested in test_external.cpp, the example programs in the
// scenario and Python tests).
std::vector<std::string> contract_matchers() {
  std::vector<std::string> names;
  for (const std::string& n : builtin_matcher_names())
    if (n != "external") names.push_back(n);
  return names;
}

INSTANTIATE_TEST_SUITE_P(Registered, MatcherContract, ::testing::ValuesIn(contract_matchers()),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

}  // namespace
}  // namespace floorcast
