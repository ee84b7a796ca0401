#include "floorcast/bench/filter_bench.hpp"

#include "floorcast/core/fields.hpp"

#include <chrono>
#include <vector>

#include "floorcast/core/math.hpp"
#include "floorcast/core/timing.hpp"
#include "floorcast/floorplans/raster.hpp"
#include "floorcast/sim/odometry.hpp"
#include "floorcast/sim/walk.hpp"
#include "floorcast/track/histogram_filter.hpp"
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

}  // namespace

FilterBenchResult bench_filter(const FloorPlan& plan, const FilterBenchParams& bp) {
  WalkParams wp;
  wp.steps = bp.steps + 1;
  wp.seed = 7;
  const Walk walk = simulate_walk(plan, random_start_pose(plan, wp), wp);
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
    std::vector<double> wall, cpu;
    for (int r = 0; r < bp.repeats; ++r) {
      HistogramFilterParams p;
      p.init = BeliefInit::kUniform;
      p.motion_noise = MotionNoiseSource::kFixed;  // F3Loc's 0.1 m, 0.1 rad kernels: the measured reference (bench_filter.md)
      HistogramFilter f(plan, p);
      f.initialise(empty, odo.steps[0]);
      const double w0 = now_s(), c0 = process_cpu_s();
      for (std::size_t k = 1; k < odo.steps.size(); ++k) {
        f.predict(odo.steps[k]);
        (void)f.estimate();
      }
      wall.push_back((now_s() - w0) / bp.steps);
      cpu.push_back((process_cpu_s() - c0) / bp.steps);
      out.hf_state_mb = f.state_bytes() / 1e6;
      out.grid_cells = f.grid().width_px * f.grid().height_px;
    }
    out.hf_ms_per_step = 1e3 * median(wall);
    out.hf_cpu_ms_per_step = 1e3 * median(cpu);
  }
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
          .integer("hf_grid_cells", &R::grid_cells, 0, 1 << 30, "histogram filter (x, y) cells");
  return f.write(r);
}

}  // namespace floorcast
