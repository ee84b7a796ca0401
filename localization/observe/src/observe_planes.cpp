// Plane fitting without PCL: PCA, weighted PCA, and the VoxelPlane-Reloc extractor.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <numeric>
#include <queue>
#include <unordered_map>

#include "floorcast/core/types.hpp"
#include "floorcast/observe/observe_planes.hpp"
#include "floorcast/core/math.hpp"

namespace floorcast {
namespace {

double deg2rad(double d) { return d * kPi / 180.0; }

/// Weighted first and second moments of a point set; planes are fitted from them.
struct Moments {
  double w = 0.0;
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  Eigen::Matrix3d ss = Eigen::Matrix3d::Zero();

  void add(const Eigen::Vector3d& p, double weight) {
    w += weight;
    s += weight * p;
    ss.noalias() += weight * p * p.transpose();
  }
  void add(const Moments& o) {
    w += o.w;
    s += o.s;
    ss += o.ss;
  }
};

struct PlaneFit {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Vector3d eigenvalues = Eigen::Vector3d::Zero();  ///< ascending
  double offset = 0.0;
};

/// Orients a normal deterministically: towards the origin (offset <= 0); for planes through the
/// origin, its largest component positive.
void orient(Eigen::Vector3d& n, const Eigen::Vector3d& c) {
  const double d = n.dot(c);
  if (d > 1e-12) {
    n = -n;
  } else if (std::abs(d) <= 1e-12) {
    int k = 0;
    n.cwiseAbs().maxCoeff(&k);
    if (n[k] < 0) n = -n;
  }
}

PlaneFit fit_from_moments(const Moments& m) {
  PlaneFit f;
  if (m.w <= 0.0) return f;
  f.centroid = m.s / m.w;
  Eigen::Matrix3d cov = m.ss / m.w - f.centroid * f.centroid.transpose();
  cov = 0.5 * (cov + cov.transpose());
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
  f.eigenvalues = es.eigenvalues().cwiseMax(0.0);
  f.normal = es.eigenvectors().col(0).normalized();
  orient(f.normal, f.centroid);
  f.offset = f.normal.dot(f.centroid);
  return f;
}

Plane3 to_plane(const PlaneFit& f, const PointCloud3f& points, std::vector<int> indices) {
  Plane3 p;
  p.normal = f.normal;
  p.offset_m = f.offset;
  p.centroid_m = f.centroid;
  std::sort(indices.begin(), indices.end());
  double sq = 0.0;
  for (int i : indices) {
    const double r = p.normal.dot(points[i].cast<double>()) - p.offset_m;
    sq += r * r;
  }
  p.rms_m = indices.empty() ? 0.0 : std::sqrt(sq / indices.size());
  p.point_indices = std::move(indices);
  return p;
}

std::vector<int> all_indices(const PointCloud3f& points) {
  std::vector<int> idx(points.size());
  std::iota(idx.begin(), idx.end(), 0);
  return idx;
}

// --- VoxelPlane ------------------------------------------------------------------------------

using CellKey = std::int64_t;
constexpr std::int64_t kKeyBias = std::int64_t(1) << 20;
constexpr std::int64_t kKeyMask = (std::int64_t(1) << 21) - 1;

CellKey pack(std::int64_t x, std::int64_t y, std::int64_t z) {
  return ((x + kKeyBias) & kKeyMask) << 42 | ((y + kKeyBias) & kKeyMask) << 21 |
         ((z + kKeyBias) & kKeyMask);
}

/// A leaf of the voxel octree holding a plane.
struct Leaf {
  std::array<std::int64_t, 3> cell{};  ///< min corner in finest-level cells
  std::int64_t size_cells = 1;         ///< edge length in finest-level cells
  std::vector<int> indices;
  Moments moments;  ///< weighted moments (weights W_i^2 of eq. 3)
  PlaneFit fit;
};

/// Fits one voxel's plane: PCA, planarity test, adaptive weights (eq. 2-3). Returns false when
/// the points are not planar.
bool fit_voxel(const PointCloud3f& points, const std::vector<int>& idx, const VoxelPlaneParams& params,
               Moments& moments, PlaneFit& fit) {
  Moments plain;
  for (int i : idx) plain.add(points[i].cast<double>(), 1.0);
  const PlaneFit pca = fit_from_moments(plain);
  const double l0 = pca.eigenvalues[0], l1 = pca.eigenvalues[1];
  if (std::sqrt(l0) > params.max_thickness_m) return false;
  if (l1 <= 0.0 || l0 > params.max_eigen_ratio * l1) return false;
  if (!params.adaptive_weights) {
    moments = plain;
    fit = pca;
    return true;
  }
  // Eq. 2: weights from the distance to the PCA centre, boundary sigma = half the largest one.
  double r_max = 0.0;
  for (int i : idx) r_max = std::max(r_max, (points[i].cast<double>() - pca.centroid).norm());
  const double sigma = 0.5 * r_max;
  Moments weighted;
  for (int i : idx) {
    const double r = (points[i].cast<double>() - pca.centroid).norm();
    const double w = voxel_plane_weight(sigma > 0.0 ? r / sigma : 0.0, params);
    weighted.add(points[i].cast<double>(), w * w);  // eq. 3 squares the weighted residual
  }
  if (weighted.w <= 0.0) return false;
  moments = weighted;
  fit = fit_from_moments(weighted);
  return true;
}

}  // namespace

std::string to_string(PlaneExtractorKind kind) {
  return kind == PlaneExtractorKind::kVoxelPlane ? "voxelplane" : "pcl";
}

PlaneExtractorKind parse_plane_extractor(const std::string& s) {
  if (s == "pcl") return PlaneExtractorKind::kPclRegionGrowing;
  if (s == "voxelplane") return PlaneExtractorKind::kVoxelPlane;
  throw InputError("plane extractor \"" + s + "\": expected pcl or voxelplane");
}

double plane_angle_error_deg(const Eigen::Vector3d& n_a, const Eigen::Vector3d& n_b) {
  const double c = std::abs(n_a.normalized().dot(n_b.normalized()));
  return std::acos(std::min(1.0, c)) * 180.0 / kPi;
}

double plane_offset_error_m(const Eigen::Vector3d& n_a, double d_a, const Eigen::Vector3d& n_b,
                            double d_b) {
  const double sign = n_a.dot(n_b) >= 0.0 ? 1.0 : -1.0;
  return std::abs(d_a - sign * d_b);
}

double voxel_plane_weight(double rho, const VoxelPlaneParams& params) {
  if (std::abs(rho) <= 1.0) return std::max(0.0, 1.0 - params.weight_alpha * rho * rho);
  return std::exp(-params.weight_beta * rho * rho);
}

Plane3 fit_plane_pca(const PointCloud3f& points, const std::vector<int>& indices) {
  std::vector<int> idx = indices.empty() ? all_indices(points) : indices;
  Moments m;
  for (int i : idx) m.add(points[i].cast<double>(), 1.0);
  return to_plane(fit_from_moments(m), points, std::move(idx));
}

Plane3 fit_plane_weighted(const PointCloud3f& points, const std::vector<int>& indices,
                          const std::vector<double>& weights) {
  std::vector<int> idx = indices.empty() ? all_indices(points) : indices;
  Moments m;
  for (std::size_t k = 0; k < idx.size(); ++k) {
    const double w = k < weights.size() ? weights[k] : 1.0;
    m.add(points[idx[k]].cast<double>(), w * w);
  }
  return to_plane(fit_from_moments(m), points, std::move(idx));
}

VoxelPlaneResult extract_planes_voxel(const PointCloud3f& points, const VoxelPlaneParams& params) {
  VoxelPlaneResult result;
  if (points.empty() || params.voxel_size_m <= 0.0) return result;
  const int levels = std::clamp(params.max_subdivisions, 0, 6);
  const std::int64_t top_cells = std::int64_t(1) << levels;
  const double cell_m = params.voxel_size_m / static_cast<double>(top_cells);

  // Finest-level cell of every point; its top-level voxel is the cell divided by 2^levels.
  auto floor_div = [](std::int64_t a, std::int64_t b) {
    return a >= 0 ? a / b : -((-a + b - 1) / b);
  };
  std::vector<std::array<std::int64_t, 3>> cell_of(points.size());
  std::vector<std::pair<CellKey, int>> keyed(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::array<std::int64_t, 3> c;
    for (int a = 0; a < 3; ++a) c[a] = static_cast<std::int64_t>(std::floor(points[i][a] / cell_m));
    cell_of[i] = c;
    keyed[i] = {pack(floor_div(c[0], top_cells), floor_div(c[1], top_cells), floor_div(c[2], top_cells)),
                static_cast<int>(i)};
  }
  std::sort(keyed.begin(), keyed.end());

  // Octree leaves: a voxel that is not planar is split into its 8 children, up to `levels`
  // times (VoxelMap style); with max_subdivisions = 0 this is the paper's uniform grid.
  std::vector<Leaf> leaves;
  std::function<void(const std::array<std::int64_t, 3>&, std::int64_t, std::vector<int>)> build =
      [&](const std::array<std::int64_t, 3>& corner, std::int64_t size, std::vector<int> idx) {
        if (static_cast<int>(idx.size()) < params.min_points_per_voxel) return;
        Leaf leaf;
        if (fit_voxel(points, idx, params, leaf.moments, leaf.fit)) {
          leaf.cell = corner;
          leaf.size_cells = size;
          leaf.indices = std::move(idx);
          leaves.push_back(std::move(leaf));
          return;
        }
        if (size <= 1) return;
        const std::int64_t half = size / 2;
        std::array<std::vector<int>, 8> children;
        for (int i : idx) {
          int child = 0;
          for (int a = 0; a < 3; ++a) {
            if (cell_of[i][a] - corner[a] >= half) child |= 1 << a;
          }
          children[child].push_back(i);
        }
        for (int child = 0; child < 8; ++child) {
          std::array<std::int64_t, 3> c = corner;
          for (int a = 0; a < 3; ++a) {
            if (child & (1 << a)) c[a] += half;
          }
          build(c, half, std::move(children[child]));
        }
      };
  for (std::size_t b = 0; b < keyed.size();) {
    std::size_t e = b;
    while (e < keyed.size() && keyed[e].first == keyed[b].first) ++e;
    if (static_cast<int>(e - b) >= params.min_points_per_voxel) {
      ++result.voxels;
      std::vector<int> idx;
      idx.reserve(e - b);
      for (std::size_t k = b; k < e; ++k) idx.push_back(keyed[k].second);
      const auto& c = cell_of[idx.front()];
      const std::array<std::int64_t, 3> corner = {floor_div(c[0], top_cells) * top_cells,
                                                   floor_div(c[1], top_cells) * top_cells,
                                                   floor_div(c[2], top_cells) * top_cells};
      build(corner, top_cells, std::move(idx));
    }
    b = e;
  }
  result.planar_voxels = static_cast<int>(leaves.size());

  // Finest cell -> leaf, for the 26-neighbourhood of any leaf.
  std::unordered_map<CellKey, int> cell_to_leaf;
  cell_to_leaf.reserve(leaves.size() * 2);
  for (std::size_t li = 0; li < leaves.size(); ++li) {
    const Leaf& l = leaves[li];
    for (std::int64_t dx = 0; dx < l.size_cells; ++dx)
      for (std::int64_t dy = 0; dy < l.size_cells; ++dy)
        for (std::int64_t dz = 0; dz < l.size_cells; ++dz)
          cell_to_leaf[pack(l.cell[0] + dx, l.cell[1] + dy, l.cell[2] + dz)] = static_cast<int>(li);
  }
  auto neighbours = [&](int li) {
    const Leaf& l = leaves[li];
    std::vector<int> out;
    for (std::int64_t dx = -1; dx <= l.size_cells; ++dx)
      for (std::int64_t dy = -1; dy <= l.size_cells; ++dy)
        for (std::int64_t dz = -1; dz <= l.size_cells; ++dz) {
          const bool inside = dx >= 0 && dy >= 0 && dz >= 0 && dx < l.size_cells &&
                              dy < l.size_cells && dz < l.size_cells;
          if (inside) continue;
          auto it = cell_to_leaf.find(pack(l.cell[0] + dx, l.cell[1] + dy, l.cell[2] + dz));
          if (it != cell_to_leaf.end()) out.push_back(it->second);
        }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  };

  // Voxel growth. Seeds: leaves with most points first (ties: grid order), so regions start
  // from well-supported planes.
  std::vector<int> seeds(leaves.size());
  std::iota(seeds.begin(), seeds.end(), 0);
  std::stable_sort(seeds.begin(), seeds.end(), [&](int a, int b) {
    return leaves[a].indices.size() > leaves[b].indices.size();
  });
  const double cos_growth = std::cos(deg2rad(params.growth_max_normal_deg));
  std::vector<int> region_of(leaves.size(), -1);
  struct Region {
    Moments moments;
    PlaneFit fit;
    std::vector<int> leaves;
  };
  std::vector<Region> regions;
  for (int seed : seeds) {
    if (region_of[seed] >= 0) continue;
    Region region;
    region.moments = leaves[seed].moments;
    region.fit = leaves[seed].fit;
    region.leaves.push_back(seed);
    const int rid = static_cast<int>(regions.size());
    region_of[seed] = rid;
    std::queue<int> frontier;
    frontier.push(seed);
    while (!frontier.empty()) {
      const int cur = frontier.front();
      frontier.pop();
      for (int nb : neighbours(cur)) {
        if (region_of[nb] >= 0) continue;
        const PlaneFit& f = leaves[nb].fit;
        if (std::abs(f.normal.dot(region.fit.normal)) < cos_growth) continue;
        if (std::abs(region.fit.normal.dot(f.centroid) - region.fit.offset) >
            params.growth_max_offset_m) {
          continue;
        }
        region_of[nb] = rid;
        region.leaves.push_back(nb);
        region.moments.add(leaves[nb].moments);
        region.fit = fit_from_moments(region.moments);
        frontier.push(nb);
      }
    }
    regions.push_back(std::move(region));
  }
  result.planes_after_growth = static_cast<int>(regions.size());

  // Region point sets and radii.
  auto region_indices = [&](const Region& r) {
    std::vector<int> idx;
    for (int li : r.leaves) idx.insert(idx.end(), leaves[li].indices.begin(), leaves[li].indices.end());
    return idx;
  };
  std::vector<std::size_t> region_size(regions.size());
  for (std::size_t r = 0; r < regions.size(); ++r) {
    std::size_t n = 0;
    for (int li : regions[r].leaves) n += leaves[li].indices.size();
    region_size[r] = n;
  }
  auto region_radius = [&](const Region& r) {
    double rad = 0.0;
    for (int li : r.leaves)
      for (int i : leaves[li].indices)
        rad = std::max(rad, (points[i].cast<double>() - r.fit.centroid).norm());
    return rad;
  };

  // Under-grown merging: smallest planes first, each into the largest plane that is parallel,
  // at the same depth and close enough.
  std::vector<bool> alive(regions.size(), true);
  if (params.merge_undergrown && regions.size() > 1) {
    std::vector<int> order(regions.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&](int a, int b) { return region_size[a] < region_size[b]; });
    std::vector<double> radius(regions.size());
    for (std::size_t r = 0; r < regions.size(); ++r) radius[r] = region_radius(regions[r]);
    const double cos_merge = std::cos(deg2rad(params.merge_max_normal_deg));
    const double sin_depth = std::sin(deg2rad(params.merge_depth_tol_deg));
    for (std::size_t oi = 0; oi < order.size(); ++oi) {
      const int small = order[oi];
      int best = -1;
      for (std::size_t oj = order.size(); oj-- > oi + 1;) {  // largest candidate first
        const int big = order[oj];
        if (!alive[big]) continue;
        const PlaneFit& fs = regions[small].fit;
        const PlaneFit& fb = regions[big].fit;
        if (std::abs(fs.normal.dot(fb.normal)) < cos_merge) continue;
        const Eigen::Vector3d delta = fs.centroid - fb.centroid;
        const double dist = delta.norm();
        if (dist > params.merge_radius_factor * radius[big]) continue;
        if (dist > 1e-9 && std::abs(fb.normal.dot(delta)) / dist > sin_depth) continue;
        best = big;
        break;
      }
      if (best < 0) continue;
      Region& into = regions[best];
      into.moments.add(regions[small].moments);
      into.leaves.insert(into.leaves.end(), regions[small].leaves.begin(), regions[small].leaves.end());
      into.fit = fit_from_moments(into.moments);
      region_size[best] += region_size[small];
      radius[best] = region_radius(into);
      alive[small] = false;
    }
  }

  for (std::size_t r = 0; r < regions.size(); ++r) {
    if (!alive[r]) continue;
    if (static_cast<int>(region_size[r]) < params.min_plane_points) continue;
    Plane3 plane = to_plane(regions[r].fit, points, region_indices(regions[r]));
    plane.voxels = static_cast<int>(regions[r].leaves.size());
    result.planes.push_back(std::move(plane));
  }
  result.planes_after_merge = static_cast<int>(std::count(alive.begin(), alive.end(), true));
  std::stable_sort(result.planes.begin(), result.planes.end(), [](const Plane3& a, const Plane3& b) {
    return a.point_indices.size() > b.point_indices.size();
  });
  return result;
}

}  // namespace floorcast
