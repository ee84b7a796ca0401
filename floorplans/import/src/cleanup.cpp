#include "floorcast/floorplans/cleanup.hpp"
#include "floorcast/core/math.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <sstream>
#include <string>
#include <type_traits>
#include <unordered_map>

#include <Eigen/Dense>

namespace floorcast {
namespace {


class UnionFind {
 public:
  explicit UnionFind(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
  std::size_t find(std::size_t i) {
    while (parent_[i] != i) {
      parent_[i] = parent_[parent_[i]];
      i = parent_[i];
    }
    return i;
  }
  void unite(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return;
    if (b < a) std::swap(a, b);
    parent_[b] = a;  // the smallest index is the root: deterministic
  }

 private:
  std::vector<std::size_t> parent_;
};

struct CellKey {
  long long x, y;
  bool operator==(const CellKey& o) const { return x == o.x && y == o.y; }
};
struct CellKeyHash {
  std::size_t operator()(const CellKey& k) const {
    return std::hash<long long>()(k.x * 73856093LL) ^ std::hash<long long>()(k.y * 19349663LL);
  }
};

/// Uniform grid over segments (each inserted into every cell its inflated bbox touches).
class SegmentGrid {
 public:
  SegmentGrid(const std::vector<Segment2>& segments, double margin_m) : margin_m_(margin_m) {
    double xmin = std::numeric_limits<double>::infinity(), ymin = xmin, xmax = -xmin, ymax = -xmin;
    for (const Segment2& s : segments) {
      xmin = std::min({xmin, s.a_m.x(), s.b_m.x()});
      xmax = std::max({xmax, s.a_m.x(), s.b_m.x()});
      ymin = std::min({ymin, s.a_m.y(), s.b_m.y()});
      ymax = std::max({ymax, s.a_m.y(), s.b_m.y()});
    }
    const double extent = segments.empty() ? 1.0 : std::max(xmax - xmin, ymax - ymin);
    const double n = std::max<double>(1.0, static_cast<double>(segments.size()));
    cell_m_ = std::max({4.0 * margin_m, extent / std::sqrt(n), 1e-3});
    for (std::size_t i = 0; i < segments.size(); ++i) {
      const Segment2& s = segments[i];
      const long long x0 = cell(std::min(s.a_m.x(), s.b_m.x()) - margin_m);
      const long long x1 = cell(std::max(s.a_m.x(), s.b_m.x()) + margin_m);
      const long long y0 = cell(std::min(s.a_m.y(), s.b_m.y()) - margin_m);
      const long long y1 = cell(std::max(s.a_m.y(), s.b_m.y()) + margin_m);
      for (long long x = x0; x <= x1; ++x) {
        for (long long y = y0; y <= y1; ++y) cells_[{x, y}].push_back(static_cast<int>(i));
      }
    }
  }
  /// Segments whose inflated bbox contains p (superset of those within margin of p).
  const std::vector<int>& near(const Vec2& p) const {
    static const std::vector<int> kNone;
    auto it = cells_.find({cell(p.x()), cell(p.y())});
    return it == cells_.end() ? kNone : it->second;
  }

