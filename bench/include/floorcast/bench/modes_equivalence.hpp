// The kernel matcher's exact branch-and-bound modes against the exhaustive FFT posterior's
// (Posterior::top_k), on seeded perfect observations: the workload of the equivalence test
// (tests/match/test_kernel_search.cpp) and of `floorcast bench match --equivalence`.
//
// Two mode lists agree when they are identical (same slice, row and column, in order), or
// identical up to the first position k where the picks differ and the search's pick is at least as
// good in exact values (max over scales of KernelMatcher::cell_score, a direct sum) and either
//   - tied with the posterior's (exact values within exact_tolerance: the same sum in another
//     order, e.g. a mirror-symmetric place), or
//   - ahead of it by no more than the FFT's own errors at the two cells (|posterior value - exact|
//     summed): the single-precision posterior cannot order values that close.
// Past position k the lists legitimately diverge (the suppression differs). Anything else is a
// mismatch, and so is a search score that differs from the direct sum by more than
// exact_tolerance.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "floorcast/core/types.hpp"
#include "floorcast/floorplans/floor_plan.hpp"
#include "floorcast/match/kernel_matcher.hpp"

namespace floorcast {

template <class T>
class FieldList;

struct ModesEquivalenceParams {
  int observations = 100;
  std::uint64_t seed = 1;
  int top_k = 5;
  /// Float round-off of the search's and the direct sums: values closer than this are ties.
  double exact_tolerance = 1e-6;
  /// Observation range (the matcher's max_range_m should match it).
  double max_range_m = 10.0;
};

struct ModesEquivalenceResult {
  int observations = 0;
  int estimates_identical = 0;  ///< same estimate cell and slice (or both no pose)
  int estimates_tied = 0;       ///< different picks of tied exact value
  int estimates_fft_order = 0;  ///< different picks ordered differently by the FFT's round-off
  int fft_order_differences = 0;  ///< lists that diverge at such a pick (any position)
  int top_k_identical = 0;      ///< whole lists identical
  int top_k_tied = 0;           ///< identical up to a tie or an FFT-order difference
  int no_pose = 0;              ///< observations both found no pose for
  int mismatches = 0;
  double max_tie_gap = 0.0;        ///< largest exact-value gap among ties
  double max_fft_order_gap = 0.0;  ///< largest exact-value gap the FFT's round-off reordered
  double max_search_error = 0.0;   ///< largest |search score - direct sum|
  double max_fft_error = 0.0;      ///< largest |posterior value - direct sum| at compared picks
  std::vector<std::string> failures;  ///< one line per mismatch
  std::vector<double> search_s;       ///< wall seconds per observation (estimate + top-K)
  std::vector<double> posterior_s;    ///< wall seconds per observation (FFT posterior + top_k)
};

/// Uniform seeded poses over a valid area (CV_8U mask on `grid`, non-zero = valid), any yaw.
std::vector<Pose2> sample_valid_poses(const cv::Mat& valid, const GridSpec& grid, int count, std::uint64_t seed);
/// The same over the matcher's valid area.
std::vector<Pose2> sample_valid_poses(const KernelMatcher& matcher, int count, std::uint64_t seed);

/// Compares one observation's search modes (`search`, MatchOutput::kModes) with its posterior's
/// (`posterior`, MatchOutput::kPosterior, same yaws) and adds the outcome to `out`.
void compare_modes(const KernelMatcher& matcher, const Observation2D& observation, const MatchResult& search,
                   const MatchResult& posterior, const ModesEquivalenceParams& params, const std::string& label,
                   ModesEquivalenceResult& out);

/// Seeded perfect observations (sample_valid_poses) matched both ways with the matcher's own
/// orientation candidates; wall times of both.
ModesEquivalenceResult compare_modes_with_posterior(const FloorPlan& plan, const KernelMatcher& matcher,
                                                    const ModesEquivalenceParams& params);

nlohmann::ordered_json to_json(const ModesEquivalenceResult& result);
/// Its field list (written by to_json; a record of it reads back with the wall-time series as
/// their medians).
const FieldList<ModesEquivalenceResult>& modes_equivalence_fields();

}  // namespace floorcast
