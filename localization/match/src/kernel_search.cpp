#include "kernel_search.hpp"

#include <algorithm>
#include <array>
#include <functional>
#include <cmath>
#include <cstring>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <queue>
#include <stdexcept>

#include "floorcast/core/types.hpp"

namespace floorcast::detail {
namespace {

/// Relative and absolute margins added to every RW bound: far above the float round-off of the
/// blur, the weights and the quantised maps (~1e-6 relative), far below any score difference the
/// search needs to tell apart.
constexpr double kBoundRelMargin = 1e-4;
constexpr double kBoundAbsMargin = 1e-7;
/// Rows per rectangle band of the CES cores.
constexpr int kCoreBand = 4;

/// out[i] = max(in[i .. i + w - 1]) (0 past the end), van Herk / Gil-Werman: O(1) per element.
void sliding_max(const std::uint8_t* in, int n, int w, std::uint8_t* out) {
  if (w <= 1) {
    std::memcpy(out, in, static_cast<std::size_t>(n));
    return;
  }
  static thread_local std::vector<std::uint8_t> pre, suf;
  const int m = (n + w - 1) / w * w + w;  // whole blocks, plus one of zeros
  pre.assign(static_cast<std::size_t>(m), 0);
  suf.assign(static_cast<std::size_t>(m), 0);
  for (int i = 0; i < m; ++i) {
    const std::uint8_t v = i < n ? in[i] : 0;
    pre[static_cast<std::size_t>(i)] = i % w == 0 ? v : std::max(pre[static_cast<std::size_t>(i) - 1], v);
  }
  for (int i = m - 1; i >= 0; --i) {
    const std::uint8_t v = i < n ? in[i] : 0;
    suf[static_cast<std::size_t>(i)] = (i + 1) % w == 0 ? v : std::max(suf[static_cast<std::size_t>(i) + 1], v);
  }
  for (int i = 0; i < n; ++i) out[i] = std::max(suf[static_cast<std::size_t>(i)], pre[static_cast<std::size_t>(i + w - 1)]);
}

}  // namespace

KernelSearchMaps::KernelSearchMaps(const cv::Mat& plan, const cv::Mat& ces, const cv::Mat& valid, int radius_px,
                                   int levels, int blur_size_px, double blur_sigma_px)
    : levels_(levels) {
  if (plan.type() != CV_8U || ces.type() != CV_8U || valid.type() != CV_8U || plan.size() != ces.size() ||
      plan.size() != valid.size()) {
    throw std::invalid_argument("KernelSearchMaps: rasters must be CV_8U of one size");
  }
  if (levels < 1 || levels > 12) throw std::invalid_argument("KernelSearchMaps: levels must be in [1, 12]");
  H = plan.rows;
  W = plan.cols;
  R = radius_px;
  pad_lo = R;
  // Lookups reach row + dr + window - 1 <= H - 1 + R + window(levels); dot products read up to 7
  // zero-weighted pixels past a run's end.
  const int pad_hi = R + window(levels) + 8;
  PH = H + pad_lo + pad_hi;
  PW = W + pad_lo + pad_hi;

  cv::Mat fpad = cv::Mat::zeros(PH, PW, CV_8U);
  cv::Mat plan01 = plan != 0;
  plan01 /= 255;
  plan01.copyTo(fpad(cv::Rect(pad_lo, pad_lo, W, H)));
  f.assign(fpad.datastart, fpad.dataend);

  // Fb: the plan raster blurred with the RW's Gaussian (the same OpenCV call on float data).
  cv::Mat fb_f;
  fpad.convertTo(fb_f, CV_32F);
  if (blur_size_px > 1 && blur_sigma_px > 0.0) {
    cv::GaussianBlur(fb_f, fb_f, cv::Size(blur_size_px, blur_size_px), blur_sigma_px, blur_sigma_px,
                     cv::BORDER_CONSTANT);
  }
  double fb_max = 0.0;
  cv::minMaxLoc(fb_f, nullptr, &fb_max);
  fb_step = fb_max > 0.0 ? fb_max / 255.0 : 1.0;
  cv::Mat q(PH, PW, CV_8U);
  for (int r = 0; r < PH; ++r) {
    const float* src = fb_f.ptr<float>(r);
    std::uint8_t* dst = q.ptr<std::uint8_t>(r);
    for (int c = 0; c < PW; ++c) {
      const double v = std::ceil(static_cast<double>(src[c]) / fb_step);
      dst[c] = static_cast<std::uint8_t>(std::min(255.0, std::max(0.0, v)));
    }
  }
  fb.resize(static_cast<std::size_t>(levels) + 1);
  fb_cols.resize(static_cast<std::size_t>(levels) + 1);
  std::vector<std::uint8_t> line_in, line_out;
  for (int h = 0; h <= levels; ++h) {
    const int w = window(h), st = stride(h);
    const int rows = (PH + st - 1) / st, cols = (PW + st - 1) / st;
    // Row pass (max over [x, x + w) at every st-th column), then column pass (every st-th row).
    std::vector<std::uint8_t> tmp(static_cast<std::size_t>(PH) * cols);
    line_out.resize(static_cast<std::size_t>(std::max(PH, PW)));
    for (int r = 0; r < PH; ++r) {
      sliding_max(q.ptr<std::uint8_t>(r), PW, w, line_out.data());
      for (int c = 0; c < cols; ++c) tmp[static_cast<std::size_t>(r) * cols + c] = line_out[static_cast<std::size_t>(c) * st];
    }
    std::vector<std::uint8_t>& out = fb[static_cast<std::size_t>(h)];
    out.assign(static_cast<std::size_t>(rows) * cols + 4, 0);  // + 4: 32-bit gathers of the last bytes
    line_in.resize(static_cast<std::size_t>(PH));
    for (int c = 0; c < cols; ++c) {
      for (int r = 0; r < PH; ++r) line_in[static_cast<std::size_t>(r)] = tmp[static_cast<std::size_t>(r) * cols + c];
      sliding_max(line_in.data(), PH, w, line_out.data());
      for (int r = 0; r < rows; ++r) out[static_cast<std::size_t>(r) * cols + c] = line_out[static_cast<std::size_t>(r) * st];
    }
    fb_cols[static_cast<std::size_t>(h)] = cols;
  }

  // Summed-area table of the CES raster on the padded grid, then its lattice samples.
  const std::size_t sw = static_cast<std::size_t>(PW) + 1;
  std::vector<std::int32_t> sat(static_cast<std::size_t>(PH + 1) * sw, 0);
  for (int r = 0; r < PH; ++r) {
    const int gr = r - pad_lo;
    const std::uint8_t* g = gr >= 0 && gr < H ? ces.ptr<std::uint8_t>(gr) : nullptr;
    const std::int32_t* above = sat.data() + static_cast<std::size_t>(r) * sw;
    std::int32_t* row = sat.data() + static_cast<std::size_t>(r + 1) * sw;
    std::int32_t acc = 0;
    for (int c = 0; c < PW; ++c) {
      const int gc = c - pad_lo;
      if (g && gc >= 0 && gc < W && g[gc]) ++acc;
      row[c + 1] = above[c + 1] + acc;
    }
  }
  const int n_sat = sat_index(levels) + 1;
  g_sat.resize(static_cast<std::size_t>(n_sat));
  g_sat_cols.resize(static_cast<std::size_t>(n_sat));
  for (int i = 1; i < n_sat; ++i) {
    const int q = 1 << i;
    const int rows = PH / q + 1, cols = PW / q + 1;
    std::vector<std::int32_t>& t = g_sat[static_cast<std::size_t>(i)];
    t.resize(static_cast<std::size_t>(rows) * cols);
    for (int a = 0; a < rows; ++a)
      for (int b = 0; b < cols; ++b)
        t[static_cast<std::size_t>(a) * cols + b] = sat[static_cast<std::size_t>(a) * q * sw + static_cast<std::size_t>(b) * q];
    g_sat_cols[static_cast<std::size_t>(i)] = cols;
  }
  g_sat[0] = std::move(sat);
  g_sat_cols[0] = PW + 1;

  // Nodes holding a valid cell, per level.
  valid_any.resize(static_cast<std::size_t>(levels) + 1);
  valid_cols.resize(static_cast<std::size_t>(levels) + 1);
  for (int h = 0; h <= levels; ++h) {
    const int side = 1 << h, rows = (H + side - 1) / side, cols = (W + side - 1) / side;
    std::vector<std::uint8_t>& v = valid_any[static_cast<std::size_t>(h)];
    v.assign(static_cast<std::size_t>(rows) * cols, 0);
    for (int r = 0; r < H; ++r) {
      const std::uint8_t* m = valid.ptr<std::uint8_t>(r);
      std::uint8_t* dst = v.data() + static_cast<std::size_t>(r >> h) * cols;
      for (int c = 0; c < W; ++c)
        if (m[c]) dst[c >> h] = 1;
    }
    valid_cols[static_cast<std::size_t>(h)] = cols;
  }
}

std::size_t KernelSearchMaps::bytes() const {
  std::size_t b = f.size();
  for (const auto& m : fb) b += m.size();
  for (const auto& t : g_sat) b += t.size() * sizeof(std::int32_t);
  for (const auto& v : valid_any) b += v.size();
  return b;
}

namespace {

/// Runs of set pixels of one row of `mask` (CV_8U 0/1) within [x0, x1), as [c0, c1) pairs.
void runs_of_row(const std::uint8_t* m, int x0, int x1, std::vector<std::pair<int, int>>& out) {
  out.clear();
  int c = x0;
  while (c < x1) {
    while (c < x1 && !m[c]) ++c;
    if (c >= x1) break;
    const int c0 = c;
    while (c < x1 && m[c]) ++c;
    out.emplace_back(c0, c);
  }
}

/// Rectangles inside `mask` (CV_8U 0/1, the part of a kernel image at kernel pixel `tl`) on the
/// lattice of step q in kernel pixels: lattice blocks wholly inside the mask, bands of `band`
/// block rows intersected, every run of an intersection a rectangle; as offsets in a summed-area
/// table sampled every q pixels with `sat_cols` columns.
std::vector<SearchKernel::Rect> lattice_rects(const cv::Mat& mask, cv::Point tl, int q, int band, int sat_cols) {
  std::vector<SearchKernel::Rect> rects;
  if (cv::countNonZero(mask) == 0) return rects;
  const cv::Rect box = cv::boundingRect(mask) + tl;  // in kernel pixels
  // Lattice blocks [i q, (i + 1) q) wholly inside the box.
  const int i0 = (box.y + q - 1) / q, i1 = (box.y + box.height) / q;
  const int j0 = (box.x + q - 1) / q, j1 = (box.x + box.width) / q;
  if (i1 <= i0 || j1 <= j0) return rects;
  const int ni = i1 - i0, nj = j1 - j0;
  std::vector<std::uint8_t> blocks(static_cast<std::size_t>(ni) * nj, 1);
  for (int i = 0; i < ni; ++i) {
    std::uint8_t* brow = blocks.data() + static_cast<std::size_t>(i) * nj;
    for (int y = (i0 + i) * q; y < (i0 + i + 1) * q; ++y) {
      const std::uint8_t* m = mask.ptr<std::uint8_t>(y - tl.y) - tl.x;  // indexed by kernel column
      for (int j = 0; j < nj; ++j) {
        if (!brow[j]) continue;
        const int x = (j0 + j) * q;
        for (int k = 0; k < q; ++k) brow[j] &= m[x + k];
      }
    }
  }
  std::vector<std::uint8_t> acc(static_cast<std::size_t>(nj));
  std::vector<std::pair<int, int>> runs;
  for (int i = 0; i < ni; i += band) {
    const int ie = std::min(ni, i + band);
    std::memcpy(acc.data(), blocks.data() + static_cast<std::size_t>(i) * nj, static_cast<std::size_t>(nj));
    for (int r = i + 1; r < ie; ++r)
      for (int j = 0; j < nj; ++j) acc[static_cast<std::size_t>(j)] &= blocks[static_cast<std::size_t>(r) * nj + j];
    runs_of_row(acc.data(), 0, nj, runs);
    for (const auto& [c0, c1] : runs) {
      const int a0 = i0 + i, a1 = i0 + ie, b0 = j0 + c0, b1 = j0 + c1;
      rects.push_back({a0 * sat_cols + b0, a0 * sat_cols + b1, a1 * sat_cols + b0, a1 * sat_cols + b1});
    }
  }
  return rects;
}

}  // namespace

void add_leaf_data(SearchKernel& k, const cv::Mat& P, const KernelSearchMaps& maps) {
  const int K = P.rows, R = (K - 1) / 2;
  if (R != maps.R || P.type() != CV_32F) throw std::invalid_argument("add_leaf_data: kernel radius or type");
  const int PW = maps.PW;
  k.p_runs.clear();
  k.p_weights.clear();
  // Dense runs of P (split at gaps of 8 or more zeros), padded to multiples of 8.
  cv::Mat nz = P > 0.0f;
  if (cv::countNonZero(nz) > 0) {
    const cv::Rect box = cv::boundingRect(nz);
    for (int r = box.y; r < box.y + box.height; ++r) {
      const float* p = P.ptr<float>(r);
      int c = box.x;
      const int end = box.x + box.width;
      while (c < end) {
        while (c < end && !(p[c] > 0.0f)) ++c;
        if (c >= end) break;
        const int c0 = c;
        int last = c;  // last non-zero
        while (c < end && c - last < 8) {
          if (p[c] > 0.0f) last = c;
          ++c;
        }
        const int len = last + 1 - c0;
        const int padded = (len + 7) / 8 * 8;
        SearchKernel::Run run;
        run.map_offset = (r - R) * PW + (c0 - R);
        run.weight_offset = static_cast<std::int32_t>(k.p_weights.size());
        run.length = padded;
        for (int i = 0; i < padded; ++i) k.p_weights.push_back(i < len ? p[c0 + i] : 0.0f);
        k.p_runs.push_back(run);
        c = last + 1;
      }
    }
  }
  k.has_leaf_data = true;
}

SearchKernel make_search_kernel(const SearchKernelInput& in, const KernelSearchMaps& maps) {
  SearchKernel k;
  const int K = in.lines.rows, R = (K - 1) / 2;
  if (R != maps.R) throw std::invalid_argument("make_search_kernel: kernel radius differs from the maps'");
  const int L = maps.levels();
  // P sums to 1 (min-max scaled, divided by its sum): every cell's RW part is at most that, up to
  // float round-off (< 1e-5 relative for the sums here).
  k.p_upper = in.p_scale > 0.0 ? 1.0 + 1e-3 : 0.0;

  // CES: exact rows and rectangles inside the cores of every level, all within E's bounding box
  // (the cores shrink towards its far corner).
  cv::Mat e = in.ces != 0;
  e /= 255;  // 0/1
  k.ces_core.resize(static_cast<std::size_t>(L) + 1);
  if (cv::countNonZero(e) > 0) {
    const cv::Rect box = cv::boundingRect(e);
    cv::Mat prev = e(box).clone();
    k.ces_rows = lattice_rects(prev, box.tl(), 1, 1, maps.g_sat_cols[0]);
    k.ces_core[0] = k.ces_rows;
    for (int h = 1; h <= L; ++h) {
      const int s = 1 << (h - 1);
      cv::Mat cur = cv::Mat::zeros(prev.size(), CV_8U);
      const int nr = prev.rows - s, nc = prev.cols - s;
      if (nr > 0 && nc > 0) {
        cv::Mat dst = cur(cv::Rect(s, s, nc, nr));
        cv::bitwise_and(prev(cv::Rect(s, s, nc, nr)), prev(cv::Rect(0, s, nc, nr)), dst);
        cv::bitwise_and(dst, prev(cv::Rect(s, 0, nc, nr)), dst);
        cv::bitwise_and(dst, prev(cv::Rect(0, 0, nc, nr)), dst);
      }
      const int q = KernelSearchMaps::sat_step(h);
      k.ces_core[static_cast<std::size_t>(h)] =
          lattice_rects(cur, box.tl(), q, std::max(1, kCoreBand / q),
                        maps.g_sat_cols[static_cast<std::size_t>(KernelSearchMaps::sat_index(h))]);
      prev = cur;
    }
  }

  // Line pixels with the largest distance weight their blur reaches, grouped per level.
  std::vector<cv::Point> pts;
  if (cv::countNonZero(in.lines) > 0) {
    const cv::Rect box = cv::boundingRect(in.lines);
    cv::findNonZero(in.lines(box), pts);
    for (cv::Point& p : pts) p += box.tl();
  }
  std::vector<double> wmax(pts.size());
  const double inv2s2 =
      in.distance_sigma_m > 0.0 ? 1.0 / (2.0 * in.distance_sigma_m * in.distance_sigma_m) : 0.0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const double dx = std::max(0, std::abs(pts[i].x - R) - in.blur_half_px) * in.resolution_m;
    const double dy = std::max(0, std::abs(pts[i].y - R) - in.blur_half_px) * in.resolution_m;
    wmax[i] = std::exp(-(dx * dx + dy * dy) * inv2s2);
  }
  const double scale = in.p_scale * maps.fb_step * (1.0 + kBoundRelMargin);
  k.line_groups.resize(static_cast<std::size_t>(L) + 1);
  std::vector<std::pair<std::int64_t, double>> keyed(pts.size());
  for (int h = 0; h <= L; ++h) {
    const int g = KernelSearchMaps::stride(h);
    const int n = (K + g - 1) / g;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      keyed[i] = {static_cast<std::int64_t>(pts[i].y / g) * n + pts[i].x / g, wmax[i]};
    }
    std::sort(keyed.begin(), keyed.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    // Level h reads its map at padded (row0 + R + gr g - R, ...) / stride = row0 / stride + gr for
    // strides g > 1 (node anchors are multiples of 2^h); at stride 1 offsets are plain pixels.
    const int cols = maps.fb_cols[static_cast<std::size_t>(h)];
    auto& groups = k.line_groups[static_cast<std::size_t>(h)];
    for (std::size_t i = 0; i < keyed.size();) {
      std::size_t e = i;
      double w = 0.0;
      for (; e < keyed.size() && keyed[e].first == keyed[i].first; ++e) w += keyed[e].second;
      const int gr = static_cast<int>(keyed[i].first / n), gc = static_cast<int>(keyed[i].first % n);
      const int off = g == 1 ? (gr - R) * cols + (gc - R) : gr * cols + gc;
      groups.push_back({off, static_cast<float>(w * scale * (1.0 + 1e-6))});
      i = e;
    }
  }
  return k;
}