 private:
  long long cell(double v) const { return static_cast<long long>(std::floor(v / cell_m_)); }
  double margin_m_;
  double cell_m_ = 1.0;
  std::unordered_map<CellKey, std::vector<int>, CellKeyHash> cells_;
};

/// Distance from p to segment s and the arc-length parameter of the closest point (clamped).
double point_segment_distance(const Vec2& p, const Segment2& s, double* t_out = nullptr) {
  const Vec2 d = s.b_m - s.a_m;
  const double len2 = d.squaredNorm();
  double t = len2 > 0.0 ? (p - s.a_m).dot(d) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  if (t_out) *t_out = t * std::sqrt(len2);
  return (p - (s.a_m + t * d)).norm();
}

/// Line angle in [0, pi).
double line_angle(const Segment2& s) {
  double a = std::atan2(s.b_m.y() - s.a_m.y(), s.b_m.x() - s.a_m.x());
  if (a < 0.0) a += kPi;
  if (a >= kPi) a -= kPi;
  return a;
}

double line_angle_difference(double a, double b) {
  const double d = std::abs(a - b);
  return std::min(d, kPi - d);
}

/// Collinear: directions within angle_tol and the shorter segment's endpoints within tol of the
/// longer one's line. Judged by direction and offset only, never by shortness: a piece a few
/// centimetres long lies within tol of almost any line through its neighbourhood (corner chamfers,
/// survey noise), so a looser angle for short pieces chains unrelated walls into one fitted line.
bool collinear(const Segment2& s1, const Segment2& s2, double tol, double angle_tol) {
  const double l1 = s1.length_m(), l2 = s2.length_m();
  if (l1 <= 0.0 || l2 <= 0.0) return false;
  if (line_angle_difference(line_angle(s1), line_angle(s2)) > angle_tol) return false;
  const Segment2& longer = l1 >= l2 ? s1 : s2;
  const Segment2& shorter = l1 >= l2 ? s2 : s1;
  const Vec2 u = (longer.b_m - longer.a_m) / longer.length_m();
  auto off = [&](const Vec2& p) {
    const Vec2 r = p - longer.a_m;
    return std::abs(u.x() * r.y() - u.y() * r.x());
  };
  return off(shorter.a_m) <= tol && off(shorter.b_m) <= tol;
}

std::string fmt(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

std::string quoted(const std::string& s) { return "\"" + s + "\""; }

/// Openings moved onto their wall's axis by more than this get a note (beyond it the native
/// format's validation would refuse them where they were).
constexpr double kOpeningNoteOffsetM = 0.05;

/// Snaps wall endpoints: clusters near-coincident endpoints, then moves vertices onto nearby
/// wall interiors. Updates walls in place; returns (snapped endpoints, endpoints snapped to walls).
std::pair<int, int> snap_endpoints(std::vector<Wall>& walls, double tol) {
  const std::size_t n = walls.size() * 2;
  if (n == 0) return {0, 0};
  auto point = [&](std::size_t k) -> Vec2& { return k % 2 == 0 ? walls[k / 2].a_m : walls[k / 2].b_m; };

  // 1. Cluster endpoints (single linkage within tol) with a hash grid.
  UnionFind uf(n);
  std::unordered_map<CellKey, std::vector<std::size_t>, CellKeyHash> grid;
  const double cell = std::max(tol, 1e-9);
  auto key = [&](const Vec2& p) {
    return CellKey{static_cast<long long>(std::floor(p.x() / cell)), static_cast<long long>(std::floor(p.y() / cell))};
  };
  for (std::size_t k = 0; k < n; ++k) grid[key(point(k))].push_back(k);
  for (std::size_t k = 0; k < n; ++k) {
    const CellKey c = key(point(k));
    for (long long dx = -1; dx <= 1; ++dx) {
      for (long long dy = -1; dy <= 1; ++dy) {
        auto it = grid.find({c.x + dx, c.y + dy});
        if (it == grid.end()) continue;
        for (std::size_t j : it->second) {
          if (j > k && (point(j) - point(k)).norm() <= tol) uf.unite(j, k);
        }
      }
    }
  }
  std::vector<Vec2> sum(n, Vec2::Zero());
  std::vector<int> count(n, 0);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t r = uf.find(k);
    sum[r] += point(k);
    count[r] += 1;
  }
  // Vertex list: one per cluster, with incident endpoint indices.
  std::vector<std::size_t> vertex_of(n);
  std::vector<Vec2> vertices;
  std::vector<std::vector<std::size_t>> incident;
  std::unordered_map<std::size_t, std::size_t> root_to_vertex;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t r = uf.find(k);
    auto [it, inserted] = root_to_vertex.emplace(r, vertices.size());
    if (inserted) {
      vertices.push_back(sum[r] / count[r]);
      incident.emplace_back();
    }
    vertex_of[k] = it->second;
    incident[it->second].push_back(k);
  }
  // A cluster's point: where the incident walls' lines meet (length-weighted least squares, so a
  // corner stays a corner and a T-junction stays on the through wall); along directions the lines
  // do not fix (near-parallel lines) the cluster's mean; the mean if that point lies farther than
  // tol from it.
  for (std::size_t v = 0; v < vertices.size(); ++v) {
    if (incident[v].size() < 2) continue;
    // Already one point (e.g. a corner shared exactly): leave it, so clean-up is idempotent.
    bool coincident = true;
    for (std::size_t k : incident[v]) coincident = coincident && point(k) == point(incident[v].front());
    if (coincident) {
      vertices[v] = point(incident[v].front());
      continue;
    }
    const Vec2 mean = vertices[v];
    Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
    Vec2 b = Vec2::Zero();
    double total = 0.0;
    for (std::size_t k : incident[v]) {
      const Wall& w = walls[k / 2];
      const Vec2 d = w.b_m - w.a_m;
      const double len = d.norm();
      if (len <= 2.0 * tol || len <= 0.0) continue;
      const Vec2 nrm(-d.y() / len, d.x() / len);
      A += len * nrm * nrm.transpose();
      b += len * nrm * nrm.dot(w.a_m);
      total += len;
    }
    if (total <= 0.0) continue;
    // Solve A x = b only along well-constrained directions: lines meeting at a small angle fix
    // the point across them but not along them (there the mean stays).
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(A);
    const Vec2 residual = b - A * mean;
    Vec2 x = mean;
    const double lmax = eig.eigenvalues()(1);
    for (int i = 0; i < 2; ++i) {
      const double l = eig.eigenvalues()(i);
      if (l <= 0.02 * lmax || l <= 0.0) continue;
      const Vec2 e = eig.eigenvectors().col(i);
      x += (e.dot(residual) / l) * e;
    }
    if (x.allFinite() && (x - mean).norm() <= tol) vertices[v] = x;
  }
  constexpr double kMoved = 1e-9;  // smaller moves are rounding, not snapping
  int snapped = 0;
  for (std::size_t k = 0; k < n; ++k) {
    if (incident[vertex_of[k]].size() > 1 && (point(k) - vertices[vertex_of[k]]).norm() > kMoved) ++snapped;
  }

