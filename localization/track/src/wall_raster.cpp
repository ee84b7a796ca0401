#include "wall_raster.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "floorcast/floorplans/raster.hpp"

namespace floorcast {

BlockingOptions map_walls() {
  BlockingOptions b;
  b.closed_doors_block = false;
  b.open_doors_block = false;
  b.glass_blocks = true;
  b.obstacles_block = false;
  b.cut_height_m = 1.0;
  return b;
}

WallRaster make_wall_raster(const FloorPlan& plan, double resolution_m) {
  WallRaster w;
  w.grid = grid_for_plan(plan, resolution_m, 0.5);
  w.blocked = rasterize_occupancy(plan, w.grid, map_walls());
  const cv::Mat interior = valid_area_mask(plan, w.grid);
  cv::bitwise_and(interior, w.blocked == 0, w.interior);
  w.clearance_m = distance_to_blocked_m(w.blocked, w.grid);
  w.inv_res = 1.0 / w.grid.resolution_m_per_px;
  w.cell_info = cv::Mat::zeros(w.blocked.size(), CV_8U);
  for (int r = 0; r < w.cell_info.rows; ++r) {
    const float* clear = w.clearance_m.ptr<float>(r);
    const std::uint8_t* in = w.interior.ptr<std::uint8_t>(r);
    std::uint8_t* info = w.cell_info.ptr<std::uint8_t>(r);
    for (int c = 0; c < w.cell_info.cols; ++c) {
      const double cells = std::floor(static_cast<double>(clear[c]) * w.inv_res * (1.0 - 1e-9));
      info[c] = static_cast<std::uint8_t>((in[c] ? 0x80 : 0) | static_cast<int>(std::clamp(cells, 0.0, 127.0)));
    }
  }
  return w;
}

bool WallRaster::crosses(const Vec2& a, const Vec2& b, Vec2* stop) const {
  // Far from every wall: the segment stays within the clear disc around a (the byte map's
  // clearance, at most clearance_m's).
  {
    int ra = 0, ca = 0, rb = 0, cb = 0;
    if (cell_of(a, ra, ca) && cell_of(b, rb, cb)) {
      const double reach = (b - a).norm() + 1.5 * grid.resolution_m_per_px;
      if ((cell_info.at<std::uint8_t>(ra, ca) & 0x7f) * grid.resolution_m_per_px > reach) return false;
    }
  }
  const Vec2 ga = grid.world_to_grid(a), gb = grid.world_to_grid(b);  // (col, row) continuous
  int c = static_cast<int>(std::floor(ga.x())), r = static_cast<int>(std::floor(ga.y()));
  const int c_end = static_cast<int>(std::floor(gb.x())), r_end = static_cast<int>(std::floor(gb.y()));
  const Vec2 d = gb - ga;
  const int step_c = d.x() > 0 ? 1 : -1, step_r = d.y() > 0 ? 1 : -1;
  const double inf = std::numeric_limits<double>::infinity();
  const double t_delta_c = d.x() != 0.0 ? std::abs(1.0 / d.x()) : inf;
  const double t_delta_r = d.y() != 0.0 ? std::abs(1.0 / d.y()) : inf;
  double t_max_c = d.x() > 0 ? (c + 1 - ga.x()) * t_delta_c : (d.x() < 0 ? (ga.x() - c) * t_delta_c : inf);
  double t_max_r = d.y() > 0 ? (r + 1 - ga.y()) * t_delta_r : (d.y() < 0 ? (ga.y() - r) * t_delta_r : inf);
  double t_enter = 0.0;
  const int max_steps = std::abs(c_end - c) + std::abs(r_end - r) + 2;
  for (int k = 0; k <= max_steps; ++k) {
    if (!grid.contains(r, c) || blocked.at<std::uint8_t>(r, c) != 0) {
      if (stop) {
        // Back off a hundredth of a cell from where the segment entered the blocked cell.
        const double len = d.norm();
        const double back = len > 0.0 ? 0.01 / len : 0.0;
        const double t = std::max(0.0, t_enter - back);
        *stop = a + (b - a) * t;
      }
      return true;
    }
    if (c == c_end && r == r_end) return false;
    if (t_max_c < t_max_r) {
      t_enter = t_max_c;
      t_max_c += t_delta_c;
      c += step_c;
    } else {
      t_enter = t_max_r;
      t_max_r += t_delta_r;
      r += step_r;
    }
    if (t_enter > 1.0) return false;
  }
  return false;
}

}  // namespace floorcast
