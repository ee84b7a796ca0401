// `floorcast bench match`: layout-matcher cost on one plan, every number measured in one run on
// the same seeded perfect observations (medians; CPU seconds of the whole process, i.e. summed
// over threads, and wall seconds):
//   - kernel matcher at O orientations (the candidates padded to O, PALMS+ O = 10) x its scales:
//     the exact branch-and-bound estimate + top-K, the estimate alone, the full FFT posterior,
//     and the FFT floor (O x S full-size FFTW r2c + c2r pairs on the correlator's transform
//     size, the least an exhaustive FFT posterior can cost), with per-observation ratios and the
//     modes of both compared (bench/modes_equivalence.hpp);
//   - ray matcher per direction count: precompute time and memory, modes, max-over-yaw and
//     full posterior;
//   - BEV matcher with and without semantics: precompute time and memory, the bounded estimate +
//     top-K beside the exhaustive one (full posterior + top-K) per field of view (one perspective
//     view, the full circle), on BEVs of the plan's truth at the sampled poses shaped by the
//     predictor's structured3d_good spreads and masses (no class confusion).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "floorcast/bench/modes_equivalence.hpp"
#include "floorcast/floorplans/floor_plan.hpp"

namespace floorcast {

struct MatchBenchParams {
  int observations = 10;
  std::uint64_t seed = 1;
  int kernel_orientations = 10;  ///< candidates padded to this many (0: the matcher's own)
  int top_k = 5;
  bool kernel = true;
  /// Also time the full posteriors (the kernel's FFT posterior, the ray matcher's slices).
  bool posteriors = true;
  std::vector<int> ray_directions = {36, 180};
  int ray_precompute_repeats = 1;
  int ray_volume_bits = 16;  ///< RayMatcherParams::volume_bits
  /// BEV matcher: fields of view of its observations, degrees (360: the full circle; empty: skip).
  std::vector<double> bev_fov_deg = {60.0, 360.0};
  double bev_resolution_m = 0.1;  ///< BevMatcherParams::resolution_m
  /// Where the kernel and ray matchers' observers stand: "uniform" (any valid cell) or
  /// "transitional" (cells in rooms of the transitional kinds with 0.5 m clearance, the scenarios'
  /// default protocol: corridors, where the ray matcher's bounds prune least).
  std::string region = "uniform";
};

/// CPU (process, all threads) and wall seconds of one call: medians over the observations.
struct MatchBenchCost {
  double cpu_s = 0.0;
  double wall_s = 0.0;
};

/// The kernel matcher's measurements (keys documented in results/bench_match.md).
struct KernelMatchBench {
  double orientations = 0.0;  ///< median candidates per observation after padding (O)
  int scales = 0;
  MatchBenchCost modes;   ///< exact estimate + top-K (branch and bound)
  MatchBenchCost argmax;  ///< exact estimate alone
  double own_candidates = 0.0;          ///< median of the matcher's own PALMS+ candidates
  MatchBenchCost modes_own_candidates;  ///< estimate + top-K with its own candidates
  double precompute_wall_s = 0.0;
  double precompute_mb = 0.0;
  double search_maps_mb = 0.0;
  int fft_cols = 0;
  int fft_rows = 0;
  double fft_pair_cpu_s = 0.0;   ///< one full-size r2c + c2r pair
  double fft_floor_cpu_s = 0.0;  ///< O x S pairs: the least an exhaustive FFT posterior costs
  nlohmann::ordered_json search_counters = nlohmann::ordered_json::object();     ///< medians
  nlohmann::ordered_json modes_stages_cpu_s = nlohmann::ordered_json::object();  ///< medians
  bool posteriors = false;  ///< the fields below were measured
  MatchBenchCost posterior;
  double posterior_over_modes = 0.0;  ///< median per-observation ratio
  double posterior_over_floor = 0.0;
  nlohmann::ordered_json posterior_stages_cpu_s = nlohmann::ordered_json::object();
  double posterior_mb = 0.0;
  ModesEquivalenceResult equivalence;  ///< the search's modes against the posterior's
  double fft_max_abs_error = 0.0;
};

/// The ray matcher's measurements at one direction count.
struct RayMatchBench {
  int directions = 0;
  double precompute_s = 0.0;  ///< median over --precompute-repeats
  double volume_mb = 0.0;
  int valid_cells = 0;
  MatchBenchCost modes;             ///< bounded estimate + top-K
  MatchBenchCost modes_exhaustive;  ///< exhaustive estimate + top-K on the same volume
  double exhaustive_over_bounded = 0.0;
  int bounded_modes_identical = 0;  ///< observations whose top-K lists are identical
  double cells_scored_share = 0.0;  ///< median share of cells the bounded search scored
  MatchBenchCost max_over_yaw;
  nlohmann::ordered_json stages_cpu_s = nlohmann::ordered_json::object();
  nlohmann::ordered_json search_counters = nlohmann::ordered_json::object();
  bool posteriors = false;
  MatchBenchCost posterior;
  double posterior_mb = 0.0;
  int same_estimate_as_posterior = 0;
};

/// The BEV matcher at one field of view.
struct BevViewBench {
  double fov_deg = 0.0;
  int columns = 0;
  MatchBenchCost modes;
  MatchBenchCost modes_exhaustive;
  double exhaustive_over_bounded = 0.0;
  int bounded_modes_identical = 0;
  double cells_scored_share = 0.0;  ///< cell-orientation pairs scored by the bounded search
  nlohmann::ordered_json stages_cpu_s = nlohmann::ordered_json::object();
  nlohmann::ordered_json search_counters = nlohmann::ordered_json::object();
  bool posteriors = false;
  MatchBenchCost posterior;
  double posterior_mb = 0.0;
};

/// The BEV matcher with or without semantics.
struct BevMatchBench {
  bool semantics = true;
  double precompute_wall_s = 0.0;
  double precompute_mb = 0.0;
  int valid_cells = 0;
  int directions = 0;
  int orientations = 0;
  std::vector<BevViewBench> views;
};

/// One plan's `bench match` (written by to_json, read back by read_match_bench).
struct MatchBenchResult {
  std::string plan;
  int threads = 0;
  int observations = 0;
  std::string region;  ///< MatchBenchParams::region
  int top_k = 0;
  bool kernel_measured = false;
  int grid_width_px = 0;   ///< the kernel matcher's grid (0.1 m)
  int grid_height_px = 0;
  int valid_cells = 0;
  KernelMatchBench kernel;
  std::vector<RayMatchBench> ray;
  std::vector<BevMatchBench> bev;
};

/// Medians and same-run ratios, measured on seeded perfect observations.
MatchBenchResult bench_match(const FloorPlan& plan, const MatchBenchParams& params);

nlohmann::ordered_json to_json(const MatchBenchResult& result);
/// Reads what to_json wrote (`bench match --json` of one plan); errors name `source` and the key.
MatchBenchResult read_match_bench(const nlohmann::json& j, const std::string& source);

/// The candidates padded to exactly n yaws (PALMS+ O = 10): clean observations of a Manhattan
/// plan give only 4 candidates with a positive histogram correlation; benches time the paper's
/// O = 10 by adding yaws of a 36-step grid away from the ones present.
std::vector<double> pad_yaws(std::vector<double> yaws, std::size_t n);

}  // namespace floorcast