  // 2. Vertices within tol of another wall's interior move onto it (T-junction gaps).
  std::vector<Segment2> segs(walls.size());
  for (std::size_t i = 0; i < walls.size(); ++i) {
    segs[i] = {vertices[vertex_of[2 * i]], vertices[vertex_of[2 * i + 1]]};
  }
  const SegmentGrid seg_grid(segs, 2.0 * tol);
  int to_walls = 0;
  for (std::size_t v = 0; v < vertices.size(); ++v) {
    std::set<int> own;
    for (std::size_t k : incident[v]) own.insert(static_cast<int>(k / 2));
    double best = std::numeric_limits<double>::infinity();
    Vec2 target = vertices[v];
    for (int j : seg_grid.near(vertices[v])) {
      if (own.count(j)) continue;
      const Segment2 s{vertices[vertex_of[2 * j]], vertices[vertex_of[2 * j + 1]]};
      const double len = s.length_m();
      if (len <= 0.0) continue;
      const Vec2 u = (s.b_m - s.a_m) / len;
      const double t = (vertices[v] - s.a_m).dot(u);
      if (t <= 0.0 || t >= len) continue;
      const Vec2 foot = s.a_m + t * u;
      const double d = (vertices[v] - foot).norm();
      if (d <= tol && d < best && d > kMoved) {
        best = d;
        target = foot;
      }
    }
    if (best < std::numeric_limits<double>::infinity()) {
      vertices[v] = target;
      to_walls += static_cast<int>(incident[v].size());
    }
  }
  for (std::size_t k = 0; k < n; ++k) point(k) = vertices[vertex_of[k]];
  return {snapped, to_walls};
}

int drop_degenerate(std::vector<Wall>& walls, std::vector<int>& origin, double min_length) {
  int dropped = 0;
  std::size_t out = 0;
  for (std::size_t i = 0; i < walls.size(); ++i) {
    if (walls[i].length_m() < min_length) {
      ++dropped;
      continue;
    }
    if (out != i) {
      walls[out] = std::move(walls[i]);
      origin[out] = origin[i];
    }
    ++out;
  }
  walls.resize(out);
  origin.resize(out);
  return dropped;
}

/// Attributes that decide whether two overlapping pieces are the same wall.
struct Attributes {
  WallMaterial material = WallMaterial::kSolid;
  double thickness_m = 0.0;
  double glass_sill_m = 0.0;
  double glass_head_m = -1.0;  // -1: none

