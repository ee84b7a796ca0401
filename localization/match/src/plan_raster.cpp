#include "floorcast/match/plan_raster.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <opencv2/imgproc.hpp>

#include "floorcast/floorplans/geometry.hpp"

namespace floorcast {
namespace {

/// Pixel coordinates are snapped to 1/1024 px so that walls lying exactly on pixel boundaries
/// (e.g. the faces of a 0.2 m wall on a 0.1 m grid) are recognised as such despite round-off, and
/// the raster stays symmetric under quarter turns and reflections of the plan.
double snap(double v) { return std::nearbyint(v * 1024.0) / 1024.0; }

}  // namespace

void draw_segment_lines(cv::Mat& image, const std::vector<Segment2>& segments, const Vec2& origin, double res,
                        LineRule rule) {
  const bool closed = rule == LineRule::kClosed;
  CV_Assert(image.type() == CV_8U);
  // Clip to the image plus a one-pixel border first (keeps coordinates small, slopes exact).
  const double bx0 = origin.x() - res, by0 = origin.y() - res;
  const double bx1 = origin.x() + (image.cols + 1) * res, by1 = origin.y() + (image.rows + 1) * res;
  for (const Segment2& s : segments) {
    Vec2 a = s.a_m, b = s.b_m;
    if (!clip_segment_to_box(a, b, bx0, by0, bx1, by1)) continue;
    Vec2 p = {snap((a.x() - origin.x()) / res - 0.5), snap((a.y() - origin.y()) / res - 0.5)};
    Vec2 q = {snap((b.x() - origin.x()) / res - 0.5), snap((b.y() - origin.y()) / res - 0.5)};
    if (p.y() > q.y()) std::swap(p, q);
    const double dx = q.x() - p.x(), dy = q.y() - p.y();
    // Pixel (c, r) is the closed square [c - 1/2, c + 1/2] x [r - 1/2, r + 1/2], or the half-open
    // [c - 1/2, c + 1/2) x [r - 1/2, r + 1/2).
    const int r0 = std::max(0, static_cast<int>(closed ? std::ceil(p.y() - 0.5) : std::floor(p.y() + 0.5)));
    const int r1 = std::min(image.rows - 1, static_cast<int>(std::floor(q.y() + 0.5)));
    for (int r = r0; r <= r1; ++r) {
      const double ylo = std::max(p.y(), r - 0.5), yhi = std::min(q.y(), r + 0.5);
      if (ylo > yhi || (!closed && ylo == r + 0.5)) continue;
      double xa, xb;
      if (dy == 0.0) {
        xa = std::min(p.x(), q.x());
        xb = std::max(p.x(), q.x());
      } else {
        xa = snap(p.x() + (ylo - p.y()) / dy * dx);
        xb = snap(p.x() + (yhi - p.y()) / dy * dx);
        if (xa > xb) std::swap(xa, xb);
      }
      const int c0 = std::max(0, static_cast<int>(closed ? std::ceil(xa - 0.5) : std::floor(xa + 0.5)));
      const int c1 = std::min(image.cols - 1, static_cast<int>(std::floor(xb + 0.5)));
      if (c0 <= c1) std::memset(image.ptr<std::uint8_t>(r) + c0, 255, static_cast<std::size_t>(c1 - c0 + 1));
    }
  }
}

void fill_triangles(cv::Mat& image, const std::vector<std::array<Vec2, 3>>& triangles, const Vec2& origin,
                    double res) {
  CV_Assert(image.type() == CV_8U);
  for (const auto& t : triangles) {
    // Continuous pixel coordinates (pixel (c, r) centred at (c, r)).
    Vec2 p[3];
    for (int k = 0; k < 3; ++k) p[k] = {(t[k].x() - origin.x()) / res - 0.5, (t[k].y() - origin.y()) / res - 0.5};
    const double ymin = std::min({p[0].y(), p[1].y(), p[2].y()});
    const double ymax = std::max({p[0].y(), p[1].y(), p[2].y()});
    // Strict interior: ymin < y < ymax, xl < x < xr.
    const int r0 = std::max(0, static_cast<int>(std::floor(ymin)) + 1);
    const int r1 = std::min(image.rows - 1, static_cast<int>(std::ceil(ymax)) - 1);
    for (int r = r0; r <= r1; ++r) {
      const double y = r;
      double xl = 1e300, xr = -1e300;
      for (int k = 0; k < 3; ++k) {
        const Vec2& a = p[k];
        const Vec2& b = p[(k + 1) % 3];
        const double lo = std::min(a.y(), b.y()), hi = std::max(a.y(), b.y());
        if (y < lo || y > hi || lo == hi) continue;
        const double x = a.x() + (y - a.y()) / (b.y() - a.y()) * (b.x() - a.x());
        xl = std::min(xl, x);
        xr = std::max(xr, x);
      }
      const int c0 = std::max(0, static_cast<int>(std::floor(xl)) + 1);
      const int c1 = std::min(image.cols - 1, static_cast<int>(std::ceil(xr)) - 1);
      if (c0 <= c1) std::memset(image.ptr<std::uint8_t>(r) + c0, 255, static_cast<std::size_t>(c1 - c0 + 1));
    }
  }
}

cv::Mat matcher_valid_mask(const FloorPlan& plan, const GridSpec& grid, const BlockingOptions& blocking) {
  const cv::Mat valid = valid_area_mask(plan, grid);
  const cv::Mat occupied = rasterize_occupancy(plan, grid, blocking);
  cv::Mat out;
  cv::bitwise_and(valid, occupied == 0, out);
  return out;
}

std::vector<Segment2> footprint_centrelines(const std::vector<Footprint>& footprints) {
  std::vector<Segment2> out;
  for (const Footprint& f : footprints) {
    if (f.has_axis) {
      out.push_back(f.axis_m);
      continue;
    }
    for (std::size_t i = 0; i < f.polygon_m.size(); ++i) {
      out.push_back({f.polygon_m[i], f.polygon_m[(i + 1) % f.polygon_m.size()]});
    }
  }
  return out;
}

std::vector<Segment2> outline_segments(const std::vector<LabeledSegment>& outline) {
  std::vector<Segment2> out;
  out.reserve(outline.size());
  for (const LabeledSegment& l : outline) out.push_back(l.segment_m);
  return out;
}

cv::Mat rasterize_outline(const std::vector<LabeledSegment>& outline, const GridSpec& grid, LineRule rule) {
  cv::Mat img = cv::Mat::zeros(grid.height_px, grid.width_px, CV_8U);
  draw_segment_lines(img, outline_segments(outline), {grid.origin_x_m, grid.origin_y_m}, grid.resolution_m_per_px, rule);
  return img;
}

}  // namespace floorcast
