// The F3Loc histogram filter (facts in ../shared/reference/f3loc.md; the thesis' sequential
// chapter): a belief over an (x, y, yaw) grid (0.1 m, 36 directions: the ray matcher's grid).
//
// Motion: per orientation slice, the ego-motion rotated into that slice's heading moves the slice
// by whole cells, the sub-cell rest kept as the slice's offset (so small motions are not lost and
// nothing is smoothed by interpolation), convolved with the discrete Gaussian of the increment's
// translation noise (F3Loc's grouped 2D convolution; separable here: two 1D passes); then the
// slices turn by whole bins (the rest kept as the heading residual) and are convolved with the
// circular discrete Gaussian of the rotation noise. The noise of each increment is the odometry's
// stated error (motion_noise odometry, the default: OdometryUncertainty, per metre, radian, second
// and step; a walk states it for its odometry, the defaults are for uncharacterised odometry) or
// F3Loc's constants (motion_noise fixed: 0.1 m and 0.1 rad per increment, whatever the odometry:
// on VIO walks without observations that diffused a correct start into a 180 deg twin within
// 20 steps, results/sequential.md). Motions larger than max_substep_m, max_substep_deg or with
// more noise than the kernels reach are split into sub-steps (variances add: splitting adds no
// noise). The belief is kept at 0 outside the building. Measurement: belief x (floor + (1 - floor)
// x posterior / max), the posterior looked up at the nearest slice in yaw and the cell (any
// matcher's posterior, any grid). Estimate: the belief's argmax (F3Loc; the default, measured
// against the window mode in results/sequential.md), or the mode of the belief summed over the
// success window. "Converged": the belief mass within 1 m and 30 deg of the estimate reaches
// converged_mass. No mass left (every hypothesis walked out of the building) is reported as
// degenerate with support 0, never a made-up pose.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <tbb/enumerable_thread_specific.h>
#include <opencv2/core.hpp>

#include "floorcast/track/tracker.hpp"

namespace floorcast {

/// What the filter reports as its pose.
enum class BeliefEstimate {
  kArgmax,  ///< the belief's largest cell (F3Loc)
  /// The pose with the most belief mass within the support window (support_radius_m,
  /// support_yaw_deg): the mode of the belief smoothed over the success window, the Bayes
  /// estimate for "within 1 m and 30 deg". Costs a box filter of every slice per step.
  kWindow,
};

enum class BeliefInit {
  kPosterior,  ///< the initial posterior as the belief (F3Loc: uniform prior x first likelihood)
  kUniform,    ///< uniform over the building, all headings
};

struct HistogramFilterParams {
  double resolution_m = 0.1;          ///< F3Loc desdf grid
  double grid_margin_m = 1.0;         ///< as the ray matcher, so its posteriors map cell to cell
  int num_orientations = 36;          ///< F3Loc: 36 (10 deg)
  MotionNoiseSource motion_noise = MotionNoiseSource::kOdometry;
  /// The odometry's error (motion_noise odometry): a walk states it for its odometry source; the
  /// defaults are for uncharacterised odometry (core/odometry.hpp).
  OdometryUncertainty odometry;
  /// How the odometry's bias terms spread over increments (core/odometry.hpp; measured in
  /// results/sequential.md): per increment (default) or linear growth.
  BiasGrowth bias_growth = BiasGrowth::kPerIncrement;
  double translation_sigma_m = 0.1;   ///< motion_noise fixed: per increment and axis (F3Loc)
  double rotation_sigma_rad = 0.1;    ///< motion_noise fixed: per increment (F3Loc)
  /// Largest motion applied in one pass; larger motions are split into sub-steps. F3Loc's fixed
  /// 7 x 7 kernels span +-0.3 m and +-30 deg; floorcast builds each step's kernels to the size of
  /// its motion, so only turns need splitting (the translation follows the arc): a walking step
  /// (~0.7 m) is one pass.
  double max_substep_m = 1.0;
  double max_substep_deg = 30.0;
  BeliefInit init = BeliefInit::kPosterior;
  double measurement_floor = 0.05;
  /// Belief below this fraction of the maximum is set to 0 after every step (0 = never): keeps
  /// the sums clean of round-off and lets converged beliefs skip empty slices and cells.
  double prune_below = 1e-7;
  /// Steps visit only the cells that hold belief (per slice and block of rows, the columns
  /// between the first and last non-zero cell; the full grid while the belief is flat), and
  /// updates ask the matcher for those cells only (point queries) when they are fewer than an
  /// eighth of the posterior's. The same arithmetic as visiting every cell (false: the dense
  /// filter, the reference of tests and benches), bit for bit.
  bool sparse = true;
  /// Sparse filter's mass accounting: after every step (prediction or update) the least likely
  /// cells holding together at most this share of the belief's mass are set to 0 and the rest
  /// renormalised; the dropped shares are accounted (dropped_mass()). Without it the measurement
  /// floor keeps every hypothesis above prune_below and most of the grid live (61% on the campus);
  /// with it the filter's steps cost what the belief's mass covers. A flat belief drops nothing
  /// (cells are dropped by value classes of 1/8 octave, whole classes only, never part of a tie),
  /// so the full grid stays live until updates concentrate the mass. 0: exact (the dense filter's
  /// arithmetic, bit for bit). The dense filter (sparse false) never drops. The tolerance against
  /// the dense filter it gives is measured in results/bench_filter.md and tests/track.
  double drop_mass = 1e-4;
  BeliefEstimate estimate = BeliefEstimate::kArgmax;
  /// The support window: TrackEstimate::support is the belief mass within support_radius_m and
  /// support_yaw_deg of the estimate (the success criterion's 1 m, 30 deg).
  double support_radius_m = 1.0;
  double support_yaw_deg = 30.0;
  /// Convergence (this filter's, not PALMS' two stages of particle groups and clusters): stage 2
  /// (converged) when the support reaches converged_mass, i.e. at least half the belief lies
  /// within 1 m and 30 deg of the estimate; stage 1 when the estimate's heading bin and its two
  /// neighbours hold orientation_mass of the belief.
  double orientation_mass = 0.8;
  double converged_mass = 0.5;
  /// Peaks of the belief reported with every estimate (TrackEstimate::modes; 0 = none): the
  /// thesis' maximum filter of 1 m x 1 m x 30 deg (seed paper 004, sec. 5.3;
  /// Posterior::maximum_filter_peaks), ranked by belief.
  int modes = 0;

