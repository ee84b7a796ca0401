#include "floorcast/eval/plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

namespace floorcast {
namespace {

/// "Nice" tick step covering `range` with about `target` ticks (1, 2, 5 x 10^k).
double nice_step(double range, int target) {
  if (!(range > 0.0)) return 1.0;
  const double raw = range / target;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (raw <= m * mag) return m * mag;
  return 10.0 * mag;
}

std::string tick_text(double v, double step) {
  char buf[32];
  const int decimals = step >= 1.0 ? 0 : static_cast<int>(std::ceil(-std::log10(step) - 1e-9));
  std::snprintf(buf, sizeof buf, "%.*f", std::max(decimals, 0), v);
  return buf;
}

void text(cv::Mat& img, const std::string& s, cv::Point at, double scale, const cv::Scalar& colour, int align = 0) {
  int base = 0;
  const cv::Size size = cv::getTextSize(s, cv::FONT_HERSHEY_SIMPLEX, scale, 1, &base);
  if (align == 1) at.x -= size.width / 2;
  if (align == 2) at.x -= size.width;
  cv::putText(img, s, at, cv::FONT_HERSHEY_SIMPLEX, scale, colour, 1, cv::LINE_AA);
}

}  // namespace

cv::Scalar series_colour(std::size_t i) {
  // Okabe-Ito palette, BGR.
  static const cv::Scalar palette[] = {{178, 114, 0},  {0, 159, 230},  {115, 158, 0}, {66, 228, 240},
                                       {167, 121, 204}, {0, 94, 213},  {233, 180, 86}, {0, 0, 0}};
  return palette[i % (sizeof palette / sizeof palette[0])];
}

cv::Mat draw_line_plot(const LinePlot& plot) {
  cv::Mat img(plot.height_px, plot.width_px, CV_8UC3, cv::Scalar(255, 255, 255));
  const int left = 80, right = 190, top = 50, bottom = 70;
  const cv::Rect area(left, top, plot.width_px - left - right, plot.height_px - top - bottom);

  double x0 = plot.x_min, x1 = plot.x_max, y0 = plot.y_min, y1 = plot.y_max;
  double dx0 = INFINITY, dx1 = -INFINITY, dy0 = INFINITY, dy1 = -INFINITY;
  for (const auto& s : plot.series) {
    for (double v : s.x) if (std::isfinite(v)) { dx0 = std::min(dx0, v); dx1 = std::max(dx1, v); }
    for (double v : s.y) if (std::isfinite(v)) { dy0 = std::min(dy0, v); dy1 = std::max(dy1, v); }
  }
  if (!plot.x_categories.empty()) {
    dx0 = -0.5;
    dx1 = static_cast<double>(plot.x_categories.size()) - 0.5;
  }
  if (std::isnan(x0)) x0 = std::isfinite(dx0) ? dx0 : 0.0;
  if (std::isnan(x1)) x1 = std::isfinite(dx1) ? dx1 : 1.0;
  if (std::isnan(y0)) y0 = std::isfinite(dy0) ? dy0 : 0.0;
  if (std::isnan(y1)) y1 = std::isfinite(dy1) ? dy1 : 1.0;
  if (x1 <= x0) x1 = x0 + 1.0;
  if (y1 <= y0) y1 = y0 + 1.0;

  auto px = [&](double x, double y) {
    return cv::Point(static_cast<int>(std::lround(area.x + (x - x0) / (x1 - x0) * area.width)),
                     static_cast<int>(std::lround(area.y + area.height - (y - y0) / (y1 - y0) * area.height)));
  };
  const cv::Scalar grid(225, 225, 225), ink(40, 40, 40);

  // Grid and ticks.
  const double ys = nice_step(y1 - y0, 6);
  for (double y = std::ceil(y0 / ys) * ys; y <= y1 + 1e-9 * ys; y += ys) {
    cv::line(img, px(x0, y), px(x1, y), grid, 1);
    text(img, tick_text(y, ys), px(x0, y) + cv::Point(-8, 5), 0.45, ink, 2);
  }
  if (plot.x_categories.empty()) {
    const double xs = nice_step(x1 - x0, 8);
    for (double x = std::ceil(x0 / xs) * xs; x <= x1 + 1e-9 * xs; x += xs) {
      cv::line(img, px(x, y0), px(x, y1), grid, 1);
      text(img, tick_text(x, xs), px(x, y0) + cv::Point(0, 20), 0.45, ink, 1);
    }
  } else {
    for (std::size_t i = 0; i < plot.x_categories.size(); ++i) {
      const double x = static_cast<double>(i);
      cv::line(img, px(x, y0), px(x, y1), grid, 1);
      text(img, plot.x_categories[i], px(x, y0) + cv::Point(0, 20), 0.45, ink, 1);
    }
  }
  cv::rectangle(img, area, ink, 1);

  // Series.
  for (std::size_t i = 0; i < plot.series.size(); ++i) {
    const auto& s = plot.series[i];
    const cv::Scalar c = series_colour(i);
    std::vector<cv::Point> pts;
    for (std::size_t k = 0; k < std::min(s.x.size(), s.y.size()); ++k) {
      if (!std::isfinite(s.x[k]) || !std::isfinite(s.y[k])) continue;
      pts.push_back(px(std::clamp(s.x[k], x0, x1), std::clamp(s.y[k], y0, y1)));
    }
    if (pts.size() >= 2) cv::polylines(img, pts, false, c, 2, cv::LINE_AA);
    if (plot.draw_markers || pts.size() == 1)
      for (const auto& p : pts) cv::circle(img, p, 4, c, cv::FILLED, cv::LINE_AA);
    // Legend entry.
    const cv::Point l(area.x + area.width + 15, area.y + 20 + 22 * static_cast<int>(i));
    cv::line(img, l, l + cv::Point(25, 0), c, 3, cv::LINE_AA);
    text(img, s.label, l + cv::Point(32, 5), 0.45, ink);
  }

  text(img, plot.title, cv::Point(plot.width_px / 2, 30), 0.65, ink, 1);
  text(img, plot.x_label, cv::Point(area.x + area.width / 2, plot.height_px - 20), 0.5, ink, 1);
  // Vertical y label: draw horizontally into a patch and rotate.
  if (!plot.y_label.empty()) {
    int base = 0;
    const cv::Size sz = cv::getTextSize(plot.y_label, cv::FONT_HERSHEY_SIMPLEX, 0.5, 1, &base);
    cv::Mat patch(sz.height + base + 4, sz.width + 4, CV_8UC3, cv::Scalar(255, 255, 255));
    cv::putText(patch, plot.y_label, cv::Point(2, sz.height + 1), cv::FONT_HERSHEY_SIMPLEX, 0.5, ink, 1, cv::LINE_AA);
    cv::Mat rotated;
    cv::rotate(patch, rotated, cv::ROTATE_90_COUNTERCLOCKWISE);
    const int x = 10, y = std::max(0, area.y + area.height / 2 - rotated.rows / 2);
    if (y + rotated.rows <= img.rows && x + rotated.cols <= img.cols) rotated.copyTo(img(cv::Rect(x, y, rotated.cols, rotated.rows)));
  }
  return img;
}

LinePlot error_cdf_plot(const std::map<std::string, std::vector<double>>& errors_by_method, double x_max,
                        const std::string& title, const std::string& x_label) {
  LinePlot p;
  p.title = title;
  p.x_label = x_label;
  p.y_label = "fraction of observations";
  p.x_min = 0.0;
  p.x_max = x_max;
  p.y_min = 0.0;
  p.y_max = 1.0;
  for (const auto& [label, errors] : errors_by_method) {
    std::vector<double> e = errors;
    std::sort(e.begin(), e.end());
    PlotSeries s;
    s.label = label;
    const double n = static_cast<double>(e.size());
    s.x.push_back(0.0);
    s.y.push_back(0.0);
    for (std::size_t i = 0; i < e.size() && e[i] <= x_max; ++i) {
      const double x = e[i];
      s.x.push_back(x);
      s.y.push_back(static_cast<double>(i) / n);
      s.x.push_back(x);
      s.y.push_back(static_cast<double>(i + 1) / n);
    }
    s.x.push_back(x_max);
    s.y.push_back(s.y.back());
    p.series.push_back(std::move(s));
  }
  return p;
}

}  // namespace floorcast
