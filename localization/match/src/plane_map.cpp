// VoxelPlane-Reloc map planes from the plan's extrusion, the transform solvers, and the plane
// matcher's parameters.
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>

#include "floorcast/core/fields.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/floorplans/geometry.hpp"
#include "floorcast/match/plane_matcher.hpp"

namespace floorcast {
namespace {

const std::vector<std::pair<const char*, PlanePairWeights>> kPairWeightNames = {
    {"inverse_frequency", PlanePairWeights::kInverseFrequency},
    {"as_printed", PlanePairWeights::kAsPrinted},
    {"overlap", PlanePairWeights::kOverlap},
};

PlaneKind kind_of(const Eigen::Vector3d& n, double tau_g_deg) {
  const double c = std::cos(deg_to_rad(tau_g_deg));
  if (n.z() >= c) return PlaneKind::kGround;
  if (n.z() <= -c) return PlaneKind::kCeiling;
  if (std::abs(n.z()) <= std::sin(deg_to_rad(tau_g_deg))) return PlaneKind::kWall;
  return PlaneKind::kOther;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Parameters.

void PlaneMatcherParams::apply_shared(const SharedParams& shared) {
  max_range_m = shared.range_m;
  blocking = shared.blocking;
}

const FieldList<PlaneMatcherParams>& PlaneMatcherParams::fields() {
  using P = PlaneMatcherParams;
  static const FieldList<P> f =
      FieldList<P>("matcher planes")
          .number("max_range_m", &P::max_range_m, 0.1, 100.0,
                  "map and submap planes farther (horizontally) are not used; map planes farther apart than twice this are "
                  "never matched together, m (default: the shared range)")
          .flatten(&P::blocking, blocking_fields())
          .number("wall_height_m", [](auto& p) -> auto& { return p.extrusion.wall_height_m; }, 0.5, 100.0,
                  "the 3D building the map planes come from: wall (= ceiling) height, m (as the simulator extrudes it)")
          .number("door_height_m", [](auto& p) -> auto& { return p.extrusion.door_height_m; }, 0.1, 100.0,
                  "the 3D building's door height, m")
          .number("cell_m", &P::cell_m, 0.02, 2.0, "l: grid cell edge for areas, projections and overlaps, m (VoxelPlane-Reloc's l x l patches)")
          .number("min_map_plane_area_m2", &P::min_map_plane_area_m2, 0.0, 1e4, "map planes smaller than this are left out (jamb and soffit slivers), m^2")
          .number("min_plane_area_m2", &P::min_plane_area_m2, 0.0, 1e4, "submap planes smaller than this are not used, m^2")
          .integer("max_planes", &P::max_planes, 3, 64, "at most this many submap planes (largest first) take part")
          .flag("incremental", &P::incremental, "incremental plane input (the paper's; false = VR-NI: every plane at once)")
          .integer("initial_planes", &P::initial_planes, 3, 64, "planes of the first incremental round")
          .flag("ground_constraint", &P::ground_constraint, "ground plane constraint: the submap ground matched to the map floor first (false = VR-NG)")
          .number("tau_g_deg", &P::tau_g_deg, 0.1, 45.0, "tau_g: a normal within this of vertical is ground/ceiling, deg")
          .flag("orthogonal_constraint", &P::orthogonal_constraint, "the planes of a triplet pairwise within [min_angle_deg, max_angle_deg]")
          .number("min_angle_deg", &P::min_angle_deg, 0.0, 90.0, "orthogonal constraint: smallest pairwise angle, deg (paper: 40)")
          .number("max_angle_deg", &P::max_angle_deg, 90.0, 180.0, "orthogonal constraint: largest pairwise angle, deg (paper: 140)")
          .number("angle_tolerance_deg", &P::angle_tolerance_deg, 0.01, 45.0,
                  "map and submap pairs agree in their signed angle within this (ours: a pair whose angles disagree fits no rotation), deg")
          .flag("sphere_constraint", &P::sphere_constraint, "sphere distance limit between the map planes of a triplet")
          .number("sphere_tolerance_m", &P::sphere_tolerance_m, 0.0, 100.0,
                  "map planes of a triplet at most (submap centre distance + this) apart, m")
          .flag("area_constraint", &P::area_constraint, "area relation: map plane cells >= area_ratio x submap plane cells")
          .number("area_ratio", &P::area_ratio, 0.0, 10.0, "area relation factor")
          .flag("projection", &P::projection, "map plane projection strategy (eq. 10; false = VR-NP)")
          .number("projection_tolerance_m", &P::projection_tolerance_m, 0.0, 5.0,
                  "a submap cell projects onto a map plane within this of it, on its extent grown by the same, m")
          .number("min_projection", &P::min_projection, 0.0, 1.0, "share of a submap plane's cells on its map plane, per triplet pair at least")
          .flag("overlap", &P::overlap, "submap plane overlap strategy (eq. 11; false = VR-NO)")
          .number("min_overlap", &P::min_overlap, 0.0, 1.0, "o(i, j) of each triplet pair at least this")
          .flag("uniqueness", &P::uniqueness, "scene uniqueness (false = VR-NS): at least tau_m submap planes agree under the transform")
          .integer("tau_m", &P::tau_m, 1, 64, "tau_m: agreeing planes needed (paper: 5); always a majority too")
          .number("match_normal_deg", &P::match_normal_deg, 0.01, 45.0, "a plane agrees: normal within this, deg")
          .number("match_offset_m", &P::match_offset_m, 0.0, 5.0, "a plane agrees: offset within this, m")
          .choice("pair_weights", &P::pair_weights, kPairWeightNames,
                  "triplet weights of eq. 13 from eq. 12's pair weights: inverse_frequency (the text), as_printed (eq. 13 as "
                  "printed), overlap (none)")
          .number("sigma_xy_m", &P::sigma_xy_m, 1e-3, 100.0, "eq. 14 kernel: sigma over x, y, z, m")
          .number("sigma_yaw_deg", &P::sigma_yaw_deg, 1e-3, 180.0, "eq. 14 kernel: sigma over the rotation, deg")
          .number("kernel_cutoff", &P::kernel_cutoff, 0.5, 20.0, "the kernel is 0 beyond this many sigmas (Mahalanobis)")
          .flag("refine", &P::refine, "refine each mode by least squares over every agreeing plane pair (ours; false = the triplet's transform)")
          .number("resolution_m", &P::resolution_m, 0.01, 2.0, "posterior grid resolution, m")
          .number("grid_margin_m", &P::grid_margin_m, 0.0, 100.0, "free margin of the posterior grid around the plan, m")
          .integer("yaw_bins", &P::yaw_bins, 4, 3600, "posterior yaw bins")
          .integer("max_hypotheses", &P::max_hypotheses, 1, 1000000000,
                   "triplet hypotheses evaluated per match at most (a guard for the unconstrained ablations; counted when reached)")
          .check([](const P& p, const ParamReader& r) {
            if (!(p.extrusion.door_height_m < p.extrusion.wall_height_m)) {
              r.fail("door_height_m", "must be below wall_height_m (" + nlohmann::json(p.extrusion.wall_height_m).dump() + ")");
            }
            if (!(p.min_angle_deg < p.max_angle_deg)) r.fail("min_angle_deg", "must be below max_angle_deg");
          });
  return f;
}

nlohmann::ordered_json PlaneMatcherParams::to_json() const { return fields().write(*this); }

void PlaneMatcherParams::apply_overrides(const nlohmann::json& overrides) { fields().read(*this, overrides); }

// ---------------------------------------------------------------------------------------------
// Map planes.

bool MapPlane::covers(const Eigen::Vector3d& p, bool use_grown) const {
  const int i = static_cast<int>(std::floor(basis.col(0).dot(p) / cell_m)) - i0;
  const int j = static_cast<int>(std::floor(basis.col(1).dot(p) / cell_m)) - j0;
  if (i < 0 || j < 0 || i >= width || j >= height) return false;
  const std::size_t k = static_cast<std::size_t>(j) * static_cast<std::size_t>(width) + static_cast<std::size_t>(i);
  return (use_grown ? grown[k] : mask[k]) != 0;
}

PlaneMap build_plane_map(const FloorPlan& plan, const PlaneMatcherParams& params) {
  const double l = params.cell_m;
  FloorPlan drawn = plan;
  if (params.blocking.open_doors_block) {
    for (Door& d : drawn.doors) d.closed = true;
  }
  std::vector<ExtrudedFace> faces;
  for (ExtrudedFace& f : extrude_faces(drawn, params.extrusion)) {
    if (f.label == MeshLabel::kGlass && !params.blocking.glass_blocks) continue;
    if (f.label == MeshLabel::kClutter && !params.blocking.obstacles_block) continue;
    faces.push_back(std::move(f));
  }
  PlaneMap map;
  map.cell_m = l;
  const int grow = static_cast<int>(std::ceil(params.projection_tolerance_m / l - 1e-9));
  for (const ExtrudedPlane& group : group_coplanar_faces(faces)) {
    MapPlane mp;
    mp.normal = group.normal;
    mp.offset_m = group.offset_m;
    mp.label = group.label;
    mp.cell_m = l;
    mp.basis = plane_cell_basis(group.normal);
    mp.kind = group.label == MeshLabel::kFloor     ? PlaneKind::kGround
              : group.label == MeshLabel::kCeiling ? PlaneKind::kCeiling
                                                   : kind_of(group.normal, params.tau_g_deg);
    if (mp.kind == PlaneKind::kGround && group.label != MeshLabel::kFloor) mp.kind = PlaneKind::kOther;
    if (mp.kind == PlaneKind::kCeiling && group.label != MeshLabel::kCeiling) mp.kind = PlaneKind::kOther;
    // The faces in the plane's (u, v) axes (counter-clockwise) and their cell range.
    std::vector<std::vector<Vec2>> polys;
    int i_lo = std::numeric_limits<int>::max(), i_hi = std::numeric_limits<int>::min();
    int j_lo = i_lo, j_hi = i_hi;
    for (int fi : group.faces) {
      std::vector<Vec2> poly = face_in_plane_axes(faces[static_cast<std::size_t>(fi)], mp.basis);
      for (const Vec2& q : poly) {
        i_lo = std::min(i_lo, static_cast<int>(std::floor(q.x() / l)));
        i_hi = std::max(i_hi, static_cast<int>(std::floor(q.x() / l)));
        j_lo = std::min(j_lo, static_cast<int>(std::floor(q.y() / l)));
        j_hi = std::max(j_hi, static_cast<int>(std::floor(q.y() / l)));
      }
      polys.push_back(std::move(poly));
    }
    if (polys.empty()) continue;
    mp.i0 = i_lo - grow;
    mp.j0 = j_lo - grow;
    mp.width = i_hi - i_lo + 1 + 2 * grow;
    mp.height = j_hi - j_lo + 1 + 2 * grow;
    mp.mask.assign(static_cast<std::size_t>(mp.width) * static_cast<std::size_t>(mp.height), 0);
    for (const std::vector<Vec2>& poly : polys) {
      double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300;
      for (const Vec2& q : poly) {
        u0 = std::min(u0, q.x());
        u1 = std::max(u1, q.x());
        v0 = std::min(v0, q.y());
        v1 = std::max(v1, q.y());
      }
      for (int j = static_cast<int>(std::floor(v0 / l)); j <= static_cast<int>(std::floor(v1 / l)); ++j) {
        for (int i = static_cast<int>(std::floor(u0 / l)); i <= static_cast<int>(std::floor(u1 / l)); ++i) {
          if (!point_in_convex_polygon(poly, Vec2((i + 0.5) * l, (j + 0.5) * l))) continue;
          mp.mask[static_cast<std::size_t>(j - mp.j0) * static_cast<std::size_t>(mp.width) + static_cast<std::size_t>(i - mp.i0)] = 1;
        }
      }
    }
    const Eigen::Vector3d foot = mp.offset_m * mp.normal;
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int j = 0; j < mp.height; ++j) {
      for (int i = 0; i < mp.width; ++i) {
        if (!mp.mask[static_cast<std::size_t>(j) * mp.width + i]) continue;
        const Eigen::Vector3d q = foot + (i + mp.i0 + 0.5) * l * mp.basis.col(0) + (j + mp.j0 + 0.5) * l * mp.basis.col(1);
        mp.cell_centres_m.push_back(q.cast<float>());
        c += q;
      }
    }
    mp.cells = static_cast<int>(mp.cell_centres_m.size());
    if (mp.cells == 0 || mp.cells * l * l < params.min_map_plane_area_m2) continue;
    mp.centroid_m = c / mp.cells;
    double r = 0.0;
    for (const std::vector<Vec2>& poly : polys) {
      for (const Vec2& q : poly) r = std::max(r, (foot + q.x() * mp.basis.col(0) + q.y() * mp.basis.col(1) - mp.centroid_m).norm());
    }
    mp.radius_m = r;
    // The extent grown by the projection tolerance (a square of `grow` cells).
    mp.grown = mp.mask;
    if (grow > 0) {
      std::vector<std::uint8_t> rows(mp.mask.size(), 0);
      for (int j = 0; j < mp.height; ++j) {
        for (int i = 0; i < mp.width; ++i) {
          std::uint8_t any = 0;
          for (int di = -grow; di <= grow && !any; ++di) {
            const int ii = i + di;
            if (ii >= 0 && ii < mp.width) any = mp.mask[static_cast<std::size_t>(j) * mp.width + ii];
          }
          rows[static_cast<std::size_t>(j) * mp.width + i] = any;
        }
      }
      for (int j = 0; j < mp.height; ++j) {
        for (int i = 0; i < mp.width; ++i) {
          std::uint8_t any = 0;
          for (int dj = -grow; dj <= grow && !any; ++dj) {
            const int jj = j + dj;
            if (jj >= 0 && jj < mp.height) any = rows[static_cast<std::size_t>(jj) * mp.width + i];
          }
          mp.grown[static_cast<std::size_t>(j) * mp.width + i] = any;
        }
      }
    }
    map.planes.push_back(std::move(mp));
  }
  for (std::size_t k = 0; k < map.planes.size(); ++k) {
    if (map.planes[k].kind == PlaneKind::kGround) map.floors.push_back(static_cast<int>(k));
    if (map.planes[k].kind == PlaneKind::kWall) map.walls.push_back(static_cast<int>(k));
  }
  // Pairs that one observer can see together: sphere distance within twice the range.
  map.neighbours.resize(map.planes.size());
  const double limit = 2.0 * params.max_range_m;
  for (std::size_t a = 0; a < map.planes.size(); ++a) {
    for (std::size_t b = a + 1; b < map.planes.size(); ++b) {
      const double d = (map.planes[a].centroid_m - map.planes[b].centroid_m).norm() - map.planes[a].radius_m -
                       map.planes[b].radius_m;
      if (d <= limit) {
        map.neighbours[a].push_back(static_cast<int>(b));
        map.neighbours[b].push_back(static_cast<int>(a));
      }
    }
  }
  for (auto& n : map.neighbours) std::sort(n.begin(), n.end());
  map.neighbours_by_azimuth.resize(map.planes.size());
  for (std::size_t a = 0; a < map.planes.size(); ++a) {
    for (int b : map.neighbours[a]) {
      const Eigen::Vector3d& n = map.planes[static_cast<std::size_t>(b)].normal;
      if (n.head<2>().norm() < 0.2) continue;
      map.neighbours_by_azimuth[a].emplace_back(std::atan2(n.y(), n.x()), b);
    }
    std::sort(map.neighbours_by_azimuth[a].begin(), map.neighbours_by_azimuth[a].end());
  }
  return map;
}

std::size_t PlaneMap::bytes() const {
  std::size_t b = sizeof(PlaneMap);
  for (const MapPlane& p : planes) {
    b += sizeof(MapPlane) + p.mask.size() + p.grown.size() + p.cell_centres_m.size() * sizeof(Eigen::Vector3f);
  }
  for (const auto& n : neighbours) b += n.size() * sizeof(int);
  for (const auto& n : neighbours_by_azimuth) b += n.size() * sizeof(std::pair<double, int>);
  return b;
}

// ---------------------------------------------------------------------------------------------
// Transform solvers.

Eigen::Matrix3d rotation_from_normals(const std::vector<Eigen::Vector3d>& n_submap, const std::vector<Eigen::Vector3d>& n_map) {
  // Horn (1987): maximise sum n_M . R n_S over unit quaternions; the optimum is the eigenvector of
  // the largest eigenvalue of the symmetric 4x4 matrix N built from M = sum n_S n_M^T. (The
  // paper's eq. 6 with Q(r), W(r) of eq. 8-9 leads to the same eigenproblem.)
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
  for (std::size_t k = 0; k < n_submap.size(); ++k) M += n_submap[k] * n_map[k].transpose();
  const double Sxx = M(0, 0), Sxy = M(0, 1), Sxz = M(0, 2), Syx = M(1, 0), Syy = M(1, 1), Syz = M(1, 2), Szx = M(2, 0),
               Szy = M(2, 1), Szz = M(2, 2);
  Eigen::Matrix4d N;
  N << Sxx + Syy + Szz, Syz - Szy, Szx - Sxz, Sxy - Syx,  //
      Syz - Szy, Sxx - Syy - Szz, Sxy + Syx, Szx + Sxz,   //
      Szx - Sxz, Sxy + Syx, -Sxx + Syy - Szz, Syz + Szy,  //
      Sxy - Syx, Szx + Sxz, Syz + Szy, -Sxx - Syy + Szz;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> es(N);
  const Eigen::Vector4d q = es.eigenvectors().col(3);  // largest eigenvalue last
  return Eigen::Quaterniond(q(0), q(1), q(2), q(3)).normalized().toRotationMatrix();
}

namespace {
/// Least squares of translation_from_offsets on a matrix type A (rows = pairs).
template <typename Matrix>
Eigen::Vector3d solve_offsets(const std::vector<Eigen::Vector3d>& n_map, const std::vector<double>& d_map,
                              const std::vector<double>& d_submap) {
  using Vector = Eigen::Matrix<double, Matrix::RowsAtCompileTime, 1, 0, Matrix::MaxRowsAtCompileTime, 1>;
  Matrix A(static_cast<Eigen::Index>(n_map.size()), 3);
  Vector b(static_cast<Eigen::Index>(n_map.size()));
  for (std::size_t k = 0; k < n_map.size(); ++k) {
    A.row(static_cast<Eigen::Index>(k)) = n_map[k].transpose();
    b(static_cast<Eigen::Index>(k)) = d_map[k] - d_submap[k];
  }
  // Thin U and V only for a dynamic number of columns (Eigen's rule); the full ones give the same
  // minimum-norm solution.
  constexpr int options = Matrix::ColsAtCompileTime == Eigen::Dynamic ? (Eigen::ComputeThinU | Eigen::ComputeThinV)
                                                                       : (Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::JacobiSVD<Matrix> svd(A, options);
  svd.setThreshold(1e-6);
  return svd.solve(b);
}
}  // namespace

Eigen::Vector3d translation_from_offsets(const std::vector<Eigen::Vector3d>& n_map, const std::vector<double>& d_map,
                                         const std::vector<double>& d_submap) {
  // Up to 16 pairs (triplets, refinements) without heap allocation.
  if (n_map.size() <= 16) return solve_offsets<Eigen::Matrix<double, Eigen::Dynamic, 3, 0, 16, 3>>(n_map, d_map, d_submap);
  return solve_offsets<Eigen::MatrixXd>(n_map, d_map, d_submap);
}

Eigen::Isometry3d gravity_aligned_transform(const std::vector<Eigen::Vector3d>& n_submap, const std::vector<double>& d_submap,
                                            const std::vector<Eigen::Vector3d>& n_map, const std::vector<double>& d_map) {
  // Yaw: least squares on the horizontal normal parts (weighted by their horizontal length).
  double sc = 0.0, ss = 0.0;
  for (std::size_t k = 0; k < n_submap.size(); ++k) {
    const Eigen::Vector2d a = n_submap[k].head<2>(), b = n_map[k].head<2>();
    sc += a.dot(b);
    ss += a.x() * b.y() - a.y() * b.x();
  }
  const double yaw = std::atan2(ss, sc);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = translation_from_offsets(n_map, d_map, d_submap);
  return T;
}

Eigen::Isometry3d gravity_aligned_transform(const std::vector<PlanePatch>& submap, const std::vector<const MapPlane*>& map) {
  std::vector<Eigen::Vector3d> ns, nm;
  std::vector<double> ds, dm;
  for (std::size_t k = 0; k < submap.size(); ++k) {
    ns.push_back(submap[k].normal);
    ds.push_back(submap[k].offset_m);
    nm.push_back(map[k]->normal);
    dm.push_back(map[k]->offset_m);
  }
  return gravity_aligned_transform(ns, ds, nm, dm);
}

Pose2 planar_pose(const Eigen::Isometry3d& T) {
  const Eigen::Vector3d x = T.linear().col(0);
  return {T.translation().x(), T.translation().y(), std::atan2(x.y(), x.x())};
}

}  // namespace floorcast