  /// Same kind of wall, thicknesses within `thickness_tol`.
  bool same(const Attributes& o, double thickness_tol) const {
    return material == o.material && std::abs(thickness_m - o.thickness_m) <= thickness_tol + 1e-12 &&
           std::abs(glass_sill_m - o.glass_sill_m) <= 1e-9 && std::abs(glass_head_m - o.glass_head_m) <= 1e-9;
  }
  /// Priority where pieces overlap: solid beats glass, then the thicker wall.
  bool beats(const Attributes& o) const {
    if (material != o.material) return material == WallMaterial::kSolid;
    if (std::abs(thickness_m - o.thickness_m) > 1e-9) return thickness_m > o.thickness_m;
    if (std::abs(glass_sill_m - o.glass_sill_m) > 1e-9) return glass_sill_m < o.glass_sill_m;
    return glass_head_m > o.glass_head_m + 1e-9;
  }
};

Attributes attributes_of(const Wall& w) {
  Attributes a;
  a.material = w.material;
  a.thickness_m = w.thickness_m;
  a.glass_sill_m = w.glass_sill_m;
  a.glass_head_m = w.glass_head_m ? *w.glass_head_m : -1.0;
  return a;
}

struct MergedPiece {
  Wall wall;
  int group = -1;
  int order_key = 0;   // smallest contributing input index
  double t0 = 0.0;     // along the group line
  std::vector<int> contributors;  // input (post-stage-2) wall indices
};

}  // namespace

std::vector<int> collinear_groups(const std::vector<Segment2>& segments, double offset_tolerance_m,
                                  double angle_tolerance_rad) {
  const std::size_t n = segments.size();
  UnionFind uf(n);
  if (n > 0) {
    // Centre coordinates so that line offsets (rho) stay small.
    Vec2 c = Vec2::Zero();
    for (const Segment2& s : segments) c += 0.5 * (s.a_m + s.b_m);
    c /= static_cast<double>(n);
    double radius = 0.0;
    for (const Segment2& s : segments) radius = std::max({radius, (s.a_m - c).norm(), (s.b_m - c).norm()});
    // Angle bins as wide as the angle tolerance.
    const double angle_bin = std::max(angle_tolerance_rad, 1e-6);
    const double widest = angle_bin;
    const long long bins = std::max(1LL, static_cast<long long>(std::ceil(kPi / angle_bin)));
    const double rho_bin = std::max(offset_tolerance_m + radius * widest, 1e-6) * 2.0;
    std::vector<double> theta(n), rho(n);
    std::unordered_map<CellKey, std::vector<std::size_t>, CellKeyHash> buckets;
    auto bin_of = [&](double th) {
      return std::min(bins - 1, static_cast<long long>(std::floor(th / angle_bin)));
    };
    for (std::size_t i = 0; i < n; ++i) {
      const Segment2& s = segments[i];
      theta[i] = line_angle(s);
      const Vec2 u(std::cos(theta[i]), std::sin(theta[i]));
      const Vec2 nrm(-u.y(), u.x());
      rho[i] = nrm.dot(0.5 * (s.a_m + s.b_m) - c);
      buckets[{bin_of(theta[i]), static_cast<long long>(std::floor(rho[i] / rho_bin))}].push_back(i);
    }
    for (std::size_t i = 0; i < n; ++i) {
      const long long b = bin_of(theta[i]);
      for (long long db = -1; db <= 1; ++db) {
        long long nb = b + db;
        bool flip = false;
        if (nb < 0) {
          nb += bins;
          flip = true;
        } else if (nb >= bins) {
          nb -= bins;
          flip = true;
        }
        const double r = flip ? -rho[i] : rho[i];
        const long long rb = static_cast<long long>(std::floor(r / rho_bin));
        for (long long dr = -1; dr <= 1; ++dr) {
          auto it = buckets.find({nb, rb + dr});
          if (it == buckets.end()) continue;
          for (std::size_t j : it->second) {
            if (j <= i) continue;
            if (collinear(segments[i], segments[j], offset_tolerance_m, angle_tolerance_rad)) uf.unite(i, j);
          }
        }
      }
    }
  }
  std::vector<int> group(n, -1);
  std::unordered_map<std::size_t, int> root_group;
  for (std::size_t i = 0; i < n; ++i) {
    auto [it, inserted] = root_group.emplace(uf.find(i), static_cast<int>(root_group.size()));
    group[i] = it->second;
  }
  return group;
}

std::vector<std::vector<int>> collinear_runs(const std::vector<Segment2>& segments, double offset_tolerance_m,
                                             double angle_tolerance_rad) {
  // Two walls belong to one run when they are collinear (collinear()) and their extents along the
  // longer one's line overlap or leave a gap of at most the tolerance. The test is local on
  // purpose: infinite lines of far-apart walls drift apart with tiny angle differences. Candidate
  // pairs come from a uniform grid over the tolerance-inflated bounding boxes.
  const std::size_t n = segments.size();
  const double tol = offset_tolerance_m;
  UnionFind uf(n);
  if (n > 0) {
    double xmin = std::numeric_limits<double>::infinity(), ymin = xmin, xmax = -xmin, ymax = -xmin;
    for (const Segment2& s : segments) {
      xmin = std::min({xmin, s.a_m.x(), s.b_m.x()});
      xmax = std::max({xmax, s.a_m.x(), s.b_m.x()});
      ymin = std::min({ymin, s.a_m.y(), s.b_m.y()});
      ymax = std::max({ymax, s.a_m.y(), s.b_m.y()});
    }
    const double extent = std::max(xmax - xmin, ymax - ymin);
    const double cell = std::max({4.0 * tol, extent / std::sqrt(static_cast<double>(n)), 1e-3});
    auto index = [&](double v) { return static_cast<long long>(std::floor(v / cell)); };
    struct Range { long long x0, x1, y0, y1; };
    std::vector<Range> ranges(n);
    std::unordered_map<CellKey, std::vector<int>, CellKeyHash> grid;
    for (std::size_t i = 0; i < n; ++i) {
      const Segment2& s = segments[i];
      Range r{index(std::min(s.a_m.x(), s.b_m.x()) - tol), index(std::max(s.a_m.x(), s.b_m.x()) + tol),
              index(std::min(s.a_m.y(), s.b_m.y()) - tol), index(std::max(s.a_m.y(), s.b_m.y()) + tol)};
      ranges[i] = r;
      for (long long x = r.x0; x <= r.x1; ++x) {
        for (long long y = r.y0; y <= r.y1; ++y) grid[{x, y}].push_back(static_cast<int>(i));
      }
    }
    auto touching = [&](const Segment2& s1, const Segment2& s2) {
      const Segment2& longer = s1.length_m() >= s2.length_m() ? s1 : s2;
      const Segment2& shorter = s1.length_m() >= s2.length_m() ? s2 : s1;
      const Vec2 u = (longer.b_m - longer.a_m) / longer.length_m();
      const double l0 = 0.0, l1 = longer.length_m();
      double s0 = (shorter.a_m - longer.a_m).dot(u), s1e = (shorter.b_m - longer.a_m).dot(u);
      if (s1e < s0) std::swap(s0, s1e);
      return std::max(l0, s0) - std::min(l1, s1e) <= tol;
    };
    std::vector<std::size_t> stamp(n, n);
    for (std::size_t i = 0; i < n; ++i) {
      const Range& r = ranges[i];
      for (long long x = r.x0; x <= r.x1; ++x) {
        for (long long y = r.y0; y <= r.y1; ++y) {
          for (int jj : grid[{x, y}]) {
            const std::size_t j = static_cast<std::size_t>(jj);
            if (j <= i || stamp[j] == i) continue;
            stamp[j] = i;
            if (collinear(segments[i], segments[j], tol, angle_tolerance_rad) && touching(segments[i], segments[j])) {
              uf.unite(i, j);
            }
          }
        }
      }
    }
  }
  std::unordered_map<std::size_t, std::size_t> root_run;
  std::vector<std::vector<int>> runs;
  for (std::size_t i = 0; i < n; ++i) {
    auto [it, inserted] = root_run.emplace(uf.find(i), runs.size());
    if (inserted) runs.emplace_back();
    runs[it->second].push_back(static_cast<int>(i));
  }
  return runs;  // members ascending; runs ordered by their first member
}

GroupLine fit_group_line(const std::vector<Segment2>& segments, const std::vector<int>& members) {
  GroupLine line;
  if (members.empty()) return line;
  int longest = members.front();
  for (int m : members) {
    if (segments[static_cast<std::size_t>(m)].length_m() > segments[static_cast<std::size_t>(longest)].length_m()) longest = m;
  }
  const Segment2& ref = segments[static_cast<std::size_t>(longest)];
  const Vec2 ref_dir = (ref.b_m - ref.a_m).normalized();
  Vec2 dir_sum = Vec2::Zero();
  Vec2 mid_sum = Vec2::Zero();
  double weight = 0.0;
  for (int m : members) {
    const Segment2& s = segments[static_cast<std::size_t>(m)];
    const double len = s.length_m();
    if (len <= 0.0) continue;
    Vec2 d = (s.b_m - s.a_m) / len;
    if (d.dot(ref_dir) < 0.0) d = -d;
    dir_sum += len * d;
    mid_sum += len * 0.5 * (s.a_m + s.b_m);
    weight += len;
  }
  if (weight <= 0.0 || dir_sum.norm() <= 0.0) {
    line.origin_m = ref.a_m;
    line.direction = ref_dir.allFinite() ? ref_dir : Vec2::UnitX();
    return line;
  }
  // Members with the exact same direction keep it bit for bit.
  bool all_same = true;
  for (int m : members) {
    const Segment2& s = segments[static_cast<std::size_t>(m)];
    Vec2 d = (s.b_m - s.a_m).normalized();
    if (d.dot(ref_dir) < 0.0) d = -d;
    if (!(d == ref_dir)) all_same = false;
  }
  line.direction = all_same ? ref_dir : Vec2(dir_sum.normalized());
  line.origin_m = mid_sum / weight;
  return line;
}

CleanupReport cleanup_floor_plan(FloorPlan& plan, const CleanupOptions& options, const std::string& source) {
  if (!(options.snap_tolerance_m >= 0.0) || !(options.angle_tolerance_rad >= 0.0) ||
      !(options.thickness_tolerance_m >= 0.0) || !std::isfinite(options.thickness_tolerance_m) ||
      !(options.min_wall_length_m >= 0.0) || !(options.opening_attach_tolerance_m >= 0.0) ||
      !std::isfinite(options.snap_tolerance_m) || !std::isfinite(options.angle_tolerance_rad) ||
      !std::isfinite(options.min_wall_length_m) || !std::isfinite(options.opening_attach_tolerance_m)) {
    throw InputError(source + ": cleanup: tolerances must be finite and non-negative");
  }
  CleanupReport report;
  report.input_walls = static_cast<int>(plan.walls.size());
  const double tol = options.snap_tolerance_m;

  // Original wall index of each opening's wall (before anything moves).
  std::map<std::string, int> input_index;
  for (std::size_t i = 0; i < plan.walls.size(); ++i) input_index.emplace(plan.walls[i].id, static_cast<int>(i));

  std::vector<Wall> walls = plan.walls;
  std::vector<int> origin(walls.size());
  std::iota(origin.begin(), origin.end(), 0);

  // 1. Degenerate walls.
  report.dropped_degenerate_walls += drop_degenerate(walls, origin, options.min_wall_length_m);

  // 2. Snap endpoints.
  {
    const auto [snapped, to_walls] = snap_endpoints(walls, tol);
    report.snapped_endpoints += snapped;
    report.endpoints_snapped_to_walls += to_walls;
    report.dropped_degenerate_walls += drop_degenerate(walls, origin, options.min_wall_length_m);
  }

  // 3. Collinear merge.
  std::vector<Segment2> segs;
  segs.reserve(walls.size());
  for (const Wall& w : walls) segs.push_back(w.centerline());
  const std::vector<std::vector<int>> members = collinear_runs(segs, tol, options.angle_tolerance_rad);
  const int group_count = static_cast<int>(members.size());
  std::vector<int> group(walls.size(), -1);
  for (int g = 0; g < group_count; ++g) {
    for (int m : members[static_cast<std::size_t>(g)]) group[static_cast<std::size_t>(m)] = g;
  }

  std::vector<GroupLine> lines(static_cast<std::size_t>(group_count));
  std::vector<MergedPiece> pieces;
  for (int g = 0; g < group_count; ++g) {
    const std::vector<int>& mem = members[static_cast<std::size_t>(g)];
    if (mem.size() > 1) ++report.collinear_groups_merged;
    const GroupLine line = fit_group_line(segs, mem);
    lines[static_cast<std::size_t>(g)] = line;
    struct Interval { double t0, t1; int wall; Attributes attr; };
    std::vector<Interval> iv;
    std::vector<double> cuts;
    std::map<double, Vec2> cut_point;  // a member endpoint lying on the line at this cut
    for (int m : mem) {
      const Vec2& pa = segs[static_cast<std::size_t>(m)].a_m;
      const Vec2& pb = segs[static_cast<std::size_t>(m)].b_m;
      double t0 = line.param(pa);
      double t1 = line.param(pb);
      for (const auto& [t, q] : {std::make_pair(t0, pa), std::make_pair(t1, pb)}) {
        if ((line.at(t) - q).norm() <= 1e-9) cut_point.emplace(t, q);
      }
      if (t1 < t0) std::swap(t0, t1);
      iv.push_back({t0, t1, m, attributes_of(walls[static_cast<std::size_t>(m)])});
      cuts.push_back(t0);
      cuts.push_back(t1);
    }
    // Pieces end at original endpoints where those already lie on the line (no rounding drift).
    auto at_cut = [&](double t) {
      auto it = cut_point.find(t);
      return it != cut_point.end() ? it->second : line.at(t);
    };
    std::sort(cuts.begin(), cuts.end());
    cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
    // Elementary intervals with their best covering wall.
    struct Elem { double t0, t1; int best = -1; std::vector<int> cover; };
    std::vector<Elem> elems;
    for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
      Elem e;
      e.t0 = cuts[k];
      e.t1 = cuts[k + 1];
      const double mid = 0.5 * (e.t0 + e.t1);
      for (std::size_t q = 0; q < iv.size(); ++q) {
        if (iv[q].t0 <= mid && mid <= iv[q].t1) {
          e.cover.push_back(static_cast<int>(q));
          if (e.best < 0 || iv[q].attr.beats(iv[static_cast<std::size_t>(e.best)].attr)) e.best = static_cast<int>(q);
        }
      }
      if (e.cover.size() > 1) report.duplicate_length_m += (e.t1 - e.t0) * static_cast<double>(e.cover.size() - 1);
      elems.push_back(std::move(e));
    }
    // Close small gaps between covered intervals.
    for (std::size_t k = 1; k + 1 < elems.size(); ++k) {
      Elem& e = elems[k];
      if (e.best >= 0 || e.t1 - e.t0 > tol) continue;
      std::size_t l = k - 1, r = k + 1;
      if (elems[l].best < 0 || elems[r].best < 0) continue;
      e.best = elems[l].best;  // bridged with the left neighbour's wall
      ++report.gaps_closed;
    }
    // Maximal runs of equal attributes.
    std::size_t k = 0;
    while (k < elems.size()) {
      if (elems[k].best < 0) {
        ++k;
        continue;
      }
      const Attributes attr = iv[static_cast<std::size_t>(elems[k].best)].attr;
      const double ttol = options.thickness_tolerance_m;
      std::size_t e = k;
      std::set<int> contrib;
      int defining = std::numeric_limits<int>::max();
      double thick_sum = 0.0, len_sum = 0.0;
      while (e < elems.size() && elems[e].best >= 0 && iv[static_cast<std::size_t>(elems[e].best)].attr.same(attr, ttol)) {
        for (int q : elems[e].cover) contrib.insert(iv[static_cast<std::size_t>(q)].wall);
        for (int q : elems[e].cover) {
          if (iv[static_cast<std::size_t>(q)].attr.same(attr, ttol)) defining = std::min(defining, iv[static_cast<std::size_t>(q)].wall);
        }
        const double len = elems[e].t1 - elems[e].t0;
        thick_sum += len * iv[static_cast<std::size_t>(elems[e].best)].attr.thickness_m;
        len_sum += len;
        ++e;
      }
      if (defining == std::numeric_limits<int>::max()) defining = iv[static_cast<std::size_t>(elems[k].best)].wall;
      MergedPiece piece;
      piece.wall = walls[static_cast<std::size_t>(defining)];
      piece.wall.a_m = at_cut(elems[k].t0);
      piece.wall.b_m = at_cut(elems[e - 1].t1);
      // Mean thickness only where thicknesses actually differ (keeps equal ones bit-exact).
      bool uniform = true;
      for (std::size_t q = k; q < e; ++q) uniform = uniform && iv[static_cast<std::size_t>(elems[q].best)].attr.thickness_m == attr.thickness_m;
      piece.wall.thickness_m = uniform || len_sum <= 0.0 ? attr.thickness_m : thick_sum / len_sum;
      piece.group = g;
      piece.t0 = elems[k].t0;
      piece.contributors.assign(contrib.begin(), contrib.end());
      piece.order_key = defining;
      pieces.push_back(std::move(piece));
      k = e;
    }
  }
  std::set<int> defining_walls;
  for (const MergedPiece& p : pieces) defining_walls.insert(p.order_key);
  std::stable_sort(pieces.begin(), pieces.end(), [](const MergedPiece& a, const MergedPiece& b) {
    if (a.order_key != b.order_key) return a.order_key < b.order_key;
    return a.t0 < b.t0;
  });

