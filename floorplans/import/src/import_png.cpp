// Occupancy image (F3Loc style: 255 free, anything else occupied) -> walls.
//
// Vectorisation: drop tiny occupied components (noise); thin the occupied mask to a one-pixel
// skeleton (Zhang-Suen, floorcast::thin_zhang_suen) and remove staircase pixels; build the skeleton graph
// (end points, junction clusters, chains between them); prune spurs the thinning grows into
// corners; split each chain into straight pieces (Douglas-Peucker); fit a line to each piece's
// pixels away from its ends; refine it against the image: at every pixel along the piece, march
// across the wall to both free boundaries — the median mid-point re-centres the line, the median
// width is the wall's thickness; finally place the ends: corners at the intersection of adjacent
// fitted lines, junction ends at the junction centre projected onto the line, free ends extended
// to the image boundary of the wall.
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include <opencv2/imgproc.hpp>

#include "floorcast/core/math.hpp"
#include "floorcast/floorplans/import.hpp"
#include "floorcast/floorplans/raster.hpp"
#include "import_common.hpp"

namespace floorcast {
namespace {

using import_detail::fmt;

constexpr int kDx[8] = {1, 1, 0, -1, -1, -1, 0, 1};
constexpr int kDy[8] = {0, 1, 1, 1, 0, -1, -1, -1};

struct Px {
  int x = 0, y = 0;
  bool operator==(const Px& o) const { return x == o.x && y == o.y; }
};

class Vectorizer {
 public:
  Vectorizer(const cv::Mat& occ_padded, const ImportOptions& options) : occ_(occ_padded), options_(options) {
    cv::distanceTransform(occ_, dist_, cv::DIST_L2, cv::DIST_MASK_PRECISE);
    skel_ = thin_zhang_suen(occ_);
  }

  struct Piece {
    Vec2 p, d;            // line point and unit direction (pixel coordinates)
    double width_px = 1.0;
    Vec2 a, b;            // final end points
  };

  std::vector<Piece> run() {
    for (int iter = 0; iter < 20; ++iter) {
      remove_staircases();
      build_graph();
      if (!prune_spurs()) break;
    }
    std::vector<Piece> out;
    for (const Edge& e : edges_) process_edge(e, out);
    return out;
  }

 private:
  struct Edge {
    std::vector<Px> chain;
    int end0 = -1, end1 = -1;  // node clusters (-1: none, a closed loop)
    bool closed = false;
  };
  struct Cluster {
    std::vector<Px> pixels;
    int degree = 0;  // skeleton degree (1 for an end point)
    Vec2 centroid = Vec2::Zero();
  };

  bool occupied(double x, double y) const {
    const int c = static_cast<int>(std::floor(x)), r = static_cast<int>(std::floor(y));
    if (r < 0 || c < 0 || r >= occ_.rows || c >= occ_.cols) return false;
    return occ_.at<uchar>(r, c) != 0;
  }
  bool skel(int x, int y) const {
    return x >= 0 && y >= 0 && x < skel_.cols && y < skel_.rows && skel_.at<uchar>(y, x) != 0;
  }
  int degree(int x, int y) const {
    int n = 0;
    for (int k = 0; k < 8; ++k) n += skel(x + kDx[k], y + kDy[k]) ? 1 : 0;
    return n;
  }
  double dist_at(const Px& p) const { return static_cast<double>(dist_.at<float>(p.y, p.x)); }

  /// Removes skeleton pixels whose neighbours stay 8-connected without them (staircase corners of
  /// the 8-connected skeleton), so that line pixels have exactly two neighbours.
  void remove_staircases() {
    for (int y = 1; y + 1 < skel_.rows; ++y) {
      for (int x = 1; x + 1 < skel_.cols; ++x) {
        if (!skel(x, y)) continue;
        int idx[8];
        int k = 0;
        for (int q = 0; q < 8; ++q) {
          if (skel(x + kDx[q], y + kDy[q])) idx[k++] = q;
        }
        if (k < 2 || k > 4) continue;
        // Are the neighbours one 8-connected group?
        int comp[8];
        for (int i = 0; i < k; ++i) comp[i] = i;
        for (int i = 0; i < k; ++i) {
          for (int j = i + 1; j < k; ++j) {
            const int dx = kDx[idx[i]] - kDx[idx[j]], dy = kDy[idx[i]] - kDy[idx[j]];
            if (std::abs(dx) <= 1 && std::abs(dy) <= 1) {
              const int ci = comp[i], cj = comp[j];
              for (int m = 0; m < k; ++m) {
                if (comp[m] == cj) comp[m] = ci;
              }
            }
          }
        }
        bool one = true;
        for (int i = 1; i < k; ++i) one = one && comp[i] == comp[0];
        if (one) skel_.at<uchar>(y, x) = 0;
      }
    }
  }

