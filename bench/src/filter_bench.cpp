#include "floorcast/bench/filter_bench.hpp"

#include "floorcast/core/fields.hpp"

#include <chrono>
#include <vector>

#include "floorcast/core/math.hpp"
#include "floorcast/core/timing.hpp"
#include "floorcast/floorplans/raster.hpp"
#include "floorcast/match/matcher.hpp"
#include "floorcast/sim/odometry.hpp"
#include "floorcast/sim/perfect_observation.hpp"
#include "floorcast/sim/walk.hpp"
#include "floorcast/track/histogram_filter.hpp"
#include "floorcast/track/multires_histogram_filter.hpp"
#include "floorcast/track/particle_filter.hpp"

namespace floorcast {
namespace {

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// An empty posterior on a grid: the uniform initialisations do not read its scores.
Posterior empty_posterior(const FloorPlan& plan, int slices) {
  Posterior p;
  p.grid = grid_for_plan(plan, 0.1, 1.0);
  for (int s = 0; s < slices; ++s) {
    p.yaw_rad.push_back(wrap_angle_rad(kTwoPi * s / slices));
    p.scores.push_back(cv::Mat::zeros(p.grid.height_px, p.grid.width_px, CV_32F));
  }
  return p;
}

/// A walk of `steps` steps (plus the start) from a random start of the plan.
Walk bench_walk(const FloorPlan& plan, int steps, std::uint64_t seed) {
  WalkParams wp;
  wp.steps = steps + 1;
  wp.seed = seed;
  return simulate_walk(plan, random_start_pose(plan, wp), wp);
}

/// The sequential comparisons (FilterBenchResult's pf_update_* and hf_seq_*).
void bench_sequential(const FloorPlan& plan, const FilterBenchParams& bp, const Walk& exact_walk, FilterBenchResult& out) {
  const PerfectObserver observer(plan);
  {
    // Particle filter: PALMS start at a perfect observation, then each way of updating two
    // filters in the same state (an observation at the same spot).
    const std::unique_ptr<Matcher> kernel = make_matcher("kernel", plan);
    const Pose2 at = exact_walk.steps.front().T_world_body;
    const Observation2D obs = observer.observe(at);
    ParticleFilterParams p;
    p.num_particles = bp.particles;
    const Posterior start = kernel->match(obs).posterior;
    std::vector<double> full_cpu, points_cpu;
    for (int r = 0; r < bp.repeats; ++r) {
      ParticleFilter a(plan, p), b(plan, p);
      a.initialise(start, OdometryStep{});
      b.initialise(start, OdometryStep{});
      double c0 = process_cpu_s();
      a.update(kernel->match(obs).posterior);
      full_cpu.push_back(process_cpu_s() - c0);
      c0 = process_cpu_s();
      b.update(kernel->query(obs));
      points_cpu.push_back(process_cpu_s() - c0);
    }
    out.pf_update_full_cpu_s = median(full_cpu);
    out.pf_update_points_cpu_s = median(points_cpu);
  }
  // The sequential walk: a VIO walk with a perfect observation every 10 steps.
  OdometryParams op;
  op.model = OdometryModel::kVio;
  op.seed = 10;
  const Walk walk = bench_walk(plan, bp.sequential_steps, 9);
  const OdometryTrack odo = simulate_odometry(walk, op);
  std::vector<Observation2D> observations(walk.steps.size());
  for (std::size_t k = 10; k < walk.steps.size(); k += 10) observations[k] = observer.observe(walk.steps[k].T_world_body);
  const int half = bp.sequential_steps / 2;
  {
    // Particle filter end to end: PALMS start from the kernel posterior of a perfect first
    // observation, point-query updates at the observations.
    const std::unique_ptr<Matcher> kernel = make_matcher("kernel", plan);
    const Posterior start = kernel->match(observer.observe(walk.steps.front().T_world_body)).posterior;
    std::vector<double> wall, cpu;
    for (int r = 0; r < bp.repeats; ++r) {
      ParticleFilterParams p;
      p.num_particles = bp.particles;
      p.odometry = odometry_uncertainty(op);
      ParticleFilter f(plan, p);
      f.initialise(start, odo.steps[0]);
      const double w0 = now_s(), c0 = process_cpu_s();
      for (std::size_t k = 1; k < odo.steps.size(); ++k) {
        f.predict(odo.steps[k]);
        if (k % 10 == 0) f.update(kernel->query(observations[k]));
        (void)f.estimate();
      }
      wall.push_back((now_s() - w0) / bp.sequential_steps);
      cpu.push_back((process_cpu_s() - c0) / bp.sequential_steps);
    }
    out.pf_seq_steps_per_s = 1.0 / median(wall);
    out.pf_seq_cpu_ms = 1e3 * median(cpu);
  }
  {
    // Histogram filter: F3Loc's start and the observations, dense (every cell, full posteriors)
    // against sparse (the parameters' defaults: live cells, point queries, drop_mass).
    const std::unique_ptr<Matcher> ray = make_matcher("ray", plan);
    const Posterior start = ray->match(observer.observe(walk.steps.front().T_world_body)).posterior;
    std::vector<double> wall[2], cpu[2], late_cpu;
    std::vector<Pose2> track[2];
    Posterior end_belief[2];
    for (int r = 0; r < bp.repeats; ++r) {
      for (int sparse = 0; sparse < 2; ++sparse) {
        HistogramFilterParams p;
        p.odometry = odometry_uncertainty(op);
        p.sparse = sparse == 1;
        if (bp.drop_mass >= 0.0) p.drop_mass = bp.drop_mass;
        HistogramFilter f(plan, p);
        f.initialise(start, odo.steps[0]);
        track[sparse].clear();
        const double w0 = now_s(), c0 = process_cpu_s();
        double c_half = c0;
        for (std::size_t k = 1; k < odo.steps.size(); ++k) {
          f.predict(odo.steps[k]);
          if (k % 10 == 0) f.update(ray->query(observations[k]));
          track[sparse].push_back(f.estimate().pose);
          if (static_cast<int>(k) == half) c_half = process_cpu_s();
        }
        const double c1 = process_cpu_s();
        wall[sparse].push_back((now_s() - w0) / bp.sequential_steps);
        cpu[sparse].push_back((c1 - c0) / bp.sequential_steps);
        if (sparse) {
          late_cpu.push_back((c1 - c_half) / (bp.sequential_steps - half));
          out.hf_seq_live_share = static_cast<double>(f.live_cells()) /
                                  (static_cast<double>(f.grid().width_px) * f.grid().height_px * p.num_orientations);
          out.hf_seq_dropped_mass = f.dropped_mass();
        }
        if (r == 0) end_belief[sparse] = f.belief();
        if (sparse && r == 0) {
          double nonzero = 0.0;
          for (const cv::Mat& m : end_belief[1].scores) nonzero += cv::countNonZero(m);
          out.hf_seq_nonzero_share = nonzero / (static_cast<double>(f.grid().width_px) * f.grid().height_px * p.num_orientations);
        }
      }
    }
    out.hf_seq_dense_ms = 1e3 * median(wall[0]);
    out.hf_seq_dense_cpu_ms = 1e3 * median(cpu[0]);
    out.hf_seq_sparse_ms = 1e3 * median(wall[1]);
    out.hf_seq_sparse_cpu_ms = 1e3 * median(cpu[1]);
    out.hf_seq_sparse_late_cpu_ms = 1e3 * median(late_cpu);
    out.hf_seq_position_diff_m = 0.0;
    out.hf_seq_yaw_diff_deg = 0.0;
    for (std::size_t k = 0; k < track[0].size() && k < track[1].size(); ++k) {
      out.hf_seq_position_diff_m = std::max(out.hf_seq_position_diff_m, (track[0][k].position_m() - track[1][k].position_m()).norm());
      out.hf_seq_yaw_diff_deg =
          std::max(out.hf_seq_yaw_diff_deg, rad_to_deg(angle_distance_rad(track[0][k].yaw_rad, track[1][k].yaw_rad)));
    }
    // hist_mr on the same walk, against the dense filter's estimates (support kept per step).
    {
      std::vector<TrackEstimate> dense_est;
      {
        HistogramFilterParams p;
        p.odometry = odometry_uncertainty(op);
        p.sparse = false;
        HistogramFilter f(plan, p);
        f.initialise(start, odo.steps[0]);
        for (std::size_t k = 1; k < odo.steps.size(); ++k) {
          f.predict(odo.steps[k]);
          if (k % 10 == 0) f.update(ray->query(observations[k]));
          dense_est.push_back(f.estimate());
        }
      }
      std::vector<double> cpu, late;
      std::vector<TrackEstimate> mr_est;
      for (int r = 0; r < bp.repeats; ++r) {
        MultiResolutionHistogramFilterParams mp;
        mp.filter.odometry = odometry_uncertainty(op);
        if (bp.drop_mass >= 0.0) mp.filter.drop_mass = bp.drop_mass;
        MultiResolutionHistogramFilter f(plan, mp);
        f.initialise(start, odo.steps[0]);
        mr_est.clear();
        const double c0 = process_cpu_s();
        double c_half = c0;
        for (std::size_t k = 1; k < odo.steps.size(); ++k) {
          f.predict(odo.steps[k]);
          if (k % 10 == 0) f.update(ray->query(observations[k]));
          mr_est.push_back(f.estimate());
          if (static_cast<int>(k) == half) c_half = process_cpu_s();
        }
        const double c1 = process_cpu_s();
        cpu.push_back((c1 - c0) / bp.sequential_steps);
        late.push_back((c1 - c_half) / (bp.sequential_steps - half));
      }
      out.hf_seq_mr_cpu_ms = 1e3 * median(cpu);
      out.hf_seq_mr_late_cpu_ms = 1e3 * median(late);
      out.hf_seq_mr_converged_diff_m = 0.0;
      out.hf_seq_dense_converged_steps = 0;
      for (std::size_t k = 0; k < dense_est.size() && k < mr_est.size(); ++k) {
        if (dense_est[k].support < 0.5) continue;
        ++out.hf_seq_dense_converged_steps;
        out.hf_seq_mr_converged_diff_m =
            std::max(out.hf_seq_mr_converged_diff_m, (dense_est[k].pose.position_m() - mr_est[k].pose.position_m()).norm());
      }
      const Vec2 truth = walk.steps.back().T_world_body.position_m();
      out.hf_seq_dense_end_error_m = (dense_est.back().pose.position_m() - truth).norm();
      out.hf_seq_mr_end_error_m = (mr_est.back().pose.position_m() - truth).norm();
    }
    double tv = 0.0;
    for (int s = 0; s < end_belief[0].num_slices(); ++s) {
      tv += cv::norm(end_belief[0].scores[static_cast<std::size_t>(s)], end_belief[1].scores[static_cast<std::size_t>(s)], cv::NORM_L1);
    }
    out.hf_seq_total_variation = 0.5 * tv;
  }
}

}  // namespace

FilterBenchResult bench_filter(const FloorPlan& plan, const FilterBenchParams& bp) {
  const Walk walk = bench_walk(plan, bp.steps, 7);
  OdometryParams op;
  op.model = OdometryModel::kExact;
  const OdometryTrack odo = simulate_odometry(walk, op);
  FilterBenchResult out;
  const Posterior empty = empty_posterior(plan, 36);
  if (bp.particle_filter) {
    std::vector<double> wall, cpu;
    for (int r = 0; r < bp.repeats; ++r) {
      ParticleFilterParams p;
      p.num_particles = bp.particles;
      p.init = ParticleInit::kUniform;
      p.motion_noise = MotionNoiseSource::kFixed;  // PALMS' per-step noise: the measured reference (bench_filter.md)
      p.seed = static_cast<std::uint64_t>(r + 1);
      ParticleFilter f(plan, p);
      f.initialise(empty, odo.steps[0]);
      const double w0 = now_s(), c0 = process_cpu_s();
      for (std::size_t k = 1; k < odo.steps.size(); ++k) f.predict(odo.steps[k]);
      wall.push_back((now_s() - w0) / bp.steps);
      cpu.push_back((process_cpu_s() - c0) / bp.steps);
      out.pf_state_mb = f.state_bytes() / 1e6;
    }
    out.pf_steps_per_s = 1.0 / median(wall);
    out.pf_cpu_ms_per_step = 1e3 * median(cpu);
  }
  if (bp.histogram_filter) {
    // Both histogram filters from a uniform belief with F3Loc's fixed 0.1 m, 0.1 rad kernels (the
    // measured reference, bench_filter.md): median wall and CPU seconds per predicted step.
    auto time_uniform_walk = [&](Tracker& f, double& wall_s, double& cpu_s) {
      f.initialise(empty, odo.steps[0]);
      const double w0 = now_s(), c0 = process_cpu_s();
      for (std::size_t k = 1; k < odo.steps.size(); ++k) {
        f.predict(odo.steps[k]);
        (void)f.estimate();
      }
      wall_s = (now_s() - w0) / bp.steps;
      cpu_s = (process_cpu_s() - c0) / bp.steps;
    };
    HistogramFilterParams p;
    p.init = BeliefInit::kUniform;
    p.motion_noise = MotionNoiseSource::kFixed;
    MultiResolutionHistogramFilterParams mp;
    mp.filter = p;
    std::vector<double> wall(static_cast<std::size_t>(bp.repeats)), cpu(wall.size()), mr_wall(wall.size()), mr_cpu(wall.size());
    for (std::size_t r = 0; r < wall.size(); ++r) {
      HistogramFilter f(plan, p);
      time_uniform_walk(f, wall[r], cpu[r]);
      out.hf_state_mb = f.state_bytes() / 1e6;
      out.grid_cells = f.grid().width_px * f.grid().height_px;
    }
    for (std::size_t r = 0; r < wall.size(); ++r) {
      MultiResolutionHistogramFilter f(plan, mp);
      time_uniform_walk(f, mr_wall[r], mr_cpu[r]);
    }
    out.hf_ms_per_step = 1e3 * median(wall);
    out.hf_cpu_ms_per_step = 1e3 * median(cpu);
    out.hf_mr_ms_per_step = 1e3 * median(mr_wall);
    out.hf_mr_cpu_ms_per_step = 1e3 * median(mr_cpu);
  }
  if (bp.sequential) bench_sequential(plan, bp, walk, out);
  return out;
}

nlohmann::ordered_json to_json(const FilterBenchResult& r) {
  using R = FilterBenchResult;
  constexpr double kAny = 1e300;
  static const FieldList<R> f =
      FieldList<R>("filter bench")
          .number("pf_steps_per_s", &R::pf_steps_per_s, 0.0, kAny, "particle filter steps per second (median, wall)")
          .number("pf_cpu_ms_per_step", &R::pf_cpu_ms_per_step, 0.0, kAny, "particle filter CPU ms per step (all threads)")
          .number("pf_state_mb", &R::pf_state_mb, 0.0, kAny, "particle filter state, MB")
          .number("hf_ms_per_step", &R::hf_ms_per_step, 0.0, kAny, "histogram filter ms per step (median, wall)")
          .number("hf_cpu_ms_per_step", &R::hf_cpu_ms_per_step, 0.0, kAny, "histogram filter CPU ms per step")
          .number("hf_state_mb", &R::hf_state_mb, 0.0, kAny, "histogram filter state, MB")
          .number("hf_mr_ms_per_step", &R::hf_mr_ms_per_step, 0.0, kAny, "hist_mr, the same uniform start and walk: ms per step (median, wall)")
          .number("hf_mr_cpu_ms_per_step", &R::hf_mr_cpu_ms_per_step, 0.0, kAny, "hist_mr: CPU ms per step")
          .integer("hf_grid_cells", &R::grid_cells, 0, 1 << 30, "histogram filter (x, y) cells")
          .number("pf_update_full_cpu_s", &R::pf_update_full_cpu_s, 0.0, kAny,
                  "particle filter: CPU s per measurement update from the kernel's full posterior (matching included)")
          .number("pf_update_points_cpu_s", &R::pf_update_points_cpu_s, 0.0, kAny,
                  "particle filter: CPU s per measurement update from the kernel's point queries (matching included)")
          .number("hf_seq_dense_ms", &R::hf_seq_dense_ms, 0.0, kAny, "histogram filter, sequential setting, dense: ms per step (wall)")
          .number("hf_seq_dense_cpu_ms", &R::hf_seq_dense_cpu_ms, 0.0, kAny, "the same, CPU ms per step")
          .number("hf_seq_sparse_ms", &R::hf_seq_sparse_ms, 0.0, kAny, "histogram filter, sequential setting, sparse: ms per step (wall)")
          .number("hf_seq_sparse_cpu_ms", &R::hf_seq_sparse_cpu_ms, 0.0, kAny, "the same, CPU ms per step")
          .number("hf_seq_sparse_late_cpu_ms", &R::hf_seq_sparse_late_cpu_ms, 0.0, kAny,
                  "the same over the walk's second half (after the first observations)")
          .number("hf_seq_live_share", &R::hf_seq_live_share, 0.0, 1.0, "sparse filter's live cells at the end, share of cells x directions")
          .number("hf_seq_nonzero_share", &R::hf_seq_nonzero_share, 0.0, 1.0,
                  "sparse filter's non-zero cells at the end, share of cells x directions (live cells: the spans around them)")
          .number("hf_seq_dropped_mass", &R::hf_seq_dropped_mass, 0.0, kAny, "sparse filter's dropped mass over the walk (drop_mass, accounted)")
          .number("hf_seq_position_diff_m", &R::hf_seq_position_diff_m, 0.0, kAny, "largest distance between the dense and sparse estimates, m")
          .number("hf_seq_yaw_diff_deg", &R::hf_seq_yaw_diff_deg, 0.0, 180.0, "largest heading difference between them, deg")
          .number("hf_seq_total_variation", &R::hf_seq_total_variation, 0.0, 1.0, "total variation between the dense and sparse beliefs at the end")
          .number("hf_seq_mr_cpu_ms", &R::hf_seq_mr_cpu_ms, 0.0, kAny, "hist_mr (coarse over the plan, fine window), same walk: CPU ms per step")
          .number("hf_seq_mr_late_cpu_ms", &R::hf_seq_mr_late_cpu_ms, 0.0, kAny, "the same over the walk's second half")
          .number("hf_seq_mr_converged_diff_m", &R::hf_seq_mr_converged_diff_m, 0.0, kAny,
                  "largest distance between the hist_mr and dense estimates at steps where the dense filter has converged, m")
          .integer("hf_seq_dense_converged_steps", &R::hf_seq_dense_converged_steps, 0, 1000000, "steps where the dense filter has converged (support >= 0.5)")
          .number("hf_seq_dense_end_error_m", &R::hf_seq_dense_end_error_m, 0.0, kAny, "dense filter's distance to the truth at the end, m")
          .number("hf_seq_mr_end_error_m", &R::hf_seq_mr_end_error_m, 0.0, kAny, "hist_mr's distance to the truth at the end, m")
          .number("pf_seq_steps_per_s", &R::pf_seq_steps_per_s, 0.0, kAny,
                  "particle filter end to end on the sequential walk (kernel point-query updates every 10 steps): steps/s, wall")
          .number("pf_seq_cpu_ms", &R::pf_seq_cpu_ms, 0.0, kAny, "the same, CPU ms per step");
  return f.write(r);
}

}  // namespace floorcast