  // Unique ids: first piece of an input wall keeps its id, later ones get suffixes.
  std::set<std::string> used;
  for (const Door& d : plan.doors) used.insert(d.id);
  for (const Window& w : plan.windows) used.insert(w.id);
  for (const Obstacle& o : plan.obstacles) used.insert(o.id);
  std::vector<Wall> merged;
  std::vector<int> piece_group;
  std::vector<int> merged_origin;
  for (MergedPiece& p : pieces) {
    std::string id = p.wall.id;
    if (used.count(id)) {
      for (int s = 2;; ++s) {
        const std::string candidate = p.wall.id + "-" + std::to_string(s);
        if (!used.count(candidate)) {
          id = candidate;
          break;
        }
      }
    }
    used.insert(id);
    p.wall.id = id;
    merged.push_back(p.wall);
    piece_group.push_back(p.group);
    merged_origin.push_back(p.order_key);
  }

  // 4. Snap again so that merged lines meet exactly; drop what became degenerate.
  {
    const auto [snapped, to_walls] = snap_endpoints(merged, tol);
    report.snapped_endpoints += snapped;
    report.endpoints_snapped_to_walls += to_walls;
    std::vector<int> keep_index(merged.size());
    std::iota(keep_index.begin(), keep_index.end(), 0);
    report.dropped_degenerate_walls += drop_degenerate(merged, keep_index, options.min_wall_length_m);
    std::vector<int> g2;
    for (int idx : keep_index) g2.push_back(piece_group[static_cast<std::size_t>(idx)]);
    piece_group = std::move(g2);
  }

