// The semantic BEV matcher (thesis, seed paper 004): its precomputed semantic ray casting against
// the brute-force segment intersection, the permeability rules, Eq. 3.3 against the obvious
// per-cell sum, exact localisation with a perfect BEV, and the locality of a plan edit.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "floorcast/core/math.hpp"
#include "floorcast/floorplans/raster.hpp"
#include "floorcast/floorplans/semantic_rays.hpp"
#include "floorcast/match/bev_matcher.hpp"
#include "floorcast/match/plan_raster.hpp"
#include "floorcast/sim/perfect_observation.hpp"
#include "match_test_plans.hpp"

namespace floorcast {
namespace {

/// The asymmetric floor with two windows (one in the outer wall, one in an inner wall).
FloorPlan windowed_floor() {
  FloorPlan p = test::asymmetric_floor();
  p.windows = {{"win_n", "n", {3.0, 8.0}, 1.2, 0.9, 2.1}, {"win_m2", "m2", {10.0, 5.0}, 1.0, 0.9, 2.1}};
  return p;
}

Observation2D perfect_observation(const FloorPlan& plan, const Pose2& pose, int columns = 72) {
  PerfectObservationParams p;
  p.bev_columns = columns;
  return PerfectObserver(plan, p).observe(pose);
}

/// The brute-force class of every bin (render_bev_column of semantic_ray_hits), with every hit
/// range moved by `nudge` metres (to tell bin-edge rounding from real differences).
std::vector<int> brute_force_bins(const SemanticPlanLines& lines, BevClasses classes, const BevDepthBins& bins,
                                  const Vec2& origin, double angle, double nudge) {
  std::vector<SemanticHit> hits = semantic_ray_hits(lines, origin, angle, bins.max_m);
  for (SemanticHit& h : hits) h.range_m += nudge;
  std::vector<int> cls(static_cast<std::size_t>(bins.count));
  render_bev_column(hits, classes, bins, cls.data());
  return cls;
}

/// The same modes (cells, slices and scores), in the same order.
void expect_same_modes(const std::vector<PoseHypothesis>& a, const std::vector<PoseHypothesis>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].slice, b[i].slice) << i;
    EXPECT_EQ(a[i].row, b[i].row) << i;
    EXPECT_EQ(a[i].col, b[i].col) << i;
    EXPECT_EQ(a[i].score, b[i].score) << i;
  }
}

class BevVolume : public ::testing::TestWithParam<BevClasses> {};

// The z-buffered volume equals the brute-force cast at 3,000 random (cell, direction) pairs, up
// to hits within 1e-6 m of a bin edge (float distances vs double).
TEST_P(BevVolume, MatchesBruteForceSegmentIntersection) {
  const FloorPlan plan = windowed_floor();
  BevMatcherParams params;
  params.semantics = GetParam() == BevClasses::kSemantic;
  const SemanticVolume v = BevMatcher::compute_volume(plan, params);
  const SemanticPlanLines lines = semantic_plan_lines(plan, GetParam(), params.blocking.cut_height_m);
  ASSERT_GT(v.num_cells(), 5000u);
  std::mt19937 rng(7);
  std::uniform_int_distribution<std::size_t> cell(0, v.num_cells() - 1);
  std::uniform_int_distribution<int> dir(0, v.num_directions - 1);
  std::vector<int> got(static_cast<std::size_t>(v.bins.count));
  int crossings = 0, stops = 0;
  for (int s = 0; s < 3000; ++s) {
    const std::size_t i = cell(rng);
    const int a = dir(rng);
    v.render(i, a, got.data());
    const int lin = v.cells[i];
    const Vec2 o = v.grid.cell_center_m(lin / v.grid.width_px, lin % v.grid.width_px);
    const double angle = 2.0 * kPi * a / v.num_directions;
    const bool same = got == brute_force_bins(lines, GetParam(), v.bins, o, angle, 0.0) ||
                      got == brute_force_bins(lines, GetParam(), v.bins, o, angle, 1e-6) ||
                      got == brute_force_bins(lines, GetParam(), v.bins, o, angle, -1e-6);
    EXPECT_TRUE(same) << "cell " << i << " at (" << o.x() << ", " << o.y() << "), direction " << a;
    for (int c : got) {
      crossings += c == kBevDoor || c == kBevWindow;
      stops += c == (GetParam() == BevClasses::kSemantic ? kBevWall : kBevOccupied);
    }
  }
  EXPECT_GT(stops, 2000);
  if (GetParam() == BevClasses::kSemantic) {
    EXPECT_GT(crossings, 100);
  }
}

