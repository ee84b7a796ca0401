// The VoxelPlane-Reloc plane matcher: triplet selection, transform evaluation and the pose
// density (plane_matcher.hpp).
#include "floorcast/match/plane_matcher.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <numeric>
#include <queue>
#include <tuple>
#include <unordered_map>

#include "floorcast/core/math.hpp"
#include "floorcast/floorplans/raster.hpp"
#include "floorcast/match/plan_raster.hpp"

namespace floorcast {
namespace {

using Clock = std::chrono::steady_clock;
double seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

double angle_between_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return rad_to_deg(std::acos(std::clamp(a.dot(b), -1.0, 1.0)));
}

/// Signed rotation about z taking the horizontal part of a to that of b (radians); false when
/// either is (nearly) vertical.
bool yaw_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double& yaw) {
  const Eigen::Vector2d p = a.head<2>(), q = b.head<2>();
  if (p.norm() < 0.2 || q.norm() < 0.2) return false;
  yaw = std::atan2(p.x() * q.y() - p.y() * q.x(), p.dot(q));
  return true;
}

/// The usable submap planes: large enough, ground first (the largest plane whose normal is within
/// tau_g of up), then by area, at most max_planes.
struct Submap {
  std::vector<PlanePatch> planes;
  std::vector<PlaneKind> kinds;
  std::vector<double> cells;  ///< area in map cells (l x l)
  int ground = -1;
};

Submap prepare_submap(const Observation2D& obs, const PlaneMatcherParams& p) {
  Submap s;
  const double cell_area = obs.plane_cell_m * obs.plane_cell_m;
  const double c = std::cos(deg_to_rad(p.tau_g_deg)), sn = std::sin(deg_to_rad(p.tau_g_deg));
  std::vector<int> order;
  for (std::size_t k = 0; k < obs.planes.size(); ++k) {
    const PlanePatch& pl = obs.planes[k];
    if (pl.cells_m.empty() || static_cast<double>(pl.cells_m.size()) * cell_area < p.min_plane_area_m2) continue;
    if (pl.centroid_m.head<2>().norm() - pl.radius_m > p.max_range_m) continue;
    order.push_back(static_cast<int>(k));
  }
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return obs.planes[static_cast<std::size_t>(a)].cells_m.size() > obs.planes[static_cast<std::size_t>(b)].cells_m.size();
  });
  int ground = -1;
  for (int k : order) {
    if (obs.planes[static_cast<std::size_t>(k)].normal.z() >= c) {
      ground = k;
      break;
    }
  }
  if (ground >= 0) {
    order.erase(std::find(order.begin(), order.end(), ground));
    order.insert(order.begin(), ground);
    s.ground = 0;
  }
  if (static_cast<int>(order.size()) > p.max_planes) order.resize(static_cast<std::size_t>(p.max_planes));
  const double to_map_cells = cell_area / (p.cell_m * p.cell_m);
  for (int k : order) {
    const PlanePatch& pl = obs.planes[static_cast<std::size_t>(k)];
    s.planes.push_back(pl);
    const double nz = pl.normal.z();
    s.kinds.push_back(nz >= c ? PlaneKind::kGround : nz <= -c ? PlaneKind::kCeiling : std::abs(nz) <= sn ? PlaneKind::kWall : PlaneKind::kOther);
    s.cells.push_back(static_cast<double>(pl.cells_m.size()) * to_map_cells);
  }
  return s;
}

/// The incremental input order: the ground, then planes of distinct orientation by size up to
/// initial_planes, then the rest by size.
std::vector<int> input_order(const Submap& s, const PlaneMatcherParams& p, int& initial) {
  std::vector<int> order, rest;
  const int n = static_cast<int>(s.planes.size());
  int start = 0;
  if (s.ground == 0) {
    order.push_back(0);
    start = 1;
  }
  const int want = p.incremental ? p.initial_planes : n;
  for (int k = start; k < n; ++k) {
    bool distinct = true;
    for (int o : order) {
      if (o != s.ground && angle_between_deg(s.planes[static_cast<std::size_t>(k)].normal, s.planes[static_cast<std::size_t>(o)].normal) < 20.0) {
        distinct = false;
      }
    }
    if (distinct && static_cast<int>(order.size()) < want) {
      order.push_back(k);
    } else {
      rest.push_back(k);
    }
  }
  for (int k : rest) {
    if (static_cast<int>(order.size()) < want) order.push_back(k);
  }
  initial = static_cast<int>(order.size());
  for (int k : rest) {
    if (std::find(order.begin(), order.end(), k) == order.end()) order.push_back(k);
  }
  return order;
}

/// Mahalanobis distance of two transforms under the kernel of eq. 14 (translation over
/// sigma_xy, rotation angle over sigma_yaw).
double transform_distance(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double sxy, double syaw) {
  const double dt = (a.translation() - b.translation()).norm() / sxy;
  const double dr = Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() / syaw;
  return std::sqrt(dt * dt + dr * dr);
}

}  // namespace

