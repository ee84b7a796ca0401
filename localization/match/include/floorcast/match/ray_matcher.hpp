// The F3Loc ray-tracing matcher: a precomputed distance volume (desdf) per grid cell and world
// direction, compared with the observation's ranges along D equiangular rays:
//
//   score(cell, o) = exp(-L1(cell, o) / lambda),
//   L1(cell, o)    = sum_i | min(V[cell][(o + i) mod D], c) - min(r_i, c) |,
//
// where slice o is the observer's world yaw 2 pi o / D, ray i points at 2 pi i / D in the observer
// frame (so at world direction o + i: the circular padding of F3Loc's localize()), c is the
// clipping range (10 m) and lambda = 40 with L1 in metres, as F3Loc (its desdf and rays are in
// metres: generate_desdf.py returns desdf * resolution; localize(..., lambd=40)).
#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "floorcast/core/params.hpp"
#include "floorcast/match/distance_volume.hpp"
#include "floorcast/match/matcher.hpp"

namespace floorcast {

/// Where the ray matcher takes the observation's rays from.
enum class RaySource { kAuto, kRanges, kSegments };

/// How the estimate and top-K modes are found (MatchOutput::kModes; the max-over-yaw map and the
/// posterior always score every cell).
enum class RaySearch {
  /// Exact best-first search: a lower bound of every cell's L1 over all orientations (the sorted
  /// observation rays against the cell's sorted distances, which no rotation can beat) orders
  /// runs of cells, which are scored exactly in that order until no unscored cell can reach the
  /// next mode. Same modes, scores and tie order as kExhaustive, bit for bit.
  kBounded,
  /// Score every stored cell at every orientation (the reference).
  kExhaustive,
};

struct RayMatcherParams {
  /// Grid resolution of the volume (F3Loc: 0.1 m desdf).
  double resolution_m = 0.1;
  double grid_margin_m = 1.0;
  /// Directions of the volume = rays of the observation (F3Loc: 36 orientations, 10 deg; the
  /// ray spacing equals the direction-bin width). PALMS+ sec. 4.4 also runs 180.
  int num_directions = 36;
  /// Clipping range (F3Loc clips the desdf to 10 m when loading it; PALMS+ sec. 4.4: 10 m).
  double max_range_m = 10.0;
  /// Likelihood temperature, metres of summed absolute range error (F3Loc: lambd = 40).
  double lambda_m = 40.0;
  /// Where the observation's rays come from: auto (its ray_ranges_m when there are exactly
  /// num_directions of them, else cast against its segments), ranges or segments.
  RaySource ray_source = RaySource::kAuto;
  /// How the modes are found: bounded (exact best-first search) or exhaustive.
  RaySearch search = RaySearch::kBounded;
  /// Bits per stored distance: 16 (millimetres) or 8 (10 m in 40 mm steps, rounded; half the
  /// memory; rays are quantised the same way; measured effect: results/bench_match.md).
  int volume_bits = 16;
  /// What blocks a ray in the plan (keys doors_closed, glass_blocks, obstacles_block,
  /// cut_height_m; PALMS+ sec. 4.4: all doors closed).
  BlockingOptions blocking = closed_door_map();

  /// Takes the experiment's shared range and blocking flags (max_range_m, blocking).
  void apply_shared(const SharedParams& shared);
  nlohmann::ordered_json to_json() const;
  void apply_overrides(const nlohmann::json& overrides);
};

class RayMatcher final : public Matcher {
 public:
  /// Computes the distance volume (the per-plan precomputation).
  RayMatcher(const FloorPlan& plan, const RayMatcherParams& params = {});
  /// Uses a volume computed earlier for this plan and these parameters (e.g. read from a cache
  /// by the caller: distance_volume_io.hpp); throws InputError when its grid, direction count
  /// or range do not match the parameters.
  RayMatcher(const FloorPlan& plan, const RayMatcherParams& params, DistanceVolume volume);
  /// Shares `other`'s precomputation (no copy) with other parameters: lambda_m, ray_source or
  /// search may differ; throws InputError when the volume's parameters (resolution, margin,
  /// directions, range, bits, blocking) differ.
  RayMatcher(const RayMatcher& other, const RayMatcherParams& params);
  ~RayMatcher() override;