INSTANTIATE_TEST_SUITE_P(Classes, BevVolume, ::testing::Values(BevClasses::kSemantic, BevClasses::kOccupancy),
                         [](const auto& info) { return std::string(bev_classes_name(info.param)); });

// A 12 m corridor crossed by an open door, a closed door and a window, ended by a wall: a ray
// along it marks each and stops at the wall; without semantics the window stops it and the doors
// are gone.
TEST(BevVolumeRules, DoorsAndWindowsPassWallsStop) {
  FloorPlan p;
  p.walls = {test::wall("s", 0, 0, 12, 0), test::wall("e", 12, 0, 12, 2), test::wall("n", 12, 2, 0, 2),
             test::wall("w", 0, 2, 0, 0),  test::wall("x1", 3, 0, 3, 2),   test::wall("x2", 5, 0, 5, 2),
             test::wall("x3", 7, 0, 7, 2)};
  p.doors = {{"open", "x1", {3.0, 1.0}, 1.0, false}, {"closed", "x2", {5.0, 1.0}, 1.0, true}};
  p.windows = {{"glass", "x3", {7.0, 1.0}, 1.0, 0.9, 2.1}};
  BevMatcherParams params;
  params.max_range_m = 12.0;
  params.num_directions = 72;
  const BevMatcher m(p, params);
  const SemanticVolume& v = m.volume();
  int row = 0, col = 0;
  ASSERT_TRUE(v.grid.world_to_cell({1.05, 1.05}, row, col));
  const std::int32_t i = v.cell_index[static_cast<std::size_t>(row) * v.grid.width_px + col];
  ASSERT_GE(i, 0);
  const Vec2 o = v.grid.cell_center_m(row, col);
  std::vector<int> cls(static_cast<std::size_t>(v.bins.count));
  v.render(static_cast<std::size_t>(i), 0, cls.data());
  const double half = 0.075;  // wall half thickness: faces at x -+ half
  auto at = [&](double x) { return cls[static_cast<std::size_t>(v.bins.bin_of(x - half - o.x()))]; };
  EXPECT_EQ(at(3.0), kBevDoor);    // open door: passes
  EXPECT_EQ(at(5.0), kBevDoor);    // closed door: passes too (the thesis' plan rays)
  EXPECT_EQ(at(7.0), kBevWindow);  // window: passes
  EXPECT_EQ(at(12.0), kBevWall);   // the end wall stops
  int marked = 0;
  for (int c : cls) marked += c != kBevEmpty;
  EXPECT_EQ(marked, 4);
  // Looking at the side wall: a wall stops at once, nothing behind it.
  v.render(static_cast<std::size_t>(i), 18, cls.data());  // +90 deg
  marked = 0;
  for (int c : cls) marked += c != kBevEmpty;
  EXPECT_EQ(marked, 1);
  EXPECT_EQ(cls[static_cast<std::size_t>(v.bins.bin_of(2.0 - half - o.y()))], kBevWall);
  // No semantics: the window is occupied and stops; the doors are removed.
  params.semantics = false;
  const BevMatcher occ(p, params);
  occ.volume().render(static_cast<std::size_t>(i), 0, cls.data());
  marked = 0;
  for (int c : cls) marked += c != kBevFree;
  EXPECT_EQ(marked, 1);
  EXPECT_EQ(cls[static_cast<std::size_t>(v.bins.bin_of(7.0 - half - o.x()))], kBevOccupied);
}

