#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "floorcast/floorplans/figure.hpp"
#include "floorcast/eval/heatmap.hpp"

namespace floorcast {
namespace {

const cv::Scalar kTruthColour(0, 170, 0);
const cv::Scalar kEstimateColour(0, 0, 230);
const cv::Vec3b kEmptyCell(235, 235, 235);
const cv::Vec3b kWallCell(0, 0, 0);
constexpr int kColourMap = cv::COLORMAP_TURBO;

/// A view of the cell image: cells [col0, col0 + cols) x [row0, row0 + rows) of the flipped
/// (top-down) cell image, drawn at ppc pixels per cell.
struct View {
  const GridSpec* grid;
  double col0 = 0.0, row0 = 0.0;  // top-left corner in flipped cell coordinates
  double ppc = 1.0;
  cv::Point to_px(double x, double y) const {
    const double col = (x - grid->origin_x_m) / grid->resolution_m_per_px;
    const double row = grid->height_px - (y - grid->origin_y_m) / grid->resolution_m_per_px;
    return {static_cast<int>(std::lround((col - col0) * ppc)), static_cast<int>(std::lround((row - row0) * ppc))};
  }
};

void draw_pose(cv::Mat& img, const View& v, const PoseHypothesis& h, bool is_truth, int radius, int thickness) {
  const cv::Point a = v.to_px(h.x_m, h.y_m);
  const cv::Point b = a + cv::Point(static_cast<int>(std::lround(2.6 * radius * std::cos(h.yaw_rad))),
                                    static_cast<int>(std::lround(-2.6 * radius * std::sin(h.yaw_rad))));
  const cv::Scalar c = is_truth ? kTruthColour : kEstimateColour;
  // A white halo keeps the markers readable on every heat colour.
  if (is_truth) {
    cv::circle(img, a, radius, cv::Scalar(255, 255, 255), thickness + 2, cv::LINE_AA);
    cv::circle(img, a, radius, c, thickness, cv::LINE_AA);
  } else {
    cv::drawMarker(img, a, cv::Scalar(255, 255, 255), cv::MARKER_TILTED_CROSS, 2 * radius, thickness + 2, cv::LINE_AA);
    cv::drawMarker(img, a, c, cv::MARKER_TILTED_CROSS, 2 * radius, thickness, cv::LINE_AA);
  }
  cv::arrowedLine(img, a, b, cv::Scalar(255, 255, 255), thickness + 2, cv::LINE_AA, 0, 0.3);
  cv::arrowedLine(img, a, b, c, thickness, cv::LINE_AA, 0, 0.3);
}

}  // namespace

cv::Mat render_posterior_heatmap(const Posterior& post, const cv::Mat& plan_raster,
                                 const std::optional<PoseHypothesis>& truth,
                                 const std::optional<PoseHypothesis>& estimate, const HeatmapStyle& style) {
  const GridSpec& g = post.grid;
  if (g.width_px <= 0 || g.height_px <= 0) throw std::invalid_argument("render_posterior_heatmap: empty grid");
  if (plan_raster.type() != CV_8U || plan_raster.rows != g.height_px || plan_raster.cols != g.width_px) {
    throw std::invalid_argument("render_posterior_heatmap: plan raster must be CV_8U on the posterior's grid");
  }
  int ppc = style.pixels_per_cell;
  if (ppc <= 0) ppc = std::max(1, style.max_side_px / std::max(g.width_px, g.height_px));

  // Cells: heat colour, walls black, zero score light grey; flipped so row 0 is the plan's top.
  const cv::Mat heat = post.scores.empty() ? cv::Mat::zeros(g.height_px, g.width_px, CV_32F) : post.max_over_yaw();
  double mx = 0.0;
  cv::minMaxLoc(heat, nullptr, &mx);
  const bool empty = !(mx > 0.0);
  cv::Mat heat8(g.height_px, g.width_px, CV_8U, cv::Scalar(0));
  if (!empty) {
    for (int r = 0; r < g.height_px; ++r) {
      const float* h = heat.ptr<float>(r);
      std::uint8_t* o = heat8.ptr<std::uint8_t>(r);
      for (int c = 0; c < g.width_px; ++c) o[c] = static_cast<std::uint8_t>(std::lround(255.0 * std::pow(h[c] / mx, style.gamma)));
    }
  }
  cv::Mat colour;
  cv::applyColorMap(heat8, colour, kColourMap);
  cv::Mat cells(g.height_px, g.width_px, CV_8UC3);
  for (int r = 0; r < g.height_px; ++r) {
    const float* h = heat.ptr<float>(r);
    const std::uint8_t* wall = plan_raster.ptr<std::uint8_t>(r);
    const cv::Vec3b* col = colour.ptr<cv::Vec3b>(r);
    cv::Vec3b* o = cells.ptr<cv::Vec3b>(g.height_px - 1 - r);
    for (int c = 0; c < g.width_px; ++c) o[c] = wall[c] ? kWallCell : (h[c] > 0.0f ? col[c] : kEmptyCell);
  }
  cv::Mat map;
  cv::resize(cells, map, cv::Size(g.width_px * ppc, g.height_px * ppc), 0, 0, cv::INTER_NEAREST);
  const View main_view{&g, 0.0, 0.0, static_cast<double>(ppc)};
  // Markers sized to the picture, not to the plan's metres.
  const int long_side = std::max(map.cols, map.rows);
  const int radius = std::clamp(static_cast<int>(std::lround(0.012 * long_side)), 6, 28);
  const int thick = std::max(2, radius / 5);

  // Inset for large plans drawn at a small scale: a window around truth and estimate.
  const double plan_long_m = std::max(g.width_px, g.height_px) * g.resolution_m_per_px;
  const double px_per_m = ppc / g.resolution_m_per_px;
  const std::optional<PoseHypothesis> anchor = truth ? truth : estimate;
  const bool inset = style.decorations && anchor && plan_long_m > style.inset_min_plan_m && px_per_m < 12.0;
  cv::Mat inset_img;
  cv::Rect inset_on_map;
  double window_m = style.inset_window_m;
  if (inset) {
    double cx = anchor->x_m, cy = anchor->y_m;
    if (truth && estimate) {
      const double d = std::hypot(truth->x_m - estimate->x_m, truth->y_m - estimate->y_m);
      if (d < 0.7 * window_m) {  // both fit: centre between them
        cx = 0.5 * (truth->x_m + estimate->x_m);
        cy = 0.5 * (truth->y_m + estimate->y_m);
      }
    }
    const double cells_w = window_m / g.resolution_m_per_px;
    const double col0 = (cx - g.origin_x_m) / g.resolution_m_per_px - 0.5 * cells_w;
    const double row0 = g.height_px - (cy - g.origin_y_m) / g.resolution_m_per_px - 0.5 * cells_w;
    const int n = std::max(4, static_cast<int>(std::lround(cells_w)));
    const double inset_ppc = static_cast<double>(style.inset_side_px) / n;
    // Crop with padding outside the grid (light grey).
    cv::Mat crop(n, n, CV_8UC3, cv::Scalar(kEmptyCell));
    const int c0 = static_cast<int>(std::floor(col0)), r0 = static_cast<int>(std::floor(row0));
    const cv::Rect src = cv::Rect(c0, r0, n, n) & cv::Rect(0, 0, g.width_px, g.height_px);
    if (src.area() > 0) cells(src).copyTo(crop(cv::Rect(src.x - c0, src.y - r0, src.width, src.height)));
    cv::resize(crop, inset_img, cv::Size(style.inset_side_px, style.inset_side_px), 0, 0, cv::INTER_NEAREST);
    const View inset_view{&g, static_cast<double>(c0), static_cast<double>(r0), inset_ppc};
    const int ir = std::max(7, style.inset_side_px / 28);
    if (truth) draw_pose(inset_img, inset_view, *truth, true, ir, 2);
    if (estimate) draw_pose(inset_img, inset_view, *estimate, false, ir, 2);
    cv::rectangle(inset_img, cv::Rect(0, 0, inset_img.cols, inset_img.rows), cv::Scalar(60, 60, 60), 2);
    figure::draw_scale_bar(inset_img, {8, inset_img.rows - 30}, inset_ppc / g.resolution_m_per_px, inset_img.cols / 3);
    inset_on_map = cv::Rect(static_cast<int>(std::lround(c0 * ppc)), static_cast<int>(std::lround(r0 * ppc)), n * ppc, n * ppc);
  }
  if (inset) cv::rectangle(map, inset_on_map, cv::Scalar(255, 0, 255), 2, cv::LINE_AA);
  if (truth) draw_pose(map, main_view, *truth, true, radius, thick);
  if (estimate) draw_pose(map, main_view, *estimate, false, radius, thick);
  if (empty) {
    const int h = std::clamp(map.rows / 6, 40, 90);
    figure::draw_banner(map, cv::Rect(0, (map.rows - h) / 2, map.cols, h), "EMPTY POSTERIOR: no pose (every cell scored 0)",
                        cv::Scalar(40, 40, 200));
  }
  if (!style.decorations) return map;

  // Layout: header (title), map | right panel (colour bar, inset), footer (scale bar, legend).
  const int header = 44, footer = 46, margin = 10;
  const int panel = inset ? style.inset_side_px + 2 * margin : 150;
  const int width = std::max(map.cols + panel + 2 * margin, 560);
  const int bar_h = std::clamp(map.rows / 2, 120, 260);
  const int body = std::max(map.rows, inset ? bar_h + 50 + style.inset_side_px + 30 : bar_h + 40);
  cv::Mat img(header + body + footer, width, CV_8UC3, cv::Scalar(255, 255, 255));
  map.copyTo(img(cv::Rect(margin, header, map.cols, map.rows)));
  cv::rectangle(img, cv::Rect(margin - 1, header - 1, map.cols + 2, map.rows + 2), cv::Scalar(120, 120, 120), 1);
  const cv::Scalar ink(30, 30, 30);
  const std::string title = style.title.empty() ? "Posterior, max over yaw" : style.title;
  figure::draw_text(img, title, {margin, 30}, figure::fit_text_scale(title, 0.7, width - 2 * margin, 2), ink, 0, 2);

  const int px0 = margin + map.cols + 2 * margin;
  // Colour bar: position f along the bar shows relative score f^(1/gamma).
  std::vector<std::pair<double, std::string>> ticks;
  for (double s : {0.0, 0.05, 0.25, 0.5, 1.0}) {
    char t[16];
    std::snprintf(t, sizeof t, "%g", s);
    ticks.emplace_back(std::pow(s, style.gamma), t);
  }
  figure::draw_text(img, "score / max", {px0, header + 12}, 0.45, ink);
  figure::draw_colour_bar(img, cv::Rect(px0, header + 22, 22, bar_h), kColourMap, ticks,
                          "relative score (gamma " + figure::tick_text(style.gamma, 0.1) + ")");
  if (inset) {
    const int iy = header + 22 + bar_h + 40;
    char cap[64];
    std::snprintf(cap, sizeof cap, "zoom: %g m x %g m (magenta frame)", window_m, window_m);
    figure::draw_text(img, cap, {px0, iy - 8}, 0.45, ink);
    inset_img.copyTo(img(cv::Rect(px0, iy, inset_img.cols, inset_img.rows)));
  }
  // Footer: scale bar, legend.
  const int fy = header + body + 12;
  const cv::Rect sb = figure::draw_scale_bar(img, {margin + 6, fy}, px_per_m, std::max(40, map.cols / 4));
  std::vector<figure::LegendEntry> legend;
  if (truth) legend.push_back({'o', kTruthColour, "truth"});
  if (estimate) legend.push_back({'x', kEstimateColour, "estimate"});
  legend.push_back({'s', cv::Scalar(0, 0, 0), "walls"});
  legend.push_back({'s', cv::Scalar(kEmptyCell), "score 0"});
  figure::draw_legend_row(img, {sb.x + sb.width + 30, fy + 12}, legend);
  return img;
}

}  // namespace floorcast
