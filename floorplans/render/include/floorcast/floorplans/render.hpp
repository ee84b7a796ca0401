// Drawing a floor plan for people: a BGR image (OpenCV) or an SVG document. Pure functions, no
// file I/O (the CLI writes the files). +y points up in the picture.
//
// What is drawn: walls black; glass walls and windows blue; doors as gaps, open ones with a swing
// arc and the leaf opened at 90 degrees, closed ones as a leaf in the door colour; obstacles grey
// (darker when taller than the cut height); the building interior lightly tinted (raster only);
// the plan name in a header band; a scale bar with its length in metres and a legend in a footer
// band. The returned PlanImage carries the world->pixel mapping so callers can draw overlays
// (heatmaps, poses, trajectories) on top. Door swings are drawn on the left of their wall's a->b
// direction (the generator orients walls so doors open into rooms and out of the building).
#pragma once

#include <opencv2/core.hpp>
#include <string>

#include "floorcast/floorplans/floor_plan.hpp"

namespace floorcast {

struct RenderOptions {
  double px_per_m = 20.0;       ///< scale of the map area
  double margin_m = 1.5;        ///< blank border around the plan's bounding box
  bool draw_interior = true;    ///< tint the building interior (valid-area mask; raster only)
  bool draw_obstacles = true;
  bool draw_door_swings = true;
  bool draw_title = true;       ///< header band with the plan name
  bool draw_scale_bar = true;   ///< footer band with scale bar (and legend)
  bool draw_legend = true;
  /// Metre coordinates: tick labels along the left and bottom edges of the map in bands of their
  /// own (the map moves right and the image grows; PlanImage's mapping accounts for it).
  bool draw_coordinates = false;
  /// Obstacles taller than this are drawn darker (they block a sensor held at this height).
  double cut_height_m = 1.5;
  /// Refuse images with a side longer than this (pixels): InputError.
  int max_side_px = 30000;
};

/// Colours (BGR) of the drawing; tests and overlays use them.
struct RenderColors {
  static cv::Scalar background() { return {255, 255, 255}; }
  static cv::Scalar interior() { return {238, 244, 247}; }
  static cv::Scalar wall() { return {0, 0, 0}; }
  static cv::Scalar glass() { return {235, 120, 20}; }
  static cv::Scalar door_closed() { return {0, 120, 230}; }
  static cv::Scalar door_swing() { return {110, 110, 110}; }
  static cv::Scalar obstacle_low() { return {200, 200, 200}; }
  static cv::Scalar obstacle_tall() { return {140, 140, 140}; }
  static cv::Scalar text() { return {30, 30, 30}; }
};

/// A rendered plan and its world->pixel mapping:
///   col = (x - origin_x_m) * px_per_m,   row = map_top_px + (top_y_m - y) * px_per_m
/// (pixel centres at integer + 0.5 in these continuous coordinates).
struct PlanImage {
  cv::Mat bgr;                 ///< CV_8UC3
  double px_per_m = 0.0;
  double origin_x_m = 0.0;     ///< world x at the left image edge
  double top_y_m = 0.0;        ///< world y at the top edge of the map area
  int map_top_px = 0;          ///< height of the header band above the map
  cv::Rect map_rect;           ///< the pixels showing the plan (between header and footer)

  cv::Point2d world_to_pixel(const Vec2& p_m) const {
    return {(p_m.x() - origin_x_m) * px_per_m, map_top_px + (top_y_m - p_m.y()) * px_per_m};
  }
  Vec2 pixel_to_world(const cv::Point2d& px) const {
    return {origin_x_m + px.x / px_per_m, top_y_m - (px.y - map_top_px) / px_per_m};
  }
};

/// World extent of the drawing before margins, [xmin, ymin, xmax, ymax]: wall rectangles
/// (extended by half their thickness past both ends) and exact obstacle shapes. The map area is
/// ceil((xmax - xmin + 2 margin) * px_per_m) x ceil((ymax - ymin + 2 margin) * px_per_m) pixels;
/// the image adds a 36 px header (title) and a 56 px footer (scale bar, legend) and is at least
/// 420 px wide when either is drawn (the map is then centred horizontally).
Eigen::Vector4d drawing_extent_m(const FloorPlan& plan);

/// Draws the plan. Throws InputError for a non-positive or non-finite scale or an image larger
/// than max_side_px.
PlanImage render_plan(const FloorPlan& plan, const RenderOptions& options = {});

/// The same drawing as an SVG document (pixel units, same mapping as render_plan; the interior
/// tint is left out).
std::string render_plan_svg(const FloorPlan& plan, const RenderOptions& options = {});

}  // namespace floorcast