// Eq. 3.3 as the matcher computes it equals the obvious sum at every orientation of sampled
// cells, for a perfect and for a soft BEV, mean and exp likelihoods.
TEST(BevMatcher, ScoresEqualTheReferenceSum) {
  const FloorPlan plan = windowed_floor();
  Observation2D obs = perfect_observation(plan, {6.72, 6.83, 5.9});
  // A soft variant: every distribution mixed with uniform, columns of a 60 deg view only.
  Observation2D soft = obs;
  BevPrediction& b = soft.bev[0];
  for (float& x : b.probabilities) x = 0.7f * x + 0.3f / 4.0f;
  BevPrediction view = b;
  view.column_azimuth_rad.clear();
  view.probabilities.clear();
  for (int w = 0; w < b.num_columns(); ++w) {
    const double az = wrap_angle_rad(b.column_azimuth_rad[static_cast<std::size_t>(w)]);
    if (std::abs(az) > deg_to_rad(30.0)) continue;
    view.column_azimuth_rad.push_back(az);
    const float* p = b.probabilities.data() + static_cast<std::size_t>(w) * b.bins.count * 4;
    view.probabilities.insert(view.probabilities.end(), p, p + b.bins.count * 4);
  }
  Observation2D persp;
  persp.bev = {view};
  for (const BevLikelihood lk : {BevLikelihood::kMean, BevLikelihood::kExp}) {
    BevMatcherParams params;
    params.likelihood = lk;
    const BevMatcher m(plan, params);
    for (const Observation2D* o : {&obs, &soft, &persp}) {
      const MatchResult r = m.match(*o);
      ASSERT_NO_THROW(r.posterior.check());
      const BevPrediction& bev = *m.observation_bev(*o);
      for (std::size_t i = 0; i < m.volume().num_cells(); i += 97) {
        const std::vector<double> ref = bev_scores_reference(m.volume(), i, bev, params.num_orientations, lk, params.temperature);
        const int lin = m.volume().cells[i];
        for (int k = 0; k < params.num_orientations; ++k) {
          const float got = r.posterior.scores[static_cast<std::size_t>(k)].ptr<float>()[lin];
          EXPECT_NEAR(got, ref[static_cast<std::size_t>(k)], 2e-5 * std::max(1.0, ref[static_cast<std::size_t>(k)]))
              << "cell " << i << " orientation " << k;
        }
      }
    }
  }
}

// A perfect BEV taken at a cell centre and an orientation of the grid localises exactly there:
// the full circle and a 90 deg view, with and without semantics.
TEST(BevMatcher, PerfectBevLocalisesADistinctiveRoomExactly) {
  const FloorPlan plan = windowed_floor();
  for (const bool semantics : {true, false}) {
    BevMatcherParams params;
    params.semantics = semantics;
    const BevMatcher m(plan, params);
    const GridSpec& g = m.grid();
    for (const auto& [x, y, k] : {std::tuple<double, double, int>{3.23, 1.61, 4}, {10.31, 3.07, 25}, {6.72, 6.83, 33}}) {
      int row = 0, col = 0;
      ASSERT_TRUE(g.world_to_cell({x, y}, row, col));
      const Vec2 c = g.cell_center_m(row, col);
      const Pose2 truth{c.x(), c.y(), 2.0 * kPi * k / params.num_orientations};
      Observation2D obs = perfect_observation(plan, truth);
      for (const bool view : {false, true}) {
        Observation2D o = obs;
        if (view) {
          for (BevPrediction& b : o.bev) {
            BevPrediction cut = b;
            cut.column_azimuth_rad.clear();
            cut.probabilities.clear();
            const int C = b.num_classes();
            for (int w = 0; w < b.num_columns(); ++w) {
              const double az = wrap_angle_rad(b.column_azimuth_rad[static_cast<std::size_t>(w)]);
              if (std::abs(az) > deg_to_rad(45.0)) continue;
              cut.column_azimuth_rad.push_back(az);
              const float* p = b.probabilities.data() + static_cast<std::size_t>(w) * b.bins.count * C;
              cut.probabilities.insert(cut.probabilities.end(), p, p + b.bins.count * C);
            }
            b = cut;
          }
        }
        const MatchResult r = m.match(o, MatchRequest::modes(1));
        ASSERT_TRUE(r.has_pose());
        EXPECT_EQ(r.estimate().row, row) << "semantics " << semantics << " view " << view << " at " << x << ", " << y;
        EXPECT_EQ(r.estimate().col, col) << "semantics " << semantics << " view " << view << " at " << x << ", " << y;
        EXPECT_EQ(r.estimate().slice, k) << "semantics " << semantics << " view " << view << " at " << x << ", " << y;
        // Every bin agrees (but for a hit within float rounding of a bin edge).
        EXPECT_GT(r.estimate().score, 1.0 - 2.0 / (32.0 * 72.0));
      }
    }
  }
}

