// 2D geometry derived from a floor plan: what blocks a horizontal ray at a given height, as
// convex footprints (for rasters and extrusion) and as the outline of their union (exact wall
// surfaces, for visibility and 2D ray casting).
#pragma once

#include <array>
#include <vector>

#include "floorcast/core/blocking.hpp"
#include "floorcast/core/box_index.hpp"
#include "floorcast/core/observation.hpp"
#include "floorcast/floorplans/floor_plan.hpp"

namespace floorcast {

/// A convex polygon (counter-clockwise) with a label.
struct Footprint {
  std::vector<Vec2> polygon_m;
  SurfaceLabel label = SurfaceLabel::kWall;
  int source_index = -1;  ///< index into plan.walls (walls, doors, glass) or plan.obstacles
  /// Axis of a wall piece / door leaf / glass pane (its centreline between the caps) or of a box
  /// obstacle (its medial segment: the long midline inset by half the short side); rasters draw it
  /// so thin walls stay watertight and thin boxes are painted. Unset (has_axis false) for pillars.
  Segment2 axis_m;
  bool has_axis = false;
};

/// The neighbourhood of every wall, built once per plan (an R-tree over the centre lines, and the
/// openings of each wall): what drawing walls needs without scanning all walls and openings for
/// each one (quadratic: a 1,000,000-wall plan took hours). Keeps a pointer to `plan`.
class WallJoins {
 public:
  explicit WallJoins(const FloorPlan& plan);
  /// True if the end `p` of wall `self` joins another wall (lies within half the thicker wall +
  /// 1 cm of its centre line): such ends get a square cap of half the thickness so corners close.
  bool end_joined(std::size_t self, const Vec2& p) const;
  /// Positions in plan.doors / plan.windows of the openings on wall `wall` (by id; with duplicate
  /// wall ids, the first wall of the id holds them, as FloorPlan::wall_index resolves them).
  const std::vector<std::size_t>& doors_on(std::size_t wall) const { return doors_[wall]; }
  const std::vector<std::size_t>& windows_on(std::size_t wall) const { return windows_[wall]; }

 private:
  const FloorPlan* plan_;
  BoxIndex tree_;
  double reach_m_ = 0.0;
  std::vector<std::vector<std::size_t>> doors_, windows_;
};

/// Convex blocking footprints at the cut height: wall pieces between openings (full thickness),
/// door leaves and glass panes in their openings, obstacles (pillars as 16-gons).
std::vector<Footprint> blocking_footprints(const FloorPlan& plan, const BlockingOptions& options);

/// A boundary segment of the union of blocking footprints, oriented so that the blocked region is
/// on its right (free space on its left), carrying the label of the footprint it bounds.
struct LabeledSegment {
  Segment2 segment_m;
  SurfaceLabel label = SurfaceLabel::kWall;
};

/// The exact outline of the union of blocking footprints: every edge piece that has free space
/// on one side. Shared edges of touching footprints and pieces inside other footprints are
/// removed; collinear touching pieces with the same label are merged.
std::vector<LabeledSegment> blocking_outline(const FloorPlan& plan, const BlockingOptions& options);

/// Same, from explicit footprints.
std::vector<LabeledSegment> footprint_outline(const std::vector<Footprint>& footprints);

/// Outline segments without labels.
std::vector<Segment2> outline_segments(const std::vector<LabeledSegment>& outline);

/// True if p lies inside (or on the boundary of) the convex CCW polygon.
bool point_in_convex_polygon(const std::vector<Vec2>& polygon_m, const Vec2& p);

/// Euclidean distance from p to the closest point of the segment (its end when p projects
/// outside it; the distance to a_m for a degenerate segment).
double point_segment_distance(const Vec2& p, const Segment2& segment);

/// Intersection of ray (origin, unit direction) with a segment; returns the ray parameter
/// (distance along a unit direction) or a negative value when there is none.
double ray_segment_distance(const Vec2& origin, const Vec2& direction, const Segment2& segment);

/// Liang-Barsky clipping of segment a-b to the closed box [x0, x1] x [y0, y1]: false when they do
/// not meet; otherwise a and b become the ends of the clipped piece.
bool clip_segment_to_box(Vec2& a, Vec2& b, double x0, double y0, double x1, double y1);

/// The plan rotated by yaw_rad about the world origin: wall ends, door, window and obstacle
/// centres (obstacles also turn by yaw_rad), room polygons and holes.
FloorPlan rotate_plan(const FloorPlan& plan, double yaw_rad);

}  // namespace floorcast
