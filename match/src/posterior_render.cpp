#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "floorcast/match/posterior.hpp"

namespace floorcast {
namespace {

cv::Point to_image(const Posterior& post, int ppc, double x, double y) {
  const GridSpec& g = post.grid;
  const double col = (x - g.origin_x_m) / g.resolution_m_per_px * ppc;
  const double row = (y - g.origin_y_m) / g.resolution_m_per_px * ppc;
  return {static_cast<int>(std::lround(col)), static_cast<int>(std::lround(g.height_px * ppc - row))};
}

void draw_heading(cv::Mat& img, const Posterior& post, int ppc, const PoseHypothesis& h, double len_m,
                  const cv::Scalar& colour, int thickness) {
  const cv::Point a = to_image(post, ppc, h.x_m, h.y_m);
  const cv::Point b = to_image(post, ppc, h.x_m + len_m * std::cos(h.yaw_rad), h.y_m + len_m * std::sin(h.yaw_rad));
  cv::arrowedLine(img, a, b, colour, thickness, cv::LINE_AA, 0, 0.3);
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

  cv::Mat heat = post.scores.empty() ? cv::Mat::zeros(g.height_px, g.width_px, CV_32F) : post.max_over_yaw();
  double mx = 0.0;
  cv::minMaxLoc(heat, nullptr, &mx);
  cv::Mat heat8(g.height_px, g.width_px, CV_8U, cv::Scalar(0));
  if (mx > 0.0) {
    for (int r = 0; r < g.height_px; ++r) {
      const float* h = heat.ptr<float>(r);
      std::uint8_t* o = heat8.ptr<std::uint8_t>(r);
      for (int c = 0; c < g.width_px; ++c) {
        o[c] = static_cast<std::uint8_t>(std::lround(255.0 * std::pow(h[c] / mx, style.gamma)));
      }
    }
  }
  cv::Mat colour;
  cv::applyColorMap(heat8, colour, cv::COLORMAP_TURBO);
  cv::Mat img(g.height_px, g.width_px, CV_8UC3);
  for (int r = 0; r < g.height_px; ++r) {
    const float* h = heat.ptr<float>(r);
    const std::uint8_t* wall = plan_raster.ptr<std::uint8_t>(r);
    const cv::Vec3b* col = colour.ptr<cv::Vec3b>(r);
    cv::Vec3b* o = img.ptr<cv::Vec3b>(r);
    for (int c = 0; c < g.width_px; ++c) {
      if (wall[c]) o[c] = cv::Vec3b(0, 0, 0);
      else if (h[c] > 0.0f) o[c] = col[c];
      else o[c] = cv::Vec3b(235, 235, 235);
    }
  }
  cv::Mat big;
  cv::resize(img, big, cv::Size(g.width_px * ppc, g.height_px * ppc), 0, 0, cv::INTER_NEAREST);
  cv::flip(big, big, 0);  // rows grow with +y in the grid; images grow downwards
  const int marker = std::max(6, static_cast<int>(std::lround(0.5 / g.resolution_m_per_px * ppc)));
  const int thick = std::max(1, ppc / 2);
  if (truth) {
    cv::circle(big, to_image(post, ppc, truth->x_m, truth->y_m), marker, cv::Scalar(0, 200, 0), thick + 1, cv::LINE_AA);
    draw_heading(big, post, ppc, *truth, 1.5, cv::Scalar(0, 200, 0), thick + 1);
  }
  if (estimate) {
    const cv::Point p = to_image(post, ppc, estimate->x_m, estimate->y_m);
    cv::drawMarker(big, p, cv::Scalar(0, 0, 255), cv::MARKER_TILTED_CROSS, 2 * marker, thick + 1, cv::LINE_AA);
    draw_heading(big, post, ppc, *estimate, 1.5, cv::Scalar(0, 0, 255), thick + 1);
  }
  return big;
}

}  // namespace floorcast
