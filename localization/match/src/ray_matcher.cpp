#include "floorcast/match/ray_matcher.hpp"
#include "floorcast/core/limits.hpp"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>
#include <memory>

#include "floorcast/match/plan_raster.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/core/timing.hpp"

namespace floorcast {
namespace {

using Clock = std::chrono::steady_clock;

double seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

const std::vector<std::pair<const char*, RaySource>> kRaySourceNames = {
    {"auto", RaySource::kAuto}, {"ranges", RaySource::kRanges}, {"segments", RaySource::kSegments}};
const std::vector<std::pair<const char*, RaySearch>> kRaySearchNames = {{"bounded", RaySearch::kBounded},
                                                                       {"exhaustive", RaySearch::kExhaustive}};
const std::vector<std::pair<const char*, RayCastPoint>> kCastPointNames = {{"centre", RayCastPoint::kCentre},
                                                                         {"corner", RayCastPoint::kCorner}};
const std::vector<std::pair<const char*, RayDistances>> kDistancesNames = {{"exact", RayDistances::kExact},
                                                                          {"raster", RayDistances::kRaster}};
const std::vector<std::pair<const char*, RayConvention>> kConventionNames = {
    {"floorcast", RayConvention::kFloorcast},   {"f3loc", RayConvention::kF3Loc},
    {"one_bin_off", RayConvention::kOneBinOff}, {"mirrored", RayConvention::kMirrored},
    {"heading_ray0", RayConvention::kHeadingRay0}};
const std::vector<std::pair<const char*, RayCells>> kCellsNames = {{"valid", RayCells::kValid}, {"all", RayCells::kAll}};

/// Parameters that only change how an observation is compared, not the volume.
const char* const kObservationSideKeys[] = {"lambda_m", "ray_source", "search", "ray_convention", "fov_deg",
                                            "clip_observation"};

/// resolution_m / raster_resolution_m when it is a whole number (within 1e-6), else 0.
int raster_ratio(const RayMatcherParams& p) {
  const double q = p.resolution_m / p.raster_resolution_m;
  const long n = std::lround(q);
  return n >= 1 && std::abs(q - static_cast<double>(n)) < 1e-6 ? static_cast<int>(n) : 0;
}

/// F3Loc's occupancy image of the plan over `grid` at ratio x its resolution (blocked = a fine
/// pixel whose centre lies in a blocking footprint, or that a wall axis crosses:
/// rasterize_occupancy), painted in tiles of rows into one bit per pixel.
BitRaster fine_occupancy(const FloorPlan& plan, const GridSpec& grid, int ratio, const BlockingOptions& blocking) {
  BitRaster fine(grid.width_px * ratio, grid.height_px * ratio);
  const double fine_res = grid.resolution_m_per_px / ratio;
  const int tile_rows = std::max(1, (1 << 24) / std::max(1, fine.width));
  for (int row0 = 0; row0 < fine.height; row0 += tile_rows) {
    GridSpec tile;
    tile.origin_x_m = grid.origin_x_m;
    tile.origin_y_m = grid.origin_y_m + row0 * fine_res;
    tile.resolution_m_per_px = fine_res;
    tile.width_px = fine.width;
    tile.height_px = std::min(tile_rows, fine.height - row0);
    const cv::Mat occ = rasterize_occupancy(plan, tile, blocking);
    for (int r = 0; r < tile.height_px; ++r) {
      const std::uint8_t* p = occ.ptr<std::uint8_t>(r);
      for (int c = 0; c < tile.width_px; ++c)
        if (p[c]) fine.set(row0 + r, c);
    }
  }
  return fine;
}

/// The parameters the distance volume depends on (to_json without the observation-side keys).
nlohmann::ordered_json volume_parameters(const RayMatcherParams& p) {
  nlohmann::ordered_json j = p.to_json();
  for (const char* k : kObservationSideKeys) j.erase(k);
  return j;
}

/// Stored cells per run of the bounded search (one grid row, 3.2 m at 0.1 m).
constexpr int kRunCells = 32;

/// Cells per tile of the scoring loop: the tile's distances (D x T uint16) and sums (D x T
/// int32) stay in L1/L2.
int tile_cells(int D) { return D <= 64 ? 512 : 128; }

/// acc[o * stride + t] = sum_j |min(V[(o + off_j) mod D][first + t], clip) - rays[j]| over the
/// R compared rays (offsets off_j, RayMatcher::ComparedRays) for the T <= stride cells of one
/// tile and the orientations o0 <= o < o1 (other rows of acc untouched), in the volume's units (mm for 16 bits). The hot loop of the matcher: 16-bit lanes
/// (|a - b| = max - min), partial sums over `block` rays (block * range < 2^16 units: 6 rays at
/// 10 m in mm) widened into 32-bit sums; vectorised over cells, with an AVX2 clone where the CPU
/// has it.
template <class V>
inline __attribute__((always_inline)) void l1_tile_body(const V* volume, std::size_t N, std::size_t first, int T,
                                                        int stride, int D, int o0, int o1, const int* offsets,
                                                        int R, const std::uint16_t* rays_u, std::uint16_t clip_u,
                                                        bool clip, int block, std::int32_t* acc, std::uint16_t* part) {
  const int kBlock = block;
  for (int o = o0; o < o1; ++o) {
    std::int32_t* a = acc + static_cast<std::size_t>(o) * stride;
    for (int t = 0; t < T; ++t) a[t] = 0;
    for (int i0 = 0; i0 < R; i0 += kBlock) {
      for (int t = 0; t < T; ++t) part[t] = 0;
      for (int i = i0; i < std::min(R, i0 + kBlock); ++i) {
        const V* p = volume + static_cast<std::size_t>((o + offsets[i]) % D) * N + first;
        const std::uint16_t r = rays_u[i];
        if (clip) {
          for (int t = 0; t < T; ++t) {
            const std::uint16_t pv = p[t];
            const std::uint16_t v = pv < clip_u ? pv : clip_u;
            const std::uint16_t hi = v > r ? v : r;
            const std::uint16_t lo = v > r ? r : v;
            part[t] = static_cast<std::uint16_t>(part[t] + static_cast<std::uint16_t>(hi - lo));
          }
        } else {
          for (int t = 0; t < T; ++t) {
            const std::uint16_t v = p[t];
            const std::uint16_t hi = v > r ? v : r;
            const std::uint16_t lo = v > r ? r : v;
            part[t] = static_cast<std::uint16_t>(part[t] + static_cast<std::uint16_t>(hi - lo));
          }
        }
      }
      for (int t = 0; t < T; ++t) a[t] += part[t];
    }
  }
}

#if defined(__GNUC__) && defined(__x86_64__) && !defined(__clang__)
__attribute__((target_clones("avx2", "default")))
#endif
void l1_tile16(const std::uint16_t* volume, std::size_t N, std::size_t first, int T, int stride, int D, int o0, int o1,
               const int* offsets, int R, const std::uint16_t* rays_u, std::uint16_t clip_u, bool clip, int block,
               std::int32_t* acc, std::uint16_t* part) {
  l1_tile_body(volume, N, first, T, stride, D, o0, o1, offsets, R, rays_u, clip_u, clip, block, acc, part);
}

#if defined(__GNUC__) && defined(__x86_64__) && !defined(__clang__)
__attribute__((target_clones("avx2", "default")))
#endif
void l1_tile8(const std::uint8_t* volume, std::size_t N, std::size_t first, int T, int stride, int D, int o0, int o1,
              const int* offsets, int R, const std::uint16_t* rays_u, std::uint16_t clip_u, bool clip, int block,
              std::int32_t* acc, std::uint16_t* part) {
  l1_tile_body(volume, N, first, T, stride, D, o0, o1, offsets, R, rays_u, clip_u, clip, block, acc, part);
}

/// The observation's compared rays in the volume's units (RayMatcher::RayUnits, public here).
struct TileRays {
  const int* offsets;
  int count;
  const std::uint16_t* rays;
  std::uint16_t clip;
  bool clipped;
  int block;
};

/// l1_tile of the volume's storage (8 or 16 bits), orientations o0 <= o < o1 (default: all).
void l1_tile(const DistanceVolume& v, std::size_t first, int T, int stride, const TileRays& r, std::int32_t* acc,
             std::uint16_t* part, int o0 = 0, int o1 = -1) {
  if (o1 < 0) o1 = v.num_directions;
  if (v.bits == 8) {
    l1_tile8(v.q8.data(), v.num_cells(), first, T, stride, v.num_directions, o0, o1, r.offsets, r.count, r.rays, r.clip,
             r.clipped, r.block, acc, part);
  } else {
    l1_tile16(v.mm.data(), v.num_cells(), first, T, stride, v.num_directions, o0, o1, r.offsets, r.count, r.rays,
              r.clip, r.clipped, r.block, acc, part);
  }
}

/// out[t] = exp(-acc[t] * k) for k > 0, as 2^y with y = -acc * k * log2(e): y = n + f with n an
/// integer and f in [-1/2, 1/2], 2^f by its degree-6 Taylor polynomial (relative error < 2e-7,
/// float precision) and 2^n put into the exponent bits, so the loop vectorises. 0 below 2^-126.
#if defined(__GNUC__) && defined(__x86_64__) && !defined(__clang__)
__attribute__((target_clones("avx2", "default")))
#endif
void exp_neg_scaled(const std::int32_t* acc, int T, float k, float* out) {
  constexpr float kLog2e = 1.4426950408889634f;
  for (int t = 0; t < T; ++t) {
    float y = -static_cast<float>(acc[t]) * k * kLog2e;  // <= 0
    const bool underflow = y <= -126.0f;
    y = underflow ? -126.0f : y;
    // Round to nearest by truncating the positive -y + 1/2 (no floor call: the loop vectorises).
    const std::int32_t ni = -static_cast<std::int32_t>(0.5f - y);
    const float f = y - static_cast<float>(ni);
    // sum_j (f ln 2)^j / j!
    float p = 1.5403530e-4f;
    p = p * f + 1.3333558e-3f;
    p = p * f + 9.6181291e-3f;
    p = p * f + 5.5504109e-2f;
    p = p * f + 2.4022651e-1f;
    p = p * f + 6.9314718e-1f;
    p = p * f + 1.0f;
    const std::int32_t bits = (ni + 127) << 23;
    float scale;
    std::memcpy(&scale, &bits, sizeof(float));
    out[t] = underflow ? 0.0f : p * scale;
  }
}



/// Orientation groups of the bounded search at D directions: group g holds orientations
/// g w .. min(D, (g + 1) w) - 1 (w = group_width(D); 0: no groups). Bounding a group costs about
/// 2 / w of scoring its cell exactly at every orientation and scoring one group w / D of it, so w
/// ~ sqrt(D) balances the two; below 72 directions the groups do not pay.
int group_width(int D) { return D < 72 ? 0 : std::max(4, static_cast<int>(std::lround(std::sqrt(2.0 * D / 3.0)))); }

/// Batches of the bounded search grow by this fraction of the runs taken so far (refined, or
/// scored): small enough not to overshoot the final threshold by much, large enough to keep both
/// threads busy (measured on the real development levels: 1/8 scores ~30% fewer cells than 1/2).
constexpr std::size_t kBatchGrowth = 8;

/// Lower bounds of every orientation group's L1 over the n <= kRunCells cells of one run (the
/// volume's cells first..first+n-1): at any orientation o of group g, ray j meets direction
/// (o + off_j) mod D, which lies in the window of w directions starting at (g w + off_j) mod D, so
/// its |v - r_j| is at least the distance of r_j from [min, max] of that window's clipped
/// distances. out[g * kRunCells + t] = that sum for cell t (t < n). Windows by doubling (min of two
/// overlapping power-of-two windows); lo, hi, tmp: D * kRunCells scratch each.
template <class V>
inline __attribute__((always_inline)) void group_bounds_body(const V* volume, std::size_t N, std::size_t first, int n,
                                                             int D, int w, const TileRays& r, std::uint16_t* lo,
                                                             std::uint16_t* hi, std::uint16_t* tmp, std::int32_t* out) {
  constexpr int S = kRunCells;
  for (int d = 0; d < D; ++d) {
    const V* p = volume + static_cast<std::size_t>(d) * N + first;
    std::uint16_t* l = lo + static_cast<std::size_t>(d) * S;
    for (int t = 0; t < S; ++t) {
      const std::uint16_t v = t < n ? static_cast<std::uint16_t>(p[t]) : 0;
      l[t] = r.clipped && v > r.clip ? r.clip : v;
    }
  }
  std::copy(lo, lo + static_cast<std::size_t>(D) * S, hi);
  // Windows of len directions, len doubling while 2 len <= w.
  int len = 1;
  for (; 2 * len <= w; len *= 2) {
    for (std::uint16_t* m : {lo, hi}) {
      const bool is_lo = m == lo;
      for (int d = 0; d < D; ++d) {
        const std::uint16_t* a = m + static_cast<std::size_t>(d) * S;
        const std::uint16_t* b = m + static_cast<std::size_t>((d + len) % D) * S;
        std::uint16_t* c = tmp + static_cast<std::size_t>(d) * S;
        for (int t = 0; t < S; ++t) c[t] = is_lo ? std::min(a[t], b[t]) : std::max(a[t], b[t]);
      }
      std::copy(tmp, tmp + static_cast<std::size_t>(D) * S, m);
    }
  }
  if (len < w) {  // window w = [d, d + len) united with [d + w - len, d + w)
    for (std::uint16_t* m : {lo, hi}) {
      const bool is_lo = m == lo;
      for (int d = 0; d < D; ++d) {
        const std::uint16_t* a = m + static_cast<std::size_t>(d) * S;
        const std::uint16_t* b = m + static_cast<std::size_t>((d + w - len) % D) * S;
        std::uint16_t* c = tmp + static_cast<std::size_t>(d) * S;
        for (int t = 0; t < S; ++t) c[t] = is_lo ? std::min(a[t], b[t]) : std::max(a[t], b[t]);
      }
      std::copy(tmp, tmp + static_cast<std::size_t>(D) * S, m);
    }
  }
  const int G = (D + w - 1) / w;
  for (int g = 0; g < G; ++g) {
    std::int32_t* acc = out + static_cast<std::size_t>(g) * S;
    for (int t = 0; t < S; ++t) acc[t] = 0;
    for (int j = 0; j < r.count; ++j) {
      const std::size_t d = static_cast<std::size_t>((g * w + r.offsets[j]) % D);
      const std::uint16_t* a = lo + d * S;
      const std::uint16_t* b = hi + d * S;
      const std::int32_t ray = r.rays[j];
      for (int t = 0; t < S; ++t) {
        const std::int32_t below = a[t] - ray, above = ray - b[t];
        acc[t] += (below > 0 ? below : 0) + (above > 0 ? above : 0);
      }
    }
  }
}

#if defined(__GNUC__) && defined(__x86_64__) && !defined(__clang__)
__attribute__((target_clones("avx2", "default")))
#endif
void group_bounds(const DistanceVolume& v, std::size_t first, int n, int w, const TileRays& r, std::uint16_t* lo,
                  std::uint16_t* hi, std::uint16_t* tmp, std::int32_t* out) {
  if (v.bits == 8) {
    group_bounds_body(v.q8.data(), v.num_cells(), first, n, v.num_directions, w, r, lo, hi, tmp, out);
  } else {
    group_bounds_body(v.mm.data(), v.num_cells(), first, n, v.num_directions, w, r, lo, hi, tmp, out);
  }
}

/// The scoring loop of both outputs: every stored cell, one task per grid row (its cells are a
/// contiguous index range), tiles of tile_cells(D) cells. on_row(row) runs first in each row's
/// task; consume(first, n, o, scores) then receives exp(-L1 / lambda) of orientation o for the
/// stored cells first..first+n-1. Adds the thread CPU seconds of the L1 sums and of exp + consume,
/// summed over workers, to l1_s and exp_s.
template <class OnRow, class Consume>
void score_all_cells(const DistanceVolume& volume, const std::vector<std::int64_t>& row_start, const TileRays& rays,
                     float k, OnRow&& on_row, Consume&& consume, double& l1_s, double& exp_s) {
  const int D = volume.num_directions;
  const int T = tile_cells(D);
  struct Scratch {
    std::vector<std::int32_t> acc;
    std::vector<std::uint16_t> part;
    std::vector<float> score;
    double l1_s = 0.0, exp_s = 0.0;
  };
  tbb::enumerable_thread_specific<Scratch> scratch;
  tbb::parallel_for(0, volume.grid.height_px, [&](int row) {
    Scratch& s = scratch.local();
    s.acc.resize(static_cast<std::size_t>(D) * T);
    s.part.resize(static_cast<std::size_t>(T));
    s.score.resize(static_cast<std::size_t>(T));
    on_row(row);
    const std::size_t begin = static_cast<std::size_t>(row_start[static_cast<std::size_t>(row)]);
    const std::size_t end = static_cast<std::size_t>(row_start[static_cast<std::size_t>(row) + 1]);
    for (std::size_t first = begin; first < end; first += static_cast<std::size_t>(T)) {
      const int n = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(T), end - first));
      const double a = thread_cpu_s();
      l1_tile(volume, first, n, T, rays, s.acc.data(), s.part.data());
      const double b = thread_cpu_s();
      for (int o = 0; o < D; ++o) {
        exp_neg_scaled(s.acc.data() + static_cast<std::size_t>(o) * T, n, k, s.score.data());
        consume(first, n, o, s.score.data());
      }
      s.l1_s += b - a;
      s.exp_s += thread_cpu_s() - b;
    }
  });
  for (const Scratch& s : scratch) {
    l1_s += s.l1_s;
    exp_s += s.exp_s;
  }
}

}  // namespace

