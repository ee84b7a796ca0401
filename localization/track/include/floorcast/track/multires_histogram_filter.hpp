// A two-resolution histogram filter (floorcast's, not a paper's; issue 25): the F3Loc histogram
// filter (histogram_filter.hpp) kept over the whole plan at a coarse resolution (coarse_factor x
// the fine one, 0.4 m by default), and at the fine resolution (0.1 m) only in a window of
// window_m x window_m around the belief once the window holds window_mass of it.
//
// Why: one step of the histogram filter reads and writes every cell x direction its belief
// covers; on a 10,000 m^2 plan with a wide belief that is ~46 M floats per pass at 0.1 m, whose
// memory traffic alone is above 20 ms per step (results/bench_filter.md). The coarse belief costs
// 1 / coarse_factor^2 of that wherever the belief is wide; the fine window what a room-sized
// region costs.
//
// How:
// - Plans that fit in the window (width and height of the fine grid <= window_m): the fine filter
//   over the whole plan, nothing else: the histogram filter itself, bit for bit.
// - Coarse filter: the fine filter's parameters on a grid coarse_factor times coarser whose cells
//   are interior where any of their fine cells is (doors narrower than a coarse cell stay open).
// - Fine filter: the fine grid cut to the window, its interior cut from the fine interior; built
//   (from the coarse belief, or from the old window's belief when moving a trusted window) when
//   the coarse belief holds window_mass within a window around its estimate; dropped when the
//   mass in its window falls below window_mass; moved when its estimate comes within a quarter
//   of the window of the window's edge (not at the plan's edge). Both filters take every
//   prediction and measurement update (point queries on each one's own cells).
// - Estimate: the fine filter's while its window holds window_mass of the coarse belief (support:
//   its support x that mass), the coarse filter's otherwise.
// Answers differ from the single-resolution filter's where the coarse belief decides (a wide
// belief: positions to a coarse cell) and where mass leaves the window; the difference is
// measured against the exact filter in results/bench_filter.md and tests/track.
#pragma once

#include <memory>

#include "floorcast/track/histogram_filter.hpp"

namespace floorcast {

struct MultiResolutionHistogramFilterParams {
  /// The filter's parameters (resolution_m: the fine resolution), as tracker hist takes them.
  HistogramFilterParams filter;
  /// Coarse resolution = coarse_factor x filter.resolution_m (1: the single-resolution filter).
  int coarse_factor = 4;
  /// Side of the fine window, m (a few rooms and their corridor at 0.1 m: 300 x 300 cells).
  double window_m = 30.0;
  /// The fine window is used (and kept) while it holds at least this share of the coarse belief.
  double window_mass = 0.5;

  static const FieldList<MultiResolutionHistogramFilterParams>& fields();
  nlohmann::ordered_json to_json() const;
  void apply_overrides(const nlohmann::json& overrides);
};

class MultiResolutionHistogramFilter final : public Tracker {
 public:
  MultiResolutionHistogramFilter(const FloorPlan& plan, const MultiResolutionHistogramFilterParams& params = {});
  ~MultiResolutionHistogramFilter() override;

  std::string name() const override { return "hist_mr"; }
  nlohmann::ordered_json parameters() const override { return params_.to_json(); }
  void initialise(const Posterior& posterior, const OdometryStep& first) override;
  void predict(const OdometryStep& step) override;
  using Tracker::update;
  void update(const PosteriorQuery& posterior) override;
  TrackEstimate estimate() const override;
  std::size_t state_bytes() const override;

  /// True when the plan fits in the window: one fine filter over the whole plan (the
  /// single-resolution filter exactly).
  bool single_resolution() const { return coarse_ == nullptr; }
  /// True when the last estimate came from the fine window.
  bool refined() const { return use_fine_; }
  /// Fine windows built so far (first builds and moves).
  int windows_built() const { return windows_built_; }
  const GridSpec& fine_grid() const { return fine_grid_; }
  const GridSpec& coarse_grid() const;

 private:
  /// After every step: keep, move, build or drop the fine window; choose the estimate's source.
  /// A new window's belief comes from `fresh` when given (the initial posterior), else from the
  /// coarse belief.
  void manage_window(const Posterior* fresh = nullptr);
  /// Builds the fine window centred (as far as the plan allows) on `centre`, its belief from
  /// `source`; false when the source holds nothing there.
  bool build_window(const Vec2& centre, const Posterior& source);
  /// The fine window's grid centred (as far as the plan allows) on `centre`: the fine grid's
  /// cells, window_m x window_m of them.
  GridSpec window_grid(const Vec2& centre) const;
  /// The fine window's world box.
  void window_box(double& x0, double& y0, double& x1, double& y1) const;

  MultiResolutionHistogramFilterParams params_;
  GridSpec fine_grid_;       ///< the whole plan at the fine resolution
  cv::Mat fine_interior_;    ///< CV_8U over fine_grid_
  std::unique_ptr<HistogramFilter> coarse_;  ///< null: single resolution
  std::unique_ptr<HistogramFilter> fine_;    ///< the window (or the whole plan when single)
  int window_c0_ = 0, window_r0_ = 0;        ///< the window's first fine cell
  bool use_fine_ = false;
  double window_share_ = 0.0;  ///< coarse belief mass inside the window (last manage_window)
  int windows_built_ = 0;
  OdometryStep last_step_;
};

}  // namespace floorcast
