// The map a tracker moves particles and beliefs in (internal): walls and glass of the plan at a
// fine resolution (doorways pass, open or closed: a map cannot know a door's state), and the
// building's interior. Exact cell traversal (Amanatides-Woo) for wall crossings, no allocation.
#pragma once

#include <opencv2/core.hpp>

#include "floorcast/core/blocking.hpp"
#include "floorcast/core/grid.hpp"
#include "floorcast/floorplans/floor_plan.hpp"

namespace floorcast {

struct WallRaster {
  GridSpec grid;
  cv::Mat blocked;  ///< CV_8U, 255 = wall or glass
  cv::Mat interior;  ///< CV_8U, 255 = free cell inside the building
  /// CV_32F metres from each cell centre to the nearest blocked cell centre: a move shorter than
  /// this minus a cell diagonal cannot touch a wall, so most moves skip the traversal.
  cv::Mat clearance_m;
  /// What the particle filter reads per move, one byte per cell (a quarter of clearance_m's
  /// memory, one cache line instead of two for the interior and the clearance): bit 7 = interior,
  /// bits 0-6 = the clearance in whole cells, rounded down and capped at 127 (a smaller clearance
  /// than clearance_m only sends more moves to the exact traversal: same answers).
  cv::Mat cell_info;
  double inv_res = 0.0;

  /// Cell of p (false outside the grid); no allocation, no libm.
  bool cell_of(const Vec2& p, int& r, int& c) const {
    const double gx = (p.x() - grid.origin_x_m) * inv_res, gy = (p.y() - grid.origin_y_m) * inv_res;
    if (!(gx >= 0.0 && gy >= 0.0 && gx < grid.width_px && gy < grid.height_px)) return false;
    c = static_cast<int>(gx);
    r = static_cast<int>(gy);
    return true;
  }
  bool inside(const Vec2& p) const {
    int r = 0, c = 0;
    return cell_of(p, r, c) && (cell_info.at<std::uint8_t>(r, c) & 0x80) != 0;
  }
  /// True when the segment a-b passes through a blocked cell (or leaves the grid); `stop`
  /// receives a point just before the first blocked cell.
  bool crosses(const Vec2& a, const Vec2& b, Vec2* stop) const;
  std::size_t bytes() const { return blocked.total() + interior.total() + clearance_m.total() * sizeof(float) + cell_info.total(); }
};

/// What blocks a walker in a map: walls and glass; doors never (closed_doors_block false).
BlockingOptions map_walls();

WallRaster make_wall_raster(const FloorPlan& plan, double resolution_m);

}  // namespace floorcast
