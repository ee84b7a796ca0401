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

#include "floorcast/core/fields.hpp"
#include "floorcast/core/params.hpp"
#include "floorcast/match/distance_volume.hpp"
#include "floorcast/match/matcher.hpp"

namespace floorcast {

/// Where the ray matcher takes the observation's rays from.
enum class RaySource { kAuto, kRanges, kSegments };

/// How the estimate and top-K modes are found (MatchOutput::kModes; the max-over-yaw map and the
/// posterior always score every cell).
enum class RaySearch {
  /// Exact best-first search, coarse to fine: a lower bound of every cell's L1 over all
  /// orientations (the sorted observation rays against the cell's sorted distances, which no
  /// rotation can beat) orders runs of cells; from 72 directions on, the runs it cannot rule out
  /// get a bound per group of orientations (each ray against the min-max interval of the
  /// directions it can meet within the group), and are scored exactly in that order, each only at
  /// the groups that can still hold a cell's best, until no unscored cell can reach the next mode.
  /// Same modes, scores and tie order as kExhaustive, bit for bit.
  kBounded,
  /// Score every stored cell at every orientation (the reference).
  kExhaustive,
};

/// Where each cell's distances are cast from and its pose is reported.
enum class RayCastPoint {
  kCentre,  ///< the cell centre
  kCorner,  ///< the cell's corner (lowest x and y), as F3Loc: raycast_desdf casts cell (row, col)
            ///< from occupancy pixel [row, col] * ratio, and its evaluation reports pose_pred * 0.1
};

/// How the distance volume is computed.
enum class RayDistances {
  kExact,   ///< exact 2D distances to the plan's wall surfaces (z-buffered parallelograms)
  kRaster,  ///< F3Loc: a march through a fine occupancy image (raster_resolution_m; F3Loc 0.01 m/px)
};

/// How the observation's rays are handed to the score: their order and which ray is the heading.
/// All but kFloorcast run F3Loc's localize() arithmetic literally on a ray array `given` (V rays,
/// left to right): it flips them (then counter-clockwise), pads the volume circularly by V//2 in
/// front, and compares flipped ray k with direction o - V//2 + k, so slice o is the heading of the
/// ray that lands at flipped index V//2, i.e. given index V - 1 - V//2 (V//2 for odd V, V//2 - 1
/// for even V). With b the ray bin width, given[k] holds the observed ray at relative angle:
enum class RayConvention {
  kFloorcast,    ///< (not localize()) ray i at 2 pi i / D from the heading compared with direction o + i
  kF3Loc,        ///< (V - 1 - V//2 - k) b: left to right, heading where localize() expects it (correct)
  kOneBinOff,    ///< (V//2 - k) b: heading at index V//2 as localize()'s docstring suggests; for even
                 ///< V (36 rays over 360 deg) every heading comes out one bin (10 deg) off
  kMirrored,     ///< (k - (V - 1 - V//2)) b: rays handed over counter-clockwise; localize() flips them
                 ///< again, so the observation is matched mirror-imaged
  kHeadingRay0,  ///< -k b: left to right but starting at the heading (ray 0 = heading), as a caster
                 ///< going clockwise from the heading produces them
};

/// Which grid cells are scored.
enum class RayCells {
  kValid,  ///< the plan's valid area minus blocked cells (matcher_valid_mask)
  kAll,    ///< every cell of the grid, walls and outside included (F3Loc: argmax over the whole map;
           ///< a cell whose cast point is blocked sees 0 m in every direction)
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

  // Paper-faithful variants (defaults: floorcast's own choices; results/paper_4_4.md measures each).
  /// Cast point of each cell's distances and of its reported pose: centre, or corner (F3Loc).
  RayCastPoint cast_point = RayCastPoint::kCentre;
  /// exact, or raster (F3Loc's fine-occupancy march, generate_desdf.raycast_desdf + utils.ray_cast).
  RayDistances distances = RayDistances::kExact;
  /// Occupancy resolution of the raster distances (F3Loc: original_resolution 0.01 m/px); must
  /// divide resolution_m.
  double raster_resolution_m = 0.01;
  /// Ray order and heading convention (see RayConvention).
  RayConvention ray_convention = RayConvention::kFloorcast;
  /// Field of view of the compared rays, centred on the heading: 360 (every ray) or less (the
  /// rays within +-fov/2 of the heading; F3Loc: 11 rays at 10 deg over +-50 deg, fov_deg 100).
  double fov_deg = 360.0;
  /// Clip the observation's rays at the clipping range (true: both sides clipped), or leave them
  /// as observed while the volume is clipped (F3Loc's evaluation: desdf truncated at 10 m on load,
  /// predicted rays up to 15 m).
  bool clip_observation = true;
  /// Cells scored: valid (default) or all (F3Loc).
  RayCells cells = RayCells::kValid;

