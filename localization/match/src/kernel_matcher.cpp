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
const std::vector<std::pair<const char*, ModesSearch>> kModesSearchNames = {
    {"branch_and_bound", ModesSearch::kBranchAndBound}, {"posterior", ModesSearch::kPosterior}};
const std::vector<std::pair<const char*, LineRule>> kLineRuleNamesAll = {
    {"closed", LineRule::kClosed}, {"half_open", LineRule::kHalfOpen}, {"bresenham", LineRule::kBresenham}};
const std::vector<std::pair<const char*, KernelConstruction>> kConstructionNames = {
    {"floorcast", KernelConstruction::kFloorcast}, {"palms_code", KernelConstruction::kPalmsCode}};
const std::vector<std::pair<const char*, MapBorder>> kBorderNames = {{"margin", MapBorder::kMargin},
                                                                     {"reflect", MapBorder::kReflect}};
const std::vector<std::pair<const char*, ValidArea>> kValidAreaNames = {{"free", ValidArea::kFree},
                                                                        {"alpha_shape", ValidArea::kAlphaShape}};
const std::vector<std::pair<const char*, ReportPoint>> kReportPointNames = {{"centre", ReportPoint::kCentre},
                                                                            {"corner", ReportPoint::kCorner}};
const std::vector<std::pair<const char*, ErodeShape>> kErodeShapeNames = {{"square", ErodeShape::kSquare},
                                                                          {"ellipse", ErodeShape::kEllipse}};

/// The modes are found through the posterior (the branch-and-bound search bounds floorcast's
/// kernels on a zero-bordered map only).
bool search_needs_posterior(const KernelMatcherParams& p) {
  return p.kernel_construction == KernelConstruction::kPalmsCode || p.map_border == MapBorder::kReflect;
}

}  // namespace

const FieldList<KernelMatcherParams>& KernelMatcherParams::fields() {
  using P = KernelMatcherParams;
  static const FieldList<P> f =
      FieldList<P>("matcher kernel")
          .number("resolution_m", &P::resolution_m, 0.01, 1.0, "grid resolution, m (PALMS+ configs resolution: 0.1)")
          .number("grid_margin_m", &P::grid_margin_m, 0.0, 100.0, "free margin of the grid around the plan, m")
          .number("max_range_m", &P::max_range_m, 0.5, 100.0,
                  "observation extent the kernels cover, m (default: the shared range; PALMS+ max_dist: 10)")
          .integer("blur_size_px", &P::blur_size_px, 0, 101,
                   "RW Gaussian blur kernel size, px, odd or 0 = none (PALMS+ gaussian_kernel_config: [15, 3])")
          .number("blur_sigma_px", &P::blur_sigma_px, 0.0, 50.0, "RW Gaussian blur sigma, px")
          .number("distance_sigma_m", &P::distance_sigma_m, 0.0, 1e6,
                  "sigma of the RW distance weight around the observer, m, 0 = none (PALMS code: 10)")
          .number("alpha", &P::alpha, 0.0, 1e6, "weight of the CES kernel (PALMS+ sec. 3.3: 10)")
          .number("ces_shrink", &P::ces_shrink, 0.0, 1.0, "CES triangles shrunk about the observer (PALMS code: 0.7)")
          .number("ces_window_m", &P::ces_window_m, 0.0, 100.0, "half-size of the CES square window, m (PALMS code: 10)")
          .integer("ces_erode_px", &P::ces_erode_px, 0, 20, "CES erosion, px (square element; PALMS code: 1)")
          .flatten(&P::orientation, orientation_fields())
          .numbers("scales", &P::scales, 0.1, 10.0, "scale candidates, max-marginalised (PALMS+ sec. 3.3: 0.9, 1, 1.1)")
          .flatten(&P::blocking, blocking_fields())
          .number("zero_below", &P::zero_below, 0.0, 1.0, "FFT round-off guard: heatmap values below it set to 0")
          .choice("plan_raster", &P::plan_raster, kPlanRasterNames,
                  "what the plan raster draws: wall surfaces, wall axes or wall bodies")
          .choice("line_rule", &P::line_rule, kLineRuleNamesAll,
                  "line rasterisation of plan and RW: closed, half_open, bresenham (PALMS; plan_raster.hpp)")
          .flag("ces_through_doorways", &P::ces_through_doorways,
                "the CES is correlated with a plan raster without door leaves (false: PALMS as published)")
          .choice("modes_search", &P::modes_search, kModesSearchNames,
                  "estimate and top-K by the exact branch and bound or from the full posterior")
          .integer("search_levels", &P::search_levels, 1, 10,
                   "levels of the branch and bound's bound maps (changes the time, never the modes)")
          .choice("kernel_construction", &P::kernel_construction, kConstructionNames,
                  "floorcast's kernels or palms_code (the authors' CES.py arithmetic; searched through the posterior)")
          .choice("map_border", &P::map_border, kBorderNames, "margin, or reflect (PALMS: no margin, reflected border)")
          .flag("map_tilt", &P::map_tilt, "PALMS: rotate the plan onto its landscape principal orientation first")
          .choice("valid_area", &P::valid_area, kValidAreaNames, "free space, or alpha_shape (PALMS)")
          .number("alpha_shape_alpha", &P::alpha_shape_alpha, 1e-4, 100.0, "PALMS alpha_shape(alpha)")
          .choice("report_point", &P::report_point, kReportPointNames, "cell centre, or corner (PALMS)")
          .choice("ces_erode_shape", &P::ces_erode_shape, kErodeShapeNames, "CES erosion element: square, or ellipse (PALMS)")
          .check([](const P& p, const ParamReader& r) {
            if (p.blur_size_px > 0 && p.blur_size_px % 2 == 0) r.fail("blur_size_px", "must be odd (or 0 for no blur)");
          });
  return f;
}

