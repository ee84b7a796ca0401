// Small drawing helpers shared by every picture floorcast makes for people (plans, posterior
// heatmaps, plots, contact sheets): nice tick steps, text that fits, scale bars, colour bars,
// legends and banners. OpenCV Hershey fonts, BGR images. Pure functions on the image given.
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <utility>
#include <vector>

namespace floorcast::figure {

/// A "nice" step (1, 2, 5 x 10^k) covering `range` with about `target` steps.
double nice_step(double range, int target);
/// The longest of 1, 2, 5, 10, 20, 50, ... metres not above max_m (at least 1).
double nice_scale_length_m(double max_m);
/// Text of a tick value with as many decimals as `step` needs.
std::string tick_text(double value, double step);

constexpr int kFont = 0;  ///< cv::FONT_HERSHEY_SIMPLEX

/// Width and height (cap height) in pixels of `text` at `scale`.
cv::Size text_size(const std::string& text, double scale, int thickness = 1);
/// The largest scale <= `scale` at which `text` is at most max_width_px wide (at least 0.3).
double fit_text_scale(const std::string& text, double scale, int max_width_px, int thickness = 1);
/// Draws text with its baseline at `at`; align 0 = left, 1 = centred, 2 = right. Non-printable
/// characters are drawn as '?'.
void draw_text(cv::Mat& img, const std::string& text, cv::Point at, double scale, const cv::Scalar& colour,
               int align = 0, int thickness = 1);
/// Text rotated 90 degrees counter-clockwise (a y-axis label) centred on `centre`.
void draw_vertical_text(cv::Mat& img, const std::string& text, cv::Point centre, double scale, const cv::Scalar& colour);

/// A black-and-white scale bar whose left end is at `at` (top-left of the bar), with "0" and its
/// length in metres under it; at most max_length_px long. Returns the bar's bounding box.
cv::Rect draw_scale_bar(cv::Mat& img, cv::Point at, double px_per_m, int max_length_px);

/// A vertical colour bar for an OpenCV colour map in `bar` (low values at the bottom) with tick
/// labels `ticks` (fraction 0..1 of the bar, text) on its right and `label` rotated beside them.
void draw_colour_bar(cv::Mat& img, cv::Rect bar, int colormap, const std::vector<std::pair<double, std::string>>& ticks,
                     const std::string& label);

/// Legend entries drawn left to right from `at` (baseline), each a symbol and its text; returns
/// the x after the last entry. Symbols: 'o' ring, 'x' cross, 's' filled square, '-' line.
struct LegendEntry {
  char symbol = 's';
  cv::Scalar colour;
  std::string text;
};
int draw_legend_row(cv::Mat& img, cv::Point at, const std::vector<LegendEntry>& entries, double scale = 0.45);

/// A translucent banner across `area` with `text` centred in it (e.g. "empty posterior").
void draw_banner(cv::Mat& img, cv::Rect area, const std::string& text, const cv::Scalar& colour);

}  // namespace floorcast::figure