// Removing a door from the plan (the wall closes) changes the posterior only at poses from which
// one of the observation's columns sees the door (the brute-force cast of the original plan
// enters its faces), and does change it there.
TEST(BevMatcher, RemovingADoorChangesThePosteriorOnlyWhereItIsVisible) {
  const FloorPlan plan = windowed_floor();
  FloorPlan edited = plan;
  const Door removed = edited.doors[1];  // d2 in m2
  edited.doors.erase(edited.doors.begin() + 1);
  BevMatcherParams params;
  const BevMatcher a(plan, params), b(edited, params);
  ASSERT_TRUE(a.grid() == b.grid());
  const Observation2D obs = perfect_observation(plan, {3.23, 1.61, 0.31});
  const Posterior pa = a.match(obs).posterior, pb = b.match(obs).posterior;
  // The door's faces, and every direction a column is drawn along at each orientation.
  const SemanticPlanLines lines = semantic_plan_lines(plan, BevClasses::kSemantic, params.blocking.cut_height_m);
  const OpeningSpan span = opening_span(plan, removed.wall_id, removed.center_m, removed.width_m);
  const Wall& wall = plan.walls[static_cast<std::size_t>(span.wall_index)];
  const Vec2 d0 = wall.a_m + span.t0_m * wall.direction(), d1 = wall.a_m + span.t1_m * wall.direction();
  auto near_door = [&](const Vec2& p) { return point_segment_distance(p, {d0, d1}) <= 0.5 * wall.thickness_m + 1e-6; };
  const int A = params.num_directions, K = params.num_orientations;
  const BevPrediction& bev = obs.bev[0];
  const GridSpec& g = a.grid();
  auto sees_door = [&](const Vec2& o, int k) {
    if ((o - removed.center_m).norm() < 0.6) return true;  // cells in the doorway itself
    for (int w = 0; w < bev.num_columns(); ++w) {
      const double az = 2.0 * kPi * k / K + bev.column_azimuth_rad[static_cast<std::size_t>(w)];
      const int dir = static_cast<int>(std::floor(az * A / (2.0 * kPi) + 0.5)) % A;
      const double angle = 2.0 * kPi * dir / A;
      for (const SemanticHit& h : semantic_ray_hits(lines, o, angle, params.max_range_m)) {
        if (h.label == SemanticClass::kWall) break;
        if (near_door(o + h.range_m * Vec2(std::cos(angle), std::sin(angle)))) return true;
      }
    }
    return false;
  };
  int changed = 0;
  for (int r = 0; r < g.height_px; ++r) {
    for (int c = 0; c < g.width_px; ++c) {
      for (int k = 0; k < K; ++k) {
        if (pa.scores[static_cast<std::size_t>(k)].at<float>(r, c) == pb.scores[static_cast<std::size_t>(k)].at<float>(r, c)) continue;
        ++changed;
        EXPECT_TRUE(sees_door(g.cell_center_m(r, c), k)) << "changed where the door is not visible: cell (" << r << ", " << c
                                                          << "), orientation " << k;
      }
    }
  }
  EXPECT_GT(changed, 1000);
  // And it changes where the door is in view: below it looking up, above it looking down.
  for (const auto& [x, y, k] : {std::tuple<double, double, int>{7.0, 3.0, 9}, {7.0, 7.0, 27}, {6.2, 2.0, 9}}) {
    int r = 0, c = 0;
    ASSERT_TRUE(g.world_to_cell({x, y}, r, c));
    EXPECT_TRUE(sees_door(g.cell_center_m(r, c), k));
    EXPECT_NE(pa.scores[static_cast<std::size_t>(k)].at<float>(r, c), pb.scores[static_cast<std::size_t>(k)].at<float>(r, c))
        << x << ", " << y;
  }
}

