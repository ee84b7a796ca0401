// Where observers stand: seeded observation poses in a plan's free space (optionally inside given
// regions, e.g. transitional spaces), used by scenarios, benches and tests.
#pragma once

#include <cstdint>
#include <vector>

#include "floorcast/core/types.hpp"
#include "floorcast/floorplans/floor_plan.hpp"
#include "floorcast/floorplans/rooms.hpp"

namespace floorcast {

/// N poses (position uniform over valid cells with at least clearance_m to the nearest blocked
/// cell — walls, closed doors, glass, and every obstacle footprint whatever its height, since
/// nobody stands inside furniture — jittered uniformly inside the cell; yaw uniform in [0, 2 pi)).
/// With `kinds` (the word "transitional" expands, rooms.hpp), only cells whose centre lies in a
/// room of those kinds count, the room being the smallest of `rooms` containing it (room_at:
/// an OSM level outline labelled "circulation" does not claim the offices inside it).
/// Point i of plan p draws from its own stream seeded by (seed, plan_index, i): same seed -> same
/// points. Throws InputError when no cell qualifies.
std::vector<Pose2> sample_observation_poses(const FloorPlan& plan, int n, std::uint64_t seed, int plan_index,
                                            double clearance_m, double resolution_m = 0.1,
                                            const std::vector<Room>& rooms = {},
                                            const std::vector<std::string>& kinds = {});

}  // namespace floorcast
