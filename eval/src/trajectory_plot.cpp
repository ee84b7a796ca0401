#include "floorcast/eval/trajectory_plot.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

#include "floorcast/floorplans/render.hpp"

namespace floorcast {

cv::Mat draw_plan_with_trajectories(const FloorPlan& plan, const std::vector<TrajectoryLayer>& lines,
                                    const std::vector<MarkerLayer>& markers, const std::string& title,
                                    int max_side_px) {
  const Eigen::Vector4d e = drawing_extent_m(plan);
  RenderOptions ro;
  const double side_m = std::max(e[2] - e[0], e[3] - e[1]) + 2.0 * ro.margin_m;
  ro.px_per_m = std::max(4.0, std::min(60.0, max_side_px / std::max(side_m, 1.0)));
  FloorPlan titled = plan;
  titled.name = title;
  PlanImage pi = render_plan(titled, ro);
  cv::Mat& img = pi.bgr;
  for (const TrajectoryLayer& l : lines) {
    std::vector<cv::Point> pts;
    for (const Vec2& p : l.points_m) {
      const cv::Point2d q = pi.world_to_pixel(p);
      pts.emplace_back(static_cast<int>(std::lround(q.x)), static_cast<int>(std::lround(q.y)));
    }
    if (l.segments) {
      for (std::size_t i = 0; i + 1 < pts.size(); i += 2) cv::line(img, pts[i], pts[i + 1], l.colour, l.thickness_px, cv::LINE_AA);
    } else if (pts.size() >= 2) {
      cv::polylines(img, pts, false, l.colour, l.thickness_px, cv::LINE_AA);
    }
  }
  for (const MarkerLayer& m : markers) {
    for (const Vec2& p : m.points_m) {
      const cv::Point2d q = pi.world_to_pixel(p);
      cv::circle(img, cv::Point(static_cast<int>(std::lround(q.x)), static_cast<int>(std::lround(q.y))), m.radius_px,
                 m.colour, m.filled ? cv::FILLED : 2, cv::LINE_AA);
    }
  }
  // Legend of the layers, top-left of the map area, on a white box (a layer without a label
  // continues the one before it, e.g. a trajectory split where it jumps: no row of its own).
  const int line_h = 20, pad = 8;
  int rows = 0;
  for (const auto& l : lines) rows += l.label.empty() ? 0 : 1;
  for (const auto& m : markers) rows += m.label.empty() ? 0 : 1;
  if (rows > 0) {
    int text_w = 0;
    for (const auto& l : lines) text_w = std::max(text_w, cv::getTextSize(l.label, cv::FONT_HERSHEY_SIMPLEX, 0.5, 1, nullptr).width);
    for (const auto& m : markers) text_w = std::max(text_w, cv::getTextSize(m.label, cv::FONT_HERSHEY_SIMPLEX, 0.5, 1, nullptr).width);
    const cv::Rect box(pi.map_rect.x + pad, pi.map_rect.y + pad, text_w + 3 * pad + 28, rows * line_h + pad);
    const cv::Rect clipped = box & cv::Rect(0, 0, img.cols, img.rows);
    img(clipped).setTo(cv::Scalar(255, 255, 255));
    cv::rectangle(img, clipped, cv::Scalar(120, 120, 120), 1);
    int y = box.y + pad / 2 + line_h / 2;
    for (const auto& l : lines) {
      if (l.label.empty()) continue;
      cv::line(img, {box.x + pad, y}, {box.x + pad + 24, y}, l.colour, l.thickness_px, cv::LINE_AA);
      cv::putText(img, l.label, {box.x + 2 * pad + 24, y + 5}, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(30, 30, 30), 1, cv::LINE_AA);
      y += line_h;
    }
    for (const auto& m : markers) {
      if (m.label.empty()) continue;
      cv::circle(img, {box.x + pad + 12, y}, std::min(m.radius_px, 6), m.colour, m.filled ? cv::FILLED : 2, cv::LINE_AA);
      cv::putText(img, m.label, {box.x + 2 * pad + 24, y + 5}, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(30, 30, 30), 1, cv::LINE_AA);
      y += line_h;
    }
  }
  return img;
}

}  // namespace floorcast
