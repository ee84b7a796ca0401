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
  /// Distances in millimetres (clipped at max_range_m), direction-major:
  /// mm[d * cells.size() + i].
  std::vector<std::uint16_t> mm;

  std::size_t num_cells() const { return cells.size(); }
  /// Distance of stored cell i along direction d, metres.
  double range_m(std::size_t i, int d) const {
    return mm[static_cast<std::size_t>(d) * cells.size() + i] * 1e-3;
  }
  /// Bytes held (cells, index, distances).
  std::size_t bytes() const {
    return cells.size() * sizeof(std::int32_t) + cell_index.size() * sizeof(std::int32_t) +
           mm.size() * sizeof(std::uint16_t);
  }
};

/// Distances from the centre of every non-zero cell of `mask` (CV_8U, on `grid`) along
/// num_directions directions to the nearest of `segments` (any orientation is a wall surface; a
/// segment is hit only from its free, left side, as the blocking outline is oriented), clipped at
/// max_range_m (<= 65.535 m).
DistanceVolume compute_distance_volume(const std::vector<Segment2>& segments, const GridSpec& grid,
                                       const cv::Mat& mask, int num_directions, double max_range_m);

/// The obvious version: min over every segment (either side) of the ray-segment distance, clipped.
double brute_force_ray_distance(const std::vector<Segment2>& segments, const Vec2& origin_m, double angle_rad,
                                double max_range_m);

/// Ranges along n equiangular rays (ray i at observer-frame angle 2 pi i / n) from the observer
/// (origin of the observer frame) to the nearest observed segment (either side), clipped at
/// max_range_m: an observation's rays cast against its own segments.
std::vector<double> cast_rays_on_segments(const std::vector<Segment2>& segments_m, int n, double max_range_m);

}  // namespace floorcast
