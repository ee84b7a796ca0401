// Trajectories over a floor plan, for people: the plan (floorplans/render.hpp: title band, scale
// bar, legend of the plan's elements) with polylines (true path, odometry, estimate) and point
// markers (start, observations, particles, convergence) drawn on top, and a legend of the layers.
// Pure: returns a BGR image.
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "floorcast/floorplans/floor_plan.hpp"

namespace floorcast {

struct TrajectoryLayer {
  std::string label;  ///< "" = a continuation of the layer before (no legend row)
  std::vector<Vec2> points_m;
  cv::Scalar colour;
  int thickness_px = 2;
  /// Points taken in pairs (a0, b0, a1, b1, ...) as separate segments (e.g. observed walls)
  /// instead of one polyline.
  bool segments = false;
};

struct MarkerLayer {
  std::string label;
  std::vector<Vec2> points_m;
  cv::Scalar colour;
  int radius_px = 4;
  bool filled = true;
};

/// Draws the plan with `lines` and `markers` on top (in order), `title` in the header band and a
/// legend of the layers in the map's top-left corner. The scale is chosen so the longer side of the
/// map is at most max_side_px (at least 4 px per metre).
cv::Mat draw_plan_with_trajectories(const FloorPlan& plan, const std::vector<TrajectoryLayer>& lines,
                                    const std::vector<MarkerLayer>& markers, const std::string& title,
                                    int max_side_px = 1600);

}  // namespace floorcast
