// Trackers on phone-like walks with no observation after the start (issue 20): the motion noise
// comes from the odometry's stated error (OdometryUncertainty), so a filter started at the truth
// keeps it over a 120-step VIO walk (the calibrated office and two real development plans), and a
// walk in a symmetric corridor keeps both twins' mass (nothing tells them apart, so neither may
// win).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <map>
#include <string>

#include "floorcast/core/math.hpp"
#include "floorcast/floorplans/import.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/floorplans/raster.hpp"
#include "floorcast/match/matcher.hpp"
#include "floorcast/sim/perfect_observation.hpp"
#include "floorcast/sim/odometry.hpp"
#include "floorcast/sim/walk.hpp"
#include "floorcast/track/histogram_filter.hpp"
#include "floorcast/track/multires_histogram_filter.hpp"
#include "floorcast/track/particle_filter.hpp"
#include "../floorplans_import/import_test_util.hpp"
#include "../match/match_test_plans.hpp"

namespace floorcast {
namespace {

/// One of the test plans: where it came from, and the plan.
struct TestPlan {
  std::string source;
  FloorPlan plan;
};

FloorPlan import_level(const std::string& path, ImportFormat format, const char* level) {
  ImportOptions o;
  o.level = level;
  return import_floor_plan(path, format, o).plan;
}

/// The calibrated office and angled building and the campus (shipped), and two real development
/// plans of different sources (RWTH PLT level 0: OSM XML; TUM StudiTUM level 0: OSM-derived
/// GeoJSON). The real plans are not part of the repository: on a clean clone (CI) the importer's fixtures of the same formats stand in
/// for them, and the test says so.
const TestPlan& test_plan(const std::string& name) {
  static std::map<std::string, TestPlan> cache;
  auto it = cache.find(name);
  if (it != cache.end()) return it->second;
  TestPlan p;
  const std::string real = test::realplans_dir();
  const std::string fixtures = std::string(FLOORCAST_SOURCE_DIR) + "/tests/floorplans_import/data/";
  if (name == "office_calibrated" || name == "campus" || name == "angled_calibrated") {
    p.source = "floorplans/buildings/" + name + ".json";
    p.plan = load_floor_plan(std::string(FLOORCAST_SOURCE_DIR) + "/" + p.source);
  } else if (name == "real_osm") {
    p.source = real.empty() ? fixtures + "osm/building.osm (no ../shared/realplans)" : real + "/rwth_aachen_plt/aachen.osm";
    p.plan = real.empty() ? import_level(fixtures + "osm/building.osm", ImportFormat::kOsm, "0")
                          : import_level(real + "/rwth_aachen_plt/aachen.osm", ImportFormat::kOsm, "0");
  } else {
    p.source = real.empty() ? fixtures + "geojson/studihaus.geojson (no ../shared/realplans)"
                            : real + "/tum_garching_studitum/studitum.geojson";
    p.plan = real.empty() ? import_level(fixtures + "geojson/studihaus.geojson", ImportFormat::kGeojson, "0")
                          : import_level(real + "/tum_garching_studitum/studitum.geojson", ImportFormat::kGeojson, "0");
  }
  return cache.emplace(name, std::move(p)).first->second;
}

/// A posterior with all its mass at one pose (one slice at its heading, one cell).
Posterior delta_at(const FloorPlan& plan, const std::vector<Pose2>& poses) {
  Posterior p;
  p.grid = grid_for_plan(plan, 0.1, 1.0);
  for (const Pose2& pose : poses) {
    p.yaw_rad.push_back(pose.yaw_rad);
    p.scores.push_back(cv::Mat::zeros(p.grid.height_px, p.grid.width_px, CV_32F));
    int r = 0, c = 0;
    EXPECT_TRUE(p.grid.world_to_cell(pose.position_m(), r, c));
    p.scores.back().at<float>(r, c) = 1.0f;
  }
  return p;
}

/// A VIO walk (the odometry model's defaults) and the tracker's parameters with its stated error,
/// as `floorcast track` and the scenarios hand them over.
struct VioWalk {
  Walk walk;
  OdometryTrack odometry;
  OdometryUncertainty uncertainty;
};

VioWalk vio_walk(const FloorPlan& plan, std::uint64_t seed, int steps) {
  WalkParams wp;
  wp.seed = seed;
  wp.steps = steps;
  VioWalk w;
  w.walk = simulate_walk(plan, random_start_pose(plan, wp), wp);
  OdometryParams op;
  op.model = OdometryModel::kVio;
  op.seed = 1000 + seed;
  w.odometry = simulate_odometry(w.walk, op);
  w.uncertainty = odometry_uncertainty(op);
  return w;
}

using PlanAndTracker = std::tuple<std::string, std::string>;
class StartedAtTheTruth : public ::testing::TestWithParam<PlanAndTracker> {};

// Started at the true pose, with no observation after it, a filter follows a 120-step VIO walk
// (70-90 m, about a minute) as well as its odometry allows: within 1 m of the truth at every step,
// or, where the odometry alone has drifted further (VIO's scale and yaw-bias errors: 1.4 m after
// 72 m on one of these walks), within 0.5 m of the odometry's own error. Its motion noise is what
// the odometry states, so the belief neither collapses onto a wrong hypothesis nor diffuses into
// another one (with F3Loc's fixed 0.1 m / 0.1 rad per step the histogram filter's estimate jumps
// metres away within 20 steps, results/sequential.md). Three walks per plan (seeds 1-3, not
// chosen); the worst errors are printed beside the odometry's.
TEST_P(StartedAtTheTruth, TracksAVioWalkAsWellAsItsOdometry) {
  const auto& [plan_name, tracker] = GetParam();
  const TestPlan& tp = test_plan(plan_name);
  std::printf("plan %s: %s\n", plan_name.c_str(), tp.source.c_str());
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    SCOPED_TRACE("walk seed " + std::to_string(seed));
    const VioWalk w = vio_walk(tp.plan, seed, 120);
    nlohmann::json overrides = {{"odometry", w.uncertainty.to_json()}};
    if (tracker == "pf") overrides["seed"] = seed;
    const std::unique_ptr<Tracker> t = make_tracker(tracker, tp.plan, overrides);
    t->initialise(delta_at(tp.plan, {w.walk.steps[0].T_world_body}), w.odometry.steps[0]);
    double worst = 0.0, odometry_worst = 0.0, end = 0.0, excess = -1e9;
    for (std::size_t k = 1; k < w.walk.steps.size(); ++k) {
      t->predict(w.odometry.steps[k]);
      const Vec2 truth = w.walk.steps[k].T_world_body.position_m();
      const double odometry_error = (w.odometry.poses[k].position_m() - truth).norm();
      end = (t->estimate().pose.position_m() - truth).norm();
      worst = std::max(worst, end);
      odometry_worst = std::max(odometry_worst, odometry_error);
      excess = std::max(excess, end - odometry_error);
      EXPECT_LE(end, std::max(1.0, odometry_error + 0.5)) << "step " << k;
    }
    std::printf("  seed %llu: %.1f m walked, worst error %.2f m, end %.2f m; odometry alone worst %.2f m; most above the odometry's error %.2f m\n",
                static_cast<unsigned long long>(seed), w.walk.summary.length_m, worst, end, odometry_worst, excess);
  }
}

INSTANTIATE_TEST_SUITE_P(Trackers, StartedAtTheTruth,
                         ::testing::Combine(::testing::Values("office_calibrated", "real_osm", "real_geojson"),
                                            ::testing::Values("hist", "pf")),
                         [](const ::testing::TestParamInfo<PlanAndTracker>& i) {
                           return std::get<0>(i.param) + "_" + std::get<1>(i.param);
                         });

/// A straight corridor, 24 m x 2.4 m, closed at both ends: symmetric under a half turn about its
/// centre, so a pose and its twin (turned by 180 deg about the centre) see the same walls.
FloorPlan symmetric_corridor() {
  FloorPlan p;
  p.name = "corridor";
  using test::wall;
  p.walls = {wall("s", 0, 0, 24, 0), wall("e", 24, 0, 24, 2.4), wall("n", 24, 2.4, 0, 2.4), wall("w", 0, 2.4, 0, 0)};
  return p;
}

Pose2 twin_of(const Pose2& p) { return {24.0 - p.x_m, 2.4 - p.y_m, wrap_angle_rad(p.yaw_rad + kPi)}; }

bool near_pose(const Pose2& a, const Vec2& position, double yaw_rad) {
  return (a.position_m() - position).norm() <= 1.0 && angle_distance_rad(a.yaw_rad, yaw_rad) <= deg_to_rad(30.0);
}

/// Share of the tracker's belief within 1 m and 30 deg of each pose (histogram filter: belief
/// mass; particle filter: share of the particles).
std::vector<double> shares_near(const Tracker& t, const std::vector<Pose2>& poses) {
  std::vector<double> share(poses.size(), 0.0);
  double total = 0.0;
  if (const auto* h = dynamic_cast<const HistogramFilter*>(&t)) {
    const Posterior b = h->belief();
    for (int s = 0; s < b.num_slices(); ++s) {
      const cv::Mat& m = b.scores[static_cast<std::size_t>(s)];
      for (int r = 0; r < m.rows; ++r)
        for (int c = 0; c < m.cols; ++c) {
          const double v = m.at<float>(r, c);
          if (v <= 0.0) continue;
          total += v;
          for (std::size_t i = 0; i < poses.size(); ++i)
            if (near_pose(poses[i], b.grid.cell_center_m(r, c), b.yaw_rad[static_cast<std::size_t>(s)])) share[i] += v;
        }
    }
  } else {
    const ParticleSet ps = dynamic_cast<const ParticleFilter&>(t).particles();
    for (const Pose2& q : ps.poses) {
      total += 1.0;
      for (std::size_t i = 0; i < poses.size(); ++i)
        if (near_pose(poses[i], q.position_m(), q.yaw_rad)) share[i] += 1.0;
    }
  }
  for (double& v : share) v = total > 0.0 ? v / total : 0.0;
  return share;
}

class SymmetricCorridor : public ::testing::TestWithParam<std::string> {};

// A walk in a symmetric corridor, started from a belief split between the truth and its twin (what
// a scan there gives): nothing along the walk tells them apart, so both keep their mass (each
// between 35% and 65% of the belief within 1 m and 30 deg of it at every step, and 80% of the
// belief near one of the two at the end). A filter whose motion step favoured a heading, or let
// one twin leak through the walls, fails. 120 steps of VIO, back and forth along the corridor.
TEST_P(SymmetricCorridor, KeepsBothTwinsMass) {
  const std::string tracker = GetParam();
  const FloorPlan plan = symmetric_corridor();
  for (std::uint64_t seed = 1; seed <= 2; ++seed) {
    SCOPED_TRACE("walk seed " + std::to_string(seed));
    const VioWalk w = vio_walk(plan, seed, 120);
    nlohmann::json overrides = {{"odometry", w.uncertainty.to_json()}};
    if (tracker == "pf") overrides["seed"] = seed;
    const std::unique_ptr<Tracker> t = make_tracker(tracker, plan, overrides);
    const Pose2 start = w.walk.steps[0].T_world_body;
    t->initialise(delta_at(plan, {start, twin_of(start)}), w.odometry.steps[0]);
    double lo = 1.0, hi = 0.0;
    std::vector<double> share;
    for (std::size_t k = 1; k < w.walk.steps.size(); ++k) {
      t->predict(w.odometry.steps[k]);
      const Pose2 truth = w.walk.steps[k].T_world_body;
      share = shares_near(*t, {truth, twin_of(truth)});
      for (double v : share) {
        lo = std::min(lo, v);
        hi = std::max(hi, v);
      }
      EXPECT_GE(share[0], 0.35) << "step " << k;
      EXPECT_GE(share[1], 0.35) << "step " << k;
    }
    std::printf("  seed %llu: %.1f m walked; each twin's share between %.3f and %.3f, at the end %.3f and %.3f\n",
                static_cast<unsigned long long>(seed), w.walk.summary.length_m, lo, hi, share[0], share[1]);
    EXPECT_GE(share[0] + share[1], 0.8);
  }
}

INSTANTIATE_TEST_SUITE_P(Trackers, SymmetricCorridor, ::testing::Values("hist", "pf"));

class SparseHistogram : public ::testing::TestWithParam<std::string> {};

/// Total variation between two beliefs on the same grid: half the L1 distance.
double total_variation(const Posterior& a, const Posterior& b) {
  double l1 = 0.0;
  for (int s = 0; s < a.num_slices(); ++s) l1 += cv::norm(a.scores[static_cast<std::size_t>(s)], b.scores[static_cast<std::size_t>(s)], cv::NORM_L1);
  return 0.5 * l1;
}

/// One histogram filter on F3Loc's sequential setting (the belief starts as the ray posterior of a
/// perfect first observation: flat, the full grid), a 60-step VIO walk, an observation every 10
/// steps; its estimates at every step, the beliefs after each observation and at the end.
struct HistogramRun {
  std::vector<TrackEstimate> estimates;
  std::vector<Posterior> beliefs;
  std::vector<double> dropped, bound;  ///< dropped_mass() and drop_bound() at each of the beliefs
  std::int64_t live = 0, cells = 0;
  int point_updates = 0;
};

/// Histogram filters (sparse or dense, drop_mass each) stepped together on one walk, so one can be
/// read where the others' estimates part from it.
struct FilterSpec {
  bool sparse = true;
  double drop_mass = 0.0;
};

std::vector<HistogramRun> run_histograms(const TestPlan& tp, const VioWalk& w, const Matcher& matcher,
                                         const std::vector<FilterSpec>& specs,
                                         const std::function<void(std::size_t, const std::vector<std::unique_ptr<HistogramFilter>>&)>& each_step = {}) {
  const PerfectObserver observer(tp.plan);
  std::vector<std::unique_ptr<HistogramFilter>> filters;
  for (const FilterSpec& spec : specs) {
    HistogramFilterParams p;
    p.odometry = w.uncertainty;
    p.sparse = spec.sparse;
    p.drop_mass = spec.drop_mass;
    filters.push_back(std::make_unique<HistogramFilter>(tp.plan, p));
  }
  const Posterior first = matcher.match(observer.observe(w.walk.steps[0].T_world_body)).posterior;
  for (auto& f : filters) f->initialise(first, w.odometry.steps[0]);
  std::vector<HistogramRun> out(specs.size());
  for (std::size_t k = 1; k < w.walk.steps.size(); ++k) {
    const bool observe = k % 10 == 0;
    std::unique_ptr<PosteriorQuery> query;
    if (observe) query = std::make_unique<PosteriorQuery>(matcher.query(observer.observe(w.walk.steps[k].T_world_body)));
    for (std::size_t i = 0; i < filters.size(); ++i) {
      HistogramFilter& f = *filters[i];
      f.predict(w.odometry.steps[k]);
      if (observe) f.update(*query);
      out[i].estimates.push_back(f.estimate());
      if (observe || k + 1 == w.walk.steps.size()) {
        out[i].beliefs.push_back(f.belief());
        out[i].dropped.push_back(f.dropped_mass());
        out[i].bound.push_back(f.drop_bound());
      }
    }
    if (each_step) each_step(k, filters);
  }
  for (std::size_t i = 0; i < filters.size(); ++i) {
    const HistogramFilter& f = *filters[i];
    HistogramRun& r = out[i];
    r.live = f.live_cells();
    r.cells = static_cast<std::int64_t>(f.grid().width_px) * f.grid().height_px * f.params().num_orientations;
    r.point_updates = f.point_query_updates();
    long long nonzero = 0;
    for (const cv::Mat& m : r.beliefs.back().scores) nonzero += cv::countNonZero(m);
    std::printf("  %s, drop_mass %g: %lld live cells (%lld non-zero) of %lld at the end, %d point-query updates, dropped mass %.3g, bound %.3g\n",
                specs[i].sparse ? "sparse" : "dense", specs[i].drop_mass, static_cast<long long>(r.live), nonzero,
                static_cast<long long>(r.cells), r.point_updates, f.dropped_mass(), f.drop_bound());
  }
  return out;
}

/// The belief's value at the cell and heading bin nearest `pose` over its largest value (1 when
/// `pose` is at the belief's argmax or ties it).
double share_of_maximum_at(const Posterior& belief, const Pose2& pose) {
  int row = 0, col = 0;
  if (!belief.grid.world_to_cell(pose.position_m(), row, col)) return 0.0;
  int slice = 0;
  double best_gap = 10.0;
  for (int s = 0; s < belief.num_slices(); ++s) {
    const double gap = angle_distance_rad(belief.yaw_rad[static_cast<std::size_t>(s)], pose.yaw_rad);
    if (gap < best_gap) best_gap = gap, slice = s;
  }
  const double max_value = belief.argmax().score;
  return max_value > 0.0 ? belief.scores[static_cast<std::size_t>(slice)].at<float>(row, col) / max_value : 0.0;
}

// The sparse histogram filter against the dense one (every cell, full posteriors) on the
// calibrated office, the campus and a real development plan (RWTH PLT level 0), in F3Loc's
// sequential setting.
// - drop_mass 0 (exact: steps over the cells holding belief, updates from the ray matcher's point
//   queries at those cells): the same estimate, support and stage at every step, bit for bit,
//   and the same belief, while the sparse filter touches a small part of the grid.
// - drop_mass at its default (1e-4 of the mass per step dropped from the least likely cells,
//   accounted): the stated tolerance (localization/track/README.md, results/bench_filter.md):
//   the dropped mass is at most drop_mass per normalisation (one per step, one more per
//   update); the total variation between the sparse and the dense belief stays within the
//   filter's worst-case bound (drop_bound()) and within twice the accounted dropped mass (measured:
//   at most 1.02 times it, after the first update) after every observation and at the end; the
//   estimates stay within 0.2 m and one heading bin of the dense filter's at every step (so their
//   errors against the truth differ by at most 0.2 m) except where the dense belief's argmax is a
//   tie (the dropping filter's estimate scores within 0.1% of the dense maximum in the dense
//   belief: the calibrated office's walk of seed 5 has an exact tie at step 4, a twin 72 m away
//   turned by 90 deg, before the second observation), and the belief holds fewer live cells than
//   the exact sparse filter's. The filters are stepped together (run_histograms) so the dense
//   belief can be read where the estimates part.
TEST_P(SparseHistogram, EqualsTheDenseFilterWithinTheAccountedMass) {
  constexpr double kTie = 1e-3;
  const TestPlan& tp = test_plan(GetParam());
  std::printf("plan %s: %s\n", GetParam().c_str(), tp.source.c_str());
  const VioWalk w = vio_walk(tp.plan, 5, 60);
  const std::unique_ptr<Matcher> matcher = make_matcher("ray", tp.plan);
  const double tolerance = HistogramFilterParams{}.drop_mass;
  ASSERT_GT(tolerance, 0.0);
  // Where the dropping filter's estimate parts from the dense one's: the dense belief there over
  // its maximum (1: a tie the dense filter broke the other way).
  std::map<std::size_t, double> parted;
  const auto compare = [&](std::size_t k, const std::vector<std::unique_ptr<HistogramFilter>>& f) {
    const TrackEstimate d = f[0]->estimate(), s = f[2]->estimate();
    if ((s.pose.position_m() - d.pose.position_m()).norm() <= 0.2 && angle_distance_rad(s.pose.yaw_rad, d.pose.yaw_rad) <= kTwoPi / 36 + 1e-9)
      return;
    parted[k] = share_of_maximum_at(f[0]->belief(), s.pose);
  };
  const std::vector<HistogramRun> runs = run_histograms(tp, w, *matcher, {{false, 0.0}, {true, 0.0}, {true, tolerance}}, compare);
  const HistogramRun &dense = runs[0], &exact = runs[1], &dropping = runs[2];
  ASSERT_EQ(exact.estimates.size(), dense.estimates.size());
  ASSERT_EQ(dropping.estimates.size(), dense.estimates.size());
  for (std::size_t k = 0; k < dense.estimates.size(); ++k) {
    const TrackEstimate &e = exact.estimates[k], &d = dense.estimates[k];
    EXPECT_EQ(e.pose.x_m, d.pose.x_m) << "step " << k + 1;
    EXPECT_EQ(e.pose.y_m, d.pose.y_m) << "step " << k + 1;
    EXPECT_EQ(e.pose.yaw_rad, d.pose.yaw_rad) << "step " << k + 1;
    EXPECT_EQ(e.support, d.support) << "step " << k + 1;
    EXPECT_EQ(e.stage, d.stage) << "step " << k + 1;
  }
  for (std::size_t i = 0; i < dense.beliefs.size(); ++i) EXPECT_EQ(total_variation(exact.beliefs[i], dense.beliefs[i]), 0.0);
  EXPECT_EQ(dense.point_updates, 0);
  EXPECT_EQ(exact.live, dense.live);  // the same belief (live cells are those between non-zero ones)
  if (GetParam() != "campus") {
    // The campus keeps 42% of its cells live without dropping (the measurement floor keeps
    // every hypothesis above prune_below): what drop_mass is for.
    EXPECT_GT(exact.point_updates, 0);
    EXPECT_LT(exact.live, exact.cells / 4);
  }
  double worst_position = 0.0, worst_yaw = 0.0, lowest_tie = 1.0;
  for (std::size_t k = 0; k < dense.estimates.size(); ++k) {
    const TrackEstimate &s = dropping.estimates[k], &d = dense.estimates[k];
    const auto p = parted.find(k + 1);
    if (p == parted.end()) {
      worst_position = std::max(worst_position, (s.pose.position_m() - d.pose.position_m()).norm());
      worst_yaw = std::max(worst_yaw, angle_distance_rad(s.pose.yaw_rad, d.pose.yaw_rad));
      continue;
    }
    // Parted: only over a tie of the dense belief's argmax (the dropping filter's cell within kTie
    // of the dense maximum: a mirrored twin of the estimate), which the dropped mass may break the
    // other way.
    lowest_tie = std::min(lowest_tie, p->second);
    std::printf("    step %zu: estimates %.2f m and %.0f deg apart, the dense belief at the dropping filter's estimate %.5f of its maximum\n",
                k + 1, (s.pose.position_m() - d.pose.position_m()).norm(), rad_to_deg(angle_distance_rad(s.pose.yaw_rad, d.pose.yaw_rad)), p->second);
    EXPECT_GE(p->second, 1.0 - kTie) << "step " << k + 1;
  }
  double worst_tv = 0.0;
  for (std::size_t i = 0; i < dense.beliefs.size(); ++i) {
    const double tv = total_variation(dropping.beliefs[i], dense.beliefs[i]);
    worst_tv = std::max(worst_tv, tv);
    std::printf("    belief %zu: total variation %.3g, dropped mass %.3g, bound %.3g\n", i, tv, dropping.dropped[i], dropping.bound[i]);
    EXPECT_LE(tv, dropping.bound[i] + 1e-5) << "belief " << i;
    EXPECT_LE(tv, 2.0 * dropping.dropped[i] + 1e-5) << "belief " << i;
  }
  std::printf("  drop_mass %g against dense: estimates at most %.3f m and %.1f deg apart (%zu step(s) over a tie: the dense "
              "belief there at least %.5f of its maximum); total variation at most %.3g "
              "(accounted mass at the end %.3g); live cells %.2f%% (exact sparse %.2f%%)\n",
              tolerance, worst_position, rad_to_deg(worst_yaw), parted.size(), lowest_tie, worst_tv, dropping.dropped.back(),
              100.0 * dropping.live / dropping.cells, 100.0 * exact.live / exact.cells);
  EXPECT_GT(dropping.dropped.back(), 0.0);
  EXPECT_LE(dropping.dropped.back(), tolerance * (2 * static_cast<double>(dense.estimates.size()) + 1) + 1e-6);
  EXPECT_LT(dropping.live, exact.live);
}

INSTANTIATE_TEST_SUITE_P(Plans, SparseHistogram, ::testing::Values("office_calibrated", "campus", "real_osm"));

}  // namespace
}  // namespace floorcast

