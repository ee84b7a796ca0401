// The floor plan as the thesis' ray casting sees it (seed paper 004, sec. 3.3.4): at a cut height,
// the surfaces that stop a ray and the faces of doors and windows a ray passes, each oriented with
// free space on its left (as blocking_outline), and the obvious per-ray cast on them. The BEV
// matcher's precomputed volume (localization/match) is tested against semantic_ray_hits; the
// perfect observer's BEV is made with it.
#pragma once

#include <vector>

#include "floorcast/core/bev.hpp"
#include "floorcast/floorplans/geometry.hpp"

namespace floorcast {

struct SemanticPlanLines {
  /// Surfaces that stop a ray: semantic classes = the wall outline with gaps at every door and
  /// window (jambs included); occupancy classes = walls and glass (windows, glass walls), doors
  /// removed (their openings are gaps).
  std::vector<Segment2> stops;
  /// Faces of door leaves (every door, drawn closed) and glass panes that touch free space, each
  /// with its class (kDoorOpen / kDoorClosed by the door's state, kWindow); a ray records the
  /// faces it enters (from their free, left side) and passes on. Empty for occupancy classes.
  std::vector<Segment2> permeable;
  std::vector<SemanticClass> permeable_labels;
};

/// The plan's semantic lines at cut_height_m for a class set (core/bev.hpp).
SemanticPlanLines semantic_plan_lines(const FloorPlan& plan, BevClasses classes, double cut_height_m = 1.5);

/// What the ray from origin at world angle angle_rad meets within max_range_m, nearest first: the
/// permeable faces it enters (from their left side) before the nearest stop, then that stop as a
/// wall hit (occupancy classes: the stop is labelled kWall whatever it is). Brute force over every
/// line: the reference of the matcher's volume.
std::vector<SemanticHit> semantic_ray_hits(const SemanticPlanLines& lines, const Vec2& origin_m, double angle_rad,
                                           double max_range_m);

}  // namespace floorcast
