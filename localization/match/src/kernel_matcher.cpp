#include "floorcast/match/kernel_matcher.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <opencv2/imgproc.hpp>

#include "floorcast/match/fft_correlator.hpp"
#include "kernel_search.hpp"
#include "floorcast/match/plan_raster.hpp"
#include "floorcast/core/timing.hpp"

namespace floorcast {
namespace {

using Clock = std::chrono::steady_clock;

double seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

Vec2 rotate_scale(const Vec2& p, double c, double s, double k) { return {k * (c * p.x() - s * p.y()), k * (s * p.x() + c * p.y())}; }

const std::vector<std::pair<const char*, PlanRasterKind>> kPlanRasterNames = {
    {"outline", PlanRasterKind::kOutline}, {"centreline", PlanRasterKind::kCentreline}, {"filled", PlanRasterKind::kFilled}};
const std::vector<std::pair<const char*, LineRule>> kLineRuleNames = {{"closed", LineRule::kClosed},
                                                                      {"half_open", LineRule::kHalfOpen}};
const std::vector<std::pair<const char*, ModesSearch>> kModesSearchNames = {
    {"branch_and_bound", ModesSearch::kBranchAndBound}, {"posterior", ModesSearch::kPosterior}};

}  // namespace

nlohmann::ordered_json KernelMatcherParams::to_json() const {
  nlohmann::ordered_json j;
  j["resolution_m"] = resolution_m;
  j["grid_margin_m"] = grid_margin_m;
  j["max_range_m"] = max_range_m;
  j["blur_size_px"] = blur_size_px;
  j["blur_sigma_px"] = blur_sigma_px;
  j["distance_sigma_m"] = distance_sigma_m;
  j["alpha"] = alpha;
  j["ces_shrink"] = ces_shrink;
  j["ces_window_m"] = ces_window_m;
  j["ces_erode_px"] = ces_erode_px;
  j["orientations"] = orientation_mode_name(orientation.mode);
  j["num_orientations"] = orientation.num_orientations;
  j["histogram_bins"] = orientation.histogram_bins;
  j["nms_radius_bins"] = orientation.nms_radius_bins;
  j["dense_step_deg"] = orientation.dense_step_deg;
  j["refine_orientations"] = orientation.refine;
  j["scales"] = scales;
  write_blocking(j, blocking);
  j["zero_below"] = zero_below;
  j["plan_raster"] = enum_name(plan_raster, kPlanRasterNames);
  j["line_rule"] = enum_name(line_rule, kLineRuleNames);
  j["ces_through_doorways"] = ces_through_doorways;
  j["modes_search"] = enum_name(modes_search, kModesSearchNames);
  j["search_levels"] = search_levels;
  return j;
}

void KernelMatcherParams::apply_overrides(const nlohmann::json& overrides) {
  ParamReader r(overrides, "matcher kernel");
  r.read("resolution_m", resolution_m, 0.01, 1.0);
  r.read("grid_margin_m", grid_margin_m, 0.0, 100.0);
  r.read("max_range_m", max_range_m, 0.5, 100.0);
  r.read("blur_size_px", blur_size_px, 0, 101);
  if (blur_size_px > 0 && blur_size_px % 2 == 0) r.fail("blur_size_px", "must be odd (or 0 for no blur)");
  r.read("blur_sigma_px", blur_sigma_px, 0.0, 50.0);
  r.read("distance_sigma_m", distance_sigma_m, 0.0, 1e6);
  r.read("alpha", alpha, 0.0, 1e6);
  r.read("ces_shrink", ces_shrink, 0.0, 1.0);
  r.read("ces_window_m", ces_window_m, 0.0, 100.0);
  r.read("ces_erode_px", ces_erode_px, 0, 20);
  r.read_enum("orientations", orientation.mode, orientation_mode_names());
  r.read("num_orientations", orientation.num_orientations, 2, 720);
  r.read("histogram_bins", orientation.histogram_bins, 4, 3600);
  r.read("nms_radius_bins", orientation.nms_radius_bins, 0, 1800);
  r.read("dense_step_deg", orientation.dense_step_deg, 0.1, 180.0);
  r.read("refine_orientations", orientation.refine);
  r.read("scales", scales, 0.1, 10.0);
  read_blocking(r, blocking);
  r.read("zero_below", zero_below, 0.0, 1.0);
  r.read_enum("plan_raster", plan_raster, kPlanRasterNames);
  r.read_enum("line_rule", line_rule, kLineRuleNames);
  r.read("ces_through_doorways", ces_through_doorways);
  r.read_enum("modes_search", modes_search, kModesSearchNames);
  r.read("search_levels", search_levels, 1, 10);
  r.finish();
}

void KernelMatcherParams::apply_shared(const SharedParams& shared) {
  max_range_m = shared.range_m;
  blocking = shared.blocking;
}

double correlation_alpha(double alpha) { return alpha >= 1.0 ? std::min(alpha, 1.5) : alpha; }

int kernel_radius_px(const KernelMatcherParams& p) {
  const double max_scale = *std::max_element(p.scales.begin(), p.scales.end());
  const double reach_m = std::max(p.max_range_m * max_scale, p.ces_window_m);
  return static_cast<int>(std::ceil(reach_m / p.resolution_m)) + p.blur_size_px / 2 + 1;
}

cv::Mat distance_weight_image(const KernelMatcherParams& params, int R) {
  const int K = 2 * R + 1;
  cv::Mat w(K, K, CV_32F, cv::Scalar(1.0f));
  if (params.distance_sigma_m > 0.0) {
    const double res = params.resolution_m;
    const double inv2s2 = 1.0 / (2.0 * params.distance_sigma_m * params.distance_sigma_m);
    for (int r = 0; r < K; ++r) {
      float* row = w.ptr<float>(r);
      const double dy = (r - R) * res;
      for (int q = 0; q < K; ++q) {
        const double dx = (q - R) * res;
        row[q] = static_cast<float>(std::exp(-(dx * dx + dy * dy) * inv2s2));
      }
    }
  }
  return w;
}

LayoutKernels make_layout_kernels(const KernelMatcherParams& params, const std::vector<Segment2>& obs, double yaw,
                                  double scale, int R) {
  return make_layout_kernels(params, obs, yaw, scale, R, distance_weight_image(params, R));
}

namespace {

/// The geometry of one (orientation, scale)'s kernels: the RW's line pixels (within the square
/// window of the scaled range) and the CES (shrunk triangles, square window, erosion), CV_8U
/// 0/255, (2R + 1)^2, observer at pixel (R, R).
struct KernelGeometry {
  cv::Mat lines;
  cv::Mat ces;
};

KernelGeometry kernel_geometry(const KernelMatcherParams& params, const std::vector<Segment2>& obs, double yaw,
                               double scale, int R) {
  const int K = 2 * R + 1;
  const double res = params.resolution_m;
  // The observer sits at the centre of pixel (R, R).
  const Vec2 origin(-(R + 0.5) * res, -(R + 0.5) * res);
  const double c = std::cos(yaw), s = std::sin(yaw);
  const double reach_m = params.max_range_m * scale;

  std::vector<Segment2> segs;
  std::vector<std::array<Vec2, 3>> triangles;
  segs.reserve(obs.size());
  triangles.reserve(obs.size());
  for (const Segment2& seg : obs) {
    const Vec2 a = rotate_scale(seg.a_m, c, s, scale), b = rotate_scale(seg.b_m, c, s, scale);
    segs.push_back({a, b});
    triangles.push_back({Vec2::Zero(), params.ces_shrink * a, params.ces_shrink * b});
  }

  KernelGeometry g;
  // RW lines, within the square window of the (scaled) range.
  g.lines = cv::Mat::zeros(K, K, CV_8U);
  draw_segment_lines(g.lines, segs, origin, res, params.line_rule);
  const int reach_px = std::min(R, static_cast<int>(std::floor(reach_m / res + 1e-9)));
  if (reach_px < R) {
    cv::Mat window = cv::Mat::zeros(K, K, CV_8U);
    window(cv::Rect(R - reach_px, R - reach_px, 2 * reach_px + 1, 2 * reach_px + 1)).setTo(255);
    cv::bitwise_and(g.lines, window, g.lines);
  }

  // CES: shrunk triangles, square window, erosion.
  g.ces = cv::Mat::zeros(K, K, CV_8U);
  fill_triangles(g.ces, triangles, origin, res);
  const int win_px = std::min(R, static_cast<int>(std::floor(params.ces_window_m / res + 1e-9)));
  if (win_px < R) {
    cv::Mat window = cv::Mat::zeros(K, K, CV_8U);
    window(cv::Rect(R - win_px, R - win_px, 2 * win_px + 1, 2 * win_px + 1)).setTo(255);
    cv::bitwise_and(g.ces, window, g.ces);
  }
  if (params.ces_erode_px > 0) {
    const int e = params.ces_erode_px;
    const cv::Mat se = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * e + 1, 2 * e + 1));
    cv::erode(g.ces, g.ces, se, cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  }
  return g;
}

bool blur_on(const KernelMatcherParams& p) { return p.blur_size_px > 1 && p.blur_sigma_px > 0.0; }

/// P: the lines blurred, distance-weighted, min-max scaled and divided by the sum.
cv::Mat rw_kernel(const KernelMatcherParams& params, const cv::Mat& lines, const cv::Mat& weight) {
  cv::Mat rw;
  lines.convertTo(rw, CV_32F, 1.0 / 255.0);
  if (blur_on(params)) {
    cv::GaussianBlur(rw, rw, cv::Size(params.blur_size_px, params.blur_size_px), params.blur_sigma_px,
                     params.blur_sigma_px, cv::BORDER_CONSTANT);
  }
  rw = rw.mul(weight);
  double mn = 0.0, mx = 0.0;
  cv::minMaxLoc(rw, &mn, &mx);
  if (!(mx > mn)) return cv::Mat::zeros(lines.size(), CV_32F);
  rw = (rw - mn) / (mx - mn);
  const double sum = cv::sum(rw)[0];
  rw /= sum;
  return rw;
}

/// The factor c of P = c (weight * blur(lines) - min) (0 when P is all zero), computed on the
/// lines' bounding box only: the same up to float round-off, for the search's bounds (which
/// carry a 1e-4 relative margin).
double rw_scale(const KernelMatcherParams& params, const cv::Mat& lines, const cv::Mat& weight) {
  if (cv::countNonZero(lines) == 0) return 0.0;
  const int half = blur_on(params) ? params.blur_size_px / 2 : 0;
  cv::Rect box = cv::boundingRect(lines);
  box = cv::Rect(box.x - half, box.y - half, box.width + 2 * half, box.height + 2 * half) &
        cv::Rect(0, 0, lines.cols, lines.rows);
  cv::Mat rw;
  lines(box).convertTo(rw, CV_32F, 1.0 / 255.0);
  if (blur_on(params)) {
    cv::GaussianBlur(rw, rw, cv::Size(params.blur_size_px, params.blur_size_px), params.blur_sigma_px,
                     params.blur_sigma_px, cv::BORDER_CONSTANT);
  }
  rw = rw.mul(weight(box));
  double mn = 0.0, mx = 0.0;
  cv::minMaxLoc(rw, &mn, &mx);
  const double total = static_cast<double>(lines.total());
  double sum = cv::sum(rw)[0];
  if (static_cast<std::size_t>(box.area()) < lines.total()) {
    mn = std::min(mn, 0.0);  // zeros outside the box
    sum -= mn * (total - box.area());
  }
  if (!(mx > mn)) return 0.0;
  sum = (sum - mn * total) / (mx - mn);
  return 1.0 / ((mx - mn) * sum);
}

}  // namespace

