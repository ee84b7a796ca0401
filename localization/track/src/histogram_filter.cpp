#include "floorcast/track/histogram_filter.hpp"

#include <opencv2/imgproc.hpp>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "floorcast/core/math.hpp"
#include "floorcast/core/params.hpp"
#include "floorcast/floorplans/raster.hpp"
#include "wall_raster.hpp"

namespace floorcast {
namespace {

/// A Gaussian of sigma (in cells) centred at `shift` cells, truncated at +-ceil(3 sigma) cells
/// around its centre and normalised: out(p) = sum_j w[j] in(p + first_offset + j) moves mass by
/// +shift. Only the taps within the truncation are stored (a shift of 7 cells with sigma 1 has 7
/// taps, not the 21 of a kernel centred on 0).
/// dst[i] = sum_k w[k] src[k][i] for i < n, the terms added in k order onto 0 (onto dst[i] with
/// `accumulate`): the arithmetic of clearing dst and adding w[k] src[k] for each k in turn, bit
/// for bit (no fused multiply-add), accumulated in registers so dst is written once: the inner
/// loop of every pass of the motion step. Compiled for AVX2 and for the baseline, chosen at load
/// time (GCC function multi-versioning), so the binary runs on any x86-64 and uses 8-wide vectors
/// where the CPU has them.
#if defined(__GNUC__) && defined(__x86_64__) && !defined(__clang__)
__attribute__((target_clones("avx2", "default")))
#endif
void weighted_sum(float* dst, const float* const* src, const float* w, int terms, int n, bool accumulate) {
  // Eight floats (unaligned loads and stores through memcpy): one AVX register, two SSE ones.
  typedef float Float8 __attribute__((vector_size(32)));
  int i = 0;
  for (; i + 16 <= n; i += 16) {
    Float8 a0 = {}, a1 = {};
    if (accumulate) {
      std::memcpy(&a0, dst + i, sizeof a0);
      std::memcpy(&a1, dst + i + 8, sizeof a1);
    }
    for (int k = 0; k < terms; ++k) {
      Float8 s0, s1;
      std::memcpy(&s0, src[k] + i, sizeof s0);
      std::memcpy(&s1, src[k] + i + 8, sizeof s1);
      a0 += w[k] * s0;
      a1 += w[k] * s1;
    }
    std::memcpy(dst + i, &a0, sizeof a0);
    std::memcpy(dst + i + 8, &a1, sizeof a1);
  }
  for (; i + 8 <= n; i += 8) {
    Float8 a0 = {};
    if (accumulate) std::memcpy(&a0, dst + i, sizeof a0);
    for (int k = 0; k < terms; ++k) {
      Float8 s0;
      std::memcpy(&s0, src[k] + i, sizeof s0);
      a0 += w[k] * s0;
    }
    std::memcpy(dst + i, &a0, sizeof a0);
  }
  for (; i < n; ++i) {
    float acc = accumulate ? dst[i] : 0.0f;
    for (int k = 0; k < terms; ++k) acc += w[k] * src[k][i];
    dst[i] = acc;
  }
}

/// dst[i] *= mask[i] for i < n (the building mask after the translation), vectorised like
/// weighted_sum.
#if defined(__GNUC__) && defined(__x86_64__) && !defined(__clang__)
__attribute__((target_clones("avx2", "default")))
#endif
void multiply_by(float* dst, const float* mask, int n) {
  for (int i = 0; i < n; ++i) dst[i] *= mask[i];
}

/// One term of a weighted sum over a row: w x row[c + offset] for the output columns c in
/// [lo, hi] (the term is absent elsewhere).
struct RowTerm {
  const float* row;
  int offset;
  float w;
  int lo, hi;
};

/// dst[c] = the sum, in the terms' order, of the terms present at column c, for c in [c0, c1] (0
/// where none is): the row is cut where a term starts or ends and each piece summed with
/// weighted_sum (the same arithmetic as clearing the row and adding each term over its columns).
/// Terms beyond kMaxTerms are added by further passes in their order (the same sums).
void sum_terms(float* dst, int c0, int c1, const RowTerm* terms, int n_terms) {
  if (c0 > c1) return;
  constexpr int kMaxTerms = 32;
  for (int first = 0; first == 0 || first < n_terms; first += kMaxTerms) {
    const bool accumulate = first > 0;
    const int n = std::min(kMaxTerms, n_terms - first);
    const RowTerm* t = terms + first;
    int cuts[2 * kMaxTerms + 2];
    int n_cuts = 0;
    cuts[n_cuts++] = c0;
    cuts[n_cuts++] = c1 + 1;
    for (int k = 0; k < n; ++k) {
      if (t[k].lo > c0 && t[k].lo <= c1) cuts[n_cuts++] = t[k].lo;
      if (t[k].hi >= c0 && t[k].hi < c1) cuts[n_cuts++] = t[k].hi + 1;
    }
    std::sort(cuts, cuts + n_cuts);
    n_cuts = static_cast<int>(std::unique(cuts, cuts + n_cuts) - cuts);
    const float* src[kMaxTerms];
    float w[kMaxTerms];
    for (int q = 0; q + 1 < n_cuts; ++q) {
      const int a = cuts[q], z = cuts[q + 1] - 1;
      int m = 0;
      for (int k = 0; k < n; ++k) {
        if (t[k].lo > a || t[k].hi < z) continue;
        src[m] = t[k].row + (a + t[k].offset);
        w[m++] = t[k].w;
      }
      if (m > 0) {
        weighted_sum(dst + a, src, w, m, z - a + 1, accumulate);
      } else if (!accumulate) {
        std::fill(dst + a, dst + z + 1, 0.0f);
      }
    }
  }
}

/// Sum (in double) and maximum of row[c0 .. c1] of non-negative floats, the cells summed in eight
/// lanes by column modulo 8 (each in column order) and the lanes added in order: vectorised, and
/// the same bits whatever c0 and c1 are as long as the cells outside are 0 (the sparse filter's
/// narrower spans sum to the dense filter's full rows exactly: adding +0 is exact).
#if defined(__GNUC__) && defined(__x86_64__) && !defined(__clang__)
__attribute__((target_clones("avx2", "default")))
#endif
double row_sum_max(const float* row, int c0, int c1, float& row_max) {
  typedef float Float4 __attribute__((vector_size(16)));
  typedef double Double4 __attribute__((vector_size(32)));
  double lane[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  float mx = 0.0f;
  int c = c0;
  for (; c <= c1 && (c & 7) != 0; ++c) {
    lane[c & 7] += row[c];
    mx = std::max(mx, row[c]);
  }
  if (c + 8 <= c1 + 1) {
    Double4 lo, hi;
    std::memcpy(&lo, lane, sizeof lo);
    std::memcpy(&hi, lane + 4, sizeof hi);
    Float4 m0 = {0, 0, 0, 0}, m1 = {0, 0, 0, 0};
    for (; c + 8 <= c1 + 1; c += 8) {
      Float4 a, b;
      std::memcpy(&a, row + c, sizeof a);
      std::memcpy(&b, row + c + 4, sizeof b);
      lo += __builtin_convertvector(a, Double4);
      hi += __builtin_convertvector(b, Double4);
      m0 = m0 > a ? m0 : a;
      m1 = m1 > b ? m1 : b;
    }
    std::memcpy(lane, &lo, sizeof lo);
    std::memcpy(lane + 4, &hi, sizeof hi);
    for (int j = 0; j < 4; ++j) mx = std::max({mx, m0[j], m1[j]});
  }
  for (; c <= c1; ++c) {
    lane[c & 7] += row[c];
    mx = std::max(mx, row[c]);
  }
  row_max = mx;
  double sum = 0.0;
  for (double v : lane) sum += v;
  return sum;
}

/// The normalisation's pass over one row of n cells: a cell whose value is below `drop` or whose
/// scaled value is below `floor` becomes 0 (dropped; its unscaled value is returned in the sum),
/// the others are scaled by `scale`; row_max is the largest kept scaled value (0 if none). Eight
/// independent lanes so the loop vectorises (float lanes, summed per row into a double).
#if defined(__GNUC__) && defined(__x86_64__) && !defined(__clang__)
__attribute__((target_clones("avx2", "default")))
#endif
double drop_and_scale(float* row, int n, float drop, float scale, float floor, float& row_max) {
  typedef float Float8 __attribute__((vector_size(32)));
  const Float8 zero = {0, 0, 0, 0, 0, 0, 0, 0};
  Float8 lane_dropped = zero, lane_max = zero;
  int c = 0;
  for (; c + 8 <= n; c += 8) {
    Float8 raw;
    std::memcpy(&raw, row + c, sizeof raw);
    const Float8 v = raw * scale;
    const auto kill = (raw < drop) | (v < floor);
    lane_dropped += kill ? raw : zero;
    const Float8 kept = kill ? zero : v;
    lane_max = lane_max > kept ? lane_max : kept;
    std::memcpy(row + c, &kept, sizeof kept);
  }
  double dropped = 0.0;
  float mx = 0.0f;
  for (; c < n; ++c) {
    const float raw = row[c], v = raw * scale;
    const bool kill = raw < drop || v < floor;
    dropped += kill ? raw : 0.0f;
    mx = std::max(mx, kill ? 0.0f : v);
    row[c] = kill ? 0.0f : v;
  }
  for (int j = 0; j < 8; ++j) {
    dropped += lane_dropped[j];
    mx = std::max(mx, lane_max[j]);
  }
  row_max = mx;
  return dropped;
}

/// drop_mass's value classes: the bits of a non-negative float shifted right by kClassShift (8
/// exponent bits and the top 3 mantissa bits: 1/8 octave), monotonic in the value.
constexpr int kClassShift = 20;
constexpr int kClasses = 1 << 11;

/// Adds the cells of row[c0 .. c1] to their value classes in h: four interleaved tables of
/// kClasses (so neighbouring cells of one class do not wait on each other's additions; the caller
/// sums them in a fixed order). Runs of eight cells of one class (most of a flat belief) are
/// summed first and added once. Zero cells land in class 0.
#if defined(__GNUC__) && defined(__x86_64__) && !defined(__clang__)
__attribute__((target_clones("avx2", "default")))
#endif
void count_classes(const float* row, int c0, int c1, double* h) {
  typedef std::uint32_t Bits8 __attribute__((vector_size(32)));
  typedef float Float4 __attribute__((vector_size(16)));
  typedef double Double4 __attribute__((vector_size(32)));
  int c = c0;
  for (; c + 8 <= c1 + 1; c += 8) {
    Bits8 bits;
    std::memcpy(&bits, row + c, sizeof bits);
    const Bits8 cls = bits >> kClassShift;
    const Bits8 same = cls == cls[0];
    if ((same[0] & same[1] & same[2] & same[3] & same[4] & same[5] & same[6] & same[7]) != 0) {
      Float4 a, b;
      std::memcpy(&a, row + c, sizeof a);
      std::memcpy(&b, row + c + 4, sizeof b);
      const Double4 pair = __builtin_convertvector(a, Double4) + __builtin_convertvector(b, Double4);
      h[static_cast<std::size_t>((c >> 3) & 3) * kClasses + cls[0]] += (pair[0] + pair[1]) + (pair[2] + pair[3]);
      continue;
    }
    for (int j = 0; j < 8; ++j) h[static_cast<std::size_t>((c + j) & 3) * kClasses + cls[j]] += row[c + j];
  }
  for (; c <= c1; ++c) {
    std::uint32_t bits = 0;
    std::memcpy(&bits, row + c, sizeof bits);
    h[static_cast<std::size_t>(c & 3) * kClasses + (bits >> kClassShift)] += row[c];
  }
}

/// Folds the four interleaved tables of h into out (kClasses, added to) in a fixed order and
/// clears them.
void fold_classes(double* h, double* out) {
  for (int k = 0; k < kClasses; ++k) {
    out[k] += ((h[k] + h[kClasses + k]) + h[2 * kClasses + k]) + h[3 * kClasses + k];
    h[k] = h[kClasses + k] = h[2 * kClasses + k] = h[3 * kClasses + k] = 0.0;
  }
}

/// Widens [lo, hi] (lo > hi: empty) by the first and last non-zero cells of row[c0 .. c1]
/// (scanned from both ends: dense rows cost two reads).
template <class Span>
void extend_by_nonzero(const float* row, int c0, int c1, Span& span) {
  int a = c0, z = c1;
  while (a <= z && row[a] == 0.0f) ++a;
  while (z >= a && row[z] == 0.0f) --z;
  if (a > z) return;
  span.lo = std::min(span.lo, a);
  span.hi = std::max(span.hi, z);
}

struct ShiftKernel {
  std::vector<float> w;
  int first_offset = 0;
};

/// The discrete Gaussian kernel of variance t (cells^2): g[j] = e^-t I_|j|(t), j = -m .. m
/// (Lindeberg's discrete analogue of the Gaussian: variance exactly t, and kernels of variances
/// t1 and t2 compose to the kernel of t1 + t2, so splitting a step into sub-steps adds no noise).
/// t = 0 gives the identity [1]; small t gives [t/2, 1 - t, t/2], where a Gaussian sampled at the
/// cells would give [0, 1, 0] and lose the noise. Truncated at 4 sigma + 1 and normalised.
std::vector<float> discrete_gaussian(double t, int& m) {
  m = t > 0.0 ? static_cast<int>(std::ceil(4.0 * std::sqrt(t))) + 1 : 0;
  std::vector<double> g(static_cast<std::size_t>(2 * m + 1));
  double sum = 0.0;
  for (int k = -m; k <= m; ++k) {
    // Large t: the sampled Gaussian (the two agree to < 1e-3 relative beyond t = 50, and the
    // scaled Bessel function would overflow first).
    const double v = t > 50.0 ? std::exp(-0.5 * k * k / t)
                              : std::exp(-t) * std::cyl_bessel_i(static_cast<double>(std::abs(k)), t);
    g[static_cast<std::size_t>(k + m)] = v;
    sum += v;
  }
  std::vector<float> out;
  for (double v : g) out.push_back(static_cast<float>(v / sum));
  return out;
}

/// The translation kernel along one axis: an integer shift by `shift` cells plus the discrete
/// Gaussian of variance t: out(p) = sum_i w[i] in(p + first_offset + i).
ShiftKernel shift_kernel(int shift, double t) {
  int m = 0;
  ShiftKernel k;
  k.w = discrete_gaussian(t, m);  // symmetric: source offset -shift + j carries g[j]
  k.first_offset = -shift - m;
  return k;
}

}  // namespace

const std::vector<std::pair<const char*, BeliefInit>>& belief_init_names() {
  static const std::vector<std::pair<const char*, BeliefInit>> n = {{"posterior", BeliefInit::kPosterior},
                                                                    {"uniform", BeliefInit::kUniform}};
  return n;
}

const std::vector<std::pair<const char*, BeliefEstimate>>& belief_estimate_names() {
  static const std::vector<std::pair<const char*, BeliefEstimate>> n = {{"argmax", BeliefEstimate::kArgmax},
                                                                        {"window", BeliefEstimate::kWindow}};
  return n;
}

const FieldList<HistogramFilterParams>& HistogramFilterParams::fields() {
  using P = HistogramFilterParams;
  static const FieldList<P> f =
      FieldList<P>("tracker hist")
          .number("resolution_m", &P::resolution_m, 0.01, 2.0, "belief grid resolution, m (F3Loc desdf grid: 0.1)")
          .number("grid_margin_m", &P::grid_margin_m, 0.0, 100.0, "free margin of the grid around the plan, m (as the ray matcher)")
          .integer("num_orientations", &P::num_orientations, 4, 720, "orientation slices (F3Loc: 36, 10 deg)")
          .choice("motion_noise", &P::motion_noise, motion_noise_names(),
                  "motion noise from the odometry's stated error (odometry) or F3Loc's constants per increment (fixed)")
          .section("odometry", &P::odometry, OdometryUncertainty::fields())
          .choice("bias_growth", &P::bias_growth, bias_growth_names(),
                  "how the odometry's bias terms spread over increments: per increment or linear growth")
          .number("translation_sigma_m", &P::translation_sigma_m, 0.0, 10.0, "motion_noise fixed: noise per increment and axis, m (F3Loc: 0.1)")
          .number("rotation_sigma_rad", &P::rotation_sigma_rad, 0.0, 3.2, "motion_noise fixed: heading noise per increment, rad (F3Loc: 0.1)")
          .number("max_substep_m", &P::max_substep_m, 0.01, 100.0, "largest motion applied in one pass, m (larger: sub-steps)")
          .number("max_substep_deg", &P::max_substep_deg, 0.1, 180.0, "largest turn applied in one pass, deg")
          .choice("init", &P::init, belief_init_names(), "initial belief: the first posterior (F3Loc) or uniform")
          .number("measurement_floor", &P::measurement_floor, 0.0, 1.0,
                  "measurement update: belief x (floor + (1 - floor) x posterior / max)")
          .number("prune_below", &P::prune_below, 0.0, 1.0, "belief below this fraction of the maximum set to 0 (0 = never)")
          .flag("sparse", &P::sparse,
                "visit only the cells holding belief and ask the matcher for those only (false: every cell, the dense filter)")
          .number("drop_mass", &P::drop_mass, 0.0, 0.1,
                  "sparse: per step, drop the least likely cells holding at most this share of the mass (accounted, renormalised; 0 = exact)")
          .choice("estimate", &P::estimate, belief_estimate_names(),
                  "the belief's largest cell (F3Loc) or the pose with the most mass within the support window")
          .number("support_radius_m", &P::support_radius_m, 0.0, 100.0, "support window radius, m (success: 1 m)")
          .number("support_yaw_deg", &P::support_yaw_deg, 0.0, 180.0, "support window half-width in heading, deg (success: 30)")
          .number("orientation_mass", &P::orientation_mass, 0.0, 1.0, "stage 1: the best +-1 orientation bins hold this much")
          .number("converged_mass", &P::converged_mass, 0.0, 1.0, "converged: the support (mass in the window around the estimate) reaches this")
          .integer("modes", &P::modes, 0, 100,
                   "peaks of the belief reported with every estimate (the thesis' 1 m x 1 m x 30 deg maximum filter); 0 = none");
  return f;
}

nlohmann::ordered_json HistogramFilterParams::to_json() const { return fields().write(*this); }

void HistogramFilterParams::apply_overrides(const nlohmann::json& overrides) { fields().read(*this, overrides); }

cv::Mat HistogramFilter::belief_interior(const FloorPlan& plan, const GridSpec& grid) {
  const cv::Mat blocked = rasterize_occupancy(plan, grid, map_walls());
  cv::Mat inside;
  cv::bitwise_and(valid_area_mask(plan, grid), blocked == 0, inside);
  return inside;
}

HistogramFilter::HistogramFilter(const FloorPlan& plan, const HistogramFilterParams& params) : params_(params) {
  const GridSpec grid = grid_for_plan(plan, params_.resolution_m, params_.grid_margin_m);
  check_raster_budget(grid, 8.0 * params_.num_orientations + 16.0, "tracker hist (belief and scratch slices)");
  setup(grid, belief_interior(plan, grid));
}

HistogramFilter::HistogramFilter(const GridSpec& grid, const cv::Mat& interior, const HistogramFilterParams& params)
    : params_(params) {
  if (interior.type() != CV_8U || interior.rows != grid.height_px || interior.cols != grid.width_px) {
    throw std::logic_error("HistogramFilter: the interior mask must be CV_8U of the grid's size");
  }
  check_raster_budget(grid, 8.0 * params_.num_orientations + 16.0, "tracker hist (belief and scratch slices)");
  setup(grid, interior);
}

void HistogramFilter::setup(const GridSpec& grid, const cv::Mat& inside) {
  grid_ = grid;
  inside.convertTo(interior_, CV_32F, 1.0 / 255.0);
  // Interior column range of every row, and the rows the vertical pass may read (the largest
  // sub-step plus four sigmas of its noise, and three rows of slack).
  const int H = grid_.height_px, W = grid_.width_px;
  row_lo_.assign(static_cast<std::size_t>(H), W);
  row_hi_.assign(static_cast<std::size_t>(H), -1);
  for (int r = 0; r < H; ++r) {
    const std::uint8_t* in = inside.ptr<std::uint8_t>(r);
    for (int c = 0; c < W; ++c) {
      if (!in[c]) continue;
      row_lo_[static_cast<std::size_t>(r)] = std::min(row_lo_[static_cast<std::size_t>(r)], c);
      row_hi_[static_cast<std::size_t>(r)] = c;
    }
  }
  reach_rows_ = static_cast<int>(std::ceil((params_.max_substep_m + 4.0 * max_substep_sigma_m()) / grid_.resolution_m_per_px)) + 3;
  const int D = params_.num_orientations;
  slice_max_.assign(static_cast<std::size_t>(D), 0.0f);
  for (int o = 0; o < D; ++o) {
    belief_.push_back(cv::Mat::zeros(grid_.height_px, grid_.width_px, CV_32F));
    scratch_.push_back(cv::Mat::zeros(grid_.height_px, grid_.width_px, CV_32F));
  }
  blocks_ = (H + kBlockRows - 1) / kBlockRows;
  span_.assign(static_cast<std::size_t>(D) * blocks_, Span{});
  scratch_span_.assign(static_cast<std::size_t>(D) * blocks_, Span{});
}

void HistogramFilter::scan_spans() {
  const int D = params_.num_orientations;
  const int H = grid_.height_px;
  tbb::parallel_for(0, D, [&](int o) {
    const cv::Mat& b = belief_[static_cast<std::size_t>(o)];
    for (int blk = 0; blk < blocks_; ++blk) {
      Span sp;
      sp.lo = grid_.width_px;
      for (int r = blk * kBlockRows; r < std::min(H, (blk + 1) * kBlockRows); ++r) {
        const float* row = b.ptr<float>(r);
        for (int c = 0; c < grid_.width_px; ++c) {
          if (row[c] == 0.0f) continue;
          sp.lo = std::min(sp.lo, c);
          sp.hi = std::max(sp.hi, c);
        }
      }
      span_[static_cast<std::size_t>(o) * blocks_ + blk] = sp;
    }
  });
}

void HistogramFilter::dense_spans() {
  if (params_.sparse) return;
  for (std::vector<Span>* spans : {&span_, &scratch_span_})
    for (Span& sp : *spans) sp = Span{0, grid_.width_px - 1};
}

std::int64_t HistogramFilter::live_cells() const {
  std::int64_t n = 0;
  const int H = grid_.height_px;
  for (std::size_t i = 0; i < span_.size(); ++i) {
    const Span& sp = span_[i];
    if (sp.empty()) continue;
    const int blk = static_cast<int>(i % static_cast<std::size_t>(blocks_));
    for (int r = blk * kBlockRows; r < std::min(H, (blk + 1) * kBlockRows); ++r) {
      const int lo = std::max(sp.lo, row_lo_[static_cast<std::size_t>(r)]), hi = std::min(sp.hi, row_hi_[static_cast<std::size_t>(r)]);
      n += std::max(0, hi - lo + 1);
    }
  }
  return n;
}

HistogramFilter::~HistogramFilter() = default;

std::size_t HistogramFilter::state_bytes() const {
  return (belief_.size() + scratch_.size() + window_.size() + 1) * static_cast<std::size_t>(grid_.width_px) * grid_.height_px * sizeof(float);
}

void HistogramFilter::measure_slices() {
  classes_valid_ = false;  // the belief is not the one the motion step counted
  dense_spans();
  const int D = params_.num_orientations;
  const int H = grid_.height_px;
  mass_.assign(static_cast<std::size_t>(D), 0.0);
  slice_max_.assign(static_cast<std::size_t>(D), 0.0f);
  tbb::parallel_for(0, D, [&](int o) {
    const cv::Mat& b = belief_[static_cast<std::size_t>(o)];
    double sum = 0.0;
    float mx = 0.0f;
    for (int r = 0; r < H; ++r) {
      const Span& sp = span_[static_cast<std::size_t>(o) * blocks_ + r / kBlockRows];
      const int c0 = std::max(sp.lo, row_lo_[static_cast<std::size_t>(r)]), c1 = std::min(sp.hi, row_hi_[static_cast<std::size_t>(r)]);
      float row_max = 0.0f;
      sum += row_sum_max(b.ptr<float>(r), c0, c1, row_max);
      mx = std::max(mx, row_max);
    }
    mass_[static_cast<std::size_t>(o)] = sum;
    slice_max_[static_cast<std::size_t>(o)] = mx;
  });
}

void HistogramFilter::finish_normalise() {
  // Over the building's rows only: scale to a PDF, prune below prune_below x the largest value,
  // and record each slice's peak (the estimate uses them). Scaling by a positive float is
  // monotonic, so the pruning floor and the peaks are those of the scaled belief.
  const int D = params_.num_orientations;
  const int H = grid_.height_px;
  double total = 0.0;
  for (double m : mass_) total += m;
  // No mass left (every hypothesis walked out of the building): the filter is lost. It says so
  // (degenerate, support 0) and keeps the estimate it had instead of making one up.
  degenerate_ = !(total > 0.0);
  lost_ = degenerate_;
  if (degenerate_) return;
  dense_spans();
  peak_.assign(static_cast<std::size_t>(D), 0.0);
  peak_at_.assign(static_cast<std::size_t>(D), cv::Point(0, 0));
  // drop_mass: cells below `drop` (unnormalised) hold `dropped` of the mass: they are set to 0
  // and the rest scaled to sum to 1 (0: nothing dropped, the exact filter).
  // Accounting (sparse filter with drop_mass): the step since the last normalisation (motion or
  // update: linear, never adding mass) took the belief's mass from belief_mass_ to total; the
  // mass the dropped cells would have carried did not grow, so its ratio to the kept belief's
  // mass grows by at most belief_mass_ / total (drop_bound()).
  const bool accounting = params_.sparse && params_.drop_mass > 0.0;
  if (accounting && belief_mass_ > 0.0) drop_ratio_ *= belief_mass_ / total;
  double dropped = 0.0;
  const float drop = drop_threshold(total, dropped);
  classes_valid_ = false;
  const float scale = static_cast<float>(1.0 / (total - dropped));
  std::vector<double> slice_dropped(static_cast<std::size_t>(D), 0.0);
  const float top = *std::max_element(slice_max_.begin(), slice_max_.end()) * scale;
  const float floor = params_.prune_below > 0.0 ? static_cast<float>(params_.prune_below * top) : 0.0f;
  tbb::parallel_for(0, D, [&](int o) {
    cv::Mat& b = belief_[static_cast<std::size_t>(o)];
    float mx = 0.0f;
    cv::Point at(0, 0);
    double& dropped_here = slice_dropped[static_cast<std::size_t>(o)];
    const bool live = slice_max_[static_cast<std::size_t>(o)] > 0.0f;
    for (int blk = 0; blk < blocks_; ++blk) {
      // The span shrinks to the cells that stay non-zero (pruned or empty cells drop out).
      Span& sp = span_[static_cast<std::size_t>(o) * blocks_ + blk];
      if (!live) {
        sp = Span{};
        continue;
      }
      if (sp.empty()) continue;
      Span kept;
      kept.lo = grid_.width_px;
      for (int r = blk * kBlockRows; r < std::min(H, (blk + 1) * kBlockRows); ++r) {
        const int c0 = std::max(sp.lo, row_lo_[static_cast<std::size_t>(r)]), c1 = std::min(sp.hi, row_hi_[static_cast<std::size_t>(r)]);
        float* row = b.ptr<float>(r);
        if (c0 > c1) continue;
        // Dropped and pruned cells: 0; with accounting (drop_mass) their mass is accounted
        // (prune_below's too). The peak: the first cell of the row's maximum (row order).
        float row_max = 0.0f;
        const double gone = drop_and_scale(row + c0, c1 - c0 + 1, drop, scale, floor, row_max);
        if (accounting) dropped_here += gone;
        if (row_max > mx) {
          mx = row_max;
          int c = c0;
          while (row[c] != row_max) ++c;
          at = cv::Point(c, r);
        }
        extend_by_nonzero(row, c0, c1, kept);
      }
      sp = kept;
    }
    peak_[static_cast<std::size_t>(o)] = mx;
    peak_at_[static_cast<std::size_t>(o)] = at;
    slice_max_[static_cast<std::size_t>(o)] = mx;
    mass_[static_cast<std::size_t>(o)] = std::max(0.0, (mass_[static_cast<std::size_t>(o)] - dropped_here) * scale);
  });
  if (accounting) {
    double removed = 0.0;
    for (double v : slice_dropped) removed += v;  // slice order: the same sum at any thread count
    dropped_mass_ += removed / total;
    drop_ratio_ = (drop_ratio_ * total + removed) / std::max(total - removed, 1e-300);
    belief_mass_ = 0.0;
    for (double m : mass_) belief_mass_ += m;
  }
  update_estimate();
}

float HistogramFilter::drop_threshold(double total, double& dropped) const {
  dropped = 0.0;
  if (!params_.sparse || !(params_.drop_mass > 0.0)) return 0.0f;
  // The mass of every value class: from the motion step's count of the belief it produced (per
  // row block, reduced in block order), or by a pass over the belief (per slice in parallel, each
  // in row order, reduced in slice order): the same threshold at any thread count.
  const double budget = params_.drop_mass * total;
  std::vector<double> all(kClasses, 0.0);
  if (classes_valid_) {
    for (int blk = 0; blk < blocks_; ++blk) {
      if (!block_counted_[static_cast<std::size_t>(blk)]) continue;
      const double* h = block_classes_.data() + static_cast<std::size_t>(blk) * kClasses;
      for (int k = 0; k < kClasses; ++k) all[static_cast<std::size_t>(k)] += h[k];
    }
  } else {
    const int D = params_.num_orientations;
    const int H = grid_.height_px;
    std::vector<std::vector<double>> hist(static_cast<std::size_t>(D));
    tbb::parallel_for(0, D, [&](int o) {
      if (!(slice_max_[static_cast<std::size_t>(o)] > 0.0f)) return;
      std::vector<double> h(4 * kClasses, 0.0);
      const cv::Mat& b = belief_[static_cast<std::size_t>(o)];
      for (int r = 0; r < H; ++r) {
        const Span& sp = span_[static_cast<std::size_t>(o) * blocks_ + r / kBlockRows];
        const int c0 = std::max(sp.lo, row_lo_[static_cast<std::size_t>(r)]), c1 = std::min(sp.hi, row_hi_[static_cast<std::size_t>(r)]);
        count_classes(b.ptr<float>(r), c0, c1, h.data());
      }
      std::vector<double>& out = hist[static_cast<std::size_t>(o)];
      out.assign(kClasses, 0.0);
      fold_classes(h.data(), out.data());
    });
    for (const std::vector<double>& h : hist)
      for (std::size_t k = 0; k < h.size(); ++k) all[k] += h[k];
  }
  // The lowest classes whose mass together stays within the budget.
  int k = 0;
  double cum = 0.0;
  while (k < kClasses && cum + all[static_cast<std::size_t>(k)] <= budget) cum += all[static_cast<std::size_t>(k++)];
  if (!(cum > 0.0) || k >= kClasses) return 0.0f;
  dropped = cum;
  const std::uint32_t bits = static_cast<std::uint32_t>(k) << kClassShift;
  float threshold = 0.0f;
  std::memcpy(&threshold, &bits, sizeof threshold);
  return threshold;
}

void HistogramFilter::initialise(const Posterior& post, const OdometryStep& first) {
  last_t_s_ = first.t_s;
  dropped_mass_ = 0.0;
  drop_ratio_ = 0.0;
  belief_mass_ = 0.0;
  elapsed_ = {};
  offset_px_.assign(static_cast<std::size_t>(params_.num_orientations), Vec2(0.0, 0.0));
  // The heading grid starts aligned with the posterior's first slice (a matcher's slices at
  // 2 pi s / S: offset 0; a posterior at one known heading: that heading exactly).
  const double bin = kTwoPi / params_.num_orientations;
  yaw_residual_rad_ = 0.0;
  if (post.num_slices() > 0 && params_.init == BeliefInit::kPosterior) {
    const double y = wrap_angle_rad(post.yaw_rad.front());
    yaw_residual_rad_ = y - std::round(y / bin) * bin;
  }
  if (params_.init == BeliefInit::kUniform) {
    for (cv::Mat& b : belief_) interior_.copyTo(b);
    scan_spans();
    normalise();
    return;
  }
  // The posterior itself (F3Loc: a uniform prior times the first likelihood), each belief slice
  // from the posterior slice nearest in yaw (0 where no slice is within half a bin), inside the
  // building only.
  const int D = params_.num_orientations;
  for (int o = 0; o < D; ++o) {
    cv::Mat& b = belief_[static_cast<std::size_t>(o)];
    b.setTo(0.0f);
    const double yaw = kTwoPi * o / D + yaw_residual_rad_;
    int slice = -1;
    double gap = 0.5 * kTwoPi / D + 1e-9;
    for (int s = 0; s < post.num_slices(); ++s) {
      const double a = angle_distance_rad(yaw, post.yaw_rad[static_cast<std::size_t>(s)]);
      if (a <= gap) {
        gap = a;
        slice = s;
      }
    }
    if (slice < 0) continue;
    const cv::Mat& m = post.scores[static_cast<std::size_t>(slice)];
    for (int r = 0; r < grid_.height_px; ++r) {
      float* row = b.ptr<float>(r);
      const float* in = interior_.ptr<float>(r);
      for (int c = 0; c < grid_.width_px; ++c) {
        if (in[c] == 0.0f) continue;
        int pr = r, pc = c;
        if (!(post.grid == grid_) && !post.grid.world_to_cell(grid_.cell_center_m(r, c), pr, pc)) continue;
        row[c] = m.at<float>(pr, pc);
      }
    }
  }
  scan_spans();
  normalise();
  if (degenerate_) throw InputError("histogram filter: the initial posterior is empty (every cell scored 0): no pose to start from");
}

void HistogramFilter::move(double dx, double dy, double dyaw, double translation_var_m2, double rotation_var_rad2) {
  const int D = params_.num_orientations;
  const int H = grid_.height_px, W = grid_.width_px;
  const double res = grid_.resolution_m_per_px;
  const double bin = kTwoPi / D;
  // Translation: slice o heads at yaw 2 pi o / D + yaw_residual_rad_; the body-frame motion
  // rotated into it is added to the slice's sub-cell offset, the belief moves by the whole cells
  // of it and the rest stays in the offset (so motions smaller than a cell are not lost and
  // nothing is smoothed by interpolation), convolved with the discrete Gaussian of the motion
  // noise (separable: two 1D passes). Rotation: the heading change is added to the heading
  // residual and the slices move by its whole bins (each slice's offset moving with its mass),
  // convolved with the circular discrete Gaussian of the rotation noise. Empty slices are skipped.
  const double t_px = translation_var_m2 / (res * res);
  std::vector<char> nonzero(static_cast<std::size_t>(D), 0);
  std::vector<ShiftKernel> kx(static_cast<std::size_t>(D)), ky(static_cast<std::size_t>(D));
  std::vector<int> y_lo(static_cast<std::size_t>(D), 0), y_hi(static_cast<std::size_t>(D), -1);
  for (int o = 0; o < D; ++o) {
    const auto so = static_cast<std::size_t>(o);
    nonzero[so] = slice_max_[so] > 0.0f ? 1 : 0;
    const double yaw = kTwoPi * o / D + yaw_residual_rad_;
    const double ex = offset_px_[so].x() + (std::cos(yaw) * dx - std::sin(yaw) * dy) / res;
    const double ey = offset_px_[so].y() + (std::sin(yaw) * dx + std::cos(yaw) * dy) / res;
    const int sx = static_cast<int>(std::lround(ex)), sy = static_cast<int>(std::lround(ey));
    offset_px_[so] = Vec2(ex - sx, ey - sy);
    if (!nonzero[so]) continue;
    kx[so] = shift_kernel(sx, t_px);
    ky[so] = shift_kernel(sy, t_px);
    // Rows the vertical pass reads lie within reach_rows_ of the row it writes (the constructor
    // sized the horizontal pass's column ranges for that); predict() splits larger motions.
    y_lo[so] = std::max(ky[so].first_offset, -reach_rows_);
    y_hi[so] = std::min(ky[so].first_offset + static_cast<int>(ky[so].w.size()) - 1, reach_rows_);
  }
  const double turned = yaw_residual_rad_ + dyaw;
  const int shift = static_cast<int>(std::lround(turned / bin));
  yaw_residual_rad_ = turned - shift * bin;
  int m = 0;
  const std::vector<float> w = discrete_gaussian(rotation_var_rad2 / (bin * bin), m);
  const int lo = shift - m, hi = shift + m;
  {
    std::vector<Vec2> moved(offset_px_.size());
    for (int o = 0; o < D; ++o) moved[static_cast<std::size_t>(((o + shift) % D + D) % D)] = offset_px_[static_cast<std::size_t>(o)];
    offset_px_ = std::move(moved);
  }
  dense_spans();
  // Row blocks: each block translates the rows it needs of every slice into a block buffer that
  // stays in cache, then rotates across slices into the output; the belief is read and the output
  // written once per step. Per-block slice sums and maxima are reduced in block order (the same
  // bytes at any thread count) and stand in for the first pass of the next normalisation.
  // Sparse: a source slice is translated only over the columns its spans (in the rows the block
  // reads) can reach through the kernel, an output slice written only where some source reached;
  // each output block's span becomes its non-zero columns, and the old contents of the output
  // buffer are cleared over its old span only.
  const int blocks = blocks_;
  std::vector<double> block_sum(static_cast<std::size_t>(blocks) * D, 0.0);
  std::vector<float> block_max(static_cast<std::size_t>(blocks) * D, 0.0f);
  std::vector<Span> out_span(static_cast<std::size_t>(D) * blocks);
  const std::size_t block_stride = static_cast<std::size_t>(kBlockRows) * W;
  int max_terms = hi - lo + 1;  // the rotation's; the translations' below
  for (int o = 0; o < D; ++o) {
    max_terms = std::max({max_terms, static_cast<int>(kx[static_cast<std::size_t>(o)].w.size()),
                          static_cast<int>(ky[static_cast<std::size_t>(o)].w.size())});
  }
  // drop_mass: the value classes of the belief this step produces, counted per block while its
  // rows are in cache (the next normalisation's drop threshold; no pass of its own).
  const bool count = params_.sparse && params_.drop_mass > 0.0;
  if (count) {
    block_classes_.resize(static_cast<std::size_t>(blocks) * kClasses);
    block_counted_.assign(static_cast<std::size_t>(blocks), 0);
  }
  tbb::parallel_for(0, blocks, [&](int blk) {
    const int r0 = blk * kBlockRows, r1 = std::min(H, r0 + kBlockRows);
    bool any_interior = false;
    for (int r = r0; r < r1; ++r) any_interior |= row_lo_[static_cast<std::size_t>(r)] <= row_hi_[static_cast<std::size_t>(r)];
    if (!any_interior) return;  // cells outside the building are never written: they stay 0
    MotionWorkspace& ws = workspace_.local();
    if (count) ws.classes.resize(4 * kClasses, 0.0);  // zero at every block's start (fold_classes clears it)
    std::vector<RowTerm> terms(static_cast<std::size_t>(max_terms));  // one row's terms of the pass at hand
    int nt = 0;
    ws.block.resize(block_stride * D);
    ws.rows.resize(static_cast<std::size_t>(kBlockRows + 2 * reach_rows_ + 1) * W);
    std::vector<Span> reach(static_cast<std::size_t>(D));  // per source slice: the columns it reaches in this block
    for (int s = 0; s < D; ++s) {
      const auto ss = static_cast<std::size_t>(s);
      if (!nonzero[ss]) continue;
      const cv::Mat& b = belief_[ss];
      // Horizontal pass over the rows the vertical pass reads (row rr -> ws.rows row rr - first).
      const int first = std::max(0, r0 + y_lo[ss]), last = std::min(H - 1, r1 - 1 + y_hi[ss]);
      Span src;
      src.lo = W;
      for (int q = first / kBlockRows; first <= last && q <= last / kBlockRows; ++q) {
        const Span& sp = span_[ss * static_cast<std::size_t>(blocks) + static_cast<std::size_t>(q)];
        if (sp.empty()) continue;
        src.lo = std::min(src.lo, sp.lo);
        src.hi = std::max(src.hi, sp.hi);
      }
      if (src.empty()) continue;
      const int taps = static_cast<int>(kx[ss].w.size());
      Span& t_span = reach[ss];
      t_span.lo = std::max(0, src.lo - kx[ss].first_offset - (taps - 1));
      t_span.hi = std::min(W - 1, src.hi - kx[ss].first_offset);
      if (t_span.empty()) continue;
      for (int rr = first; rr <= last; ++rr) {
        // The columns the vertical pass reads of this row: the interior of the block's rows
        // within the vertical kernel's reach.
        int need_lo = W, need_hi = -1;
        for (int r = std::max(r0, rr - y_hi[ss]); r <= std::min(r1 - 1, rr - y_lo[ss]); ++r) {
          need_lo = std::min(need_lo, row_lo_[static_cast<std::size_t>(r)]);
          need_hi = std::max(need_hi, row_hi_[static_cast<std::size_t>(r)]);
        }
        const int c0 = std::max(t_span.lo, need_lo);
        const int c1 = std::min(t_span.hi, need_hi);
        if (c0 > c1) continue;
        const float* in = b.ptr<float>(rr);
        float* t = ws.rows.data() + static_cast<std::size_t>(rr - first) * W;
        nt = 0;
        for (int i = 0; i < taps; ++i) {
          const int off = kx[ss].first_offset + i;
          terms[static_cast<std::size_t>(nt++)] =
              RowTerm{in, off, kx[ss].w[static_cast<std::size_t>(i)], std::max(c0, -off), std::min(c1, W - 1 - off)};
        }
        sum_terms(t, c0, c1, terms.data(), nt);
      }
      // Vertical pass into the block buffer, times the interior mask.
      for (int r = r0; r < r1; ++r) {
        const int c0 = std::max(t_span.lo, row_lo_[static_cast<std::size_t>(r)]);
        const int c1 = std::min(t_span.hi, row_hi_[static_cast<std::size_t>(r)]);
        if (c0 > c1) continue;
        float* row = ws.block.data() + ss * block_stride + static_cast<std::size_t>(r - r0) * W;
        nt = 0;
        for (int off = y_lo[ss]; off <= y_hi[ss]; ++off) {
          const int rr = r + off;
          if (rr < first || rr > last) continue;
          terms[static_cast<std::size_t>(nt++)] = RowTerm{ws.rows.data() + static_cast<std::size_t>(rr - first) * W, 0,
                                                          ky[ss].w[static_cast<std::size_t>(off - ky[ss].first_offset)], c0, c1};
        }
        sum_terms(row, c0, c1, terms.data(), nt);
        float* acc = row + c0;
        const float* in = interior_.ptr<float>(r) + c0;
        multiply_by(acc, in, c1 - c0 + 1);
      }
    }
    // Rotation into the output slices, with the block's per-slice sum, maximum and span.
    for (int o = 0; o < D; ++o) {
      double sum = 0.0;
      float mx = 0.0f;
      cv::Mat& out = scratch_[static_cast<std::size_t>(o)];
      const std::size_t si = static_cast<std::size_t>(o) * blocks + static_cast<std::size_t>(blk);
      // Clear the output buffer's old contents of this block.
      const Span old = scratch_span_[si];
      Span written;
      written.lo = W;
      for (int k = lo; k <= hi; ++k) {
        const Span& sp = reach[static_cast<std::size_t>(((o - k) % D + D) % D)];
        if (sp.empty()) continue;
        written.lo = std::min(written.lo, sp.lo);
        written.hi = std::max(written.hi, sp.hi);
      }
      Span nz;
      nz.lo = W;
      for (int r = r0; r < r1; ++r) {
        float* dst = out.ptr<float>(r);
        const int rlo = row_lo_[static_cast<std::size_t>(r)], rhi = row_hi_[static_cast<std::size_t>(r)];
        const int c0 = std::max(written.lo, rlo), c1 = std::min(written.hi, rhi);
        {
          // The old contents outside the columns written below.
          const int o0 = std::max(old.lo, rlo), o1 = std::min(old.hi, rhi);
          if (o0 <= o1 && c0 > c1) {
            std::fill(dst + o0, dst + o1 + 1, 0.0f);
          } else if (o0 <= o1) {
            if (o0 < c0) std::fill(dst + o0, dst + std::min(o1 + 1, c0), 0.0f);
            if (o1 > c1) std::fill(dst + std::max(o0, c1 + 1), dst + o1 + 1, 0.0f);
          }
        }
        if (c0 > c1) continue;
        nt = 0;
        for (int k = lo; k <= hi; ++k) {
          const int src = ((o - k) % D + D) % D;  // mass of heading src moves to heading src + k
          const Span& sp = reach[static_cast<std::size_t>(src)];
          const int a = std::max(c0, sp.lo), z = std::min(c1, sp.hi);
          if (a > z) continue;
          terms[static_cast<std::size_t>(nt++)] =
              RowTerm{ws.block.data() + static_cast<std::size_t>(src) * block_stride + static_cast<std::size_t>(r - r0) * W, 0,
                      w[static_cast<std::size_t>(k - lo)], a, z};
        }
        sum_terms(dst, c0, c1, terms.data(), nt);
        float row_max = 0.0f;
        sum += row_sum_max(dst, c0, c1, row_max);
        mx = std::max(mx, row_max);
        if (count) count_classes(dst, c0, c1, ws.classes.data());
        extend_by_nonzero(dst, c0, c1, nz);
      }
      block_sum[static_cast<std::size_t>(blk) * D + o] = sum;
      block_max[static_cast<std::size_t>(blk) * D + o] = mx;
      out_span[si] = nz;
    }
    if (count) {
      double* out = block_classes_.data() + static_cast<std::size_t>(blk) * kClasses;
      std::fill(out, out + kClasses, 0.0);
      fold_classes(ws.classes.data(), out);
      block_counted_[static_cast<std::size_t>(blk)] = 1;
    }
  });
  classes_valid_ = count;
  // Blocks without interior rows were skipped: their buffers are 0 in both.
  for (std::size_t i = 0; i < out_span.size(); ++i) scratch_span_[i] = out_span[i];
  std::swap(span_, scratch_span_);
  std::swap(belief_, scratch_);
  mass_.assign(static_cast<std::size_t>(D), 0.0);
  slice_max_.assign(static_cast<std::size_t>(D), 0.0f);
  for (int blk = 0; blk < blocks; ++blk) {
    for (int o = 0; o < D; ++o) {
      mass_[static_cast<std::size_t>(o)] += block_sum[static_cast<std::size_t>(blk) * D + o];
      slice_max_[static_cast<std::size_t>(o)] =
          std::max(slice_max_[static_cast<std::size_t>(o)], block_max[static_cast<std::size_t>(blk) * D + o]);
    }
  }
}

void HistogramFilter::predict(const OdometryStep& step) {
  const Pose2& t = step.T_prev_curr;
  const double dt = step.t_s - last_t_s_;
  last_t_s_ = step.t_s;
  // Noise of this increment: the odometry's stated error, or F3Loc's fixed sigmas. The
  // translation kernel is isotropic (separable on the grid): its per-axis variance is the mean of
  // the along- and across-track variances, so the total variance is the odometry's.
  double translation_var = 0.0, rotation_var = 0.0;
  if (params_.motion_noise == MotionNoiseSource::kOdometry) {
    const IncrementNoise e = increment_noise(params_.odometry, step, dt, params_.bias_growth, elapsed_);
    translation_var = 0.5 * (e.along_m * e.along_m + e.across_m * e.across_m);
    rotation_var = e.rotation_rad * e.rotation_rad;
  } else {
    translation_var = params_.translation_sigma_m * params_.translation_sigma_m;
    rotation_var = params_.rotation_sigma_rad * params_.rotation_sigma_rad;
  }
  const double len = t.position_m().norm();
  // Sub-steps: at most max_substep_m and max_substep_deg of motion, and at most
  // kMaxSubstepSigma of translation noise (the kernel reach the constructor sized) each.
  const int n = std::max({1, static_cast<int>(std::ceil(len / params_.max_substep_m)),
                          static_cast<int>(std::ceil(std::abs(t.yaw_rad) / deg_to_rad(params_.max_substep_deg))),
                          static_cast<int>(std::ceil(translation_var / (max_substep_sigma_m() * max_substep_sigma_m())))});
  // The body frame turns between sub-steps, so the translation of each is expressed in the body
  // frame at its start (an arc from the previous to the current pose). Each of the n sub-steps
  // diffuses by variance / n (the discrete Gaussians compose exactly): splitting adds no noise.
  for (int k = 0; k < n; ++k) {
    const double turned = t.yaw_rad * k / n;
    const double c = std::cos(-turned), s = std::sin(-turned);
    const double dx = (c * t.x_m - s * t.y_m) / n, dy = (s * t.x_m + c * t.y_m) / n;
    move(dx, dy, t.yaw_rad / n, translation_var / n, rotation_var / n);
  }
  finish_normalise();  // move() measured the slices
}

void HistogramFilter::update(const PosteriorQuery& query) {
  const int D = params_.num_orientations;
  const int H = grid_.height_px;
  const double floor = params_.measurement_floor;
  if (query.num_slices() == 0) {
    degenerate_ = true;  // an empty posterior carries no information: the belief stays
    return;
  }
  // The posterior slice of each belief slice, and whether it stands for that heading: a posterior
  // slice stands for headings within half a belief bin of its yaw; farther headings were not
  // evaluated by the matcher: they get the floor.
  std::vector<int> slice_of(static_cast<std::size_t>(D));
  std::vector<char> covered(static_cast<std::size_t>(D));
  std::vector<Vec2> offset_m(static_cast<std::size_t>(D));
  for (int o = 0; o < D; ++o) {
    double gap = 0.0;
    slice_of[static_cast<std::size_t>(o)] = query.nearest_slice(kTwoPi * o / D + yaw_residual_rad_, &gap);
    covered[static_cast<std::size_t>(o)] = gap <= 0.5 * kTwoPi / D + 1e-9;
    offset_m[static_cast<std::size_t>(o)] = offset_px_[static_cast<std::size_t>(o)] * grid_.resolution_m_per_px;
  }
  dense_spans();
  const bool same_grid = query.grid() == grid_;
  // The posterior cell of belief cell (o, r, c) (false: outside the posterior's grid). Same
  // grid: the offset (<= half a cell) keeps the cell.
  auto posterior_cell = [&](int o, int r, int c, int& pr, int& pc) {
    pr = r;
    pc = c;
    return same_grid || query.grid().world_to_cell(grid_.cell_center_m(r, c) + offset_m[static_cast<std::size_t>(o)], pr, pc);
  };
  // Point queries when the live cells are few against the full posterior's (its grid cells x
  // slices; the full posterior is read otherwise): the same values either way.
  const double posterior_cells = static_cast<double>(query.grid().width_px) * query.grid().height_px * query.num_slices();
  const bool points = params_.sparse && query.scores_points() && 8.0 * static_cast<double>(live_cells()) < posterior_cells;
  const Posterior* post = points ? nullptr : &query.full();
  double best = 0.0;
  if (points) {
    best = query.max_score();
  } else {
    for (const cv::Mat& m : post->scores) {
      double mx = 0.0;
      cv::minMaxLoc(m, nullptr, &mx);
      best = std::max(best, mx);
    }
  }
  if (!(best > 0.0)) {
    degenerate_ = true;  // an empty posterior carries no information: the belief stays
    return;
  }
  // Point queries: the non-zero covered cells of every slice, in the order the weighting below
  // visits them.
  std::vector<std::vector<PosteriorCell>> asked(static_cast<std::size_t>(D));
  std::vector<std::size_t> first_value(static_cast<std::size_t>(D) + 1, 0);
  std::vector<float> values;
  if (points) {
    tbb::parallel_for(0, D, [&](int o) {
      if (!covered[static_cast<std::size_t>(o)]) return;
      const cv::Mat& b = belief_[static_cast<std::size_t>(o)];
      std::vector<PosteriorCell>& cells = asked[static_cast<std::size_t>(o)];
      for (int blk = 0; blk < blocks_; ++blk) {
        const Span& sp = span_[static_cast<std::size_t>(o) * blocks_ + blk];
        if (sp.empty()) continue;
        for (int r = blk * kBlockRows; r < std::min(H, (blk + 1) * kBlockRows); ++r) {
          const float* row = b.ptr<float>(r);
          for (int c = sp.lo; c <= sp.hi; ++c) {
            int pr = 0, pc = 0;
            if (row[c] != 0.0f && posterior_cell(o, r, c, pr, pc)) cells.push_back({slice_of[static_cast<std::size_t>(o)], pr, pc});
          }
        }
      }
    });
    std::vector<PosteriorCell> all;
    for (int o = 0; o < D; ++o) {
      first_value[static_cast<std::size_t>(o)] = all.size();
      all.insert(all.end(), asked[static_cast<std::size_t>(o)].begin(), asked[static_cast<std::size_t>(o)].end());
    }
    first_value[static_cast<std::size_t>(D)] = all.size();
    query.scores(all, values);
    ++point_query_updates_;
  }
  // The weighted belief goes into the scratch slices (cleared over their old spans, written over
  // the belief's); it replaces the belief only when some mass survives (an update that zeroes
  // everything is reported, and the prior kept).
  std::vector<double> slice_total(static_cast<std::size_t>(D), 0.0);
  tbb::parallel_for(0, D, [&](int o) {
    const auto so = static_cast<std::size_t>(o);
    const cv::Mat& m = points ? cv::Mat() : post->scores[static_cast<std::size_t>(slice_of[so])];
    const cv::Mat& b = belief_[so];
    cv::Mat& out = scratch_[so];
    std::size_t next = first_value[so];
    double total = 0.0;
    for (int blk = 0; blk < blocks_; ++blk) {
      const std::size_t si = so * static_cast<std::size_t>(blocks_) + static_cast<std::size_t>(blk);
      const Span old = scratch_span_[si], sp = span_[si];
      for (int r = blk * kBlockRows; r < std::min(H, (blk + 1) * kBlockRows); ++r) {
        float* dst = out.ptr<float>(r);
        if (!old.empty()) std::fill(dst + old.lo, dst + old.hi + 1, 0.0f);
        if (sp.empty()) continue;
        const float* row = b.ptr<float>(r);
        for (int c = sp.lo; c <= sp.hi; ++c) {
          if (row[c] == 0.0f) {
            dst[c] = 0.0f;
            continue;
          }
          double value = 0.0;
          int pr = 0, pc = 0;
          if (covered[so] && posterior_cell(o, r, c, pr, pc)) value = (points ? values[next++] : m.at<float>(pr, pc)) / best;
          dst[c] = static_cast<float>(row[c] * (floor + (1.0 - floor) * value));
          total += dst[c];
        }
      }
      scratch_span_[si] = sp;
    }
    slice_total[so] = total;
  });
  double total = 0.0;
  for (double t : slice_total) total += t;
  if (!(total > 0.0)) {
    degenerate_ = true;
    return;
  }
  std::swap(belief_, scratch_);
  std::swap(span_, scratch_span_);
  normalise();
  elapsed_ = {};  // the biases' error restarts from the pose this update told
}

double HistogramFilter::mass_within(double x0_m, double y0_m, double x1_m, double y1_m) const {
  if (lost_ || mass_.empty()) return 0.0;
  const double res = grid_.resolution_m_per_px;
  // Cells whose centre (moved by the slice's sub-cell offset) lies in the box; the belief is
  // normalised, so the sum is a share of the mass.
  double total = 0.0;
  for (int o = 0; o < params_.num_orientations; ++o) {
    const Vec2 off = offset_px_.empty() ? Vec2(0.0, 0.0) : offset_px_[static_cast<std::size_t>(o)];
    const int c0 = std::max(0, static_cast<int>(std::ceil((x0_m - grid_.origin_x_m) / res - 0.5 - off.x())));
    const int c1 = std::min(grid_.width_px - 1, static_cast<int>(std::floor((x1_m - grid_.origin_x_m) / res - 0.5 - off.x())));
    const int r0 = std::max(0, static_cast<int>(std::ceil((y0_m - grid_.origin_y_m) / res - 0.5 - off.y())));
    const int r1 = std::min(grid_.height_px - 1, static_cast<int>(std::floor((y1_m - grid_.origin_y_m) / res - 0.5 - off.y())));
    if (c0 > c1 || r0 > r1) continue;
    total += cv::sum(belief_[static_cast<std::size_t>(o)](cv::Range(r0, r1 + 1), cv::Range(c0, c1 + 1)))[0];
  }
  return total;
}

double HistogramFilter::mass_near(int slice, const cv::Point& at) const {
  const int D = params_.num_orientations;
  const double res = grid_.resolution_m_per_px;
  const double radius = params_.support_radius_m / res;
  const int rad = static_cast<int>(std::floor(radius));
  const int span = static_cast<int>(std::floor(deg_to_rad(params_.support_yaw_deg) / (kTwoPi / D) + 1e-9));
  double near = 0.0;
  for (int k = -std::min(span, D / 2); k <= std::min(span, (D - 1) / 2); ++k) {
    const cv::Mat& b = belief_[static_cast<std::size_t>(((slice + k) % D + D) % D)];
    for (int r = std::max(0, at.y - rad); r <= std::min(grid_.height_px - 1, at.y + rad); ++r) {
      const float* row = b.ptr<float>(r);
      for (int c = std::max(0, at.x - rad); c <= std::min(grid_.width_px - 1, at.x + rad); ++c) {
        if ((r - at.y) * (r - at.y) + (c - at.x) * (c - at.x) <= radius * radius) near += row[c];
      }
    }
  }
  return near;
}

void HistogramFilter::update_estimate() {
  const int D = params_.num_orientations;
  int bo = 0;
  cv::Point bp(0, 0);
  if (params_.estimate == BeliefEstimate::kArgmax) {
    bo = static_cast<int>(std::max_element(peak_.begin(), peak_.end()) - peak_.begin());
    bp = peak_at_[static_cast<std::size_t>(bo)];
  } else {
    // The mode of the belief summed over the support window: a square of the disc's area per
    // slice (box filter), summed over the slices within support_yaw_deg (a running sum around
    // the circle); ties: lowest slice, then row, then column.
    const int k = std::max(1, static_cast<int>(std::lround(std::sqrt(kPi) * params_.support_radius_m / grid_.resolution_m_per_px)) | 1);
    const int span = std::min(static_cast<int>(std::floor(deg_to_rad(params_.support_yaw_deg) / (kTwoPi / D) + 1e-9)), (D - 1) / 2);
    window_.resize(static_cast<std::size_t>(D));
    tbb::parallel_for(0, D, [&](int o) {
      cv::boxFilter(belief_[static_cast<std::size_t>(o)], window_[static_cast<std::size_t>(o)], CV_32F, cv::Size(k, k),
                    cv::Point(-1, -1), false, cv::BORDER_CONSTANT);
    });
    cv::Mat acc = cv::Mat::zeros(grid_.height_px, grid_.width_px, CV_32F);
    for (int j = -span; j <= span; ++j) acc += window_[static_cast<std::size_t>((j + D) % D)];
    double best = -1.0;
    for (int o = 0; o < D; ++o) {
      if (o > 0) {
        acc += window_[static_cast<std::size_t>((o + span) % D)];
        acc -= window_[static_cast<std::size_t>((o - span - 1 + D) % D)];
      }
      double mx = 0.0;
      cv::Point at;
      cv::minMaxLoc(acc, nullptr, &mx, nullptr, &at);
      if (mx > best) {
        best = mx;
        bo = o;
        bp = at;
      }
    }
  }
  const Vec2 c = grid_.cell_center_m(bp.y, bp.x) + offset_px_[static_cast<std::size_t>(bo)] * grid_.resolution_m_per_px;
  current_.pose = {c.x(), c.y(), wrap_angle_rad(kTwoPi * bo / D + yaw_residual_rad_)};
  // Convergence: the belief mass within the support window of the estimate (stage 2 when it
  // reaches converged_mass); stage 1 when the estimate's heading bin and its two neighbours hold
  // orientation_mass of the belief.
  const double orient = mass_[static_cast<std::size_t>(bo)] + mass_[static_cast<std::size_t>((bo + 1) % D)] +
                        mass_[static_cast<std::size_t>((bo + D - 1) % D)];
  current_.support = mass_near(bo, bp);
  current_.stage = current_.support >= params_.converged_mass ? 2 : (orient >= params_.orientation_mass ? 1 : 0);
}

TrackEstimate HistogramFilter::estimate() const {
  TrackEstimate e = current_;
  e.degenerate = degenerate_;
  if (lost_) {
    e.support = 0.0;
    e.stage = 0;
  }
  if (params_.modes > 0) {
    // The thesis' 5 x 5 x 3 filter on its 0.2 m, 10 deg grid: 1 m x 1 m x 30 deg.
    const int D = params_.num_orientations;
    const int half_cells = std::max(0, static_cast<int>(std::floor((1.0 / grid_.resolution_m_per_px - 1.0) / 2.0 + 1e-9)));
    const int half_slices = std::max(0, static_cast<int>(std::floor((30.0 * D / 360.0 - 1.0) / 2.0 + 1e-9)));
    for (const PoseHypothesis& h : belief().maximum_filter_peaks(params_.modes, half_cells, half_slices)) {
      e.modes.push_back({h.x_m, h.y_m, h.yaw_rad});
    }
  }
  return e;
}

Posterior HistogramFilter::belief() const {
  // Each slice at its heading, its mass moved by its sub-cell offset onto the grid (linear
  // interpolation: each cell's mass shared between the cells around where it stands), so the
  // exported belief has the filter's mean position and mass; its spread grows by at most a
  // quarter of a cell squared per axis.
  Posterior p;
  p.grid = grid_;
  for (int o = 0; o < params_.num_orientations; ++o) {
    p.yaw_rad.push_back(wrap_angle_rad(kTwoPi * o / params_.num_orientations + yaw_residual_rad_));
    const Vec2 off = offset_px_.empty() ? Vec2(0.0, 0.0) : offset_px_[static_cast<std::size_t>(o)];
    cv::Mat moved;
    const cv::Matx23d shift(1.0, 0.0, off.x(), 0.0, 1.0, off.y());
    cv::warpAffine(belief_[static_cast<std::size_t>(o)], moved, shift, belief_[static_cast<std::size_t>(o)].size(), cv::INTER_LINEAR,
                   cv::BORDER_CONSTANT, cv::Scalar(0));
    p.scores.push_back(moved);
  }
  return p;
}

}  // namespace floorcast