const FieldList<RayMatcherParams>& RayMatcherParams::fields() {
  using P = RayMatcherParams;
  static const FieldList<P> f =
      FieldList<P>("matcher ray")
          .number("resolution_m", &P::resolution_m, 0.01, 1.0, "grid resolution of the distance volume, m (F3Loc: 0.1)")
          .number("grid_margin_m", &P::grid_margin_m, 0.0, 100.0, "free margin of the grid around the plan, m")
          .integer("num_directions", &P::num_directions, 4, 3600,
                   "directions of the volume = rays of the observation (F3Loc: 36; PALMS+ sec. 4.4 also 180)")
          .number("max_range_m", &P::max_range_m, 0.1, 65.0, "clipping range, m (default: the shared range; F3Loc: 10)")
          .number("lambda_m", &P::lambda_m, 1e-6, 1e9, "likelihood temperature, m of summed range error (F3Loc: lambd = 40)")
          .choice("ray_source", &P::ray_source, kRaySourceNames,
                  "observation rays from its ranges, cast against its segments, or auto (ranges when there are "
                  "num_directions of them)")
          .choice("search", &P::search, kRaySearchNames, "modes by the exact bounded search or exhaustively")
          .integer("volume_bits", &P::volume_bits, 8, 16, "bits per stored distance: 16 (mm) or 8 (40 mm steps)")
          .flatten(&P::blocking, blocking_fields())
          .choice("cast_point", &P::cast_point, kCastPointNames, "where each cell's distances are cast from: centre, or corner (F3Loc)")
          .choice("distances", &P::distances, kDistancesNames,
                  "exact distances to the wall surfaces, or raster (F3Loc: a march through a fine occupancy image)")
          .number("raster_resolution_m", &P::raster_resolution_m, 0.001, 1.0,
                  "occupancy resolution of the raster distances, m (F3Loc: 0.01; must divide resolution_m)")
          .choice("ray_convention", &P::ray_convention, kConventionNames, "how ray i maps to a world direction (F3Loc variants)")
          .number("fov_deg", &P::fov_deg, 1.0, 360.0, "rays within +-fov/2 of the heading are compared (F3Loc: 100)")
          .flag("clip_observation", &P::clip_observation, "observation ranges clipped at max_range_m")
          .choice("cells", &P::cells, kCellsNames, "cells scored: valid (free space) or all (F3Loc)")
          .check([](const P& p, const ParamReader& r) {
            if (p.volume_bits != 8 && p.volume_bits != 16) r.fail("volume_bits", "must be 8 or 16");
            if (p.distances == RayDistances::kRaster && raster_ratio(p) < 1) {
              r.fail("raster_resolution_m",
                     "must divide resolution_m (" + std::to_string(p.resolution_m) + " m) a whole number of times");
            }
          });
  return f;
}