detail::SearchKernel detail::build_search_kernel(const KernelMatcherParams& params, const std::vector<Segment2>& obs,
                                                 double yaw, double scale, const cv::Mat& weight,
                                                 const KernelSearchMaps& maps, bool with_leaf_data, cv::Mat* lines) {
  const KernelGeometry g = kernel_geometry(params, obs, yaw, scale, maps.R);
  SearchKernelInput in;
  in.lines = g.lines;
  in.ces = g.ces;
  in.p_scale = rw_scale(params, g.lines, weight);
  in.resolution_m = params.resolution_m;
  in.distance_sigma_m = params.distance_sigma_m;
  in.blur_half_px = blur_on(params) ? params.blur_size_px / 2 : 0;
  SearchKernel k = make_search_kernel(in, maps);
  if (with_leaf_data) add_leaf_data(k, rw_kernel(params, g.lines, weight), maps);
  if (lines) *lines = g.lines;
  return k;
}

LayoutKernels make_layout_kernels(const KernelMatcherParams& params, const std::vector<Segment2>& obs, double yaw,
                                  double scale, int R, const cv::Mat& weight) {
  const KernelGeometry g = kernel_geometry(params, obs, yaw, scale, R);
  LayoutKernels k;
  k.p = rw_kernel(params, g.lines, weight);
  g.ces.convertTo(k.ces, CV_32F, 1.0 / 255.0);
  return k;
}

