// The PALMS / PALMS+ kernel layout matcher.
//
// For each orientation candidate psi and scale s, the observed segments (observer frame) are
// rotated by psi and scaled by s about the observer, then rasterised into two kernels centred on
// the observer:
//   RW  = lines (the pixels each segment touches), Gaussian blur, times a Gaussian distance weight (sigma 10 m) around the
//         observer; P = RW min-max scaled to [0, 1], then divided by its sum;
//   CES = union of the triangles (observer, a, b) of every segment, shrunk about the observer by
//         0.7, limited to a 10 m square window, eroded by one pixel ("Certainly Empty Space").
// Kernel = P - alpha * CES. The heatmap of (psi, s) is the cross-correlation of the plan raster
// (the blocking outline drawn the same way, doors closed) with the kernel, clipped at 0 and multiplied
// by the valid-area mask; the slice of psi is the maximum over s.
//
// Occluding corners: the sides of a CES triangle are rays from the observer through occluding
// wall corners, which lie exactly on them, so the CES touches the plan there at pixel level.
// Triangles are filled by strict pixel-centre containment, lines are drawn as the pixels they
// touch (so every pixel contains a point of its wall), and the CES is eroded with a 3x3 square (one pixel in every
// direction): then no corner pixel survives inside the CES even when the true observer is
// anywhere in its cell (up to half a cell from the kernel centre). With PALMS' 3x3 cross, corners
// on diagonal rays still collide and zero the true pose.
//
// Why the plan raster is the outline and not filled walls: observations are wall SURFACES; a
// filled raster would let observed lines score inside wall bodies (smearing the peak over the
// wall thickness and rewarding thick walls), while PALMS itself correlates against a 1-px
// Bresenham raster of the plan's wall lines.
#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "floorcast/core/fields.hpp"
#include "floorcast/core/params.hpp"
#include "floorcast/match/matcher.hpp"
#include "floorcast/match/orientation.hpp"
#include "floorcast/match/plan_raster.hpp"

