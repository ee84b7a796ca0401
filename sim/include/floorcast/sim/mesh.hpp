// Extrusion of a floor plan into a labelled 3D triangle mesh (world frame: floor-plan metres,
// z up from the floor).
//
// What is built
// - Walls: every wall surface a horizontal cut meets, extruded band by band between the critical
//   heights (door height, window sills/heads, glass-wall sills/heads), so faces are exactly the
//   boundary of the union of all walls (no faces hidden inside walls, corners and T-junctions
//   closed). Both faces and the thickness (end faces, jambs) are present.
// - Doors: a closed door is a leaf filling the opening from the floor to door_height_m; an open
//   door is an empty opening. Above door_height_m the wall continues (lintel) with its soffit.
// - Windows: glass pane between sill and head; solid wall below the sill and above the head.
//   Glass walls: glass between glass_sill_m and glass_head_m (or the ceiling), solid elsewhere.
// - Obstacles (the plan's and generated clutter): one prism each (vertical faces and a top, up to
//   the ceiling), independent of the walls.
// - Floor (z = 0) and ceiling (z = wall_height_m) over the building interior (valid-area raster,
//   dilated to reach under the walls).
// All triangles are wound counter-clockwise seen from free space (outward normals).
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "floorcast/floorplans/floor_plan.hpp"

namespace floorcast {

/// Semantic label of a mesh triangle. Values are stable (files, glTF material order) and agree
/// with SurfaceLabel for 0..3.
enum class MeshLabel : std::uint8_t {
  kWall = 0,        ///< solid wall, including lintels, sills, heads and jambs
  kDoorClosed = 1,  ///< closed door leaf
  kGlass = 2,       ///< window pane or glass wall panel
  kClutter = 3,     ///< obstacles: the plan's own and generated clutter
  kFloor = 4,
  kCeiling = 5,
};
constexpr int kNumMeshLabels = 6;

/// "wall", "door_closed", "glass", "clutter", "floor", "ceiling".
const char* mesh_label_name(MeshLabel label);
/// Inverse of mesh_label_name; false if unknown.
bool mesh_label_from_name(const std::string& name, MeshLabel& label);

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

struct ExtrusionParams {
  double wall_height_m = 3.0;   ///< floor to ceiling; also the top of every wall
  double door_height_m = 2.1;   ///< top of door openings and closed door leaves; lintel above
  bool floor = true;            ///< emit the floor
  bool ceiling = true;          ///< emit the ceiling
  /// Resolution of the interior raster the floor and ceiling are built from (metres per cell).
  double floor_resolution_m = 0.1;
};

/// Builds the mesh of a plan (its obstacles included). Throws InputError for parameters that
/// make no sense (door height not inside (0, wall height), non-positive sizes).
Mesh extrude_plan(const FloorPlan& plan, const ExtrusionParams& params = {});

/// Axis-aligned box [min, max] of a mesh.
void mesh_bounds(const Mesh& mesh, Eigen::Vector3f& min_m, Eigen::Vector3f& max_m);

}  // namespace floorcast
