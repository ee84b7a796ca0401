#include "floorcast/eval/scan_sheet.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "floorcast/core/math.hpp"
#include "floorcast/core/types.hpp"
#include "floorcast/floorplans/figure.hpp"

namespace floorcast {
namespace {

constexpr int kColourMap = cv::COLORMAP_TURBO;

/// Yaw of a view's optical axis in the scan frame, degrees (camera z projected on the scan's xy).
double view_yaw_deg(const DepthView& v) {
  const Eigen::Vector3d z = v.T_scan_camera.linear().col(2);
  return std::atan2(z.y(), z.x()) * 180.0 / kPi;
}

cv::Mat colour_depth(const DepthView& v, double max_m) {
  cv::Mat d8(v.depth_m.rows, v.depth_m.cols, CV_8U);
  for (int r = 0; r < d8.rows; ++r) {
    const float* d = v.depth_m.ptr<float>(r);
    std::uint8_t* o = d8.ptr<std::uint8_t>(r);
    for (int c = 0; c < d8.cols; ++c) o[c] = static_cast<std::uint8_t>(std::clamp(std::lround(255.0 * d[c] / max_m), 0L, 255L));
  }
  cv::Mat out;
  cv::applyColorMap(d8, out, kColourMap);
  for (int r = 0; r < out.rows; ++r) {
    const float* d = v.depth_m.ptr<float>(r);
    const std::uint8_t* g = v.glass_mask.empty() ? nullptr : v.glass_mask.ptr<std::uint8_t>(r);
    cv::Vec3b* o = out.ptr<cv::Vec3b>(r);
    for (int c = 0; c < out.cols; ++c) {
      if (!(d[c] > 0.0f)) o[c] = cv::Vec3b(0, 0, 0);
      else if (g && g[c]) o[c] = cv::Vec3b(static_cast<std::uint8_t>((o[c][0] + 255) / 2), static_cast<std::uint8_t>(o[c][1] / 2),
                                            static_cast<std::uint8_t>((o[c][2] + 255) / 2));
    }
  }
  return out;
}

}  // namespace

cv::Mat draw_scan_contact_sheet(const Scan& scan, const std::string& title, const ScanSheetStyle& style) {
  if (scan.views.empty()) throw InputError("contact sheet: the scan has no views");
  bool any_rgb = false, any_depth = false;
  std::vector<float> depths;
  for (std::size_t k = 0; k < scan.views.size(); ++k) {
    const DepthView& v = scan.views[k];
    if (v.depth_m.empty() && v.rgb.empty()) throw InputError("contact sheet: view " + std::to_string(k) + " has neither depth nor colour");
    any_rgb = any_rgb || !v.rgb.empty();
    any_depth = any_depth || !v.depth_m.empty();
    if (!v.depth_m.empty())
      for (int r = 0; r < v.depth_m.rows; r += 4)
        for (int c = 0; c < v.depth_m.cols; c += 4)
          if (v.depth_m.at<float>(r, c) > 0.0f) depths.push_back(v.depth_m.at<float>(r, c));
  }
  double max_m = 1.0;
  if (!depths.empty()) {
    const std::size_t q = std::min(depths.size() - 1, static_cast<std::size_t>(0.99 * static_cast<double>(depths.size())));
    std::nth_element(depths.begin(), depths.begin() + static_cast<std::ptrdiff_t>(q), depths.end());
    max_m = std::max(1.0, std::ceil(static_cast<double>(depths[q])));
  }
  const int n = static_cast<int>(scan.views.size());
  const int cols = std::max(1, std::min(style.columns, n));
  const int rows = (n + cols - 1) / cols;
  const DepthView& v0 = scan.views.front();
  const int W = style.tile_width_px;
  const int H = static_cast<int>(std::lround(static_cast<double>(W) * v0.intrinsics.height_px / v0.intrinsics.width_px));
  const int caption = 22, gap = 8;
  const int layers = (any_rgb ? 1 : 0) + (any_depth ? 1 : 0);
  const int cell_h = caption + layers * H + (layers - 1) * 2 + gap;
  const int header = 46, bar_panel = any_depth ? 110 : 0, footer = 10;
  const int width = gap + cols * (W + gap) + bar_panel;
  cv::Mat img(header + rows * cell_h + footer, width, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Scalar ink(30, 30, 30);
  figure::draw_text(img, title, {gap, 30}, figure::fit_text_scale(title, 0.7, width - 2 * gap, 2), ink, 0, 2);
  for (int k = 0; k < n; ++k) {
    const DepthView& v = scan.views[static_cast<std::size_t>(k)];
    const int x = gap + (k % cols) * (W + gap), y = header + (k / cols) * cell_h;
    double valid = 0.0;
    if (!v.depth_m.empty()) valid = 100.0 * cv::countNonZero(v.depth_m > 0.0f) / static_cast<double>(v.depth_m.total());
    char cap[96];
    if (!v.depth_m.empty()) std::snprintf(cap, sizeof cap, "view %d  yaw %.0f deg  %.0f%% depth", v.view_index, view_yaw_deg(v), valid);
    else std::snprintf(cap, sizeof cap, "view %d  yaw %.0f deg", v.view_index, view_yaw_deg(v));
    figure::draw_text(img, cap, {x, y + 15}, figure::fit_text_scale(cap, 0.42, W), ink);
    int ty = y + caption;
    const int h = static_cast<int>(std::lround(static_cast<double>(W) * v.intrinsics.height_px / v.intrinsics.width_px));
    auto place = [&](const cv::Mat& tile) {
      cv::Mat scaled;
      cv::resize(tile, scaled, cv::Size(W, std::min(h, H)), 0, 0, cv::INTER_AREA);
      scaled.copyTo(img(cv::Rect(x, ty, scaled.cols, scaled.rows)));
      ty += H + 2;
    };
    if (any_rgb) {
      if (!v.rgb.empty()) place(v.rgb);
      else ty += H + 2;
    }
    if (any_depth && !v.depth_m.empty()) place(colour_depth(v, max_m));
  }
  if (any_depth) {
    std::vector<std::pair<double, std::string>> ticks;
    const double step = figure::nice_step(max_m, 5);
    for (double t = 0.0; t <= max_m + 1e-9; t += step) ticks.emplace_back(t / max_m, figure::tick_text(t, step));
    const int bar_h = std::min(260, rows * cell_h - 40);
    figure::draw_colour_bar(img, cv::Rect(width - bar_panel + 10, header + 20, 20, std::max(60, bar_h)), kColourMap, ticks,
                            "depth [m] (black: none)");
  }
  return img;
}

}  // namespace floorcast