  std::string name() const override { return "ray"; }
  nlohmann::ordered_json parameters() const override { return params_.to_json(); }
  double precompute_s() const override { return precompute_s_; }
  std::size_t precompute_bytes() const override { return pre_->volume.bytes() + pre_->rank_codes.size(); }
  BlockingOptions blocking() const override { return params_.blocking; }
  using Matcher::match;
  MatchResult match(const Observation2D& observation, const MatchRequest& request) const override;

  /// The observation's rays (metres, ray i at 2 pi i / D), as match() uses them.
  std::vector<double> observation_rays(const Observation2D& observation) const;

  /// Per stored cell, a lower bound (mm) of its L1 at every orientation, as the bounded search
  /// uses it (exposed for tests and analyses).
  std::vector<std::int32_t> lower_bounds_mm(const Observation2D& observation) const;

  const DistanceVolume& volume() const { return pre_->volume; }
  const GridSpec& grid() const { return pre_->volume.grid; }
  const RayMatcherParams& params() const { return params_; }

  /// The volume the matcher precomputes for a plan (what the first constructor computes).
  static DistanceVolume compute_volume(const FloorPlan& plan, const RayMatcherParams& params);
  /// Identity of that volume (plan hash and the parameters it depends on), as a cache key.
  static std::string volume_key(const FloorPlan& plan, const RayMatcherParams& params);

 private:
  /// The estimate, top-K modes and (if asked) the max-over-yaw map without the full posterior.
  void match_modes(const std::vector<std::uint16_t>& rays_mm, std::uint16_t clip_mm, bool clip, int block,
                   const MatchRequest& request, MatchResult& result) const;
  struct RankTables {
    std::vector<std::int32_t> lo, hi;  ///< per rank block j: [j * 256 + bin]
  };
  RankTables rank_tables(const std::vector<std::uint16_t>& rays_mm, int top_mm) const;
  /// lb[0..n) = lower bounds (mm) of stored cells first..first+n-1.
  void rank_bounds(const RankTables& tables, std::size_t first, int n, std::int32_t* lb) const;
  /// The observation's rays and clipping range in the volume's units.
  struct RayUnits {
    std::vector<std::uint16_t> rays;
    std::uint16_t clip = 0;
    bool clipped = false;  ///< clip below the volume's range
  };
  RayUnits ray_units(const Observation2D& observation) const;
  RayMatcherParams params_;
  /// The per-plan precomputation: volume, row index, runs and rank bounds. Shared (read-only)
  /// by matchers built from one another (same volume, other lambda or search).
  struct Precomputed {
    DistanceVolume volume;
    std::vector<std::int64_t> row_start;  ///< first stored cell of each grid row, plus the end
    /// Runs of at most kRunCells consecutive stored cells of one grid row (first cell, count):
    /// the unit the bounded search scores.
    std::vector<std::pair<std::int64_t, int>> runs;
    /// Rank bounds of every stored cell's sorted distances: for j = 0..rank_count, the 8-bit bin
    /// (width rank_bin, in the volume's units) of the distance of rank min(j * rank_step, D - 1),
    /// at rank_codes[j * N + cell].
    std::vector<std::uint8_t> rank_codes;
    int rank_step = 1;
    int rank_count = 0;
    int rank_bin = 1;
  };
  static std::shared_ptr<const Precomputed> index_volume(DistanceVolume volume);
  std::shared_ptr<const Precomputed> pre_;
  double precompute_s_ = 0.0;
};

/// Reference scores of one cell (slow, obvious): exp(-L1/lambda) for every slice.
std::vector<double> ray_scores_reference(const DistanceVolume& volume, std::size_t cell,
                                         const std::vector<double>& rays_m, double clip_m, double lambda_m);

}  // namespace floorcast
