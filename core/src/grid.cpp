#include "floorcast/core/grid.hpp"

#include <cmath>

namespace floorcast {

bool GridSpec::world_to_cell(const Vec2& p_m, int& row, int& col) const {
  const Vec2 g = world_to_grid(p_m);
  if (!std::isfinite(g.x()) || !std::isfinite(g.y())) return false;
  col = static_cast<int>(std::floor(g.x()));
  row = static_cast<int>(std::floor(g.y()));
  return contains(row, col);
}

}  // namespace floorcast
