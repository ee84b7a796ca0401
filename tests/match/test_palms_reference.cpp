// The PALMS authors' published layout-matching arithmetic as a slow reference (issue 20 item 3):
// layout_matching_module/CES.py (ConvCES.initialize_kernels, create_heatmap with kernel 'com')
// and test_pp.py's loop (scales, orientation candidates, np.where(map_mask), max over scales,
// argmax over (orientation, row, col)), written out step by step as the Python does them: kernel
// grids from np.arange, matplotlib-style point-in-triangle, cv2.resize / GaussianBlur / erode /
// filter2D (BORDER_REFLECT_101, anchor at the kernel centre) and scipy.ndimage.shift. Its inputs
// are the binary map and valid mask the kernel matcher builds in its PALMS mode (PALMS' Bresenham
// centre lines, no margin, alpha-shape mask), so what is compared is the arithmetic from
// observation to pose. The matcher (FFT correlation of the authors' kernels embedded one pixel off
// centre) must pick the same pose on >= 95% of seeded observations; the rest must be ties within
// single-precision FFT round-off.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>

#include <opencv2/imgproc.hpp>

#include "floorcast/core/math.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/match/kernel_matcher.hpp"
#include "floorcast/match/plan_raster.hpp"
#include "floorcast/sim/perfect_observation.hpp"
#include "match_test_plans.hpp"