namespace floorcast {
namespace {

/// Estimates of a tracker on F3Loc's sequential setting (as run_histograms: the ray posterior of a
/// perfect first observation, then an observation every `every` steps; 0 = none).
std::vector<TrackEstimate> run_sequential(Tracker& t, const FloorPlan& plan, const VioWalk& w, const Matcher& matcher, int every) {
  const PerfectObserver observer(plan);
  t.initialise(matcher.match(observer.observe(w.walk.steps[0].T_world_body)).posterior, w.odometry.steps[0]);
  std::vector<TrackEstimate> out;
  for (std::size_t k = 1; k < w.walk.steps.size(); ++k) {
    t.predict(w.odometry.steps[k]);
    if (every > 0 && k % static_cast<std::size_t>(every) == 0) t.update(matcher.query(observer.observe(w.walk.steps[k].T_world_body)));
    out.push_back(t.estimate());
  }
  return out;
}

// hist_mr on a plan whose grid fits in its window (the shipped apartment, 12 x 11 m) is the
// single-resolution filter: the same estimates, support and stage at every step, bit for bit.
TEST(MultiResolutionHistogram, IsTheHistogramFilterOnPlansThatFitTheWindow) {
  const FloorPlan plan = load_floor_plan(std::string(FLOORCAST_SOURCE_DIR) + "/floorplans/buildings/apartment.json");
  const VioWalk w = vio_walk(plan, 3, 40);
  const std::unique_ptr<Matcher> matcher = make_matcher("ray", plan);
  HistogramFilterParams p;
  p.odometry = w.uncertainty;
  HistogramFilter single(plan, p);
  MultiResolutionHistogramFilterParams mp;
  mp.filter = p;
  MultiResolutionHistogramFilter multi(plan, mp);
  ASSERT_TRUE(multi.single_resolution());
  const std::vector<TrackEstimate> a = run_sequential(single, plan, w, *matcher, 10), b = run_sequential(multi, plan, w, *matcher, 10);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].pose.x_m, b[k].pose.x_m) << "step " << k + 1;
    EXPECT_EQ(a[k].pose.y_m, b[k].pose.y_m) << "step " << k + 1;
    EXPECT_EQ(a[k].pose.yaw_rad, b[k].pose.yaw_rad) << "step " << k + 1;
    EXPECT_EQ(a[k].support, b[k].support) << "step " << k + 1;
    EXPECT_EQ(a[k].stage, b[k].stage) << "step " << k + 1;
  }
}

