// 2D points -> raster -> probabilistic Hough -> wall segments (PALMS+), with optional refinement,
// and F3Loc-style ray ranges.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "floorcast/core/grid.hpp"
#include "floorcast/observe/observation_module.hpp"
#include "floorcast/core/math.hpp"

namespace floorcast {
namespace {


/// Total-least-squares re-fit of a segment to the points near it, in passes with a halving band
/// (so points of a perpendicular wall at a corner drop out); endpoints are projected on the
/// fitted line and clamped to the extent of the supporting points. Returns the input when there
/// is too little support or the support is not along the segment.
Segment2 refine_segment(const Segment2& s, const std::vector<Eigen::Vector2d>& pts, double band_m,
                        double resolution_m, double max_gap_m) {
  const double len = s.length_m();
  if (len <= 0.0) return s;
  const Vec2 u0 = (s.b_m - s.a_m) / len;
  Vec2 c = 0.5 * (s.a_m + s.b_m), dir = u0;
  double lo = 0.0, hi = 0.0;
  for (int pass = 0; pass < 3; ++pass) {
    const double band = band_m / double(1 << pass);
    const Vec2 nrm(-dir.y(), dir.x());
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    Eigen::Matrix2d ss = Eigen::Matrix2d::Zero();
    int n = 0;
    for (const auto& p : pts) {
      const double along = (p - s.a_m).dot(u0);  // within the Hough segment's extent
      if (along < -band || along > len + band) continue;
      if (std::abs((p - c).dot(nrm)) > band) continue;
      sum += p;
      ss.noalias() += p * p.transpose();
      ++n;
    }
    if (n < 3) return s;
    const Eigen::Vector2d cn = sum / n;
    const Eigen::Matrix2d cov = ss / n - cn * cn.transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov);
    Vec2 d = es.eigenvectors().col(1).normalized();
    if (d.dot(u0) < 0) d = -d;
    // The Hough direction of a short segment on a 2-px trace is uncertain by ~atan(2 px / length).
    const double tol = std::max(10.0 * kPi / 180.0, std::atan2(2.0 * resolution_m, len));
    if (d.dot(u0) < std::cos(tol)) return s;  // the support is not this line
    c = cn;
    dir = d;
  }
  // Extent: the Hough segment's ends projected on the fitted line, trimmed to the support
  // inside them, then grown along the line over supporting points with gaps <= max_gap_m (Hough
  // splits thick traces into pieces; the data is one wall).
  const Vec2 nrm(-dir.y(), dir.x());
  const double band = band_m / 4.0;
  std::vector<double> along;
  for (const auto& p : pts) {
    if (std::abs((p - c).dot(nrm)) <= band) along.push_back((p - c).dot(dir));
  }
  std::sort(along.begin(), along.end());
  double ta = (s.a_m - c).dot(dir), tb = (s.b_m - c).dot(dir);
  const auto first_in = std::lower_bound(along.begin(), along.end(), ta - band);
  const auto last_in = std::upper_bound(along.begin(), along.end(), tb + band);
  if (first_in == last_in) return s;
  lo = *first_in;
  hi = *(last_in - 1);
  ta = std::max(ta, lo);
  tb = std::min(tb, hi);
  if (max_gap_m > 0.0) {
    for (auto it = last_in; it != along.end() && *it <= tb + max_gap_m; ++it) tb = std::max(tb, *it);
    for (auto it = std::make_reverse_iterator(first_in); it != along.rend() && *it >= ta - max_gap_m; ++it) {
      ta = std::min(ta, *it);
    }
  }
  Segment2 out;
  out.a_m = c + dir * ta;
  out.b_m = c + dir * tb;
  return out;
}

/// Drops segments lying on a longer one (nearly parallel, both ends within tol_m of its line)
/// after extending the longer one over their union when they overlap it or leave a gap of at
/// most max_gap_m. Longest first; deterministic.
std::vector<Segment2> merge_collinear(std::vector<Segment2> segs, double tol_m, double tol_deg,
                                      double max_gap_m) {
  std::stable_sort(segs.begin(), segs.end(),
                   [](const Segment2& a, const Segment2& b) { return a.length_m() > b.length_m(); });
  const double cos_tol = std::cos(tol_deg * kPi / 180.0);
  std::vector<Segment2> out;
  for (const Segment2& s : segs) {
    bool absorbed = false;
    for (Segment2& keep : out) {
      const double len = keep.length_m();
      const Vec2 u = (keep.b_m - keep.a_m) / len;
      const Vec2 sd = (s.b_m - s.a_m).normalized();
      if (std::abs(sd.dot(u)) < cos_tol) continue;
      const Vec2 nrm(-u.y(), u.x());
      if (std::abs((s.a_m - keep.a_m).dot(nrm)) > tol_m || std::abs((s.b_m - keep.a_m).dot(nrm)) > tol_m) continue;
      double sa = (s.a_m - keep.a_m).dot(u), sb = (s.b_m - keep.a_m).dot(u);
      if (sa > sb) std::swap(sa, sb);
      if (sa > len + max_gap_m || sb < -max_gap_m) continue;  // disjoint along the line
      const double lo = std::min(0.0, sa), hi = std::max(len, sb);
      const Vec2 a0 = keep.a_m;
      keep.a_m = a0 + u * lo;
      keep.b_m = a0 + u * hi;
      absorbed = true;
      break;
    }
    if (!absorbed) out.push_back(s);
  }
  return out;
}

}  // namespace

