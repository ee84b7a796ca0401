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

void draw_bresenham_line(cv::Mat& image, double x0, double y0, double x1, double y1) {
  // PALMS Bresenham.point_rounder: floor(v / cell_size), negative results clamped to 0 (here the
  // coordinates are already in pixels).
  auto round_px = [](double v) { return std::max(0.0, std::floor(v)); };
  const double ax = round_px(x0), ay = round_px(y0), bx = round_px(x1), by = round_px(y1);
  const double dx = std::abs(bx - ax), dy = std::abs(by - ay);
  const double sx = ax > bx ? -1.0 : 1.0, sy = ay > by ? -1.0 : 1.0;
  double x = ax, y = ay;
  auto mark = [&](double px, double py) {
    if (px >= 0.0 && py >= 0.0 && px < image.cols && py < image.rows) image.at<std::uint8_t>(static_cast<int>(py), static_cast<int>(px)) = 255;
  };
  if (dx > dy) {
    double err = dx / 2.0;
    while (x != bx) {
      mark(x, y);
      err -= dy;
      if (err < 0) {
        y += sy;
        err += dx;
        mark(x, y);  // "enhance the wall"
      }
      x += sx;
    }
  } else {
    double err = dy / 2.0;
    while (y != by) {
      mark(x, y);
      err -= dx;
      if (err < 0) {
        x += sx;
        err += dy;
        mark(x, y);
      }
      y += sy;
    }
  }
  mark(x, y);
}

void draw_segment_lines(cv::Mat& image, const std::vector<Segment2>& segments, const Vec2& origin, double res,
                        LineRule rule) {
  if (rule == LineRule::kBresenham) {
    CV_Assert(image.type() == CV_8U);
    // Pixel coordinates with pixel c covering [c, c + 1); clipped to the image plus a border of
    // one pixel first (so far-away ends do not make long loops).
    const double bx0 = origin.x() - res, by0 = origin.y() - res;
    const double bx1 = origin.x() + (image.cols + 1) * res, by1 = origin.y() + (image.rows + 1) * res;
    for (const Segment2& s : segments) {
      Vec2 a = s.a_m, b = s.b_m;
      if (!clip_segment_to_box(a, b, bx0, by0, bx1, by1)) continue;
      draw_bresenham_line(image, (a.x() - origin.x()) / res, (a.y() - origin.y()) / res, (b.x() - origin.x()) / res,
                          (b.y() - origin.y()) / res);
    }
    return;
  }
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
    if (f.has_axis && f.label != SurfaceLabel::kObstacle) {  // a box obstacle: its outline, as always
      out.push_back(f.axis_m);
      continue;
    }
    for (std::size_t i = 0; i < f.polygon_m.size(); ++i) {
      out.push_back({f.polygon_m[i], f.polygon_m[(i + 1) % f.polygon_m.size()]});
    }
  }
  return out;
}

cv::Mat rasterize_outline(const std::vector<LabeledSegment>& outline, const GridSpec& grid, LineRule rule) {
  cv::Mat img = cv::Mat::zeros(grid.height_px, grid.width_px, CV_8U);
  draw_segment_lines(img, outline_segments(outline), {grid.origin_x_m, grid.origin_y_m}, grid.resolution_m_per_px, rule);
  return img;
}