// The bounded search finds the modes of the full posterior, scores and ties alike: perfect, soft
// and diffuse BEVs, full circle and a 60 deg view, top-1, top-3 and top-8, both likelihoods, with
// and without semantics.
TEST(BevMatcher, BoundedSearchEqualsTheFullPosterior) {
  const FloorPlan plan = windowed_floor();
  int checked = 0, switched = 0;
  for (const bool semantics : {true, false}) {
   for (const BevLikelihood lk : {BevLikelihood::kMean, BevLikelihood::kExp}) {
    BevMatcherParams params;
    params.likelihood = lk;
    params.semantics = semantics;
    params.search = BevSearch::kBounded;
    const BevMatcher bounded(plan, params);
    // search auto made to switch at its check: the exhaustive modes through the auto path.
    BevMatcherParams switching = params;
    switching.search = BevSearch::kAuto;
    switching.auto_exhaustive_share = 0.0;
    const BevMatcher auto_switching(bounded, switching);
    for (const Pose2& pose : {Pose2{3.23, 1.61, 0.31}, Pose2{10.31, 3.07, 4.4}, Pose2{6.72, 6.83, 5.9}}) {
      const Observation2D perfect = perfect_observation(plan, pose);
      for (const float mix : {0.0f, 0.3f, 0.9f}) {
        for (const double fov_deg : {360.0, 60.0}) {
          Observation2D o;
          const BevPrediction& b = perfect.bev[semantics ? 0 : 1];
          BevPrediction cut = b;
          cut.column_azimuth_rad.clear();
          cut.probabilities.clear();
          for (int w = 0; w < b.num_columns(); ++w) {
            const double az = wrap_angle_rad(b.column_azimuth_rad[static_cast<std::size_t>(w)]);
            if (fov_deg < 360.0 && std::abs(az) > deg_to_rad(fov_deg / 2)) continue;
            cut.column_azimuth_rad.push_back(az);
            const int C = b.num_classes();
            for (int q = 0; q < b.bins.count * C; ++q) {
              cut.probabilities.push_back((1.0f - mix) * b.probabilities[static_cast<std::size_t>(w) * b.bins.count * C + q] +
                                          mix / static_cast<float>(C));
            }
          }
          o.bev = {cut};
          const Posterior full = bounded.match(o).posterior;
          for (const int k : {1, 3, 8}) {
            const std::vector<PoseHypothesis> expect = full.top_k(k);
            const MatchResult r = bounded.match(o, MatchRequest::modes(k));
            expect_same_modes(r.modes, expect);
            EXPECT_EQ(r.counters.at("search_exhaustive"), 0.0);
            ++checked;
            if (mix == 0.0f && fov_deg == 360.0 && k == 1) {
              EXPECT_LT(r.counters.at("cells_scored_share"), 0.5);
            }
            if (k != 3) continue;
            const MatchResult sw = auto_switching.match(o, MatchRequest::modes(k));
            expect_same_modes(sw.modes, expect);
            // It decides once 2% of the pairs are scored; a search that ends sooner is kept.
            const bool sw_exhaustive = sw.counters.at("search_exhaustive") == 1.0;
            EXPECT_EQ(sw_exhaustive, sw.stage_s.count("bounded_until_switch") == 1);
            switched += sw_exhaustive;
          }
        }
      }
    }
   }
  }
  EXPECT_EQ(checked, 216);
  EXPECT_GT(switched, 0);
}

