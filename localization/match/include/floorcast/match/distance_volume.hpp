// The F3Loc "desdf": for every valid grid cell and each of D equiangular world directions, the
// distance from the cell centre to the first wall surface, clipped at a maximum range.
//
// Computed exactly in 2D, per direction, by z-buffering: the origins whose ray along u meets a
// front-facing outline segment (a, b) within the range form the parallelogram
// {a, b, b - range*u, a - range*u}; every cell centre inside it gets t = distance to the segment
// along u, and each cell keeps the minimum. Directions run in parallel (TBB), each with its own
// buffer, so results do not depend on the thread count.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "floorcast/floorplans/raster.hpp"

namespace floorcast {

struct DistanceVolume {
  GridSpec grid;
  int num_directions = 0;   ///< direction d points at world angle 2 pi d / num_directions (CCW from +x)
  double max_range_m = 0.0;
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

/// Distances from the centre of every non-zero cell of `mask` (CV_8U, on `grid`) along
/// num_directions directions to the nearest of `segments` (any orientation is a wall surface; a
/// segment is hit only from its free, left side, as the blocking outline is oriented), clipped at
/// max_range_m (<= 65.535 m), stored in `bits` (16: mm; 8: units of ceil(max_range / 255)).
DistanceVolume compute_distance_volume(const std::vector<Segment2>& segments, const GridSpec& grid,
                                       const cv::Mat& mask, int num_directions, double max_range_m, int bits = 16);

/// The obvious version: min over every segment (either side) of the ray-segment distance, clipped.
double brute_force_ray_distance(const std::vector<Segment2>& segments, const Vec2& origin_m, double angle_rad,
                                double max_range_m);

/// Ranges along n equiangular rays (ray i at observer-frame angle 2 pi i / n) from the observer
/// (origin of the observer frame) to the nearest observed segment (either side), clipped at
/// max_range_m: an observation's rays cast against its own segments.
std::vector<double> cast_rays_on_segments(const std::vector<Segment2>& segments_m, int n, double max_range_m);

}  // namespace floorcast
