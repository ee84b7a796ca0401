// Trackers: histogram-filter motion known answers, particle-filter wall handling and resampling
// known answers, initialisation modes, convergence on a walk, determinism.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "floorcast/core/math.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/match/matcher.hpp"
#include "floorcast/sim/odometry.hpp"
#include "floorcast/sim/perfect_observation.hpp"
#include "floorcast/sim/walk.hpp"
#include "floorcast/track/histogram_filter.hpp"
#include "floorcast/track/particle_filter.hpp"
#include "../match/match_test_plans.hpp"

namespace floorcast {
namespace {

Wall make_wall(const char* id, double ax, double ay, double bx, double by, double t = 0.1) {
  Wall w;
  w.id = id;
  w.a_m = {ax, ay};
  w.b_m = {bx, by};
  w.thickness_m = t;
  return w;
}

/// A closed 20 x 10 m hall (nothing inside): an "empty map".
FloorPlan hall() {
  FloorPlan p;
  p.name = "hall";
  p.walls = {make_wall("s", 0, 0, 20, 0), make_wall("e", 20, 0, 20, 10), make_wall("n", 20, 10, 0, 10), make_wall("w", 0, 10, 0, 0)};
  return p;
}

/// A posterior with all its mass in the given cells (value 1) on a grid over `plan`.
Posterior delta_posterior(const GridSpec& grid, int slices, const std::vector<std::tuple<int, Vec2>>& at) {
  Posterior p;
  p.grid = grid;
  for (int s = 0; s < slices; ++s) {
    p.yaw_rad.push_back(wrap_angle_rad(kTwoPi * s / slices));
    p.scores.push_back(cv::Mat::zeros(grid.height_px, grid.width_px, CV_32F));
  }
  for (const auto& [slice, pos] : at) {
    int r = 0, c = 0;
    EXPECT_TRUE(grid.world_to_cell(pos, r, c));
    p.scores[static_cast<std::size_t>(slice)].at<float>(r, c) = 1.0f;
  }
  return p;
}

OdometryStep motion(double dx, double dy, double dyaw) {
  OdometryStep s;
  s.T_prev_curr = {dx, dy, dyaw};
  s.moving = true;
  return s;
}

/// Mean position and circular-mean yaw of a belief.
Pose2 belief_mean(const Posterior& b) {
  double sx = 0, sy = 0, sw = 0, cs = 0, sn = 0;
  for (int s = 0; s < b.num_slices(); ++s) {
    const cv::Mat& m = b.scores[static_cast<std::size_t>(s)];
    for (int r = 0; r < m.rows; ++r)
      for (int c = 0; c < m.cols; ++c) {
        const double w = m.at<float>(r, c);
        if (w <= 0) continue;
        const Vec2 p = b.grid.cell_center_m(r, c);
        sx += w * p.x();
        sy += w * p.y();
        sw += w;
        cs += w * std::cos(b.yaw_rad[static_cast<std::size_t>(s)]);
        sn += w * std::sin(b.yaw_rad[static_cast<std::size_t>(s)]);
      }
  }
  return {sx / sw, sy / sw, std::atan2(sn, cs)};
}

// Histogram filter on an empty map: a delta at (5, 5) heading 40 deg moved 0.25 m forward ends,
// in mean, 0.25 m along 40 deg (within 2 cm), and turning by 20 deg turns the mean heading by
// 20 deg (within 1 deg).
TEST(HistogramFilter, MotionMovesADeltaByTheCommandedMotion) {
  const FloorPlan plan = hall();
  HistogramFilterParams fixed;
  fixed.motion_noise = MotionNoiseSource::kFixed;
  HistogramFilter f(plan, fixed);
  const Posterior start = delta_posterior(f.grid(), 36, {{4, {5.05, 5.05}}});
  f.initialise(start, OdometryStep{});
  const Pose2 before = belief_mean(f.belief());
  EXPECT_NEAR(before.x_m, 5.05, 1e-6);
  f.predict(motion(0.25, 0.0, 0.0));
  const Pose2 after = belief_mean(f.belief());
  EXPECT_NEAR(after.x_m - before.x_m, 0.25 * std::cos(deg_to_rad(40.0)), 0.02);
  EXPECT_NEAR(after.y_m - before.y_m, 0.25 * std::sin(deg_to_rad(40.0)), 0.02);
  EXPECT_NEAR(angle_distance_rad(after.yaw_rad, deg_to_rad(40.0)), 0.0, deg_to_rad(1.0));
  f.predict(motion(0.0, 0.0, deg_to_rad(20.0)));
  const Pose2 turned = belief_mean(f.belief());
  EXPECT_NEAR(angle_distance_rad(turned.yaw_rad, deg_to_rad(60.0)), 0.0, deg_to_rad(1.0));
  EXPECT_NEAR(turned.x_m, after.x_m, 0.01);
  // A sideways step (body y) moves along heading + 90 deg.
  f.predict(motion(0.0, 0.2, 0.0));
  const Pose2 side = belief_mean(f.belief());
  EXPECT_NEAR(side.x_m - turned.x_m, 0.2 * std::cos(deg_to_rad(150.0)), 0.02);
  EXPECT_NEAR(side.y_m - turned.y_m, 0.2 * std::sin(deg_to_rad(150.0)), 0.02);
}

/// Mean and standard deviation of a belief's x over all slices.
std::pair<double, double> x_spread(const Posterior& b) {
  double sw = 0, sx = 0, sxx = 0;
  for (const cv::Mat& m : b.scores)
    for (int r = 0; r < m.rows; ++r)
      for (int c = 0; c < m.cols; ++c) {
        const double w = m.at<float>(r, c);
        const double x = b.grid.cell_center_m(r, c).x();
        sw += w;
        sx += w * x;
        sxx += w * x * x;
      }
  const double mean = sx / sw;
  return {mean, std::sqrt(std::max(0.0, sxx / sw - mean * mean))};
}

// A motion larger than the kernels' span (here F3Loc's 0.3 m) is split into sub-steps: one 0.9 m
// step moves the mean by 0.9 m and diffuses like one F3Loc step (sigma 0.1 m, not 0.1 x sqrt(3)).
TEST(HistogramFilter, LargeStepsAreSplitWithoutExtraNoise) {
  const FloorPlan plan = hall();
  HistogramFilterParams p;
  p.motion_noise = MotionNoiseSource::kFixed;
  p.rotation_sigma_rad = 0.0;
  p.max_substep_m = 0.3;
  HistogramFilter f(plan, p);
  f.initialise(delta_posterior(f.grid(), 36, {{0, {5.05, 5.05}}}), OdometryStep{});
  f.predict(motion(0.9, 0.0, 0.0));
  const auto [mean, sd] = x_spread(f.belief());
  EXPECT_NEAR(mean, 5.05 + 0.9, 0.01);
  EXPECT_NEAR(sd, 0.1, 0.02);
  HistogramFilter g(plan, p);
  g.initialise(delta_posterior(g.grid(), 36, {{0, {5.05, 5.05}}}), OdometryStep{});
  g.predict(motion(0.3, 0.0, 0.0));
  EXPECT_NEAR(x_spread(g.belief()).second, 0.1, 0.02);
}

// A turn larger than max_substep_deg (here 90 deg = 3 sub-steps of 30 deg) turns the whole
// belief: every sub-step sees the slices the previous one filled, so the mean heading turns by
// 90 deg (within 1 deg), the position stays (within 1 cm) and the belief keeps its mass (the
// normalised belief sums to 1 and nothing is left near the start heading).
TEST(HistogramFilter, LargeTurnsAreSplitAndKeepTheirMass) {
  const FloorPlan plan = hall();
  HistogramFilterParams p;
  p.motion_noise = MotionNoiseSource::kFixed;
  p.max_substep_deg = 30.0;
  HistogramFilter f(plan, p);
  f.initialise(delta_posterior(f.grid(), 36, {{0, {5.05, 5.05}}}), OdometryStep{});
  f.predict(motion(0.0, 0.0, deg_to_rad(90.0)));
  const Pose2 turned = belief_mean(f.belief());
  EXPECT_NEAR(angle_distance_rad(turned.yaw_rad, deg_to_rad(90.0)), 0.0, deg_to_rad(1.0));
  EXPECT_NEAR(turned.x_m, 5.05, 0.01);
  EXPECT_NEAR(turned.y_m, 5.05, 0.01);
  double total = 0.0, near_start = 0.0;
  const Posterior& b = f.belief();
  for (int s = 0; s < b.num_slices(); ++s) {
    const double m = cv::sum(b.scores[static_cast<std::size_t>(s)])[0];
    total += m;
    if (angle_distance_rad(b.yaw_rad[static_cast<std::size_t>(s)], 0.0) < deg_to_rad(45.0)) near_start += m;
  }
  EXPECT_GT(total, 0.0);
  EXPECT_LT(near_start / total, 0.01);
}

// A measurement update multiplies the belief: mass where the posterior is high.
TEST(HistogramFilter, UpdateAndEstimate) {
  const FloorPlan plan = hall();
  HistogramFilterParams p;
  p.init = BeliefInit::kUniform;
  p.measurement_floor = 0.0;
  HistogramFilter f(plan, p);
  f.initialise(delta_posterior(f.grid(), 36, {}), OdometryStep{});
  EXPECT_EQ(f.estimate().stage, 0);
  f.update(delta_posterior(f.grid(), 36, {{18, {14.05, 3.05}}}));
  const TrackEstimate e = f.estimate();
  EXPECT_NEAR(e.pose.x_m, 14.05, 1e-6);
  EXPECT_NEAR(e.pose.y_m, 3.05, 1e-6);
  EXPECT_NEAR(angle_distance_rad(e.pose.yaw_rad, kPi), 0.0, 1e-9);
  EXPECT_EQ(e.stage, 2);
  // An empty posterior is reported and changes nothing.
  f.update(delta_posterior(f.grid(), 36, {}));
  EXPECT_TRUE(f.estimate().degenerate);
  EXPECT_NEAR(f.estimate().pose.x_m, 14.05, 1e-6);
}

// The belief's peaks (the thesis' 1 m x 1 m x 30 deg maximum filter) come with the estimate when
// asked for: best first, the estimate among them, separated peaks kept apart.
TEST(HistogramFilter, ReportsTheBeliefsPeaks) {
  const FloorPlan plan = hall();
  HistogramFilterParams p;
  p.init = BeliefInit::kUniform;
  p.measurement_floor = 0.0;
  p.modes = 3;
  HistogramFilter f(plan, p);
  f.initialise(delta_posterior(f.grid(), 36, {}), OdometryStep{});
  f.update(delta_posterior(f.grid(), 36, {{18, {14.05, 3.05}}, {4, {4.05, 6.05}}}));
  const TrackEstimate e = f.estimate();
  ASSERT_EQ(e.modes.size(), 2u);
  EXPECT_NEAR(e.modes[0].x_m, e.pose.x_m, 1e-9);
  EXPECT_NEAR(e.modes[0].y_m, e.pose.y_m, 1e-9);
  const Pose2& other = e.modes[0].x_m > 10.0 ? e.modes[1] : e.modes[0];
  EXPECT_NEAR(other.x_m, 4.05, 1e-6);
  EXPECT_NEAR(other.y_m, 6.05, 1e-6);
  p.modes = 0;
  HistogramFilter g(plan, p);
  g.initialise(delta_posterior(g.grid(), 36, {{18, {14.05, 3.05}}}), OdometryStep{});
  EXPECT_TRUE(g.estimate().modes.empty());
}

/// Two rooms split by a wall at x = 10 (no door).
FloorPlan two_rooms() {
  FloorPlan p = hall();
  p.walls.push_back(make_wall("mid", 10, 0, 10, 10, 0.2));
  return p;
}

ParticleFilterParams quiet_pf(int n) {
  ParticleFilterParams p;
  p.num_particles = n;
  p.motion_noise = MotionNoiseSource::kFixed;
  p.drift_sigma_rad = 0.0;
  p.heading_sigma_rad = 0.0;
  p.step_sigma_m = 0.0;
  p.jitter_sigma_m = 0.0;
  p.init_percentile = 0.0;
  return p;
}

// Weighted walls (PALMS default): half the particles cross the wall with one step, half do not;
// after resampling the crossers hold 0.3 / 1.3 of the particles (low-variance resampling: within
// one particle).
TEST(ParticleFilter, WeightedWallCrossingKnownAnswer) {
  const FloorPlan plan = two_rooms();
  ParticleFilter f(plan, quiet_pf(1000));
  const GridSpec grid = grid_for_plan(plan, 0.1, 1.0);
  f.initialise(delta_posterior(grid, 4, {{0, {9.55, 5.05}}, {0, {5.05, 5.05}}}), OdometryStep{});
  f.predict(motion(1.0, 0.0, 0.0));
  int crossed = 0;
  for (const Pose2& p : f.particles().poses) crossed += p.x_m > 10.0 ? 1 : 0;
  EXPECT_NEAR(crossed, 1000.0 * 0.3 / 1.3, 1.0);
}

// No-pass walls: no particle ends inside or beyond a wall, whatever the noise.
TEST(ParticleFilter, NoPassKeepsEveryParticleOutOfWalls) {
  const FloorPlan plan = two_rooms();
  ParticleFilterParams p;
  p.num_particles = 2000;
  p.wall_handling = WallHandling::kNoPass;
  p.init_percentile = 0.0;
  ParticleFilter f(plan, p);
  const GridSpec grid = grid_for_plan(plan, 0.1, 1.0);
  f.initialise(delta_posterior(grid, 4, {{0, {9.35, 5.05}}, {0, {8.85, 2.05}}}), OdometryStep{});
  for (int k = 0; k < 20; ++k) {
    f.predict(motion(0.7, 0.0, 0.0));
    for (const Pose2& q : f.particles().poses) {
      ASSERT_TRUE(f.inside(q.position_m())) << "step " << k;
      ASSERT_LT(q.x_m, 10.0) << "step " << k;
    }
  }
}

// Initialisation modes: palms draws only from the top 1% of scored cells; uniform everywhere.
TEST(ParticleFilter, InitialisationModes) {
  const FloorPlan plan = hall();
  const GridSpec grid = grid_for_plan(plan, 0.1, 1.0);
  Posterior post = delta_posterior(grid, 4, {});
  // A ramp over x in slice 1: the top 1% of the scored cells are the rightmost ones.
  for (int r = 20; r < 80; ++r)
    for (int c = 20; c < 200; ++c) post.scores[1].at<float>(r, c) = static_cast<float>(c);
  ParticleFilterParams p;
  p.num_particles = 500;
  ParticleFilter palms(plan, p);
  palms.initialise(post, OdometryStep{});
  for (const Pose2& q : palms.particles().poses) {
    EXPECT_GE(q.x_m, grid.cell_center_m(0, 198).x() - 0.06);
    EXPECT_NEAR(angle_distance_rad(q.yaw_rad, post.yaw_rad[1]), 0.0, 1e-9);
  }
  p.init = ParticleInit::kUniform;
  ParticleFilter uniform(plan, p);
  uniform.initialise(post, OdometryStep{});
  int left = 0;
  for (const Pose2& q : uniform.particles().poses) left += q.x_m < 10.0 ? 1 : 0;
  EXPECT_NEAR(left, 250, 50);
  p.init = ParticleInit::kUniformOri;
  ParticleFilter ori(plan, p);
  ori.initialise(post, OdometryStep{});
  for (const Pose2& q : ori.particles().poses) {
    double gap = 1e9;
    for (double y : post.yaw_rad) gap = std::min(gap, angle_distance_rad(q.yaw_rad, y));
    EXPECT_LT(gap, 1e-9);
  }
  // An empty posterior cannot start the posterior-based modes: reported, not invented.
  ParticleFilter none(plan, ParticleFilterParams{});
  EXPECT_THROW(none.initialise(delta_posterior(grid, 4, {}), OdometryStep{}), InputError);
}

struct WalkRun {
  std::vector<double> errors;
  std::vector<int> stages;
  int point_query_updates = 0;  ///< histogram filter: updates that asked for its live cells only
  std::int64_t live_cells = 0;  ///< histogram filter: live cells at the end
};

/// Tracks a simulated walk through the rooms of the asymmetric test floor (tests/match: four rooms
/// of different sizes, doors, an angled wall: a distinctive walk) from a posterior of a perfect
/// observation at the start, with exact odometry.
/// Updates: from the full posterior, or from point queries (Matcher::query) of matcher `matcher`
/// (empty: kernel for pf, ray for hist).
enum class Updates { kFullPosterior, kPointQueries };

WalkRun track_apartment_walk(const std::string& tracker, std::uint64_t seed,
                              const nlohmann::json& overrides = nlohmann::json::object(), int observe_every = 0,
                              Updates updates = Updates::kFullPosterior, const std::string& matcher_name = "") {
  const FloorPlan plan = test::asymmetric_floor();
  WalkParams wp;
  wp.seed = seed;
  wp.steps = 80;
  wp.min_goal_distance_m = 6.0;
  wp.clearance_m = 0.3;
  const Walk walk = simulate_walk(plan, random_start_pose(plan, wp), wp);
  OdometryParams op;
  op.model = OdometryModel::kExact;
  const OdometryTrack odo = simulate_odometry(walk, op);
  const std::unique_ptr<Matcher> matcher =
      make_matcher(!matcher_name.empty() ? matcher_name : tracker == "hist" ? "ray" : "kernel", plan);
  const PerfectObserver observer(plan);
  const Posterior post = matcher->match(observer.observe(walk.steps[0].T_world_body)).posterior;
  // The walk states its odometry's error (exact: none), as scenarios and `floorcast track` do.
  const std::unique_ptr<Tracker> t = make_tracker(tracker, plan, with_odometry(overrides, odometry_uncertainty(op)));
  t->initialise(post, odo.steps[0]);
  WalkRun run;
  for (std::size_t k = 1; k < walk.steps.size(); ++k) {
    t->predict(odo.steps[k]);
    if (observe_every > 0 && k % static_cast<std::size_t>(observe_every) == 0) {
      const Observation2D obs = observer.observe(walk.steps[k].T_world_body);
      if (updates == Updates::kPointQueries) {
        t->update(matcher->query(obs));
      } else {
        t->update(matcher->match(obs).posterior);
      }
    }
    const TrackEstimate e = t->estimate();
    run.errors.push_back((e.pose.position_m() - walk.steps[k].T_world_body.position_m()).norm());
    run.stages.push_back(e.stage);
    if (const auto* h = dynamic_cast<const HistogramFilter*>(t.get())) {
      run.point_query_updates = h->point_query_updates();
      run.live_cells = h->live_cells();
    }
    if (std::getenv("TRACK_DEBUG")) {
      std::printf("%zu err %.2f stage %d support %.2f truth %.2f %.2f est %.2f %.2f\n", k, run.errors.back(), e.stage,
                  e.support, walk.steps[k].T_world_body.x_m, walk.steps[k].T_world_body.y_m, e.pose.x_m, e.pose.y_m);
    }
  }
  return run;
}

double last10_rmse(const std::vector<double>& e) {
  double s = 0.0;
  for (std::size_t i = e.size() - 10; i < e.size(); ++i) s += e[i] * e[i];
  return std::sqrt(s / 10.0);
}

// With exact odometry and a PALMS initialisation from a distinctive spot the particle filter
// converges and tracks: last-10 RMSE < 0.5 m. The motion noise is the exact odometry's (none: the
// resampling jitter alone spreads the cloud); with PALMS' 0.356 m step noise, meant for phone
// odometry, the cloud stays ~0.6 m wide on this walk.
TEST(ParticleFilter, ConvergesOnAWalkWithExactOdometry) {
  int converged = 0;
  for (std::uint64_t seed : {1, 2, 3}) {
    const WalkRun run = track_apartment_walk("pf", seed, {{"seed", seed}});
    EXPECT_LT(last10_rmse(run.errors), 0.5) << "seed " << seed;
    converged += run.stages.back() == 2 ? 1 : 0;
  }
  EXPECT_GE(converged, 2);
}

// Measurement updates from point queries (the particles' cells only) against the full posterior:
// with the ray matcher, whose point queries are bit for bit its posterior's, the same track to the
// last bit; with the kernel matcher (direct sums against the FFT posterior's round-off, which moves
// a resampling pointer now and then) the same track within 5 cm (1.2 cm measured on these walks).
TEST(ParticleFilter, PointQueryUpdatesEqualFullPosteriorUpdates) {
  for (std::uint64_t seed : {1, 2}) {
    for (const char* matcher : {"ray", "kernel"}) {
      const WalkRun full = track_apartment_walk("pf", seed, {{"seed", seed}}, 5, Updates::kFullPosterior, matcher);
      const WalkRun points = track_apartment_walk("pf", seed, {{"seed", seed}}, 5, Updates::kPointQueries, matcher);
      ASSERT_EQ(full.errors.size(), points.errors.size());
      double worst = 0.0;
      for (std::size_t k = 0; k < full.errors.size(); ++k) worst = std::max(worst, std::abs(full.errors[k] - points.errors[k]));
      if (std::string(matcher) == "ray") {
        EXPECT_EQ(worst, 0.0) << "seed " << seed;
        EXPECT_EQ(full.stages, points.stages) << "seed " << seed;
      } else {
        EXPECT_LE(worst, 0.05) << "seed " << seed;
      }
    }
  }
}

// The histogram filter asks the ray matcher for its live cells only once its belief is
// concentrated (point queries, bit for bit the posterior's values): the same track to the last bit
// as with full posteriors, and the belief's live cells (what motion and updates touch) end up a
// small part of the grid.
TEST(HistogramFilter, PointQueryUpdatesEqualFullPosteriorUpdates) {
  for (std::uint64_t seed : {1, 2}) {
    const WalkRun full = track_apartment_walk("hist", seed, nlohmann::json::object(), 4, Updates::kFullPosterior);
    const WalkRun points = track_apartment_walk("hist", seed, nlohmann::json::object(), 4, Updates::kPointQueries);
    EXPECT_EQ(full.errors, points.errors) << "seed " << seed;
    EXPECT_EQ(full.stages, points.stages) << "seed " << seed;
    EXPECT_EQ(full.point_query_updates, 0);
    EXPECT_GT(points.point_query_updates, 5) << "seed " << seed;
    const FloorPlan plan = test::asymmetric_floor();
    const HistogramFilter f(plan);
    EXPECT_LT(points.live_cells, static_cast<std::int64_t>(f.grid().width_px) * f.grid().height_px * 36 / 8) << "seed " << seed;
  }
}

// F3Loc's sequential setting: an observation (here perfect, ray matcher) every few steps.
TEST(HistogramFilter, TracksAWalkWithExactOdometryAndObservations) {
  for (std::uint64_t seed : {1, 2}) {
    const WalkRun run = track_apartment_walk("hist", seed, nlohmann::json::object(), 4);
    EXPECT_LT(last10_rmse(run.errors), 0.5) << "seed " << seed;
    EXPECT_EQ(run.stages.back(), 2) << "seed " << seed;
  }
}

// mass_within: a uniform belief over a closed 20 x 10 m hall holds all its mass in a box around the
// hall and half of it (within a cell row of the 0.1 m grid) in its left half.
TEST(HistogramFilter, MassWithinABox) {
  HistogramFilterParams p;
  p.init = BeliefInit::kUniform;
  HistogramFilter f(hall(), p);
  f.initialise(Posterior{}, OdometryStep{});
  EXPECT_NEAR(f.mass_within(-5.0, -5.0, 25.0, 15.0), 1.0, 1e-5);
  EXPECT_NEAR(f.mass_within(-5.0, -5.0, 10.0, 15.0), 0.5, 0.01);
  EXPECT_EQ(f.mass_within(30.0, 30.0, 40.0, 40.0), 0.0);
}

// Same seed, same bytes, at 1 and 2 threads.
TEST(Trackers, DeterministicAtAnyThreadCount) {
  for (const std::string name : {"pf", "hist", "hist_mr"}) {
    auto run = [&](int threads) {
      tbb::global_control gc(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
      return track_apartment_walk(name, 4);
    };
    const WalkRun one = run(1), two = run(2);
    ASSERT_EQ(one.errors.size(), two.errors.size());
    EXPECT_EQ(std::memcmp(one.errors.data(), two.errors.data(), one.errors.size() * sizeof(double)), 0) << name;
  }
}

TEST(Trackers, ParametersAndRegistry) {
  EXPECT_EQ(tracker_names(), (std::vector<std::string>{"hist", "hist_mr", "pf"}));
  const FloorPlan plan = hall();
  EXPECT_THROW(make_tracker("kalman", plan), InputError);
  EXPECT_THROW(make_tracker("pf", plan, {{"num_particle", 10}}), ParameterError);
  EXPECT_THROW(make_tracker("pf", plan, {{"init", "everywhere"}}), ParameterError);
  EXPECT_THROW(make_tracker("hist", plan, {{"num_orientations", 2}}), ParameterError);
  const auto pf = make_tracker("pf", plan, {{"num_particles", 100}, {"wall_handling", "bounce"}});
  EXPECT_EQ(pf->parameters()["num_particles"], 100);
  EXPECT_EQ(pf->parameters()["wall_handling"], "bounce");
}

}  // namespace
}  // namespace floorcast
