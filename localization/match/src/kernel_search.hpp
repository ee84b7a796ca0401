// Exact branch-and-bound search for the kernel matcher's modes (private to match/).
//
// The kernel matcher's heatmap of (orientation o, scale s) at cell x is
//
//   h(o, s, x) = sum_d P(d) F(x + d) - alpha' sum_d E(d) G(x + d),
//
// with P >= 0 the normalised RW kernel, E the 0/1 certainly-empty-space (CES) kernel, F the plan
// raster and G the raster the CES is tested against (both 0/1), alpha' = correlation_alpha(alpha).
// The posterior's slice o is max_s of h clipped at zero_below and masked by the valid area; its
// argmax and greedy-NMS top-K are what the search returns, without computing the posterior.
//
// Search: best-first over nodes (o, s, level h, square of 2^h x 2^h cells), keyed by an upper
// bound of h over the node, which is admissible (never below the value of any cell inside):
//   - valid area: a node without a valid cell is dropped (summed-area table of the valid mask);
//   - CES: for every translation t in the node, the CES kernel covers the "core"
//     E_h(u) = min_{t in [0, 2^h)^2} E(u - t) (E eroded towards the node's extent), so the count of
//     G pixels under the core (under rectangles inside it: bands of rows intersected, counted with
//     a summed-area table of G) is a lower bound of every cell's CES hits;
//   - RW: P = c W blur(L) with L the observed line pixels, W the distance weight and c >= the
//     normalisation, so sum_d P(d) F(x + d) <= c sum_{l in L} Wmax(l) Fb(x + l) with Fb the plan
//     raster blurred with the same Gaussian and Wmax(l) the largest weight the blur spreads l to.
//     Over a node, Fb(x + t + l) is bounded by Fb max-pooled over a window covering the node and
//     the group of line pixels l shares (line pixels grouped in 2^(h-1) squares, one lookup per
//     group). Maps are quantised upwards to 8 bits; a relative margin of 1e-4 covers all float
//     round-off.
// Leaves (one cell) are first keyed by their exact CES count and the per-pixel RW bound, and
// evaluated exactly (dense dot product of P with F, float lanes summed in double) only when that
// key reaches the top of the queue. Evaluated leaves leave the queue in exactly descending score
// order (ties: lowest slice, row, column, as Posterior::argmax), and greedy NMS over that stream is
// Posterior::top_k: a leaf or node wholly within an accepted mode's separation is dropped.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "floorcast/core/grid.hpp"
#include "floorcast/match/kernel_matcher.hpp"
#include "floorcast/match/posterior.hpp"

namespace floorcast::detail {

/// The per-plan maps of the search.
class KernelSearchMaps {
 public:
  /// plan_raster / ces_raster / valid: CV_8U on the grid (non-zero = set). blur: the RW Gaussian
  /// (size 0 or 1, or sigma 0: no blur). levels: the coarsest node is 2^levels cells wide.
  KernelSearchMaps(const cv::Mat& plan_raster, const cv::Mat& ces_raster, const cv::Mat& valid, int radius_px,
                   int levels, int blur_size_px, double blur_sigma_px);

  std::size_t bytes() const;
  int levels() const { return levels_; }
  /// Side of the max-pooling window of level h's RW bound.
  int window(int h) const { return h == 0 ? 1 : (1 << h) + (1 << (h - 1)) - 1; }

  int H = 0, W = 0, R = 0;
  int pad_lo = 0;  ///< padded index = (row + pad_lo) * PW + col + pad_lo
  int PH = 0, PW = 0;
  std::vector<std::uint8_t> f;                ///< padded plan raster, 0/1
  /// Per level h: ceil(max over [y, y + window(h))^2 of Fb / fb_step) at padded positions that
  /// are multiples of stride(h) (the only ones level h reads: node anchors are multiples of 2^h,
  /// line groups of stride(h)), row-major with fb_cols[h] columns.
  std::vector<std::vector<std::uint8_t>> fb;
  std::vector<int> fb_cols;
  double fb_step = 0.0;
  /// Grid stride of level h's line groups and RW bound map: 2^(h-1) (1 for h <= 1).
  static int stride(int h) { return h <= 1 ? 1 : 1 << (h - 1); }
  /// Summed-area tables of the padded CES raster, sampled every q = 2^i padded pixels ([i]): entry
  /// (a, b) = CES raster pixels in padded [0, a q) x [0, b q). Level h's rectangles have their
  /// corners on the lattice of sat_step(h) (a node's padded anchor is row0 + R - R = row0, a
  /// multiple of 2^h), so coarse levels read small tables.
  std::vector<std::vector<std::int32_t>> g_sat;
  std::vector<int> g_sat_cols;
  static int sat_step(int h) { return h <= 2 ? 1 : 1 << (h - 2); }
  static int sat_index(int h) { return h <= 2 ? 0 : h - 2; }
  /// Per level h: 1 where the node of 2^h x 2^h cells anchored at (i 2^h, j 2^h) holds a valid
  /// cell ([0]: the valid mask itself), row-major with valid_cols[h] columns.
  std::vector<std::vector<std::uint8_t>> valid_any;
  std::vector<int> valid_cols;
  bool valid_node(int h, int r0, int c0) const {
    return valid_any[static_cast<std::size_t>(h)][static_cast<std::size_t>(r0 >> h) * valid_cols[static_cast<std::size_t>(h)] +
                                                  static_cast<std::size_t>(c0 >> h)] != 0;
  }

