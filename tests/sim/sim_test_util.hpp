// Small plans and helpers shared by the simulator tests.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <vector>

#include "floorcast/floorplans/floor_plan.hpp"
#include "floorcast/sim/mesh.hpp"

namespace floorcast::test {

/// A closed rectangular room with wall centrelines on [0, w] x [0, h], thickness t: the free
/// interior is [t/2, w - t/2] x [t/2, h - t/2].
inline FloorPlan box_room(double w = 6.0, double h = 4.0, double t = 0.2) {
  FloorPlan p;
  p.name = "box";
  p.walls = {{"s", {0, 0}, {w, 0}, t, WallMaterial::kSolid, 0.0, {}},
             {"e", {w, 0}, {w, h}, t, WallMaterial::kSolid, 0.0, {}},
             {"n", {w, h}, {0, h}, t, WallMaterial::kSolid, 0.0, {}},
             {"w", {0, h}, {0, 0}, t, WallMaterial::kSolid, 0.0, {}}};
  return p;
}

/// Box room 10 x 4 split at x = 5 by a full-height glass wall (thickness 0.02).
inline FloorPlan glass_split_room() {
  FloorPlan p = box_room(10.0, 4.0, 0.2);
  p.name = "glass split";
  Wall g{"glass", {5.0, 0.0}, {5.0, 4.0}, 0.02, WallMaterial::kGlass, 0.0, {}};
  p.walls.push_back(g);
  return p;
}

/// One of everything: glass wall with sill and head, window, closed and open doors, a desk, a
/// pillar, an interior wall with a T-junction.
inline FloorPlan feature_plan() {
  FloorPlan p = box_room(8.0, 5.0, 0.2);
  p.name = "features";
  p.walls.push_back({"mid", {5.0, 0.0}, {5.0, 5.0}, 0.1, WallMaterial::kSolid, 0.0, {}});
  Wall g{"glass", {5.0, 3.5}, {8.0, 3.5}, 0.04, WallMaterial::kGlass, 0.3, 2.5};
  p.walls.push_back(g);
  p.doors.push_back({"front", "s", {2.0, 0.0}, 1.0, true});
  p.doors.push_back({"inner", "mid", {5.0, 1.5}, 0.9, false});
  p.windows.push_back({"win", "n", {2.5, 5.0}, 1.5, 0.9, 2.1});
  p.obstacles.push_back({"desk", ObstacleKind::kBox, {2.0, 3.8}, {1.4, 0.7}, 0.2, 0.75});
  p.obstacles.push_back({"column", ObstacleKind::kPillar, {6.5, 1.5}, {0.4, 0.4}, 0.0, 3.0});
  return p;
}

/// Exact ray/triangle intersection in double precision (Moller-Trumbore); returns t >= 0 or -1.
inline double ray_triangle(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& a,
                           const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d e1 = b - a, e2 = c - a;
  const Eigen::Vector3d p = d.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-15) return -1.0;
  const Eigen::Vector3d s = o - a;
  const double u = s.dot(p) / det;
  if (u < 0.0 || u > 1.0) return -1.0;
  const Eigen::Vector3d q = s.cross(e1);
  const double v = d.dot(q) / det;
  if (v < 0.0 || u + v > 1.0) return -1.0;
  const double t = e2.dot(q) / det;
  return t >= 0.0 ? t : -1.0;
}

/// Brute-force closest hit over all triangles: t (inf if none) and the triangle index.
inline double brute_force_hit(const Mesh& mesh, const Eigen::Vector3d& o, const Eigen::Vector3d& d, int& tri,
                              double* second_best = nullptr) {
  double best = std::numeric_limits<double>::infinity(), second = best;
  tri = -1;
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const Eigen::Vector3i& t = mesh.triangles[i];
    const double h = ray_triangle(o, d, mesh.vertices_m[static_cast<std::size_t>(t[0])].cast<double>(),
                                  mesh.vertices_m[static_cast<std::size_t>(t[1])].cast<double>(),
                                  mesh.vertices_m[static_cast<std::size_t>(t[2])].cast<double>());
    if (h < 0.0) continue;
    if (h < best) {
      second = best;
      best = h;
      tri = static_cast<int>(i);
    } else if (h < second) {
      second = h;
    }
  }
  if (second_best) *second_best = second;
  return best;
}

}  // namespace floorcast::test