// On large plans in F3Loc's sequential setting, hist_mr keeps a coarse belief (0.4 m) over the plan
// and refines in a 30 m window once the window holds half of it.
// - The calibrated angled building (shipped; 93 x 68 m of grid), on a walk whose belief
//   concentrates after the observations (the first of seeds 5-12 on which the single-resolution
//   filter converges at more than 10 steps; measured: seed 5, 20 steps): it reports from the
//   window at the end, and wherever the single-resolution filter has converged (support >= 0.5)
//   the two estimates are within 0.5 m and one heading bin (measured 0.13 m). Until the sampler
//   painted thin partitions this ran on the calibrated office, seed 5 (0.34 m); its walks now
//   start elsewhere and the office's repeated wings keep the belief spread (at most 10 converged
//   steps on seeds 5-14; 16 on seed 15), so that plan no longer tests the window.
// - Shipped campus (repeated rooms): the exact filter's belief stays wide over the whole walk (no
//   step converged); hist_mr reports the coarse estimate, which stays within 1 m of the exact
//   filter's at every step after the second observation (measured: printed), and both end within
//   1 m of the truth.
std::vector<TrackEstimate> compare_multires(const std::string& name, std::unique_ptr<MultiResolutionHistogramFilter>& multi,
                                            std::vector<TrackEstimate>& exact, VioWalk& w, std::uint64_t walk_seed = 5) {
  const TestPlan& tp = test_plan(name);
  w = vio_walk(tp.plan, walk_seed, 60);
  const std::unique_ptr<Matcher> matcher = make_matcher("ray", tp.plan);
  HistogramFilterParams p;
  p.odometry = w.uncertainty;
  HistogramFilter single(tp.plan, p);
  MultiResolutionHistogramFilterParams mp;
  mp.filter = p;
  multi = std::make_unique<MultiResolutionHistogramFilter>(tp.plan, mp);
  EXPECT_FALSE(multi->single_resolution());
  EXPECT_NEAR(multi->coarse_grid().resolution_m_per_px, 0.4, 1e-12);
  exact = run_sequential(single, tp.plan, w, *matcher, 10);
  return run_sequential(*multi, tp.plan, w, *matcher, 10);
}