/// One match's search: the submap, the map and every check of the paper.
struct PlaneMatcher::Search {
  const PlaneMatcherParams& p;
  const PlaneMap& map;
  Submap sub;
  // Map planes by normal direction, for the uniqueness check: wall planes in 1-degree azimuth
  // bins sorted by offset, the others in one list.
  std::vector<std::vector<int>> azimuth_bins;
  std::vector<int> non_walls;
  std::map<std::string, double> counters;
  long long evaluated = 0;
  bool truncated = false;
  std::vector<int> window;  ///< ground_triplets' candidate map planes (reused)
  mutable std::vector<Eigen::Vector3d> scratch_ns, scratch_nm;  ///< solve()'s pairs (reused)
  mutable std::vector<double> scratch_ds, scratch_dm;

  Search(const PlaneMatcherParams& params, const PlaneMap& m, Submap s) : p(params), map(m), sub(std::move(s)) {
    azimuth_bins.assign(360, {});
    const double sn = std::sin(deg_to_rad(p.match_normal_deg));
    for (std::size_t k = 0; k < map.planes.size(); ++k) {
      const Eigen::Vector3d& n = map.planes[k].normal;
      if (std::abs(n.z()) <= sn) {
        const double az = std::atan2(n.y(), n.x());
        int bin = static_cast<int>(std::floor((rad_to_deg(az) + 180.0)));
        bin = ((bin % 360) + 360) % 360;
        azimuth_bins[static_cast<std::size_t>(bin)].push_back(static_cast<int>(k));
      } else {
        non_walls.push_back(static_cast<int>(k));
      }
    }
    for (auto& b : azimuth_bins) {
      std::sort(b.begin(), b.end(), [&](int x, int y) {
        return std::make_pair(map.planes[static_cast<std::size_t>(x)].offset_m, x) <
               std::make_pair(map.planes[static_cast<std::size_t>(y)].offset_m, y);
      });
    }
  }

