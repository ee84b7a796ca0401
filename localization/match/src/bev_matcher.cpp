#include "floorcast/match/bev_matcher.hpp"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>

#include "floorcast/core/limits.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/core/timing.hpp"
#include "floorcast/match/plan_raster.hpp"

namespace floorcast {
namespace {

using Clock = std::chrono::steady_clock;
double seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

const std::vector<std::pair<const char*, BevLikelihood>> kLikelihoodNames = {{"mean", BevLikelihood::kMean},
                                                                             {"exp", BevLikelihood::kExp}};
const std::vector<std::pair<const char*, BevSearch>> kSearchNames = {
    {"auto", BevSearch::kAuto}, {"bounded", BevSearch::kBounded}, {"exhaustive", BevSearch::kExhaustive}};
const std::vector<std::pair<const char*, BevPeaks>> kPeakNames = {{"suppression", BevPeaks::kSuppression},
                                                                  {"max_filter", BevPeaks::kMaxFilter}};

/// Stored cells per tile of the scoring loop.
constexpr int kTileCells = 256;

/// Direction index (0..A-1) nearest an angle.
int nearest_direction(double angle_rad, int A) {
  // floor(x + 1/2), not lround: shifting the angle by whole directions shifts the result alike.
  const long k = static_cast<long>(std::floor(angle_rad * A / (2.0 * kPi) + 0.5));
  return static_cast<int>(((k % A) + A) % A);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Parameters

const FieldList<BevMatcherParams>& BevMatcherParams::fields() {
  using P = BevMatcherParams;
  static const FieldList<P> f =
      FieldList<P>("matcher bev")
          .number("resolution_m", &P::resolution_m, 0.01, 1.0, "grid resolution of the semantic volume, m (the thesis: 0.2)")
          .number("grid_margin_m", &P::grid_margin_m, 0.0, 100.0, "free margin of the grid around the plan, m")
          .integer("num_orientations", &P::num_orientations, 4, 3600, "orientations of the posterior (the thesis: 36, 10 deg)")
          .integer("num_directions", &P::num_directions, 4, 3600,
                   "directions the plan is rendered along, a multiple of num_orientations (angular resolution of the rendered BEV)")
          .integer("depth_bins", &P::depth_bins, 1, kMaxSemanticBins,
                   "log-spaced depth bins from min_depth_m to max_range_m (the observation's BEV must have the same)")
          .number("min_depth_m", &P::min_depth_m, 0.01, 100.0, "first depth bin edge, m")
          .number("max_range_m", &P::max_range_m, 0.1, 1000.0, "last depth bin edge, m (default: the shared range)")
          .flag("semantics", &P::semantics,
                "wall, window, door, empty with doors and windows passing rays (the thesis); false: occupied, empty, "
                "doors removed (Table 4.3 without semantics)")
          .choice("likelihood", &P::likelihood, kLikelihoodNames, "mean: Eq. 3.3 as is; exp: exp(-(1 - L) / temperature)")
          .number("temperature", &P::temperature, 1e-6, 1e6, "temperature of the exp likelihood")
          .choice("search", &P::search, kSearchNames,
                  "modes by the exact bounded block search, exhaustively, or auto: bounded unless, once 2% of the pairs are "
                  "scored, it predicts more than auto_exhaustive_share of them to score")
          .number("auto_exhaustive_share", &P::auto_exhaustive_share, 0.0, 1.0,
                  "search auto: the predicted share of (block, orientation) pairs above which the exhaustive search runs")
          .choice("peaks", &P::peaks, kPeakNames,
                  "top-K by greedy suppression at the request's separation, or the thesis' maximum filter (sec. 5.3)")
          .number("peak_window_m", &P::peak_window_m, 0.0, 100.0, "max_filter extent, m (the thesis: 5 cells of 0.2 m = 1)")
          .number("peak_window_deg", &P::peak_window_deg, 0.0, 360.0, "max_filter extent, deg (the thesis: 3 x 10 deg = 30)")
          .flatten(&P::blocking, blocking_fields())
          .check([](const P& p, const ParamReader& r) {
            if (p.num_directions % p.num_orientations != 0) {
              r.fail("num_directions", "must be a multiple of num_orientations (" + std::to_string(p.num_orientations) + ")");
            }
            if (!(p.min_depth_m < p.max_range_m)) r.fail("min_depth_m", "must be below max_range_m");
          });
  return f;
}

nlohmann::ordered_json BevMatcherParams::to_json() const { return fields().write(*this); }

void BevMatcherParams::apply_overrides(const nlohmann::json& overrides) { fields().read(*this, overrides); }

void BevMatcherParams::apply_shared(const SharedParams& shared) {
  max_range_m = shared.range_m;
  blocking = shared.blocking;
}

// ---------------------------------------------------------------------------------------------
// Precomputation

SemanticVolume BevMatcher::compute_volume(const FloorPlan& plan, const BevMatcherParams& p) {
  if (p.num_directions % p.num_orientations != 0) {
    throw InputError("matcher bev: num_directions must be a multiple of num_orientations");
  }
  const GridSpec grid = grid_for_plan(plan, p.resolution_m, p.grid_margin_m);
  // Refused before anything is allocated: cell index and stored cells (8 bytes), per direction a
  // stop byte and (semantic) two crossing bytes, and a match's K float posterior slices.
  check_limit("max_rays", p.num_directions, "matcher bev: num_directions", "directions");
  check_raster_budget(grid, 8.0 + (p.semantics ? 3.0 : 1.0) * p.num_directions + 4.0 * p.num_orientations, "matcher bev");
  const BevClasses classes = p.semantics ? BevClasses::kSemantic : BevClasses::kOccupancy;
  const SemanticPlanLines lines = semantic_plan_lines(plan, classes, p.blocking.cut_height_m);
  const cv::Mat valid = matcher_valid_mask(plan, grid, p.blocking);
  return compute_semantic_volume(lines, classes, grid, valid, p.num_directions, p.bins());
}

BevMatcher::BevMatcher(const FloorPlan& plan, const BevMatcherParams& params) : params_(params) {
  const auto t0 = Clock::now();
  auto pre = std::make_shared<Precomputed>();
  pre->volume = compute_volume(plan, params_);
  index_blocks(*pre);
  pre_ = std::move(pre);
  precompute_s_ = seconds(t0, Clock::now());
}

void BevMatcher::index_blocks(Precomputed& pre) const {
  SemanticVolume& v = pre.volume;
  const GridSpec& g = v.grid;
  const int B = kBlockCells, A = v.num_directions;
  const std::size_t N = v.num_cells();
  // Stored cells block by block: a stable sort of the row-major cells by block keeps them
  // row-major within each block.
  const std::int64_t blocks_per_row = (g.width_px + B - 1) / B;
  auto block_of = [&](std::int32_t lin) {
    return static_cast<std::int64_t>(lin / g.width_px / B) * blocks_per_row + (lin % g.width_px) / B;
  };
  std::vector<std::uint32_t> perm(N);  // new index -> old index
  for (std::size_t i = 0; i < N; ++i) perm[i] = static_cast<std::uint32_t>(i);
  std::stable_sort(perm.begin(), perm.end(),
                   [&](std::uint32_t x, std::uint32_t y) { return block_of(v.cells[x]) < block_of(v.cells[y]); });
  std::vector<std::uint32_t> inverse(N);
  for (std::size_t j = 0; j < N; ++j) inverse[perm[j]] = static_cast<std::uint32_t>(j);
  {
    std::vector<std::int32_t> cells(N);
    for (std::size_t j = 0; j < N; ++j) cells[j] = v.cells[perm[j]];
    v.cells.swap(cells);
  }
  for (std::size_t j = 0; j < N; ++j) v.cell_index[static_cast<std::size_t>(v.cells[j])] = static_cast<std::int32_t>(j);
  const bool semantic = !v.crossings.empty();
  tbb::parallel_for(0, A, [&](int a) {
    const std::size_t off = static_cast<std::size_t>(a) * N;
    std::vector<std::uint8_t> st(N);
    for (std::size_t j = 0; j < N; ++j) st[j] = v.stop[off + perm[j]];
    std::copy(st.begin(), st.end(), v.stop.begin() + static_cast<std::ptrdiff_t>(off));
    if (semantic) {
      std::vector<std::uint16_t> cr(N);
      for (std::size_t j = 0; j < N; ++j) cr[j] = v.crossings[off + perm[j]];
      std::copy(cr.begin(), cr.end(), v.crossings.begin() + static_cast<std::ptrdiff_t>(off));
    }
  });
  // Overflow keys (cell, direction) renumbered; same-key entries keep their order.
  for (auto& o : v.overflow) o.first = static_cast<std::uint64_t>(inverse[o.first / A]) * A + o.first % A;
  std::stable_sort(v.overflow.begin(), v.overflow.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  for (std::size_t j = 0; j < N;) {
    const std::int64_t blk = block_of(v.cells[j]);
    std::size_t e = j + 1;
    while (e < N && block_of(v.cells[e]) == blk) ++e;
    pre.block_range.emplace_back(static_cast<std::int64_t>(j), static_cast<int>(e - j));
    j = e;
  }

  const std::size_t NB = pre.block_range.size();
  pre.block_stop_lo.assign(NB * static_cast<std::size_t>(A), 255);
  pre.block_stop_hi.assign(NB * static_cast<std::size_t>(A), 0);
  if (semantic) {
    pre.block_doors.assign(NB * static_cast<std::size_t>(A), 0);
    pre.block_windows.assign(NB * static_cast<std::size_t>(A), 0);
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, NB, 16), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t b = range.begin(); b != range.end(); ++b) {
      auto mark = [&](int a, std::uint8_t byte) {
        if (!(byte & 0x80)) return;
        std::uint64_t& m = (byte & 0x40) ? pre.block_windows[b * A + static_cast<std::size_t>(a)]
                                         : pre.block_doors[b * A + static_cast<std::size_t>(a)];
        m |= std::uint64_t{1} << (byte & 0x3f);
      };
      const auto [first, n] = pre.block_range[b];
      for (int a = 0; a < A; ++a) {
        std::uint8_t lo = 255, hi = 0;
        const std::uint8_t* st = v.stop.data() + static_cast<std::size_t>(a) * N + static_cast<std::size_t>(first);
        for (int j = 0; j < n; ++j) {
          lo = std::min(lo, st[j]);
          hi = std::max(hi, st[j]);
        }
        if (semantic) {
          const std::uint16_t* cr = v.crossings.data() + static_cast<std::size_t>(a) * N + static_cast<std::size_t>(first);
          for (int j = 0; j < n; ++j) {
            mark(a, static_cast<std::uint8_t>(cr[j] & 0xff));
            mark(a, static_cast<std::uint8_t>(cr[j] >> 8));
          }
        }
        pre.block_stop_lo[b * A + static_cast<std::size_t>(a)] = lo;
        pre.block_stop_hi[b * A + static_cast<std::size_t>(a)] = hi;
      }
      if (!semantic || v.overflow.empty()) continue;
      const std::uint64_t k0 = static_cast<std::uint64_t>(first) * A;
      const std::uint64_t k1 = static_cast<std::uint64_t>(first + n) * A;
      for (auto it = std::lower_bound(v.overflow.begin(), v.overflow.end(), std::make_pair(k0, std::uint8_t{0}));
           it != v.overflow.end() && it->first < k1; ++it) {
        mark(static_cast<int>(it->first % A), it->second);
      }
    }
  });
}

BevMatcher::BevMatcher(const BevMatcher& other, const BevMatcherParams& params) : params_(params), pre_(other.pre_) {
  nlohmann::ordered_json a = params.to_json(), b = other.params_.to_json();
  for (const char* k : {"likelihood", "temperature", "search", "auto_exhaustive_share", "peaks", "peak_window_m", "peak_window_deg"}) {
    a.erase(k);
    b.erase(k);
  }
  if (a != b) {
    throw InputError("bev matcher: cannot share the semantic volume of a matcher with other volume parameters (" +
                     b.dump() + " vs " + a.dump() + ")");
  }
}

BevMatcher::~BevMatcher() = default;

std::size_t BevMatcher::precompute_bytes() const {
  // The volume and the bounded search's block index (ranges, stop ranges, crossing masks).
  return pre_->volume.bytes() + pre_->block_range.size() * sizeof(pre_->block_range[0]) + pre_->block_stop_lo.size() +
         pre_->block_stop_hi.size() + (pre_->block_doors.size() + pre_->block_windows.size()) * sizeof(std::uint64_t);
}

// ---------------------------------------------------------------------------------------------
// Scoring

/// Per observation: each column's tables of Eq. 3.3 in the volume's codes. Column w's
/// contribution at a cell and direction is E_w + tstop[w][stop] + tx[w][crossing bytes], with
/// E_w = sum_d B[w, d, empty] and T[w](c, d) = B[w, d, c] - B[w, d, empty] for a marked bin.
struct BevMatcher::Tables {
  int W = 0, K = 0, A = 0, step = 1;
  std::vector<int> offset;   ///< direction of column w at orientation 0
  double base = 0.0;         ///< sum_w E_w
  std::vector<float> tstop;  ///< W x 256: stop code -> T(wall or occupied, bin); code D -> 0
  std::vector<float> tx;     ///< W x 256: crossing byte -> T(door or window, bin); 0 -> 0
  float scale = 1.0f;        ///< 1 / (D W)
  BevLikelihood likelihood = BevLikelihood::kMean;
  float inv_temperature = 1.0f;
  /// Bounds (bounded search): rm[w][lo * (D + 1) + hi] = max of tstop[w][lo..hi]; the positive
  /// parts of the crossing entries per bin, door (pos[w][d]) and window (pos[w][64 + d]).
  int D = 0;
  std::vector<float> rm;
  std::vector<float> pos;
};

const BevPrediction* BevMatcher::observation_bev(const Observation2D& obs) const {
  const BevClasses want = params_.semantics ? BevClasses::kSemantic : BevClasses::kOccupancy;
  for (const BevPrediction& b : obs.bev) {
    if (b.classes == want) return &b;
  }
  return nullptr;
}

BevMatcher::Tables BevMatcher::tables(const BevPrediction& bev) const {
  const SemanticVolume& v = pre_->volume;
  if (!(bev.bins == v.bins)) {
    throw InputError("matcher bev: the observation's BEV has " + std::to_string(bev.bins.count) + " depth bins over [" +
                     std::to_string(bev.bins.min_m) + ", " + std::to_string(bev.bins.max_m) + ") m but the matcher " +
                     std::to_string(v.bins.count) + " over [" + std::to_string(v.bins.min_m) + ", " +
                     std::to_string(v.bins.max_m) + ") m (matcher parameters depth_bins, min_depth_m, max_range_m)");
  }
  bev.check("matcher bev: observation BEV");
  Tables t;
  t.W = bev.num_columns();
  t.K = params_.num_orientations;
  t.A = v.num_directions;
  t.step = t.A / t.K;
  const int D = v.bins.count, C = bev.num_classes(), empty = bev_empty_class(bev.classes);
  const int stop_class = params_.semantics ? kBevWall : kBevOccupied;
  t.offset.resize(static_cast<std::size_t>(t.W));
  t.tstop.assign(static_cast<std::size_t>(t.W) * 256, 0.0f);
  t.tx.assign(static_cast<std::size_t>(t.W) * 256, 0.0f);
  double base = 0.0;
  for (int w = 0; w < t.W; ++w) {
    t.offset[static_cast<std::size_t>(w)] = nearest_direction(bev.column_azimuth_rad[static_cast<std::size_t>(w)], t.A);
    float* ts = t.tstop.data() + static_cast<std::size_t>(w) * 256;
    float* tx = t.tx.data() + static_cast<std::size_t>(w) * 256;
    for (int d = 0; d < D; ++d) {
      const float pe = bev.p(w, d, empty);
      base += pe;
      ts[d] = bev.p(w, d, stop_class) - pe;
      if (C == 4) {
        tx[semantic_crossing_byte(false, d)] = bev.p(w, d, kBevDoor) - pe;
        tx[semantic_crossing_byte(true, d)] = bev.p(w, d, kBevWindow) - pe;
      }
    }
  }
  t.base = base;
  t.scale = static_cast<float>(1.0 / (static_cast<double>(D) * t.W));
  if (params_.search != BevSearch::kExhaustive) {
    t.D = D;
    const std::size_t D1 = static_cast<std::size_t>(D) + 1;
    t.rm.assign(static_cast<std::size_t>(t.W) * D1 * D1, 0.0f);
    t.pos.assign(static_cast<std::size_t>(t.W) * 128, 0.0f);
    for (int w = 0; w < t.W; ++w) {
      const float* ts = t.tstop.data() + static_cast<std::size_t>(w) * 256;
      float* rm = t.rm.data() + static_cast<std::size_t>(w) * D1 * D1;
      for (std::size_t lo = 0; lo < D1; ++lo) {
        float m = ts[lo];
        for (std::size_t hi = lo; hi < D1; ++hi) {
          m = std::max(m, ts[hi]);
          rm[lo * D1 + hi] = m;
        }
      }
      const float* tx = t.tx.data() + static_cast<std::size_t>(w) * 256;
      float* pos = t.pos.data() + static_cast<std::size_t>(w) * 128;
      for (int d = 0; d < D && C == 4; ++d) {
        pos[d] = std::max(0.0f, tx[semantic_crossing_byte(false, d)]);
        pos[64 + d] = std::max(0.0f, tx[semantic_crossing_byte(true, d)]);
      }
    }
  }
  t.likelihood = params_.likelihood;
  t.inv_temperature = static_cast<float>(1.0 / params_.temperature);
  return t;
}

/// out[j] = the score of stored cell first + j at orientation k (j < n <= kTileCells). One fixed
/// order of additions per cell and orientation, whatever the tile or the orientations scored with
/// it: the bounded search and the posterior get the same bits.
void BevMatcher::score_orientation(const Tables& t, std::size_t first, int n, int k, float* out) const {
  const SemanticVolume& v = pre_->volume;
  const std::size_t N = v.num_cells();
  const bool semantic = !v.crossings.empty();
  const float base = static_cast<float>(t.base);
  for (int j = 0; j < n; ++j) out[j] = base;
  int a0 = k * t.step;
  if (n <= 64) {
    // A block of the bounded search: its W direction rows are scattered over the volume, so their
    // cache lines are requested before they are read.
    for (int w = 0; w < t.W; ++w) {
      const int a = (a0 + t.offset[static_cast<std::size_t>(w)]) % t.A;
      __builtin_prefetch(v.stop.data() + static_cast<std::size_t>(a) * N + first);
      if (semantic) {
        const std::uint16_t* cr = v.crossings.data() + static_cast<std::size_t>(a) * N + first;
        __builtin_prefetch(cr);
        __builtin_prefetch(cr + n - 1);
      }
    }
  }
  for (int w = 0; w < t.W; ++w) {
    const int a = (a0 + t.offset[static_cast<std::size_t>(w)]) % t.A;
    const std::uint8_t* st = v.stop.data() + static_cast<std::size_t>(a) * N + first;
    const float* ts = t.tstop.data() + static_cast<std::size_t>(w) * 256;
    for (int j = 0; j < n; ++j) out[j] += ts[st[j]];
    if (semantic) {
      const std::uint16_t* cr = v.crossings.data() + static_cast<std::size_t>(a) * N + first;
      std::uint16_t any = 0;
      for (int j = 0; j < n; ++j) any |= cr[j];
      if (!any) continue;  // x + (0 + 0) == x: nothing to add
      const float* tx = t.tx.data() + static_cast<std::size_t>(w) * 256;
      // Branch-free: tx[0] = 0, and x + (0 + 0) == x.
      for (int j = 0; j < n; ++j) out[j] += tx[cr[j] & 0xff] + tx[cr[j] >> 8];
    }
  }
  // Crossings beyond the second: cell-major, so one range per tile.
  if (!v.overflow.empty()) {
    const std::uint64_t A = static_cast<std::uint64_t>(t.A);
    auto it = std::lower_bound(v.overflow.begin(), v.overflow.end(), std::make_pair(first * A, std::uint8_t{0}));
    for (; it != v.overflow.end() && it->first < (first + static_cast<std::size_t>(n)) * A; ++it) {
      const std::size_t j = static_cast<std::size_t>(it->first / A) - first;
      const int a = static_cast<int>(it->first % A);
      for (int w = 0; w < t.W; ++w) {
        const int rel = ((a - t.offset[static_cast<std::size_t>(w)]) % t.A + t.A) % t.A;
        if (rel % t.step || rel / t.step != k) continue;
        out[j] += t.tx[static_cast<std::size_t>(w) * 256 + it->second];
      }
    }
  }
  if (t.likelihood == BevLikelihood::kMean) {
    for (int j = 0; j < n; ++j) out[j] = std::max(0.0f, out[j] * t.scale);
  } else {
    for (int j = 0; j < n; ++j) out[j] = std::exp(-(1.0f - out[j] * t.scale) * t.inv_temperature);
  }
}

/// out[k * n + j] = the score of stored cell first + j at orientation k (k < K).
void BevMatcher::score_tile(const Tables& t, std::size_t first, int n, float* out) const {
  for (int k = 0; k < t.K; ++k) score_orientation(t, first, n, k, out + static_cast<std::size_t>(k) * n);
}

MatchResult BevMatcher::match(const Observation2D& obs, const MatchRequest& request) const {
  const auto t0 = Clock::now();
  MatchResult result;
  const SemanticVolume& v = pre_->volume;
  const GridSpec& g = v.grid;
  const int K = params_.num_orientations;
  const BevPrediction* bev = observation_bev(obs);
  Posterior& post = result.posterior;
  post.grid = g;
  result.grid = g;
  // The full posterior is made only when it is needed (campus: 5 MB per orientation).
  const bool max_filter = params_.peaks == BevPeaks::kMaxFilter;
  const bool bounded = request.output == MatchOutput::kModes && params_.search != BevSearch::kExhaustive && !max_filter;
  auto allocate = [&] {
    post.yaw_rad.resize(static_cast<std::size_t>(K));
    post.scores.resize(static_cast<std::size_t>(K));
    for (int k = 0; k < K; ++k) {
      post.yaw_rad[static_cast<std::size_t>(k)] = 2.0 * kPi * k / K;
      post.scores[static_cast<std::size_t>(k)] = cv::Mat::zeros(g.height_px, g.width_px, CV_32F);
    }
  };
  if (!bev) {
    result.counters["bev_missing"] = 1.0;
    if (request.output != MatchOutput::kModes) allocate();
    finish_from_posterior(result, request);
    result.match_s = seconds(t0, Clock::now());
    return result;
  }
  const Tables t = tables(*bev);
  if (bounded) {
    result.stage_s["tables"] = seconds(t0, Clock::now());
    if (match_modes(t, request, result, params_.search == BevSearch::kAuto)) {
      result.counters["search_exhaustive"] = 0.0;
      result.match_s = seconds(t0, Clock::now());
      return result;
    }
  }
  if (request.output == MatchOutput::kModes && !max_filter) result.counters["search_exhaustive"] = 1.0;
  allocate();
  const auto t1 = Clock::now();
  std::vector<float*> slices(static_cast<std::size_t>(K));
  for (int k = 0; k < K; ++k) slices[static_cast<std::size_t>(k)] = post.scores[static_cast<std::size_t>(k)].ptr<float>();
  tbb::enumerable_thread_specific<std::vector<float>> scratch;
  const std::size_t N = v.num_cells();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, (N + kTileCells - 1) / kTileCells), [&](const tbb::blocked_range<std::size_t>& range) {
    std::vector<float>& s = scratch.local();
    s.resize(static_cast<std::size_t>(K) * kTileCells);
    for (std::size_t tile = range.begin(); tile != range.end(); ++tile) {
      const std::size_t first = tile * kTileCells;
      const int n = static_cast<int>(std::min<std::size_t>(kTileCells, N - first));
      score_tile(t, first, n, s.data());
      for (int k = 0; k < K; ++k) {
        float* dst = slices[static_cast<std::size_t>(k)];
        for (int j = 0; j < n; ++j) dst[v.cells[first + static_cast<std::size_t>(j)]] = s[static_cast<std::size_t>(k) * n + j];
      }
    }
  });
  const auto t2 = Clock::now();
  // The thesis' peaks instead of the greedy suppression (found before the slices may go).
  std::vector<PoseHypothesis> peaks;
  if (max_filter) {
    const double res = g.resolution_m_per_px;
    const int half_cells = std::max(0, static_cast<int>(std::floor((params_.peak_window_m / res - 1.0) / 2.0 + 1e-9)));
    const int half_slices = std::max(0, static_cast<int>(std::floor((params_.peak_window_deg * K / 360.0 - 1.0) / 2.0 + 1e-9)));
    peaks = post.maximum_filter_peaks(request.top_k, half_cells, half_slices);
  }
  finish_from_posterior(result, request);
  if (max_filter) result.modes = std::move(peaks);
  result.stage_s["tables"] = seconds(t0, t1) - (bounded ? result.stage_s["bounded_until_switch"] : 0.0);
  result.stage_s["scores"] = seconds(t1, t2);
  result.stage_s["modes"] = seconds(t2, Clock::now());
  result.match_s = seconds(t0, Clock::now());
  return result;
}

