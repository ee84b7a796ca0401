// Simulated human walks through a floor plan's free space: the "then walk" of PALMS (scan, then
// walk), with the observations a tracker receives along the way.
//
// A walk is planned on a navigation grid of the plan's free space (interior cells at least
// `clearance_m` from any wall, closed door, glass or piece of furniture, whatever its height):
// goal after goal is drawn far away (geodesic distance) and preferably in transitional space
// (cells with a wide clearance: corridors, lobbies, junctions), the route to it is the cheapest
// grid path under a cost that prefers the middle of corridors, shortened by line-of-sight string
// pulling and rounded at corners. A walker then follows it with human gait: a walking speed per
// walk in [1.0, 1.4] m/s, steps at 1.8-2 Hz with small per-step variation, turns limited to a
// human turn rate, and occasional pauses. Every step segment stays in free space.
//
// Frames: world = plan metres; T_world_body is the walker's (phone's) pose: position and heading.
// Randomness: CounterRng streams of the walk's seed (same seed, same walk, any thread count).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "floorcast/core/fields.hpp"

#include "floorcast/core/blocking.hpp"
#include "floorcast/core/types.hpp"
#include "floorcast/floorplans/floor_plan.hpp"

namespace floorcast {

struct WalkParams {
  /// Step samples of the walk (PALMS' walks: 100-200 steps). Pauses count as samples.
  int steps = 120;
  /// Minimum distance of the walked path from walls, closed doors, glass and furniture.
  double clearance_m = 0.4;
  /// Walking speed, drawn once per walk (human walking: 1.0-1.4 m/s; sensors.md).
  double speed_min_mps = 1.0;
  double speed_max_mps = 1.4;
  /// Step frequency, drawn once per walk (~1.8-2 steps/s).
  double cadence_min_hz = 1.8;
  double cadence_max_hz = 2.0;
  /// Per-step variation of step length and duration (relative sigma).
  double step_variation_rel = 0.05;
  /// Largest heading change rate of the walker (humans turn at ~90-180 deg/s while walking).
  double max_turn_rate_dps = 120.0;
  /// Probability that the walker stops after a step, and how long (uniform) the pause lasts.
  double pause_probability = 0.01;
  double pause_min_s = 1.0;
  double pause_max_s = 3.0;
  /// Goals are drawn at least this far away along the free space (geodesic), when possible.
  double min_goal_distance_m = 15.0;
  /// Cells with at least this clearance are transitional space (corridors, lobbies, junctions);
  /// goals are drawn there with probability transitional_goal_share.
  double transitional_clearance_m = 0.9;
  double transitional_goal_share = 0.8;
  /// Cost of a grid step = length x (1 + centre_weight x exp(-(d - clearance_m) / 0.5 m)) for a
  /// cell at distance d from the nearest obstacle: walkers keep to the middle of corridors.
  double centre_weight = 2.0;
  /// Navigation grid resolution.
  double resolution_m = 0.1;
  /// Corner rounding: radius of the arcs replacing route corners, where the free space allows.
  double corner_radius_m = 0.6;
  std::uint64_t seed = 1;

  /// The field list (core/fields.hpp): keys, ranges, docs; to_json and apply_overrides use it.
  static const FieldList<WalkParams>& fields();
  nlohmann::ordered_json to_json() const;
  /// Strict overrides (keys as in to_json); throws ParameterError naming the key.
  void apply_overrides(const nlohmann::json& overrides);
};

/// One sample of the walk, at a step (or during a pause).
struct WalkStep {
  double t_s = 0.0;      ///< time since the walk started
  Pose2 T_world_body;    ///< true pose after this step
  bool moving = true;    ///< false: the walker stands (pause); the first sample is the start
  double step_length_m = 0.0;  ///< distance walked since the previous sample
};

struct WalkSummary {
  double length_m = 0.0;
  double duration_s = 0.0;
  double speed_mps = 0.0;     ///< the walk's walking speed
  double cadence_hz = 0.0;    ///< the walk's step frequency
  int pauses = 0;
  double total_turn_deg = 0.0;     ///< sum of absolute heading changes
  double transitional_share = 0.0; ///< share of samples in transitional space
  int goals = 0;
  /// Longest stretch walked without turning more than 20 deg (a long homogeneous corridor is the
  /// hard case of sequential localization).
  double longest_straight_m = 0.0;
};

struct Walk {
  std::vector<WalkStep> steps;  ///< steps[0] is the start (t = 0, not moving)
  std::vector<Vec2> route_m;    ///< the planned (smoothed) path the walker followed
  WalkSummary summary;
  WalkParams params;
};

/// What counts as an obstacle for a walker: walls, closed doors, glass, and every piece of
/// furniture (cut just above the floor).
BlockingOptions walker_blocking();

/// A random start pose in the largest connected region of the plan's free space (clearance as for
/// walking), heading uniform.
/// Throws InputError when the plan has no free space with that clearance.
Pose2 random_start_pose(const FloorPlan& plan, const WalkParams& params);

/// Simulates a walk from `start`. Throws InputError when the start is not in free space (with the
/// clearance) or nothing can be reached from it.
Walk simulate_walk(const FloorPlan& plan, const Pose2& start, const WalkParams& params);

/// Step indices at which observations are made: the start (PALMS: scan, then walk), then every
/// `every_steps` samples and/or every `every_m` metres walked (0 = off).
struct ObservationSchedule {
  bool initial = true;
  int every_steps = 0;
  double every_m = 0.0;
};
/// Its fields (initial, every_steps, every_m) as scenarios and walk.json write them.
const FieldList<ObservationSchedule>& schedule_fields();
std::vector<int> schedule_observations(const Walk& walk, const ObservationSchedule& schedule);

}  // namespace floorcast