namespace {

#if defined(__GNUC__) && defined(__x86_64__) && !defined(__clang__)
__attribute__((target_clones("avx2", "default")))
#endif
double runs_dot(const float* weights, const SearchKernel::Run* runs, std::size_t n, const std::uint8_t* f) {
  double total = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const float* w = weights + runs[i].weight_offset;
    const std::uint8_t* m = f + runs[i].map_offset;
    float acc[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    for (int j = 0; j < runs[i].length; j += 8) {
      for (int k = 0; k < 8; ++k) acc[k] += w[j + k] * static_cast<float>(m[j + k]);
    }
    total += static_cast<double>(((acc[0] + acc[1]) + (acc[2] + acc[3])) + ((acc[4] + acc[5]) + (acc[6] + acc[7])));
  }
  return total;
}

/// sum_g weight_g * m[offset_g]: eight float lanes (throughput, not add latency); the lanes' round-off
/// (< 1e-5 relative for the group counts here) is far inside kBoundRelMargin.
double groups_dot_portable(const SearchKernel::Group* g, std::size_t n, const std::uint8_t* m) {
  float acc[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  std::size_t i = 0;
  for (; i + 8 <= n; i += 8) {
    for (int k = 0; k < 8; ++k) acc[k] += g[i + k].weight * static_cast<float>(m[g[i + k].map_offset]);
  }
  for (; i < n; ++i) acc[i % 8] += g[i].weight * static_cast<float>(m[g[i].map_offset]);
  return static_cast<double>(((acc[0] + acc[1]) + (acc[2] + acc[3])) + ((acc[4] + acc[5]) + (acc[6] + acc[7])));
}

double groups_dot(const std::vector<SearchKernel::Group>& groups, const std::uint8_t* m) {
  return groups_dot_portable(groups.data(), groups.size(), m);
}

/// CES pixels under `rects` on G, for the cell / node whose padded SAT index is `sat`; stops
/// counting once `stop` is reached.
int ces_count(const std::vector<SearchKernel::Rect>& rects, const std::int32_t* sat, int stop) {
  int n = 0;
  for (const SearchKernel::Rect& r : rects) {
    n += sat[r.o11] - sat[r.o01] - sat[r.o10] + sat[r.o00];
    if (n >= stop) return n;
  }
  return n;
}

/// A queue entry: its key (an upper bound, or a cell's exact value) and a tag that orders equal
/// keys: bounds before exact values, exact values by lowest (slice, row, column) first.
struct Node {
  std::uint64_t key;  ///< the bits of a positive double: same order
  std::uint64_t tag;
};

std::uint64_t key_bits(double v) {
  std::uint64_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}
double key_value(std::uint64_t b) {
  double v;
  std::memcpy(&v, &b, sizeof v);
  return v;
}

constexpr int kSliceBits = 12, kRowBits = 20, kColBits = 20, kLevelBits = 4, kScaleBits = 7;
constexpr std::uint64_t mask(int bits) { return (std::uint64_t{1} << bits) - 1; }

std::uint64_t make_tag(bool exact, int o, int row, int col, int level, int s) {
  return (exact ? std::uint64_t{0} : std::uint64_t{1}) << 63 |
         (mask(kSliceBits) - static_cast<std::uint64_t>(o)) << (kRowBits + kColBits + kLevelBits + kScaleBits) |
         (mask(kRowBits) - static_cast<std::uint64_t>(row)) << (kColBits + kLevelBits + kScaleBits) |
         (mask(kColBits) - static_cast<std::uint64_t>(col)) << (kLevelBits + kScaleBits) |
         static_cast<std::uint64_t>(level) << kScaleBits | static_cast<std::uint64_t>(s);
}
struct Decoded {
  bool exact;
  int o, row, col, level, s;
};
Decoded decode(std::uint64_t t) {
  Decoded d;
  d.exact = (t >> 63) == 0;
  d.o = static_cast<int>(mask(kSliceBits) - ((t >> (kRowBits + kColBits + kLevelBits + kScaleBits)) & mask(kSliceBits)));
  d.row = static_cast<int>(mask(kRowBits) - ((t >> (kColBits + kLevelBits + kScaleBits)) & mask(kRowBits)));
  d.col = static_cast<int>(mask(kColBits) - ((t >> (kLevelBits + kScaleBits)) & mask(kColBits)));
  d.level = static_cast<int>((t >> kScaleBits) & mask(kLevelBits));
  d.s = static_cast<int>(t & mask(kScaleBits));
  return d;
}

struct NodeLess {
  bool operator()(const Node& a, const Node& b) const { return a.key < b.key || (a.key == b.key && a.tag < b.tag); }
};

/// A max-priority queue of nodes (order: NodeLess) in buckets of key ranges: a push below the
/// current top bucket is an append (most nodes are never popped: the modes score above them);
/// only the top bucket is a heap, built when it becomes the top.
class BucketQueue {
 public:
  explicit BucketQueue(int buckets_per_unit) : scale_(buckets_per_unit), buckets_(static_cast<std::size_t>(buckets_per_unit) + 2) {}
  bool empty() const { return size_ == 0; }
  std::size_t size() const { return size_; }
  void push(const Node& n) {
    const std::size_t b = bucket(n.key);
    auto& v = buckets_[b];
    v.push_back(n);
    if (b == top_ && heap_) {
      std::push_heap(v.begin(), v.end(), NodeLess{});
    } else if (b > top_ || size_ == 0) {
      top_ = b;
      heap_ = false;
    }
    ++size_;
  }
  /// The maximum; the queue must not be empty.
  const Node& top() {
    settle();
    return buckets_[top_].front();
  }
  void pop() {
    settle();
    auto& v = buckets_[top_];
    std::pop_heap(v.begin(), v.end(), NodeLess{});
    v.pop_back();
    --size_;
  }

 private:
  std::size_t bucket(std::uint64_t key_bits_) const {
    const double k = key_value(key_bits_);
    const double b = std::floor(k * scale_) + 1.0;  // keys below 0 would go to bucket 0
    return static_cast<std::size_t>(std::min<double>(std::max(b, 0.0), static_cast<double>(buckets_.size() - 1)));
  }
  void settle() {
    while (buckets_[top_].empty()) {
      --top_;
      heap_ = false;
    }
    if (!heap_) {
      std::make_heap(buckets_[top_].begin(), buckets_[top_].end(), NodeLess{});
      heap_ = true;
    }
  }
  double scale_;
  std::vector<std::vector<Node>> buckets_;
  std::size_t top_ = 0;
  bool heap_ = false;
  std::size_t size_ = 0;
};

}  // namespace

double node_upper_bound(const KernelSearchMaps& maps, const SearchKernel& k, double alpha, double floor_score, int h,
                        int r0, int c0, bool* ces_drop) {
  constexpr double kDrop = -std::numeric_limits<double>::infinity();
  if (!maps.valid_node(h, r0, c0)) return kDrop;
  const double p_up = k.p_upper;
  // CES hits that drive any value with RW part <= p_up to <= 0.
  const int stop = alpha > 0.0 ? static_cast<int>(std::max(1.0, std::min(std::ceil(p_up / alpha), 1e9))) : 1 << 30;
  const int i = KernelSearchMaps::sat_index(h), q = KernelSearchMaps::sat_step(h);
  const std::int32_t* sat = maps.g_sat[static_cast<std::size_t>(i)].data() +
                            static_cast<std::size_t>(r0 / q) * maps.g_sat_cols[static_cast<std::size_t>(i)] +
                            static_cast<std::size_t>(c0 / q);
  const double ces = alpha * ces_count(k.ces_core[static_cast<std::size_t>(h)], sat, stop);
  if (!(p_up - ces >= floor_score && p_up - ces > 0.0)) {
    if (ces_drop) *ces_drop = true;
    return kDrop;
  }
  // Level h's RW bound map at the node's anchor.
  const int st = KernelSearchMaps::stride(h);
  const std::size_t cols = static_cast<std::size_t>(maps.fb_cols[static_cast<std::size_t>(h)]);
  const std::size_t base = st == 1 ? static_cast<std::size_t>(r0 + maps.pad_lo) * cols + (c0 + maps.pad_lo)
                                   : static_cast<std::size_t>(r0 / st) * cols + static_cast<std::size_t>(c0 / st);
  const double rw =
      groups_dot(k.line_groups[static_cast<std::size_t>(h)], maps.fb[static_cast<std::size_t>(h)].data() + base) +
      kBoundAbsMargin;
  return std::min(rw, p_up) - ces;
}

double exact_cell_score(const KernelSearchMaps& maps, const SearchKernel& k, double alpha, int row, int col) {
  const std::size_t base = static_cast<std::size_t>(row + maps.pad_lo) * maps.PW + (col + maps.pad_lo);
  const double p = runs_dot(k.p_weights.data(), k.p_runs.data(), k.p_runs.size(), maps.f.data() + base);
  const std::size_t sat = static_cast<std::size_t>(row) * maps.g_sat_cols[0] + col;
  const int n = ces_count(k.ces_rows, maps.g_sat[0].data() + sat, std::numeric_limits<int>::max());
  return p - alpha * n;
}

std::vector<PoseHypothesis> branch_and_bound_modes(const KernelSearchMaps& maps, const GridSpec& grid,
                                                   std::vector<SearchKernel>& kernels, const SearchRequest& rq,
                                                   std::map<std::string, double>* counters) {
  std::vector<PoseHypothesis> modes;
  const int S = rq.num_scales;
  if (kernels.empty() || rq.top_k <= 0) return modes;
  const int O = static_cast<int>(rq.yaw_rad.size());
  if (static_cast<int>(kernels.size()) != S * O) {
    throw std::invalid_argument("branch_and_bound_modes: kernel count differs from orientations x scales");
  }
  const int H = maps.H, W = maps.W, L = maps.levels();
  if (O > static_cast<int>(mask(kSliceBits)) || S > static_cast<int>(mask(kScaleBits)) ||
      H > static_cast<int>(mask(kRowBits)) || W > static_cast<int>(mask(kColBits)) || L > static_cast<int>(mask(kLevelBits))) {
    throw std::invalid_argument("branch_and_bound_modes: too many orientations, scales, rows or columns");
  }
  const double alpha = rq.alpha;
  // A mode must score >= zero_below and > 0 (Posterior::top_k takes cells with score > 0 of the
  // posterior clipped at zero_below).
  const double floor_score = rq.zero_below;
  auto admissible = [&](double v) { return v >= floor_score && v > 0.0; };
  const double res = grid.resolution_m_per_px;
  double n_bounds = 0, n_ces_drops = 0;
  double n_expanded = 0, n_leaf_keys = 0, n_exact = 0, n_suppressed = 0;
  BucketQueue queue(512);
  std::size_t max_queue = 0;

  auto bound = [&](int j, int h, int r0, int c0) -> double {
    ++n_bounds;
    bool ces_drop = false;
    const double ub = node_upper_bound(maps, kernels[static_cast<std::size_t>(j)], alpha, floor_score, h, r0, c0, &ces_drop);
    n_ces_drops += ces_drop;
    return ub;
  };
  double n_pushes = 0;
  auto push = [&](double key, bool exact, int j, int row, int col, int level) {
    ++n_pushes;
    queue.push({key_bits(key), make_tag(exact, j / S, row, col, level, j % S)});
  };
  auto ensure_leaf_data = [&](int j) {
    SearchKernel& k = kernels[static_cast<std::size_t>(j)];
    if (k.has_leaf_data) return;
    if (!rq.leaf_data) throw std::logic_error("branch_and_bound_modes: no leaf data for a kernel");
    rq.leaf_data(static_cast<std::size_t>(j), k);
  };

  // Roots: every kernel, the grid in squares of 2^L cells.
  const int top = 1 << L;
  for (int j = 0; j < static_cast<int>(kernels.size()); ++j) {
    if (kernels[static_cast<std::size_t>(j)].p_upper <= 0.0) continue;
    for (int r0 = 0; r0 < H; r0 += top) {
      for (int c0 = 0; c0 < W; c0 += top) {
        const double ub = bound(j, L, r0, c0);
        if (admissible(ub)) push(ub, false, j, r0, c0, L);
      }
    }
  }

  // Fully within an accepted mode's separation (position and yaw)? Inclusive cell ranges.
  auto suppressed = [&](int o, int r0, int c0, int r1, int c1) {
    for (const PoseHypothesis& m : modes) {
      if (angle_distance_rad(rq.yaw_rad[static_cast<std::size_t>(o)], m.yaw_rad) > rq.separation_rad) continue;
      const int dc = std::max(std::abs(c0 - m.col), std::abs(c1 - m.col));
      const int dr = std::max(std::abs(r0 - m.row), std::abs(r1 - m.row));
      const double dx = dc * res, dy = dr * res;
      if (std::sqrt(dx * dx + dy * dy) <= rq.separation_m + 1e-12) return true;
    }
    return false;
  };

  while (!queue.empty() && static_cast<int>(modes.size()) < rq.top_k) {
    max_queue = std::max(max_queue, queue.size());
    const Node n = queue.top();
    queue.pop();
    const Decoded d = decode(n.tag);
    const int j = d.o * S + d.s;
    const int side = 1 << d.level;
    if (!modes.empty() &&
        suppressed(d.o, d.row, d.col, std::min(H, d.row + side) - 1, std::min(W, d.col + side) - 1)) {
      ++n_suppressed;
      continue;
    }
    if (d.exact) {
      PoseHypothesis h;
      const Vec2 p = grid.cell_center_m(d.row, d.col);
      h.x_m = p.x();
      h.y_m = p.y();
      h.yaw_rad = rq.yaw_rad[static_cast<std::size_t>(d.o)];
      h.score = key_value(n.key);
      h.slice = d.o;
      h.row = d.row;
      h.col = d.col;
      modes.push_back(h);
      continue;
    }
    if (d.level == 0) {
      ++n_exact;
      ensure_leaf_data(j);
      const SearchKernel& k = kernels[static_cast<std::size_t>(j)];
      const double v = exact_cell_score(maps, k, alpha, d.row, d.col);
      if (admissible(v)) push(v, true, j, d.row, d.col, 0);
      continue;
    }
    ++n_expanded;
    const int h = d.level - 1, half = 1 << h;
    for (int dr = 0; dr < 2; ++dr) {
      for (int dc = 0; dc < 2; ++dc) {
        const int r0 = d.row + dr * half, c0 = d.col + dc * half;
        if (r0 >= H || c0 >= W) continue;
        n_leaf_keys += h == 0;
        const double ub = bound(j, h, r0, c0);
        if (admissible(ub)) push(ub, false, j, r0, c0, h);
      }
    }
  }
  if (counters) {
    (*counters)["bb_bounds"] = n_bounds;
    (*counters)["bb_ces_drops"] = n_ces_drops;
    (*counters)["bb_expanded"] = n_expanded;
    (*counters)["bb_leaf_keys"] = n_leaf_keys;
    (*counters)["bb_exact_cells"] = n_exact;
    (*counters)["bb_suppressed"] = n_suppressed;
    (*counters)["bb_pushes"] = n_pushes;
    (*counters)["bb_max_queue"] = static_cast<double>(max_queue);
  }
  return modes;
}

}  // namespace floorcast::detail