  /// Eq. 10: the share of the submap plane's cells that, transformed, lie within the tolerance
  /// of the map plane and on its (grown) extent. Stops early (returning a lower bound) once
  /// `need` is out of reach.
  double projection_share(const PlanePatch& s, const MapPlane& m, const Eigen::Isometry3d& T, double need) const {
    const std::size_t n = s.cells_m.size();
    if (n == 0) return 0.0;
    std::size_t in = 0;
    const std::size_t need_count = static_cast<std::size_t>(std::ceil(need * static_cast<double>(n) - 1e-9));
    // The map plane's normal and in-plane axes taken into the submap frame once (q = T c, so
    // a . q = (R^T a) . c + a . t): three dot products per cell instead of a transform and
    // MapPlane::covers' own projections.
    const Eigen::Matrix3d Rt = T.linear().transpose();
    const Eigen::Vector3d& t = T.translation();
    const Eigen::Vector3d n_s = Rt * m.normal, u_s = Rt * m.basis.col(0), v_s = Rt * m.basis.col(1);
    const double d0 = m.normal.dot(t) - m.offset_m, u0 = m.basis.col(0).dot(t), v0 = m.basis.col(1).dot(t);
    const double inv_l = 1.0 / m.cell_m;
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d& c = s.cells_m[i];
      if (std::abs(n_s.dot(c) + d0) <= p.projection_tolerance_m) {
        const int ci = static_cast<int>(std::floor((u_s.dot(c) + u0) * inv_l)) - m.i0;
        const int cj = static_cast<int>(std::floor((v_s.dot(c) + v0) * inv_l)) - m.j0;
        if (ci >= 0 && cj >= 0 && ci < m.width && cj < m.height &&
            m.grown[static_cast<std::size_t>(cj) * static_cast<std::size_t>(m.width) + static_cast<std::size_t>(ci)] != 0) {
          ++in;
        }
      }
      if (in + (n - i - 1) < need_count) return static_cast<double>(in) / static_cast<double>(n);
    }
    return static_cast<double>(in) / static_cast<double>(n);
  }

  /// Eq. 11: o = max(share of the map plane's cells within the transformed submap sphere, share
  /// of the transformed submap cells within the map plane's sphere).
  double overlap(const PlanePatch& s, const MapPlane& m, const Eigen::Isometry3d& T) const {
    std::size_t in_map_sphere = 0;
    for (const Eigen::Vector3d& c : s.cells_m) in_map_sphere += ((T * c) - m.centroid_m).norm() < m.radius_m ? 1 : 0;
    const double b = s.cells_m.empty() ? 0.0 : static_cast<double>(in_map_sphere) / static_cast<double>(s.cells_m.size());
    if (b >= 1.0) return 1.0;
    const Eigen::Vector3d c = T * s.centroid_m;
    const float r2 = static_cast<float>(s.radius_m * s.radius_m);
    const Eigen::Vector3f cf = c.cast<float>();
    std::size_t in_sub_sphere = 0;
    for (const Eigen::Vector3f& q : m.cell_centres_m) in_sub_sphere += (q - cf).squaredNorm() < r2 ? 1 : 0;
    const double a = m.cell_centres_m.empty() ? 0.0 : static_cast<double>(in_sub_sphere) / static_cast<double>(m.cell_centres_m.size());
    return std::max(a, b);
  }

  /// The map plane submap plane k agrees with under T (normal, offset, projection), or -1.
  int agreeing_map_plane(int k, const Eigen::Isometry3d& T) const {
    const PlanePatch& s = sub.planes[static_cast<std::size_t>(k)];
    const Eigen::Vector3d n = T.linear() * s.normal;
    const double d = s.offset_m + n.dot(T.translation());
    const double cos_tol = std::cos(deg_to_rad(p.match_normal_deg));
    int best = -1;
    double best_share = -1.0;
    auto consider = [&](int mi) {
      const MapPlane& m = map.planes[static_cast<std::size_t>(mi)];
      if (m.normal.dot(n) < cos_tol || std::abs(m.offset_m - d) > p.match_offset_m) return;
      const double share = projection_share(s, m, T, p.min_projection);
      if (share >= p.min_projection && share > best_share) {
        best_share = share;
        best = mi;
      }
    };
    const double sn = std::sin(deg_to_rad(p.match_normal_deg));
    if (std::abs(n.z()) <= sn) {
      const double az = rad_to_deg(std::atan2(n.y(), n.x())) + 180.0;
      const int span = static_cast<int>(std::ceil(p.match_normal_deg)) + 1;
      const int centre = static_cast<int>(std::floor(az));
      for (int b = centre - span; b <= centre + span; ++b) {
        const std::vector<int>& bin = azimuth_bins[static_cast<std::size_t>(((b % 360) + 360) % 360)];
        auto lo = std::lower_bound(bin.begin(), bin.end(), d - p.match_offset_m,
                                   [&](int mi, double v) { return map.planes[static_cast<std::size_t>(mi)].offset_m < v; });
        for (auto it = lo; it != bin.end() && map.planes[static_cast<std::size_t>(*it)].offset_m <= d + p.match_offset_m; ++it) consider(*it);
      }
    }
    for (int mi : non_walls) consider(mi);
    return best;
  }

  /// Evaluates a triplet's transform with the enabled strategies; true and the hypothesis
  /// filled when it is accepted.
  bool evaluate(const std::array<int, 3>& s, const std::array<int, 3>& m, const Eigen::Isometry3d& T, PlaneHypothesis& h) {
    ++evaluated;
    h.submap = s;
    h.map = m;
    h.T_world_observer = T;
    for (int k = 0; k < 3; ++k) {
      const PlanePatch& sp = sub.planes[static_cast<std::size_t>(s[static_cast<std::size_t>(k)])];
      const MapPlane& mp = map.planes[static_cast<std::size_t>(m[static_cast<std::size_t>(k)])];
      // The plane pair itself must agree under the transform (normal and offset); a rotation
      // fitted to three pairs can leave one of them far off.
      const Eigen::Vector3d n = T.linear() * sp.normal;
      if (angle_between_deg(n, mp.normal) > p.match_normal_deg) return false;
      if (std::abs(sp.offset_m + n.dot(T.translation()) - mp.offset_m) > p.match_offset_m) return false;
    }
    if (p.projection) {
      // Every pair must pass, so the order only changes the cost: the smallest submap planes
      // first (a wrong transform usually fails on a wall; the ground patch, the largest, lands on
      // some floor almost anywhere).
      std::array<int, 3> order{{0, 1, 2}};
      std::sort(order.begin(), order.end(), [&](int a, int b) {
        const std::size_t na = sub.planes[static_cast<std::size_t>(s[static_cast<std::size_t>(a)])].cells_m.size();
        const std::size_t nb = sub.planes[static_cast<std::size_t>(s[static_cast<std::size_t>(b)])].cells_m.size();
        return na != nb ? na < nb : a < b;
      });
      for (const int k : order) {
        const PlanePatch& sp = sub.planes[static_cast<std::size_t>(s[static_cast<std::size_t>(k)])];
        const MapPlane& mp = map.planes[static_cast<std::size_t>(m[static_cast<std::size_t>(k)])];
        h.projection[static_cast<std::size_t>(k)] = projection_share(sp, mp, T, p.min_projection);
        if (h.projection[static_cast<std::size_t>(k)] < p.min_projection) return false;
      }
    }
    for (int k = 0; k < 3; ++k) {
      h.overlap[static_cast<std::size_t>(k)] =
          overlap(sub.planes[static_cast<std::size_t>(s[static_cast<std::size_t>(k)])], map.planes[static_cast<std::size_t>(m[static_cast<std::size_t>(k)])], T);
      if (p.overlap && h.overlap[static_cast<std::size_t>(k)] < p.min_overlap) return false;
    }
    // Scene uniqueness and the majority of the planes (incremental input: "the preponderance of
    // planes successfully aligns").
    int agree = 0;
    const int n = static_cast<int>(sub.planes.size());
    for (int k = 0; k < n; ++k) {
      const bool in_triplet = k == s[0] || k == s[1] || k == s[2];
      if (in_triplet || agreeing_map_plane(k, T) >= 0) ++agree;
      if (agree + (n - k - 1) < (p.uniqueness ? p.tau_m : 0) || 2 * (agree + (n - k - 1)) <= n) return false;
    }
    h.agreeing_planes = agree;
    if (p.uniqueness && agree < p.tau_m) return false;
    return 2 * agree > n;
  }

  /// Least squares over every plane pair that agrees with T (ours, `refine`): the rotation from
  /// all their normals (about z only when T is gravity aligned), then the translation correction
  /// of minimum norm (directions no pair constrains keep T's translation).
  Eigen::Isometry3d refine(const Eigen::Isometry3d& T) const {
    std::vector<Eigen::Vector3d> ns, nm;
    std::vector<double> ds, dm;
    for (int k = 0; k < static_cast<int>(sub.planes.size()); ++k) {
      const int m = agreeing_map_plane(k, T);
      if (m < 0) continue;
      ns.push_back(sub.planes[static_cast<std::size_t>(k)].normal);
      ds.push_back(sub.planes[static_cast<std::size_t>(k)].offset_m);
      nm.push_back(map.planes[static_cast<std::size_t>(m)].normal);
      dm.push_back(map.planes[static_cast<std::size_t>(m)].offset_m);
    }
    if (ns.size() < 3) return T;
    Eigen::Isometry3d out = T;
    if (std::abs(T.linear()(2, 2) - 1.0) < 1e-9) {
      double sc = 0.0, ss = 0.0;
      for (std::size_t k = 0; k < ns.size(); ++k) {
        const Eigen::Vector2d a = ns[k].head<2>(), b = nm[k].head<2>();
        sc += a.dot(b);
        ss += a.x() * b.y() - a.y() * b.x();
      }
      out.linear() = Eigen::AngleAxisd(std::atan2(ss, sc), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    } else {
      out.linear() = rotation_from_normals(ns, nm);
    }
    for (std::size_t k = 0; k < ns.size(); ++k) ds[k] += nm[k].dot(T.translation());
    out.translation() = T.translation() + translation_from_offsets(nm, dm, ds);
    return out;
  }

  /// The triplet transform: gravity aligned when the ground is one of its pairs, else the
  /// quaternion and least-squares solution.
  Eigen::Isometry3d solve(const std::array<int, 3>& s, const std::array<int, 3>& m, bool gravity) const {
    // Normals and offsets only (the patches' cells are not copied), in reused buffers.
    std::vector<Eigen::Vector3d>& ns = scratch_ns;
    std::vector<Eigen::Vector3d>& nm = scratch_nm;
    std::vector<double>& ds = scratch_ds;
    std::vector<double>& dm = scratch_dm;
    ns.clear();
    nm.clear();
    ds.clear();
    dm.clear();
    for (int k = 0; k < 3; ++k) {
      const PlanePatch& sp = sub.planes[static_cast<std::size_t>(s[static_cast<std::size_t>(k)])];
      const MapPlane& mp = map.planes[static_cast<std::size_t>(m[static_cast<std::size_t>(k)])];
      ns.push_back(sp.normal);
      nm.push_back(mp.normal);
      ds.push_back(sp.offset_m);
      dm.push_back(mp.offset_m);
    }
    if (gravity) return gravity_aligned_transform(ns, ds, nm, dm);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = rotation_from_normals(ns, nm);
    T.translation() = translation_from_offsets(nm, dm, ds);
    return T;
  }

  bool area_ok(int s, int m) const {
    return !p.area_constraint || map.planes[static_cast<std::size_t>(m)].cells >= p.area_ratio * sub.cells[static_cast<std::size_t>(s)];
  }
  bool sphere_ok(int sa, int sb, int ma, int mb) const {
    if (!p.sphere_constraint) return true;
    const MapPlane& a = map.planes[static_cast<std::size_t>(ma)];
    const MapPlane& b = map.planes[static_cast<std::size_t>(mb)];
    const double map_d = (a.centroid_m - b.centroid_m).norm() - a.radius_m - b.radius_m;
    const double sub_d = (sub.planes[static_cast<std::size_t>(sa)].centroid_m - sub.planes[static_cast<std::size_t>(sb)].centroid_m).norm();
    return map_d <= sub_d + p.sphere_tolerance_m;
  }
  bool angle_ok(int a, int b) const {
    if (!p.orthogonal_constraint) return true;
    const double ang = angle_between_deg(sub.planes[static_cast<std::size_t>(a)].normal, sub.planes[static_cast<std::size_t>(b)].normal);
    return ang >= p.min_angle_deg && ang <= p.max_angle_deg;
  }
  bool budget() {
    if (evaluated >= p.max_hypotheses) truncated = true;
    return !truncated;
  }

  /// Ground-constrained triplets (ground, a, b) for the submap pair (a, b): the map pairs of
  /// planes close together whose orientation agrees with (a, b) about the vertical.
  void ground_triplets(int a, int b, std::vector<PlaneHypothesis>& out) {
    const PlanePatch& sa = sub.planes[static_cast<std::size_t>(a)];
    const PlanePatch& sb = sub.planes[static_cast<std::size_t>(b)];
    if (!angle_ok(a, b) || !angle_ok(0, a) || !angle_ok(0, b)) return;
    const double tol = deg_to_rad(p.angle_tolerance_deg);
    const double el_a = std::asin(std::clamp(sa.normal.z(), -1.0, 1.0)), el_b = std::asin(std::clamp(sb.normal.z(), -1.0, 1.0));
    const double az_b = std::atan2(sb.normal.y(), sb.normal.x());
    for (std::size_t ma = 0; ma < map.planes.size(); ++ma) {
      const MapPlane& pa = map.planes[ma];
      if (pa.kind == PlaneKind::kGround || pa.kind == PlaneKind::kCeiling) continue;
      if (std::abs(std::asin(std::clamp(pa.normal.z(), -1.0, 1.0)) - el_a) > tol || !area_ok(a, static_cast<int>(ma))) continue;
      double yaw_a = 0.0;
      if (!yaw_between(sa.normal, pa.normal, yaw_a)) continue;
      // The rotation about z that takes a to m_a takes b to azimuth az_b + yaw_a: only the
      // neighbours whose normals point there (within the tolerance) can be m_b.
      const auto& nb = map.neighbours_by_azimuth[ma];
      window.clear();
      const double want = wrap_angle_rad(az_b + yaw_a);
      for (const double centre : {want - 2.0 * kPi, want, want + 2.0 * kPi}) {
        auto lo = std::lower_bound(nb.begin(), nb.end(), std::make_pair(centre - tol, -1));
        for (auto it = lo; it != nb.end() && it->first <= centre + tol; ++it) window.push_back(it->second);
      }
      std::sort(window.begin(), window.end());
      window.erase(std::unique(window.begin(), window.end()), window.end());
      for (int mb : window) {
        const MapPlane& pb = map.planes[static_cast<std::size_t>(mb)];
        if (pb.kind == PlaneKind::kGround || pb.kind == PlaneKind::kCeiling) continue;
        if (std::abs(std::asin(std::clamp(pb.normal.z(), -1.0, 1.0)) - el_b) > tol || !area_ok(b, mb)) continue;
        double yaw_b = 0.0;
        if (!yaw_between(sb.normal, pb.normal, yaw_b) || angle_distance_rad(yaw_a, yaw_b) > tol) continue;
        if (!sphere_ok(a, b, static_cast<int>(ma), mb)) continue;
        if (!budget()) return;
        ++counters["map_pairs"];
        // The floor under the observer is the ground's match (every floor plane is z = 0).
        std::array<int, 3> m{{map.floors.empty() ? -1 : map.floors.front(), static_cast<int>(ma), mb}};
        if (m[0] < 0) return;
        const std::array<int, 3> s{{0, a, b}};
        const Eigen::Isometry3d T = solve(s, m, true);
        if (p.projection) {
          int under = -1;
          for (int f : map.floors) {
            if (map.planes[static_cast<std::size_t>(f)].covers(Eigen::Vector3d(T.translation().x(), T.translation().y(), 0.0))) {
              under = f;
              break;
            }
          }
          if (under < 0) {
            ++evaluated;
            continue;
          }
          m[0] = under;
        }
        PlaneHypothesis h;
        if (evaluate(s, m, T, h)) out.push_back(h);
      }
    }
  }

  /// Triplets without the ground constraint: any three input planes whose normals span space,
  /// map triplets of mutual neighbours whose pairwise angles agree.
  void free_triplets(int a, int b, int c, std::vector<PlaneHypothesis>& out) {
    const Eigen::Vector3d na = sub.planes[static_cast<std::size_t>(a)].normal, nb = sub.planes[static_cast<std::size_t>(b)].normal,
                          nc = sub.planes[static_cast<std::size_t>(c)].normal;
    if (std::abs(na.dot(nb.cross(nc))) < 0.2) return;  // degenerate: no unique transform
    if (!angle_ok(a, b) || !angle_ok(a, c) || !angle_ok(b, c)) return;
    const double tol = p.angle_tolerance_deg;
    const double ab = angle_between_deg(na, nb), ac = angle_between_deg(na, nc), bc = angle_between_deg(nb, nc);
    for (std::size_t ma = 0; ma < map.planes.size(); ++ma) {
      if (!area_ok(a, static_cast<int>(ma))) continue;
      const MapPlane& pa = map.planes[ma];
      for (int mb : map.neighbours[ma]) {
        const MapPlane& pb = map.planes[static_cast<std::size_t>(mb)];
        if (!area_ok(b, mb) || std::abs(angle_between_deg(pa.normal, pb.normal) - ab) > tol || !sphere_ok(a, b, static_cast<int>(ma), mb)) continue;
        for (int mc : map.neighbours[ma]) {
          if (mc == mb) continue;
          const MapPlane& pc = map.planes[static_cast<std::size_t>(mc)];
          if (!area_ok(c, mc) || std::abs(angle_between_deg(pa.normal, pc.normal) - ac) > tol ||
              std::abs(angle_between_deg(pb.normal, pc.normal) - bc) > tol || !sphere_ok(a, c, static_cast<int>(ma), mc) ||
              !sphere_ok(b, c, mb, mc)) {
            continue;
          }
          if (!budget()) return;
          const std::array<int, 3> s{{a, b, c}};
          const std::array<int, 3> m{{static_cast<int>(ma), mb, mc}};
          PlaneHypothesis h;
          if (evaluate(s, m, solve(s, m, false), h)) out.push_back(h);
        }
      }
    }
  }

  /// Every submap triplet against every ordered map triplet: no selection, only the evaluation.
  void brute_force(std::vector<PlaneHypothesis>& out) {
    const int n = static_cast<int>(sub.planes.size());
    const int M = static_cast<int>(map.planes.size());
    for (int a = 0; a < n; ++a) {
      for (int b = a + 1; b < n; ++b) {
        for (int c = b + 1; c < n; ++c) {
          const Eigen::Vector3d na = sub.planes[static_cast<std::size_t>(a)].normal, nb = sub.planes[static_cast<std::size_t>(b)].normal,
                                nc = sub.planes[static_cast<std::size_t>(c)].normal;
          if (std::abs(na.dot(nb.cross(nc))) < 0.2) continue;
          for (int ma = 0; ma < M; ++ma) {
            for (int mb = 0; mb < M; ++mb) {
              for (int mc = 0; mc < M; ++mc) {
                if (ma == mb || ma == mc || mb == mc) continue;
                const std::array<int, 3> s{{a, b, c}};
                const std::array<int, 3> m{{ma, mb, mc}};
                PlaneHypothesis h;
                if (evaluate(s, m, solve(s, m, false), h)) out.push_back(h);
              }
            }
          }
        }
      }
    }
  }

  /// The incremental (or all-at-once) search: triplets of the input planes, one more plane per
  /// round until a round accepts a transform.
  std::vector<PlaneHypothesis> run() {
    std::vector<PlaneHypothesis> out;
    const int n = static_cast<int>(sub.planes.size());
    if (n < 3) return out;
    int initial = 0;
    const std::vector<int> order = input_order(sub, p, initial);
    const bool ground = p.ground_constraint && sub.ground == 0 && !map.floors.empty();
    std::vector<int> inputs;
    int rounds = 0;
    for (std::size_t next = 0; next < order.size();) {
      std::vector<int> added;
      const std::size_t until = inputs.empty() ? static_cast<std::size_t>(initial) : next + 1;
      for (; next < until && next < order.size(); ++next) added.push_back(order[next]);
      std::vector<int> before = inputs;
      inputs.insert(inputs.end(), added.begin(), added.end());
      ++rounds;
      auto is_new = [&](int k) { return std::find(added.begin(), added.end(), k) != added.end(); };
      if (ground) {
        for (std::size_t i = 0; i < inputs.size(); ++i) {
          for (std::size_t j = i + 1; j < inputs.size(); ++j) {
            const int a = std::min(inputs[i], inputs[j]), b = std::max(inputs[i], inputs[j]);
            if (a == 0 || b == 0) continue;
            if (!is_new(a) && !is_new(b)) continue;
            ground_triplets(a, b, out);
            ground_triplets(b, a, out);
          }
        }
      } else {
        for (std::size_t i = 0; i < inputs.size(); ++i) {
          for (std::size_t j = i + 1; j < inputs.size(); ++j) {
            for (std::size_t k = j + 1; k < inputs.size(); ++k) {
              if (!is_new(inputs[i]) && !is_new(inputs[j]) && !is_new(inputs[k])) continue;
              std::array<int, 3> t{{inputs[i], inputs[j], inputs[k]}};
              std::sort(t.begin(), t.end());
              free_triplets(t[0], t[1], t[2], out);
            }
          }
        }
      }
      if (!out.empty() || truncated) break;
    }
    counters["input_planes"] = static_cast<double>(inputs.size());
    counters["rounds"] = rounds;
    return out;
  }
};