nlohmann::ordered_json RayMatcherParams::to_json() const { return fields().write(*this); }

void RayMatcherParams::apply_overrides(const nlohmann::json& overrides) { fields().read(*this, overrides); }

void RayMatcherParams::apply_shared(const SharedParams& shared) {
  max_range_m = shared.range_m;
  blocking = shared.blocking;
}

DistanceVolume RayMatcher::compute_volume(const FloorPlan& plan, const RayMatcherParams& params) {
  const GridSpec grid = grid_for_plan(plan, params.resolution_m, params.grid_margin_m);
  const bool raster = params.distances == RayDistances::kRaster;
  const int ratio = raster ? raster_ratio(params) : 1;
  if (ratio < 1) throw InputError("matcher ray: raster_resolution_m must divide resolution_m a whole number of times");
  // Refused before the volume is allocated: cell index, stored cells, their D distances (8 or 16
  // bits), their rank bounds (at most 19 bytes) and the per-match best score, orientation and
  // flag (7 bytes), the D float posterior slices of a match (every cell counted as valid), and for
  // raster distances the fine occupancy bits (ratio^2 per cell) and one tile of bytes.
  check_limit("max_rays", params.num_directions, "matcher ray: num_directions", "rays");
  check_raster_budget(grid,
                      8.0 + 19.0 + 7.0 + (params.volume_bits / 8.0 + 4.0) * params.num_directions +
                          (raster ? ratio * ratio / 8.0 : 0.0),
                      "matcher ray");
  const double off = params.cast_point == RayCastPoint::kCorner ? 0.0 : 0.5;
  const cv::Mat mask = params.cells == RayCells::kAll ? cv::Mat(grid.height_px, grid.width_px, CV_8U, cv::Scalar(255))
                                                      : matcher_valid_mask(plan, grid, params.blocking);
  if (raster) {
    return compute_distance_volume_raster(fine_occupancy(plan, grid, ratio, params.blocking), ratio, grid, mask,
                                          params.num_directions, params.max_range_m, params.volume_bits, off);
  }
  const std::vector<Segment2> outline = outline_segments(blocking_outline(plan, params.blocking));
  DistanceVolume v =
      compute_distance_volume(outline, grid, mask, params.num_directions, params.max_range_m, params.volume_bits, off);
  if (params.cells == RayCells::kAll) {
    // A cast point inside a wall or a door leaf sees the wall at 0 m in every direction (as a
    // march through the occupancy does), where the outline's back faces would let it see through.
    GridSpec at_cast = grid;
    at_cast.origin_x_m += (off - 0.5) * grid.resolution_m_per_px;
    at_cast.origin_y_m += (off - 0.5) * grid.resolution_m_per_px;
    const cv::Mat blocked = rasterize_occupancy(plan, at_cast, params.blocking);
    const std::size_t N = v.num_cells();
    for (std::size_t i = 0; i < N; ++i) {
      if (!blocked.data[static_cast<std::size_t>(v.cells[i])]) continue;
      for (int d = 0; d < v.num_directions; ++d) {
        const std::size_t k = static_cast<std::size_t>(d) * N + i;
        if (v.bits == 8) {
          v.q8[k] = 0;
        } else {
          v.mm[k] = 0;
        }
      }
    }
  }
  return v;
}

RayMatcher::RayMatcher(const FloorPlan& plan, const RayMatcherParams& params) : params_(params) {
  const auto t0 = Clock::now();
  pre_ = index_volume(compute_volume(plan, params_));
  precompute_s_ = seconds(t0, Clock::now());
}

RayMatcher::RayMatcher(const FloorPlan& plan, const RayMatcherParams& params, DistanceVolume volume) : params_(params) {
  const auto t0 = Clock::now();
  const GridSpec grid = grid_for_plan(plan, params_.resolution_m, params_.grid_margin_m);
  const double off = params_.cast_point == RayCastPoint::kCorner ? 0.0 : 0.5;
  if (!(volume.grid == grid) || volume.num_directions != params_.num_directions ||
      volume.max_range_m != params_.max_range_m || volume.bits != params_.volume_bits || volume.sample_offset != off) {
    throw InputError("ray matcher: the given distance volume was computed for another plan grid, direction count, "
                     "range, volume_bits or cast point than these parameters");
  }
  pre_ = index_volume(std::move(volume));
  precompute_s_ = seconds(t0, Clock::now());
}