  /// Takes the experiment's shared range and blocking flags (max_range_m, blocking).
  void apply_shared(const SharedParams& shared);
  /// The field list (core/fields.hpp): keys, ranges, docs; to_json and apply_overrides use it.
  static const FieldList<RayMatcherParams>& fields();
  nlohmann::ordered_json to_json() const;
  /// Applies overrides (keys as in to_json); throws ParameterError naming the key.
  void apply_overrides(const nlohmann::json& overrides);
};

class RayMatcher final : public Matcher {
 public:
  /// Computes the distance volume (the per-plan precomputation).
  RayMatcher(const FloorPlan& plan, const RayMatcherParams& params = {});
  /// Uses a volume computed earlier for this plan and these parameters (compute_volume); throws InputError when its grid, direction count
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
  /// Point queries: the maximum by the bounded search (top 1), each asked cell's L1 at its slice
  /// (the posterior's arithmetic: bit for bit its value).
  PosteriorQuery query(const Observation2D& observation) const override;

  /// The observation's rays (metres, ray i at 2 pi i / D), before the ray convention.
  std::vector<double> observation_rays(const Observation2D& observation) const;

  /// What the score compares: at slice o, range_m[j] with the volume's direction
  /// (o + offset[j]) mod D, for the rays of the field of view under the ray convention.
  struct ComparedRays {
    std::vector<int> offset;
    std::vector<double> range_m;
  };
  ComparedRays compared_rays(const Observation2D& observation) const;

  /// Per stored cell, a lower bound (mm) of its L1 at every orientation, as the bounded search
  /// uses it (exposed for tests and analyses).
  std::vector<std::int32_t> lower_bounds_mm(const Observation2D& observation) const;
  /// Per stored cell and orientation group, a lower bound (mm) of its L1 at every orientation of
  /// the group, as the bounded search refines its order with it (72 or more directions; exposed
  /// for tests and analyses). Group g holds orientations g w .. min(D, (g + 1) w) - 1.
  struct GroupBounds {
    int group_width = 0;  ///< w; 0: the search uses no groups at this direction count
    int groups = 0;
    std::vector<std::int32_t> mm;  ///< [cell * groups + g]
  };
  GroupBounds group_bounds_mm(const Observation2D& observation) const;

  const DistanceVolume& volume() const { return pre_->volume; }
  const GridSpec& grid() const { return pre_->volume.grid; }
  const RayMatcherParams& params() const { return params_; }

  /// The volume the matcher precomputes for a plan (what the first constructor computes).
  static DistanceVolume compute_volume(const FloorPlan& plan, const RayMatcherParams& params);

 private:
  /// The observation's rays and clipping range in the volume's units.
  struct RayUnits {
    std::vector<int> offsets;          ///< ComparedRays::offset
    std::vector<std::uint16_t> rays;   ///< ComparedRays::range_m in the volume's units
    std::uint16_t clip = 0;
    bool clipped = false;  ///< clip the volume's values below its range
    int block = 1;         ///< rays per 16-bit partial sum
  };
  RayUnits ray_units(const Observation2D& observation) const;
  /// The estimate, top-K modes and (if asked) the max-over-yaw map without the full posterior.
  void match_modes(const RayUnits& ru, const MatchRequest& request, MatchResult& result) const;
  struct RankTables {
    std::vector<std::int32_t> lo, hi;  ///< per rank block j: [j * 256 + bin]
  };
  RankTables rank_tables(const std::vector<std::uint16_t>& rays_mm, int top_mm) const;
  /// lb[0..n) = lower bounds (mm) of stored cells first..first+n-1.
  void rank_bounds(const RankTables& tables, std::size_t first, int n, std::int32_t* lb) const;
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

/// The cast point of grid cell (row, col) of a volume (its centre or corner, sample_offset), where
/// the ray matcher reports a pose in that cell.
Vec2 volume_cast_point(const DistanceVolume& volume, int row, int col);

}  // namespace floorcast