  // Group of each input wall (by input index), for re-attaching openings.
  std::vector<int> input_group(plan.walls.size(), -1);
  for (std::size_t i = 0; i < walls.size(); ++i) input_group[static_cast<std::size_t>(origin[i])] = group[i];

  // 5. Re-attach openings.
  std::vector<Segment2> merged_segs;
  for (const Wall& w : merged) merged_segs.push_back(w.centerline());
  double max_half = 0.0;
  for (const Wall& w : merged) max_half = std::max(max_half, 0.5 * w.thickness_m);
  const SegmentGrid grid(merged_segs, max_half + options.opening_attach_tolerance_m);

  std::multimap<int, int> group_pieces;  // run -> merged walls
  for (std::size_t w = 0; w < merged.size(); ++w) group_pieces.emplace(piece_group[w], static_cast<int>(w));
  struct Placement {
    int wall = -1;
    double t0 = 0.0, t1 = 0.0;  // span along the wall (may overshoot its ends)
    double across = 0.0;        // distance of the centre from the wall axis
    double overshoot = 0.0;     // how far the span leaves the wall (both ends together)
  };
  // Ranking of candidate walls: spans that fit (overshoot within the snap tolerance) before spans
  // that must slide, then the smaller overshoot, then the nearer axis.
  auto better = [&](const Placement& a, const Placement& b) {
    const bool a_slides = a.overshoot > tol + 1e-9, b_slides = b.overshoot > tol + 1e-9;
    if (a_slides != b_slides) return !a_slides;
    if (a_slides && std::abs(a.overshoot - b.overshoot) > 1e-9) return a.overshoot < b.overshoot;
    return a.across < b.across;
  };
  // Finds the wall for an opening; returns a placement or a reason in `why`.
  auto place = [&](const std::string& old_wall, const Vec2& center, double width, bool is_window,
                   std::string& why) -> Placement {
    // A candidate: the centre lies within thickness/2 + the attach tolerance of the wall's axis and
    // along the wall, or beyond one of its ends by at most half the opening's width (a door node
    // on a wall end: the span then slides inside the wall).
    auto try_wall = [&](int w, Placement& out) {
      const Wall& wall = merged[static_cast<std::size_t>(w)];
      if (is_window && wall.material == WallMaterial::kGlass) return false;
      const double len = wall.length_m();
      const Vec2 u = wall.direction();
      const Vec2 r = center - wall.a_m;
      const double along = r.dot(u);
      const double across = std::abs(u.x() * r.y() - u.y() * r.x());
      if (across > 0.5 * wall.thickness_m + options.opening_attach_tolerance_m) return false;
      if (along < -0.5 * width - 1e-9 || along > len + 0.5 * width + 1e-9) return false;
      const double t0 = along - 0.5 * width, t1 = along + 0.5 * width;
      out = {w, t0, t1, across, std::max(0.0, -t0) + std::max(0.0, t1 - len)};
      return true;
    };
    Placement best;
    auto consider = [&](int w) {
      Placement p;
      if (try_wall(w, p) && (best.wall < 0 || better(p, best))) best = p;
    };
    // Prefer the merged walls of the opening's original line group (the source said which wall);
    // look around only when none of them takes it.
    auto it = input_index.find(old_wall);
    if (it != input_index.end() && input_group[static_cast<std::size_t>(it->second)] >= 0) {
      const auto range = group_pieces.equal_range(input_group[static_cast<std::size_t>(it->second)]);
      for (auto p = range.first; p != range.second; ++p) consider(p->second);
    }
    if (best.wall < 0) {
      for (int w : grid.near(center)) consider(w);
    }
    if (best.wall >= 0) return best;
    // Explain why not.
    double nearest = std::numeric_limits<double>::infinity();
    int nearest_wall = -1;
    for (std::size_t w = 0; w < merged.size(); ++w) {
      const double d = point_segment_distance(center, merged_segs[w]);
      if (d < nearest) {
        nearest = d;
        nearest_wall = static_cast<int>(w);
      }
    }
    if (nearest_wall < 0) {
      why = "there are no walls";
    } else {
      const Wall& w = merged[static_cast<std::size_t>(nearest_wall)];
      const double reach = 0.5 * w.thickness_m + options.opening_attach_tolerance_m;
      if (nearest > reach) {
        why = "does not lie on any wall (nearest wall " + quoted(w.id) + " is " + fmt(nearest) +
              " m away, attach tolerance " + fmt(reach) + " m)";
      } else if (is_window && w.material == WallMaterial::kGlass) {
        why = "lies on glass wall " + quoted(w.id) + " (windows go into solid walls)";
      } else {
        const double along = (center - w.a_m).dot(w.direction());
        why = "its span [" + fmt(along - 0.5 * width) + ", " + fmt(along + 0.5 * width) +
              "] m does not reach wall " + quoted(w.id) + " [0, " + fmt(w.length_m()) + "] m";
      }
    }
    return {};
  };

