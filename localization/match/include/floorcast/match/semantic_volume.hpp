// The BEV matcher's precomputation: the thesis' semantic ray casting of the plan (seed paper 004,
// sec. 3.3.4 and 3.4) from every stored grid cell along A equiangular world directions, binned
// into the BEV's D log-spaced depth bins:
//
//   stop[a][i]       bin of the first surface that stops the ray (semantic: a wall; occupancy:
//                    a wall or a window), or D when there is none within the last bin edge;
//   crossings[a][i]  the doors and windows the ray passes before it (semantic classes only).
//
// Computed exactly in 2D per direction with the distance volume's sweep (sweep_segment): the
// stops' minimum distance per cell (z-buffer), then every permeable face's crossings nearer than
// the cell's stop. Directions run in parallel (TBB), each with its own buffers, so results do not
// depend on the thread count. The one-hot BEV of a cell along a direction (render) equals
// render_bev_column of the brute-force cast (floorplans/semantic_rays.hpp): crossings in the
// stop's bin are dropped and of two in one bin the farther is kept, so every marked bin is
// distinct and a score is the sum of one table entry per marked bin.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <utility>
#include <vector>

#include "floorcast/core/bev.hpp"
#include "floorcast/core/grid.hpp"
#include "floorcast/floorplans/semantic_rays.hpp"

namespace floorcast {

struct SemanticVolume {
  GridSpec grid;
  int num_directions = 0;  ///< direction a points at world angle 2 pi a / num_directions (CCW from +x)
  BevClasses classes = BevClasses::kSemantic;
  BevDepthBins bins;
  /// Stored cells in row-major order (linear index row * width + col), and per grid cell its
  /// index into `cells` or -1.
  std::vector<std::int32_t> cells;
  std::vector<std::int32_t> cell_index;
  /// stop[a * N + i]: bin of the first stop of stored cell i along direction a, or bins.count.
  std::vector<std::uint8_t> stop;
  /// crossings[a * N + i] (semantic classes only): up to two crossings, the nearer in the low
  /// byte; a byte is 0 (none) or 0x80 | (0x40 for a window, 0 for a door) | bin.
  std::vector<std::uint16_t> crossings;
  /// Crossings beyond the second (rare), sorted by (cell, direction): key i * A + a, byte.
  std::vector<std::pair<std::uint64_t, std::uint8_t>> overflow;

  std::size_t num_cells() const { return cells.size(); }
  std::size_t bytes() const {
    return cells.size() * sizeof(std::int32_t) + cell_index.size() * sizeof(std::int32_t) + stop.size() +
           crossings.size() * sizeof(std::uint16_t) + overflow.size() * sizeof(overflow[0]);
  }
  /// The one-hot BEV class of every bin of stored cell i along direction a (D entries).
  void render(std::size_t i, int a, int* class_of_bin) const;
};

/// Crossing byte of a class and bin (0x80 | window bit | bin).
inline std::uint8_t semantic_crossing_byte(bool window, int bin) {
  return static_cast<std::uint8_t>(0x80 | (window ? 0x40 : 0) | bin);
}

/// Largest depth-bin count the semantic volume stores (6 bits per crossing bin).
constexpr int kMaxSemanticBins = 63;

/// The volume over every non-zero cell of `mask` (CV_8U on `grid`): the lines of
/// semantic_plan_lines(plan, classes, cut height), num_directions directions, bins (count <=
/// kMaxSemanticBins). Throws std::invalid_argument for bad arguments.
SemanticVolume compute_semantic_volume(const SemanticPlanLines& lines, BevClasses classes, const GridSpec& grid,
                                       const cv::Mat& mask, int num_directions, const BevDepthBins& bins);

}  // namespace floorcast