// ---------------------------------------------------------------------------------------------

PlaneMatcher::PlaneMatcher(const FloorPlan& plan, const PlaneMatcherParams& params) : params_(params) {
  const auto t0 = Clock::now();
  validate_extrusion(params_.extrusion);
  map_ = std::make_shared<const PlaneMap>(build_plane_map(plan, params_));
  grid_ = grid_for_plan(plan, params_.resolution_m, params_.grid_margin_m);
  check_raster_budget(grid_, 4.0 * params_.yaw_bins + 1.0, "matcher planes");
  valid_ = matcher_valid_mask(plan, grid_, params_.blocking);
  precompute_s_ = seconds(t0, Clock::now());
}

PlaneMatcher::~PlaneMatcher() = default;

std::size_t PlaneMatcher::precompute_bytes() const { return map_->bytes() + valid_.total(); }

std::vector<PlaneHypothesis> PlaneMatcher::hypotheses(const Observation2D& observation, bool brute_force) const {
  Search search(params_, *map_, prepare_submap(observation, params_));
  std::vector<PlaneHypothesis> hs;
  if (brute_force) {
    search.brute_force(hs);
  } else {
    hs = search.run();
  }
  weigh(hs);
  return hs;
}

void PlaneMatcher::weigh(std::vector<PlaneHypothesis>& hs) const {
  // Eq. 12: a pair's weight is the inverse of how often its map plane appears among the
  // triplets, each appearance counted by the similarity exp(-|log(v_a^-1 v_b)|) of the two
  // transforms (the triplet itself included, so every sum is >= 1). Eq. 13: w_a from the pairs'
  // overlaps. Eq. 14: the density at every triplet transform.
  const double sxy = params_.sigma_xy_m, syaw = deg_to_rad(params_.sigma_yaw_deg), cut = params_.kernel_cutoff;
  const std::size_t n = hs.size();
  // Neighbours within the kernel's cut-off, found by sorting on x.
  std::vector<std::size_t> by_x(n);
  std::iota(by_x.begin(), by_x.end(), 0);
  std::sort(by_x.begin(), by_x.end(), [&](std::size_t a, std::size_t b) {
    return std::make_pair(hs[a].T_world_observer.translation().x(), a) < std::make_pair(hs[b].T_world_observer.translation().x(), b);
  });
  std::vector<std::vector<std::pair<std::size_t, double>>> near(n);  // (b, distance)
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t a = by_x[i];
    for (std::size_t j = i; j < n; ++j) {
      const std::size_t b = by_x[j];
      if (hs[b].T_world_observer.translation().x() - hs[a].T_world_observer.translation().x() > cut * sxy) break;
      const double d = transform_distance(hs[a].T_world_observer, hs[b].T_world_observer, sxy, syaw);
      if (d > cut) continue;
      near[a].emplace_back(b, d);
      if (a != b) near[b].emplace_back(a, d);
    }
  }
  for (auto& v : near) std::sort(v.begin(), v.end());
  for (std::size_t a = 0; a < n; ++a) {
    double w = 0.0;
    for (int k = 0; k < 3; ++k) {
      double freq = 0.0;
      for (const auto& [b, d] : near[a]) {
        for (int q = 0; q < 3; ++q) freq += hs[b].map[static_cast<std::size_t>(q)] == hs[a].map[static_cast<std::size_t>(k)] ? std::exp(-d) : 0.0;
      }
      freq = std::max(freq, 1.0);
      const double o = hs[a].overlap[static_cast<std::size_t>(k)];
      switch (params_.pair_weights) {
        case PlanePairWeights::kInverseFrequency: w += o / freq; break;
        case PlanePairWeights::kAsPrinted: w += o * freq; break;
        case PlanePairWeights::kOverlap: w += o; break;
      }
    }
    hs[a].weight = w;
  }
  for (std::size_t b = 0; b < n; ++b) {
    double dens = 0.0;
    for (const auto& [a, d] : near[b]) dens += hs[a].weight * std::exp(-0.5 * d * d);
    hs[b].density = dens;
  }
}