  /// The field list (core/fields.hpp): keys, ranges, docs; to_json and apply_overrides use it.
  static const FieldList<HistogramFilterParams>& fields();
  nlohmann::ordered_json to_json() const;
  /// Strict overrides (keys as in to_json); throws ParameterError naming the key.
  void apply_overrides(const nlohmann::json& overrides);
};

const std::vector<std::pair<const char*, BeliefInit>>& belief_init_names();
const std::vector<std::pair<const char*, BeliefEstimate>>& belief_estimate_names();

class HistogramFilter final : public Tracker {
 public:
  HistogramFilter(const FloorPlan& plan, const HistogramFilterParams& params = {});
  /// A filter on a given grid (any part of a plan's grid: a window) whose belief lives where
  /// `interior` (CV_8U, the grid's size) is non-zero; params.resolution_m and grid_margin_m are
  /// not used (the grid says them).
  HistogramFilter(const GridSpec& grid, const cv::Mat& interior, const HistogramFilterParams& params);
  /// Where the filter of `plan` keeps belief on `grid` (CV_8U 255): the valid area less every
  /// cell a map wall covers.
  static cv::Mat belief_interior(const FloorPlan& plan, const GridSpec& grid);
  ~HistogramFilter() override;

  std::string name() const override { return "hist"; }
  nlohmann::ordered_json parameters() const override { return params_.to_json(); }
  void initialise(const Posterior& posterior, const OdometryStep& first) override;
  void predict(const OdometryStep& step) override;
  using Tracker::update;
  void update(const PosteriorQuery& posterior) override;
  TrackEstimate estimate() const override;
  std::size_t state_bytes() const override;

  /// The belief (a PDF: sums to 1) as a Posterior on the filter's grid.
  Posterior belief() const;
  /// Cells (x slices) the filter's steps touch: those inside the live spans (every cell outside
  /// them holds 0). The whole building's cells x directions when the belief is flat.
  std::int64_t live_cells() const;
  /// Measurement updates so far that asked the posterior for the live cells only (point queries)
  /// instead of reading the full posterior.
  int point_query_updates() const { return point_query_updates_; }
  /// The belief mass dropped by drop_mass (and prune_below) so far: the sum over steps of the
  /// share of the belief each step set to 0 before renormalising (0 for the dense filter and
  /// drop_mass 0).
  double dropped_mass() const { return dropped_mass_; }
  /// A bound on the total variation between this belief and the dense filter's (the same steps
  /// without dropping): every step is linear and positive and never adds mass (motion: a
  /// normalised kernel times the building mask; update: a likelihood of at most 1), so the dense
  /// filter's unnormalised belief is this one's plus what the dropped cells would have become,
  /// whose mass is at most what was dropped; against the kept mass that ratio R grows by 1 / (the
  /// share of its mass the kept belief keeps through a step) and by each drop, and the total
  /// variation is at most R / (1 + R). Updates that weigh the kept belief down (a likelihood far
  /// below 1 where it sits) grow it: a worst case (it assumes the dropped cells were weighed 1),
  /// so it is often far above the measured total variation (results/bench_filter.md). The dense
  /// filter's own pruning (prune_below, 1e-7 of the maximum per cell) is not in it.
  double drop_bound() const { return drop_ratio_ / (1.0 + drop_ratio_); }
  const GridSpec& grid() const { return grid_; }
  const HistogramFilterParams& params() const { return params_; }
  /// Share of the belief (normalised) at positions inside the world box [x0, x1] x [y0, y1] (m),
  /// all headings; 0 when the filter is lost.
  double mass_within(double x0_m, double y0_m, double x1_m, double y1_m) const;

