#include "floorcast/core/plane_patch.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace floorcast {

Eigen::Matrix3d plane_cell_basis(const Eigen::Vector3d& normal) {
  const Eigen::Vector3d n = normal.normalized();
  // u horizontal for every plane that is not horizontal; for (near) horizontal planes u follows
  // the frame's x axis.
  Eigen::Vector3d u = Eigen::Vector3d::UnitZ().cross(n);
  if (u.norm() < 1e-6) u = Eigen::Vector3d::UnitY().cross(n);
  u.normalize();
  const Eigen::Vector3d v = n.cross(u);
  Eigen::Matrix3d B;
  B.col(0) = u;
  B.col(1) = v;
  B.col(2) = n;
  return B;
}

PlanePatch make_plane_patch(const Eigen::Vector3d& normal, double offset_m, const std::vector<Eigen::Vector3d>& points_m,
                            double cell_m, int min_points_per_cell) {
  PlanePatch p;
  const double len = normal.norm();
  p.normal = normal / len;
  p.offset_m = offset_m / len;
  if (p.offset_m > 0.0) {  // the origin must be on the positive side
    p.normal = -p.normal;
    p.offset_m = -p.offset_m;
  }
  p.support_points = static_cast<int>(points_m.size());
  if (points_m.empty()) return p;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& x : points_m) c += x;
  c /= static_cast<double>(points_m.size());
  p.centroid_m = c;
  double r2 = 0.0;
  for (const Eigen::Vector3d& x : points_m) r2 = std::max(r2, (x - c).squaredNorm());
  p.radius_m = std::sqrt(r2);

  const Eigen::Matrix3d B = plane_cell_basis(p.normal);
  const Eigen::Vector3d foot = p.offset_m * p.normal;
  std::map<std::pair<long long, long long>, int> counts;
  for (const Eigen::Vector3d& x : points_m) {
    const Eigen::Vector3d q = x - foot;
    const long long i = static_cast<long long>(std::floor(q.dot(B.col(0)) / cell_m));
    const long long j = static_cast<long long>(std::floor(q.dot(B.col(1)) / cell_m));
    ++counts[{i, j}];
  }
  for (const auto& [ij, n] : counts) {
    if (n < min_points_per_cell) continue;
    p.cells_m.push_back(foot + (static_cast<double>(ij.first) + 0.5) * cell_m * B.col(0) +
                        (static_cast<double>(ij.second) + 0.5) * cell_m * B.col(1));
  }
  return p;
}

PlanePatch transform_patch(const PlanePatch& patch, const Eigen::Isometry3d& T) {
  PlanePatch out = patch;
  out.normal = T.linear() * patch.normal;
  out.offset_m = patch.offset_m + out.normal.dot(T.translation());
  out.centroid_m = T * patch.centroid_m;
  for (Eigen::Vector3d& c : out.cells_m) c = T * c;
  return out;
}

}  // namespace floorcast