  void build_graph() {
    edges_.clear();
    clusters_.clear();
    cluster_of_.assign(static_cast<std::size_t>(skel_.rows) * static_cast<std::size_t>(skel_.cols), -1);
    std::vector<uchar> visited(cluster_of_.size(), 0);
    auto at = [&](int x, int y) { return static_cast<std::size_t>(y) * static_cast<std::size_t>(skel_.cols) + static_cast<std::size_t>(x); };
    // Node clusters: 8-connected groups of pixels whose degree is not 2.
    for (int y = 0; y < skel_.rows; ++y) {
      for (int x = 0; x < skel_.cols; ++x) {
        if (!skel(x, y) || degree(x, y) == 2 || cluster_of_[at(x, y)] >= 0) continue;
        Cluster c;
        std::vector<Px> stack{{x, y}};
        const int id = static_cast<int>(clusters_.size());
        cluster_of_[at(x, y)] = id;
        while (!stack.empty()) {
          const Px p = stack.back();
          stack.pop_back();
          c.pixels.push_back(p);
          for (int k = 0; k < 8; ++k) {
            const int nx = p.x + kDx[k], ny = p.y + kDy[k];
            if (skel(nx, ny) && degree(nx, ny) != 2 && cluster_of_[at(nx, ny)] < 0) {
              cluster_of_[at(nx, ny)] = id;
              stack.push_back({nx, ny});
            }
          }
        }
        std::sort(c.pixels.begin(), c.pixels.end(), [](const Px& a, const Px& b) { return a.y != b.y ? a.y < b.y : a.x < b.x; });
        // Degree of the cluster: skeleton pixels outside it adjacent to it.
        std::vector<std::size_t> outside;
        for (const Px& p : c.pixels) {
          c.centroid += Vec2(p.x + 0.5, p.y + 0.5);
          for (int k = 0; k < 8; ++k) {
            const int nx = p.x + kDx[k], ny = p.y + kDy[k];
            if (skel(nx, ny) && cluster_of_[at(nx, ny)] != id) outside.push_back(at(nx, ny));
          }
        }
        std::sort(outside.begin(), outside.end());
        outside.erase(std::unique(outside.begin(), outside.end()), outside.end());
        c.degree = static_cast<int>(outside.size());
        c.centroid /= static_cast<double>(c.pixels.size());
        clusters_.push_back(std::move(c));
      }
    }
    // Chains from every cluster.
    for (std::size_t ci = 0; ci < clusters_.size(); ++ci) {
      for (const Px& start : clusters_[ci].pixels) {
        for (int k = 0; k < 8; ++k) {
          const int nx = start.x + kDx[k], ny = start.y + kDy[k];
          if (!skel(nx, ny)) continue;
          const int other = cluster_of_[at(nx, ny)];
          if (other >= 0) {
            // Two clusters touching directly: a one-step chain, recorded once.
            if (other > static_cast<int>(ci)) {
              Edge e;
              e.chain = {start, {nx, ny}};
              e.end0 = static_cast<int>(ci);
              e.end1 = other;
              // Avoid duplicates from several touching pixel pairs.
              bool dup = false;
              for (const Edge& f : edges_) dup = dup || (f.chain.size() == 2 && f.end0 == e.end0 && f.end1 == e.end1);
              if (!dup) edges_.push_back(std::move(e));
            }
            continue;
          }
          if (visited[at(nx, ny)]) continue;
          Edge e;
          e.end0 = static_cast<int>(ci);
          e.chain = {start, {nx, ny}};
          visited[at(nx, ny)] = 1;
          Px prev = start, cur{nx, ny};
          while (true) {
            bool advanced = false;
            Px next_node{-1, -1};
            for (int q = 0; q < 8; ++q) {
              const int mx = cur.x + kDx[q], my = cur.y + kDy[q];
              if (!skel(mx, my) || (mx == prev.x && my == prev.y)) continue;
              if (cluster_of_[at(mx, my)] >= 0) {
                if (!(mx == start.x && my == start.y) || e.chain.size() > 2) next_node = {mx, my};
                continue;
              }
              if (visited[at(mx, my)]) continue;
              visited[at(mx, my)] = 1;
              e.chain.push_back({mx, my});
              prev = cur;
              cur = {mx, my};
              advanced = true;
              break;
            }
            if (advanced) continue;
            if (next_node.x >= 0) {
              e.chain.push_back(next_node);
              e.end1 = cluster_of_[at(next_node.x, next_node.y)];
            } else {
              e.end1 = -1;  // should not happen on a cleaned skeleton; treated as a free end
            }
            break;
          }
          edges_.push_back(std::move(e));
        }
      }
    }
    // Closed loops without any node.
    for (int y = 0; y < skel_.rows; ++y) {
      for (int x = 0; x < skel_.cols; ++x) {
        if (!skel(x, y) || cluster_of_[at(x, y)] >= 0 || visited[at(x, y)]) continue;
        Edge e;
        e.closed = true;
        Px cur{x, y};
        visited[at(x, y)] = 1;
        e.chain.push_back(cur);
        while (true) {
          bool advanced = false;
          for (int q = 0; q < 8; ++q) {
            const int mx = cur.x + kDx[q], my = cur.y + kDy[q];
            if (!skel(mx, my) || visited[at(mx, my)]) continue;
            visited[at(mx, my)] = 1;
            e.chain.push_back({mx, my});
            cur = {mx, my};
            advanced = true;
            break;
          }
          if (!advanced) break;
        }
        edges_.push_back(std::move(e));
      }
    }
  }

