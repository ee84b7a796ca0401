// A regular 2D grid over the world plane (rasters, posteriors, beliefs).
//
// Cell (row r, col c) covers world x in [origin_x + c*res, origin_x + (c+1)*res) and y in
// [origin_y + r*res, origin_y + (r+1)*res). Rows grow with +y (so an image written as is appears
// upside down; renderers flip it).
#pragma once

#include <string>

#include "floorcast/core/types.hpp"

namespace floorcast {

struct GridSpec {
  double origin_x_m = 0.0;
  double origin_y_m = 0.0;
  double resolution_m_per_px = 0.1;
  int width_px = 0;
  int height_px = 0;

  Vec2 cell_center_m(int row, int col) const {
    return {origin_x_m + (col + 0.5) * resolution_m_per_px,
            origin_y_m + (row + 0.5) * resolution_m_per_px};
  }
  /// Continuous cell coordinates (col, row) of a world point (cell centres at integer + 0.5).
  Vec2 world_to_grid(const Vec2& p_m) const {
    return {(p_m.x() - origin_x_m) / resolution_m_per_px, (p_m.y() - origin_y_m) / resolution_m_per_px};
  }
  /// Cell containing p; false if outside the grid.
  bool world_to_cell(const Vec2& p_m, int& row, int& col) const;
  bool contains(int row, int col) const {
    return row >= 0 && col >= 0 && row < height_px && col < width_px;
  }
  bool operator==(const GridSpec& o) const {
    return origin_x_m == o.origin_x_m && origin_y_m == o.origin_y_m &&
           resolution_m_per_px == o.resolution_m_per_px && width_px == o.width_px &&
           height_px == o.height_px;
  }
};

/// Refuses a grid before anything is allocated over it: its cells against the limit
/// max_raster_cells, and `bytes_per_cell` (every raster, orientation and channel a stage keeps per
/// cell) times its cells against max_raster_bytes. `what` names the stage in the LimitError.
void check_raster_budget(const GridSpec& grid, double bytes_per_cell, const std::string& what);

/// The same check for a grid of width x height cells given as doubles (before they are known to
/// fit an int).
void check_raster_budget(double width_px, double height_px, double resolution_m_per_px, double bytes_per_cell,
                         const std::string& what);

}  // namespace floorcast