RayMatcher::RayMatcher(const RayMatcher& other, const RayMatcherParams& params) : params_(params), pre_(other.pre_) {
  const nlohmann::ordered_json a = volume_parameters(params), b = volume_parameters(other.params_);
  if (a != b) {
    throw InputError("ray matcher: cannot share the distance volume of a matcher with other volume parameters (" +
                     b.dump() + " vs " + a.dump() + ")");
  }
}

std::shared_ptr<const RayMatcher::Precomputed> RayMatcher::index_volume(DistanceVolume volume) {
  auto pre = std::make_shared<Precomputed>();
  pre->volume = std::move(volume);
  const DistanceVolume& v = pre->volume;
  std::vector<std::int64_t>& row_start = pre->row_start;
  // First stored cell of every grid row (cells are sorted row-major).
  const GridSpec& vg = v.grid;
  row_start.assign(static_cast<std::size_t>(vg.height_px) + 1, 0);
  std::size_t i = 0;
  for (int r = 0; r <= vg.height_px; ++r) {
    const std::int64_t first_lin = static_cast<std::int64_t>(r) * vg.width_px;
    while (i < v.cells.size() && v.cells[i] < first_lin) ++i;
    row_start[static_cast<std::size_t>(r)] = static_cast<std::int64_t>(i);
  }
  // Runs: at most kRunCells consecutive stored cells of one row, each a contiguous index range.
  pre->runs.clear();
  for (int r = 0; r < vg.height_px; ++r) {
    for (std::int64_t a = row_start[static_cast<std::size_t>(r)]; a < row_start[static_cast<std::size_t>(r) + 1];
         a += kRunCells) {
      pre->runs.emplace_back(a, static_cast<int>(std::min<std::int64_t>(kRunCells, row_start[static_cast<std::size_t>(r) + 1] - a)));
    }
  }
  // Rank bounds: about 18 ranks of each cell's sorted distances, in 256 bins, counted per run
  // (a histogram of the run's cells, then a walk to each rank).
  const int D = v.num_directions;
  const std::size_t N = v.num_cells();
  pre->rank_step = std::max(1, (D + 17) / 18);  // at most 18 blocks, 19 ranks
  pre->rank_count = (D + pre->rank_step - 1) / pre->rank_step;
  pre->rank_bin = (v.max_units() + 1 + 255) / 256;
  pre->rank_codes.assign(static_cast<std::size_t>(pre->rank_count + 1) * N, 0);
  const int J = pre->rank_count, q = pre->rank_step, w = pre->rank_bin;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pre->runs.size(), 64), [&](const tbb::blocked_range<std::size_t>& range) {
    std::vector<std::uint16_t> hist(static_cast<std::size_t>(kRunCells) * 256);
    for (std::size_t u = range.begin(); u != range.end(); ++u) {
      const std::size_t first = static_cast<std::size_t>(pre->runs[u].first);
      const int n = pre->runs[u].second;
      std::fill(hist.begin(), hist.end(), 0);
      auto count = [&](const auto* values) {
        for (int d = 0; d < D; ++d) {
          const auto* v = values + static_cast<std::size_t>(d) * N + first;
          for (int t = 0; t < n; ++t) ++hist[static_cast<std::size_t>(t) * 256 + v[t] / w];
        }
      };
      if (v.bits == 8) {
        count(v.q8.data());
      } else {
        count(v.mm.data());
      }
      for (int t = 0; t < n; ++t) {
        const std::uint16_t* h = hist.data() + static_cast<std::size_t>(t) * 256;
        int c = 0, below = h[0];  // values in bins 0..c
        for (int j = 0; j <= J; ++j) {
          const int rank = std::min(j * q, D - 1);
          while (below <= rank) below += h[++c];
          pre->rank_codes[static_cast<std::size_t>(j) * N + first + static_cast<std::size_t>(t)] = static_cast<std::uint8_t>(c);
        }
      }
    }
  });
  return pre;
}

RayMatcher::~RayMatcher() = default;

std::vector<double> RayMatcher::observation_rays(const Observation2D& obs) const {
  const int D = params_.num_directions;
  const bool have_ranges = static_cast<int>(obs.ray_ranges_m.size()) == D;
  std::vector<double> rays;
  if (params_.ray_source == RaySource::kRanges || (params_.ray_source == RaySource::kAuto && have_ranges)) {
    if (!have_ranges) {
      throw InputError("matcher ray: the observation has " + std::to_string(obs.ray_ranges_m.size()) +
                       " ray ranges but the matcher needs " + std::to_string(D) + " (ray_source \"ranges\")");
    }
    rays = obs.ray_ranges_m;
  } else {
    rays = cast_rays_on_segments(obs.segments_m, D, params_.max_range_m);
  }
  for (double& r : rays) {
    if (!std::isfinite(r) || r < 0.0) throw InputError("matcher ray: observation ray range is negative or not finite");
  }
  return rays;
}

RayMatcher::ComparedRays RayMatcher::compared_rays(const Observation2D& obs) const {
  const std::vector<double> r = observation_rays(obs);
  const int D = params_.num_directions;
  // Rays within +-fov/2 of the heading: V = 2 h + 1 of them, or all D.
  const int half = static_cast<int>(std::floor(0.5 * params_.fov_deg / (360.0 / D) + 1e-9));
  const int V = 2 * half + 1 < D ? 2 * half + 1 : D;
  ComparedRays out;
  auto ray_at = [&](int relative_bins) { return r[static_cast<std::size_t>(((relative_bins % D) + D) % D)]; };
  if (params_.ray_convention == RayConvention::kFloorcast) {
    // Ray i (at 2 pi i / D from the heading) against direction o + i, in increasing i.
    for (int i = 0; i < D; ++i) {
      const int signed_i = i <= D / 2 ? i : i - D;
      if (V < D && std::abs(signed_i) > half) continue;
      out.offset.push_back(i);
      out.range_m.push_back(r[static_cast<std::size_t>(i)]);
    }
    return out;
  }
  // F3Loc's localize(): given[k] (left to right) is flipped, and flipped[k] = given[V - 1 - k] is
  // compared with direction o - V//2 + k. given[m] holds the ray at relative angle rel(m) bins.
  const int c = V - 1 - V / 2;  // the given index localize() takes as the heading
  auto rel = [&](int m) {
    switch (params_.ray_convention) {
      case RayConvention::kF3Loc: return c - m;
      case RayConvention::kOneBinOff: return V / 2 - m;
      case RayConvention::kMirrored: return m - c;
      case RayConvention::kHeadingRay0: return -m;
      case RayConvention::kFloorcast: break;
    }
    return 0;
  };
  for (int k = 0; k < V; ++k) {
    out.offset.push_back(((k - V / 2) % D + D) % D);
    out.range_m.push_back(ray_at(rel(V - 1 - k)));
  }
  return out;
}

RayMatcher::RayUnits RayMatcher::ray_units(const Observation2D& obs) const {
  const ComparedRays cr = compared_rays(obs);
  // Both sides are clipped at the smaller of the volume's and the observation's range, unless the
  // observation is left unclipped (then only the volume's own range applies, to its side).
  const double clip_m = std::min(pre_->volume.max_range_m, obs.max_range_m > 0.0 ? obs.max_range_m : pre_->volume.max_range_m);
  const double per_unit = 1000.0 / pre_->volume.step_mm;
  RayUnits r;
  r.offsets = cr.offset;
  r.rays.resize(cr.range_m.size());
  if (params_.clip_observation) {
    r.clip = static_cast<std::uint16_t>(std::min<long>(std::lround(clip_m * per_unit), pre_->volume.max_units()));
    r.clipped = r.clip < pre_->volume.max_units();
    for (std::size_t i = 0; i < cr.range_m.size(); ++i)
      r.rays[i] = static_cast<std::uint16_t>(std::min<long>(r.clip, std::lround(cr.range_m[i] * per_unit)));
  } else {
    r.clip = static_cast<std::uint16_t>(pre_->volume.max_units());
    r.clipped = false;
    for (std::size_t i = 0; i < cr.range_m.size(); ++i)
      r.rays[i] = static_cast<std::uint16_t>(std::min<long>(65535, std::lround(cr.range_m[i] * per_unit)));
  }
  // Rays per 16-bit partial sum: each |v - r| is at most the larger of the clip and the longest ray.
  int top = r.clip;
  for (const std::uint16_t x : r.rays) top = std::max<int>(top, x);
  r.block = std::max(1, 65535 / std::max(1, top));
  return r;
}

