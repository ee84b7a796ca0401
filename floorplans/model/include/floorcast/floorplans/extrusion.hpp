// The 3D geometry of a floor plan: the rule that turns walls, doors, windows, glass walls and
// obstacles into planar faces (world frame: floor-plan metres, z up from the floor). The
// simulator's mesh (sim/mesh.hpp) triangulates these faces; the plane matcher groups them into
// map planes. One rule, so what a simulated sensor sees and what a matcher expects agree.
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
//   dilated to reach under the walls), as rectangles.
// Every face's outward normal points into free space.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "floorcast/core/box_index.hpp"
#include "floorcast/floorplans/floor_plan.hpp"

namespace floorcast {

/// Semantic label of a face (and of a mesh triangle). Values are stable (files, glTF material
/// order) and agree with SurfaceLabel for 0..3.
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

struct ExtrusionParams {
  double wall_height_m = 3.0;   ///< floor to ceiling; also the top of every wall
  double door_height_m = 2.1;   ///< top of door openings and closed door leaves; lintel above
  bool floor = true;            ///< emit the floor
  bool ceiling = true;          ///< emit the ceiling
  /// Resolution of the interior raster the floor and ceiling are built from (metres per cell).
  double floor_resolution_m = 0.1;
};

/// Throws InputError for parameters that make no sense (door height not inside (0, wall height),
/// non-positive sizes).
void validate_extrusion(const ExtrusionParams& params);

/// One planar face of the extruded plan: a convex polygon, world frame.
struct ExtrudedFace {
  /// Vertices in order around the face (either winding; quads: a, b, b up, a up for vertical
  /// faces). Floats, as meshes and ray casters store them.
  std::vector<Eigen::Vector3f> polygon_m;
  Eigen::Vector3f outward = Eigen::Vector3f::UnitZ();  ///< unit normal into free space
  MeshLabel label = MeshLabel::kWall;
  /// Glass faces: the glass element (window k -> k, glass wall w -> windows.size() + w); -1 else.
  int part_id = -1;
};

/// The glass panes of a plan and a spatial index over them, built once per extrusion: which glass
/// element (window k -> k, glass wall w -> windows.size() + w, as ExtrudedFace::part_id) a point
/// on a glass face belongs to, from the few panes near it instead of a scan over every window and
/// every wall (quadratic on a plan of 1,000,000 walls). Keeps a reference to the plan.
class GlassPaneIndex {
 public:
  GlassPaneIndex(const FloorPlan& plan, const WallIdIndex& ids);
  /// The window whose pane (its interval along the wall, the wall's thickness, 1e-6 m tolerance)
  /// holds p, the one nearest the wall's centre line; else the glass wall that holds p, the
  /// nearest; the first in plan order on a tie; -1 when none does.
  int part_id(const Vec2& p);

 private:
  static constexpr double kTol = 1e-6;
  struct Pane {
    int id;
    int wall;
    double t0_m, t1_m;
  };
  const FloorPlan& plan_;
  std::size_t windows_;
  std::vector<Pane> panes_;
  BoxIndex index_;
  std::vector<std::uint32_t> candidates_;  // query buffer, reused
};

/// Every face of the plan's extrusion, in a fixed order (vertical faces band by band, door
/// soffits, obstacles, then floor and ceiling rectangles). Validates params first.
std::vector<ExtrudedFace> extrude_faces(const FloorPlan& plan, const ExtrusionParams& params = {});

/// A face's vertices in a plane's in-plane axes (u = basis.col(0), v = basis.col(1), e.g.
/// plane_cell_basis of the face's plane), counter-clockwise in (u, v) whatever the face's winding.
std::vector<Vec2> face_in_plane_axes(const ExtrudedFace& face, const Eigen::Matrix3d& basis);

/// Coplanar, connected faces of an extrusion: one physical planar surface (a wall side with its
/// lintels and closed door leaves, a glass pane, the floor of a connected interior, ...).
struct ExtrudedPlane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< outward, into free space
  double offset_m = 0.0;                              ///< normal . p on the plane
  /// kWall (walls, lintels, sills, jambs and closed door leaves), kGlass, kClutter, kFloor or
  /// kCeiling.
  MeshLabel label = MeshLabel::kWall;
  std::vector<int> faces;  ///< indices into the faces, ascending
};

/// Groups faces into planes: same label (closed doors count as walls), normals within 1e-6 rad,
/// offsets within 1e-6 m, and connected (face rectangles in the plane touching or overlapping
/// within gap_m). Planes come in the order of their first face.
std::vector<ExtrudedPlane> group_coplanar_faces(const std::vector<ExtrudedFace>& faces, double gap_m = 1e-3);

}  // namespace floorcast
