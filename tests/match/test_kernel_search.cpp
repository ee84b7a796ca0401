// The kernel matcher's exact branch-and-bound search (localization/match/src/kernel_search.hpp): the same
// estimate and top-K modes as the exhaustive FFT posterior on seeded observations of every
// shipped building, admissible bounds, exact cell values, the no-pose state, determinism.
// Larger comparisons (hundreds of observations per shipped building): `floorcast bench match
// --equivalence N`, results/bench_match.md.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <string>

#include "floorcast/bench/match_bench.hpp"
#include "floorcast/bench/modes_equivalence.hpp"
#include "floorcast/core/params.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/floorplans/generate.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/match/kernel_matcher.hpp"
#include "floorcast/sim/perfect_observation.hpp"
#include "kernel_search.hpp"
#include "match_test_plans.hpp"

namespace floorcast {
namespace {

FloorPlan shipped(const std::string& name) {
  return load_floor_plan(std::string(FLOORCAST_SOURCE_DIR) + "/floorplans/buildings/" + name + ".json");
}

void expect_equivalent(const std::string& what, const FloorPlan& plan, const KernelMatcherParams& params,
                       int observations, std::uint64_t seed, int top_k = 5) {
  const KernelMatcher m(plan, params);
  ModesEquivalenceParams p;
  p.observations = observations;
  p.seed = seed;
  p.top_k = top_k;
  p.max_range_m = params.max_range_m;
  const ModesEquivalenceResult r = compare_modes_with_posterior(plan, m, p);
  EXPECT_EQ(r.observations, observations) << what;
  EXPECT_EQ(r.mismatches, 0) << what << ": " << (r.failures.empty() ? "" : r.failures.front());
  // Exact values: the search's scores are the direct sums, to float round-off.
  EXPECT_LE(r.max_search_error, 1e-6) << what;
  // Every estimate is the posterior's own pick, or tied with it (mirror-symmetric places), or
  // ordered differently by the FFT's round-off (a gap of at most a few 1e-5).
  EXPECT_EQ(r.estimates_identical + r.estimates_tied + r.estimates_fft_order, observations) << what;
  EXPECT_LE(r.max_fft_order_gap, 3e-4) << what;
  ::testing::Test::RecordProperty(what, to_json(r).dump());
}

// Hundreds of seeded observations on small plans (uniform poses over the valid area, any yaw:
// distinctive spots, symmetric rooms, corridors, cluttered corners, no-pose cases).
TEST(KernelSearch, ModesEqualPosteriorOnSmallPlans) {
  const KernelMatcherParams defaults;
  expect_equivalent("asymmetric", test::asymmetric_floor(), defaults, 60, 1);
  expect_equivalent("asymmetric rotated 30 deg", test::transformed(test::asymmetric_floor(), 0.52, 3.0, -1.0),
                    defaults, 30, 2);
  expect_equivalent("two_rooms", shipped("two_rooms"), defaults, 40, 3);
  expect_equivalent("apartment", shipped("apartment"), defaults, 60, 4);
  for (std::uint64_t seed : {2, 3, 4}) {
    expect_equivalent("generated apartment " + std::to_string(seed),
                      generate_building(Archetype::kApartment, seed).plan, defaults, 30, 10 + seed);
  }
}

// Every parameter the search handles explicitly: a CES weight below 1 (hit counts matter), no
// round-off guard, one scale, dense orientations, no blur, the centre-line raster, one raster for
// both parts, open doors, a short range, a single mode.
TEST(KernelSearch, ModesEqualPosteriorForParameterVariants) {
  const FloorPlan plan = shipped("apartment");
  auto with = [](auto change) {
    KernelMatcherParams p;
    change(p);
    return p;
  };
  expect_equivalent("alpha 0.3", plan, with([](KernelMatcherParams& p) { p.alpha = 0.3; }), 15, 21);
  expect_equivalent("zero_below 0", plan, with([](KernelMatcherParams& p) { p.zero_below = 0.0; }), 10, 22);
  expect_equivalent("one scale", plan, with([](KernelMatcherParams& p) { p.scales = {1.0}; }), 10, 23);
  expect_equivalent("dense orientations", plan,
                    with([](KernelMatcherParams& p) { p.orientation.mode = OrientationMode::kDense; }), 6, 24);
  expect_equivalent("no blur", plan, with([](KernelMatcherParams& p) { p.blur_size_px = 0; }), 10, 25);
  expect_equivalent("centreline", plan,
                    with([](KernelMatcherParams& p) { p.plan_raster = PlanRasterKind::kCentreline; }), 10, 26);
  expect_equivalent("one raster", plan, with([](KernelMatcherParams& p) { p.ces_through_doorways = false; }), 10, 27);
  expect_equivalent("doors open", plan, with([](KernelMatcherParams& p) {
                      p.blocking.open_doors_block = false;
                      p.blocking.closed_doors_block = false;
                    }),
                    10, 28);
  expect_equivalent("range 6 m", plan, with([](KernelMatcherParams& p) {
                      p.max_range_m = 6.0;
                      p.ces_window_m = 6.0;
                    }),
                    10, 29);
  expect_equivalent("levels 3", plan, with([](KernelMatcherParams& p) { p.search_levels = 3; }), 10, 30);
  expect_equivalent("top-1", plan, KernelMatcherParams{}, 10, 31, 1);
  expect_equivalent("top-20", plan, KernelMatcherParams{}, 10, 32, 20);
}

// The large shipped buildings, a few observations each (their FFT posteriors take ~0.1-0.3 s).
TEST(KernelSearch, ModesEqualPosteriorOnLargeShippedBuildings) {
  for (const char* b : {"office", "angled", "campus"}) expect_equivalent(b, shipped(b), KernelMatcherParams{}, 6, 5);
}

// Every bound is admissible: no cell of a node scores above the node's bound, at every level, for
// nodes sampled over the whole grid (white box: the private search header).
TEST(KernelSearch, BoundsAreAdmissible) {
  const FloorPlan plan = shipped("apartment");
  const KernelMatcher m(plan);
  const detail::KernelSearchMaps& maps = *m.search_maps();
  const PerfectObserver observer(plan);
  const double alpha = correlation_alpha(m.params().alpha);
  int checked = 0, tight = 0;
  for (const Pose2& pose : sample_valid_poses(m, 4, 41)) {
    const Observation2D obs = observer.observe(pose);
    for (double yaw : {pose.yaw_rad, pose.yaw_rad + 0.07}) {
      for (double scale : {0.9, 1.1}) {
        const detail::SearchKernel k =
            detail::build_search_kernel(m.params(), obs.segments_m, yaw, scale, m.distance_weight(), maps, true);
        for (int h = 0; h <= maps.levels(); ++h) {
          const int side = 1 << h;
          for (int r0 = 0; r0 < maps.H; r0 += side * 3) {
            for (int c0 = 0; c0 < maps.W; c0 += side * 3) {
              const double floor_score = m.params().zero_below;
              const double ub = detail::node_upper_bound(maps, k, alpha, floor_score, h, r0, c0);
              double best = -std::numeric_limits<double>::infinity();
              for (int r = r0; r < std::min(maps.H, r0 + side); ++r)
                for (int c = c0; c < std::min(maps.W, c0 + side); ++c)
                  if (m.valid_mask().at<std::uint8_t>(r, c)) best = std::max(best, detail::exact_cell_score(maps, k, alpha, r, c));
              if (std::isinf(ub)) {
                // Dropped: no cell of the node can be a mode.
                ASSERT_TRUE(best < floor_score || best <= 0.0) << "level " << h << " node (" << r0 << ", " << c0 << ")";
              } else {
                ASSERT_GE(ub, best) << "level " << h << " node (" << r0 << ", " << c0 << ")";
                tight += best > floor_score && ub - best < 0.05;
              }
              ++checked;
            }
          }
        }
        // Exact values equal the direct correlation sum.
        for (int i = 0; i < 20; ++i) {
          const int r = (37 * i + 11) % maps.H, c = (53 * i + 7) % maps.W;
          EXPECT_NEAR(detail::exact_cell_score(maps, k, alpha, r, c), m.cell_score(obs, yaw, scale, r, c), 1e-6);
        }
      }
    }
  }
  EXPECT_GT(checked, 1000);
  EXPECT_GT(tight, 20);  // the bounds are not vacuous
}

// No observed wall: no pose, from the search and from the posterior alike.
TEST(KernelSearch, NoPose) {
  const KernelMatcher m(test::asymmetric_floor());
  Observation2D empty;
  empty.max_range_m = 10.0;
  EXPECT_FALSE(m.match(empty, MatchRequest::modes(5)).has_pose());
  EXPECT_FALSE(m.match(empty).has_pose());
  EXPECT_THROW((void)m.match(empty, MatchRequest::modes(1)).estimate(), std::logic_error);
}

// Same modes at 1 and 2 threads (the kernels are built in parallel; the search is sequential).
TEST(KernelSearch, DeterministicAtAnyThreadCount) {
  const FloorPlan plan = shipped("apartment");
  const KernelMatcher m(plan);
  const Observation2D obs = PerfectObserver(plan).observe(sample_valid_poses(m, 1, 51).front());
  auto run = [&](int threads) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    return m.match(obs, MatchRequest::modes(8)).modes;
  };
  const std::vector<PoseHypothesis> a = run(1), b = run(2);
  ASSERT_EQ(a.size(), b.size());
  ASSERT_FALSE(a.empty());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].slice, b[i].slice);
    EXPECT_EQ(a[i].row, b[i].row);
    EXPECT_EQ(a[i].col, b[i].col);
    EXPECT_EQ(a[i].score, b[i].score);
  }
}

