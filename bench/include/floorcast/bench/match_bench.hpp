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
#include <vector>

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
};

/// Medians and same-run ratios as JSON (keys documented in results/bench_match.md).
nlohmann::ordered_json bench_match(const FloorPlan& plan, const MatchBenchParams& params);

/// The candidates padded to exactly n yaws (PALMS+ O = 10): clean observations of a Manhattan
/// plan give only 4 candidates with a positive histogram correlation; benches time the paper's
/// O = 10 by adding yaws of a 36-step grid away from the ones present.
std::vector<double> pad_yaws(std::vector<double> yaws, std::size_t n);

}  // namespace floorcast
