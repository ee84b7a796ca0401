// PALMS+ per-view relative scale alignment (eq. 2-3): L-BFGS-B (LBFGSpp) over the depth scales
// of all views but the reference, minimising the robust nearest-neighbour distance between the
// overlapping parts of neighbouring views (nanoflann kd-trees).
#include <LBFGSB.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <nanoflann.hpp>
#include <stdexcept>

#include "floorcast/core/random.hpp"
#include "floorcast/observe/observation_module.hpp"

namespace floorcast {
namespace {

/// Up to `limit` of `indices`, chosen uniformly at random by a hash of (seed, stream, index):
/// the same subset at any thread count and on any platform. Returned in ascending order.
std::vector<int> hashed_subset(const std::vector<int>& indices, std::size_t limit, std::uint64_t seed,
                               std::uint64_t stream) {
  if (indices.size() <= limit) return indices;
  std::vector<std::pair<std::uint64_t, int>> h(indices.size());
  const std::uint64_t base = mix64(seed ^ mix64(stream));
  for (std::size_t k = 0; k < indices.size(); ++k) {
    h[k] = {mix64(base + static_cast<std::uint64_t>(indices[k])), indices[k]};
  }
  std::nth_element(h.begin(), h.begin() + static_cast<std::ptrdiff_t>(limit), h.end());
  std::vector<int> out(limit);
  for (std::size_t k = 0; k < limit; ++k) out[k] = h[k].second;
  std::sort(out.begin(), out.end());
  return out;
}

/// Points of view `m` (scale 1) among `candidates` that project inside view `n`'s image.
std::vector<int> overlap_indices(const ViewCloud& m, const std::vector<int>& candidates, const ViewCloud& n) {
  const Eigen::Isometry3d T_n_m = n.T_scan_camera.inverse() * m.T_scan_camera;
  const Eigen::Matrix3f R = T_n_m.linear().cast<float>();
  const Eigen::Vector3f t = T_n_m.translation().cast<float>();
  const CameraIntrinsics& K = n.intrinsics;
  std::vector<int> out;
  for (const int i : candidates) {
    const Eigen::Vector3f q = R * m.points_camera[i] + t;
    if (q.z() <= 1e-3f) continue;
    const double u = K.fx_px * q.x() / q.z() + K.cx_px;
    const double v = K.fy_px * q.y() / q.z() + K.cy_px;
    if (u >= -0.5 && v >= -0.5 && u < K.width_px - 0.5 && v < K.height_px - 0.5) out.push_back(i);
  }
  return out;
}

/// A uniform random subsample of about `target` points of a view (hash threshold, deterministic):
/// PALMS+'s "<= 5000 points per cloud"; the overlaps with other views are subsets of it.
std::vector<int> candidate_pool(const ViewCloud& v, std::size_t target, std::uint64_t seed, std::uint64_t stream) {
  const std::size_t n = v.points_camera.size();
  std::vector<int> out;
  if (n <= target) {
    out.resize(n);
    for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<int>(i);
    return out;
  }
  const double frac = static_cast<double>(target) / static_cast<double>(n);
  const std::uint64_t threshold = static_cast<std::uint64_t>(frac * 18446744073709551615.0);
  const std::uint64_t base = mix64(seed ^ mix64(stream + 0x51ed2701u));
  out.reserve(target + target / 8);
  for (std::size_t i = 0; i < n; ++i) {
    if (mix64(base + i) < threshold) out.push_back(static_cast<int>(i));
  }
  return out;
}

/// nanoflann adaptor over a vector of 3D points.
struct CloudAdaptor {
  const std::vector<Eigen::Vector3f>* pts = nullptr;
  std::size_t kdtree_get_point_count() const { return pts->size(); }
  float kdtree_get_pt(std::size_t i, std::size_t d) const { return (*pts)[i][d]; }
  template <class BBox>
  bool kdtree_get_bbox(BBox&) const {
    return false;
  }
};
using KdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, CloudAdaptor>,
                                                   CloudAdaptor, 3, std::size_t>;

/// One direction m -> n of a neighbouring pair: sampled points of m inside n's view, and the
/// sampled points of n inside m's view as the nearest-neighbour target.
struct Term {
  int m = 0, n = 0;
  std::vector<Eigen::Vector3d> query_dir;   ///< R_m a (scan orientation, camera-centred, scale 1)
  Eigen::Vector3d t_m = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> target_dir;  ///< R_n b
  std::vector<Eigen::Vector3f> target_f;    ///< the same in float, for the kd-tree (searched in float,
                                            ///< distances then computed in double)
  Eigen::Vector3d t_n = Eigen::Vector3d::Zero();
  CloudAdaptor adaptor;
  std::unique_ptr<KdTree> tree;
};

struct Problem {
  std::vector<std::unique_ptr<Term>> terms;
};

/// Index of the target point nearest to the query point i of `t` at scales (lam_m, lam_n): the
/// NN in {t_n + lam_n r_j} of p = t_m + lam_m q_i is the NN of (p - t_n) / lam_n in {r_j}.
std::size_t nearest_target(const Term& t, std::size_t i, double lam_m, double lam_n) {
  const Eigen::Vector3d p = t.t_m + lam_m * t.query_dir[i];
  const Eigen::Vector3f xf = ((p - t.t_n) / lam_n).cast<float>();
  std::size_t j = 0;
  float sq = 0.0f;
  nanoflann::KNNResultSet<float, std::size_t> rs(1);
  rs.init(&j, &sq);
  t.tree->findNeighbors(rs, xf.data(), nanoflann::SearchParams(10));
  return j;
}

std::vector<Eigen::Vector3d> rotated(const ViewCloud& v, const std::vector<int>& idx) {
  const Eigen::Matrix3d R = v.T_scan_camera.linear();
  std::vector<Eigen::Vector3d> out(idx.size());
  for (std::size_t k = 0; k < idx.size(); ++k) out[k] = R * v.points_camera[idx[k]].cast<double>();
  return out;
}

Problem build_problem(const std::vector<ViewCloud>& views, const std::vector<std::pair<int, int>>& pairs,
                      const ScaleAlignmentParams& params,
                      const std::vector<std::vector<std::vector<int>>>& overlaps) {
  Problem prob;
  const std::size_t limit = static_cast<std::size_t>(std::max(1, params.max_points_per_cloud));
  const std::uint64_t nv = views.size();
  for (const auto& [a, b] : pairs) {
    const std::vector<int> sa = hashed_subset(overlaps[a][b], limit, params.seed, a * nv + b);
    const std::vector<int> sb = hashed_subset(overlaps[b][a], limit, params.seed, b * nv + a);
    for (int dir = 0; dir < 2; ++dir) {
      auto term = std::make_unique<Term>();
      term->m = dir == 0 ? a : b;
      term->n = dir == 0 ? b : a;
      term->query_dir = rotated(views[term->m], dir == 0 ? sa : sb);
      term->target_dir = rotated(views[term->n], dir == 0 ? sb : sa);
      term->t_m = views[term->m].T_scan_camera.translation();
      term->t_n = views[term->n].T_scan_camera.translation();
      prob.terms.push_back(std::move(term));
    }
  }
  tbb::parallel_for(std::size_t(0), prob.terms.size(), [&](std::size_t k) {
    Term& t = *prob.terms[k];
    t.target_f.resize(t.target_dir.size());
    for (std::size_t i = 0; i < t.target_dir.size(); ++i) t.target_f[i] = t.target_dir[i].cast<float>();
    t.adaptor.pts = &t.target_f;
    t.tree = std::make_unique<KdTree>(3, t.adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(10));
    t.tree->buildIndex();
  });
  return prob;
}

struct TermValue {
  double value = 0.0;
  double grad_m = 0.0;
  double grad_n = 0.0;
};

/// Eq. 3 from per-point distances and their derivatives w.r.t. the two scales: value and exact
/// gradient (the min and max points of the normalisation included).
TermValue combine_eq3(const std::vector<double>& dist, const std::vector<double>& dd_m,
                      const std::vector<double>& dd_n) {
  TermValue out;
  const std::size_t np = dist.size();
  if (np == 0) return out;
  std::size_t imin = 0, imax = 0;
  for (std::size_t i = 1; i < np; ++i) {
    if (dist[i] < dist[imin]) imin = i;
    if (dist[i] > dist[imax]) imax = i;
  }
  const double dmin = dist[imin], dmax = dist[imax], range = dmax - dmin;
  double sum = 0.0, g_m = 0.0, g_n = 0.0;
  if (range <= 1e-12) {
    for (std::size_t i = 0; i < np; ++i) {
      sum += dist[i];
      g_m += dd_m[i];
      g_n += dd_n[i];
    }
  } else {
    double c_max = 0.0, c_min = 0.0;  // d sum / d dmax, d sum / d dmin
    for (std::size_t i = 0; i < np; ++i) {
      const double d = dist[i];
      const double den = d + dmax - 2.0 * dmin;  // = (d - dmin) + range > 0
      sum += d * range / den;
      const double df_dd = range * (dmax - 2.0 * dmin) / (den * den);
      g_m += df_dd * dd_m[i];
      g_n += df_dd * dd_n[i];
      c_max += d * (d - dmin) / (den * den);
      c_min += d * (dmax - d) / (den * den);
    }
    g_m += c_max * dd_m[imax] + c_min * dd_m[imin];
    g_n += c_max * dd_n[imax] + c_min * dd_n[imin];
  }
  out.value = sum / np;
  out.grad_m = g_m / np;
  out.grad_n = g_n / np;
  return out;
}

/// Eq. 3 for one direction: d(P, Q) = 1/|P| sum_p ||p - NN_Q(p)|| / (||.||_[0,1] + 1), the
/// distances min-max normalised over P, nearest neighbours searched at the given scales.
TermValue evaluate_term(const Term& t, double lam_m, double lam_n) {
  TermValue out;
  const std::size_t np = t.query_dir.size();
  if (np == 0 || t.target_dir.empty()) return out;
  std::vector<double> dist(np), dd_m(np), dd_n(np);
  for (std::size_t i = 0; i < np; ++i) {
    const Eigen::Vector3d p = t.t_m + lam_m * t.query_dir[i];
    const std::size_t j = nearest_target(t, i, lam_m, lam_n);
    const Eigen::Vector3d e = p - (t.t_n + lam_n * t.target_dir[j]);
    const double d = e.norm();
    dist[i] = d;
    if (d > 0.0) {
      dd_m[i] = e.dot(t.query_dir[i]) / d;
      dd_n[i] = -e.dot(t.target_dir[j]) / d;
    } else {
      dd_m[i] = dd_n[i] = 0.0;
    }
  }
  return combine_eq3(dist, dd_m, dd_n);
}

double evaluate_problem(const Problem& prob, const std::vector<double>& scales,
                        std::vector<double>* gradient) {
  std::vector<TermValue> values(prob.terms.size());
  tbb::parallel_for(std::size_t(0), prob.terms.size(), [&](std::size_t k) {
    const Term& t = *prob.terms[k];
    values[k] = evaluate_term(t, scales[t.m], scales[t.n]);
  });
  double f = 0.0;
  if (gradient) gradient->assign(scales.size(), 0.0);
  for (std::size_t k = 0; k < values.size(); ++k) {  // fixed order: deterministic sums
    f += values[k].value;
    if (gradient) {
      (*gradient)[prob.terms[k]->m] += values[k].grad_m;
      (*gradient)[prob.terms[k]->n] += values[k].grad_n;
    }
  }
  return f;
}

/// Nearest neighbours of one term's query points at given scales, frozen for an inner solve,
/// with the min-max normalisation constants of eq. 3 at that moment.
struct Association {
  std::vector<int> nn;
  /// Per query point, |e|^2 as a quadratic in the two scales: with c = t_m - t_n, a = R_m p,
  /// b = R_n q_nn, e = c + lam_m a - lam_n b: {c.c, a.a, b.b, c.a, c.b, a.b}.
  std::vector<std::array<double, 6>> quad;
  double dmin = 0.0;
  double range = 0.0;
  double value = 0.0;  ///< eq. 3 at the association's scales
};

Association associate(const Term& t, double lam_m, double lam_n) {
  Association a;
  const std::size_t np = t.query_dir.size();
  a.nn.assign(np, 0);
  if (np == 0 || t.target_dir.empty()) return a;
  a.quad.resize(np);
  std::vector<double> dist(np);
  for (std::size_t i = 0; i < np; ++i) {
    const Eigen::Vector3d p = t.t_m + lam_m * t.query_dir[i];
    const std::size_t j = nearest_target(t, i, lam_m, lam_n);
    a.nn[i] = static_cast<int>(j);
    dist[i] = (p - (t.t_n + lam_n * t.target_dir[j])).norm();
    const Eigen::Vector3d c = t.t_m - t.t_n;
    const Eigen::Vector3d& qa = t.query_dir[i];
    const Eigen::Vector3d& qb = t.target_dir[j];
    a.quad[i] = {c.dot(c), qa.dot(qa), qb.dot(qb), c.dot(qa), c.dot(qb), qa.dot(qb)};
  }
  const auto [mn, mx] = std::minmax_element(dist.begin(), dist.end());
  a.dmin = *mn;
  a.range = *mx - *mn;
  double sum = 0.0;
  for (double d : dist) sum += a.range > 1e-12 ? d / ((d - a.dmin) / a.range + 1.0) : d;
  a.value = sum / np;
  return a;
}

/// Eq. 3 for one direction with its nearest neighbours frozen: the min-max normalisation is
/// recomputed from the current distances (so the loss stays relative to the current spread and
/// never saturates), and the gradient is exact, including the normalisation's min and max points.
TermValue evaluate_frozen(const Term& t, const Association& a, double lam_m, double lam_n) {
  TermValue out;
  const std::size_t np = a.quad.size();
  if (np == 0 || t.target_dir.empty()) return out;
  thread_local std::vector<double> dist, dd_m, dd_n;
  dist.resize(np);
  dd_m.resize(np);
  dd_n.resize(np);
  for (std::size_t i = 0; i < np; ++i) {
    const std::array<double, 6>& q = a.quad[i];
    const double d2 = q[0] + lam_m * lam_m * q[1] + lam_n * lam_n * q[2] + 2.0 * lam_m * q[3] -
                      2.0 * lam_n * q[4] - 2.0 * lam_m * lam_n * q[5];
    const double d = std::sqrt(std::max(0.0, d2));
    dist[i] = d;
    if (d > 0.0) {
      dd_m[i] = (lam_m * q[1] + q[3] - lam_n * q[5]) / d;
      dd_n[i] = (lam_n * q[2] - q[4] - lam_m * q[5]) / d;
    } else {
      dd_m[i] = dd_n[i] = 0.0;
    }
  }
  return combine_eq3(dist, dd_m, dd_n);
}

/// The L-BFGS-B functor over the free scales (all views but the reference) for frozen
/// associations; remembers the best point it has evaluated (a line search failure leaves the
/// solver's x at its last trial).
struct Objective {
  const Problem* prob = nullptr;
  const std::vector<Association>* assoc = nullptr;
  int n_views = 0;
  int reference = 0;
  int evaluations = 0;
  double best_f = std::numeric_limits<double>::infinity();
  Eigen::VectorXd best_x;