 private:
  void setup(const GridSpec& grid, const cv::Mat& interior);
  /// One sub-step: body-frame motion, noise variances (translation per axis, rotation).
  void move(double dx_m, double dy_m, double dyaw_rad, double translation_var_m2, double rotation_var_rad2);
  /// Largest translation-noise sigma of one sub-step (larger noise is split into sub-steps): half
  /// the largest sub-step motion.
  double max_substep_sigma_m() const { return 0.5 * params_.max_substep_m; }
  /// Per-slice mass and maximum of the belief (pass 1 of normalise; move() produces them itself).
  void measure_slices();
  /// Scale to a PDF, prune and record the peaks, from mass_ and slice_max_ (pass 2).
  void finish_normalise();
  /// The estimate, its support and stage from the normalised belief (into current_).
  void update_estimate();
  /// Belief mass within the support window of cell `at` of slice `slice`.
  double mass_near(int slice, const cv::Point& at) const;
  void normalise() {
    measure_slices();
    finish_normalise();
  }
  HistogramFilterParams params_;
  GridSpec grid_;
  cv::Mat interior_;               ///< CV_32F 1 inside the building, 0 elsewhere
  std::vector<cv::Mat> belief_;    ///< one CV_32F slice per orientation
  std::vector<cv::Mat> scratch_;   ///< rotation buffers
  /// Sparse bookkeeping: per slice and block of kBlockRows rows, the column interval [lo, hi]
  /// outside which the buffer holds 0 (lo > hi: the block is empty), for the belief and for the
  /// scratch buffers (index o * blocks_ + block). Motion, normalisation and updates visit these
  /// intervals only, so a concentrated belief costs what it covers and a flat one the full grid;
  /// the arithmetic inside them is the dense filter's (the zeros outside add nothing).
  struct Span {
    int lo = 0;
    int hi = -1;
    bool empty() const { return lo > hi; }
  };
  static constexpr int kBlockRows = 16;
  int blocks_ = 0;
  std::vector<Span> span_, scratch_span_;
  /// The spans of the belief by a scan of every interior cell (after initialisation).
  void scan_spans();
  /// sparse false: every span is the whole row (the dense filter).
  void dense_spans();
  int point_query_updates_ = 0;
  double dropped_mass_ = 0.0;
  /// drop_bound(): what the dropped cells would have carried, against the kept belief's mass.
  double drop_ratio_ = 0.0;
  /// Mass of the belief after the last normalisation (accounting; 0: not normalised yet).
  double belief_mass_ = 0.0;
  /// drop_mass: the value (unnormalised, as the belief holds it now) below which cells are dropped
  /// and the mass they hold (0, 0: nothing to drop). From a histogram of the live cells' values
  /// by float exponent and 3 mantissa bits.
  float drop_threshold(double total, double& dropped) const;
  /// The value classes of the belief as the last motion step produced it, per block of rows
  /// (block_counted_: the block had interior rows), for drop_threshold; valid until the belief
  /// changes otherwise (classes_valid_).
  std::vector<double> block_classes_;
  std::vector<char> block_counted_;
  bool classes_valid_ = false;
  /// Per slice after the last normalisation: mass, maximum and where it is.
  std::vector<double> mass_, peak_;
  /// Per slice: the unnormalised maximum of the belief as it is now (0: the slice is empty).
  std::vector<float> slice_max_;
  std::vector<cv::Point> peak_at_;
  /// Interior column range of each row.
  std::vector<int> row_lo_, row_hi_;
  /// Rows the vertical translation pass may read on either side of the row it writes (the
  /// largest sub-step plus four sigmas of its noise; predict() splits larger motions).
  int reach_rows_ = 0;
  /// Per-thread buffers of the motion step: horizontal-pass rows and one block of translated rows
  /// of every slice.
  struct MotionWorkspace {
    std::vector<float> rows, block;
    std::vector<double> classes;  ///< drop_mass's value classes of the block's rows (4 interleaved tables)
  };
  mutable tbb::enumerable_thread_specific<MotionWorkspace> workspace_;
  bool degenerate_ = false;
  double last_t_s_ = 0.0;  ///< time of the last odometry sample (increment durations)
  TrackEstimate current_;  ///< the estimate of the last normalised belief
  bool lost_ = false;      ///< no mass left: every hypothesis walked out of the building
  std::vector<cv::Mat> window_;  ///< estimate window: per-slice box sums
  /// Odometry travelled since the start or the last update (the biases' error grows with it).
  OdometryElapsed elapsed_;
  /// The belief's heading grid: slice o is the heading 2 pi o / D + yaw_residual_rad_ (|residual|
  /// <= half a bin); slice o's mass at cell (r, c) stands for the position cell_center(r, c) +
  /// offset_px_[o] x resolution (|offset| <= half a cell per axis; x = column, y = row).
  double yaw_residual_rad_ = 0.0;
  std::vector<Vec2> offset_px_;
};

}  // namespace floorcast