nlohmann::ordered_json KernelMatcherParams::to_json() const { return fields().write(*this); }

void KernelMatcherParams::apply_overrides(const nlohmann::json& overrides) { fields().read(*this, overrides); }

void KernelMatcherParams::apply_shared(const SharedParams& shared) {
  max_range_m = shared.range_m;
  blocking = shared.blocking;
}

double correlation_alpha(double alpha) { return alpha >= 1.0 ? std::min(alpha, 1.5) : alpha; }

int kernel_radius_px(const KernelMatcherParams& p) {
  const double max_scale = *std::max_element(p.scales.begin(), p.scales.end());
  const double reach_m = std::max(p.max_range_m * max_scale, p.ces_window_m);
  // palms_code: the authors' kernel is padded by 10 px and placed one pixel off centre (at most
  // 10 + 2 more pixels), its grid rounded up by np.arange and the odd-size rule (2 more).
  const int palms_extra = p.kernel_construction == KernelConstruction::kPalmsCode ? 14 : 0;
  return static_cast<int>(std::ceil(reach_m / p.resolution_m)) + p.blur_size_px / 2 + 1 + palms_extra;
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
    const cv::Mat se = cv::getStructuringElement(
        params.ces_erode_shape == ErodeShape::kEllipse ? cv::MORPH_ELLIPSE : cv::MORPH_RECT, cv::Size(2 * e + 1, 2 * e + 1));
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


namespace {

/// matplotlib Path.contains_points for one triangle (crossing-number test; points exactly on an
/// edge fall to one side or the other, a measure-zero case for real observations).
bool in_triangle(const Vec2& p, const Vec2 (&t)[3]) {
  bool inside = false;
  for (int i = 0, j = 2; i < 3; j = i++) {
    if ((t[i].y() > p.y()) != (t[j].y() > p.y()) &&
        p.x() < (t[j].x() - t[i].x()) * (p.y() - t[i].y()) / (t[j].y() - t[i].y()) + t[i].x())
      inside = !inside;
  }
  return inside;
}

/// np.arange(start, stop, step).size
int arange_size(double start, double stop, double step) {
  return std::max(0, static_cast<int>(std::ceil((stop - start) / step)));
}

}  // namespace

LayoutKernels make_palms_code_kernels(const KernelMatcherParams& params, const std::vector<Segment2>& obs, double yaw,
                                      double scale, int R) {
  const int K = 2 * R + 1;
  LayoutKernels out;
  out.p = cv::Mat::zeros(K, K, CV_32F);
  out.ces = cv::Mat::zeros(K, K, CV_32F);
  if (obs.empty()) return out;
  const double res = params.resolution_m;
  // obs_planes * scale, then CES.rotate(theta): T @ [x, y, 1].
  const double c = std::cos(yaw), s = std::sin(yaw);
  std::vector<std::array<Vec2, 2>> segs;
  for (const Segment2& seg : obs) {
    const Vec2 a = scale * seg.a_m, b = scale * seg.b_m;
    segs.push_back({Vec2(c * a.x() - s * a.y(), s * a.x() + c * a.y()), Vec2(c * b.x() - s * b.y(), s * b.x() + c * b.y())});
  }
  // initialize_kernels: triangles (observer at the origin, a, b), their bounds, the grid.
  double min_x = 0.0, max_x = 0.0, min_y = 0.0, max_y = 0.0;
  for (const auto& g : segs)
    for (const Vec2& v : g) {
      min_x = std::min(min_x, v.x());
      max_x = std::max(max_x, v.x());
      min_y = std::min(min_y, v.y());
      max_y = std::max(max_y, v.y());
    }
  std::vector<double> xs, ys;
  for (int i = 0, n = arange_size(min_x, max_x + res, res); i < n; ++i) xs.push_back(min_x + i * res);
  for (int i = 0, n = arange_size(min_y, max_y + res, res); i < n; ++i) ys.push_back(min_y + i * res);
  if (xs.size() % 2 == 0) xs.push_back(xs.back() + res);
  if (ys.size() % 2 == 0) ys.push_back(ys.back() + res);
  const int kw = static_cast<int>(xs.size()), kh = static_cast<int>(ys.size());
  cv::Mat ces(kh, kw, CV_64F, cv::Scalar(0.0));
  for (const auto& g : segs) {
    const Vec2 tri[3] = {Vec2::Zero(), g[0], g[1]};
    for (int r = 0; r < kh; ++r)
      for (int q = 0; q < kw; ++q)
        if (in_triangle(Vec2(xs[static_cast<std::size_t>(q)], ys[static_cast<std::size_t>(r)]), tri)) ces.at<double>(r, q) = 1.0;
  }
  // seg_kernel: PALMS' Bresenham of (end - min) / cell_size.
  cv::Mat lines = cv::Mat::zeros(kh, kw, CV_8U);
  for (const auto& g : segs)
    draw_bresenham_line(lines, (g[0].x() - min_x) / res, (g[0].y() - min_y) / res, (g[1].x() - min_x) / res,
                        (g[1].y() - min_y) / res);
  constexpr int kPad = 10;
  cv::Mat seg;
  lines.convertTo(seg, CV_64F, 1.0 / 255.0);
  cv::copyMakeBorder(seg, seg, kPad, kPad, kPad, kPad, cv::BORDER_CONSTANT, cv::Scalar(0.0));
  // Shrink: the whole image resized (nearest) and re-padded so the observer's truncated index
  // stays put.
  const int new_h = static_cast<int>(kh * params.ces_shrink), new_w = static_cast<int>(kw * params.ces_shrink);
  const int x_obs = static_cast<int>((0.0 - min_x) / res), y_obs = static_cast<int>((0.0 - min_y) / res);
  cv::Mat shrunk_full(kh, kw, CV_64F, cv::Scalar(0.0));
  if (new_h > 0 && new_w > 0) {
    cv::Mat shrunk;
    cv::resize(ces, shrunk, cv::Size(new_w, new_h), 0, 0, cv::INTER_NEAREST);
    const int top = y_obs - static_cast<int>(y_obs * params.ces_shrink);
    const int left = x_obs - static_cast<int>(x_obs * params.ces_shrink);
    for (int r = 0; r < new_h; ++r)
      for (int q = 0; q < new_w; ++q)
        if (r + top < kh && q + left < kw) shrunk_full.at<double>(r + top, q + left) = shrunk.at<double>(r, q);
  }
  cv::Mat ces_p;
  cv::copyMakeBorder(shrunk_full, ces_p, kPad, kPad, kPad, kPad, cv::BORDER_CONSTANT, cv::Scalar(0.0));
  const double min_x_p = min_x - kPad * res, min_y_p = min_y - kPad * res;
  const int H = kh + 2 * kPad, W = kw + 2 * kPad;
  // mode 'weighted': blur, distance weighting at the observer's fractional position, square
  // window (centred on the unpadded index, as the code does), erosion.
  if (params.blur_size_px > 1 && params.blur_sigma_px > 0.0)
    cv::GaussianBlur(seg, seg, cv::Size(params.blur_size_px, params.blur_size_px), params.blur_sigma_px, params.blur_sigma_px);
  if (params.distance_sigma_m > 0.0) {
    const double sigma = params.distance_sigma_m / res;
    cv::Mat g(H, W, CV_64F);
    double gmax = 0.0;
    for (int r = 0; r < H; ++r)
      for (int q = 0; q < W; ++q) {
        const double X = q - (-min_x_p / res), Y = r - (-min_y_p / res);
        const double v = std::exp(-((X * X) / (2 * sigma * sigma) + (Y * Y) / (2 * sigma * sigma)));
        g.at<double>(r, q) = v;
        gmax = std::max(gmax, v);
      }
    seg = seg.mul(g / gmax);
  }
  {
    const int md = static_cast<int>(params.ces_window_m / res);
    const int x1 = std::max(x_obs - md, 0), x2 = std::min(x_obs + md, W);
    const int y1 = std::max(y_obs - md, 0), y2 = std::min(y_obs + md, H);
    cv::Mat mask = cv::Mat::zeros(H, W, CV_64F);
    if (x2 > x1 && y2 > y1) mask(cv::Rect(x1, y1, x2 - x1, y2 - y1)).setTo(1.0);
    ces_p = ces_p.mul(mask);
  }
  cv::Mat ces8;
  ces_p.convertTo(ces8, CV_8U);
  if (params.ces_erode_px > 0) {
    const int e = params.ces_erode_px;
    const cv::Mat se = cv::getStructuringElement(
        params.ces_erode_shape == ErodeShape::kEllipse ? cv::MORPH_ELLIPSE : cv::MORPH_RECT, cv::Size(2 * e + 1, 2 * e + 1));
    cv::erode(ces8, ces8, se);
  }
  // normalize_heatmap(seg, as_prob_distribution=True): min-max, divided by the sum, values below
  // 1e-8 lifted by 1e-8 and the rest scaled so the sum stays 1.
  cv::Mat P;
  double mn = 0.0, mx = 0.0;
  cv::minMaxLoc(seg, &mn, &mx);
  if (!(mx > mn)) {
    P = cv::Mat(H, W, CV_64F, cv::Scalar(1.0 / (H * W)));
  } else {
    P = (seg - mn) / (mx - mn);
    P /= cv::sum(P)[0];
    constexpr double kEps = 1e-8;
    const double below = static_cast<double>(cv::countNonZero(P < kEps));
    for (int r = 0; r < H; ++r)
      for (int q = 0; q < W; ++q) {
        double& v = P.at<double>(r, q);
        v = v < kEps ? v + kEps : v * (1.0 - below * kEps);
      }
  }
  // create_heatmap: filter2D (anchor at the padded kernel's centre), then shift by
  // (bot - kh // 2 - 9, left - kw // 2 - 9): heatmap(p) = sum_k kernel[k] map[p - shift + k -
  // anchor], i.e. kernel pixel (bot, left) (the observer's truncated index) one pixel before the
  // centre of a centred kernel.
  const int bot = static_cast<int>(std::abs(min_y_p - 0.0) / res), left = static_cast<int>(std::abs(min_x_p - 0.0) / res);
  out.shift_row = bot - kh / 2 - 9;
  out.shift_col = left - kw / 2 - 9;
  for (int r = 0; r < H; ++r) {
    const int gr = R + r - bot - 1;
    if (gr < 0 || gr >= K) continue;
    for (int q = 0; q < W; ++q) {
      const int gc = R + q - left - 1;
      if (gc < 0 || gc >= K) continue;
      out.p.at<float>(gr, gc) = static_cast<float>(P.at<double>(r, q));
      out.ces.at<float>(gr, gc) = ces8.at<std::uint8_t>(r, q) ? 1.0f : 0.0f;
    }
  }
  return out;
}

struct KernelMatcher::Impl {
  std::unique_ptr<FftCorrelator> correlator;
  std::unique_ptr<detail::KernelSearchMaps> search;
  int radius_px = 0;
  cv::Mat distance_weight;
  std::vector<Segment2> plan_segments;
  mutable tbb::enumerable_thread_specific<std::unique_ptr<FftCorrelator::Workspace>> workspaces;
};

KernelMatcher::KernelMatcher(const FloorPlan& world_plan, const KernelMatcherParams& params)
    : params_(params), impl_(std::make_unique<Impl>()) {
  if (params_.scales.empty()) throw InputError("matcher kernel: no scale candidates");
  const auto t0 = Clock::now();
  // map_tilt: the matcher works on the plan turned onto the raster axes (PALMS'
  // rotate_segments_to_landscape); poses and posteriors go back to the world in to_world().
  FloorPlan tilted;
  if (params_.map_tilt) {
    tilt_rad_ = palms_landscape_rotation_rad(footprint_centrelines(blocking_footprints(world_plan, params_.blocking)));
    tilted = rotate_plan(world_plan, tilt_rad_);
  }
  const FloorPlan& plan = params_.map_tilt ? tilted : world_plan;
  const LineRule rule = params_.line_rule;
  // The segments the plan raster draws (wall surfaces or wall axes).
  auto raster_segments = [&](const BlockingOptions& blocking) {
    return params_.plan_raster == PlanRasterKind::kCentreline ? footprint_centrelines(blocking_footprints(plan, blocking))
                                                              : outline_segments(blocking_outline(plan, blocking));
  };
  if (params_.map_border == MapBorder::kReflect) {
    // PALMS: the raster spans the drawn lines exactly (origin at their smallest corner, no margin).
    double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
    for (const Segment2& sg : raster_segments(params_.blocking))
      for (const Vec2& v : {sg.a_m, sg.b_m}) {
        x0 = std::min(x0, v.x());
        y0 = std::min(y0, v.y());
        x1 = std::max(x1, v.x());
        y1 = std::max(y1, v.y());
      }
    if (!(x1 >= x0 && y1 >= y0)) throw InputError("matcher kernel: the plan draws no wall line");
    grid_.resolution_m_per_px = params_.resolution_m;
    grid_.origin_x_m = x0;
    grid_.origin_y_m = y0;
    grid_.width_px = std::max(1, static_cast<int>(std::ceil((x1 - x0) / params_.resolution_m)));
    grid_.height_px = std::max(1, static_cast<int>(std::ceil((y1 - y0) / params_.resolution_m)));
  } else {
    grid_ = grid_for_plan(plan, params_.resolution_m, params_.grid_margin_m);
  }
  output_grid_ = params_.map_tilt ? grid_for_plan(world_plan, params_.resolution_m, params_.grid_margin_m) : grid_;
  impl_->radius_px = kernel_radius_px(params_);
  if (params_.map_border == MapBorder::kReflect) border_px_ = impl_->radius_px;
  {
    // Memory refused before any raster is allocated: the plan, CES and valid rasters, their float
    // copies and spectra, per-thread FFT workspaces, and one posterior slice per candidate yaw.
    const OrientationParams& o = params_.orientation;
    const double yaws = o.mode == OrientationMode::kDense ? std::ceil(360.0 / o.dense_step_deg) : 4.0 * o.num_orientations;
    GridSpec padded = grid_;
    padded.width_px += 2 * border_px_;
    padded.height_px += 2 * border_px_;
    check_raster_budget(padded, 64.0 + 4.0 * yaws, "matcher kernel");
  }
  const std::vector<LabeledSegment> outline = blocking_outline(plan, params_.blocking);
  impl_->plan_segments = outline_segments(outline);
  auto raster = [&](const BlockingOptions& blocking) {
    if (params_.plan_raster == PlanRasterKind::kOutline) return rasterize_outline(blocking_outline(plan, blocking), grid_, rule);
    if (params_.plan_raster == PlanRasterKind::kCentreline) {
      // Half-open (unless Bresenham): wall axes of generated and imported plans lie on multiples
      // of the resolution, i.e. on pixel boundaries, where the closed rule draws 2-px lines (every
      // wall counted twice, twice as wide as in PALMS' 1-px line rasters).
      cv::Mat m = cv::Mat::zeros(grid_.height_px, grid_.width_px, CV_8U);
      draw_segment_lines(m, raster_segments(blocking), {grid_.origin_x_m, grid_.origin_y_m}, grid_.resolution_m_per_px,
                         rule == LineRule::kBresenham ? LineRule::kBresenham : LineRule::kHalfOpen);
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
  if (params_.valid_area == ValidArea::kAlphaShape) {
    valid_ = alpha_shape_mask(footprint_centrelines(blocking_footprints(plan, params_.blocking)), params_.alpha_shape_alpha,
                              1.0, grid_, params_.report_point == ReportPoint::kCorner ? 0.0 : 0.5);
  } else {
    valid_ = matcher_valid_mask(plan, grid_, params_.blocking);
  }
  orientation_cache_ = make_plan_orientation_cache(params_.orientation, impl_->plan_segments);
  impl_->distance_weight = distance_weight_image(params_, impl_->radius_px);
  // The correlated maps; with map_border reflect each is reflected (BORDER_REFLECT_101, as
  // cv2.filter2D) by the kernel radius on every side.
  auto correlated = [&](const cv::Mat& raster_8u) {
    cv::Mat f;
    raster_8u.convertTo(f, CV_32F, 1.0 / 255.0);
    if (border_px_ > 0) cv::copyMakeBorder(f, f, border_px_, border_px_, border_px_, border_px_, cv::BORDER_REFLECT_101);
    return f;
  };
  const cv::Mat plan_f = correlated(plan_raster_);
  if (ces_raster_.data == plan_raster_.data) {
    impl_->correlator = std::make_unique<FftCorrelator>(plan_f, impl_->radius_px);
  } else {
    // Two maps: the wall score on plan_raster_, the CES collision on ces_raster_ (one sum).
    impl_->correlator = std::make_unique<FftCorrelator>(std::vector<cv::Mat>{plan_f, correlated(ces_raster_)}, impl_->radius_px);
  }
  if (params_.modes_search == ModesSearch::kBranchAndBound && !search_needs_posterior(params_)) {
    impl_->search = std::make_unique<detail::KernelSearchMaps>(plan_raster_, ces_raster_, valid_, impl_->radius_px,
                                                               params_.search_levels, params_.blur_size_px,
                                                               params_.blur_sigma_px);
  }
  precompute_s_ = seconds(t0, Clock::now());
}

KernelMatcher::~KernelMatcher() = default;

int KernelMatcher::fft_cols() const { return impl_->correlator->fft_cols(); }
int KernelMatcher::fft_rows() const { return impl_->correlator->fft_rows(); }

std::vector<std::string> KernelMatcher::notes() const {
  return orientation_notes(params_.orientation, orientation_cache_.histogram);
}

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
  MatchResult r = match_frame(obs, yaws, request);
  to_world(r);
  r.stage_s["orientation_candidates"] = orient_s;
  r.match_s = seconds(t0, Clock::now());
  return r;
}

std::vector<double> KernelMatcher::yaw_candidates(const Observation2D& obs) const {
  std::vector<double> yaws = orientation_candidates(params_.orientation, orientation_cache_, obs.segments_m);
  if (tilt_rad_ != 0.0)
    for (double& y : yaws) y = wrap_2pi(y - tilt_rad_);
  return yaws;
}

MatchResult KernelMatcher::match_yaws(const Observation2D& obs, const std::vector<double>& yaws) const {
  return match_yaws(obs, yaws, MatchRequest{});
}

MatchResult KernelMatcher::match_yaws(const Observation2D& obs, const std::vector<double>& world_yaws,
                                      const MatchRequest& request) const {
  std::vector<double> yaws = world_yaws;
  if (tilt_rad_ != 0.0)
    for (double& y : yaws) y += tilt_rad_;
  MatchResult r = match_frame(obs, yaws, request);
  to_world(r);
  return r;
}

void KernelMatcher::to_world(MatchResult& result) const {
  const double res = grid_.resolution_m_per_px;
  const double shift = params_.report_point == ReportPoint::kCorner ? -0.5 * res : 0.0;
  const double c = std::cos(-tilt_rad_), s = std::sin(-tilt_rad_);
  for (PoseHypothesis& h : result.modes) {
    const double x = h.x_m + shift, y = h.y_m + shift;
    if (tilt_rad_ == 0.0) {
      h.x_m = x;
      h.y_m = y;
      continue;
    }
    h.x_m = c * x - s * y;
    h.y_m = s * x + c * y;
    h.yaw_rad = wrap_2pi(h.yaw_rad - tilt_rad_);
  }
  if (tilt_rad_ == 0.0) return;
  // Posteriors onto the plan's own grid: each output cell takes the frame cell under its centre.
  const GridSpec& out = output_grid_;
  cv::Mat map_x(out.height_px, out.width_px, CV_32F), map_y(out.height_px, out.width_px, CV_32F);
  const double ct = std::cos(tilt_rad_), st = std::sin(tilt_rad_);
  for (int r = 0; r < out.height_px; ++r)
    for (int q = 0; q < out.width_px; ++q) {
      const Vec2 w = out.cell_center_m(r, q);
      const Vec2 f(ct * w.x() - st * w.y(), st * w.x() + ct * w.y());
      map_x.at<float>(r, q) = static_cast<float>((f.x() - grid_.origin_x_m) / res - 0.5);
      map_y.at<float>(r, q) = static_cast<float>((f.y() - grid_.origin_y_m) / res - 0.5);
    }
  auto resample = [&](const cv::Mat& m) {
    cv::Mat o;
    cv::remap(m, o, map_x, map_y, cv::INTER_NEAREST, cv::BORDER_CONSTANT, cv::Scalar(0));
    return o;
  };
  for (cv::Mat& slice : result.posterior.scores) slice = resample(slice);
  for (double& y : result.posterior.yaw_rad) y = wrap_2pi(y - tilt_rad_);
  if (!result.posterior.scores.empty()) result.posterior.grid = out;
  if (!result.max_over_yaw.empty()) result.max_over_yaw = resample(result.max_over_yaw);
  result.grid = out;
}

double KernelMatcher::cell_score(const Observation2D& obs, double yaw, double scale, int row, int col) const {
  if (!grid_.contains(row, col)) throw std::invalid_argument("KernelMatcher::cell_score: cell outside the grid");
  const int R = impl_->radius_px;
  const bool palms = params_.kernel_construction == KernelConstruction::kPalmsCode;
  const LayoutKernels k = palms ? make_palms_code_kernels(params_, obs.segments_m, yaw, scale, R)
                                : make_layout_kernels(params_, obs.segments_m, yaw, scale, R, impl_->distance_weight);
  // palms_code: 0 where create_heatmap's shift brings in nothing.
  if (palms && !grid_.contains(row - k.shift_row, col - k.shift_col)) return 0.0;
  const double alpha = correlation_alpha(params_.alpha);
  const bool reflect = params_.map_border == MapBorder::kReflect;
  double p = 0.0, ces = 0.0;
  for (int dr = -R; dr <= R; ++dr) {
    int rr = row + dr;
    if (reflect) rr = cv::borderInterpolate(rr, grid_.height_px, cv::BORDER_REFLECT_101);
    if (rr < 0 || rr >= grid_.height_px) continue;
    const std::uint8_t* f = plan_raster_.ptr<std::uint8_t>(rr);
    const std::uint8_t* g = ces_raster_.ptr<std::uint8_t>(rr);
    const float* kp = k.p.ptr<float>(R + dr);
    const float* ke = k.ces.ptr<float>(R + dr);
    for (int dc = -R; dc <= R; ++dc) {
      int cc = col + dc;
      if (reflect) cc = cv::borderInterpolate(cc, grid_.width_px, cv::BORDER_REFLECT_101);
      if (cc < 0 || cc >= grid_.width_px) continue;
      if (f[cc]) p += kp[R + dc];
      if (g[cc]) ces += ke[R + dc];
    }
  }
  return p - alpha * ces;
}

MatchResult KernelMatcher::match_frame(const Observation2D& obs, const std::vector<double>& yaws,
                                       const MatchRequest& request) const {
  if (request.top_k < 1) throw std::invalid_argument("KernelMatcher: top_k must be >= 1");
  if (request.output == MatchOutput::kModes && impl_->search) return search_modes(obs, yaws, request);
  MatchResult result = posterior_yaws(obs, yaws);
  const auto t = Clock::now();
  finish_from_posterior(result, request);
  result.stage_s["modes"] = seconds(t, Clock::now());
  return result;
}

std::vector<detail::SearchKernel> KernelMatcher::search_kernels(const Observation2D& obs, const std::vector<double>& yaws,
                                                               std::vector<cv::Mat>& lines, double& kernel_s) const {
  const std::size_t S = params_.scales.size();
  std::vector<detail::SearchKernel> kernels(yaws.size() * S);
  lines.assign(kernels.size(), cv::Mat());
  tbb::enumerable_thread_specific<double> kernel_cpu(0.0);
  tbb::parallel_for(std::size_t{0}, kernels.size(), [&](std::size_t j) {
    const double a = thread_cpu_s();
    kernels[j] = detail::build_search_kernel(params_, obs.segments_m, yaws[j / S], params_.scales[j % S],
                                             impl_->distance_weight, *impl_->search, false, &lines[j]);
    kernel_cpu.local() += thread_cpu_s() - a;
  });
  kernel_s = 0.0;
  for (double v : kernel_cpu) kernel_s += v;
  return kernels;
}

void KernelMatcher::search_with(std::vector<detail::SearchKernel>& kernels, const std::vector<cv::Mat>& lines,
                                const std::vector<double>& yaws, const MatchRequest& request, MatchResult& result) const {
  const double b = thread_cpu_s();
  detail::SearchRequest sr;
  sr.num_scales = static_cast<int>(params_.scales.size());
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
  result.stage_s["branch_and_bound"] = thread_cpu_s() - b - leaf_kernel_s;
  result.stage_s["leaf_kernels"] = leaf_kernel_s;
  result.counters["kernels"] = static_cast<double>(kernels.size());
  result.counters["leaf_kernels"] = leaf_kernels;
}

MatchResult KernelMatcher::search_modes(const Observation2D& obs, const std::vector<double>& yaws,
                                        const MatchRequest& request) const {
  const auto t0 = Clock::now();
  MatchResult result;
  result.grid = grid_;
  std::vector<cv::Mat> lines;
  double kernel_s = 0.0;
  std::vector<detail::SearchKernel> kernels = search_kernels(obs, yaws, lines, kernel_s);
  search_with(kernels, lines, yaws, request, result);
  result.stage_s["search_kernels"] = kernel_s;
  result.match_s = seconds(t0, Clock::now());
  return result;
}

PosteriorQuery KernelMatcher::query(const Observation2D& obs) const {
  // The search's maps score cells directly in the matcher's frame on the output grid; tilted
  // plans and the variants searched through the posterior look the full posterior up instead.
  if (!impl_->search || tilt_rad_ != 0.0) return Matcher::query(obs);
  const std::vector<double> yaws = orientation_candidates(params_.orientation, orientation_cache_, obs.segments_m);
  // The kernels of every (orientation, scale), shared by the maximum's search and the scorer.
  struct Kernels {
    std::vector<detail::SearchKernel> kernels;
    std::vector<cv::Mat> lines;
    std::mutex mutex;
  };
  auto state = std::make_shared<Kernels>();
  double kernel_s = 0.0;
  state->kernels = search_kernels(obs, yaws, state->lines, kernel_s);
  MatchResult best;
  search_with(state->kernels, state->lines, yaws, MatchRequest::modes(1), best);
  // The posterior's maximum: the best mode's score as the posterior stores it (float).
  const double max_score = best.modes.empty() ? 0.0 : static_cast<double>(static_cast<float>(best.modes.front().score));
  const int S = static_cast<int>(params_.scales.size());
  auto scorer = [this, state, S](const std::vector<PosteriorCell>& cells, float* out) {
    {
      // P of the kernels of the asked slices (those the search did not evaluate yet).
      std::lock_guard<std::mutex> lock(state->mutex);
      std::vector<char> asked(state->kernels.size() / static_cast<std::size_t>(S), 0);
      for (const PosteriorCell& c : cells) asked[static_cast<std::size_t>(c.slice)] = 1;
      std::vector<std::size_t> todo;
      for (std::size_t o = 0; o < asked.size(); ++o)
        for (int s = 0; asked[o] && s < S; ++s)
          if (!state->kernels[o * S + static_cast<std::size_t>(s)].has_leaf_data) todo.push_back(o * S + static_cast<std::size_t>(s));
      tbb::parallel_for(std::size_t{0}, todo.size(), [&](std::size_t i) {
        detail::add_leaf_data(state->kernels[todo[i]], rw_kernel(params_, state->lines[todo[i]], impl_->distance_weight),
                              *impl_->search);
      });
    }
    // Each cell as posterior_yaws scores it: max over scales of the value clipped at zero_below,
    // 0 outside the valid area; the value summed directly (exact_cell_score, as the search).
    const double alpha = correlation_alpha(params_.alpha);
    const float zero_below = static_cast<float>(params_.zero_below);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells.size(), 16), [&](const tbb::blocked_range<std::size_t>& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        const PosteriorCell& c = cells[i];
        float v = 0.0f;
        if (valid_.at<std::uint8_t>(c.row, c.col)) {
          for (int s = 0; s < S; ++s) {
            const detail::SearchKernel& k = state->kernels[static_cast<std::size_t>(c.slice) * S + static_cast<std::size_t>(s)];
            const float h = static_cast<float>(detail::exact_cell_score(*impl_->search, k, alpha, c.row, c.col));
            if (h >= zero_below) v = std::max(v, h);
          }
        }
        out[i] = v;
      }
    });
  };
  Observation2D copy = obs;
  auto full = [this, copy = std::move(copy), yaws]() { return posterior_yaws(copy, yaws).posterior; };
  return PosteriorQuery(grid_, yaws, max_score, scorer, full);
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
      const LayoutKernels k = params_.kernel_construction == KernelConstruction::kPalmsCode
                                  ? make_palms_code_kernels(params_, obs.segments_m, yaws[o], scale, R)
                                  : make_layout_kernels(params_, obs.segments_m, yaws[o], scale, R, impl_->distance_weight);
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
      // Clip at 0, drop FFT round-off, restrict to the valid area (and, palms_code, to where the
      // shifted heatmap has values), max over scales.
      const int r0 = std::max(0, k.shift_row), r1 = std::min(grid_.height_px, grid_.height_px + k.shift_row);
      const int c0 = std::max(0, k.shift_col), c1 = std::min(grid_.width_px, grid_.width_px + k.shift_col);
      for (int row = r0; row < r1; ++row) {
        const float* h = impl_->correlator->result_row(*ws, row + border_px_) + border_px_;
        const std::uint8_t* v = valid_.ptr<std::uint8_t>(row);
        float* out = best.ptr<float>(row);
        for (int col = c0; col < c1; ++col) {
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