TEST(MultiResolutionHistogram, RefinesInAWindowAndAgreesWithTheExactFilterOnceConverged) {
  std::unique_ptr<MultiResolutionHistogramFilter> multi;
  std::vector<TrackEstimate> a;
  VioWalk w;
  std::vector<TrackEstimate> b;
  std::uint64_t seed = 5;
  for (; seed <= 12; ++seed) {
    b = compare_multires("angled_calibrated", multi, a, w, seed);
    const auto converged = std::count_if(a.begin(), a.end(), [](const TrackEstimate& e) { return e.support >= 0.5; });
    std::printf("  walk seed %llu: the exact filter converged at %ld of %zu steps\n", static_cast<unsigned long long>(seed),
                static_cast<long>(converged), a.size());
    if (converged > 10) break;
  }
  ASSERT_EQ(a.size(), b.size());
  int compared = 0;
  double worst = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    if (a[k].support < 0.5) continue;
    ++compared;
    const double d = (a[k].pose.position_m() - b[k].pose.position_m()).norm();
    worst = std::max(worst, d);
    EXPECT_LE(d, 0.5) << "step " << k + 1;
    EXPECT_LE(angle_distance_rad(a[k].pose.yaw_rad, b[k].pose.yaw_rad), kTwoPi / 36 + 1e-9) << "step " << k + 1;
  }
  const Vec2 truth = w.walk.steps.back().T_world_body.position_m();
  std::printf("  angled_calibrated, walk seed %llu: %d of %zu steps with the exact filter converged, estimates at most %.2f m apart there; end "
              "errors %.2f / %.2f m (exact / hist_mr); %d window(s) built, refined at the end: %s\n",
              static_cast<unsigned long long>(seed), compared, a.size(), worst, (a.back().pose.position_m() - truth).norm(), (b.back().pose.position_m() - truth).norm(),
              multi->windows_built(), multi->refined() ? "yes" : "no");
  EXPECT_GT(compared, 10);
  EXPECT_GE(multi->windows_built(), 1);
  EXPECT_TRUE(multi->refined());
}