struct KernelMatcher::Impl {
  std::unique_ptr<FftCorrelator> correlator;
  std::unique_ptr<detail::KernelSearchMaps> search;
  int radius_px = 0;
  cv::Mat distance_weight;
  std::vector<Segment2> plan_segments;
  mutable tbb::enumerable_thread_specific<std::unique_ptr<FftCorrelator::Workspace>> workspaces;
};

KernelMatcher::KernelMatcher(const FloorPlan& plan, const KernelMatcherParams& params)
    : params_(params), impl_(std::make_unique<Impl>()) {
  if (params_.scales.empty()) throw InputError("matcher kernel: no scale candidates");
  const auto t0 = Clock::now();
  grid_ = grid_for_plan(plan, params_.resolution_m, params_.grid_margin_m);
  {
    // Memory refused before any raster is allocated: the plan, CES and valid rasters, their float
    // copies and spectra, per-thread FFT workspaces, and one posterior slice per candidate yaw.
    const OrientationParams& o = params_.orientation;
    const double yaws = o.mode == OrientationMode::kDense ? std::ceil(360.0 / o.dense_step_deg) : 4.0 * o.num_orientations;
    check_raster_budget(grid_, 64.0 + 4.0 * yaws, "matcher kernel");
  }
  const std::vector<LabeledSegment> outline = blocking_outline(plan, params_.blocking);
  impl_->plan_segments = outline_segments(outline);
  const LineRule rule = params_.line_rule;
  auto raster = [&](const BlockingOptions& blocking) {
    if (params_.plan_raster == PlanRasterKind::kOutline) return rasterize_outline(blocking_outline(plan, blocking), grid_, rule);
    if (params_.plan_raster == PlanRasterKind::kCentreline) {
      // Always half-open: wall axes of generated and imported plans lie on multiples of the
      // resolution, i.e. on pixel boundaries, where the closed rule draws 2-px lines (every wall
      // counted twice, twice as wide as in PALMS' 1-px line rasters).
      cv::Mat m = cv::Mat::zeros(grid_.height_px, grid_.width_px, CV_8U);
      draw_segment_lines(m, footprint_centrelines(blocking_footprints(plan, blocking)), {grid_.origin_x_m, grid_.origin_y_m},
                         grid_.resolution_m_per_px, LineRule::kHalfOpen);
      return m;
    }
    return rasterize_occupancy(plan, grid_, blocking);
  };
  plan_raster_ = raster(params_.blocking);
  ces_raster_ = plan_raster_;
  if (params_.ces_through_doorways) {
    BlockingOptions no_doors = params_.blocking;
    no_doors.closed_doors_block = false;
    no_doors.open_doors_block = false;
    ces_raster_ = raster(no_doors);
    if (cv::countNonZero(ces_raster_ != plan_raster_) == 0) ces_raster_ = plan_raster_;  // the map draws no door
  }
  valid_ = matcher_valid_mask(plan, grid_, params_.blocking);
  orientation_cache_ = make_plan_orientation_cache(params_.orientation, impl_->plan_segments);
  impl_->radius_px = kernel_radius_px(params_);
  impl_->distance_weight = distance_weight_image(params_, impl_->radius_px);
  cv::Mat plan_f;
  plan_raster_.convertTo(plan_f, CV_32F, 1.0 / 255.0);
  if (ces_raster_.data == plan_raster_.data) {
    impl_->correlator = std::make_unique<FftCorrelator>(plan_f, impl_->radius_px);
  } else {
    // Two maps: the wall score on plan_raster_, the CES collision on ces_raster_ (one sum).
    cv::Mat ces_f;
    ces_raster_.convertTo(ces_f, CV_32F, 1.0 / 255.0);
    impl_->correlator = std::make_unique<FftCorrelator>(std::vector<cv::Mat>{plan_f, ces_f}, impl_->radius_px);
  }
  if (params_.modes_search == ModesSearch::kBranchAndBound) {
    impl_->search = std::make_unique<detail::KernelSearchMaps>(plan_raster_, ces_raster_, valid_, impl_->radius_px,
                                                               params_.search_levels, params_.blur_size_px,
                                                               params_.blur_sigma_px);
  }
  precompute_s_ = seconds(t0, Clock::now());
}