namespace floorcast {

namespace detail {
class KernelSearchMaps;
struct SearchKernel;
}

/// What the kernel matcher's plan raster draws.
enum class PlanRasterKind { kOutline, kCentreline, kFilled };

/// How the kernel matcher finds the estimate and top-K modes when the caller asks for nothing
/// else (MatchOutput::kModes).
enum class ModesSearch {
  kBranchAndBound,  ///< exact branch and bound over (orientation, scale, x, y), no posterior
  kPosterior,       ///< the full FFT posterior, then Posterior::top_k
};

/// How the two kernels of an (orientation, scale) are built.
enum class KernelConstruction {
  kFloorcast,  ///< centred on the observer's cell (see the file comment)
  /// The PALMS authors' code (layout_matching_module/CES.py ConvCES.initialize_kernels and
  /// create_heatmap), arithmetic for arithmetic: a kernel grid from the triangles' smallest corner
  /// (np.arange), CES by point-in-triangle at its grid points, RW by PALMS' Bresenham, both padded
  /// by 10 px, the CES shrunk by resizing the image (cv2.resize, nearest) about the observer's
  /// truncated index, its square window centred 10 px off (the code's own index), RW blurred and
  /// weighted by a Gaussian at the observer's fractional position, normalised with the 1e-8
  /// floor; the heatmap shifted as create_heatmap shifts it (including its "-9" correction),
  /// which places the kernel pixel of the observer's truncated index one pixel before the centre,
  /// and zero where the shift brings in nothing (scipy shift, cval 0).
  kPalmsCode,
};

/// What lies outside the plan raster in the correlation.
enum class MapBorder {
  kMargin,   ///< the grid has grid_margin_m of free space around the plan; beyond it, nothing
  kReflect,  ///< PALMS: the raster spans exactly the plan's wall lines (no margin, origin at their
             ///< smallest corner, ceil((max - min) / resolution) cells: lines on the far edge fall
             ///< outside) and cv2.filter2D reflects it at the border (BORDER_REFLECT_101)
};

/// Where an observer may stand.
enum class ValidArea {
  kFree,        ///< matcher_valid_mask: the plan's interior free space
  kAlphaShape,  ///< PALMS: the alpha shape (alpha_shape_alpha) of the wall centrelines sampled
                ///< every metre, wall bodies included (alpha_shape_mask)
};

/// Where the pose of a cell is reported.
enum class ReportPoint {
  kCentre,
  kCorner,  ///< PALMS: pose_pred = pixel index * resolution (and the alpha mask sampled there)
};

/// The CES erosion's structuring element.
enum class ErodeShape {
  kSquare,   ///< (2e+1)^2 square (see "Occluding corners")
  kEllipse,  ///< PALMS: cv2.getStructuringElement(MORPH_ELLIPSE, (2e+1)^2): a cross at 3 x 3
};

struct KernelMatcherParams {
  /// Grid resolution (PALMS+ configs: `resolution: 0.1`; PALMS+ sec. 3: 0.1 m raster).
  double resolution_m = 0.1;
  /// Free margin of the grid around the plan's bounding box.
  double grid_margin_m = 1.0;
  /// Observation extent the kernels cover: observed geometry farther than this (times the
  /// largest scale) from the observer along x or y is cut off (PALMS+ sec. 4.4 and configs
  /// `max_dist: 10`).
  double max_range_m = 10.0;
  /// RW Gaussian blur (kernel size, sigma) in px: PALMS+ large buildings and sequential
  /// (configs/pp_custom_config.yaml `gaussian_kernel_config: [15, 3]`); PALMS used (7, 3).
  int blur_size_px = 15;
  double blur_sigma_px = 3.0;
  /// Distance weighting of RW: Gaussian of sigma 10 m centred on the observer (PALMS code,
  /// CES.py apply_gaussian_weighting with sigma = 10 / resolution px).
  double distance_sigma_m = 10.0;
  /// Weight of the CES kernel (PALMS+ sec. 3.3: alpha = 10; also the PALMS code). Every
  /// alpha >= 1 gives the same clipped heatmap (see correlation_alpha).
  double alpha = 10.0;
  /// CES triangles shrunk about the observer (PALMS code: shrink_factor = 0.7).
  double ces_shrink = 0.7;
  /// CES limited to a square window of this half-size around the observer (PALMS code:
  /// apply_square_mask max_distance = 10 m).
  double ces_window_m = 10.0;
  /// CES eroded by this many pixels (PALMS code: erode_binary_mask radius_px = 1). The element
  /// is a (2e+1)^2 square, not PALMS' 3x3 ellipse (a cross): see "Occluding corners" above.
  int ces_erode_px = 1;
  /// Orientation candidates (defaults: PALMS+ O = 10, 360 bins, NMS 10 bins).
  OrientationParams orientation;
  /// Scale candidates, max-marginalised (PALMS+ sec. 3.3: S = {0.9, 1.0, 1.1}).
  std::vector<double> scales = {0.9, 1.0, 1.1};
  /// What blocks in the map the plan raster draws (keys doors_closed, glass_blocks,
  /// obstacles_block, cut_height_m): open doors drawn closed (PALMS+ sec. 4.4: all doors
  /// "closed"); glass walls and windows drawn; obstacles not drawn (floor plans do not show
  /// furniture); cut at camera height.
  BlockingOptions blocking = closed_door_map();
  /// Doorways never collide with the certainly-empty space: the CES is correlated with a plan
  /// raster without door leaves (open or closed), whatever `blocking` draws for the wall score. A
  /// map cannot know which doors stand open; a scan that sees through an open door must not zero
  /// the true pose (with doors drawn for the CES it did: localization/match/README.md, "Doors"). false = one
  /// raster for both parts (PALMS as published; also what happens when the raster draws no door).
  bool ces_through_doorways = true;
  /// FFT round-off guard: heatmap values below this are set to 0. Single-precision round-off
  /// reaches ~3e-5 on the campus (`bench match` measures it); one matched wall pixel is worth
  /// ~1e-4 and good matches score 0.2-0.3.
  double zero_below = 1e-4;
  /// What the plan raster draws: outline (wall surfaces), centreline (wall axes, like the line
  /// plans PALMS reads; always drawn with the half-open rule, 1 px wide, whatever line_rule says)
  /// or filled (wall bodies).
  PlanRasterKind plan_raster = PlanRasterKind::kOutline;
  /// Line rasterisation (plan and RW): closed or half_open (see plan_raster.hpp).
  LineRule line_rule = LineRule::kClosed;
  /// Estimate and top-K without a posterior: the exact branch-and-bound search (same modes as
  /// the FFT posterior's top_k, found without correlating everywhere; kernel_search.hpp) or the
  /// posterior itself.
  ModesSearch modes_search = ModesSearch::kBranchAndBound;
  /// Levels of the search's bound maps: its coarsest nodes are 2^levels cells wide (5: 3.2 m at
  /// 0.1 m; measured fastest on the campus and the office). Changes the time, never the modes.
  int search_levels = 5;


