#include "floorcast/sim/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace floorcast {
namespace {

/// Adds quad p0-p1-p2-p3 (a planar loop in either order) as two triangles whose normal points
/// along `outward`.
void add_quad(Mesh& mesh, Eigen::Vector3f p0, Eigen::Vector3f p1, Eigen::Vector3f p2, Eigen::Vector3f p3,
              const Eigen::Vector3f& outward, MeshLabel label, int part) {
  if ((p1 - p0).cross(p2 - p0).dot(outward) < 0.0f) std::swap(p1, p3);
  mesh.add_triangle(p0, p1, p2, label, part);
  mesh.add_triangle(p0, p2, p3, label, part);
}

/// Adds a convex polygon (any winding) as a fan whose normal points along `outward`.
void add_convex_polygon(Mesh& mesh, const std::vector<Eigen::Vector3f>& poly, const Eigen::Vector3f& outward,
                        MeshLabel label, int part) {
  if (poly.size() < 3) return;
  Eigen::Vector3f n = Eigen::Vector3f::Zero();
  for (std::size_t i = 1; i + 1 < poly.size(); ++i) n += (poly[i] - poly[0]).cross(poly[i + 1] - poly[0]);
  const bool flip = n.dot(outward) < 0.0f;
  for (std::size_t i = 1; i + 1 < poly.size(); ++i) {
    if (flip) {
      mesh.add_triangle(poly[0], poly[i + 1], poly[i], label, part);
    } else {
      mesh.add_triangle(poly[0], poly[i], poly[i + 1], label, part);
    }
  }
}

}  // namespace

Eigen::Vector3f Mesh::normal(std::size_t i) const {
  const Eigen::Vector3i& t = triangles[i];
  const Eigen::Vector3f& a = vertices_m[static_cast<std::size_t>(t[0])];
  const Eigen::Vector3f& b = vertices_m[static_cast<std::size_t>(t[1])];
  const Eigen::Vector3f& c = vertices_m[static_cast<std::size_t>(t[2])];
  return (b - a).cross(c - a).normalized();
}

std::size_t Mesh::add_triangle(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c,
                               MeshLabel label, int part_id) {
  const int base = static_cast<int>(vertices_m.size());
  vertices_m.push_back(a);
  vertices_m.push_back(b);
  vertices_m.push_back(c);
  triangles.emplace_back(base, base + 1, base + 2);
  labels.push_back(label);
  part_ids.push_back(part_id);
  return triangles.size() - 1;
}

std::size_t Mesh::count(MeshLabel label) const {
  return static_cast<std::size_t>(std::count(labels.begin(), labels.end(), label));
}

void mesh_bounds(const Mesh& mesh, Eigen::Vector3f& min_m, Eigen::Vector3f& max_m) {
  min_m = Eigen::Vector3f::Constant(std::numeric_limits<float>::infinity());
  max_m = -min_m;
  for (const Eigen::Vector3f& v : mesh.vertices_m) {
    min_m = min_m.cwiseMin(v);
    max_m = max_m.cwiseMax(v);
  }
}

Mesh extrude_plan(const FloorPlan& plan, const ExtrusionParams& params) {
  return mesh_from_faces(extrude_faces(plan, params));
}

Mesh mesh_from_faces(const std::vector<ExtrudedFace>& faces) {
  Mesh mesh;
  for (const ExtrudedFace& f : faces) {
    const auto& p = f.polygon_m;
    if (p.size() == 4) {
      add_quad(mesh, p[0], p[1], p[2], p[3], f.outward, f.label, f.part_id);
    } else {
      add_convex_polygon(mesh, p, f.outward, f.label, f.part_id);
    }
  }
  return mesh;
}

}  // namespace floorcast
