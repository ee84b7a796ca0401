#include "floorcast/match/semantic_volume.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "floorcast/core/math.hpp"
#include "floorcast/match/distance_volume.hpp"

namespace floorcast {

void SemanticVolume::render(std::size_t i, int a, int* class_of_bin) const {
  const int D = bins.count;
  const int empty = bev_empty_class(classes);
  for (int d = 0; d < D; ++d) class_of_bin[d] = empty;
  const std::size_t N = num_cells();
  const std::size_t k = static_cast<std::size_t>(a) * N + i;
  auto mark = [&](std::uint8_t byte) {
    if (!(byte & 0x80)) return;
    class_of_bin[byte & 0x3f] = (byte & 0x40) ? kBevWindow : kBevDoor;
  };
  if (!crossings.empty()) {
    mark(static_cast<std::uint8_t>(crossings[k] & 0xff));
    mark(static_cast<std::uint8_t>(crossings[k] >> 8));
    const std::uint64_t key = static_cast<std::uint64_t>(i) * static_cast<std::uint64_t>(num_directions) +
                              static_cast<std::uint64_t>(a);
    auto it = std::lower_bound(overflow.begin(), overflow.end(), std::make_pair(key, std::uint8_t{0}));
    for (; it != overflow.end() && it->first == key; ++it) mark(it->second);
  }
  if (stop[k] < D) class_of_bin[stop[k]] = classes == BevClasses::kSemantic ? kBevWall : kBevOccupied;
}

SemanticVolume compute_semantic_volume(const SemanticPlanLines& lines, BevClasses classes, const GridSpec& grid,
                                       const cv::Mat& mask, int A, const BevDepthBins& bins) {
  if (A <= 0) throw std::invalid_argument("compute_semantic_volume: num_directions must be positive");
  if (bins.count < 1 || bins.count > kMaxSemanticBins || !(bins.min_m > 0.0) || !(bins.max_m > bins.min_m)) {
    throw std::invalid_argument("compute_semantic_volume: bins must have 1..63 bins and 0 < min < max");
  }
  if (mask.type() != CV_8U || mask.rows != grid.height_px || mask.cols != grid.width_px) {
    throw std::invalid_argument("compute_semantic_volume: mask must be CV_8U on the grid");
  }
  SemanticVolume v;
  v.grid = grid;
  v.num_directions = A;
  v.classes = classes;
  v.bins = bins;
  const std::size_t HW = static_cast<std::size_t>(grid.height_px) * grid.width_px;
  v.cell_index.assign(HW, -1);
  for (int r = 0; r < grid.height_px; ++r) {
    const std::uint8_t* m = mask.ptr<std::uint8_t>(r);
    for (int c = 0; c < grid.width_px; ++c) {
      if (!m[c]) continue;
      const std::size_t lin = static_cast<std::size_t>(r) * grid.width_px + c;
      v.cell_index[lin] = static_cast<std::int32_t>(v.cells.size());
      v.cells.push_back(static_cast<std::int32_t>(lin));
    }
  }
  const std::size_t N = v.cells.size();
  const bool semantic = classes == BevClasses::kSemantic;
  v.stop.assign(static_cast<std::size_t>(A) * N, static_cast<std::uint8_t>(bins.count));
  if (semantic) v.crossings.assign(static_cast<std::size_t>(A) * N, 0);
  const std::size_t GW = static_cast<std::size_t>(grid.width_px);
  const float range = static_cast<float>(bins.max_m);

  struct Crossing {
    std::int32_t cell;  ///< stored cell index
    float t;
    std::uint8_t window;
    bool operator<(const Crossing& o) const { return cell != o.cell ? cell < o.cell : t < o.t; }
  };
  struct Buffers {
    std::vector<float> z;
    std::vector<Crossing> crossings;
  };
  tbb::enumerable_thread_specific<Buffers> buffers;
  // Crossings beyond the second, per direction: (cell, byte), cell ascending.
  std::vector<std::vector<std::pair<std::int32_t, std::uint8_t>>> overflow(static_cast<std::size_t>(A));
  tbb::parallel_for(0, A, [&](int a) {
    Buffers& b = buffers.local();
    b.z.assign(HW, range);
    const double ang = 2.0 * kPi * a / A;
    const Vec2 u(std::cos(ang), std::sin(ang));
    for (const Segment2& s : lines.stops) {
      if (!front_facing(u, s)) continue;
      sweep_segment(grid, s.a_m, s.b_m, u, bins.max_m, 0.5, [&](int r, int c, double t) {
        float& zc = b.z[static_cast<std::size_t>(r) * GW + static_cast<std::size_t>(c)];
        const float tf = static_cast<float>(t);
        if (tf < zc) zc = tf;
      });
    }
    std::uint8_t* stop = v.stop.data() + static_cast<std::size_t>(a) * N;
    for (std::size_t i = 0; i < N; ++i) {
      const int bin = bins.bin_of(b.z[static_cast<std::size_t>(v.cells[i])]);
      stop[i] = static_cast<std::uint8_t>(bin < 0 ? bins.count : bin);
    }
    if (!semantic) return;
    b.crossings.clear();
    for (std::size_t j = 0; j < lines.permeable.size(); ++j) {
      const Segment2& s = lines.permeable[j];
      if (!front_facing(u, s)) continue;
      const std::uint8_t window = lines.permeable_labels[j] == SemanticClass::kWindow ? 1 : 0;
      sweep_segment(grid, s.a_m, s.b_m, u, bins.max_m, 0.5, [&](int r, int c, double t) {
        const std::size_t lin = static_cast<std::size_t>(r) * GW + static_cast<std::size_t>(c);
        const std::int32_t i = v.cell_index[lin];
        const float tf = static_cast<float>(t);
        if (i >= 0 && tf < b.z[lin]) b.crossings.push_back({i, tf, window});
      });
    }
    std::sort(b.crossings.begin(), b.crossings.end());
    std::uint16_t* out = v.crossings.data() + static_cast<std::size_t>(a) * N;
    std::vector<std::pair<std::int32_t, std::uint8_t>>& more = overflow[static_cast<std::size_t>(a)];
    for (std::size_t p = 0; p < b.crossings.size();) {
      const std::int32_t i = b.crossings[p].cell;
      // This cell's crossings, nearest first, as bytes: the stop's bin and all but the farthest
      // of one bin dropped (render_bev_column overwrites a marked bin).
      std::uint8_t kept[64];
      int n = 0;
      int last_bin = -1;
      for (; p < b.crossings.size() && b.crossings[p].cell == i; ++p) {
        const int bin = bins.bin_of(b.crossings[p].t);
        if (bin < 0 || bin == stop[i]) continue;
        const std::uint8_t byte = semantic_crossing_byte(b.crossings[p].window != 0, bin);
        if (bin == last_bin) {
          kept[n - 1] = byte;
        } else if (n < 64) {
          kept[n++] = byte;
          last_bin = bin;
        }
      }
      if (n > 0) out[i] = kept[0];
      if (n > 1) out[i] = static_cast<std::uint16_t>(out[i] | (kept[1] << 8));
      for (int q = 2; q < n; ++q) more.emplace_back(i, kept[q]);
    }
  });
  for (int a = 0; a < A; ++a) {
    for (const auto& [i, byte] : overflow[static_cast<std::size_t>(a)]) {
      v.overflow.emplace_back(static_cast<std::uint64_t>(i) * static_cast<std::uint64_t>(A) + static_cast<std::uint64_t>(a), byte);
    }
  }
  std::stable_sort(v.overflow.begin(), v.overflow.end(),
                   [](const auto& x, const auto& y) { return x.first < y.first; });
  return v;
}

}  // namespace floorcast
