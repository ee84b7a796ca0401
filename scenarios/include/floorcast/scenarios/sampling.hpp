// Where observers stand: seeded observation poses in a plan's free space (optionally inside given
// regions, e.g. transitional spaces), used by scenarios, benches and tests.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
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

/// What a sampling covered, so a run can say where its points are.
struct SamplingCoverage {
  int points = 0;
  /// Points per room kind (room_at; "unlabelled" outside every room), most first.
  std::vector<std::pair<std::string, int>> points_per_kind;
  /// Distinct 2 m x 2 m cells (world grid from the origin) holding a point.
  int distinct_cells_2m = 0;
  /// Area of the cells the points are drawn from (free, clearance kept, in the sampled kinds).
  double candidate_area_m2 = 0.0;
  /// With kinds: the labelled area of rooms of those kinds (their polygons' areas) and the free
  /// floor (valid area) in them (cells whose smallest room is one of them), whatever the clearance.
  double kind_area_m2 = 0.0;
  double kind_free_area_m2 = 0.0;
  /// Worth a look although points were drawn (the sampled kinds' rooms mostly outside the free
  /// space; points crowded into a few 2 m cells).
  std::vector<std::string> warnings;
};

/// Why no point could be drawn.
enum class SamplingRefusal {
  kNoRoomOfKinds,          ///< the plan has no room of the sampled kinds
  kKindsOutsideFreeSpace,  ///< it has, but they lie outside the free space (missing from the plan's floor)
  kKindsTooNarrow,         ///< they are free floor, but nowhere wide enough for the clearance
  kNoClearance,            ///< (uniform) no free cell keeps the clearance
};
/// The refusal of sample_observation_points: an InputError whose message names the plan, the
/// cause and the figures behind it.
class SamplingError : public InputError {
 public:
  SamplingError(SamplingRefusal cause, const std::string& message) : InputError(message), cause_(cause) {}
  SamplingRefusal cause() const { return cause_; }

 private:
  SamplingRefusal cause_;
};

struct SampledPoints {
  std::vector<Pose2> poses;
  SamplingCoverage coverage;
};
/// sample_observation_poses() (the same points) with its coverage; refusals are SamplingErrors
/// with one message per cause: no room of the sampled kinds (listing the kinds the plan has), such
/// rooms outside the free space (their labelled and free areas), such rooms too narrow for the
/// clearance (their widest free point), no free cell with the clearance at all.
SampledPoints sample_observation_points(const FloorPlan& plan, int n, std::uint64_t seed, int plan_index,
                                        double clearance_m, double resolution_m = 0.1,
                                        const std::vector<Room>& rooms = {},
                                        const std::vector<std::string>& kinds = {});

/// One line: "30 corridor, 10 hallway; 36 distinct 2 m cells; 412.0 m^2 to draw from".
std::string sampling_coverage_summary(const SamplingCoverage& coverage);

}  // namespace floorcast
