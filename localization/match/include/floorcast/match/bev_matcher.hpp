// The semantic BEV matcher of the floor-plan localization thesis (seed paper 004, sec. 3.4): the
// observation's bird's-eye view B_pred (W columns x D log-spaced depth bins x C classes,
// core/bev.hpp) against the plan's one-hot BEV B_s rendered at every pose s = (x, y, theta):
//
//   L(s) = 1 / (D W) sum_{w, d, c} B_pred[w, d, c] B_s[w, d, c]                    (Eq. 3.3)
//
// i.e. the mean over columns and bins of the predicted probability of the class the plan shows
// there. Column w of the observation (observer-frame azimuth alpha_w) is rendered along the
// precomputed world direction nearest theta + alpha_w (semantic_volume.hpp: A directions, K
// orientations, A a multiple of K). Scores over the shared grid form the posterior (normalised by
// Posterior::normalised_pdf; the thesis: "normalizing over the entire volume"); top-K modes as
// every matcher's (greedy suppression, MatchRequest); Posterior-consuming filters use it as is.
//
// Variants (parameters): semantics = false is the thesis' no-semantics model (Table 4.3: doors
// removed, walls and windows one occupied class that stops the ray; it takes the observation's
// occupancy BEV); likelihood = "exp" turns the mean into exp(-(1 - L) / temperature), a sharper
// likelihood for the filters (not in the thesis).
#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "floorcast/core/fields.hpp"
#include "floorcast/core/params.hpp"
#include "floorcast/match/matcher.hpp"
#include "floorcast/match/semantic_volume.hpp"

namespace floorcast {

enum class BevLikelihood {
  kMean,  ///< Eq. 3.3 as is (the thesis)
  kExp,   ///< exp(-(1 - L) / temperature)
};

/// How the estimate and top-K modes are found (MatchOutput::kModes; the posterior and the
/// max-over-yaw map always score every cell).
enum class BevSearch {
  /// kBounded, deciding once 2% of the (block, orientation) pairs are scored: the pairs scored
  /// and those still open (bound above the lower bound of the last mode) are all it can score;
  /// when their share of all pairs exceeds auto_exhaustive_share the modes come from kExhaustive
  /// instead (a pair scored by the bounded search costs about twice its cells in the exhaustive
  /// one). Same modes either way; counters["search_exhaustive"] (0, 1) says which ran,
  /// counters["search_predicted_share"] the share compared, stage_s["bounded_until_switch"] the
  /// time spent before a switch.
  kAuto,
  /// Exact best-first search over (block of cells, orientation) pairs: an upper bound of each
  /// pair's scores from the range of the block's stop bins and the union of its crossings orders
  /// the pairs, which are scored exactly in that order until no unscored pair can reach the next
  /// mode (each mode the best candidate outside the earlier modes' separation). Same modes,
  /// scores and ties as kExhaustive.
  kBounded,
  /// Score every stored cell at every orientation (the reference).
  kExhaustive,
};

/// How the top-K modes are picked.
enum class BevPeaks {
  /// Greedy suppression at the request's separation (1 m, 30 deg), as every matcher's modes.
  kSuppression,
  /// The thesis' local maxima of a maximum filter (sec. 5.3: 5 x 5 x 3 on 0.2 m x 10 deg: 1 m x 1 m
  /// x 30 deg; Posterior::maximum_filter_peaks), ranked by score; needs the full posterior.
  kMaxFilter,
};

struct BevMatcherParams {
  /// Grid resolution (the thesis: 0.2 m on its office plans; F3Loc's grid 0.1 m).
  double resolution_m = 0.1;
  double grid_margin_m = 1.0;
  /// Orientations of the posterior (the thesis: 10 deg, K = 36).
  int num_orientations = 36;
  /// Directions the plan is rendered along (a multiple of num_orientations): an observation
  /// column is drawn along the nearest one, so this is the angular resolution of the rendered
  /// BEV (72: 5 deg).
  int num_directions = 72;
  /// Log-spaced depth bins of the BEV, from min_depth_m to max_range_m (the observation's BEV
  /// must have the same bins).
  int depth_bins = 32;
  double min_depth_m = 0.3;
  /// Last bin edge: the localization range (shared range_m).
  double max_range_m = 10.0;
  /// true: wall, window, door, empty (doors and windows let rays pass); false: the thesis'
  /// no-semantics variant (occupied, empty; doors removed, windows stop rays).
  bool semantics = true;
  BevLikelihood likelihood = BevLikelihood::kMean;
  /// kExp only: score = exp(-(1 - L) / temperature).
  double temperature = 0.02;
  BevSearch search = BevSearch::kAuto;
  /// kAuto: largest predicted share of the (block, orientation) pairs the bounded search may score
  /// (checked once 2% are scored) before the exhaustive search runs instead.
  double auto_exhaustive_share = 0.6;
  BevPeaks peaks = BevPeaks::kSuppression;
  /// kMaxFilter: the filter's extent, metres (square) and degrees (1 m, 30 deg: the thesis').
  double peak_window_m = 1.0;
  double peak_window_deg = 30.0;
  /// Cut height (where the plan is cut) and where an observer may stand (matcher_valid_mask);
  /// what a ray passes is the BEV's own rule (doors and windows always, sec. 3.3.4), whatever
  /// doors_closed and glass_blocks say.
  BlockingOptions blocking = closed_door_map();

