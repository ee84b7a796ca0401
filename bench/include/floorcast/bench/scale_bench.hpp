// Plans of a chosen size for `floorcast bench scale`: generated buildings, and for areas above
// one campus, several campus buildings (distinct seeds) side by side, so matcher cost and memory
// can be measured against floor area (2,000 - 100,000 m^2 and beyond).
#pragma once

#include <cstdint>

#include "floorcast/floorplans/floor_plan.hpp"

namespace floorcast {

struct ScalePlanParams {
  /// Free floor area aimed at (the generators size their buildings for it; the result is within
  /// a few per cent, see plan area in the bench output).
  double area_m2 = 10000.0;
  std::uint64_t seed = 1;
  /// Above this area the plan is several campus buildings of about this size each.
  double campus_area_m2 = 10000.0;
  /// Gap between neighbouring buildings (m).
  double gap_m = 6.0;
};

/// The smallest area scale_plan makes: the office generator cannot fit its corridor, stair and
/// rooms with their doors below it for every seed (seeds 1-5 fail at 200-400 m^2).
constexpr double kMinScalePlanAreaM2 = 500.0;

/// Below 5,000 m^2: one office sized for the area; otherwise round(area / campus_area) campus
/// buildings (seeds seed, seed + 1, ...) sized area / count each, stacked along y with gap_m
/// between them, ids prefixed "b<k>_". Deterministic.
/// Refuses an area below kMinScalePlanAreaM2.
FloorPlan scale_plan(const ScalePlanParams& params);

/// A plan of about `walls` walls (issue 28: commands that pair or search walls must stay
/// near-linear in the wall count): scale_plan(params) with every wall that holds no door or
/// window cut into equal collinear pieces, as walls traced from images or exported from CAD
/// drawings arrive, so the wall count grows while the area (and every raster over it) stays that
/// of scale_plan. Named "walls_<N>". Deterministic; refuses a count that would need pieces
/// shorter than 2 cm.
FloorPlan many_walls_plan(const ScalePlanParams& params, std::size_t walls);

}  // namespace floorcast
