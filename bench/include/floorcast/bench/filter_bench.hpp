// `floorcast bench filter`: tracker throughput on a shipped building. A walk of the building
// (sim), exact odometry; the particle filter started uniformly over the building (every particle
// live, walls checked on every move), the histogram filter from a uniform belief (the densest
// case). Medians over repeats; wall and process-CPU time.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "floorcast/floorplans/floor_plan.hpp"

namespace floorcast {

struct FilterBenchParams {
  int steps = 60;             ///< predicted steps per repeat
  int repeats = 3;
  int particles = 2000;       ///< PALMS
  bool particle_filter = true;
  bool histogram_filter = true;
};

struct FilterBenchResult {
  double pf_steps_per_s = 0.0;      ///< median over repeats, wall time
  double pf_cpu_ms_per_step = 0.0;  ///< median, process CPU (all threads)
  double hf_ms_per_step = 0.0;      ///< median, wall
  double hf_cpu_ms_per_step = 0.0;
  double hf_state_mb = 0.0;
  double pf_state_mb = 0.0;
  int grid_cells = 0;               ///< histogram-filter grid (x, y) cells
};

FilterBenchResult bench_filter(const FloorPlan& plan, const FilterBenchParams& params);

nlohmann::ordered_json to_json(const FilterBenchResult& result);

}  // namespace floorcast
