// Structure measures of a floor plan: what makes a building distinctive or repetitive for
// localization (room-size spread, repeated room widths, corridor widths, door density, wall
// directions and thickness classes). Used to calibrate the generators on real plans
// (`floorcast plan stats`, results/realplans_vs_generated.md). Pure computation, no I/O.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "floorcast/floorplans/floor_plan.hpp"

namespace floorcast {

struct PlanStatsParams {
  /// Width of the wall-direction bins (degrees, directions folded into [0, 180)); bins are
  /// centred on multiples of the width.
  double direction_bin_deg = 15.0;
  /// A direction bin "is used" when it holds at least this share of the total wall length.
  double direction_min_share = 0.02;
  /// Two rooms are neighbours when their outlines come this close (wall centrelines; a shared
  /// wall gives 0).
  double neighbour_gap_m = 0.35;
  /// A room's width "repeats" a neighbour's when they differ by at most this share of the larger.
  double repeat_tolerance = 0.05;
  /// Raster resolution for corridor widths (distance transform of each transitional room).
  double resolution_m_per_px = 0.1;
  /// Corridor ridge samples narrower than this are slivers (gaps between mapped rooms), not
  /// corridors, and are ignored.
  double min_corridor_width_m = 0.6;
  /// Non-transitional rooms smaller than this are ignored (slivers, shafts drawn as rooms).
  double min_room_area_m2 = 1.0;
};

/// Order statistics of a sample (all zero with count 0). cv = standard deviation / mean.
struct Distribution {
  int count = 0;
  double min = 0.0, q1 = 0.0, median = 0.0, q3 = 0.0, max = 0.0, mean = 0.0, cv = 0.0;
};
/// Distribution of `values` (linear interpolation between order statistics for the quartiles).
Distribution describe(std::vector<double> values);

struct ThicknessClass {
  double thickness_m = 0.0;  ///< rounded to 1 cm
  int walls = 0;
  double length_share = 0.0;  ///< of the total wall length
};

struct PlanStats {
  std::string name;
  double direction_bin_deg = 15.0;   ///< PlanStatsParams::direction_bin_deg used
  double free_area_m2 = 0.0;         ///< free_floor_area_m2 (doors open)
  int walls = 0;
  int glass_walls = 0;
  double wall_length_m = 0.0;        ///< sum of wall centreline lengths
  /// Share of the wall length per direction bin (bin k centred on k * direction_bin_deg).
  std::vector<double> direction_share;
  int directions_used = 0;           ///< bins holding >= direction_min_share of the length
  std::vector<ThicknessClass> thickness_classes;  ///< sorted by thickness
  int doors = 0;
  double doors_per_10m_wall = 0.0;
  int pillars = 0;                   ///< obstacles of kind pillar (columns)
  int rooms = 0;                     ///< labelled rooms (FloorPlan::rooms, "unmapped" regions not counted)
  int transitional_rooms = 0;        ///< is_transitional_kind
  /// Non-transitional rooms of at least min_room_area_m2.
  Distribution room_area_m2;
  /// Their widths: the shorter side of each room's minimum-area enclosing rectangle.
  Distribution room_width_m;
  /// Share of those rooms whose width is within repeat_tolerance of a neighbouring room's width
  /// (rows of identical offices give ~1, varied rooms ~0). 0 without rooms.
  double repeated_width_share = 0.0;
  /// Width of the transitional space (all transitional rooms as one region, so alcoves and
  /// corridor pieces count as the circulation they form): twice the distance-transform value at
  /// every ridge (medial-axis) pixel, centreline to centreline; samples are ridge pixels, so the
  /// distribution is weighted by corridor length.
  Distribution corridor_width_m;
};

/// The statistics as `floorcast plan stats --json` writes them (measures rounded to 0.001),
/// from their field list.
nlohmann::ordered_json to_json(const PlanStats& stats);

/// Measures `plan`. Without room labels the room and corridor measures stay empty (count 0).
PlanStats plan_stats(const FloorPlan& plan, const PlanStatsParams& params = {});

/// Minimum-area enclosing rectangle of a point set: (shorter side, longer side) in metres.
std::pair<double, double> min_area_rect_sides_m(const std::vector<Vec2>& points);

}  // namespace floorcast
