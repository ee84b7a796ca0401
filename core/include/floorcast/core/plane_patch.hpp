// Plane patches: a planar surface seen by a 3D sensor (or built from a floor plan's extrusion),
// as the plane, its extent on an l x l grid of the plane, and the bounding sphere VoxelPlane-Reloc
// compares planes with (Suo et al. 2024: centre and radius; area counted on l x l patches).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace floorcast {

/// A planar patch in some frame (the observer's scan frame in observations: origin at the
/// sensor, gravity aligned, z up).
struct PlanePatch {
  /// Unit normal pointing to the observer's side of the plane (into free space): the frame's
  /// origin satisfies normal . 0 - offset_m >= 0.
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  /// normal . p = offset_m for the points p of the plane (<= 0 by the orientation above).
  double offset_m = 0.0;
  /// Centre of the supporting points and the largest distance of one from it (the paper's
  /// enclosing sphere).
  Eigen::Vector3d centroid_m = Eigen::Vector3d::Zero();
  double radius_m = 0.0;
  /// Centres of the occupied cells of the plane's l x l grid (plane_cell_basis, cells aligned to
  /// the plane's foot point), in ascending (u, v) order; their count x l^2 is the patch's area.
  std::vector<Eigen::Vector3d> cells_m;
  /// Measured points supporting the patch (0 for patches built from geometry).
  int support_points = 0;
};

/// The in-plane axes (u, v) of the cell grid of a plane with unit normal n, and n: a right-handed
/// orthonormal basis [u v n]. For a vertical plane u is horizontal and v = +-z.
Eigen::Matrix3d plane_cell_basis(const Eigen::Vector3d& normal);

/// A patch from a plane (normal, offset; any sign) and points on or near it: the normal turned
/// to the origin's side, the points projected on the plane and counted on its cell_m x cell_m grid;
/// cells with at least min_points_per_cell points are occupied. Centroid and radius from the
/// points. No points gives a patch without cells.
PlanePatch make_plane_patch(const Eigen::Vector3d& normal, double offset_m,
                            const std::vector<Eigen::Vector3d>& points_m, double cell_m,
                            int min_points_per_cell = 1);

/// The patch in another frame: T_target_source applied to the plane, centroid and cells (the
/// normal is not re-oriented: it keeps pointing to the same physical side).
PlanePatch transform_patch(const PlanePatch& patch, const Eigen::Isometry3d& T_target_source);

/// Area of a patch on a grid of cell_m: cells x cell_m^2.
inline double patch_area_m2(const PlanePatch& patch, double cell_m) {
  return static_cast<double>(patch.cells_m.size()) * cell_m * cell_m;
}

}  // namespace floorcast
