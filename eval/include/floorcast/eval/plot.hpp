// Plots drawn by floorcast itself with OpenCV (no Python): line plots, error CDFs, categorical
// sweeps. Pure functions returning BGR images.
#pragma once

#include <limits>
#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace floorcast {

struct PlotSeries {
  std::string label;
  std::vector<double> x;
  std::vector<double> y;
  /// Optional interval per point (e.g. bootstrap 95%), drawn as error bars (categorical axes) or a
  /// shaded band (numeric axes); empty = none, NaN entries = none for that point.
  std::vector<double> y_low;
  std::vector<double> y_high;
};

struct LinePlot {
  std::string title;
  std::string x_label;
  std::string y_label;
  std::vector<PlotSeries> series;
  /// Axis limits; NaN = from the data.
  double x_min = std::numeric_limits<double>::quiet_NaN();
  double x_max = std::numeric_limits<double>::quiet_NaN();
  double y_min = std::numeric_limits<double>::quiet_NaN();
  double y_max = std::numeric_limits<double>::quiet_NaN();
  /// Categorical x axis: when non-empty, x values are indices into these labels. Categories are
  /// drawn as points with error bars, series side by side, never joined by lines (the order of
  /// categories means nothing).
  std::vector<std::string> x_categories;
  bool draw_markers = false;
  int width_px = 900;
  int height_px = 560;
};

/// Renders a line plot (axes, ticks, grid, legend, intervals) as a BGR image. The title is shrunk
/// to fit the width; long category labels are shrunk or slanted to fit their slot.
cv::Mat draw_line_plot(const LinePlot& plot);

/// Empirical CDF of errors per method, clipped at x_max: fraction of observations with error
/// <= x.
LinePlot error_cdf_plot(const std::map<std::string, std::vector<double>>& errors_by_method, double x_max,
                        const std::string& title, const std::string& x_label);

/// The colour of series i (a fixed, colour-blind friendly palette), BGR.
cv::Scalar series_colour(std::size_t i);

}  // namespace floorcast
