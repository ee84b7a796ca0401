// Seeded clutter: furniture-like boxes against walls (desks, cabinets, shelves) and free-standing
// pillars in open areas, so scans see occluded walls like real ones do.
//
// Placement (deterministic for a seed, single-threaded):
// - Boxes: every solid wall face inside the building is cut into slots of slot_length_m; a slot
//   gets an item with probability `density`. The item stands wall_gap_m off the face, aligned
//   with it, and is accepted only if its footprint lies in free interior space (walls, doors,
//   earlier items and the plan's obstacles excluded, on a resolution_m raster), stays
//   door_clearance_m beyond every door's half-width from the door centre, stays
//   keep_clear_radius_m from every keep-clear point, and leaves at least
//   centerline_clearance_m between its far side and the local centre line of the free space
//   (the ridge of the distance-to-wall field along the wall normal), so corridors stay passable.
// - Pillars: density * open_area / pillar_area_m2 of them (open area = interior farther than
//   pillar_min_wall_distance_m from any wall, i.e. never in corridors narrower than twice that),
//   at random points there, at least pillar_spacing_m apart.
#pragma once

#include <cstdint>
#include <vector>

#include "floorcast/floorplans/floor_plan.hpp"

namespace floorcast {

struct ClutterParams {
  double density = 0.0;  ///< 0 = no clutter, 1 = every wall slot tried
  std::uint64_t seed = 0;
  double slot_length_m = 2.5;
  double wall_gap_m = 0.05;
  double door_clearance_m = 0.8;
  double centerline_clearance_m = 0.6;
  double keep_clear_radius_m = 0.6;
  std::vector<Vec2> keep_clear_m;  ///< e.g. the scan poses
  double pillar_area_m2 = 80.0;
  double pillar_min_wall_distance_m = 2.0;
  double pillar_spacing_m = 3.0;
  double pillar_height_m = 3.0;  ///< floor to ceiling at the default wall height
  double resolution_m = 0.05;
};

/// Generated obstacles (ids "clutter_box_<k>", "clutter_pillar_<k>"). Throws InputError on
/// parameters out of range (density outside [0, 1], non-positive sizes).
std::vector<Obstacle> generate_clutter(const FloorPlan& plan, const ClutterParams& params);

/// The plan with generated clutter appended to its obstacles.
FloorPlan with_clutter(const FloorPlan& plan, const ClutterParams& params);

}  // namespace floorcast