 private:
  int levels_ = 0;
};

/// One (orientation, scale)'s kernels in the search's form.
struct SearchKernel {
  struct Run {
    std::int32_t map_offset;  ///< padded-map offset of the run's first pixel from the cell
    std::int32_t weight_offset;
    std::int32_t length;  ///< multiple of 8 (zero weights pad it)
  };
  /// A rectangle of kernel pixels, as the four offsets of its corners in a summed-area table
  /// (g_sat[sat_index(h)] of its level) from the node's anchor entry.
  struct Rect {
    std::int32_t o00, o01, o10, o11;
  };
  struct Group {
    std::int32_t map_offset;
    float weight;
  };
  std::vector<Run> p_runs;
  std::vector<float> p_weights;
  double p_upper = 0.0;                          ///< >= every cell's RW part (0: P is all zero)
  bool has_leaf_data = false;                    ///< p_runs / p_weights are filled
  std::vector<Rect> ces_rows;                ///< E row by row (exact counts)
  std::vector<std::vector<Rect>> ces_core;   ///< [h]: rectangles inside the core E_h ([0]: ces_rows)
  std::vector<std::vector<Group>> line_groups;   ///< [h]: grouped line pixels with their weights
};

/// The geometry of one (orientation, scale)'s kernels, as make_layout_kernels builds them, and
/// what the search needs to bound them.
struct SearchKernelInput {
  cv::Mat ces;    ///< CV_8U K x K, non-zero = CES
  cv::Mat lines;  ///< CV_8U K x K: the RW's line pixels (after the range window)
  double p_scale = 0.0;  ///< c with P <= c * W * blur(lines), to float round-off; 0: P is all zero
  double resolution_m = 0.1;
  double distance_sigma_m = 0.0;
  int blur_half_px = 0;
};

/// The search kernel of one (orientation, scale) as the kernel matcher builds it (kernel_matcher.cpp):
/// geometry as make_layout_kernels, P only with_leaf_data; the RW line pixels into *lines.
SearchKernel build_search_kernel(const KernelMatcherParams& params, const std::vector<Segment2>& obs, double yaw,
                                 double scale, const cv::Mat& weight, const KernelSearchMaps& maps, bool with_leaf_data,
                                 cv::Mat* lines = nullptr);

/// The search kernel's bounds and exact CES (P itself comes later: add_leaf_data).
SearchKernel make_search_kernel(const SearchKernelInput& in, const KernelSearchMaps& maps);
/// P (CV_32F K x K) as dense runs, for exact cell values.
void add_leaf_data(SearchKernel& kernel, const cv::Mat& p, const KernelSearchMaps& maps);

struct SearchRequest {
  /// Called (from the searching thread) before kernel j's first exact cell value, to add_leaf_data.
  std::function<void(std::size_t j, SearchKernel& kernel)> leaf_data;
  int num_scales = 1;
  std::vector<double> yaw_rad;  ///< per orientation slice
  double alpha = 1.5;           ///< correlation_alpha
  double zero_below = 1e-4;
  int top_k = 1;
  double separation_m = 1.0;
  double separation_rad = 0.5235987755982988;
};

/// Modes (best first, Posterior::top_k semantics) over kernels[o * num_scales + s].
std::vector<PoseHypothesis> branch_and_bound_modes(const KernelSearchMaps& maps, const GridSpec& grid,
                                                   std::vector<SearchKernel>& kernels, const SearchRequest& request,
                                                   std::map<std::string, double>* counters);

/// The search's upper bound of every cell value in node (h, r0, c0) (r0, c0 multiples of 2^h), or
/// -inf when the node holds no valid cell or its CES hits alone push every value below
/// floor_score (then *ces_drop is set).
double node_upper_bound(const KernelSearchMaps& maps, const SearchKernel& kernel, double alpha, double floor_score,
                        int h, int r0, int c0, bool* ces_drop = nullptr);

/// The search's exact value h(o, s, cell) of one kernel at one cell (no clipping, no mask).
double exact_cell_score(const KernelSearchMaps& maps, const SearchKernel& kernel, double alpha, int row, int col);

}  // namespace floorcast::detail