KernelMatcher::~KernelMatcher() = default;

int KernelMatcher::fft_cols() const { return impl_->correlator->fft_cols(); }
int KernelMatcher::fft_rows() const { return impl_->correlator->fft_rows(); }

std::size_t KernelMatcher::precompute_bytes() const {
  return impl_->correlator->spectrum_bytes() + plan_raster_.total() + valid_.total() +
         (ces_raster_.data == plan_raster_.data ? 0 : ces_raster_.total()) + search_bytes();
}

std::size_t KernelMatcher::search_bytes() const { return impl_->search ? impl_->search->bytes() : 0; }

const detail::KernelSearchMaps* KernelMatcher::search_maps() const { return impl_->search.get(); }

const cv::Mat& KernelMatcher::distance_weight() const { return impl_->distance_weight; }

MatchResult KernelMatcher::match(const Observation2D& obs, const MatchRequest& request) const {
  const auto t0 = Clock::now();
  const std::vector<double> yaws = orientation_candidates(params_.orientation, orientation_cache_, obs.segments_m);
  const double orient_s = seconds(t0, Clock::now());
  MatchResult r = match_yaws(obs, yaws, request);
  r.stage_s["orientation_candidates"] = orient_s;
  r.match_s = seconds(t0, Clock::now());
  return r;
}