MatchResult RayMatcher::match(const Observation2D& obs, const MatchRequest& request) const {
  const auto t0 = Clock::now();
  MatchResult result;
  const int D = params_.num_directions;
  const RayUnits ru = ray_units(obs);
  const TileRays rays{ru.offsets.data(), static_cast<int>(ru.offsets.size()), ru.rays.data(), ru.clip, ru.clipped, ru.block};
  const auto t1 = Clock::now();
  if (request.output != MatchOutput::kPosterior) {
    match_modes(ru, request, result);
    result.stage_s["observation_rays"] = seconds(t0, t1);
    result.match_s = seconds(t0, Clock::now());
    return result;
  }

  Posterior& post = result.posterior;
  const GridSpec& g = pre_->volume.grid;
  post.grid = g;
  post.yaw_rad.resize(static_cast<std::size_t>(D));
  post.scores.resize(static_cast<std::size_t>(D));
  std::vector<float*> slices(static_cast<std::size_t>(D));
  for (int o = 0; o < D; ++o) {
    post.yaw_rad[static_cast<std::size_t>(o)] = 2.0 * kPi * o / D;
    // Not zeroed here: every row is written in full below (0 where no cell is stored).
    post.scores[static_cast<std::size_t>(o)].create(g.height_px, g.width_px, CV_32F);
    slices[static_cast<std::size_t>(o)] = post.scores[static_cast<std::size_t>(o)].ptr<float>();
  }
  const auto t2 = Clock::now();

  const float k = static_cast<float>(1e-3 * pre_->volume.step_mm / params_.lambda_m);
  const std::size_t W = static_cast<std::size_t>(g.width_px);
  double l1_s = 0.0, exp_s = 0.0;
  // The row of every slice is written once, front to back (0 where no cell is stored).
  score_all_cells(
      pre_->volume, pre_->row_start, rays, k,
      [&](int row) {
        const std::size_t row_offset = static_cast<std::size_t>(row) * W;
        for (int o = 0; o < D; ++o) std::memset(slices[static_cast<std::size_t>(o)] + row_offset, 0, W * sizeof(float));
      },
      [&](std::size_t first, int n, int o, const float* score) {
        const std::int32_t* cells = pre_->volume.cells.data() + first;
        float* dst = slices[static_cast<std::size_t>(o)];
        for (int t = 0; t < n; ++t) dst[cells[t]] = score[t];
      },
      l1_s, exp_s);
  result.stage_s["observation_rays"] = seconds(t0, t1);
  result.stage_s["posterior_alloc"] = seconds(t1, t2);
  // Thread CPU seconds summed over workers.
  result.stage_s["l1_distances"] = l1_s;
  result.stage_s["exp_scatter"] = exp_s;
  const auto t3 = Clock::now();
  finish_from_posterior(result, request);
  // Poses at each cell's cast point (the posterior's modes are at cell centres).
  for (PoseHypothesis& h : result.modes) {
    const Vec2 p = volume_cast_point(pre_->volume, h.row, h.col);
    h.x_m = p.x();
    h.y_m = p.y();
  }
  result.stage_s["modes"] = seconds(t3, Clock::now());
  result.match_s = seconds(t0, Clock::now());
  return result;
}

PosteriorQuery RayMatcher::query(const Observation2D& obs) const {
  auto ru = std::make_shared<const RayUnits>(ray_units(obs));
  MatchResult best;
  match_modes(*ru, MatchRequest::modes(1), best);
  const double max_score = best.modes.empty() ? 0.0 : best.modes.front().score;
  const int D = params_.num_directions;
  std::vector<double> yaws(static_cast<std::size_t>(D));
  for (int o = 0; o < D; ++o) yaws[static_cast<std::size_t>(o)] = 2.0 * kPi * o / D;
  auto scorer = [this, ru](const std::vector<PosteriorCell>& cells, float* out) {
    // Each cell's L1 at its slice, in integers as l1_tile sums it, then the same exp.
    const DistanceVolume& v = pre_->volume;
    const std::size_t N = v.num_cells();
    const int Dv = v.num_directions;
    const float k = static_cast<float>(1e-3 * v.step_mm / params_.lambda_m);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells.size(), 256), [&](const tbb::blocked_range<std::size_t>& range) {
      std::vector<std::int32_t> acc(range.size());
      std::vector<char> stored(range.size());
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        const PosteriorCell& c = cells[i];
        const std::int32_t index = v.cell_index[static_cast<std::size_t>(c.row) * v.grid.width_px + static_cast<std::size_t>(c.col)];
        std::int32_t sum = 0;
        stored[i - range.begin()] = index >= 0;
        if (index >= 0) {
          for (std::size_t j = 0; j < ru->offsets.size(); ++j) {
            const std::size_t d = static_cast<std::size_t>((c.slice + ru->offsets[j]) % Dv);
            const int raw = v.bits == 8 ? v.q8[d * N + static_cast<std::size_t>(index)] : v.mm[d * N + static_cast<std::size_t>(index)];
            const int value = ru->clipped ? std::min<int>(raw, ru->clip) : raw;
            sum += std::abs(value - static_cast<int>(ru->rays[j]));
          }
        }
        acc[i - range.begin()] = sum;
      }
      exp_neg_scaled(acc.data(), static_cast<int>(range.size()), k, out + range.begin());
      for (std::size_t i = range.begin(); i != range.end(); ++i)
        if (!stored[i - range.begin()]) out[i] = 0.0f;
    });
  };
  Observation2D copy = obs;
  auto full = [this, copy = std::move(copy)]() { return match(copy).posterior; };
  return PosteriorQuery(pre_->volume.grid, std::move(yaws), max_score, scorer, full);
}

RayMatcher::RankTables RayMatcher::rank_tables(const std::vector<std::uint16_t>& rays_u, int top_mm) const {
  // Lower bound of min over orientations of L1(cell, o): the sorted rays matched rank for rank
  // with the cell's sorted distances (the L1-optimal pairing, so no rotation does better), each
  // distance of rank block j (ranks j q .. (j + 1) q - 1) replaced by the interval its stored
  // rank bins allow (bin of rank j q from below, bin of rank (j + 1) q from above), every value
  // clipped at top_mm as the L1 clips. Per block: a table over the 256 bins of each end.
  const int D = pre_->volume.num_directions, J = pre_->rank_count, q = pre_->rank_step, w = pre_->rank_bin;
  std::vector<int> sorted_rays(rays_u.begin(), rays_u.end());
  std::sort(sorted_rays.begin(), sorted_rays.end());
  RankTables t;
  t.lo.resize(static_cast<std::size_t>(J) * 256);
  t.hi.resize(static_cast<std::size_t>(J) * 256);
  for (int j = 0; j < J; ++j) {
    for (int c = 0; c < 256; ++c) {
      const int lo = std::min(c * w, top_mm), hi = std::min((c + 1) * w - 1, top_mm);
      std::int32_t a = 0, b = 0;
      for (int r = j * q; r < std::min((j + 1) * q, D); ++r) {
        a += std::max(0, lo - sorted_rays[static_cast<std::size_t>(r)]);
        b += std::max(0, sorted_rays[static_cast<std::size_t>(r)] - hi);
      }
      t.lo[static_cast<std::size_t>(j) * 256 + static_cast<std::size_t>(c)] = a;
      t.hi[static_cast<std::size_t>(j) * 256 + static_cast<std::size_t>(c)] = b;
    }
  }
  return t;
}

void RayMatcher::rank_bounds(const RankTables& t, std::size_t first, int n, std::int32_t* lb) const {
  const std::size_t N = pre_->volume.num_cells();
  for (int i = 0; i < n; ++i) lb[i] = 0;
  for (int j = 0; j < pre_->rank_count; ++j) {
    const std::uint8_t* lo = pre_->rank_codes.data() + static_cast<std::size_t>(j) * N + first;
    const std::uint8_t* hi = lo + N;
    const std::int32_t* tl = t.lo.data() + static_cast<std::size_t>(j) * 256;
    const std::int32_t* th = t.hi.data() + static_cast<std::size_t>(j) * 256;
    for (int i = 0; i < n; ++i) lb[i] += tl[lo[i]] + th[hi[i]];
  }
}

