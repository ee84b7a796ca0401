// The F3Loc "desdf": for every valid grid cell and each of D equiangular world directions, the
// distance from the cell centre (or corner: sample_offset) to the first wall surface, clipped at a
// maximum range.
//
// Computed exactly in 2D, per direction, by z-buffering: the origins whose ray along u meets a
// front-facing outline segment (a, b) within the range form the parallelogram
// {a, b, b - range*u, a - range*u}; every cell centre inside it gets t = distance to the segment
// along u, and each cell keeps the minimum. Directions run in parallel (TBB), each with its own
// buffer, so results do not depend on the thread count.
//
// compute_distance_volume_raster is F3Loc's own way (generate_desdf.raycast_desdf with
// utils.ray_cast): a march through a fine occupancy image, reproduced arithmetic for arithmetic.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "floorcast/floorplans/raster.hpp"

namespace floorcast {

struct DistanceVolume {
  GridSpec grid;
  int num_directions = 0;   ///< direction d points at world angle 2 pi d / num_directions (CCW from +x)
  double max_range_m = 0.0;
  /// Where the distances of cell (row, col) are cast from: grid origin + (col + sample_offset,
  /// row + sample_offset) * resolution (0.5: the cell centre; 0: its corner, as F3Loc's desdf).
  double sample_offset = 0.5;
  /// Stored cells in row-major order: linear index row * width + col.
  std::vector<std::int32_t> cells;
  /// Per grid cell (row-major), its index into `cells`, or -1.
  std::vector<std::int32_t> cell_index;
  /// Bits per stored distance: 16 (millimetres, in `mm`) or 8 (units of step_mm, rounded to the
  /// nearest, in `q8`: 10 m in 40 mm steps).
  int bits = 16;
  /// Distance unit of the stored values, mm (1 for 16 bits; ceil(max_range / 255) for 8 bits).
  int step_mm = 1;
  /// 16 bits: distances in millimetres (clipped at max_range_m), direction-major:
  /// mm[d * cells.size() + i].
  std::vector<std::uint16_t> mm;
  /// 8 bits: distances in units of step_mm, same layout.
  std::vector<std::uint8_t> q8;

