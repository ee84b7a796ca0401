// What blocks a horizontal ray (a sensor ray, a line of sight, a walker) when a floor plan is cut
// at a given height. One struct shared by rasters, perfect observers, matchers and walks, so one
// door/glass/obstacle policy flows to every stage.
#pragma once

namespace floorcast {

/// What counts as blocking when cutting the plan with a horizontal plane.
struct BlockingOptions {
  bool closed_doors_block = true;   ///< closed door leaves block
  bool open_doors_block = false;    ///< treat open doors as closed (PALMS+ sec. 4.4 "doors closed")
  bool glass_blocks = true;         ///< glass walls and windows block
  bool obstacles_block = false;     ///< clutter obstacles block
  /// Height of the horizontal cut above the floor (decides whether a window or a partial-height
  /// glass wall or an obstacle is cut). Default: a phone held at 1.5 m.
  double cut_height_m = 1.5;
};

}  // namespace floorcast
