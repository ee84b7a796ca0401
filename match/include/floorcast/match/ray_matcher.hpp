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

#include "floorcast/match/distance_volume.hpp"
#include "floorcast/match/matcher.hpp"

namespace floorcast {

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
  /// Where the observation's rays come from: "auto" (its ray_ranges_m when there are exactly
  /// num_directions of them, else cast against its segments), "ranges" or "segments".
  std::string ray_source = "auto";
  /// What blocks a ray in the plan (PALMS+ sec. 4.4: all doors closed).
  bool doors_closed = true;
  bool glass_blocks = true;
  bool obstacles_block = false;
  double cut_height_m = 1.5;
  /// Directory of the on-disk volume cache (keyed by plan hash and these parameters); empty =
  /// no cache.
  std::string cache_dir;

  nlohmann::ordered_json to_json() const;
  void apply_overrides(const nlohmann::json& overrides);
};

class RayMatcher final : public Matcher {
 public:
  RayMatcher(const FloorPlan& plan, const RayMatcherParams& params = {});
  ~RayMatcher() override;

  std::string name() const override { return "ray"; }
  nlohmann::ordered_json parameters() const override { return params_.to_json(); }
  double precompute_s() const override { return precompute_s_; }
  std::size_t precompute_bytes() const override { return volume_.bytes(); }
  MatchResult match(const Observation2D& observation) const override;

  /// The observation's rays (metres, ray i at 2 pi i / D), as match() uses them.
  std::vector<double> observation_rays(const Observation2D& observation) const;

  const DistanceVolume& volume() const { return volume_; }
  const GridSpec& grid() const { return volume_.grid; }
  const RayMatcherParams& params() const { return params_; }
  /// True when the volume came from the disk cache.
  bool loaded_from_cache() const { return from_cache_; }

 private:
  RayMatcherParams params_;
  DistanceVolume volume_;
  std::vector<std::int64_t> row_start_;  ///< first stored cell of each grid row, plus the end
  double precompute_s_ = 0.0;
  bool from_cache_ = false;
};

/// Reference scores of one cell (slow, obvious): exp(-L1/lambda) for every slice.
std::vector<double> ray_scores_reference(const DistanceVolume& volume, std::size_t cell,
                                         const std::vector<double>& rays_m, double clip_m, double lambda_m);

}  // namespace floorcast