  std::size_t num_cells() const { return cells.size(); }
  /// Stored value (units of step_mm) of cell i along direction d.
  int units(std::size_t i, int d) const {
    const std::size_t k = static_cast<std::size_t>(d) * cells.size() + i;
    return bits == 8 ? q8[k] : mm[k];
  }
  /// Largest stored value (units of step_mm): the clipping range.
  int max_units() const;
  /// Distance of stored cell i along direction d, metres.
  double range_m(std::size_t i, int d) const { return units(i, d) * step_mm * 1e-3; }
  /// Bytes held (cells, index, distances).
  std::size_t bytes() const {
    return cells.size() * sizeof(std::int32_t) + cell_index.size() * sizeof(std::int32_t) +
           mm.size() * sizeof(std::uint16_t) + q8.size();
  }
};

/// For every cell of `grid` whose cast point (origin + (col + offset, row + offset) * resolution;
/// offset 0.5: the centre) lies inside the parallelogram {a, b, b - range u, a - range u} (the
/// origins whose ray along the unit direction u meets segment a-b within `range`), calls
/// visit(row, col, t) with t = the distance along u from the cast point to the segment, clamped to
/// [0, range]. Rows in increasing order, columns in increasing order within a row. The sweep of the
/// distance volume (compute_distance_volume) and of the BEV matcher's semantic volume.
template <class Visit>
void sweep_segment(const GridSpec& grid, const Vec2& a, const Vec2& b, const Vec2& u, double range, double offset,
                   Visit&& visit) {
  auto cross = [](const Vec2& p, const Vec2& q) { return p.x() * q.y() - p.y() * q.x(); };
  const Vec2 e = b - a;
  const double ue = cross(u, e);
  const Vec2 back = -range * u;
  const Vec2 quad[4] = {a, b, b + back, a + back};
  double ymin = quad[0].y(), ymax = quad[0].y();
  for (const Vec2& q : quad) {
    ymin = std::min(ymin, q.y());
    ymax = std::max(ymax, q.y());
  }
  const double res = grid.resolution_m_per_px;
  const double ox = grid.origin_x_m, oy = grid.origin_y_m;
  // Rows whose cast point y lies in [ymin, ymax].
  const int r0 = std::max(0, static_cast<int>(std::ceil((ymin - oy) / res - offset)));
  const int r1 = std::min(grid.height_px - 1, static_cast<int>(std::floor((ymax - oy) / res - offset)));
  const double inv_ue = 1.0 / ue;
  for (int r = r0; r <= r1; ++r) {
    const double y = oy + (r + offset) * res;
    // The quad's x-interval on this horizontal line: intersections with its edges.
    double xl = 1e300, xr = -1e300;
    for (int k = 0; k < 4; ++k) {
      const Vec2& p = quad[k];
      const Vec2& q = quad[(k + 1) % 4];
      const double dy = q.y() - p.y();
      if (dy == 0.0) {
        if (y == p.y()) {
          xl = std::min({xl, p.x(), q.x()});
          xr = std::max({xr, p.x(), q.x()});
        }
        continue;
      }
      const double s = (y - p.y()) / dy;
      if (s < 0.0 || s > 1.0) continue;
      const double x = p.x() + s * (q.x() - p.x());
      xl = std::min(xl, x);
      xr = std::max(xr, x);
    }
    if (xl > xr) continue;
    const int c0 = std::max(0, static_cast<int>(std::ceil((xl - ox) / res - offset)));
    const int c1 = std::min(grid.width_px - 1, static_cast<int>(std::floor((xr - ox) / res - offset)));
    if (c0 > c1) continue;
    // t(x) = cross(a - p, e) / cross(u, e) is affine in x along the row.
    const double ay = a.y() - y;
    for (int c = c0; c <= c1; ++c) {
      const double x = ox + (c + offset) * res;
      const double t = ((a.x() - x) * e.y() - ay * e.x()) * inv_ue;
      visit(r, c, std::clamp(t, 0.0, range));
    }
  }
}

/// True when a ray along u meets segment s from its free (left) side: the faces a ray enters.
inline bool front_facing(const Vec2& u, const Segment2& s) {
  const Vec2 e = s.b_m - s.a_m;
  return u.x() * e.y() - u.y() * e.x() > 1e-12 * e.norm();
}

/// Distances from the cast point (sample_offset) of every non-zero cell of `mask` (CV_8U, on
/// `grid`) along num_directions directions to the nearest of `segments` (any orientation is a wall
/// surface; a segment is hit only from its free, left side, as the blocking outline is oriented),
/// clipped at max_range_m (<= 65.535 m), stored in `bits` (16: mm; 8: units of
/// ceil(max_range / 255)).
DistanceVolume compute_distance_volume(const std::vector<Segment2>& segments, const GridSpec& grid,
                                       const cv::Mat& mask, int num_directions, double max_range_m, int bits = 16,
                                       double sample_offset = 0.5);

/// A binary image, one bit per pixel (set = blocked), row-major: fine occupancy images of whole
/// buildings (0.01 m/px: 100 pixels per 0.1 m cell) without a byte per pixel.
struct BitRaster {
  BitRaster() = default;
  BitRaster(int width_px, int height_px);
  int width = 0;
  int height = 0;
  std::vector<std::uint64_t> words;
  bool blocked(int row, int col) const;
  void set(int row, int col);
  std::size_t bytes() const { return words.size() * sizeof(std::uint64_t); }
};

/// F3Loc's ray_cast (utils/utils.py), arithmetic for arithmetic: from (pos_row, pos_col) in pixel
/// units (pixel (r, c) covers [r, r + 1) x [c, c + 1); the angle counter-clockwise in the
/// (col = x, row = y) frame), cardinal directions step one pixel at a time, other directions walk
/// the pixel-boundary crossings (the next row or column boundary, by comparing tan(angle) with the
/// slope to the next corner), and each crossing tests the pixel at (int(row), int(col)) of the
/// crossing point: the pixel entered when moving up or right, the pixel just crossed when moving
/// down or left (F3Loc's own asymmetry, kept); the start pixel is never tested. Returns the
/// Euclidean distance (pixels) from the start to the crossing point of the first blocked pixel, or
/// dist_max_px when the ray leaves the image. F3Loc marches until a hit or the image border;
/// here the march also stops (returning dist_max_px) once it is farther than stop_px, which gives
/// the same distance after clipping at any range <= stop_px.
///
/// With a skip map the march jumps over empty space (see RasterSkipMap): the same pixels are
/// tested up to the hit except free ones, and the hit's crossing point is recomputed from the
/// landing point, so distances agree with the literal march to round-off (a crossing that passes
/// exactly through a pixel corner may then fall to the other side: at most one pixel).
struct RasterSkipMap {
  int ratio = 1;   ///< pixels per block side
  cv::Mat blocks;  ///< CV_8U per block: chessboard distance (blocks, saturated at 255) to the
                   ///< nearest block holding a blocked pixel (0: the block holds one)
};
RasterSkipMap make_raster_skip_map(const BitRaster& occupancy, int ratio);
double f3loc_ray_cast(const BitRaster& occupancy, double pos_row, double pos_col, double angle_rad, double dist_max_px,
                      double stop_px, const RasterSkipMap* skip = nullptr);

/// F3Loc's desdf (generate_desdf.raycast_desdf): for every non-zero cell of `mask`, f3loc_ray_cast
/// from fine pixel ((row + sample_offset) * ratio, (col + sample_offset) * ratio) of `occupancy`
/// (which covers `grid` at ratio x its resolution: F3Loc 0.01 m/px for a 0.1 m desdf) along
/// theta_d = d / D * pi * 2, times the fine resolution, clipped at max_range_m (F3Loc truncates the
/// desdf at 10 m when loading it).
DistanceVolume compute_distance_volume_raster(const BitRaster& occupancy, int ratio, const GridSpec& grid,
                                              const cv::Mat& mask, int num_directions, double max_range_m,
                                              int bits = 16, double sample_offset = 0.5);

/// The obvious version: min over every segment (either side) of the ray-segment distance, clipped.
double brute_force_ray_distance(const std::vector<Segment2>& segments, const Vec2& origin_m, double angle_rad,
                                double max_range_m);

/// Ranges along n equiangular rays (ray i at observer-frame angle 2 pi i / n) from the observer
/// (origin of the observer frame) to the nearest observed segment (either side), clipped at
/// max_range_m: an observation's rays cast against its own segments.
std::vector<double> cast_rays_on_segments(const std::vector<Segment2>& segments_m, int n, double max_range_m);

}  // namespace floorcast
