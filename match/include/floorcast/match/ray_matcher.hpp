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
  ~RayMatcher() override;

  std::string name() const override { return "ray"; }
  nlohmann::ordered_json parameters() const override { return params_.to_json(); }
  double precompute_s() const override { return precompute_s_; }
  std::size_t precompute_bytes() const override { return volume_.bytes(); }
  BlockingOptions blocking() const override { return params_.blocking; }
  using Matcher::match;
  MatchResult match(const Observation2D& observation, const MatchRequest& request) const override;

  /// The observation's rays (metres, ray i at 2 pi i / D), as match() uses them.
  std::vector<double> observation_rays(const Observation2D& observation) const;

  const DistanceVolume& volume() const { return volume_; }
  const GridSpec& grid() const { return volume_.grid; }
  const RayMatcherParams& params() const { return params_; }

  /// The volume the matcher precomputes for a plan (what the first constructor computes).
  static DistanceVolume compute_volume(const FloorPlan& plan, const RayMatcherParams& params);
  /// Identity of that volume (plan hash and the parameters it depends on), as a cache key.
  static std::string volume_key(const FloorPlan& plan, const RayMatcherParams& params);

 private:
  /// The estimate, top-K modes and (if asked) the max-over-yaw map without the full posterior.
  void match_modes(const std::vector<std::uint16_t>& rays_mm, std::uint16_t clip_mm, bool clip, int block,
                   const MatchRequest& request, MatchResult& result) const;
  void index_rows();
  RayMatcherParams params_;
  DistanceVolume volume_;
  std::vector<std::int64_t> row_start_;  ///< first stored cell of each grid row, plus the end
  double precompute_s_ = 0.0;
};

/// Reference scores of one cell (slow, obvious): exp(-L1/lambda) for every slice.
std::vector<double> ray_scores_reference(const DistanceVolume& volume, std::size_t cell,
                                         const std::vector<double>& rays_m, double clip_m, double lambda_m);

}  // namespace floorcast
