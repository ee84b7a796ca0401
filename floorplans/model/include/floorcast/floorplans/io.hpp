// Native floor-plan JSON format (documented in floorplans/README.md): reading, validation,
// writing. This is the floorplans library's only file-I/O part.
#pragma once

#include <string>

#include "floorcast/core/file_io.hpp"
#include "floorcast/floorplans/floor_plan.hpp"

namespace floorcast {

/// Limits the validator enforces; anything outside is refused as absurd.
struct PlanLimits {
  double max_abs_coordinate_m = kMaxAbsCoordinateM;  ///< 100 km from the origin
  double min_wall_length_m = 1.0e-3;     ///< shorter walls are degenerate
  double max_wall_length_m = 1.0e4;      ///< 10 km
  double min_thickness_m = 1.0e-3;
  double max_thickness_m = 5.0;
  double min_opening_width_m = 0.05;
  double max_opening_width_m = 100.0;
  double max_height_m = 100.0;
  /// A door/window centre may lie at most thickness/2 + this far from its wall's centreline.
  double opening_on_wall_tolerance_m = 0.05;
};

/// Parses and validates a plan from JSON text. `source` names the file in error messages.
/// Throws InputError on malformed JSON, missing/unknown fields, non-finite numbers, degenerate or
/// absurd geometry, duplicate ids, openings not on their wall or overlapping.
FloorPlan parse_floor_plan_json(const std::string& json_text, const std::string& source,
                                const PlanLimits& limits = {});

/// Validates an in-memory plan with the same rules (importers and generators call this before
/// handing a plan out). Throws InputError naming `source`.
void validate_floor_plan(const FloorPlan& plan, const std::string& source,
                         const PlanLimits& limits = {});

/// Canonical JSON text (fixed key order, shortest round-trip numbers, 2-space indent, trailing
/// newline): the same plan always gives the same bytes.
std::string floor_plan_to_json(const FloorPlan& plan);

/// Reads a plan file. Throws InputError if unreadable or invalid.
FloorPlan load_floor_plan(const std::string& path, const PlanLimits& limits = {});

/// Writes a plan file atomically (temporary file + rename). Throws InputError on failure.
void save_floor_plan(const FloorPlan& plan, const std::string& path);

}  // namespace floorcast
