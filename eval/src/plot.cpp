#include "floorcast/eval/plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "floorcast/floorplans/figure.hpp"

namespace floorcast {
namespace {

using figure::draw_text;

bool finite_at(const std::vector<double>& v, std::size_t k) { return k < v.size() && std::isfinite(v[k]); }

}  // namespace

cv::Scalar series_colour(std::size_t i) {
  // Okabe-Ito palette, BGR.
  static const cv::Scalar palette[] = {{178, 114, 0},  {0, 159, 230},  {115, 158, 0}, {66, 228, 240},
                                       {167, 121, 204}, {0, 94, 213},  {233, 180, 86}, {0, 0, 0}};
  return palette[i % (sizeof palette / sizeof palette[0])];
}

cv::Mat draw_line_plot(const LinePlot& plot) {
  cv::Mat img(plot.height_px, plot.width_px, CV_8UC3, cv::Scalar(255, 255, 255));
  // Legend width from the longest label.
  int legend_w = 0;
  for (const auto& s : plot.series) legend_w = std::max(legend_w, figure::text_size(s.label, 0.45).width);
  const int right = std::clamp(legend_w + 60, 120, plot.width_px / 3);
  const bool categorical = !plot.x_categories.empty();
  const int left = 80, top = 50, bottom = categorical ? 90 : 70;
  const cv::Rect area(left, top, plot.width_px - left - right, plot.height_px - top - bottom);

  double x0 = plot.x_min, x1 = plot.x_max, y0 = plot.y_min, y1 = plot.y_max;
  double dx0 = INFINITY, dx1 = -INFINITY, dy0 = INFINITY, dy1 = -INFINITY;
  for (const auto& s : plot.series) {
    for (double v : s.x) if (std::isfinite(v)) { dx0 = std::min(dx0, v); dx1 = std::max(dx1, v); }
    for (const auto* ys : {&s.y, &s.y_low, &s.y_high})
      for (double v : *ys) if (std::isfinite(v)) { dy0 = std::min(dy0, v); dy1 = std::max(dy1, v); }
  }
  if (categorical) {
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
  const double ys = figure::nice_step(y1 - y0, 6);
  for (double y = std::ceil(y0 / ys) * ys; y <= y1 + 1e-9 * ys; y += ys) {
    cv::line(img, px(x0, y), px(x1, y), grid, 1);
    draw_text(img, figure::tick_text(y, ys), px(x0, y) + cv::Point(-8, 5), 0.45, ink, 2);
  }
  if (!categorical) {
    const double xs = figure::nice_step(x1 - x0, 8);
    for (double x = std::ceil(x0 / xs) * xs; x <= x1 + 1e-9 * xs; x += xs) {
      cv::line(img, px(x, y0), px(x, y1), grid, 1);
      draw_text(img, figure::tick_text(x, xs), px(x, y0) + cv::Point(0, 20), 0.45, ink, 1);
    }
  } else {
    const int slot = std::max(8, area.width / static_cast<int>(plot.x_categories.size()));
    for (std::size_t i = 0; i < plot.x_categories.size(); ++i) {
      const double x = static_cast<double>(i);
      cv::line(img, px(x, y0), px(x, y1), grid, 1);
      const std::string& label = plot.x_categories[i];
      const double scale = figure::fit_text_scale(label, 0.45, slot - 6);
      if (figure::text_size(label, scale).width <= slot - 6 || scale > 0.3) {
        draw_text(img, label, px(x, y0) + cv::Point(0, 20), scale, ink, 1);
      } else {
        draw_text(img, label.substr(0, 12) + "..", px(x, y0) + cv::Point(0, 20), 0.3, ink, 1);
      }
    }
  }
  cv::rectangle(img, area, ink, 1);

  // Series.
  const std::size_t n_series = plot.series.size();
  const double group_w = categorical ? std::min(0.6, 0.15 * static_cast<double>(n_series)) : 0.0;
  for (std::size_t i = 0; i < n_series; ++i) {
    const auto& s = plot.series[i];
    const cv::Scalar c = series_colour(i);
    // Side by side within a category so intervals do not hide one another.
    const double offset = categorical && n_series > 1
                              ? -0.5 * group_w + group_w * static_cast<double>(i) / static_cast<double>(n_series - 1)
                              : 0.0;
    std::vector<cv::Point> pts;
    std::vector<cv::Point> band_top, band_bottom;
    for (std::size_t k = 0; k < std::min(s.x.size(), s.y.size()); ++k) {
      if (!std::isfinite(s.x[k]) || !std::isfinite(s.y[k])) continue;
      const double x = std::clamp(s.x[k] + offset, x0, x1);
      const cv::Point p = px(x, std::clamp(s.y[k], y0, y1));
      pts.push_back(p);
      if (finite_at(s.y_low, k) && finite_at(s.y_high, k)) {
        const cv::Point lo = px(x, std::clamp(s.y_low[k], y0, y1)), hi = px(x, std::clamp(s.y_high[k], y0, y1));
        if (categorical) {
          cv::line(img, lo, hi, c, 2, cv::LINE_AA);
          cv::line(img, lo - cv::Point(5, 0), lo + cv::Point(5, 0), c, 2, cv::LINE_AA);
          cv::line(img, hi - cv::Point(5, 0), hi + cv::Point(5, 0), c, 2, cv::LINE_AA);
        } else {
          band_top.push_back(hi);
          band_bottom.push_back(lo);
        }
      }
    }
    if (band_top.size() >= 2) {
      std::vector<cv::Point> poly = band_top;
      poly.insert(poly.end(), band_bottom.rbegin(), band_bottom.rend());
      cv::Mat overlay = img.clone();
      cv::fillPoly(overlay, std::vector<std::vector<cv::Point>>{poly}, c, cv::LINE_AA);
      cv::addWeighted(overlay, 0.18, img, 0.82, 0.0, img);
    }
    if (!categorical && pts.size() >= 2) cv::polylines(img, pts, false, c, 2, cv::LINE_AA);
    if (categorical || plot.draw_markers || pts.size() == 1)
      for (const auto& p : pts) cv::circle(img, p, categorical ? 5 : 4, c, cv::FILLED, cv::LINE_AA);
    // Legend entry.
    const cv::Point l(area.x + area.width + 15, area.y + 20 + 22 * static_cast<int>(i));
    if (categorical) cv::circle(img, l + cv::Point(12, 0), 5, c, cv::FILLED, cv::LINE_AA);
    else cv::line(img, l, l + cv::Point(25, 0), c, 3, cv::LINE_AA);
    draw_text(img, s.label, l + cv::Point(32, 5), 0.45, ink);
  }
  bool any_interval = false;
  for (const auto& s : plot.series) any_interval = any_interval || !s.y_low.empty();
  if (any_interval) {
    draw_text(img, categorical ? "bars: 95% interval" : "band: 95% interval",
              cv::Point(area.x + area.width + 15, area.y + 20 + 22 * static_cast<int>(n_series) + 6), 0.4,
              cv::Scalar(110, 110, 110));
  }

  const double title_scale = figure::fit_text_scale(plot.title, 0.65, plot.width_px - 20);
  draw_text(img, plot.title, cv::Point(plot.width_px / 2, 30), title_scale, ink, 1);
  draw_text(img, plot.x_label, cv::Point(area.x + area.width / 2, plot.height_px - (categorical ? 30 : 20)),
            figure::fit_text_scale(plot.x_label, 0.5, area.width), ink, 1);
  figure::draw_vertical_text(img, plot.y_label, {20, area.y + area.height / 2}, 0.5, ink);
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
