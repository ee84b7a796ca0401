#include "floorcast/match/distance_volume.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include "floorcast/floorplans/geometry.hpp"
#include "floorcast/core/math.hpp"

namespace floorcast {

int DistanceVolume::max_units() const {
  return static_cast<int>(std::lround(max_range_m * 1000.0 / step_mm));
}

namespace {

/// The volume's header and stored cells (every non-zero cell of mask), distances not yet set.
DistanceVolume empty_volume(const GridSpec& grid, const cv::Mat& mask, int D, double max_range_m, int bits,
                            double sample_offset) {
  if (bits != 8 && bits != 16) throw std::invalid_argument("compute_distance_volume: bits must be 8 or 16");
  if (D <= 0) throw std::invalid_argument("compute_distance_volume: num_directions must be positive");
  if (!(max_range_m > 0.0) || max_range_m > 65.535) {
    throw std::invalid_argument("compute_distance_volume: max_range_m must be in (0, 65.535]");
  }
  if (mask.type() != CV_8U || mask.rows != grid.height_px || mask.cols != grid.width_px) {
    throw std::invalid_argument("compute_distance_volume: mask must be CV_8U on the grid");
  }
  if (!(sample_offset >= 0.0 && sample_offset < 1.0)) {
    throw std::invalid_argument("compute_distance_volume: sample_offset must be in [0, 1)");
  }
  DistanceVolume v;
  v.grid = grid;
  v.num_directions = D;
  v.bits = bits;
  v.step_mm = bits == 8 ? static_cast<int>(std::ceil(std::lround(max_range_m * 1000.0) / 255.0)) : 1;
  v.max_range_m = max_range_m;
  v.sample_offset = sample_offset;
  const std::size_t HW = static_cast<std::size_t>(grid.height_px) * grid.width_px;
  v.cell_index.assign(HW, -1);
  for (int r = 0; r < grid.height_px; ++r) {
    const std::uint8_t* m = mask.ptr<std::uint8_t>(r);
    for (int c = 0; c < grid.width_px; ++c) {
      if (m[c]) {
        const std::size_t lin = static_cast<std::size_t>(r) * grid.width_px + c;
        v.cell_index[lin] = static_cast<std::int32_t>(v.cells.size());
        v.cells.push_back(static_cast<std::int32_t>(lin));
      }
    }
  }
  const std::size_t N = v.cells.size();
  if (bits == 8) {
    v.q8.assign(N * static_cast<std::size_t>(D), 0);
  } else {
    v.mm.assign(N * static_cast<std::size_t>(D), 0);
  }
  return v;
}

/// Stores direction d: distance_m(i) (metres, <= max_range) of every stored cell i, rounded to the
/// volume's unit.
template <class DistanceOf>
void store_direction(DistanceVolume& v, int d, DistanceOf&& distance_m) {
  const std::size_t N = v.cells.size();
  if (v.bits == 8) {
    std::uint8_t* out = v.q8.data() + static_cast<std::size_t>(d) * N;
    const double per_unit = 1000.0 / v.step_mm;
    for (std::size_t i = 0; i < N; ++i) out[i] = static_cast<std::uint8_t>(std::lround(distance_m(i) * per_unit));
  } else {
    std::uint16_t* out = v.mm.data() + static_cast<std::size_t>(d) * N;
    for (std::size_t i = 0; i < N; ++i) out[i] = static_cast<std::uint16_t>(std::lround(distance_m(i) * 1000.0));
  }
}

}  // namespace

DistanceVolume compute_distance_volume(const std::vector<Segment2>& segments, const GridSpec& grid, const cv::Mat& mask,
                                       int D, double max_range_m, int bits, double sample_offset) {
  DistanceVolume v = empty_volume(grid, mask, D, max_range_m, bits, sample_offset);
  const std::size_t HW = static_cast<std::size_t>(grid.height_px) * grid.width_px;
  tbb::enumerable_thread_specific<std::vector<float>> buffers;
  tbb::parallel_for(0, D, [&](int d) {
    std::vector<float>& z = buffers.local();
    z.assign(HW, static_cast<float>(max_range_m));
    const double ang = 2.0 * kPi * d / D;
    const Vec2 u(std::cos(ang), std::sin(ang));
    for (const Segment2& s : segments) {
      // Front face for a ray along u: the free (left) side faces the ray.
      if (!front_facing(u, s)) continue;
      sweep_segment(grid, s.a_m, s.b_m, u, max_range_m, sample_offset, [&](int r, int c, double t) {
        float& zc = z[static_cast<std::size_t>(r) * static_cast<std::size_t>(grid.width_px) + static_cast<std::size_t>(c)];
        const float tf = static_cast<float>(t);
        if (tf < zc) zc = tf;
      });
    }
    store_direction(v, d, [&](std::size_t i) { return static_cast<double>(z[static_cast<std::size_t>(v.cells[i])]); });
  });
  return v;
}

bool BitRaster::blocked(int row, int col) const {
  const std::size_t k = static_cast<std::size_t>(row) * static_cast<std::size_t>(width) + static_cast<std::size_t>(col);
  return (words[k >> 6] >> (k & 63)) & 1u;
}

void BitRaster::set(int row, int col) {
  const std::size_t k = static_cast<std::size_t>(row) * static_cast<std::size_t>(width) + static_cast<std::size_t>(col);
  words[k >> 6] |= std::uint64_t{1} << (k & 63);
}

BitRaster::BitRaster(int width_px, int height_px) : width(width_px), height(height_px) {
  if (width_px < 0 || height_px < 0) throw std::invalid_argument("BitRaster: negative size");
  words.assign((static_cast<std::size_t>(width_px) * static_cast<std::size_t>(height_px) + 63) / 64, 0);
}

RasterSkipMap make_raster_skip_map(const BitRaster& occupancy, int ratio) {
  if (ratio < 1 || occupancy.width % ratio != 0 || occupancy.height % ratio != 0) {
    throw std::invalid_argument("make_raster_skip_map: the occupancy must be whole blocks of ratio x ratio pixels");
  }
  RasterSkipMap m;
  m.ratio = ratio;
  cv::Mat free_blocks(occupancy.height / ratio, occupancy.width / ratio, CV_8U, cv::Scalar(255));
  // Visit the set bits only.
  for (std::size_t wi = 0; wi < occupancy.words.size(); ++wi) {
    std::uint64_t word = occupancy.words[wi];
    while (word) {
      const int bit = __builtin_ctzll(word);
      word &= word - 1;
      const std::size_t k = wi * 64 + static_cast<std::size_t>(bit);
      const int row = static_cast<int>(k / static_cast<std::size_t>(occupancy.width));
      const int col = static_cast<int>(k % static_cast<std::size_t>(occupancy.width));
      free_blocks.at<std::uint8_t>(row / ratio, col / ratio) = 0;
    }
  }
  cv::Mat dist;
  cv::distanceTransform(free_blocks, dist, cv::DIST_C, 3, CV_32F);
  dist.convertTo(m.blocks, CV_8U);  // saturates at 255
  return m;
}

double f3loc_ray_cast(const BitRaster& occ, double pos_row, double pos_col, double angle_rad, double dist_max_px,
                      double stop_px, const RasterSkipMap* skip) {
  // F3Loc utils.ray_cast, case by case (see the header). pos = (row, col) = (h, w).
  const double h = occ.height, w = occ.width;
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  const double stop2 = stop_px * stop_px;
  auto hit_at = [&](double r, double q) { return occ.blocked(static_cast<int>(r), static_cast<int>(q)); };
  auto far = [&](double r, double q) {
    const double dr = r - pos_row, dq = q - pos_col;
    return dr * dr + dq * dq > stop2;
  };
  // np.linalg.norm(current_pos - pos, 2) of a 2-vector: sqrt of the sum of squares.
  auto dist = [&](double r, double q) {
    const double dr = r - pos_row, dq = q - pos_col;
    return std::sqrt(dr * dr + dq * dq);
  };
  const bool cardinal = c == 1.0 || s == 1.0 || c == -1.0 || s == -1.0;
  // Unit direction in (row, col) pixels of the march.
  const double ur = cardinal ? (s == 1.0 ? 1.0 : s == -1.0 && c != 1.0 && c != -1.0 ? -1.0 : 0.0) : s;
  const double uq = cardinal ? (c == 1.0 ? 1.0 : c == -1.0 && s != 1.0 ? -1.0 : 0.0) : c;
  // Empty-space skip: from a point in block (br, bq) whose chessboard distance k to the nearest
  // block holding a blocked pixel is >= 2, every pixel of the square of blocks within k - 1 is
  // free; the march may jump to where the ray leaves that square shrunk by one pixel (every
  // crossing on the way would have tested a free pixel). Returns the jump length in pixels (0:
  // none).
  auto jump = [&](double r, double q) -> double {
    if (!skip || r < 0.0 || q < 0.0 || r >= h || q >= w) return 0.0;
    const int br = static_cast<int>(r) / skip->ratio, bq = static_cast<int>(q) / skip->ratio;
    const int k = skip->blocks.at<std::uint8_t>(br, bq);
    if (k < 2) return 0.0;
    const double lo_r = (br - (k - 1)) * skip->ratio + 1.0, hi_r = (br + k) * skip->ratio - 1.0;
    const double lo_q = (bq - (k - 1)) * skip->ratio + 1.0, hi_q = (bq + k) * skip->ratio - 1.0;
    double t = 1e300;
    if (ur > 0.0) t = std::min(t, (hi_r - r) / ur);
    if (ur < 0.0) t = std::min(t, (lo_r - r) / ur);
    if (uq > 0.0) t = std::min(t, (hi_q - q) / uq);
    if (uq < 0.0) t = std::min(t, (lo_q - q) / uq);
    return t > 1.0 ? t : 0.0;
  };
  if (cardinal) {
    // One pixel at a time along the row or column; the start pixel is never tested.
    double r = pos_row, q = pos_col;
    for (;;) {
      // Jumps by whole pixels keep the positions integral, as F3Loc's stepping.
      const double j = std::floor(jump(r, q));
      if (j >= 1.0) {
        r += j * ur;
        q += j * uq;
        if (far(r, q)) return dist_max_px;
      }
      r += ur;
      q += uq;
      if (r < 0.0 || q < 0.0 || r >= h || q >= w) return dist_max_px;
      if (hit_at(r, q)) return dist(r, q);
      if (far(r, q)) return dist_max_px;
    }
  }
  const double t = std::tan(angle_rad);
  const bool up = s > 0.0, right = c > 0.0;
  // The next pixel boundaries (row, column) the ray meets, and how they advance.
  auto next_row_boundary = [&](double r) { return up ? std::floor(r + 1.0) : std::ceil(r - 1.0); };
  auto next_col_boundary = [&](double q) { return right ? std::floor(q + 1.0) : std::ceil(q - 1.0); };
  double corner_r = next_row_boundary(pos_row), corner_q = next_col_boundary(pos_col);
  const double step_r = up ? 1.0 : -1.0, step_q = right ? 1.0 : -1.0;
  // F3Loc compares tan(angle) with the slope to the next corner; whether "greater" means the row
  // boundary comes first depends on the quadrant (up-right and down-left: greater; the others: less).
  const bool greater_means_row = up == right;
  double r = pos_row, q = pos_col;
  for (;;) {
    const double j = jump(r, q);
    if (j > 0.0) {
      r += j * ur;
      q += j * uq;
      if (r < 0.0 || q < 0.0 || r >= h || q >= w || far(r, q)) return dist_max_px;
      corner_r = next_row_boundary(r);
      corner_q = next_col_boundary(q);
    }
    const double dw = corner_q - q, dh = corner_r - r;
    const double corner_slope = dh / dw;
    const bool row_first = greater_means_row ? t > corner_slope : t < corner_slope;
    const bool col_first = greater_means_row ? t < corner_slope : t > corner_slope;
    if (row_first) {
      q = q + dh / t;
      r = corner_r;
      corner_r += step_r;
    } else if (col_first) {
      r = r + dw * t;
      q = corner_q;
      corner_q += step_q;
    } else {
      r = corner_r;
      q = corner_q;
      corner_r += step_r;
      corner_q += step_q;
    }
    if ((up ? r >= h : r < 0.0) || (right ? q >= w : q < 0.0)) return dist_max_px;
    if (hit_at(r, q)) return dist(r, q);
    if (far(r, q)) return dist_max_px;
  }
}

DistanceVolume compute_distance_volume_raster(const BitRaster& occupancy, int ratio, const GridSpec& grid,
                                              const cv::Mat& mask, int D, double max_range_m, int bits,
                                              double sample_offset) {
  if (ratio < 1) throw std::invalid_argument("compute_distance_volume_raster: ratio must be >= 1");
  if (occupancy.width != grid.width_px * ratio || occupancy.height != grid.height_px * ratio) {
    throw std::invalid_argument("compute_distance_volume_raster: the occupancy must cover the grid at ratio x its resolution");
  }
  DistanceVolume v = empty_volume(grid, mask, D, max_range_m, bits, sample_offset);
  const double fine_res = grid.resolution_m_per_px / ratio;
  const double range_px = max_range_m / fine_res;
  const std::size_t N = v.cells.size();
  const RasterSkipMap skip = make_raster_skip_map(occupancy, ratio);
  tbb::parallel_for(0, D, [&](int d) {
    // F3Loc generate_desdf.raycast_desdf: theta = o / orn_slice * pi * 2, in this order.
    const double theta = static_cast<double>(d) / D * kPi * 2.0;
    std::vector<float> dist(N);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, N, 256), [&](const tbb::blocked_range<std::size_t>& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        const int lin = v.cells[i];
        const int row = lin / grid.width_px, col = lin % grid.width_px;
        const double px = f3loc_ray_cast(occupancy, (row + sample_offset) * ratio, (col + sample_offset) * ratio, theta,
                                         range_px, range_px + 2.0, &skip);
        dist[i] = static_cast<float>(std::min(px * fine_res, max_range_m));
      }
    });
    store_direction(v, d, [&](std::size_t i) { return static_cast<double>(dist[i]); });
  });
  return v;
}

double brute_force_ray_distance(const std::vector<Segment2>& segments, const Vec2& origin, double angle,
                                double max_range_m) {
  const Vec2 dir(std::cos(angle), std::sin(angle));
  double best = max_range_m;
  for (const Segment2& s : segments) {
    const double t = ray_segment_distance(origin, dir, s);
    if (t >= 0.0 && t < best) best = t;
  }
  return best;
}

std::vector<double> cast_rays_on_segments(const std::vector<Segment2>& segments, int n, double max_range_m) {
  std::vector<double> out(static_cast<std::size_t>(std::max(n, 0)), max_range_m);
  for (int i = 0; i < n; ++i) {
    out[static_cast<std::size_t>(i)] = brute_force_ray_distance(segments, Vec2::Zero(), 2.0 * kPi * i / n, max_range_m);
  }
  return out;
}

}  // namespace floorcast