// search auto (the default): bounded unless the share of pairs it predicts to score exceeds
// auto_exhaustive_share; the choice and the prediction are reported, the best pose and the modes are
// those of both searches whichever runs (auto_exhaustive_share = 1: never switches).
TEST(BevMatcher, AutoSearchChoosesByPredictedShareAndReportsIt) {
  const FloorPlan plan = windowed_floor();
  BevMatcherParams params;
  ASSERT_EQ(params.search, BevSearch::kAuto);
  const BevMatcher automatic(plan, params);
  BevMatcherParams bp = params, ep = params, never = params;
  bp.search = BevSearch::kBounded;
  ep.search = BevSearch::kExhaustive;
  never.auto_exhaustive_share = 1.0;
  const BevMatcher bounded(automatic, bp), exhaustive(automatic, ep), auto_never(automatic, never);
  int switched = 0, kept = 0;
  for (const Pose2& pose : {Pose2{3.23, 1.61, 0.31}, Pose2{10.31, 3.07, 4.4}, Pose2{6.72, 6.83, 5.9}}) {
    const Observation2D perfect = perfect_observation(plan, pose);
    for (const float mix : {0.0f, 0.5f, 0.95f}) {
      Observation2D o;
      BevPrediction b = perfect.bev[0];
      const float C = static_cast<float>(b.num_classes());
      for (float& p : b.probabilities) p = (1.0f - mix) * p + mix / C;
      o.bev = {b};
      const MatchResult a = automatic.match(o, MatchRequest::modes(5));
      const MatchResult x = exhaustive.match(o, MatchRequest::modes(5));
      const MatchResult y = bounded.match(o, MatchRequest::modes(5));
      const MatchResult n = auto_never.match(o, MatchRequest::modes(5));
      ASSERT_FALSE(a.modes.empty());
      for (const MatchResult* r : {&x, &y, &n}) expect_same_modes(a.modes, r->modes);
      // The reported choice follows the documented rule.
      const double share = a.counters.at("search_predicted_share");
      EXPECT_GT(share, 0.0);
      EXPECT_LE(share, 1.0);
      EXPECT_EQ(a.counters.at("search_exhaustive"), share > params.auto_exhaustive_share ? 1.0 : 0.0) << share;
      EXPECT_EQ(n.counters.at("search_exhaustive"), 0.0);
      EXPECT_EQ(x.counters.at("search_exhaustive"), 1.0);
      EXPECT_EQ(y.counters.at("search_exhaustive"), 0.0);
      EXPECT_EQ(a.stage_s.count("bounded_until_switch"), a.counters.at("search_exhaustive") == 1.0 ? 1u : 0u);
      (a.counters.at("search_exhaustive") == 1.0 ? switched : kept)++;
    }
  }
  // On this small floor the bounded search scores most pairs of a full circle (a uniform mix
  // changes no ranking, so no pruning): auto runs the exhaustive search.
  EXPECT_EQ(kept, 0);
  EXPECT_EQ(switched, 9);
}