std::vector<double> KernelMatcher::yaw_candidates(const Observation2D& obs) const {
  return orientation_candidates(params_.orientation, orientation_cache_, obs.segments_m);
}

MatchResult KernelMatcher::match_yaws(const Observation2D& obs, const std::vector<double>& yaws) const {
  return match_yaws(obs, yaws, MatchRequest{});
}

double KernelMatcher::cell_score(const Observation2D& obs, double yaw, double scale, int row, int col) const {
  if (!grid_.contains(row, col)) throw std::invalid_argument("KernelMatcher::cell_score: cell outside the grid");
  const int R = impl_->radius_px;
  const LayoutKernels k = make_layout_kernels(params_, obs.segments_m, yaw, scale, R, impl_->distance_weight);
  const double alpha = correlation_alpha(params_.alpha);
  double p = 0.0, ces = 0.0;
  for (int dr = -R; dr <= R; ++dr) {
    const int rr = row + dr;
    if (rr < 0 || rr >= grid_.height_px) continue;
    const std::uint8_t* f = plan_raster_.ptr<std::uint8_t>(rr);
    const std::uint8_t* g = ces_raster_.ptr<std::uint8_t>(rr);
    const float* kp = k.p.ptr<float>(R + dr);
    const float* ke = k.ces.ptr<float>(R + dr);
    for (int dc = -R; dc <= R; ++dc) {
      const int cc = col + dc;
      if (cc < 0 || cc >= grid_.width_px) continue;
      if (f[cc]) p += kp[R + dc];
      if (g[cc]) ces += ke[R + dc];
    }
  }
  return p - alpha * ces;
}

MatchResult KernelMatcher::match_yaws(const Observation2D& obs, const std::vector<double>& yaws,
                                      const MatchRequest& request) const {
  if (request.top_k < 1) throw std::invalid_argument("KernelMatcher: top_k must be >= 1");
  if (request.output == MatchOutput::kModes && impl_->search) return search_modes(obs, yaws, request);
  MatchResult result = posterior_yaws(obs, yaws);
  const auto t = Clock::now();
  finish_from_posterior(result, request);
  result.stage_s["modes"] = seconds(t, Clock::now());
  return result;
}

MatchResult KernelMatcher::search_modes(const Observation2D& obs, const std::vector<double>& yaws,
                                        const MatchRequest& request) const {
  const auto t0 = Clock::now();
  MatchResult result;
  result.grid = grid_;
  const std::size_t S = params_.scales.size();
  std::vector<detail::SearchKernel> kernels(yaws.size() * S);
  std::vector<cv::Mat> lines(kernels.size());
  tbb::enumerable_thread_specific<double> kernel_cpu(0.0);
  tbb::parallel_for(std::size_t{0}, kernels.size(), [&](std::size_t j) {
    const double a = thread_cpu_s();
    kernels[j] = detail::build_search_kernel(params_, obs.segments_m, yaws[j / S], params_.scales[j % S],
                                             impl_->distance_weight, *impl_->search, false, &lines[j]);
    kernel_cpu.local() += thread_cpu_s() - a;
  });
  double kernel_s = 0.0;
  for (double v : kernel_cpu) kernel_s += v;
  const double b = thread_cpu_s();
  detail::SearchRequest sr;
  sr.num_scales = static_cast<int>(S);
  sr.yaw_rad = yaws;
  sr.alpha = correlation_alpha(params_.alpha);
  sr.zero_below = params_.zero_below;
  sr.top_k = request.top_k;
  sr.separation_m = request.mode_separation_m;
  sr.separation_rad = request.mode_separation_rad;
  // P itself only for kernels whose cells get evaluated exactly (most never do).
  double leaf_kernel_s = 0.0;
  int leaf_kernels = 0;
  sr.leaf_data = [&](std::size_t j, detail::SearchKernel& k) {
    const double a = thread_cpu_s();
    detail::add_leaf_data(k, rw_kernel(params_, lines[j], impl_->distance_weight), *impl_->search);
    leaf_kernel_s += thread_cpu_s() - a;
    ++leaf_kernels;
  };
  result.modes = detail::branch_and_bound_modes(*impl_->search, grid_, kernels, sr, &result.counters);
  result.stage_s["search_kernels"] = kernel_s;
  result.stage_s["branch_and_bound"] = thread_cpu_s() - b - leaf_kernel_s;
  result.stage_s["leaf_kernels"] = leaf_kernel_s;
  result.counters["kernels"] = static_cast<double>(kernels.size());
  result.counters["leaf_kernels"] = leaf_kernels;
  result.match_s = seconds(t0, Clock::now());
  return result;
}

