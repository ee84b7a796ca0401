// Point queries: a posterior known by its grid, its orientation slices and its maximum, whose
// scores are computed only where a caller asks (the particle filter's measurement update needs
// them at its particles' cells, ~2000 of millions). Every matcher answers them
// (Matcher::query): the kernel matcher correlates directly at each asked cell and scale, the ray
// matcher sums the L1 of each asked cell and slice; others compute the full posterior and look the
// cells up (the documented fallback). The values are the full posterior's at those cells: bit for
// bit where the matcher computes both the same way (ray, fallbacks), within the posterior's FFT
// round-off for the kernel matcher (whose posterior correlates by FFT and whose point queries and
// branch-and-bound modes sum directly; tests/match/test_posterior_query.cpp).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "floorcast/match/posterior.hpp"

namespace floorcast {

/// One cell of a posterior: orientation slice, grid row and column.
struct PosteriorCell {
  int slice = 0;
  int row = 0;
  int col = 0;
  bool operator==(const PosteriorCell& o) const { return slice == o.slice && row == o.row && col == o.col; }
};

class PosteriorQuery {
 public:
  /// Scores of cells into out[0 .. cells.size()) (every cell inside the grid and slices).
  using PointScorer = std::function<void(const std::vector<PosteriorCell>& cells, float* out)>;
  /// Computes the full posterior (called at most once, when full() is first asked for).
  using FullPosterior = std::function<Posterior()>;

  /// Over a full posterior: lookups.
  explicit PosteriorQuery(Posterior posterior);
  /// Computed where asked: grid and slices of the posterior, its maximum over every cell and
  /// slice (0: every score is 0), the point scorer, and how to compute the full posterior.
  PosteriorQuery(GridSpec grid, std::vector<double> yaw_rad, double max_score, PointScorer scorer, FullPosterior full);

  const GridSpec& grid() const { return grid_; }
  const std::vector<double>& yaw_rad() const { return yaw_rad_; }
  int num_slices() const { return static_cast<int>(yaw_rad_.size()); }
  /// The largest score over all cells and slices (the posterior's maximum).
  double max_score() const { return max_score_; }
  /// The slice whose yaw is closest to yaw_rad (ties: the lowest slice), and the angular gap.
  int nearest_slice(double yaw_rad, double* gap_rad = nullptr) const;
  /// Scores of `cells`, as full().scores[slice].at<float>(row, col); out is resized. A query
  /// with a point scorer always uses it (also after full() was computed).
  void scores(const std::vector<PosteriorCell>& cells, std::vector<float>& out) const;
  /// True when the full posterior is at hand (built from one, or full() was called).
  bool has_full() const;
  /// True when scores() computes the asked cells (a matcher's point queries) rather than looking
  /// them up in a full posterior.
  bool scores_points() const;
  /// The full posterior (computed on the first call when this query was built without it;
  /// thread-safe).
  const Posterior& full() const;
  /// Cells scored by point queries so far (0 for lookups), for benches.
  std::int64_t cells_scored() const;

 private:
  struct State;
  GridSpec grid_;
  std::vector<double> yaw_rad_;
  double max_score_ = 0.0;
  std::shared_ptr<State> state_;
};

}  // namespace floorcast