  /// The depth bins these parameters describe.
  BevDepthBins bins() const { return {depth_bins, min_depth_m, max_range_m}; }
  /// Takes the experiment's shared range and blocking flags (max_range_m, blocking).
  void apply_shared(const SharedParams& shared);
  /// The field list (core/fields.hpp): keys, ranges, docs; to_json and apply_overrides use it.
  static const FieldList<BevMatcherParams>& fields();
  nlohmann::ordered_json to_json() const;
  /// Applies overrides (keys as in to_json); throws ParameterError naming the key.
  void apply_overrides(const nlohmann::json& overrides);
};

class BevMatcher final : public Matcher {
 public:
  /// Computes the semantic volume (the per-plan precomputation).
  BevMatcher(const FloorPlan& plan, const BevMatcherParams& params = {});
  /// Shares `other`'s volume (no copy) with other scoring parameters (likelihood, temperature,
  /// search); throws InputError when the volume's parameters differ.
  BevMatcher(const BevMatcher& other, const BevMatcherParams& params);
  ~BevMatcher() override;

  std::string name() const override { return "bev"; }
  nlohmann::ordered_json parameters() const override { return params_.to_json(); }
  double precompute_s() const override { return precompute_s_; }
  std::size_t precompute_bytes() const override;
  BlockingOptions blocking() const override { return params_.blocking; }
  using Matcher::match;
  /// An observation without a BEV of the matcher's class set gives an all-zero posterior (no
  /// pose) and counters["bev_missing"] = 1; a BEV with other depth bins is refused (InputError).
  MatchResult match(const Observation2D& observation, const MatchRequest& request) const override;

  /// The observation's BEV this matcher uses (nullptr when it has none of its class set).
  const BevPrediction* observation_bev(const Observation2D& observation) const;

  /// The semantic volume, its cells stored block by block (Precomputed::block_range).
  const SemanticVolume& volume() const { return pre_->volume; }
  const GridSpec& grid() const { return pre_->volume.grid; }
  const BevMatcherParams& params() const { return params_; }

  /// The volume the matcher precomputes for a plan.
  static SemanticVolume compute_volume(const FloorPlan& plan, const BevMatcherParams& params);

 private:
  /// The per-plan precomputation, shared (read-only) by matchers built from one another.
  struct Precomputed {
    SemanticVolume volume;
    /// Blocks of kBlockCells x kBlockCells grid cells holding stored cells, for the bounded
    /// search: the volume stores its cells block by block (row-major within a block and over the
    /// blocks), so each block is one range of stored cells (first, count).
    std::vector<std::pair<std::int64_t, int>> block_range;
    /// Per block b and direction a (index b * A + a): the smallest and largest stop code of its
    /// cells, and (semantic) the union of their door and window crossing bins (bit = bin).
    std::vector<std::uint8_t> block_stop_lo, block_stop_hi;
    std::vector<std::uint64_t> block_doors, block_windows;
  };
  /// Grid cells per block side of the bounded search (0.8 m at 0.1 m).
  static constexpr int kBlockCells = 8;
  struct Tables;
  Tables tables(const BevPrediction& bev) const;
  void score_tile(const Tables& t, std::size_t first, int n, float* out) const;
  void score_orientation(const Tables& t, std::size_t first, int n, int k, float* out) const;
  /// The bounded search; false when `may_switch` and it predicts more than auto_exhaustive_share
  /// of the pairs to score (result then holds only the prediction and the time spent).
  bool match_modes(const Tables& t, const MatchRequest& request, MatchResult& result, bool may_switch) const;
  void index_blocks(Precomputed& pre) const;
  BevMatcherParams params_;
  std::shared_ptr<const Precomputed> pre_;
  double precompute_s_ = 0.0;
};

/// Reference scores of one stored cell (slow, obvious): for every orientation k (yaw 2 pi k / K),
/// Eq. 3.3 on the volume's one-hot rendering (SemanticVolume::render) along the direction nearest
/// 2 pi k / K + alpha_w of each column, then the likelihood.
std::vector<double> bev_scores_reference(const SemanticVolume& volume, std::size_t cell, const BevPrediction& bev,
                                         int num_orientations, BevLikelihood likelihood, double temperature);

}  // namespace floorcast