cv::Mat alpha_shape_mask(const std::vector<Segment2>& lines, double alpha, double sample_m, const GridSpec& grid,
                         double sample_offset) {
  cv::Mat mask = cv::Mat::zeros(grid.height_px, grid.width_px, CV_8U);
  // sample_points_from_segments(segments, sample_density): num = ceil(length / density) steps.
  std::vector<cv::Point2d> points;
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  for (const Segment2& l : lines) {
    const Vec2 v = l.b_m - l.a_m;
    const double len = std::sqrt(v.x() * v.x() + v.y() * v.y());
    const int n = std::max(1, static_cast<int>(std::ceil(len / sample_m)));
    for (int i = 0; i <= n; ++i) {
      const cv::Point2d p(l.a_m.x() + v.x() / n * i, l.a_m.y() + v.y() / n * i);
      points.push_back(p);
      x0 = std::min(x0, p.x);
      y0 = std::min(y0, p.y);
      x1 = std::max(x1, p.x);
      y1 = std::max(y1, p.y);
    }
  }
  if (points.size() < 3) return mask;
  // Delaunay in float coordinates relative to the points' box (Subdiv2D works in float).
  const cv::Rect2f box(-1.0f, -1.0f, static_cast<float>(x1 - x0) + 2.0f, static_cast<float>(y1 - y0) + 2.0f);
  cv::Subdiv2D subdiv(cv::Rect(static_cast<int>(std::floor(box.x)), static_cast<int>(std::floor(box.y)),
                               static_cast<int>(std::ceil(box.width)) + 1, static_cast<int>(std::ceil(box.height)) + 1));
  for (const cv::Point2d& p : points) subdiv.insert(cv::Point2f(static_cast<float>(p.x - x0), static_cast<float>(p.y - y0)));
  std::vector<cv::Vec6f> triangles;
  subdiv.getTriangleList(triangles);
  const double res = grid.resolution_m_per_px;
  for (const cv::Vec6f& t : triangles) {
    const Vec2 a(t[0] + x0, t[1] + y0), b(t[2] + x0, t[3] + y0), c(t[4] + x0, t[5] + y0);
    bool inside = true;
    for (const Vec2& q : {a, b, c}) inside = inside && q.x() >= x0 - 1e-6 && q.x() <= x1 + 1e-6 && q.y() >= y0 - 1e-6 && q.y() <= y1 + 1e-6;
    if (!inside) continue;  // a triangle on Subdiv2D's virtual outer vertices
    const double la = (b - c).norm(), lb = (a - c).norm(), lc = (a - b).norm();
    const double area2 = std::abs((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
    if (!(area2 > 0.0)) continue;
    const double circumradius = la * lb * lc / (2.0 * area2);
    if (!(circumradius < 1.0 / alpha)) continue;
    // Cells whose sample point lies in the triangle (edges included).
    const int c0 = std::max(0, static_cast<int>(std::floor((std::min({a.x(), b.x(), c.x()}) - grid.origin_x_m) / res - sample_offset)));
    const int c1 = std::min(grid.width_px - 1, static_cast<int>(std::ceil((std::max({a.x(), b.x(), c.x()}) - grid.origin_x_m) / res - sample_offset)));
    const int r0 = std::max(0, static_cast<int>(std::floor((std::min({a.y(), b.y(), c.y()}) - grid.origin_y_m) / res - sample_offset)));
    const int r1 = std::min(grid.height_px - 1, static_cast<int>(std::ceil((std::max({a.y(), b.y(), c.y()}) - grid.origin_y_m) / res - sample_offset)));
    auto side = [](const Vec2& p, const Vec2& q, const Vec2& x) { return (q.x() - p.x()) * (x.y() - p.y()) - (q.y() - p.y()) * (x.x() - p.x()); };
    const double orient = side(a, b, c) > 0 ? 1.0 : -1.0;
    const double eps = 1e-9 * area2;
    for (int r = r0; r <= r1; ++r) {
      for (int col = c0; col <= c1; ++col) {
        const Vec2 x(grid.origin_x_m + (col + sample_offset) * res, grid.origin_y_m + (r + sample_offset) * res);
        if (orient * side(a, b, x) >= -eps && orient * side(b, c, x) >= -eps && orient * side(c, a, x) >= -eps)
          mask.at<std::uint8_t>(r, col) = 255;
      }
    }
  }
  // Holes of the union (regions not connected to the grid border) are filled, as polygonize +
  // unary_union fill them.
  cv::Mat outside;
  cv::copyMakeBorder(mask, outside, 1, 1, 1, 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  cv::floodFill(outside, cv::Point(0, 0), cv::Scalar(128), nullptr, cv::Scalar(0), cv::Scalar(0), 4);
  const cv::Mat inner = outside(cv::Rect(1, 1, mask.cols, mask.rows));
  mask.setTo(255, inner == 0);
  return mask;
}

}  // namespace floorcast