  std::vector<double> scales_of(const Eigen::VectorXd& x) const {
    std::vector<double> s(n_views, 1.0);
    for (int v = 0, k = 0; v < n_views; ++v) {
      if (v != reference) s[v] = x[k++];
    }
    return s;
  }
  double operator()(const Eigen::VectorXd& x, Eigen::VectorXd& grad) {
    ++evaluations;
    const std::vector<double> s = scales_of(x);
    std::vector<double> g(n_views, 0.0);
    std::vector<TermValue> values(prob->terms.size());
    tbb::parallel_for(std::size_t(0), prob->terms.size(), [&](std::size_t k) {
      const Term& t = *prob->terms[k];
      values[k] = evaluate_frozen(t, (*assoc)[k], s[t.m], s[t.n]);
    });
    double f = 0.0;
    for (std::size_t k = 0; k < values.size(); ++k) {  // fixed order: deterministic sums
      const Term& t = *prob->terms[k];
      f += values[k].value;
      g[t.m] += values[k].grad_m;
      g[t.n] += values[k].grad_n;
    }
    for (int v = 0, k = 0; v < n_views; ++v) {
      if (v != reference) grad[k++] = g[v];
    }
    if (f < best_f) {
      best_f = f;
      best_x = x;
    }
    return f;
  }
};

struct Overlaps {
  std::vector<std::vector<int>> pools;
  std::vector<std::vector<std::vector<int>>> ov;  ///< ov[a][b]: pool points of a inside b's view
};

Overlaps all_overlaps(const std::vector<ViewCloud>& views, const ScaleAlignmentParams& params) {
  const std::size_t n = views.size();
  Overlaps o;
  o.pools.resize(n);
  o.ov.assign(n, std::vector<std::vector<int>>(n));
  const std::size_t target = static_cast<std::size_t>(std::max(1, params.max_points_per_cloud));
  tbb::parallel_for(std::size_t(0), n, [&](std::size_t k) {
    // A little over the target by hash threshold, then exactly at most the target.
    o.pools[k] = hashed_subset(candidate_pool(views[k], target + target / 16 + 64, params.seed, k), target,
                               params.seed, 0x9000 + k);
  });
  tbb::parallel_for(std::size_t(0), n * n, [&](std::size_t k) {
    const std::size_t a = k / n, b = k % n;
    if (a != b) o.ov[a][b] = overlap_indices(views[a], o.pools[a], views[b]);
  });
  return o;
}

std::vector<std::pair<int, int>> neighbour_pairs(const Overlaps& o, const ScaleAlignmentParams& params) {
  std::vector<std::pair<int, int>> pairs;
  const int n = static_cast<int>(o.ov.size());
  auto enough = [&](int a, int b) {
    const double need = std::max(static_cast<double>(params.min_overlap_points),
                                 params.min_overlap_fraction * static_cast<double>(o.pools[a].size()));
    return static_cast<double>(o.ov[a][b].size()) >= need;
  };
  // Each view proposes its max_neighbours_per_view largest overlaps (the adjacent views of the
  // rotation); a pair is used when either view proposes it and both overlaps are large enough.
  std::vector<std::vector<bool>> proposed(n, std::vector<bool>(n, false));
  for (int a = 0; a < n; ++a) {
    std::vector<int> others;
    for (int b = 0; b < n; ++b) {
      if (b != a) others.push_back(b);
    }
    std::stable_sort(others.begin(), others.end(), [&](int x, int y) {
      return std::min(o.ov[a][x].size(), o.ov[x][a].size()) > std::min(o.ov[a][y].size(), o.ov[y][a].size());
    });
    const int keep = params.max_neighbours_per_view > 0
                         ? std::min<int>(params.max_neighbours_per_view, static_cast<int>(others.size()))
                         : static_cast<int>(others.size());
    for (int k = 0; k < keep; ++k) proposed[a][others[k]] = proposed[others[k]][a] = true;
  }
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b) {
      if (proposed[a][b] && enough(a, b) && enough(b, a)) pairs.emplace_back(a, b);
    }
  return pairs;
}

/// log(lambda_n / lambda_m) of a pair from shared rays: a point of m (scale 1) seen at pixel
/// (u, v) of n has z-depth q_z in n's frame, while n measured z_n there; with the right scales
/// lambda_m q_z = lambda_n z_n. Median over the overlap points; false when too few rays agree.
bool pair_log_ratio(const ViewCloud& m, const std::vector<int>& idx, const ViewCloud& n, double& log_ratio) {
  if (n.depth_m.empty()) return false;
  const Eigen::Isometry3d T_n_m = n.T_scan_camera.inverse() * m.T_scan_camera;
  const Eigen::Matrix3f R = T_n_m.linear().cast<float>();
  const Eigen::Vector3f t = T_n_m.translation().cast<float>();
  const CameraIntrinsics& K = n.intrinsics;
  std::vector<double> logs;
  logs.reserve(idx.size());
  for (const int i : idx) {
    const Eigen::Vector3f q = R * m.points_camera[i] + t;
    if (q.z() <= 1e-3f) continue;
    const int u = static_cast<int>(std::lround(K.fx_px * q.x() / q.z() + K.cx_px));
    const int v = static_cast<int>(std::lround(K.fy_px * q.y() / q.z() + K.cy_px));
    if (u < 0 || v < 0 || u >= n.depth_m.cols || v >= n.depth_m.rows) continue;
    const float zn = n.depth_m.at<float>(v, u);
    if (!(zn > 0.0f) || !std::isfinite(zn)) continue;
    logs.push_back(std::log(static_cast<double>(q.z()) / zn));
  }
  if (logs.size() < 20) return false;
  auto mid = logs.begin() + static_cast<std::ptrdiff_t>(logs.size() / 2);
  std::nth_element(logs.begin(), mid, logs.end());
  log_ratio = *mid;
  return true;
}

/// Initial scales: least squares on log scales over the pair graph, reference fixed at 0.
std::vector<double> ray_ratio_scales(const std::vector<ViewCloud>& views, const Overlaps& o,
                                     const std::vector<std::pair<int, int>>& pairs, int reference,
                                     double lo, double hi) {
  const int n = static_cast<int>(views.size());
  std::vector<double> out(n, 1.0);
  std::vector<std::pair<std::pair<int, int>, double>> eqs;
  for (const auto& [a, b] : pairs) {
    double r_ab = 0.0, r_ba = 0.0;
    const bool ok_ab = pair_log_ratio(views[a], o.ov[a][b], views[b], r_ab);  // log(l_b / l_a)
    const bool ok_ba = pair_log_ratio(views[b], o.ov[b][a], views[a], r_ba);  // log(l_a / l_b)
    if (ok_ab) eqs.push_back({{a, b}, r_ab});
    if (ok_ba) eqs.push_back({{a, b}, -r_ba});
  }
  if (eqs.empty()) return out;
  // Unknowns: log scales of all views but the reference; a tiny ridge keeps views without an
  // equation at 0.
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(static_cast<int>(eqs.size()) + n, n);
  Eigen::VectorXd y = Eigen::VectorXd::Zero(static_cast<int>(eqs.size()) + n);
  for (std::size_t k = 0; k < eqs.size(); ++k) {
    A(static_cast<int>(k), eqs[k].first.second) = 1.0;
    A(static_cast<int>(k), eqs[k].first.first) = -1.0;
    y(static_cast<int>(k)) = eqs[k].second;
  }
  for (int v = 0; v < n; ++v) A(static_cast<int>(eqs.size()) + v, v) = v == reference ? 1e3 : 1e-6;
  const Eigen::VectorXd ls = A.colPivHouseholderQr().solve(y);
  for (int v = 0; v < n; ++v) out[v] = std::clamp(std::exp(ls[v] - ls[reference]), lo, hi);
  out[reference] = 1.0;
  return out;
}

}  // namespace