  // Paper-faithful variants (defaults: floorcast's own choices; results/paper_4_4.md measures each).
  /// Kernel construction: floorcast (default) or palms_code (the authors' arithmetic; searched
  /// through the posterior).
  KernelConstruction kernel_construction = KernelConstruction::kFloorcast;
  /// margin (default) or reflect (PALMS: no margin, reflected border; searched through the
  /// posterior).
  MapBorder map_border = MapBorder::kMargin;
  /// PALMS: rotate the plan by palms_landscape_rotation_rad before rasterising it (its principal
  /// orientation onto the raster axes, landscape); poses are rotated back, posteriors resampled
  /// (nearest) onto the plan's own grid.
  bool map_tilt = false;
  /// free (default) or alpha_shape (PALMS).
  ValidArea valid_area = ValidArea::kFree;
  /// PALMS alpha_shape(alpha = 0.15).
  double alpha_shape_alpha = 0.15;
  /// centre (default) or corner (PALMS).
  ReportPoint report_point = ReportPoint::kCentre;
  /// square (default) or ellipse (PALMS).
  ErodeShape ces_erode_shape = ErodeShape::kSquare;

  /// Takes the experiment's shared range and blocking flags (max_range_m, blocking).
  void apply_shared(const SharedParams& shared);
  /// The field list (core/fields.hpp): keys, ranges, docs; to_json and apply_overrides use it.
  static const FieldList<KernelMatcherParams>& fields();
  nlohmann::ordered_json to_json() const;
  /// Applies overrides (keys as in to_json); throws ParameterError naming the key.
  void apply_overrides(const nlohmann::json& overrides);
};

/// The two kernels of one (orientation, scale), centred on the observer: CV_32F
/// (2R+1) x (2R+1), pixel (R, R) is the observer's cell.
struct LayoutKernels {
  cv::Mat p;    ///< normalised RW (sums to 1, or all zero without segments)
  cv::Mat ces;  ///< 0/1; the correlated kernel is p - alpha * ces
  /// palms_code: create_heatmap's shift (rows, cols): heatmap cell p holds the correlation at
  /// p - shift, and 0 where p - shift leaves the map.
  int shift_row = 0, shift_col = 0;
};

/// The PALMS authors' kernels of one (orientation, scale) (KernelConstruction::kPalmsCode),
/// embedded in (2R + 1)^2 so that correlating them centred reproduces create_heatmap's shifted
/// filter2D; parts beyond R are dropped.
LayoutKernels make_palms_code_kernels(const KernelMatcherParams& params, const std::vector<Segment2>& obs_segments,
                                      double yaw_rad, double scale, int radius_px);

/// Builds the kernels for observer-frame segments rotated by yaw_rad and scaled by scale.
LayoutKernels make_layout_kernels(const KernelMatcherParams& params, const std::vector<Segment2>& obs_segments,
                                  double yaw_rad, double scale, int radius_px);
/// Same, with the distance weight image (distance_weight_image) precomputed.
LayoutKernels make_layout_kernels(const KernelMatcherParams& params, const std::vector<Segment2>& obs_segments,
                                  double yaw_rad, double scale, int radius_px, const cv::Mat& distance_weight);
/// exp(-d^2 / (2 sigma^2)) of each kernel pixel's distance d to the centre (all ones for sigma 0).
cv::Mat distance_weight_image(const KernelMatcherParams& params, int radius_px);

/// The CES weight actually correlated. corr(plan, P) <= sum(P) = 1 (the plan raster is 0/1), so
/// for alpha >= 1 any CES hit drives the score to <= 0 and the clipped heatmap is the same for
/// every alpha >= 1 (exactly). Correlating with min(alpha, 1.5) instead of 10 gives the same
/// heatmap with ~7x less single-precision FFT round-off (which scales with the kernel's norm).
/// alpha < 1 is used as is.
double correlation_alpha(double alpha);

/// Kernel radius (px) the parameters need: max_range * max scale plus the blur half-size.
int kernel_radius_px(const KernelMatcherParams& params);

class KernelMatcher final : public Matcher {
 public:
  KernelMatcher(const FloorPlan& plan, const KernelMatcherParams& params = {});
  ~KernelMatcher() override;

  std::string name() const override { return "kernel"; }
  nlohmann::ordered_json parameters() const override { return params_.to_json(); }
  double precompute_s() const override { return precompute_s_; }
  std::size_t precompute_bytes() const override;
  BlockingOptions blocking() const override { return params_.blocking; }
  /// orientation_notes() of the plan (more main wall directions than the candidates test).
  std::vector<std::string> notes() const override;
  using Matcher::match;
  MatchResult match(const Observation2D& observation, const MatchRequest& request) const override;
  /// Point queries: the posterior's maximum by the branch-and-bound search (top 1), each asked
  /// cell correlated directly at every scale (exact_cell_score: within the FFT posterior's
  /// round-off of its value). map_tilt and the variants searched through the posterior
  /// (palms_code, reflect, modes_search posterior) compute the full posterior instead.
  PosteriorQuery query(const Observation2D& observation) const override;