TEST(MultiResolutionHistogram, ReportsTheCoarseEstimateWhileTheBeliefIsWide) {
  std::unique_ptr<MultiResolutionHistogramFilter> multi;
  std::vector<TrackEstimate> a;
  VioWalk w;
  const std::vector<TrackEstimate> b = compare_multires("campus", multi, a, w);
  ASSERT_EQ(a.size(), b.size());
  double worst = 0.0;
  int converged = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    converged += a[k].support >= 0.5;
    if (k + 1 < 20) continue;
    const double d = (a[k].pose.position_m() - b[k].pose.position_m()).norm();
    worst = std::max(worst, d);
    EXPECT_LE(d, 1.0) << "step " << k + 1;
  }
  const Vec2 truth = w.walk.steps.back().T_world_body.position_m();
  const double ea = (a.back().pose.position_m() - truth).norm(), eb = (b.back().pose.position_m() - truth).norm();
  std::printf("  campus: exact filter converged at %d of %zu steps; from step 20 the estimates are at most %.2f m apart; end errors "
              "%.2f / %.2f m (exact / hist_mr); %d window(s) built, refined at the end: %s\n",
              converged, a.size(), worst, ea, eb, multi->windows_built(), multi->refined() ? "yes" : "no");
  EXPECT_LE(ea, 1.0);
  EXPECT_LE(eb, 1.0);
}

}  // namespace
}  // namespace floorcast