double relative_scale_objective(const std::vector<ViewCloud>& views,
                                const std::vector<std::pair<int, int>>& pairs,
                                const std::vector<double>& scales, const ScaleAlignmentParams& params,
                                std::vector<double>* gradient) {
  const Overlaps o = all_overlaps(views, params);
  const Problem prob = build_problem(views, pairs, params, o.ov);
  return evaluate_problem(prob, scales, gradient);
}

RelativeScaleResult estimate_relative_scales(const std::vector<ViewCloud>& views,
                                             const ScaleAlignmentParams& params) {
  RelativeScaleResult res;
  const int n = static_cast<int>(views.size());
  res.scales.assign(n, 1.0);
  if (n < 2) {
    res.status = "fewer than two views: nothing to align";
    return res;
  }
  const int reference = std::clamp(params.reference_view, 0, n - 1);
  const auto t_setup = std::chrono::steady_clock::now();
  const Overlaps o = all_overlaps(views, params);
  res.pairs = neighbour_pairs(o, params);
  // Only views connected to the reference through neighbour pairs have a determined relative
  // scale; the others keep scale 1 (reported in status), and their pairs are left out (the
  // objective is not scale invariant: an unanchored group would just shrink).
  std::vector<bool> linked(n, false);
  linked[reference] = true;
  for (bool grew = true; grew;) {
    grew = false;
    for (const auto& [a, b] : res.pairs) {
      if (linked[a] != linked[b]) {
        linked[a] = linked[b] = true;
        grew = true;
      }
    }
  }
  res.pairs.erase(std::remove_if(res.pairs.begin(), res.pairs.end(),
                                 [&](const std::pair<int, int>& p) { return !linked[p.first]; }),
                  res.pairs.end());
  if (res.pairs.empty()) {
    res.status = "no overlapping neighbour views: scales left at 1";
    return res;
  }
  const Problem prob = build_problem(views, res.pairs, params, o.ov);
  res.setup_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_setup).count();

  LBFGSpp::LBFGSBParam<double> lp;
  lp.epsilon = params.gradient_epsilon;
  lp.epsilon_rel = 0.0;
  lp.past = 3;
  lp.delta = params.relative_epsilon;
  lp.max_iterations = params.max_iterations;
  lp.max_linesearch = 40;
  const Eigen::VectorXd lb = Eigen::VectorXd::Constant(n - 1, params.min_scale);
  const Eigen::VectorXd ub = Eigen::VectorXd::Constant(n - 1, params.max_scale);
  res.initial_scales.assign(n, 1.0);
  if (params.ray_ratio_init) {
    res.initial_scales = ray_ratio_scales(views, o, res.pairs, reference, params.min_scale, params.max_scale);
  }
  Eigen::VectorXd x(n - 1);
  for (int v = 0, k = 0; v < n; ++v) {
    if (v != reference) x[k++] = res.initial_scales[v];
  }
  x = x.cwiseMax(lb).cwiseMin(ub);

  // Rounds: freeze nearest neighbours and normalisation at the current scales (ICP style), solve
  // the now smooth eq. 2 with L-BFGS-B, repeat until the scales stop moving.
  std::vector<Association> assoc(prob.terms.size());
  std::string last_status;
  double max_step = 0.0;
  for (int round = 0; round < std::max(1, params.max_rounds); ++round) {
    Objective obj;
    obj.prob = &prob;
    obj.assoc = &assoc;
    obj.n_views = n;
    obj.reference = reference;
    const std::vector<double> s = obj.scales_of(x);
    auto t_assoc = std::chrono::steady_clock::now();
    tbb::parallel_for(std::size_t(0), prob.terms.size(), [&](std::size_t k) {
      const Term& t = *prob.terms[k];
      assoc[k] = associate(t, s[t.m], s[t.n]);
    });
    res.association_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t_assoc).count();
    double eq3 = 0.0;
    for (const auto& a : assoc) eq3 += a.value;
    if (round == 0) res.objective_initial = eq3;
    res.objective_final = eq3;
    ++res.rounds;
    if (round > 0 && max_step < params.round_tolerance) {
      res.converged = true;
      break;
    }
    const auto t_solve = std::chrono::steady_clock::now();
    LBFGSpp::LBFGSBSolver<double> solver(lp);
    Eigen::VectorXd xs = x;
    double fx = 0.0;
    try {
      // Trust region: frozen neighbours are only valid near the scales they were found at.
      const Eigen::VectorXd lb_r = lb.cwiseMax((x.array() - params.round_trust_region).matrix());
      const Eigen::VectorXd ub_r = ub.cwiseMin((x.array() + params.round_trust_region).matrix());
      res.iterations += solver.minimize(obj, xs, fx, lb_r, ub_r);
      last_status = "ok";
    } catch (const std::exception& e) {
      last_status = std::string("line search stopped (best point kept): ") + e.what();
    }
    res.evaluations += obj.evaluations;
    res.solve_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t_solve).count();
    const Eigen::VectorXd next = obj.best_x.size() == x.size() ? obj.best_x : x;
    max_step = (next - x).cwiseAbs().maxCoeff();
    res.round_steps.push_back(max_step);
    x = next;
  }
  res.status = (res.converged ? "converged after " : "round limit reached after ") +
               std::to_string(res.rounds) + " rounds; last inner solve: " + last_status;
  Objective fin;
  fin.n_views = n;
  fin.reference = reference;
  res.scales = fin.scales_of(x);
  int unlinked = 0;
  for (int v = 0; v < n; ++v) {
    if (!linked[v] && v != reference) {
      res.scales[v] = 1.0;
      ++unlinked;
    }
  }
  if (unlinked > 0) res.status += "; " + std::to_string(unlinked) + " view(s) without a neighbour kept at 1";
  return res;
}

}  // namespace floorcast