bool BevMatcher::match_modes(const Tables& t, const MatchRequest& request, MatchResult& result, bool may_switch) const {
  // Exact best-first search over (block, orientation) pairs. A pair's bound adds, per column, the
  // largest table entry over its block's stop codes (the range [lo, hi] holds every cell's code)
  // and the positive entries of every bin where one of its cells has a crossing: each cell's sum
  // is at most that, since its marked bins are distinct. Greedy suppression (Posterior::top_k)
  // picks as mode i the best candidate not within the separation of modes 1..i-1; it is found
  // among the scored pairs once every pair whose bound reaches it is scored, so pairs are scored
  // in descending order of their bounds until none left reaches the best live candidate. Each
  // scored pair keeps only its best live candidate; a new mode makes those near it stale and their
  // pairs are scored again. No candidate pool: a flat posterior (a 60 deg view in a large
  // building) has hundreds of thousands of candidates near the top.
  const auto t0 = Clock::now();
  const SemanticVolume& v = pre_->volume;
  const GridSpec& g = v.grid;
  const int K = t.K, W = t.W, A = t.A, D1 = t.D + 1;
  const std::size_t NB = pre_->block_range.size();
  const std::size_t NU = NB * static_cast<std::size_t>(K);
  const bool semantic = !v.crossings.empty();
  result.grid = g;
  auto transform = [&](double acc) {
    return t.likelihood == BevLikelihood::kMean ? std::max(0.0, acc * t.scale)
                                                : std::exp(-(1.0 - acc * t.scale) * t.inv_temperature);
  };
  // Float sums of up to 3 W terms of magnitude <= D: bounds are raised by a margin above their
  // rounding before they are compared with exact scores.
  const double margin = 1e-3 + 1e-5 * t.base;
  std::vector<double> bound(NU);  // pair u = b * K + k
  // Column w at orientation k reads direction (k step + offset_w) mod A: the orientations of a
  // block are summed column by column (independent sums, no division).
  std::vector<int> dir0(static_cast<std::size_t>(W));
  for (int w = 0; w < W; ++w) dir0[static_cast<std::size_t>(w)] = t.offset[static_cast<std::size_t>(w)] % A;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, NB, 64), [&](const tbb::blocked_range<std::size_t>& range) {
    std::vector<double> ub(static_cast<std::size_t>(K));
    for (std::size_t b = range.begin(); b != range.end(); ++b) {
      std::fill(ub.begin(), ub.end(), t.base);
      const std::uint8_t* lo = pre_->block_stop_lo.data() + b * static_cast<std::size_t>(A);
      const std::uint8_t* hi = pre_->block_stop_hi.data() + b * static_cast<std::size_t>(A);
      for (int w = 0; w < W; ++w) {
        const float* rm = t.rm.data() + static_cast<std::size_t>(w) * D1 * D1;
        int a = dir0[static_cast<std::size_t>(w)];
        for (int k = 0; k < K; ++k, a = a + t.step >= A ? a + t.step - A : a + t.step) {
          ub[static_cast<std::size_t>(k)] += rm[static_cast<std::size_t>(lo[a]) * D1 + hi[a]];
        }
        if (!semantic) continue;
        const std::uint64_t* doors = pre_->block_doors.data() + b * static_cast<std::size_t>(A);
        const std::uint64_t* windows = pre_->block_windows.data() + b * static_cast<std::size_t>(A);
        const float* pos = t.pos.data() + static_cast<std::size_t>(w) * 128;
        a = dir0[static_cast<std::size_t>(w)];
        for (int k = 0; k < K; ++k, a = a + t.step >= A ? a + t.step - A : a + t.step) {
          double x = 0.0;
          for (std::uint64_t m = doors[a]; m; m &= m - 1) x += pos[__builtin_ctzll(m)];
          for (std::uint64_t m = windows[a]; m; m &= m - 1) x += pos[64 + __builtin_ctzll(m)];
          ub[static_cast<std::size_t>(k)] += x;
        }
      }
      for (int k = 0; k < K; ++k) bound[b * static_cast<std::size_t>(K) + static_cast<std::size_t>(k)] = transform(ub[static_cast<std::size_t>(k)] + margin);
    }
  });
  // Open pairs: unscored, with a positive bound (only positive scores are modes), bound kept
  // beside the index (the batch selection compares them). First the best kSeedPairs by bound
  // (one pass); the others enter once the seeds' candidates give a lower bound of the last mode,
  // and only those whose bound reaches it.
  struct OpenPair {
    double bound;
    std::uint32_t u;
  };
  auto before = [](const OpenPair& a, const OpenPair& b) { return a.bound != b.bound ? a.bound > b.bound : a.u < b.u; };
  constexpr std::size_t kSeedPairs = 64;
  constexpr double kAutoCheckShare = 0.02;
  std::vector<OpenPair> open;
  std::size_t positive = 0;
  for (std::size_t u = 0; u < NU; ++u) {
    if (!(bound[u] > 0.0)) continue;
    ++positive;
    const OpenPair p{bound[u], static_cast<std::uint32_t>(u)};
    if (open.size() < kSeedPairs) {
      open.push_back(p);
      std::push_heap(open.begin(), open.end(), before);  // front: the worst seed
    } else if (before(p, open.front())) {
      std::pop_heap(open.begin(), open.end(), before);
      open.back() = p;
      std::push_heap(open.begin(), open.end(), before);
    }
  }
  std::sort(open.begin(), open.end(), before);
  const bool rest_exists = positive > open.size();
  const OpenPair last_seed = open.empty() ? OpenPair{0.0, 0} : open.back();
  const auto t1 = Clock::now();

  struct Candidate {
    float score = -1.0f;  ///< < 0: none
    std::int32_t slice = 0, row = 0, col = 0;
    bool operator<(const Candidate& o) const {  // Posterior::top_k's order: score, slice, row, column
      if (score != o.score) return score > o.score;
      if (slice != o.slice) return slice < o.slice;
      if (row != o.row) return row < o.row;
      return col < o.col;
    }
  };
  const double res = g.resolution_m_per_px;
  const double sep_m = request.mode_separation_m + 1e-12, sep_rad = request.mode_separation_rad;
  std::vector<Candidate> modes;
  auto suppressed = [&](const Candidate& c) {
    for (const Candidate& m : modes) {
      if (angle_distance_rad(2.0 * kPi * c.slice / K, 2.0 * kPi * m.slice / K) > sep_rad) continue;
      const double dx = (c.col - m.col) * res, dy = (c.row - m.row) * res;
      if (std::sqrt(dx * dx + dy * dy) <= sep_m) return true;
    }
    return false;
  };
  // The best live (positive, not suppressed by a mode) candidate of pair u, scored afresh.
  auto best_live = [&](std::uint32_t u) {
    const std::size_t b = u / static_cast<std::uint32_t>(K);
    const int k = static_cast<int>(u % static_cast<std::uint32_t>(K));
    float s[kTileCells];
    Candidate best;
    const auto [first, n] = pre_->block_range[b];
    score_orientation(t, static_cast<std::size_t>(first), n, k, s);
    for (int j = 0; j < n; ++j) {
      if (!(s[j] > 0.0f)) continue;
      const int lin = v.cells[static_cast<std::size_t>(first) + static_cast<std::size_t>(j)];
      const Candidate c{s[j], k, lin / g.width_px, lin % g.width_px};
      if ((best.score < 0.0f || c < best) && !suppressed(c)) best = c;
    }
    return best;
  };
  // Mode i is the best live candidate: the scored pairs' best live ones, after scoring every pair
  // whose bound reaches it (in growing batches of the best open pairs). A new mode can only take
  // the best of the pairs near it: those are scored again.
  std::vector<std::uint32_t> scored;
  std::vector<Candidate> pair_best;
  std::size_t head = 0, cells_scored = 0, rounds = 0, rescored = 0, dropped = 0, opened = open.size();
  bool rest_pending = rest_exists;
  // search auto decides once kAutoCheckShare of the pairs are scored (the lower bound has risen
  // by then; the first rounds' is weak).
  bool checked = false;
  const std::size_t check_at = std::max(kSeedPairs, static_cast<std::size_t>(std::ceil(kAutoCheckShare * static_cast<double>(NU))));
  double lower = 0.0;
  double open_max = open.empty() ? -1.0 : std::numeric_limits<double>::infinity();
  double score_s = 0.0, modes_s = 0.0;
  while (static_cast<int>(modes.size()) < request.top_k) {
    const auto tm = Clock::now();
    Candidate best;
    for (const Candidate& c : pair_best) {
      if (c.score >= 0.0f && (best.score < 0.0f || c < best)) best = c;
    }
    modes_s += seconds(tm, Clock::now());
    while (head < open.size() && (best.score < 0.0f || open_max >= static_cast<double>(best.score))) {
      const auto ts = Clock::now();
      ++rounds;
      std::size_t take = std::min(open.size() - head, std::max<std::size_t>(kSeedPairs, scored.size() / 2));
      const auto first = open.begin() + static_cast<std::ptrdiff_t>(head);
      const auto nth = first + static_cast<std::ptrdiff_t>(take);
      if (nth != open.end()) std::nth_element(first, nth, open.end(), before);
      open_max = nth != open.end() ? nth->bound : -1.0;  // the best of the rest
      if (best.score >= 0.0f) {
        // Of the batch, only the pairs that can reach the best live candidate now; the others
        // stay open for later modes.
        const double need = static_cast<double>(best.score);
        const auto mid = std::partition(first, nth, [&](const OpenPair& p) { return p.bound >= need; });
        take = static_cast<std::size_t>(mid - first);
        for (auto it = mid; it != nth; ++it) open_max = std::max(open_max, it->bound);
      }
      std::vector<Candidate> found(take);
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, take, 16), [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t q = range.begin(); q != range.end(); ++q) found[q] = best_live(open[head + q].u);
      });
      for (std::size_t q = 0; q < take; ++q) {
        const std::uint32_t u = open[head + q].u;
        cells_scored += static_cast<std::size_t>(pre_->block_range[u / static_cast<std::uint32_t>(K)].second);
        scored.push_back(u);
        pair_best.push_back(found[q]);
        if (found[q].score >= 0.0f && (best.score < 0.0f || found[q] < best)) best = found[q];
      }
      head += take;
      // Lower bound of the last mode's score: K scored candidates pairwise farther apart than
      // twice the separation (in position or in yaw) are suppressed one at most per mode
      // (triangle inequality), so greedy suppression finds K modes scoring at least the lowest
      // of them. Open pairs whose bound is below it can hold no mode: they go.
      if (request.top_k > 0 && scored.size() >= static_cast<std::size_t>(request.top_k)) {
        std::vector<Candidate> sorted_best;
        sorted_best.reserve(pair_best.size());
        // Only candidates above the current lower bound can raise it: the greedy pass over them
        // picks what it picks over all of them (they come first in the order).
        for (const Candidate& c : pair_best) {
          if (c.score >= 0.0f && static_cast<double>(c.score) > lower) sorted_best.push_back(c);
        }
        std::sort(sorted_best.begin(), sorted_best.end());
        std::vector<Candidate> far;
        for (const Candidate& c : sorted_best) {
          if (static_cast<int>(far.size()) >= request.top_k) break;
          if (std::none_of(far.begin(), far.end(), [&](const Candidate& m) {
                if (angle_distance_rad(2.0 * kPi * c.slice / K, 2.0 * kPi * m.slice / K) > 2.0 * sep_rad + 1e-9) return false;
                const double dx = (c.col - m.col) * res, dy = (c.row - m.row) * res;
                return std::sqrt(dx * dx + dy * dy) <= 2.0 * sep_m + 1e-9;
              })) {
            far.push_back(c);
          }
        }
        if (static_cast<int>(far.size()) >= request.top_k && static_cast<double>(far.back().score) > lower) {
          lower = far.back().score;
          const std::size_t before_drop = open.size();
          open.erase(std::remove_if(open.begin() + static_cast<std::ptrdiff_t>(head), open.end(),
                                    [&](const OpenPair& p) { return p.bound < lower; }),
                     open.end());
          dropped += before_drop - open.size();
        }
      }
      if (rest_pending) {
        // The pairs after the seeds (pairs ordered as `before`), those that reach the lower bound.
        rest_pending = false;
        std::size_t added = 0;
        for (std::size_t u = 0; u < NU; ++u) {
          const double bu = bound[u];
          if (!(bu > 0.0) || bu < lower || !before(last_seed, OpenPair{bu, static_cast<std::uint32_t>(u)})) continue;
          open.push_back({bu, static_cast<std::uint32_t>(u)});
          open_max = std::max(open_max, bu);
          ++added;
        }
        dropped += positive - kSeedPairs - added;
        opened = kSeedPairs + added;
      }
      if (!checked && scored.size() >= check_at) {
        // search auto: the pairs scored and those still open (bound above the lower bound of the
        // last mode) are all the search can score: their share predicts its cost.
        checked = true;
        const double share = static_cast<double>(scored.size() + (open.size() - head)) / static_cast<double>(NU);
        result.counters["search_predicted_share"] = share;
        if (may_switch && share > params_.auto_exhaustive_share) {
          // The bounded part's work (scored before the switch).
          result.counters["pairs_scored"] = static_cast<double>(scored.size());
          result.counters["pairs_opened"] = static_cast<double>(opened);
          result.counters["cells_scored"] = static_cast<double>(cells_scored);
          result.counters["cells_scored_share"] =
              v.num_cells() ? static_cast<double>(cells_scored) / (static_cast<double>(v.num_cells()) * K) : 0.0;
          result.stage_s["bounded_until_switch"] = seconds(t0, Clock::now());
          return false;
        }
      }
      score_s += seconds(ts, Clock::now());
    }
    if (best.score < 0.0f) break;  // no positive score left
    const auto tr = Clock::now();
    modes.push_back(best);
    if (static_cast<int>(modes.size()) >= request.top_k) break;
    std::vector<std::size_t> stale;
    for (std::size_t q = 0; q < pair_best.size(); ++q) {
      const Candidate& c = pair_best[q];
      if (c.score < 0.0f) continue;
      if (angle_distance_rad(2.0 * kPi * c.slice / K, 2.0 * kPi * best.slice / K) > sep_rad) continue;
      const double dx = (c.col - best.col) * res, dy = (c.row - best.row) * res;
      if (std::sqrt(dx * dx + dy * dy) <= sep_m) stale.push_back(q);
    }
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, stale.size(), 8), [&](const tbb::blocked_range<std::size_t>& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) pair_best[stale[i]] = best_live(scored[stale[i]]);
    });
    rescored += stale.size();
    modes_s += seconds(tr, Clock::now());
  }
  result.modes.clear();
  for (const Candidate& c : modes) {
    PoseHypothesis h;
    const Vec2 p = g.cell_center_m(c.row, c.col);
    h.x_m = p.x();
    h.y_m = p.y();
    h.yaw_rad = 2.0 * kPi * c.slice / K;
    h.score = c.score;
    h.slice = c.slice;
    h.row = c.row;
    h.col = c.col;
    result.modes.push_back(h);
  }
  result.stage_s["bounds"] = seconds(t0, t1);
  result.stage_s["scores"] = score_s;
  result.stage_s["modes"] = modes_s;
  result.counters["pairs_scored"] = static_cast<double>(scored.size());
  result.counters["pairs_rescored"] = static_cast<double>(rescored);
  result.counters["pairs_dropped"] = static_cast<double>(dropped);
  result.counters["pairs_opened"] = static_cast<double>(opened);
  result.counters["rounds"] = static_cast<double>(rounds);
  result.counters["cells_scored"] = static_cast<double>(cells_scored);
  result.counters["cells_scored_share"] =
      v.num_cells() ? static_cast<double>(cells_scored) / (static_cast<double>(v.num_cells()) * K) : 0.0;
  if (!checked) {  // the search ended first: what it scored
    result.counters["search_predicted_share"] = NU ? static_cast<double>(scored.size()) / static_cast<double>(NU) : 0.0;
  }
  return true;
}

std::vector<double> bev_scores_reference(const SemanticVolume& v, std::size_t cell, const BevPrediction& bev,
                                         int K, BevLikelihood likelihood, double temperature) {
  const int A = v.num_directions, D = v.bins.count, W = bev.num_columns();
  std::vector<double> out(static_cast<std::size_t>(K));
  std::vector<int> cls(static_cast<std::size_t>(D));
  for (int k = 0; k < K; ++k) {
    double sum = 0.0;
    for (int w = 0; w < W; ++w) {
      const int a = nearest_direction(2.0 * kPi * k / K + bev.column_azimuth_rad[static_cast<std::size_t>(w)], A);
      v.render(cell, a, cls.data());
      for (int d = 0; d < D; ++d) sum += bev.p(w, d, cls[static_cast<std::size_t>(d)]);
    }
    const double L = sum / (static_cast<double>(D) * W);
    out[static_cast<std::size_t>(k)] = likelihood == BevLikelihood::kMean ? L : std::exp(-(1.0 - L) / temperature);
  }
  return out;
}

}  // namespace floorcast