  bool is_free_end(int cluster) const {
    return cluster < 0 || clusters_[static_cast<std::size_t>(cluster)].degree <= 1;
  }

  /// Removes short branches from a junction to a free end; true if anything changed.
  bool prune_spurs() {
    bool changed = false;
    for (const Edge& e : edges_) {
      if (e.closed) continue;
      const bool free0 = is_free_end(e.end0), free1 = is_free_end(e.end1);
      if (free0 == free1) continue;  // isolated piece or junction-to-junction
      const int junction = free0 ? e.end1 : e.end0;
      double half = 1.0;
      for (const Px& p : clusters_[static_cast<std::size_t>(junction)].pixels) half = std::max(half, dist_at(p));
      const double limit = std::max(options_.png_min_branch_px, 1.5 * half);
      double length = 0.0;
      for (std::size_t k = 1; k < e.chain.size(); ++k) {
        length += std::hypot(e.chain[k].x - e.chain[k - 1].x, e.chain[k].y - e.chain[k - 1].y);
      }
      if (length >= limit) continue;
      for (const Px& p : e.chain) {
        const int c = cluster_of_[static_cast<std::size_t>(p.y) * static_cast<std::size_t>(skel_.cols) + static_cast<std::size_t>(p.x)];
        if (c == junction) continue;
        skel_.at<uchar>(p.y, p.x) = 0;
      }
      changed = true;
    }
    return changed;
  }

  /// Douglas-Peucker on a polyline, returning the kept indices (first and last included).
  static void douglas_peucker(const std::vector<Vec2>& pts, std::size_t i0, std::size_t i1, double eps,
                              std::vector<std::size_t>& keep) {
    if (i1 <= i0 + 1) return;
    const Vec2 a = pts[i0], b = pts[i1];
    const Vec2 d = b - a;
    const double len = d.norm();
    double best = -1.0;
    std::size_t idx = i0;
    for (std::size_t k = i0 + 1; k < i1; ++k) {
      const Vec2 r = pts[k] - a;
      const double dev = len > 0.0 ? std::abs(d.x() * r.y() - d.y() * r.x()) / len : r.norm();
      if (dev > best) {
        best = dev;
        idx = k;
      }
    }
    if (best > eps) {
      douglas_peucker(pts, i0, idx, eps, keep);
      keep.push_back(idx);
      douglas_peucker(pts, idx, i1, eps, keep);
    }
  }

  enum class EndKind { kFree, kJunction, kBend };

