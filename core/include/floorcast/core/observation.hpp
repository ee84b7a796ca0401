// The 2D observation every matcher consumes: observed wall surfaces (and optional F3Loc-style
// ray ranges) in the observer's frame. Produced by perfect observers (sim) and by the observation
// module (observe); plan-independent.
#pragma once

#include <vector>

#include "floorcast/core/bev.hpp"
#include "floorcast/core/plane_patch.hpp"
#include "floorcast/core/types.hpp"

namespace floorcast {

/// Semantic label of a blocking element. Values are stable (used in files and meshes).
enum class SurfaceLabel : int {
  kWall = 0,
  kDoorClosed = 1,
  kGlass = 2,
  kObstacle = 3,
};

/// A 2D observation of the walls around one observer, in the observer's frame.
/// Produced by the simulator (perfect observations) and by the observation module; consumed by
/// every matcher.
struct Observation2D {
  /// Observed wall surfaces as segments, observer frame, metres.
  std::vector<Segment2> segments_m;
  /// Optional F3Loc-style ranges along equiangular rays: ray i points at angle
  /// i * 2*pi / ray_ranges_m.size() (CCW from the observer's +x). A ray without a return within
  /// max_range_m holds max_range_m.
  std::vector<double> ray_ranges_m;
  /// Range the observation was limited to, metres.
  double max_range_m = 10.0;
  /// Optional bird's-eye-view predictions (core/bev.hpp) in the observer frame, at most one per
  /// class set (semantic, occupancy), for the BEV matcher; empty when none was made.
  std::vector<BevPrediction> bev;
  /// Optional 3D plane patches (walls, floor, ceiling, ...) in the observer's 3D frame: the 2D
  /// frame above with z up, origin at the sensor (the scan frame of core/scan.hpp). For plane
  /// matchers; empty when none were extracted.
  std::vector<PlanePatch> planes;
  /// Cell edge of every patch's grid in `planes`, metres.
  double plane_cell_m = 0.25;
};

}  // namespace floorcast