// The thesis' 5 x 5 x 3 maximum filter: local maxima within +-2 cells and +-1 slice (circular).
TEST(BevPeaks, MaximumFilterFindsLocalMaxima) {
  Posterior p;
  p.grid = {0.0, 0.0, 0.2, 20, 20};
  for (int s = 0; s < 36; ++s) {
    p.yaw_rad.push_back(2.0 * kPi * s / 36);
    p.scores.push_back(cv::Mat::zeros(20, 20, CV_32F));
  }
  auto at = [&](int s, int r, int c) -> float& { return p.scores[static_cast<std::size_t>(s)].at<float>(r, c); };
  at(0, 5, 5) = 1.0f;
  at(0, 5, 7) = 0.9f;    // within 2 cells of a higher one: not a peak
  at(0, 5, 10) = 0.8f;   // 3 cells from the 0.9: a peak
  at(35, 10, 10) = 0.7f;
  at(1, 10, 11) = 0.75f;  // slice 1 is 2 slices from 35 (circular): both peaks
  at(0, 10, 10) = 0.6f;   // next to both in yaw and space: not a peak
  const std::vector<PoseHypothesis> peaks = p.maximum_filter_peaks(10, 2, 1);
  ASSERT_EQ(peaks.size(), 4u);
  EXPECT_EQ(peaks[0].score, 1.0f);
  EXPECT_EQ(peaks[1].score, 0.8f);
  EXPECT_EQ(peaks[1].col, 10);
  EXPECT_EQ(peaks[2].slice, 1);
  EXPECT_EQ(peaks[3].slice, 35);
  EXPECT_EQ(p.maximum_filter_peaks(2, 2, 1).size(), 2u);
  // The bev matcher's max_filter peaks are such peaks of its posterior.
  const FloorPlan plan = windowed_floor();
  const std::unique_ptr<Matcher> m = make_matcher("bev", plan, {{"peaks", "max_filter"}});
  const Observation2D obs = perfect_observation(plan, {3.23, 1.61, 0.31});
  const MatchResult r = m->match(obs, MatchRequest::modes(5));
  const std::vector<PoseHypothesis> expect = m->match(obs).posterior.maximum_filter_peaks(5, 4, 1);
  ASSERT_EQ(r.modes.size(), expect.size());
  for (std::size_t i = 0; i < expect.size(); ++i) EXPECT_EQ(r.modes[i].score, expect[i].score);
}

TEST(BevMatcher, MissingOrMismatchedBev) {
  const FloorPlan plan = windowed_floor();
  const BevMatcher m(plan);
  Observation2D none = perfect_observation(plan, {3.23, 1.61, 0.31}, 0);
  const MatchResult r = m.match(none, MatchRequest::modes(3));
  EXPECT_FALSE(r.has_pose());
  EXPECT_EQ(r.counters.at("bev_missing"), 1.0);
  Observation2D other = perfect_observation(plan, {3.23, 1.61, 0.31});
  for (BevPrediction& b : other.bev) b.bins.min_m = 0.5;
  EXPECT_THROW(m.match(other), InputError);
  // The no-semantics matcher takes the occupancy BEV and ignores the semantic one.
  BevMatcherParams p;
  p.semantics = false;
  const BevMatcher occ(plan, p);
  Observation2D sem_only = perfect_observation(plan, {3.23, 1.61, 0.31});
  sem_only.bev.pop_back();
  EXPECT_FALSE(occ.match(sem_only, MatchRequest::modes(1)).has_pose());
}

TEST(BevMatcher, ParametersAreChecked) {
  EXPECT_THROW(make_matcher_config("bev", {{"num_directions", 50}}), ParameterError);  // not a multiple of 36
  EXPECT_THROW(make_matcher_config("bev", {{"depth_bins", 64}}), ParameterError);
  EXPECT_THROW(make_matcher_config("bev", {{"min_depth_m", 20.0}}), ParameterError);
  EXPECT_THROW(make_matcher_config("bev", {{"likelihood", "max"}}), ParameterError);
  EXPECT_EQ(make_matcher_config("bev", {{"semantics", false}})->parameters()["semantics"], false);
}

}  // namespace
}  // namespace floorcast