  /// The orientation candidates match() searches for this observation (world yaws).
  std::vector<double> yaw_candidates(const Observation2D& observation) const;

  /// Posterior for explicit yaws (no candidate search); used by tests and analyses.
  MatchResult match_yaws(const Observation2D& observation, const std::vector<double>& yaws_rad) const;
  /// What `request` asks for, over explicit yaws (no candidate search).
  MatchResult match_yaws(const Observation2D& observation, const std::vector<double>& yaws_rad,
                         const MatchRequest& request) const;
  /// The exact heatmap value h(yaw, scale) of one cell (before clipping and the valid mask), as
  /// the branch-and-bound search computes it: the correlation summed directly, float products in
  /// double sums (the FFT's is within its round-off of it). yaw and cell in the matcher's frame
  /// (the world's unless map_tilt).
  double cell_score(const Observation2D& observation, double yaw_rad, double scale, int row, int col) const;
  /// The branch-and-bound search's maps (null when modes_search is posterior) and the RW distance
  /// weight image; for white-box tests of the search (localization/match/src/kernel_search.hpp).
  const detail::KernelSearchMaps* search_maps() const;
  const cv::Mat& distance_weight() const;
  /// Bytes of the branch-and-bound search's maps (built with the matcher unless modes_search is
  /// posterior; part of precompute_bytes).
  std::size_t search_bytes() const;

  /// The grid the matcher works on (the tilted plan's with map_tilt; posteriors are returned on
  /// output_grid()).
  const GridSpec& grid() const { return grid_; }
  /// The grid of returned posteriors (grid() unless map_tilt turns the plan).
  const GridSpec& output_grid() const { return output_grid_; }
  /// The plan rotation of map_tilt (0 without it): the matcher's frame is the world turned by it.
  double tilt_rad() const { return tilt_rad_; }
  /// Plan raster (CV_8U, 255 = wall surface) and valid-area mask (CV_8U, 255 = valid).
  const cv::Mat& plan_raster() const { return plan_raster_; }
  /// The raster the CES is correlated with (equals plan_raster() unless ces_through_doorways
  /// removes door leaves from it).
  const cv::Mat& ces_raster() const { return ces_raster_; }
  const cv::Mat& valid_mask() const { return valid_; }
  const KernelMatcherParams& params() const { return params_; }
  /// Size of the correlation transform (columns, rows): the grid padded by the kernel radius.
  int fft_cols() const;
  int fft_rows() const;

 private:
  struct Impl;
  /// match_yaws in the matcher's frame (yaws and results before to_world).
  MatchResult match_frame(const Observation2D& observation, const std::vector<double>& yaws_rad,
                          const MatchRequest& request) const;
  MatchResult posterior_yaws(const Observation2D& observation, const std::vector<double>& yaws_rad) const;
  MatchResult search_modes(const Observation2D& observation, const std::vector<double>& yaws_rad,
                           const MatchRequest& request) const;
  /// The search kernels of every (orientation, scale) (j = o * scales + s) and their RW line
  /// pixels; kernel_s: thread CPU seconds summed.
  std::vector<detail::SearchKernel> search_kernels(const Observation2D& observation, const std::vector<double>& yaws_rad,
                                                   std::vector<cv::Mat>& lines, double& kernel_s) const;
  /// The branch-and-bound modes over those kernels into result (modes, stages, counters).
  void search_with(std::vector<detail::SearchKernel>& kernels, const std::vector<cv::Mat>& lines,
                   const std::vector<double>& yaws_rad, const MatchRequest& request, MatchResult& result) const;
  /// Modes (and posterior) from the matcher's frame to the world: report point, tilt.
  void to_world(MatchResult& result) const;
  KernelMatcherParams params_;
  GridSpec grid_;
  GridSpec output_grid_;
  double tilt_rad_ = 0.0;
  /// map_border reflect: the correlated maps carry this many reflected pixels on every side.
  int border_px_ = 0;
  cv::Mat plan_raster_;
  cv::Mat ces_raster_;
  cv::Mat valid_;
  PlanOrientationCache orientation_cache_;
  std::unique_ptr<Impl> impl_;
  double precompute_s_ = 0.0;
};

}  // namespace floorcast
