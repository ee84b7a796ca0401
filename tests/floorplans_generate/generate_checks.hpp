// Independent checks of generated buildings, shared by the generator tests.
#pragma once

#include <opencv2/imgproc.hpp>
#include <vector>

#include "floorcast/floorplans/generate.hpp"
#include "floorcast/floorplans/raster.hpp"

namespace floorcast::test {

/// Even-odd point-in-polygon (any simple polygon).
inline bool inside_polygon(const std::vector<Vec2>& poly, const Vec2& p) {
  bool in = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Vec2& a = poly[i];
    const Vec2& b = poly[j];
    if ((a.y() > p.y()) != (b.y() > p.y())) {
      const double x = a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
      if (p.x() < x) in = !in;
    }
  }
  return in;
}

inline double polygon_area(const std::vector<Vec2>& poly) {
  double a = 0.0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec2& p = poly[i];
    const Vec2& q = poly[(i + 1) % poly.size()];
    a += p.x() * q.y() - q.x() * p.y();
  }
  return 0.5 * a;
}

inline Vec2 polygon_centroid(const std::vector<Vec2>& poly) {
  Vec2 c = Vec2::Zero();
  double a = 0.0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec2& p = poly[i];
    const Vec2& q = poly[(i + 1) % poly.size()];
    const double w = p.x() * q.y() - q.x() * p.y();
    a += w;
    c += w * (p + q);
  }
  return c / (3.0 * a);
}

/// Exact (no gap bridging) inside/outside split of a plan with every door and window closed:
/// `outside` = free cells reachable from the grid border. A generated building's envelope must be
/// watertight, so its rooms never touch `outside`.
struct EnvelopeRaster {
  GridSpec grid;
  cv::Mat envelope;  ///< 255 = blocked with all doors/windows closed
  cv::Mat outside;   ///< 255 = free cell connected to the border
};

inline EnvelopeRaster envelope_raster(const FloorPlan& plan, double res) {
  EnvelopeRaster r;
  r.grid = grid_for_plan(plan, res);
  BlockingOptions env;
  env.closed_doors_block = true;
  env.open_doors_block = true;
  env.glass_blocks = true;
  env.obstacles_block = false;
  r.envelope = rasterize_occupancy(plan, r.grid, env);
  cv::Mat pad;
  cv::copyMakeBorder(r.envelope, pad, 1, 1, 1, 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  cv::floodFill(pad, cv::Point(0, 0), cv::Scalar(128), nullptr, cv::Scalar(0), cv::Scalar(0), 4);
  cv::compare(pad(cv::Rect(1, 1, r.envelope.cols, r.envelope.rows)), 128, r.outside, cv::CMP_EQ);
  return r;
}

/// Number of 4-connected components of the interior free space with every door open (door
/// openings count as interior; nothing is bridged).
inline int interior_components_doors_open(const FloorPlan& plan, double res) {
  const EnvelopeRaster env = envelope_raster(plan, res);
  FloorPlan open = plan;
  for (Door& d : open.doors) d.closed = false;
  BlockingOptions walk;
  walk.closed_doors_block = true;
  walk.open_doors_block = false;
  walk.glass_blocks = true;
  const cv::Mat occ = rasterize_occupancy(open, env.grid, walk);
  cv::Mat free_cells, not_outside, interior;
  cv::compare(occ, 0, free_cells, cv::CMP_EQ);
  cv::bitwise_not(env.outside, not_outside);
  cv::bitwise_and(free_cells, not_outside, interior);
  cv::Mat labels;
  return cv::connectedComponents(interior, labels, 4) - 1;
}

}  // namespace floorcast::test