std::vector<std::int32_t> RayMatcher::lower_bounds_mm(const Observation2D& obs) const {
  const RayUnits ru = ray_units(obs);
  const RankTables t = rank_tables(ru.rays, ru.clip);
  std::vector<std::int32_t> out(pre_->volume.num_cells());
  for (const auto& run : pre_->runs) rank_bounds(t, static_cast<std::size_t>(run.first), run.second, out.data() + run.first);
  for (std::int32_t& b : out) b *= pre_->volume.step_mm;
  return out;
}

RayMatcher::GroupBounds RayMatcher::group_bounds_mm(const Observation2D& obs) const {
  const RayUnits ru = ray_units(obs);
  const TileRays rays{ru.offsets.data(), static_cast<int>(ru.offsets.size()), ru.rays.data(), ru.clip, ru.clipped, ru.block};
  const int D = pre_->volume.num_directions;
  GroupBounds out;
  out.group_width = group_width(D);
  const int w = out.group_width > 0 ? out.group_width : D;
  out.groups = (D + w - 1) / w;
  const std::size_t cells = static_cast<std::size_t>(D) * kRunCells;
  std::vector<std::uint16_t> lo(cells), hi(cells), tmp(cells);
  std::vector<std::int32_t> acc(static_cast<std::size_t>(out.groups) * kRunCells);
  out.mm.resize(pre_->volume.num_cells() * static_cast<std::size_t>(out.groups));
  for (const auto& run : pre_->runs) {
    group_bounds(pre_->volume, static_cast<std::size_t>(run.first), run.second, w, rays, lo.data(), hi.data(), tmp.data(),
                 acc.data());
    for (int t = 0; t < run.second; ++t)
      for (int g = 0; g < out.groups; ++g)
        out.mm[(static_cast<std::size_t>(run.first) + static_cast<std::size_t>(t)) * static_cast<std::size_t>(out.groups) +
               static_cast<std::size_t>(g)] = acc[static_cast<std::size_t>(g) * kRunCells + static_cast<std::size_t>(t)] *
                                              pre_->volume.step_mm;
  }
  return out;
}

