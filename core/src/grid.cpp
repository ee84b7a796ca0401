#include "floorcast/core/grid.hpp"

#include <cmath>
#include <iomanip>
#include <sstream>

#include "floorcast/core/limits.hpp"

namespace floorcast {

bool GridSpec::world_to_cell(const Vec2& p_m, int& row, int& col) const {
  const Vec2 g = world_to_grid(p_m);
  if (!std::isfinite(g.x()) || !std::isfinite(g.y())) return false;
  col = static_cast<int>(std::floor(g.x()));
  row = static_cast<int>(std::floor(g.y()));
  return contains(row, col);
}

void check_raster_budget(double width_px, double height_px, double resolution_m_per_px, double bytes_per_cell,
                         const std::string& what) {
  std::ostringstream grid;
  grid << what << ": raster of " << width_px << " x " << height_px << " cells at " << resolution_m_per_px << " m/px";
  const double cells = width_px * height_px;
  check_limit("max_raster_cells", cells, grid.str() + ":", "cells");
  std::ostringstream need;
  need << grid.str() << " needs about " << std::setprecision(3) << cells * bytes_per_cell / (1024.0 * 1024.0 * 1024.0)
       << " GiB:";
  check_limit("max_raster_bytes", cells * bytes_per_cell, need.str(), "bytes");
}

void check_raster_budget(const GridSpec& grid, double bytes_per_cell, const std::string& what) {
  check_raster_budget(grid.width_px, grid.height_px, grid.resolution_m_per_px, bytes_per_cell, what);
}

}  // namespace floorcast