namespace floorcast {
namespace {

struct RefConvCes {
  cv::Mat ces;  ///< CV_8U 0/1 (after erosion), padded
  cv::Mat seg;  ///< CV_64F, padded, blurred and weighted
  int kernel_h = 0, kernel_w = 0;  ///< kernel_shape (unpadded)
  double min_x = 0, min_y = 0;     ///< after the padding correction
  double max_x = 0, max_y = 0;
};

/// ConvCES(obs_segments, resolution, mode='weighted', gaussian_kernel_config).initialize_kernels.
RefConvCes ref_initialize_kernels(const std::vector<std::array<Vec2, 2>>& segs, double resolution, int blur_k,
                                  double blur_sigma) {
  RefConvCes k;
  // triangles = [[obs_point, s0, s1]]; bounds over every vertex.
  k.min_x = k.max_x = k.min_y = k.max_y = 0.0;
  for (const auto& s : segs)
    for (const Vec2& v : s) {
      k.min_x = std::min(k.min_x, v.x());
      k.max_x = std::max(k.max_x, v.x());
      k.min_y = std::min(k.min_y, v.y());
      k.max_y = std::max(k.max_y, v.y());
    }
  // x = np.arange(min_x, max_x + resolution, resolution); odd lengths.
  std::vector<double> x, y;
  for (double v = 0; static_cast<int>(x.size()) < static_cast<int>(std::ceil((k.max_x + resolution - k.min_x) / resolution)); v += 1)
    x.push_back(k.min_x + v * resolution);
  for (double v = 0; static_cast<int>(y.size()) < static_cast<int>(std::ceil((k.max_y + resolution - k.min_y) / resolution)); v += 1)
    y.push_back(k.min_y + v * resolution);
  if (x.size() % 2 == 0) x.push_back(x.back() + resolution);
  if (y.size() % 2 == 0) y.push_back(y.back() + resolution);
  k.kernel_h = static_cast<int>(y.size());
  k.kernel_w = static_cast<int>(x.size());
  // CES_kernel: Path(triangle).contains_points over the meshgrid, OR over triangles.
  cv::Mat ces(k.kernel_h, k.kernel_w, CV_64F, cv::Scalar(0));
  for (const auto& s : segs) {
    const Vec2 tri[3] = {Vec2(0, 0), s[0], s[1]};
    for (int r = 0; r < k.kernel_h; ++r)
      for (int c = 0; c < k.kernel_w; ++c) {
        const double px = x[static_cast<std::size_t>(c)], py = y[static_cast<std::size_t>(r)];
        bool inside = false;  // crossing-number test, as matplotlib's point_in_path
        for (int i = 0, j = 2; i < 3; j = i++)
          if ((tri[i].y() > py) != (tri[j].y() > py) &&
              px < (tri[j].x() - tri[i].x()) * (py - tri[i].y()) / (tri[j].y() - tri[i].y()) + tri[i].x())
            inside = !inside;
        if (inside) ces.at<double>(r, c) = 1.0;
      }
  }
  // seg_kernel: Bresenham(cell_size).seg(x0 - min_x, y0 - min_y, x1 - min_x, y1 - min_y).
  cv::Mat seg8 = cv::Mat::zeros(k.kernel_h, k.kernel_w, CV_8U);
  for (const auto& s : segs) {
    auto rounder = [&](double v) { return std::max(0.0, std::floor(v / resolution)); };
    double x0 = rounder(s[0].x() - k.min_x), y0 = rounder(s[0].y() - k.min_y);
    const double x1 = rounder(s[1].x() - k.min_x), y1 = rounder(s[1].y() - k.min_y);
    const double dx = std::abs(x1 - x0), dy = std::abs(y1 - y0), sx = x0 > x1 ? -1 : 1, sy = y0 > y1 ? -1 : 1;
    std::vector<std::pair<double, double>> pts;
    double xx = x0, yy = y0;
    if (dx > dy) {
      double err = dx / 2.0;
      while (xx != x1) {
        pts.emplace_back(xx, yy);
        err -= dy;
        if (err < 0) {
          yy += sy;
          err += dx;
          pts.emplace_back(xx, yy);
        }
        xx += sx;
      }
    } else {
      double err = dy / 2.0;
      while (yy != y1) {
        pts.emplace_back(xx, yy);
        err -= dx;
        if (err < 0) {
          xx += sx;
          err += dy;
          pts.emplace_back(xx, yy);
        }
        yy += sy;
      }
    }
    pts.emplace_back(xx, yy);
    for (const auto& [px, py] : pts)
      if (0 <= px && px < k.kernel_w && 0 <= py && py < k.kernel_h) seg8.at<std::uint8_t>(static_cast<int>(py), static_cast<int>(px)) = 1;
  }
  cv::Mat seg;
  seg8.convertTo(seg, CV_64F);
  const int pad = 10;
  cv::copyMakeBorder(seg, seg, pad, pad, pad, pad, cv::BORDER_CONSTANT, 0);
  // Shrink factor 0.7: resize (nearest), re-pad around (x, y) = int((obs - min) / resolution).
  const double shrink = 0.7;
  const int new_h = static_cast<int>(static_cast<std::int16_t>(k.kernel_h * shrink));
  const int new_w = static_cast<int>(static_cast<std::int16_t>(k.kernel_w * shrink));
  cv::Mat shrunk;
  cv::resize(ces, shrunk, cv::Size(new_w, new_h), 0, 0, cv::INTER_NEAREST);
  const int xo = static_cast<int>((0 - k.min_x) / resolution), yo = static_cast<int>((0 - k.min_y) / resolution);
  const int new_x = static_cast<int>(xo * shrink), new_y = static_cast<int>(yo * shrink);
  const int top = yo - new_y, bottom = k.kernel_h - new_h - top, left = xo - new_x, right = k.kernel_w - new_w - left;
  cv::Mat padded;
  cv::copyMakeBorder(shrunk, padded, top, bottom, left, right, cv::BORDER_CONSTANT, 0);
  cv::copyMakeBorder(padded, ces, pad, pad, pad, pad, cv::BORDER_CONSTANT, 0);
  k.min_x -= pad * resolution;
  k.min_y -= pad * resolution;
  // mode 'weighted'
  cv::GaussianBlur(seg, seg, cv::Size(blur_k, blur_k), blur_sigma, blur_sigma);
  {
    const double sigma = 10 / resolution;
    cv::Mat g(seg.rows, seg.cols, CV_64F);
    for (int r = 0; r < seg.rows; ++r)
      for (int c = 0; c < seg.cols; ++c) {
        const double X = c - (-k.min_x / resolution), Y = r - (-k.min_y / resolution);
        g.at<double>(r, c) = std::exp(-((X * X) / (2 * sigma * sigma) + (Y * Y) / (2 * sigma * sigma)));
      }
    double gmax = 0;
    cv::minMaxLoc(g, nullptr, &gmax);
    g /= gmax;
    seg = seg.mul(g);
  }
  {
    const int md = static_cast<int>(10 / resolution);  // apply_square_mask(center=(x, y), 10 / resolution)
    cv::Mat mask = cv::Mat::zeros(ces.rows, ces.cols, CV_64F);
    const int x1 = std::max(xo - md, 0), x2 = std::min(xo + md, ces.cols), y1 = std::max(yo - md, 0), y2 = std::min(yo + md, ces.rows);
    for (int r = y1; r < y2; ++r)
      for (int c = x1; c < x2; ++c) mask.at<double>(r, c) = 1;
    ces = ces.mul(mask);
  }
  ces.convertTo(k.ces, CV_8U);
  cv::erode(k.ces, k.ces, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(3, 3)));
  k.seg = seg;
  return k;
}

/// normalize_heatmap(heatmap, as_prob_distribution=True).
cv::Mat ref_normalize(const cv::Mat& h) {
  double mn, mx;
  cv::minMaxLoc(h, &mn, &mx);
  if (mn == mx) return cv::Mat(h.size(), CV_64F, cv::Scalar(1.0 / h.total()));
  cv::Mat n = (h - mn) / (mx - mn);
  n /= cv::sum(n)[0];
  const double eps = 1e-8;
  const cv::Mat mask = n < eps;
  const double count = cv::countNonZero(mask);
  for (int r = 0; r < n.rows; ++r)
    for (int c = 0; c < n.cols; ++c) {
      double& v = n.at<double>(r, c);
      if (mask.at<std::uint8_t>(r, c)) {
        v += eps;
      } else {
        v *= 1 - count * eps;
      }
    }
  return n;
}

/// create_heatmap(binary_fp, kernel='com', alpha): filter2D, clip at 0, shift.
cv::Mat ref_create_heatmap(const cv::Mat& binary_fp, const RefConvCes& k, double resolution, double alpha) {
  cv::Mat ces;
  k.ces.convertTo(ces, CV_64F);
  const cv::Mat combined = -alpha * ces + ref_normalize(k.seg);
  cv::Mat fp32, heatmap;
  binary_fp.convertTo(fp32, CV_32F);
  cv::filter2D(fp32, heatmap, -1, combined);
  heatmap = cv::max(heatmap, 0.0f);
  const int bot = static_cast<int>(std::abs(k.min_y - 0) / resolution);
  const int left = static_cast<int>(std::abs(k.min_x - 0) / resolution);
  const int dy = bot - k.kernel_h / 2 - 9, dx = left - k.kernel_w / 2 - 9;
  // scipy.ndimage.shift(heatmap, (dy, dx), order=1, mode='constant', cval=0): integer shift.
  cv::Mat out = cv::Mat::zeros(heatmap.size(), CV_32F);
  for (int r = 0; r < out.rows; ++r)
    for (int c = 0; c < out.cols; ++c) {
      const int sr = r - dy, sc = c - dx;
      if (sr >= 0 && sr < heatmap.rows && sc >= 0 && sc < heatmap.cols) out.at<float>(r, c) = heatmap.at<float>(sr, sc);
    }
  return out;
}

struct RefResult {
  int orientation = 0, row = 0, col = 0;
  std::vector<cv::Mat> final_heatmap;  ///< per orientation, max over scales (masked)
};

/// test_pp.py's PALMS+ loop for one observation.
RefResult ref_localize(const cv::Mat& binary_map, const cv::Mat& map_mask, const std::vector<Segment2>& obs,
                       const std::vector<double>& thetas, const std::vector<double>& scales, double resolution, int blur_k,
                       double blur_sigma, double alpha) {
  RefResult out;
  for (std::size_t o = 0; o < thetas.size(); ++o) out.final_heatmap.push_back(cv::Mat::zeros(binary_map.size(), CV_32F));
  for (double scale : scales) {
    for (std::size_t o = 0; o < thetas.size(); ++o) {
      const double c = std::cos(thetas[o]), s = std::sin(thetas[o]);
      std::vector<std::array<Vec2, 2>> segs;
      for (const Segment2& g : obs) {
        const Vec2 a = g.a_m * scale, b = g.b_m * scale;
        segs.push_back({Vec2(c * a.x() - s * a.y(), s * a.x() + c * a.y()), Vec2(c * b.x() - s * b.y(), s * b.x() + c * b.y())});
      }
      const cv::Mat h = ref_create_heatmap(binary_map, ref_initialize_kernels(segs, resolution, blur_k, blur_sigma), resolution, alpha);
      cv::Mat masked = cv::Mat::zeros(h.size(), CV_32F);
      h.copyTo(masked, map_mask);
      out.final_heatmap[o] = cv::max(out.final_heatmap[o], masked);
    }
  }
  // np.argmax over (O, H, W): the first maximum in that order.
  float best = -1;
  for (std::size_t o = 0; o < thetas.size(); ++o)
    for (int r = 0; r < binary_map.rows; ++r)
      for (int c = 0; c < binary_map.cols; ++c)
        if (out.final_heatmap[o].at<float>(r, c) > best) {
          best = out.final_heatmap[o].at<float>(r, c);
          out.orientation = static_cast<int>(o);
          out.row = r;
          out.col = c;
        }
  return out;
}

KernelMatcherParams palms_code_params() {
  KernelMatcherParams p;
  p.kernel_construction = KernelConstruction::kPalmsCode;
  p.map_border = MapBorder::kReflect;
  p.plan_raster = PlanRasterKind::kCentreline;
  p.line_rule = LineRule::kBresenham;
  p.valid_area = ValidArea::kAlphaShape;
  p.report_point = ReportPoint::kCorner;
  p.ces_erode_shape = ErodeShape::kEllipse;
  p.ces_through_doorways = false;
  return p;
}

struct Agreement {
  int observations = 0, same = 0, ties = 0;
};

Agreement compare(const FloorPlan& plan, int count, std::uint64_t seed, const KernelMatcherParams& params) {
  const KernelMatcher m(plan, params);
  cv::Mat binary_map, mask;
  cv::compare(m.plan_raster(), 0, binary_map, cv::CMP_NE);
  binary_map /= 255;
  cv::compare(m.valid_mask(), 0, mask, cv::CMP_NE);
  const PerfectObserver observer(plan, PerfectObservationParams{});
  const cv::Mat free_cells = matcher_valid_mask(plan, grid_for_plan(plan, 0.1), closed_door_map());
  const GridSpec fg = grid_for_plan(plan, 0.1);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  Agreement a;
  while (a.observations < count) {
    const int r = static_cast<int>(rng() % static_cast<std::uint64_t>(fg.height_px));
    const int c = static_cast<int>(rng() % static_cast<std::uint64_t>(fg.width_px));
    if (!free_cells.at<std::uint8_t>(r, c)) continue;
    const Pose2 truth{fg.origin_x_m + (c + u01(rng)) * 0.1, fg.origin_y_m + (r + u01(rng)) * 0.1, 2 * kPi * u01(rng)};
    const Observation2D obs = observer.observe(truth);
    if (obs.segments_m.empty()) continue;
    ++a.observations;
    const std::vector<double> thetas = m.yaw_candidates(obs);
    const RefResult ref = ref_localize(binary_map, mask, obs.segments_m, thetas, params.scales, params.resolution_m,
                                       params.blur_size_px, params.blur_sigma_px, params.alpha);
    const MatchResult got = m.match(obs, MatchRequest::modes(1));
    EXPECT_FALSE(got.modes.empty()) << "observation " << a.observations;
    if (got.modes.empty()) continue;
    const PoseHypothesis& h = got.modes[0];
    if (h.slice == ref.orientation && h.row == ref.row && h.col == ref.col) {
      ++a.same;
      // Reported at the pixel's corner: pose_pred = [w, h] * resolution from the map's origin.
      EXPECT_NEAR(h.x_m, m.grid().origin_x_m + ref.col * params.resolution_m, 1e-9);
      EXPECT_NEAR(h.y_m, m.grid().origin_y_m + ref.row * params.resolution_m, 1e-9);
      continue;
    }
    const float best = ref.final_heatmap[static_cast<std::size_t>(ref.orientation)].at<float>(ref.row, ref.col);
    const float there = ref.final_heatmap[static_cast<std::size_t>(h.slice)].at<float>(h.row, h.col);
    const bool tie = there >= best - 5e-5f;  // single-precision FFT vs filter2D round-off
    EXPECT_TRUE(tie) << "observation " << a.observations << ": reference (" << ref.orientation << ", " << ref.row << ", "
                     << ref.col << ") " << best << ", matcher (" << h.slice << ", " << h.row << ", " << h.col
                     << ") reference value there " << there;
    if (tie) ++a.ties;
    if (std::getenv("PALMS_REF_DEBUG"))
      std::printf("obs %d: ref (%d,%d,%d) %.7g matcher (%d,%d,%d) score %.7g ref there %.7g\n", a.observations, ref.orientation,
                  ref.row, ref.col, best, h.slice, h.row, h.col, h.score, there);
  }
  return a;
}

TEST(PalmsReference, SamePoseAsTheAuthorsArithmetic) {
  const KernelMatcherParams p = palms_code_params();
  const FloorPlan apartment = load_floor_plan(FLOORCAST_SOURCE_DIR "/floorplans/buildings/apartment.json");
  const Agreement a = compare(apartment, 30, 1, p);
  const Agreement b = compare(test::asymmetric_floor(), 30, 2, p);
  std::printf("PALMS reference: apartment %d/%d same pose (ties %d), asymmetric floor %d/%d (ties %d)\n", a.same,
              a.observations, a.ties, b.same, b.observations, b.ties);
  EXPECT_GE(a.same, static_cast<int>(std::ceil(0.95 * a.observations)));
  EXPECT_GE(b.same, static_cast<int>(std::ceil(0.95 * b.observations)));
  EXPECT_EQ(a.same + a.ties, a.observations);
  EXPECT_EQ(b.same + b.ties, b.observations);
}

}  // namespace
}  // namespace floorcast