  // Puts an opening on its wall: the centre onto the wall's axis; a span overshooting an end by at
  // most the snap tolerance is shortened, one overshooting more slides inside the wall, one wider
  // than the wall is narrowed to it. Every repair is counted; the larger ones get a note.
  auto fit_span = [&](const std::string& name, const Placement& p, Vec2& center, double& width) {
    const Wall& wall = merged[static_cast<std::size_t>(p.wall)];
    const double len = wall.length_m();
    double t0 = p.t0, t1 = p.t1;
    if (t1 - t0 > len) {
      report.notes.push_back(name + " narrowed from " + fmt(t1 - t0) + " m to the " + fmt(len) + " m of wall " +
                             quoted(wall.id) + " (wider than its wall)");
      ++report.openings_narrowed;
      t0 = 0.0;
      t1 = len;
    } else if (t0 < 0.0 || t1 > len) {
      if (p.overshoot <= tol + 1e-9) {
        t0 = std::max(t0, 0.0);
        t1 = std::min(t1, len);
        ++report.openings_trimmed;
      } else {
        const double shift = t0 < 0.0 ? -t0 : len - t1;
        t0 += shift;
        t1 += shift;
        ++report.openings_slid;
        report.notes.push_back(name + " slid " + fmt(std::abs(shift)) + " m along wall " + quoted(wall.id) +
                               " to lie inside it (its span overran the wall's end)");
      }
    }
    const Vec2 u = wall.direction();
    center = wall.a_m + 0.5 * (t0 + t1) * u;
    width = t1 - t0;
    constexpr double kOnAxis = 1e-3;  // within a millimetre: coordinate noise, not a repair
    if (p.across > kOnAxis) {
      ++report.openings_moved_to_axis;
      if (p.across > kOpeningNoteOffsetM) {
        report.notes.push_back(name + " moved " + fmt(p.across) + " m onto the axis of wall " + quoted(wall.id));
      }
    }
  };