// modes_search = posterior answers kModes requests from the FFT posterior (no search maps).
TEST(KernelSearch, PosteriorModeSearchOption) {
  KernelMatcherParams p;
  p.modes_search = ModesSearch::kPosterior;
  const KernelMatcher m(test::asymmetric_floor(), p);
  EXPECT_EQ(m.search_maps(), nullptr);
  EXPECT_EQ(m.search_bytes(), 0u);
  const Observation2D obs = PerfectObserver(test::asymmetric_floor()).observe({3.23, 1.61, 0.31});
  const MatchResult r = m.match(obs, MatchRequest::modes(3));
  ASSERT_TRUE(r.has_pose());
  EXPECT_TRUE(r.posterior.scores.empty());
  EXPECT_EQ(r.counters.count("bb_bounds"), 0u);
  EXPECT_LE(std::hypot(r.estimate().x_m - 3.23, r.estimate().y_m - 1.61), 0.15);
  EXPECT_EQ(make_matcher_config("kernel", {{"modes_search", "posterior"}})->parameters()["modes_search"], "posterior");
  EXPECT_THROW((void)make_matcher_config("kernel", {{"modes_search", "fast"}}), ParameterError);
}

// `bench match`'s record (what `bench scale` reads back from its children): every measured
// field survives to_json -> read_match_bench, the optional blocks are absent when not measured,
// and a misspelt key is refused naming it.
TEST(MatchBenchRecord, RoundTripsAndRefusesUnknownKeys) {
  MatchBenchParams p;
  p.observations = 1;
  p.ray_directions = {36};
  p.bev_fov_deg = {60.0};
  const MatchBenchResult r = bench_match(shipped("apartment"), p);
  ASSERT_TRUE(r.kernel_measured);
  ASSERT_EQ(r.ray.size(), 1u);
  ASSERT_EQ(r.bev.size(), 2u);
  ASSERT_EQ(r.bev.front().views.size(), 1u);
  EXPECT_TRUE(r.bev.front().semantics);
  EXPECT_FALSE(r.bev.back().semantics);
  EXPECT_GT(r.ray.front().cells_scored_share, 0.0);
  const nlohmann::ordered_json j = to_json(r);
  const MatchBenchResult back = read_match_bench(nlohmann::json(j), "record");
  EXPECT_EQ(to_json(back).dump(), j.dump());
  EXPECT_EQ(back.ray.front().directions, 36);
  EXPECT_EQ(back.bev.front().views.front().fov_deg, 60.0);

  MatchBenchParams q = p;
  q.kernel = false;
  q.posteriors = false;
  q.bev_fov_deg.clear();
  const MatchBenchResult lean = bench_match(shipped("apartment"), q);
  const nlohmann::ordered_json lj = to_json(lean);
  EXPECT_FALSE(lj.contains("kernel"));
  EXPECT_FALSE(lj.at("ray").at(0).contains("posterior"));
  EXPECT_EQ(to_json(read_match_bench(nlohmann::json(lj), "lean")).dump(), lj.dump());

  nlohmann::json bad = nlohmann::json(lj);
  bad["ray"][0]["precompute_sec"] = 1.0;
  try {
    (void)read_match_bench(bad, "bad.json");
    FAIL() << "a misspelt key was accepted";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("precompute_sec"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("bad.json"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace floorcast
