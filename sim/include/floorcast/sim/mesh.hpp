// The extruded floor plan as a labelled 3D triangle mesh (world frame: floor-plan metres, z up
// from the floor): the faces of floorplans/extrusion.hpp (what is built is described there),
// triangulated, every triangle wound counter-clockwise seen from free space (outward normals).
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "floorcast/floorplans/extrusion.hpp"
#include "floorcast/floorplans/floor_plan.hpp"

namespace floorcast {

struct Mesh {
  std::vector<Eigen::Vector3f> vertices_m;
  std::vector<Eigen::Vector3i> triangles;  ///< vertex indices, CCW seen from outside
  std::vector<MeshLabel> labels;           ///< one per triangle
  /// One per triangle: for glass, the id of the glass element it belongs to (window k -> k,
  /// glass wall w -> windows.size() + w) so sensor models can treat a pane coherently; -1 else.
  std::vector<int> part_ids;

  std::size_t num_triangles() const { return triangles.size(); }
  /// Unit normal of triangle i from its winding.
  Eigen::Vector3f normal(std::size_t i) const;
  /// Adds a triangle; returns its index.
  std::size_t add_triangle(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c,
                           MeshLabel label, int part_id = -1);
  /// Number of triangles with this label.
  std::size_t count(MeshLabel label) const;
};

/// Triangulates faces (quads and convex polygons), keeping their labels and part ids.
Mesh mesh_from_faces(const std::vector<ExtrudedFace>& faces);

/// Builds the mesh of a plan (its obstacles included): mesh_from_faces(extrude_faces(...)). Throws InputError for parameters that
/// make no sense (door height not inside (0, wall height), non-positive sizes).
Mesh extrude_plan(const FloorPlan& plan, const ExtrusionParams& params = {});

/// Axis-aligned box [min, max] of a mesh.
void mesh_bounds(const Mesh& mesh, Eigen::Vector3f& min_m, Eigen::Vector3f& max_m);

}  // namespace floorcast
