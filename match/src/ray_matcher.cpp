#include "floorcast/match/ray_matcher.hpp"
#include "floorcast/core/limits.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>

#include "floorcast/core/hash.hpp"
#include "floorcast/match/plan_raster.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/core/timing.hpp"

namespace floorcast {
namespace {

using Clock = std::chrono::steady_clock;

double seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

const std::vector<std::pair<const char*, RaySource>> kRaySourceNames = {
    {"auto", RaySource::kAuto}, {"ranges", RaySource::kRanges}, {"segments", RaySource::kSegments}};

/// Cells per tile of the scoring loop: the tile's distances (D x T uint16) and sums (D x T
/// int32) stay in L1/L2.
int tile_cells(int D) { return D <= 64 ? 512 : 128; }

/// acc[o * stride + t] = sum_i |min(V[(o + i) mod D][first + t], clip) - rays[i]| for the
/// T <= stride cells of one tile, in millimetres. The hot loop of the matcher: 16-bit lanes
/// (|a - b| = max - min), partial sums over `block` rays (block * range < 2^16 mm: 6 rays at
/// 10 m) widened into 32-bit sums; vectorised over cells, with an AVX2 clone where the CPU has it.
#if defined(__GNUC__) && defined(__x86_64__) && !defined(__clang__)
__attribute__((target_clones("avx2", "default")))
#endif
void l1_tile(const std::uint16_t* volume, std::size_t N, std::size_t first, int T, int stride, int D,
             const std::uint16_t* rays_mm, std::uint16_t clip_mm, bool clip, int block, std::int32_t* acc,
             std::uint16_t* part) {
  const int kBlock = block;
  for (int o = 0; o < D; ++o) {
    std::int32_t* a = acc + static_cast<std::size_t>(o) * stride;
    for (int t = 0; t < T; ++t) a[t] = 0;
    for (int i0 = 0; i0 < D; i0 += kBlock) {
      for (int t = 0; t < T; ++t) part[t] = 0;
      for (int i = i0; i < std::min(D, i0 + kBlock); ++i) {
        const std::uint16_t* p = volume + static_cast<std::size_t>((o + i) % D) * N + first;
        const std::uint16_t r = rays_mm[i];
        if (clip) {
          for (int t = 0; t < T; ++t) {
            const std::uint16_t v = p[t] < clip_mm ? p[t] : clip_mm;
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



/// The scoring loop of both outputs: every stored cell, one task per grid row (its cells are a
/// contiguous index range), tiles of tile_cells(D) cells. on_row(row) runs first in each row's
/// task; consume(first, n, o, scores) then receives exp(-L1 / lambda) of orientation o for the
/// stored cells first..first+n-1. Adds the thread CPU seconds of the L1 sums and of exp + consume,
/// summed over workers, to l1_s and exp_s.
template <class OnRow, class Consume>
void score_all_cells(const DistanceVolume& volume, const std::vector<std::int64_t>& row_start,
                     const std::vector<std::uint16_t>& rays_mm, std::uint16_t clip_mm, bool clip, int block, float k,
                     OnRow&& on_row, Consume&& consume, double& l1_s, double& exp_s) {
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
      l1_tile(volume.mm.data(), volume.num_cells(), first, n, T, D, rays_mm.data(), clip_mm, clip, block,
              s.acc.data(), s.part.data());
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

nlohmann::ordered_json RayMatcherParams::to_json() const {
  nlohmann::ordered_json j;
  j["resolution_m"] = resolution_m;
  j["grid_margin_m"] = grid_margin_m;
  j["num_directions"] = num_directions;
  j["max_range_m"] = max_range_m;
  j["lambda_m"] = lambda_m;
  j["ray_source"] = enum_name(ray_source, kRaySourceNames);
  write_blocking(j, blocking);
  return j;
}

void RayMatcherParams::apply_overrides(const nlohmann::json& overrides) {
  ParamReader r(overrides, "matcher ray");
  r.read("resolution_m", resolution_m, 0.01, 1.0);
  r.read("grid_margin_m", grid_margin_m, 0.0, 100.0);
  r.read("num_directions", num_directions, 4, 3600);
  r.read("max_range_m", max_range_m, 0.1, 65.0);
  r.read("lambda_m", lambda_m, 1e-6, 1e9);
  r.read_enum("ray_source", ray_source, kRaySourceNames);
  read_blocking(r, blocking);
  r.finish();
}

void RayMatcherParams::apply_shared(const SharedParams& shared) {
  max_range_m = shared.range_m;
  blocking = shared.blocking;
}

DistanceVolume RayMatcher::compute_volume(const FloorPlan& plan, const RayMatcherParams& params) {
  const GridSpec grid = grid_for_plan(plan, params.resolution_m, params.grid_margin_m);
  // Refused before the volume is allocated: cell index, stored cells and their D 16-bit
  // distances, and the D float posterior slices of a match (every cell counted as valid).
  check_limit("max_rays", params.num_directions, "matcher ray: num_directions", "rays");
  check_raster_budget(grid, 8.0 + 6.0 * params.num_directions, "matcher ray");
  const std::vector<Segment2> outline = outline_segments(blocking_outline(plan, params.blocking));
  const cv::Mat valid = matcher_valid_mask(plan, grid, params.blocking);
  return compute_distance_volume(outline, grid, valid, params.num_directions, params.max_range_m);
}

std::string RayMatcher::volume_key(const FloorPlan& plan, const RayMatcherParams& params) {
  nlohmann::ordered_json k = params.to_json();
  k.erase("lambda_m");
  k.erase("ray_source");
  k["plan_hash"] = hex64(plan_hash(plan));
  k["algorithm"] = "zbuffer-parallelogram-v1";
  return k.dump();
}

RayMatcher::RayMatcher(const FloorPlan& plan, const RayMatcherParams& params) : params_(params) {
  const auto t0 = Clock::now();
  volume_ = compute_volume(plan, params_);
  index_rows();
  precompute_s_ = seconds(t0, Clock::now());
}

RayMatcher::RayMatcher(const FloorPlan& plan, const RayMatcherParams& params, DistanceVolume volume)
    : params_(params), volume_(std::move(volume)) {
  const auto t0 = Clock::now();
  const GridSpec grid = grid_for_plan(plan, params_.resolution_m, params_.grid_margin_m);
  if (!(volume_.grid == grid) || volume_.num_directions != params_.num_directions ||
      volume_.max_range_m != params_.max_range_m) {
    throw InputError("ray matcher: the given distance volume was computed for another plan grid, direction count "
                     "or range than these parameters");
  }
  index_rows();
  precompute_s_ = seconds(t0, Clock::now());
}

void RayMatcher::index_rows() {
  // First stored cell of every grid row (cells are sorted row-major).
  const GridSpec& vg = volume_.grid;
  row_start_.assign(static_cast<std::size_t>(vg.height_px) + 1, 0);
  std::size_t i = 0;
  for (int r = 0; r <= vg.height_px; ++r) {
    const std::int64_t first_lin = static_cast<std::int64_t>(r) * vg.width_px;
    while (i < volume_.cells.size() && volume_.cells[i] < first_lin) ++i;
    row_start_[static_cast<std::size_t>(r)] = static_cast<std::int64_t>(i);
  }
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

MatchResult RayMatcher::match(const Observation2D& obs, const MatchRequest& request) const {
  const auto t0 = Clock::now();
  MatchResult result;
  const int D = params_.num_directions;
  const std::vector<double> rays = observation_rays(obs);
  // Both sides are clipped at the smaller of the volume's and the observation's range.
  const double clip_m = std::min(volume_.max_range_m, obs.max_range_m > 0.0 ? obs.max_range_m : volume_.max_range_m);
  const std::uint16_t clip_mm = static_cast<std::uint16_t>(std::min<long>(std::lround(clip_m * 1000.0), 65535));
  const bool clip = clip_mm < std::lround(volume_.max_range_m * 1000.0);
  // Rays per 16-bit partial sum (see l1_tile).
  const int block = std::max(1, 65535 / std::max<int>(1, clip_mm));
  std::vector<std::uint16_t> rays_mm(static_cast<std::size_t>(D));
  for (int i = 0; i < D; ++i) {
    rays_mm[static_cast<std::size_t>(i)] = static_cast<std::uint16_t>(
        std::min<long>(clip_mm, std::lround(rays[static_cast<std::size_t>(i)] * 1000.0)));
  }
  const auto t1 = Clock::now();
  if (request.output != MatchOutput::kPosterior) {
    match_modes(rays_mm, clip_mm, clip, block, request, result);
    result.stage_s["observation_rays"] = seconds(t0, t1);
    result.match_s = seconds(t0, Clock::now());
    return result;
  }

  Posterior& post = result.posterior;
  const GridSpec& g = volume_.grid;
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

  const float k = static_cast<float>(1e-3 / params_.lambda_m);
  const std::size_t W = static_cast<std::size_t>(g.width_px);
  double l1_s = 0.0, exp_s = 0.0;
  // The row of every slice is written once, front to back (0 where no cell is stored).
  score_all_cells(
      volume_, row_start_, rays_mm, clip_mm, clip, block, k,
      [&](int row) {
        const std::size_t row_offset = static_cast<std::size_t>(row) * W;
        for (int o = 0; o < D; ++o) std::memset(slices[static_cast<std::size_t>(o)] + row_offset, 0, W * sizeof(float));
      },
      [&](std::size_t first, int n, int o, const float* score) {
        const std::int32_t* cells = volume_.cells.data() + first;
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
  result.stage_s["modes"] = seconds(t3, Clock::now());
  result.match_s = seconds(t0, Clock::now());
  return result;
}

void RayMatcher::match_modes(const std::vector<std::uint16_t>& rays_mm, std::uint16_t clip_mm, bool clip, int block,
                             const MatchRequest& request, MatchResult& result) const {
  // The estimate, top-K modes and max-over-yaw map without the D x H x W posterior (which costs
  // ~200 MB per office-sized match, its first touch dominating the time): one pass keeps each
  // stored cell's best orientation; the greedy suppression of Posterior::top_k then needs the
  // full orientation vector only of the few cells within the separation of a chosen mode, which
  // is recomputed with the same arithmetic (same L1 sums, same exp), so the modes are those
  // top_k finds on the full posterior, ties broken the same way (lowest slice, then row-major).
  const int D = params_.num_directions;
  const GridSpec& g = volume_.grid;
  const std::size_t N = volume_.num_cells();
  const float k = static_cast<float>(1e-3 / params_.lambda_m);
  std::vector<float> best(N, 0.0f);
  std::vector<std::uint16_t> best_o(N, 0);
  const auto t0 = Clock::now();
  double l1_s = 0.0, exp_s = 0.0;
  score_all_cells(
      volume_, row_start_, rays_mm, clip_mm, clip, block, k, [](int) {},
      [&](std::size_t first, int n, int o, const float* score) {
        for (int t = 0; t < n; ++t) {
          const std::size_t i = first + static_cast<std::size_t>(t);
          if (score[t] > best[i]) {  // strict: the lowest slice wins ties
            best[i] = score[t];
            best_o[i] = static_cast<std::uint16_t>(o);
          }
        }
      },
      l1_s, exp_s);
  result.stage_s["l1_distances"] = l1_s;
  result.stage_s["exp_best_orientation"] = exp_s;
  const auto t1 = Clock::now();
  result.grid = g;
  const std::size_t W = static_cast<std::size_t>(g.width_px);
  if (request.output == MatchOutput::kMaxOverYaw) {
    result.max_over_yaw = cv::Mat::zeros(g.height_px, g.width_px, CV_32F);
    float* m = result.max_over_yaw.ptr<float>();
    for (std::size_t i = 0; i < N; ++i) m[static_cast<std::size_t>(volume_.cells[i])] = best[i];
  }

  // Greedy suppression on the per-cell best over the live orientations.
  auto yaw_of = [&](int o) { return 2.0 * kPi * o / D; };
  std::map<std::size_t, std::vector<float>> full;     // all D scores of cells touched by a suppression
  std::map<std::size_t, std::vector<std::uint8_t>> dead;
  std::vector<std::int32_t> acc1(static_cast<std::size_t>(D));
  std::vector<std::uint16_t> part1(1);
  auto scores_of = [&](std::size_t i) -> const std::vector<float>& {
    auto it = full.find(i);
    if (it != full.end()) return it->second;
    l1_tile(volume_.mm.data(), N, i, 1, 1, D, rays_mm.data(), clip_mm, clip, block, acc1.data(), part1.data());
    std::vector<float> v(static_cast<std::size_t>(D));
    for (int o = 0; o < D; ++o) exp_neg_scaled(acc1.data() + o, 1, k, &v[static_cast<std::size_t>(o)]);
    return full.emplace(i, std::move(v)).first->second;
  };
  const double res = g.resolution_m_per_px;
  const int rad = static_cast<int>(std::floor(request.mode_separation_m / res + 1e-9));
  while (static_cast<int>(result.modes.size()) < request.top_k) {
    std::size_t bi = N;
    for (std::size_t i = 0; i < N; ++i) {
      const float v = best[i];
      if (v <= 0.0f) continue;
      if (bi == N || v > best[bi] || (v == best[bi] && best_o[i] < best_o[bi])) bi = i;
    }
    if (bi == N) break;
    const int lin = volume_.cells[bi];
    const int br = lin / g.width_px, bc = lin % g.width_px, bo = best_o[bi];
    PoseHypothesis h;
    const Vec2 p = g.cell_center_m(br, bc);
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
      const auto rb = volume_.cells.begin() + row_start_[static_cast<std::size_t>(r)];
      const auto re = volume_.cells.begin() + row_start_[static_cast<std::size_t>(r) + 1];
      for (int c = std::max(0, bc - rad - 1); c <= std::min(g.width_px - 1, bc + rad + 1); ++c) {
        const double dx = (c - bc) * res, dy = (r - br) * res;
        if (!(std::sqrt(dx * dx + dy * dy) <= request.mode_separation_m + 1e-12)) continue;
        const std::int32_t want = static_cast<std::int32_t>(static_cast<std::size_t>(r) * W + static_cast<std::size_t>(c));
        const auto it = std::lower_bound(rb, re, want);
        if (it == re || *it != want) continue;
        const std::size_t i = static_cast<std::size_t>(it - volume_.cells.begin());
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
  result.stage_s["modes"] = seconds(t1, Clock::now());
  result.stage_s["scores"] = seconds(t0, t1);
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