  auto unattachable = [&](const std::string& name, const std::string& why) {
    if (!options.drop_unattachable_openings) throw InputError(source + ": " + name + ": " + why);
    report.notes.push_back(name + " dropped: " + why);
    ++report.openings_dropped;
  };

  // Doors and windows alike: place each on its (merged) wall, fit its span, or drop it with a note.
  auto reattach = [&](const auto& openings, const char* kind, bool is_window) {
    std::remove_const_t<std::remove_reference_t<decltype(openings)>> kept;
    for (std::size_t i = 0; i < openings.size(); ++i) {
      auto o = openings[i];
      std::string why;
      const Placement p = place(o.wall_id, o.center_m, o.width_m, is_window, why);
      const std::string name = std::string(kind) + "[" + std::to_string(i) + "] (id " + quoted(o.id) + ")";
      if (p.wall < 0) {
        unattachable(name, why);
        continue;
      }
      fit_span(name, p, o.center_m, o.width_m);
      const std::string& wid = merged[static_cast<std::size_t>(p.wall)].id;
      if (wid != o.wall_id) ++report.openings_reattached;
      o.wall_id = wid;
      kept.push_back(std::move(o));
    }
    return kept;
  };
  std::vector<Door> doors = reattach(plan.doors, "doors", false);
  std::vector<Window> windows = reattach(plan.windows, "windows", true);

  // Merge openings of one kind whose spans overlap on one wall.
  std::map<std::string, int> merged_index;
  for (std::size_t w = 0; w < merged.size(); ++w) merged_index.emplace(merged[w].id, static_cast<int>(w));
  auto merge_openings = [&](auto& list, auto combine) {
    using T = typename std::decay_t<decltype(list)>::value_type;
    std::map<std::string, std::vector<std::size_t>> by_wall;
    for (std::size_t i = 0; i < list.size(); ++i) by_wall[list[i].wall_id].push_back(i);
    std::vector<bool> gone(list.size(), false);
    for (const auto& [wall_id, idx] : by_wall) {
      const Wall& wall = merged[static_cast<std::size_t>(merged_index.at(wall_id))];
      const Vec2 u = wall.direction();
      bool changed = true;
      while (changed) {
        changed = false;
        for (std::size_t ia = 0; ia < idx.size(); ++ia) {
          const std::size_t a = idx[ia];
          if (gone[a]) continue;
          for (std::size_t ib = ia + 1; ib < idx.size(); ++ib) {
            const std::size_t b = idx[ib];
            if (gone[b]) continue;
            const double ca = (list[a].center_m - wall.a_m).dot(u), cb = (list[b].center_m - wall.a_m).dot(u);
            const double a0 = ca - 0.5 * list[a].width_m, a1 = ca + 0.5 * list[a].width_m;
            const double b0 = cb - 0.5 * list[b].width_m, b1 = cb + 0.5 * list[b].width_m;
            if (std::min(a1, b1) - std::max(a0, b0) <= 1e-6) continue;
            const double t0 = std::min(a0, b0), t1 = std::max(a1, b1);
            T& keep = list[a];
            combine(keep, list[b]);
            keep.center_m = wall.a_m + 0.5 * (t0 + t1) * u;
            keep.width_m = t1 - t0;
            gone[b] = true;
            ++report.openings_merged;
            changed = true;
          }
        }
      }
    }
    std::vector<T> out;
    for (std::size_t i = 0; i < list.size(); ++i) {
      if (!gone[i]) out.push_back(std::move(list[i]));
    }
    list = std::move(out);
  };
  merge_openings(doors, [](Door& keep, const Door& other) { keep.closed = keep.closed || other.closed; });
  merge_openings(windows, [](Window& keep, const Window& other) {
    keep.sill_m = std::min(keep.sill_m, other.sill_m);
    keep.head_m = std::max(keep.head_m, other.head_m);
  });

  plan.walls = std::move(merged);
  plan.doors = std::move(doors);
  plan.windows = std::move(windows);
  report.output_walls = static_cast<int>(plan.walls.size());
  report.walls_merged_away = static_cast<int>(walls.size() - defining_walls.size());
  return report;
}

}  // namespace floorcast
