// `floorcast bench filter`: tracker throughput on a shipped building. A walk of the building
// (sim), exact odometry; the particle filter started uniformly over the building (every particle
// live, walls checked on every move), the histogram filter from a uniform belief (the densest
// case). Then the sequential setting, each way measured in the same run: the particle filter's
// measurement update from the kernel matcher's full posterior against its point queries, and the
// histogram filter on a VIO walk from the ray posterior of a perfect first observation with an
// observation every 10 steps (F3Loc's sequential setting), dense (every cell, full posteriors)
// against sparse (the cells holding belief, point queries). Medians over repeats; wall and
// process-CPU time.
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
  bool sequential = true;     ///< the measurement-update and sparse-filter comparisons
  int sequential_steps = 60;  ///< steps of the sequential histogram-filter walk
  double drop_mass = -1.0;    ///< the sparse histogram filter's drop_mass (< 0: its default)
};

struct FilterBenchResult {
  double pf_steps_per_s = 0.0;      ///< median over repeats, wall time
  double pf_cpu_ms_per_step = 0.0;  ///< median, process CPU (all threads)
  double hf_ms_per_step = 0.0;      ///< median, wall
  double hf_cpu_ms_per_step = 0.0;
  double hf_state_mb = 0.0;
  /// hist_mr (its defaults) on the same uniform start and walk: a flat belief stays on its coarse
  /// grid (no window holds half of it).
  double hf_mr_ms_per_step = 0.0;      ///< median, wall
  double hf_mr_cpu_ms_per_step = 0.0;
  double pf_state_mb = 0.0;
  int grid_cells = 0;               ///< histogram-filter grid (x, y) cells
  /// Particle-filter measurement update (kernel matcher, PALMS start at a perfect observation),
  /// CPU s per update including the matcher's work: from the full posterior, and from point
  /// queries.
  double pf_update_full_cpu_s = 0.0;
  double pf_update_points_cpu_s = 0.0;
  /// Histogram filter in the sequential setting: ms per step (wall and CPU, matching included),
  /// dense and sparse, the sparse filter's live cells at the end (share of the grid x
  /// directions), and whether both tracks were the same to the last bit.
  double hf_seq_dense_ms = 0.0;
  double hf_seq_dense_cpu_ms = 0.0;
  double hf_seq_sparse_ms = 0.0;
  double hf_seq_sparse_cpu_ms = 0.0;
  double hf_seq_sparse_late_cpu_ms = 0.0;  ///< sparse, CPU ms per step over the walk's second half
  double hf_seq_live_share = 0.0;
  double hf_seq_nonzero_share = 0.0;  ///< the sparse belief's non-zero cells at the end (the spans cover more)
  /// Sparse against dense: the sparse filter's accounted dropped mass (drop_mass), the largest
  /// position and heading differences between the two tracks, and the total variation between
  /// the two beliefs at the end.
  double hf_seq_dropped_mass = 0.0;
  double hf_seq_position_diff_m = 0.0;
  double hf_seq_yaw_diff_deg = 0.0;
  double hf_seq_total_variation = 0.0;
  /// hist_mr (coarse belief over the plan, fine window; its defaults) on the same walk: CPU ms
  /// per step, over the second half, and its estimates against the dense filter's (largest
  /// distance where the dense filter has converged, support >= 0.5; end errors against the truth).
  double hf_seq_mr_cpu_ms = 0.0;
  double hf_seq_mr_late_cpu_ms = 0.0;
  double hf_seq_mr_converged_diff_m = 0.0;
  int hf_seq_dense_converged_steps = 0;
  double hf_seq_dense_end_error_m = 0.0;
  double hf_seq_mr_end_error_m = 0.0;
  /// Particle filter end to end on the same walk (PALMS start, kernel point-query updates every
  /// 10 steps, observations included): steps per second (wall) and CPU ms per step.
  double pf_seq_steps_per_s = 0.0;
  double pf_seq_cpu_ms = 0.0;
};

FilterBenchResult bench_filter(const FloorPlan& plan, const FilterBenchParams& params);

nlohmann::ordered_json to_json(const FilterBenchResult& result);

}  // namespace floorcast