std::vector<double> ray_ranges_2d(const std::vector<Eigen::Vector2d>& points_m, int num_rays,
                                  double tolerance_deg, double max_range_m) {
  std::vector<double> ranges(std::max(0, num_rays), max_range_m);
  if (num_rays <= 0) return ranges;
  const double tol = tolerance_deg * kPi / 180.0;
  const double step = 2.0 * kPi / num_rays;
  const int span = static_cast<int>(std::ceil(tol / step));
  for (const auto& p : points_m) {
    const double r = p.norm();
    if (r >= max_range_m || r <= 0.0) continue;
    double a = std::atan2(p.y(), p.x());
    if (a < 0) a += 2.0 * kPi;
    const int centre = static_cast<int>(std::lround(a / step));
    for (int k = centre - span; k <= centre + span; ++k) {
      const int ray = ((k % num_rays) + num_rays) % num_rays;
      if (angle_distance_rad(a, ray * step) <= tol) ranges[ray] = std::min(ranges[ray], r);
    }
  }
  return ranges;
}

SegmentExtractionResult extract_segments_2d(const std::vector<Eigen::Vector2d>& points_m,
                                            const SegmentExtractionParams& params, double max_range_m) {
  SegmentExtractionResult res;
  const double res_m = params.resolution_m_per_px;
  if (!(res_m > 0.0)) throw InputError("segments.resolution_m_per_px must be > 0");
  double extent = 0.0;
  for (const auto& p : points_m) extent = std::max({extent, std::abs(p.x()), std::abs(p.y())});
  // The raster spans the points (within the slice's range): refused before it is allocated.
  const double half = std::ceil(extent / res_m) + 2.0;
  check_raster_budget(2.0 * half, 2.0 * half, res_m, 2.0, "observation slice (segments.resolution_m_per_px)");
  const int half_px = static_cast<int>(half);
  res.origin_x_m = -half_px * res_m;
  res.origin_y_m = -half_px * res_m;
  res.raster = cv::Mat(2 * half_px, 2 * half_px, CV_8U, cv::Scalar(0));
  for (const auto& p : points_m) {
    const int c = static_cast<int>(std::floor((p.x() - res.origin_x_m) / res_m));
    const int r = static_cast<int>(std::floor((p.y() - res.origin_y_m) / res_m));
    if (r >= 0 && c >= 0 && r < res.raster.rows && c < res.raster.cols) res.raster.at<std::uint8_t>(r, c) = 255;
  }
  cv::Mat hough_input = res.raster;
  if (params.canny_before_hough) {
    cv::Canny(res.raster, hough_input, 10, 20);
  }
  std::vector<cv::Vec4i> lines;
  if (!points_m.empty()) {
    cv::HoughLinesP(hough_input, lines, params.hough_rho_px, params.hough_theta_deg * kPi / 180.0,
                    params.hough_threshold, params.hough_min_length_px, params.hough_max_gap_px);
  }
  for (const auto& l : lines) {
    Segment2 s;
    s.a_m = {res.origin_x_m + (l[0] + 0.5) * res_m, res.origin_y_m + (l[1] + 0.5) * res_m};
    s.b_m = {res.origin_x_m + (l[2] + 0.5) * res_m, res.origin_y_m + (l[3] + 0.5) * res_m};
    if (params.refine_segments) {
      s = refine_segment(s, points_m, params.refine_band_m, res_m, params.hough_max_gap_px * res_m);
    }
    if (s.length_m() > 0.0) res.segments_m.push_back(s);
  }
  if (params.merge_collinear) {
    res.segments_m = merge_collinear(std::move(res.segments_m), params.merge_tolerance_m,
                                     params.merge_tolerance_deg, params.hough_max_gap_px * res_m);
  }
  for (Segment2& s : res.segments_m) orient_observer_left(s);
  if (params.num_rays > 0) {
    res.ray_ranges_m = ray_ranges_2d(points_m, params.num_rays, params.ray_tolerance_deg, max_range_m);
  }
  return res;
}

}  // namespace floorcast