  /// Marches from `from` along `dir` while occupied; returns the distance to the boundary of the
  /// occupied pixels (located by bisection between the last occupied and first free sample).
  double march(const Vec2& from, const Vec2& dir, double max_px) const {
    constexpr double kStep = 0.25;
    auto occ_at = [&](double s) { return occupied(from.x() + s * dir.x(), from.y() + s * dir.y()); };
    double s = 0.0;
    while (s <= max_px && occ_at(s + kStep)) s += kStep;
    double lo = s, hi = s + kStep;
    for (int k = 0; k < 12; ++k) {
      const double mid = 0.5 * (lo + hi);
      (occ_at(mid) ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  }

  void process_edge(const Edge& e, std::vector<Piece>& out) const {
    if (e.chain.size() < 2) return;
    std::vector<Vec2> pts;
    for (const Px& p : e.chain) pts.emplace_back(p.x + 0.5, p.y + 0.5);
    // Junction ends sit at their cluster's centroid.
    EndKind k0 = EndKind::kFree, k1 = EndKind::kFree;
    if (!e.closed) {
      if (!is_free_end(e.end0)) {
        k0 = EndKind::kJunction;
        pts.front() = clusters_[static_cast<std::size_t>(e.end0)].centroid;
      }
      if (!is_free_end(e.end1)) {
        k1 = EndKind::kJunction;
        pts.back() = clusters_[static_cast<std::size_t>(e.end1)].centroid;
      }
    }
    std::vector<std::size_t> verts;
    if (e.closed) {
      if (pts.size() < 4) return;
      // Split the loop at the point farthest from its start.
      std::size_t far = 0;
      for (std::size_t k = 1; k < pts.size(); ++k) {
        if ((pts[k] - pts[0]).norm() > (pts[far] - pts[0]).norm()) far = k;
      }
      pts.push_back(pts.front());
      verts.push_back(0);
      douglas_peucker(pts, 0, far, options_.png_polyline_epsilon_px, verts);
      verts.push_back(far);
      douglas_peucker(pts, far, pts.size() - 1, options_.png_polyline_epsilon_px, verts);
      verts.push_back(pts.size() - 1);
      k0 = k1 = EndKind::kBend;
    } else {
      verts.push_back(0);
      douglas_peucker(pts, 0, pts.size() - 1, options_.png_polyline_epsilon_px, verts);
      verts.push_back(pts.size() - 1);
    }
    std::sort(verts.begin(), verts.end());
    verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
    if (verts.size() < 2) return;

    auto local_half = [&](const Vec2& q) {
      const int c = std::clamp(static_cast<int>(q.x()), 0, dist_.cols - 1);
      const int r = std::clamp(static_cast<int>(q.y()), 0, dist_.rows - 1);
      return std::max(1.0, static_cast<double>(dist_.at<float>(r, c)));
    };
    // The skeleton cuts corners of thick walls with a short diagonal: a piece between two bends
    // shorter than the wall is thick is such a cut; replace its two bends by one in its middle
    // (the corner is then found by intersecting the neighbouring pieces' lines).
    for (bool merged = true; merged;) {
      merged = false;
      for (std::size_t i = 1; i + 2 < verts.size(); ++i) {
        const Vec2& p = pts[verts[i]];
        const Vec2& q = pts[verts[i + 1]];
        if ((q - p).norm() < std::max(2.0, 2.0 * std::max(local_half(p), local_half(q)))) {
          verts[i] = (verts[i] + verts[i + 1]) / 2;
          verts.erase(verts.begin() + static_cast<long>(i) + 1);
          merged = true;
          break;
        }
      }
    }
    // At a free end the thinning bends towards one corner of the wall's end: a first or last
    // piece shorter than the wall is thick is that hook; drop it (the next piece is extended to
    // the wall's end below).
    if (!e.closed && verts.size() >= 3 && k0 == EndKind::kFree &&
        (pts[verts[1]] - pts[verts[0]]).norm() < 2.0 * local_half(pts[verts[1]])) {
      verts.erase(verts.begin());
    }
    if (!e.closed && verts.size() >= 3 && k1 == EndKind::kFree &&
        (pts[verts.back()] - pts[verts[verts.size() - 2]]).norm() < 2.0 * local_half(pts[verts[verts.size() - 2]])) {
      verts.pop_back();
    }
    // Douglas-Peucker judges straightness by the chord between the ends, which the skeleton bends
    // near corners and junctions; re-join neighbouring pieces whose pixels (away from those ends)
    // fit one line within the tolerance.
    auto end_radius = [&](std::size_t vi, bool is_chain_end_free) {
      return is_chain_end_free ? 0.0 : 1.5 * local_half(pts[verts[vi]]) + 1.0;
    };
    auto one_line = [&](std::size_t va, std::size_t vb) {
      const double ra = end_radius(va, va == 0 && k0 == EndKind::kFree);
      const double rb = end_radius(vb, vb + 1 == verts.size() && k1 == EndKind::kFree);
      std::vector<cv::Point2f> fit;
      for (std::size_t k = verts[va]; k <= verts[vb]; ++k) {
        if ((pts[k] - pts[verts[va]]).norm() < ra || (pts[k] - pts[verts[vb]]).norm() < rb) continue;
        fit.emplace_back(static_cast<float>(pts[k].x()), static_cast<float>(pts[k].y()));
      }
      if (fit.size() < 3) return false;
      cv::Vec4f line;
      cv::fitLine(fit, line, cv::DIST_L2, 0, 0.01, 0.01);
      double worst = 0.0;
      for (const cv::Point2f& q : fit) {
        worst = std::max(worst, static_cast<double>(std::abs(line[0] * (q.y - line[3]) - line[1] * (q.x - line[2]))));
      }
      return worst <= options_.png_polyline_epsilon_px;
    };
    for (bool merged = true; merged;) {
      merged = false;
      for (std::size_t i = 1; i + 1 < verts.size(); ++i) {
        if (one_line(i - 1, i + 1)) {
          verts.erase(verts.begin() + static_cast<long>(i));
          merged = true;
          break;
        }
      }
    }

    const std::size_t n_pieces = verts.size() - 1;
    std::vector<Piece> pieces(n_pieces);
    std::vector<EndKind> start_kind(n_pieces), end_kind(n_pieces);
    for (std::size_t i = 0; i < n_pieces; ++i) {
      const std::size_t i0 = verts[i], i1 = verts[i + 1];
      start_kind[i] = i == 0 ? k0 : EndKind::kBend;
      end_kind[i] = i + 1 == n_pieces ? k1 : EndKind::kBend;
      const double r0 = start_kind[i] == EndKind::kFree ? 0.0 : local_half(pts[i0]);
      const double r1 = end_kind[i] == EndKind::kFree ? 0.0 : local_half(pts[i1]);
      std::vector<cv::Point2f> fit;
      for (std::size_t k = i0; k <= i1; ++k) {
        if ((pts[k] - pts[i0]).norm() < r0 || (pts[k] - pts[i1]).norm() < r1) continue;
        fit.emplace_back(static_cast<float>(pts[k].x()), static_cast<float>(pts[k].y()));
      }
      if (fit.size() < 3) {
        fit.clear();
        for (std::size_t k = i0; k <= i1; ++k) fit.emplace_back(static_cast<float>(pts[k].x()), static_cast<float>(pts[k].y()));
      }
      Piece& pc = pieces[i];
      if (fit.size() >= 2) {
        cv::Vec4f line;
        cv::fitLine(fit, line, cv::DIST_L2, 0, 0.01, 0.01);
        pc.d = Vec2(line[0], line[1]).normalized();
        pc.p = Vec2(line[2], line[3]);
      } else {
        pc.d = (pts[i1] - pts[i0]).normalized();
        pc.p = pts[i0];
      }
      if ((pts[i1] - pts[i0]).dot(pc.d) < 0.0) pc.d = -pc.d;
      if (!pc.d.allFinite()) pc.d = Vec2::UnitX();
      // Re-centre and measure thickness across the piece, away from its ends.
      const Vec2 nrm(-pc.d.y(), pc.d.x());
      const double t_start = (pts[i0] - pc.p).dot(pc.d) + r0;
      const double t_end = (pts[i1] - pc.p).dot(pc.d) - r1;
      double max_half = 1.0;
      for (std::size_t k = i0; k <= i1; ++k) max_half = std::max(max_half, local_half(pts[k]));
      const double reach = 3.0 * max_half + 4.0;
      std::vector<double> ts, mids, widths;
      for (double t = t_start + 0.5; t <= t_end - 0.5; t += 1.0) {
        const Vec2 q = pc.p + t * pc.d;
        if (!occupied(q.x(), q.y())) continue;
        const double plus = march(q, nrm, reach), minus = march(q, -nrm, reach);
        if (plus > reach || minus > reach) continue;
        ts.push_back(t);
        mids.push_back(0.5 * (plus - minus));
        widths.push_back(plus + minus);
      }
      if (!widths.empty()) {
        // Cross-sections as wide as the wall (not running into a crossing wall) re-centre and
        // re-orient the line: least squares of mid-point offset against position along it.
        const double w_med = median(widths);
        double sw = 0.0, st = 0.0, sm = 0.0, stt = 0.0, stm = 0.0;
        std::vector<double> kept_widths;
        for (std::size_t k = 0; k < ts.size(); ++k) {
          if (std::abs(widths[k] - w_med) > 1.0) continue;
          kept_widths.push_back(widths[k]);
          sw += 1.0;
          st += ts[k];
          sm += mids[k];
          stt += ts[k] * ts[k];
          stm += ts[k] * mids[k];
        }
        const double det = sw * stt - st * st;
        if (sw >= 3.0 && det > 1e-9 * std::max(1.0, sw * stt)) {
          const double slope = (sw * stm - st * sm) / det;
          const double offset = (sm - slope * st) / sw;
          pc.p += offset * nrm;
          pc.d = (pc.d + slope * nrm).normalized();
        } else {
          pc.p += median(mids) * nrm;
        }
        pc.width_px = std::max(1.0, median(kept_widths.empty() ? widths : kept_widths));
      } else {
        const Vec2 mid = 0.5 * (pts[i0] + pts[i1]);
        pc.width_px = std::max(1.0, 2.0 * local_half(mid) - 1.0);
      }
    }
    // End points.
    auto project = [](const Piece& pc, const Vec2& q) { return pc.p + (q - pc.p).dot(pc.d) * pc.d; };
    for (std::size_t i = 0; i < n_pieces; ++i) {
      Piece& pc = pieces[i];
      const Vec2 q0 = pts[verts[i]], q1 = pts[verts[i + 1]];
      pc.a = project(pc, q0);
      pc.b = project(pc, q1);
      if (start_kind[i] == EndKind::kFree) {
        pc.a -= (march(pc.a, -pc.d, 3.0 * local_half(q0) + 4.0)) * pc.d;
      }
      if (end_kind[i] == EndKind::kFree) {
        pc.b += (march(pc.b, pc.d, 3.0 * local_half(q1) + 4.0)) * pc.d;
      }
    }
    // Corners: intersect adjacent fitted lines.
    auto corner = [&](Piece& first, Piece& second, const Vec2& vertex) {
      const double cross = first.d.x() * second.d.y() - first.d.y() * second.d.x();
      if (std::abs(cross) < std::sin(10.0 * 3.14159265358979323846 / 180.0)) return;
      const Vec2 w = second.p - first.p;
      const double t = (w.x() * second.d.y() - w.y() * second.d.x()) / cross;
      const Vec2 x = first.p + t * first.d;
      if ((x - vertex).norm() > 2.0 * local_half(vertex) + 2.0) return;
      first.b = x;
      second.a = x;
    };
    for (std::size_t i = 0; i + 1 < n_pieces; ++i) corner(pieces[i], pieces[i + 1], pts[verts[i + 1]]);
    if (e.closed && n_pieces >= 2) corner(pieces[n_pieces - 1], pieces[0], pts[verts[0]]);
    for (Piece& pc : pieces) {
      if ((pc.b - pc.a).norm() >= 0.5) out.push_back(pc);
    }
  }

  cv::Mat occ_;
  cv::Mat dist_;
  cv::Mat skel_;
  const ImportOptions& options_;
  std::vector<Edge> edges_;
  std::vector<Cluster> clusters_;
  std::vector<int> cluster_of_;
};

}  // namespace

std::vector<Wall> vectorize_occupancy(const cv::Mat& occupied, double resolution_m_per_px, const ImportOptions& options,
                                      std::vector<std::string>* notes) {
  if (occupied.empty() || occupied.type() != CV_8UC1) throw InputError("vectorize_occupancy: expected a non-empty CV_8UC1 mask");
  if (!(resolution_m_per_px > 0.0) || !std::isfinite(resolution_m_per_px)) {
    throw InputError("vectorize_occupancy: resolution must be positive");
  }
  cv::Mat occ = (occupied != 0);
  // Noise: small connected components.
  if (options.png_min_component_px > 1) {
    cv::Mat labels, stats, centroids;
    const int n = cv::connectedComponentsWithStats(occ, labels, stats, centroids, 8, CV_32S);
    int dropped = 0, dropped_px = 0;
    std::vector<uchar> drop(static_cast<std::size_t>(n), 0);
    for (int l = 1; l < n; ++l) {
      const int area = stats.at<int>(l, cv::CC_STAT_AREA);
      if (area < options.png_min_component_px) {
        drop[static_cast<std::size_t>(l)] = 1;
        ++dropped;
        dropped_px += area;
      }
    }
    if (dropped > 0) {
      for (int r = 0; r < occ.rows; ++r) {
        for (int c = 0; c < occ.cols; ++c) {
          if (drop[static_cast<std::size_t>(labels.at<int>(r, c))]) occ.at<uchar>(r, c) = 0;
        }
      }
      if (notes) {
        notes->push_back(std::to_string(dropped) + " occupied speck(s) smaller than " +
                         std::to_string(options.png_min_component_px) + " px (" + std::to_string(dropped_px) +
                         " px in all) dropped as noise");
      }
    }
  }
  // One free pixel of padding so every wall has a boundary.
  cv::Mat padded;
  cv::copyMakeBorder(occ, padded, 1, 1, 1, 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  Vectorizer vec(padded, options);
  const std::vector<Vectorizer::Piece> pieces = vec.run();
  const double h = static_cast<double>(occ.rows);
  auto to_world = [&](const Vec2& q) {
    return Vec2(options.png_origin_m.x() + (q.x() - 1.0) * resolution_m_per_px,
                options.png_origin_m.y() + (h - (q.y() - 1.0)) * resolution_m_per_px);
  };
  std::vector<Wall> walls;
  for (const auto& pc : pieces) {
    Wall w;
    w.id = "w" + std::to_string(walls.size() + 1);
    w.a_m = to_world(pc.a);
    w.b_m = to_world(pc.b);
    w.thickness_m = pc.width_px * resolution_m_per_px;
    walls.push_back(std::move(w));
  }
  return walls;
}

namespace {

/// Solid mass is not a wall: occupied regions thicker than `max_wall_m` (an occupied exterior
/// around the building, filled shafts) keep only a band along their free boundary as thick as the
/// image's walls (the median thickness of the other walls, else 0.2 m); the rest becomes free.
/// Returns how many regions were hollowed and adds a note for each.
int hollow_solid_regions(cv::Mat& occupied, double res, double max_wall_m, std::vector<std::string>& notes) {
  if (!(max_wall_m > 0.0)) return 0;
  cv::Mat dist;
  cv::distanceTransform(occupied, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  const float deep_px = static_cast<float>(0.5 * max_wall_m / res);
  cv::Mat labels;
  const int n = cv::connectedComponents(occupied, labels, 8, CV_32S);
  std::vector<bool> deep(static_cast<std::size_t>(n), false);
  for (int r = 0; r < occupied.rows; ++r) {
    const float* d = dist.ptr<float>(r);
    const int* l = labels.ptr<int>(r);
    for (int c = 0; c < occupied.cols; ++c) {
      if (d[c] > deep_px) deep[static_cast<std::size_t>(l[c])] = true;
    }
  }
  if (std::none_of(deep.begin() + 1, deep.end(), [](bool b) { return b; })) return 0;
  // Wall thickness of the image: twice the distance at ridge pixels (3x3 local maxima) of the
  // regions that are walls.
  std::vector<float> half;
  for (int r = 1; r + 1 < occupied.rows; ++r) {
    for (int c = 1; c + 1 < occupied.cols; ++c) {
      const float v = dist.at<float>(r, c);
      if (v <= 0.0f || deep[static_cast<std::size_t>(labels.at<int>(r, c))]) continue;
      bool ridge = true;
      for (int dr = -1; dr <= 1 && ridge; ++dr) {
        for (int dc = -1; dc <= 1; ++dc) ridge = ridge && dist.at<float>(r + dr, c + dc) <= v;
      }
      if (ridge) half.push_back(v);
    }
  }
  double band_px = 0.2 / res;
  if (!half.empty()) {
    std::nth_element(half.begin(), half.begin() + static_cast<std::ptrdiff_t>(half.size() / 2), half.end());
    band_px = 2.0 * half[half.size() / 2];
  }
  band_px = std::clamp(band_px, 2.0, static_cast<double>(deep_px));
  std::vector<int> removed(static_cast<std::size_t>(n), 0);
  for (int r = 0; r < occupied.rows; ++r) {
    const float* d = dist.ptr<float>(r);
    const int* l = labels.ptr<int>(r);
    uchar* o = occupied.ptr<uchar>(r);
    for (int c = 0; c < occupied.cols; ++c) {
      if (o[c] && deep[static_cast<std::size_t>(l[c])] && d[c] > band_px) {
        o[c] = 0;
        ++removed[static_cast<std::size_t>(l[c])];
      }
    }
  }
  int hollowed = 0;
  for (int k = 1; k < n; ++k) {
    if (!deep[static_cast<std::size_t>(k)]) continue;
    ++hollowed;
    notes.push_back("occupied region " + std::to_string(k) + " is solid mass thicker than " +
                    import_detail::fmt(max_wall_m) + " m (an occupied exterior or a filled shaft): " +
                    std::to_string(removed[static_cast<std::size_t>(k)]) + " px inside it made free, a " +
                    import_detail::fmt(band_px * res) + " m band along its free boundary kept as wall");
  }
  return hollowed;
}

}  // namespace

ImportResult import_png_image(const cv::Mat& image, const std::string& source, const ImportOptions& options) {
  if (!options.resolution_m_per_px) {
    throw InputError(source + ": png import needs the image resolution (--resolution M_PER_PX)");
  }
  const double res = *options.resolution_m_per_px;
  if (!std::isfinite(res) || res <= 0.0 || res > 10.0) {
    throw InputError(source + ": resolution " + fmt(res) + " m/px is outside (0, 10]");
  }
  if (image.empty()) throw InputError(source + ": empty image");
  if (image.depth() != CV_8U) {
    throw InputError(source + ": expected an 8-bit image (255 = free, anything else occupied), got " +
                     std::to_string(8 * image.elemSize1()) + "-bit samples");
  }
  const int channels = image.channels();
  if (channels != 1 && channels != 3 && channels != 4) {
    throw InputError(source + ": expected a gray, RGB or RGBA image, got " + std::to_string(channels) + " channels");
  }
  cv::Mat occupied(image.rows, image.cols, CV_8UC1);
  for (int r = 0; r < image.rows; ++r) {
    const uchar* row = image.ptr<uchar>(r);
    for (int c = 0; c < image.cols; ++c) {
      bool free = true;
      for (int ch = 0; ch < std::min(channels, 3); ++ch) free = free && row[c * channels + ch] == 255;
      occupied.at<uchar>(r, c) = free ? 0 : 255;
    }
  }
  ImportResult result;
  const int occupied_px = cv::countNonZero(occupied);
  if (occupied_px == 0) {
    throw InputError(source + ": every pixel is free (255): no walls to vectorise (F3Loc maps: 255 free, anything else "
                              "occupied)");
  }
  if (occupied_px == image.rows * image.cols) {
    throw InputError(source + ": every pixel is occupied (no free pixel of value 255): not an occupancy map of a floor, "
                              "or its colours are inverted (F3Loc maps: 255 free, 0 walls)");
  }
  import_detail::count_repair(result, "solid_regions_hollowed",
                              hollow_solid_regions(occupied, res, options.png_max_wall_thickness_m, result.notes));
  ImportOptions opts = options;
  opts.cleanup.snap_tolerance_m = std::max(opts.cleanup.snap_tolerance_m, 1.5 * res);
  opts.cleanup.angle_tolerance_rad = std::max(opts.cleanup.angle_tolerance_rad, 3.0 * 3.14159265358979323846 / 180.0);
  opts.cleanup.thickness_tolerance_m = std::max(opts.cleanup.thickness_tolerance_m, res);
  FloorPlan plan;
  plan.level = import_detail::plain_level(options, source);
  plan.walls = vectorize_occupancy(occupied, res, opts, &result.notes);
  result.source_counts = {{"pixels", image.rows * image.cols},
                          {"occupied_pixels", occupied_px},
                          {"vectorised_walls", static_cast<int>(plan.walls.size())}};
  if (plan.walls.empty()) {
    throw InputError(source + ": no wall could be vectorised from the " + std::to_string(occupied_px) +
                     " occupied pixels (too few, or only solid mass)");
  }
  const import_detail::UnitCheck check{res, "px", "--resolution"};
  return import_detail::finish_import(std::move(plan), source, import_detail::stem_of(source), opts, std::move(result), &check);
}

}  // namespace floorcast