void RayMatcher::match_modes(const RayUnits& ru, const MatchRequest& request, MatchResult& result) const {
  const TileRays rays{ru.offsets.data(), static_cast<int>(ru.offsets.size()), ru.rays.data(), ru.clip, ru.clipped, ru.block};
  // The estimate, top-K modes and max-over-yaw map without the D x H x W posterior (which costs
  // ~200 MB per office-sized match, its first touch dominating the time): one pass keeps each
  // stored cell's best orientation; the greedy suppression of Posterior::top_k then needs the
  // full orientation vector only of the few cells within the separation of a chosen mode, which
  // is recomputed with the same arithmetic (same L1 sums, same exp), so the modes are those
  // top_k finds on the full posterior, ties broken the same way (lowest slice, then row-major).
  const int D = params_.num_directions;
  const GridSpec& g = pre_->volume.grid;
  const std::size_t N = pre_->volume.num_cells();
  const float k = static_cast<float>(1e-3 * pre_->volume.step_mm / params_.lambda_m);
  std::vector<float> best(N, 0.0f);
  std::vector<std::uint16_t> best_o(N, 0);
  const auto t0 = Clock::now();
  double l1_s = 0.0, exp_s = 0.0;
  // The rank bound pairs all D distances with all D rays: a field of view narrower than 360 deg
  // is searched exhaustively.
  const bool bounded = params_.search == RaySearch::kBounded && request.output == MatchOutput::kModes &&
                       static_cast<int>(ru.offsets.size()) == D;
  // Cells whose best is final: recomputed over the live orientations by a suppression.
  std::vector<std::uint8_t> touched(bounded ? N : 0, 0);
  // Bounded search, coarse to fine: runs ordered by the smallest rank bound of their cells' L1
  // (order, rotation-invariant, cheap); with orientation groups (group_width), runs are taken from
  // that order in batches and bounded per group (group_bounds: orientation-aware, much tighter
  // in corridors), and the refined runs are scored from a heap in ascending refined bound, each
  // cell only at the groups that can still hold its best orientation. order[0..next_rank) have
  // left the rank order (refined, or scored directly without groups); `scored` lists the runs
  // scored.
  std::vector<std::int32_t> run_lb;
  std::vector<std::uint32_t> order;
  std::size_t next_rank = 0;
  std::vector<std::uint32_t> scored;
  const int gw = bounded ? group_width(D) : 0;
  const int G = gw > 0 ? (D + gw - 1) / gw : 0;
  std::vector<std::pair<std::int32_t, std::uint32_t>> heap;  // (refined bound, run), a min-heap
  std::unique_ptr<std::int32_t[]> group_lb;                   // G per run (only refined runs written)
  std::int32_t margin_u = 0;
  double bound_s = 0.0;
  std::size_t cells_scored = 0, runs_refined = 0;
  auto update_best = [&](std::size_t first, int n, int o, const float* score) {
    for (int t = 0; t < n; ++t) {
      const std::size_t i = first + static_cast<std::size_t>(t);
      if (score[t] > best[i]) {  // strict: the lowest slice wins ties
        best[i] = score[t];
        best_o[i] = static_cast<std::uint16_t>(o);
      }
    }
  };
  struct RunScratch {
    std::vector<std::int32_t> acc;
    std::vector<std::uint16_t> part, lo, hi, tmp;
    std::vector<float> score;
    double l1_s = 0.0, exp_s = 0.0, group_s = 0.0;
    std::size_t orientations = 0;
  };
  tbb::enumerable_thread_specific<RunScratch> run_scratch;
  // Scores the runs batch[0..) exactly, the same arithmetic as score_all_cells: every
  // orientation, or with groups the groups in ascending bound until no cell of the run can have
  // its best orientation in the rest (a group's bound above every cell's best L1 so far plus the
  // rounding margin); ties go to the lowest slice as in the exhaustive pass.
  auto score_runs = [&](const std::vector<std::uint32_t>& batch) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, batch.size(), 4), [&](const tbb::blocked_range<std::size_t>& range) {
      RunScratch& s = run_scratch.local();
      s.acc.resize(static_cast<std::size_t>(D) * kRunCells);
      s.part.resize(kRunCells);
      s.score.resize(kRunCells);
      for (std::size_t u = range.begin(); u != range.end(); ++u) {
        const std::size_t first = static_cast<std::size_t>(pre_->runs[batch[u]].first);
        const int n = pre_->runs[batch[u]].second;
        if (G == 0) {
          const double ta = thread_cpu_s();
          l1_tile(pre_->volume, first, n, kRunCells, rays, s.acc.data(), s.part.data());
          const double tb = thread_cpu_s();
          for (int o = 0; o < D; ++o) {
            exp_neg_scaled(s.acc.data() + static_cast<std::size_t>(o) * kRunCells, n, k, s.score.data());
            for (int t = 0; t < n; ++t) {
              const std::size_t i = first + static_cast<std::size_t>(t);
              if (!touched[i] && s.score[t] > best[i]) {
                best[i] = s.score[t];
                best_o[i] = static_cast<std::uint16_t>(o);
              }
            }
          }
          s.l1_s += tb - ta;
          s.exp_s += thread_cpu_s() - tb;
          s.orientations += static_cast<std::size_t>(D) * static_cast<std::size_t>(n);
          continue;
        }
        const std::int32_t* gl = group_lb.get() + static_cast<std::size_t>(batch[u]) * static_cast<std::size_t>(G);
        std::vector<int> groups(static_cast<std::size_t>(G));
        for (int g = 0; g < G; ++g) groups[static_cast<std::size_t>(g)] = g;
        std::sort(groups.begin(), groups.end(), [&](int a, int b) { return gl[a] != gl[b] ? gl[a] < gl[b] : a < b; });
        std::int32_t cell_min[kRunCells];
        for (int t = 0; t < kRunCells; ++t) cell_min[t] = std::numeric_limits<std::int32_t>::max();
        for (int idx = 0; idx < G; ++idx) {
          const int g = groups[static_cast<std::size_t>(idx)];
          if (idx > 0) {
            const std::int64_t worst = *std::max_element(cell_min, cell_min + n);
            if (static_cast<std::int64_t>(gl[g]) > worst + margin_u) break;
          }
          const int o0 = g * gw, o1 = std::min(D, o0 + gw);
          const double ta = thread_cpu_s();
          l1_tile(pre_->volume, first, n, kRunCells, rays, s.acc.data(), s.part.data(), o0, o1);
          const double tb = thread_cpu_s();
          for (int o = o0; o < o1; ++o) {
            const std::int32_t* acc = s.acc.data() + static_cast<std::size_t>(o) * kRunCells;
            exp_neg_scaled(acc, n, k, s.score.data());
            for (int t = 0; t < n; ++t) {
              cell_min[t] = std::min(cell_min[t], acc[t]);
              const std::size_t i = first + static_cast<std::size_t>(t);
              if (!touched[i] && (s.score[t] > best[i] || (s.score[t] == best[i] && o < best_o[i]))) {
                best[i] = s.score[t];
                best_o[i] = static_cast<std::uint16_t>(o);
              }
            }
          }
          s.l1_s += tb - ta;
          s.exp_s += thread_cpu_s() - tb;
          s.orientations += static_cast<std::size_t>(o1 - o0) * static_cast<std::size_t>(n);
        }
      }
    });
    for (const std::uint32_t u : batch) {
      cells_scored += static_cast<std::size_t>(pre_->runs[u].second);
      scored.push_back(u);
    }
  };
  // Bounds the runs order[a..b) per orientation group and puts them on the heap.
  auto refine_runs = [&](std::size_t a, std::size_t b) {
    std::vector<std::int32_t> refined(b - a);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(a, b, 8), [&](const tbb::blocked_range<std::size_t>& range) {
      RunScratch& s = run_scratch.local();
      const std::size_t cells = static_cast<std::size_t>(D) * kRunCells;
      s.lo.resize(cells);
      s.hi.resize(cells);
      s.tmp.resize(cells);
      s.acc.resize(std::max(s.acc.size(), static_cast<std::size_t>(std::max(D, G)) * kRunCells));
      const double ta = thread_cpu_s();
      for (std::size_t v = range.begin(); v != range.end(); ++v) {
        const std::uint32_t u = order[v];
        const int n = pre_->runs[u].second;
        group_bounds(pre_->volume, static_cast<std::size_t>(pre_->runs[u].first), n, gw, rays, s.lo.data(), s.hi.data(),
                     s.tmp.data(), s.acc.data());
        std::int32_t* gl = group_lb.get() + static_cast<std::size_t>(u) * static_cast<std::size_t>(G);
        std::int32_t lowest = std::numeric_limits<std::int32_t>::max();
        for (int g = 0; g < G; ++g) {
          const std::int32_t* acc = s.acc.data() + static_cast<std::size_t>(g) * kRunCells;
          gl[g] = *std::min_element(acc, acc + n);
          lowest = std::min(lowest, gl[g]);
        }
        // The rank bound holds as well: keep the larger.
        refined[v - a] = std::max(lowest, run_lb[u]);
      }
      s.group_s += thread_cpu_s() - ta;
    });
    for (std::size_t v = a; v < b; ++v) {
      heap.emplace_back(refined[v - a], order[v]);
      std::push_heap(heap.begin(), heap.end(), std::greater<>());
    }
    runs_refined += b - a;
  };
  if (!bounded) {
    score_all_cells(pre_->volume, pre_->row_start, rays, k, [](int) {}, update_best, l1_s, exp_s);
  } else {
    // Every run's smallest lower bound (rank_tables), then the runs in ascending bound order.
    const auto tb0 = Clock::now();
    const RankTables tables = rank_tables(ru.rays, ru.clipped ? ru.clip : pre_->volume.max_units());
    run_lb.resize(pre_->runs.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pre_->runs.size(), 256), [&](const tbb::blocked_range<std::size_t>& range) {
      std::int32_t lb[kRunCells];
      for (std::size_t u = range.begin(); u != range.end(); ++u) {
        const int n = pre_->runs[u].second;
        rank_bounds(tables, static_cast<std::size_t>(pre_->runs[u].first), n, lb);
        run_lb[u] = *std::min_element(lb, lb + n);
      }
    });
    order.resize(pre_->runs.size());
    for (std::size_t u = 0; u < order.size(); ++u) order[u] = static_cast<std::uint32_t>(u);
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
      return run_lb[a] != run_lb[b] ? run_lb[a] < run_lb[b] : a < b;
    });
    // exp_neg_scaled is monotone only up to float rounding (relative ~1e-5 at the largest sums):
    // bounds are lowered by a margin worth 1e-4 of the exponent before they are compared.
    margin_u = static_cast<std::int32_t>(std::min(1e9, std::ceil(0.1 * params_.lambda_m / pre_->volume.step_mm)));
    if (G > 0) group_lb.reset(new std::int32_t[pre_->runs.size() * static_cast<std::size_t>(G)]);
    bound_s = seconds(tb0, Clock::now());
  }
  // The lowest L1 bound of the runs still in the rank order.
  constexpr std::int64_t kNone = std::numeric_limits<std::int64_t>::max();
  auto frontier = [&]() -> std::int64_t { return next_rank < order.size() ? run_lb[order[next_rank]] : kNone; };
  auto all_scored = [&]() { return next_rank >= order.size() && heap.empty(); };
  // Highest score an unscored cell can reach (0 when every run is scored).
  auto unscored_bound = [&]() -> float {
    if (!bounded || all_scored()) return 0.0f;
    const std::int64_t lowest = std::min(frontier(), heap.empty() ? kNone : static_cast<std::int64_t>(heap.front().first));
    const std::int32_t a = static_cast<std::int32_t>(std::max<std::int64_t>(0, lowest - margin_u));
    float u = 0.0f;
    exp_neg_scaled(&a, 1, k, &u);
    return u;
  };
  // One step of the search: score the refined runs no rank-ordered run can undercut (a batch),
  // else refine the next batch of the rank order (without groups: score it).
  auto advance = [&]() {
    std::vector<std::uint32_t> batch;
    const std::size_t size = std::max<std::size_t>(32, scored.size() / kBatchGrowth);
    if (!heap.empty() && heap.front().first <= frontier()) {
      while (!heap.empty() && heap.front().first <= frontier() && batch.size() < size) {
        std::pop_heap(heap.begin(), heap.end(), std::greater<>());
        batch.push_back(heap.back().second);
        heap.pop_back();
      }
      score_runs(batch);
      return;
    }
    if (G > 0) {
      const std::size_t end = std::min(order.size(), next_rank + std::max<std::size_t>(64, next_rank / kBatchGrowth));
      refine_runs(next_rank, end);
      next_rank = end;
      return;
    }
    const std::size_t end = std::min(order.size(), next_rank + size);
    batch.assign(order.begin() + static_cast<std::ptrdiff_t>(next_rank), order.begin() + static_cast<std::ptrdiff_t>(end));
    next_rank = end;
    score_runs(batch);
  };
  const auto t1 = Clock::now();
  result.grid = g;
  const std::size_t W = static_cast<std::size_t>(g.width_px);
  if (request.output == MatchOutput::kMaxOverYaw) {
    result.max_over_yaw = cv::Mat::zeros(g.height_px, g.width_px, CV_32F);
    float* m = result.max_over_yaw.ptr<float>();
    for (std::size_t i = 0; i < N; ++i) m[static_cast<std::size_t>(pre_->volume.cells[i])] = best[i];
  }

  // Greedy suppression on the per-cell best over the live orientations.
  auto yaw_of = [&](int o) { return 2.0 * kPi * o / D; };
  std::map<std::size_t, std::vector<float>> full;     // all D scores of cells touched by a suppression
  std::map<std::size_t, std::vector<std::uint8_t>> dead;
  // All D scores of a cell within a chosen mode's separation (filled by fill_row below).
  auto scores_of = [&](std::size_t i) -> const std::vector<float>& { return full.at(i); };
  // All D scores of the stored cells of row r between columns c0 and c1, for the cells not yet
  // in `full`: vectorised over the row's contiguous cells (the same arithmetic per cell).
  std::vector<std::int32_t> acc_row(static_cast<std::size_t>(D) * kRunCells);
  std::vector<std::uint16_t> part_row(kRunCells);
  std::vector<float> score_row(static_cast<std::size_t>(D) * kRunCells);
  auto fill_row = [&](int r, int c0, int c1) {
    const auto rb = pre_->volume.cells.begin() + pre_->row_start[static_cast<std::size_t>(r)];
    const auto re = pre_->volume.cells.begin() + pre_->row_start[static_cast<std::size_t>(r) + 1];
    const std::int32_t base = static_cast<std::int32_t>(static_cast<std::size_t>(r) * W);
    const std::size_t a = static_cast<std::size_t>(std::lower_bound(rb, re, base + c0) - pre_->volume.cells.begin());
    const std::size_t b = static_cast<std::size_t>(std::upper_bound(rb, re, base + c1) - pre_->volume.cells.begin());
    for (std::size_t f = a; f < b; f += kRunCells) {
      const int n = static_cast<int>(std::min<std::size_t>(kRunCells, b - f));
      bool missing = false;
      for (int t = 0; t < n && !missing; ++t) missing = !full.count(f + static_cast<std::size_t>(t));
      if (!missing) continue;
      l1_tile(pre_->volume, f, n, kRunCells, rays, acc_row.data(), part_row.data());
      for (int o = 0; o < D; ++o) {
        exp_neg_scaled(acc_row.data() + static_cast<std::size_t>(o) * kRunCells, n, k,
                       score_row.data() + static_cast<std::size_t>(o) * kRunCells);
      }
      for (int t = 0; t < n; ++t) {
        if (full.count(f + static_cast<std::size_t>(t))) continue;
        std::vector<float> v(static_cast<std::size_t>(D));
        for (int o = 0; o < D; ++o) v[static_cast<std::size_t>(o)] = score_row[static_cast<std::size_t>(o) * kRunCells + static_cast<std::size_t>(t)];
        full.emplace(f + static_cast<std::size_t>(t), std::move(v));
      }
    }
  };
  const double res = g.resolution_m_per_px;
  const int rad = static_cast<int>(std::floor(request.mode_separation_m / res + 1e-9));
  // The best live (cell, orientation): highest score, then lowest slice, then lowest cell. The
  // bounded search looks only at the scored runs and the cells a suppression recomputed (every
  // other cell's best is still 0).
  std::vector<std::size_t> touched_list;
  auto find_best = [&]() {
    std::size_t bi = N;
    auto consider = [&](std::size_t i) {
      const float v = best[i];
      if (v <= 0.0f) return;
      if (bi == N || v > best[bi] ||
          (v == best[bi] && (best_o[i] < best_o[bi] || (best_o[i] == best_o[bi] && i < bi))))
        bi = i;
    };
    if (!bounded) {
      for (std::size_t i = 0; i < N; ++i) consider(i);
      return bi;
    }
    for (const std::uint32_t u : scored) {
      const std::size_t first = static_cast<std::size_t>(pre_->runs[u].first);
      for (int t = 0; t < pre_->runs[u].second; ++t) consider(first + static_cast<std::size_t>(t));
    }
    for (const std::size_t i : touched_list) consider(i);
    return bi;
  };
  while (static_cast<int>(result.modes.size()) < request.top_k) {
    std::size_t bi = find_best();
    // Bounded: the candidate is the next mode once no unscored cell can reach (or tie) it; until
    // then score more runs, in bound order, in growing batches.
    while (bounded && !all_scored() && !(bi != N && best[bi] > unscored_bound())) {
      advance();
      bi = find_best();
    }
    if (bi == N) break;
    const int lin = pre_->volume.cells[bi];
    const int br = lin / g.width_px, bc = lin % g.width_px, bo = best_o[bi];
    PoseHypothesis h;
    const Vec2 p = volume_cast_point(pre_->volume, br, bc);
    h.x_m = p.x();
    h.y_m = p.y();
    h.yaw_rad = yaw_of(bo);
    h.score = best[bi];
    h.slice = bo;
    h.row = br;
    h.col = bc;
    result.modes.push_back(h);
    std::vector<std::uint8_t> suppress(static_cast<std::size_t>(D), 0);
    for (int o = 0; o < D; ++o) suppress[static_cast<std::size_t>(o)] = angle_distance_rad(yaw_of(o), h.yaw_rad) <= request.mode_separation_rad;
    for (int r = std::max(0, br - rad - 1); r <= std::min(g.height_px - 1, br + rad + 1); ++r) {
      fill_row(r, std::max(0, bc - rad - 1), std::min(g.width_px - 1, bc + rad + 1));
      const auto rb = pre_->volume.cells.begin() + pre_->row_start[static_cast<std::size_t>(r)];
      const auto re = pre_->volume.cells.begin() + pre_->row_start[static_cast<std::size_t>(r) + 1];
      for (int c = std::max(0, bc - rad - 1); c <= std::min(g.width_px - 1, bc + rad + 1); ++c) {
        const double dx = (c - bc) * res, dy = (r - br) * res;
        if (!(std::sqrt(dx * dx + dy * dy) <= request.mode_separation_m + 1e-12)) continue;
        const std::int32_t want = static_cast<std::int32_t>(static_cast<std::size_t>(r) * W + static_cast<std::size_t>(c));
        const auto it = std::lower_bound(rb, re, want);
        if (it == re || *it != want) continue;
        const std::size_t i = static_cast<std::size_t>(it - pre_->volume.cells.begin());
        if (bounded && !touched[i]) {
          touched[i] = 1;
          touched_list.push_back(i);
        }
        std::vector<std::uint8_t>& d = dead.try_emplace(i, std::vector<std::uint8_t>(static_cast<std::size_t>(D), 0)).first->second;
        for (int o = 0; o < D; ++o) d[static_cast<std::size_t>(o)] |= suppress[static_cast<std::size_t>(o)];
        const std::vector<float>& v = scores_of(i);
        float m = 0.0f;
        std::uint16_t mo = 0;
        for (int o = 0; o < D; ++o) {
          if (!d[static_cast<std::size_t>(o)] && v[static_cast<std::size_t>(o)] > m) {
            m = v[static_cast<std::size_t>(o)];
            mo = static_cast<std::uint16_t>(o);
          }
        }
        best[i] = m;
        best_o[i] = mo;
      }
    }
  }
  if (bounded) {
    std::size_t orientations = 0;
    double group_s = 0.0;
    for (const RunScratch& sc : run_scratch) {
      l1_s += sc.l1_s;
      exp_s += sc.exp_s;
      group_s += sc.group_s;
      orientations += sc.orientations;
    }
    result.stage_s["bounds_wall"] = bound_s;
    result.stage_s["group_bounds"] = group_s;
    result.counters["runs_refined_share"] = pre_->runs.empty() ? 0.0 : static_cast<double>(runs_refined) / static_cast<double>(pre_->runs.size());
    result.counters["orientations_scored_share"] =
        cells_scored ? static_cast<double>(orientations) / (static_cast<double>(cells_scored) * D) : 0.0;
    result.counters["cells_scored"] = static_cast<double>(cells_scored);
    result.counters["cells_scored_share"] = N ? static_cast<double>(cells_scored) / static_cast<double>(N) : 0.0;
  }
  result.stage_s["l1_distances"] = l1_s;
  result.stage_s["exp_best_orientation"] = exp_s;
  result.stage_s["modes"] = seconds(t1, Clock::now());
  result.stage_s["scores"] = seconds(t0, t1);
}

Vec2 volume_cast_point(const DistanceVolume& v, int row, int col) {
  const GridSpec& g = v.grid;
  return {g.origin_x_m + (col + v.sample_offset) * g.resolution_m_per_px,
          g.origin_y_m + (row + v.sample_offset) * g.resolution_m_per_px};
}

std::vector<double> ray_scores_reference(const DistanceVolume& v, std::size_t cell, const std::vector<double>& rays,
                                         double clip_m, double lambda_m) {
  const int D = v.num_directions;
  std::vector<double> out(static_cast<std::size_t>(D));
  for (int o = 0; o < D; ++o) {
    double l1 = 0.0;
    for (int i = 0; i < D; ++i) {
      const double vm = std::min(v.range_m(cell, (o + i) % D), clip_m);
      l1 += std::abs(vm - std::min(rays[static_cast<std::size_t>(i)], clip_m));
    }
    out[static_cast<std::size_t>(o)] = std::exp(-l1 / lambda_m);
  }
  return out;
}

}  // namespace floorcast