MatchResult PlaneMatcher::match(const Observation2D& observation, const MatchRequest& request) const {
  const auto t0 = Clock::now();
  MatchResult result;
  result.grid = grid_;
  Search search(params_, *map_, prepare_submap(observation, params_));
  const auto t1 = Clock::now();
  std::vector<PlaneHypothesis> hs = search.run();
  const auto t2 = Clock::now();
  weigh(hs);
  const auto t3 = Clock::now();
  for (const auto& [k, v] : search.counters) result.counters[k] = v;
  result.counters["submap_planes"] = static_cast<double>(search.sub.planes.size());
  result.counters["map_planes"] = static_cast<double>(map_->planes.size());
  result.counters["hypotheses_evaluated"] = static_cast<double>(search.evaluated);
  result.counters["hypotheses_accepted"] = static_cast<double>(hs.size());
  result.counters["truncated"] = search.truncated ? 1.0 : 0.0;

  // The density on the grid: every accepted transform's kernel over (x, y, yaw), cut at
  // kernel_cutoff sigmas, zero outside the valid area. Accumulated per cell in the fixed order of
  // the hypotheses (same bytes whatever is asked for).
  const int K = params_.yaw_bins;
  std::vector<double> slice_yaw(static_cast<std::size_t>(K));
  for (int k = 0; k < K; ++k) slice_yaw[static_cast<std::size_t>(k)] = 2.0 * kPi * k / K;
  const double sxy = params_.sigma_xy_m, syaw = deg_to_rad(params_.sigma_yaw_deg), cut = params_.kernel_cutoff;
  const double res = grid_.resolution_m_per_px;
  std::unordered_map<long long, double> cells;
  std::vector<long long> cell_order;
  std::vector<Pose2> pose(hs.size());
  for (std::size_t a = 0; a < hs.size(); ++a) {
    pose[a] = planar_pose(hs[a].T_world_observer);
    const Pose2& v = pose[a];
    const int r0 = static_cast<int>(std::floor((v.y_m - cut * sxy - grid_.origin_y_m) / res));
    const int r1 = static_cast<int>(std::floor((v.y_m + cut * sxy - grid_.origin_y_m) / res));
    const int c0 = static_cast<int>(std::floor((v.x_m - cut * sxy - grid_.origin_x_m) / res));
    const int c1 = static_cast<int>(std::floor((v.x_m + cut * sxy - grid_.origin_x_m) / res));
    for (int k = 0; k < K; ++k) {
      const double dyaw = angle_distance_rad(slice_yaw[static_cast<std::size_t>(k)], v.yaw_rad) / syaw;
      if (dyaw > cut) continue;
      for (int r = std::max(0, r0); r <= std::min(grid_.height_px - 1, r1); ++r) {
        const unsigned char* vrow = valid_.ptr<unsigned char>(r);
        for (int c = std::max(0, c0); c <= std::min(grid_.width_px - 1, c1); ++c) {
          if (!vrow[c]) continue;
          const Vec2 cc = grid_.cell_center_m(r, c);
          const double dx = (cc.x() - v.x_m) / sxy, dy = (cc.y() - v.y_m) / sxy;
          const double m2 = dx * dx + dy * dy + dyaw * dyaw;
          if (m2 > cut * cut) continue;
          const long long key = (static_cast<long long>(k) * grid_.height_px + r) * grid_.width_px + c;
          auto [it, fresh] = cells.emplace(key, 0.0);
          if (fresh) cell_order.push_back(key);
          it->second += hs[a].weight * std::exp(-0.5 * m2);
        }
      }
    }
  }
  // Modes: greedy non-maximum suppression in descending score order, ties by (slice, row, col)
  // (Posterior::top_k's order and rule, on the non-zero cells only).
  struct Cell {
    float score;
    long long key;
  };
  std::vector<Cell> live;
  live.reserve(cell_order.size());
  for (long long key : cell_order) {
    const float s = static_cast<float>(cells[key]);
    if (s > 0.0f) live.push_back({s, key});
  }
  std::sort(live.begin(), live.end(), [](const Cell& a, const Cell& b) { return a.score > b.score || (a.score == b.score && a.key < b.key); });
  auto unpack = [&](long long key, int& k, int& r, int& c) {
    c = static_cast<int>(key % grid_.width_px);
    r = static_cast<int>((key / grid_.width_px) % grid_.height_px);
    k = static_cast<int>(key / (static_cast<long long>(grid_.width_px) * grid_.height_px));
  };
  std::vector<PoseHypothesis> modes;
  for (const Cell& cell : live) {
    if (static_cast<int>(modes.size()) >= request.top_k) break;
    int k, r, c;
    unpack(cell.key, k, r, c);
    bool suppressed = false;
    for (const PoseHypothesis& m : modes) {
      if (angle_distance_rad(slice_yaw[static_cast<std::size_t>(k)], m.yaw_rad) > request.mode_separation_rad) continue;
      const double dx = (c - m.col) * res, dy = (r - m.row) * res;
      if (std::sqrt(dx * dx + dy * dy) <= request.mode_separation_m + 1e-12) suppressed = true;
    }
    if (suppressed) continue;
    PoseHypothesis h;
    const Vec2 cc = grid_.cell_center_m(r, c);
    h.x_m = cc.x();
    h.y_m = cc.y();
    h.yaw_rad = slice_yaw[static_cast<std::size_t>(k)];
    h.score = cell.score;
    h.slice = k;
    h.row = r;
    h.col = c;
    modes.push_back(h);
  }
  // Each mode's pose: the accepted transform of highest density nearest to it (within the mode
  // separation), refined by least squares over every plane pair that agrees with it.
  std::vector<int> best_of_mode(modes.size(), -1);
  for (std::size_t a = 0; a < hs.size(); ++a) {
    double best_d = 1e300;
    int best_m = -1;
    for (std::size_t q = 0; q < modes.size(); ++q) {
      const double dxy = std::hypot(pose[a].x_m - modes[q].x_m, pose[a].y_m - modes[q].y_m);
      const double dyaw = angle_distance_rad(pose[a].yaw_rad, modes[q].yaw_rad);
      if (dxy > request.mode_separation_m || dyaw > request.mode_separation_rad) continue;
      const double d = dxy / sxy + dyaw / syaw;
      if (d < best_d) {
        best_d = d;
        best_m = static_cast<int>(q);
      }
    }
    if (best_m < 0) continue;
    int& b = best_of_mode[static_cast<std::size_t>(best_m)];
    if (b < 0 || hs[a].density > hs[static_cast<std::size_t>(b)].density) b = static_cast<int>(a);
  }
  for (std::size_t q = 0; q < modes.size(); ++q) {
    if (best_of_mode[q] < 0) continue;
    const PlaneHypothesis& h = hs[static_cast<std::size_t>(best_of_mode[q])];
    Eigen::Isometry3d T = h.T_world_observer;
    if (params_.refine) T = search.refine(T);
    const Pose2 v = planar_pose(T);
    modes[q].x_m = v.x_m;
    modes[q].y_m = v.y_m;
    modes[q].yaw_rad = wrap_angle_rad(v.yaw_rad);
  }
  result.modes = std::move(modes);
  const auto t4 = Clock::now();

  if (request.output != MatchOutput::kModes) {
    Posterior post;
    post.grid = grid_;
    post.yaw_rad = slice_yaw;
    for (int k = 0; k < K; ++k) post.scores.push_back(cv::Mat::zeros(grid_.height_px, grid_.width_px, CV_32F));
    for (long long key : cell_order) {
      int k, r, c;
      unpack(key, k, r, c);
      post.scores[static_cast<std::size_t>(k)].at<float>(r, c) = static_cast<float>(cells[key]);
    }
    if (request.output == MatchOutput::kMaxOverYaw) {
      result.max_over_yaw = post.max_over_yaw();
    } else {
      result.posterior = std::move(post);
    }
  }
  const auto t5 = Clock::now();
  result.stage_s["submap"] = seconds(t0, t1);
  result.stage_s["triplets"] = seconds(t1, t2);
  result.stage_s["density"] = seconds(t2, t3);
  result.stage_s["modes"] = seconds(t3, t4);
  result.stage_s["posterior"] = seconds(t4, t5);
  result.match_s = seconds(t0, t5);
  return result;
}

}  // namespace floorcast