MatchResult KernelMatcher::posterior_yaws(const Observation2D& obs, const std::vector<double>& yaws) const {
  const auto t0 = Clock::now();
  MatchResult result;
  result.grid = grid_;
  Posterior& post = result.posterior;
  post.grid = grid_;
  post.yaw_rad = yaws;
  post.scores.resize(yaws.size());

  struct Times {
    double kernels = 0, forward = 0, product = 0, inverse = 0, combine = 0;
  };
  tbb::enumerable_thread_specific<Times> times;
  const int R = impl_->radius_px;
  const float alpha = static_cast<float>(correlation_alpha(params_.alpha));
  const float zero_below = static_cast<float>(params_.zero_below);

  tbb::parallel_for(std::size_t{0}, yaws.size(), [&](std::size_t o) {
    auto& ws = impl_->workspaces.local();
    if (!ws) ws = impl_->correlator->make_workspace();
    Times& tm = times.local();
    cv::Mat best = cv::Mat::zeros(grid_.height_px, grid_.width_px, CV_32F);
    for (double scale : params_.scales) {
      const double a = thread_cpu_s();
      const LayoutKernels k = make_layout_kernels(params_, obs.segments_m, yaws[o], scale, R, impl_->distance_weight);
      FftCorrelator::StageTimes st;
      double b = 0.0;
      if (impl_->correlator->num_maps() == 1) {
        const cv::Mat kernel = k.p - alpha * k.ces;
        b = thread_cpu_s();
        impl_->correlator->run(kernel, *ws, &st);
      } else {
        const cv::Mat ces = -alpha * k.ces;
        b = thread_cpu_s();
        impl_->correlator->run_sum({&k.p, &ces}, *ws, &st);
      }
      const double c = thread_cpu_s();
      // Clip at 0, drop FFT round-off, restrict to the valid area, max over scales.
      for (int row = 0; row < grid_.height_px; ++row) {
        const float* h = impl_->correlator->result_row(*ws, row);
        const std::uint8_t* v = valid_.ptr<std::uint8_t>(row);
        float* out = best.ptr<float>(row);
        for (int col = 0; col < grid_.width_px; ++col) {
          const float x = (v[col] && h[col] >= zero_below) ? h[col] : 0.0f;
          out[col] = std::max(out[col], x);
        }
      }
      tm.kernels += b - a;
      tm.forward += st.forward_s;
      tm.product += st.product_s;
      tm.inverse += st.inverse_s;
      tm.combine += thread_cpu_s() - c;
    }
    post.scores[o] = best;
  });

  Times sum;
  for (const Times& t : times) {
    sum.kernels += t.kernels;
    sum.forward += t.forward;
    sum.product += t.product;
    sum.inverse += t.inverse;
    sum.combine += t.combine;
  }
  // Stage times are thread CPU seconds summed over workers; match_s is wall time.
  result.stage_s["kernel_build"] = sum.kernels;
  result.stage_s["fft_forward"] = sum.forward;
  result.stage_s["spectrum_product"] = sum.product;
  result.stage_s["fft_inverse"] = sum.inverse;
  result.stage_s["clip_mask_max"] = sum.combine;
  result.match_s = seconds(t0, Clock::now());
  return result;
}

}  // namespace floorcast
