// Geometric clean-up of imported floor plans: real-world files draw shared edges twice, leave
// tiny gaps at corners and split straight walls into many pieces. cleanup_floor_plan() turns such
// a wall soup into a clean plan and reports what it changed. Pure algorithm: no I/O.
//
// Stages, in order (each counted in CleanupReport):
//   1. drop degenerate walls (shorter than min_wall_length_m);
//   2. snap endpoints: endpoints closer than snap_tolerance_m (single linkage) move to their
//      cluster's mean; then an endpoint within snap_tolerance_m of another wall's interior moves
//      onto that wall's centreline (closes T-junction gaps);
//   3. merge collinear walls: walls whose directions differ by at most angle_tolerance_rad, whose
//      endpoints lie within snap_tolerance_m of each other's line and whose extents overlap or
//      touch along it form runs (connected components). Direction and offset decide, never
//      shortness: a piece a few centimetres long is not collinear with a wall it crosses or
//      chamfers, whatever its length. A run's walls are projected onto the
//      run's length-weighted mean line and their union is
//      rebuilt as maximal pieces (duplicates and overlaps vanish, touching pieces and gaps up to
//      snap_tolerance_m join). Where pieces of different kind overlap, solid beats glass and the
//      thicker wall wins, so a piece only changes where its attributes change (thicknesses within
//      thickness_tolerance_m count as equal and are averaged);
//   4. snap again (stage 2) so corners of merged lines meet exactly, drop pieces that became
//      degenerate;
//   5. re-attach doors and windows: each opening goes to the merged wall that now carries its
//      centre (openings with an empty or unknown wall id go to the nearest wall within
//      thickness/2 + opening_attach_tolerance_m, preferring walls along which the span fits);
//      the centre moves onto the wall's axis; a span that overshoots a wall end by at most
//      snap_tolerance_m is shortened to fit, one that overruns it further (a door node on a wall
//      end) slides inside the wall, one wider than its wall is narrowed to it; openings of one
//      kind whose spans overlap on one wall are merged into one spanning both (a door drawn once
//      per room; a merged door is closed if either was). Windows never go into glass walls.
// Output walls keep the id of their first contributing input wall (later pieces of the same
// wall get "-2", "-3", ... suffixes), in input order, so results are deterministic.
#pragma once

#include <string>
#include <vector>

#include "floorcast/floorplans/floor_plan.hpp"

namespace floorcast {

struct CleanupOptions {
  /// Points closer than this are one point; gaps up to this along a line are closed; walls whose
  /// ends lie this close to each other's line are collinear. Default 2 cm: well below any real
  /// wall thickness and door width, well above coordinate noise of surveyed plans (WGS84 at 7
  /// decimals is ~1 cm).
  double snap_tolerance_m = 0.02;
  /// Maximum direction difference of collinear walls (default 1 degree).
  double angle_tolerance_rad = 0.017453292519943295;
  /// Touching collinear walls of one material whose thicknesses differ by at most this are one
  /// wall, with the length-weighted mean thickness (default 1 cm; measured thicknesses of
  /// vectorised images vary by a pixel).
  double thickness_tolerance_m = 0.01;
  /// Walls shorter than this after snapping are dropped as degenerate (default 1 cm).
  double min_wall_length_m = 0.01;
  /// An opening without a (known) wall attaches to the nearest wall whose centreline is within
  /// thickness/2 + this of its centre (default 10 cm).
  double opening_attach_tolerance_m = 0.10;
  /// Openings that cannot be placed on any wall (none near, or the span does not fit) are an
  /// InputError by default; with this set they are dropped and listed in CleanupReport::notes.
  bool drop_unattachable_openings = false;
};

/// What cleanup_floor_plan changed.
struct CleanupReport {
  int input_walls = 0;
  int output_walls = 0;
  int dropped_degenerate_walls = 0;  ///< shorter than min_wall_length_m (before or after snapping)
  int snapped_endpoints = 0;         ///< endpoints moved onto a nearby endpoint (cluster mean)
  int endpoints_snapped_to_walls = 0;  ///< endpoints moved onto a nearby wall's interior
  int collinear_groups_merged = 0;   ///< runs of touching collinear walls that had more than one wall
  int walls_merged_away = 0;         ///< walls absorbed into another (duplicates, collinear pieces)
  double duplicate_length_m = 0.0;   ///< total wall length that was drawn more than once
  int gaps_closed = 0;               ///< gaps up to snap_tolerance_m closed along a line
  int openings_reattached = 0;       ///< doors/windows moved to a different (merged) wall id
  int openings_merged = 0;           ///< duplicate doors/windows merged into another
  int openings_trimmed = 0;          ///< spans overshooting a wall end by <= snap_tolerance_m, shortened
  int openings_slid = 0;             ///< spans overrunning a wall end by more, slid inside the wall (noted)
  int openings_narrowed = 0;         ///< openings wider than their wall, narrowed to it (noted)
  int openings_moved_to_axis = 0;    ///< centres more than 1 mm off their wall's axis moved onto it (noted beyond 5 cm)
  int openings_dropped = 0;          ///< unattachable openings dropped (drop_unattachable_openings)
  std::vector<std::string> notes;    ///< one line per dropped element, with the reason
};

/// Cleans `plan` in place (walls, doors, windows; obstacles untouched). `source` names the input
/// in error messages. Throws InputError when an opening cannot be placed on a wall (unless
/// drop_unattachable_openings) or when the options are invalid.
CleanupReport cleanup_floor_plan(FloorPlan& plan, const CleanupOptions& options,
                                 const std::string& source);

/// Groups segments into collinear line groups (same rule as cleanup stage 3). Returns, for each
/// input segment, its group index (groups numbered in order of first appearance).
std::vector<int> collinear_groups(const std::vector<Segment2>& segments, double offset_tolerance_m,
                                  double angle_tolerance_rad);

/// Runs of collinear segments: the connected components of "collinear (as above) and overlapping
/// or touching along the longer one's line, gaps up to offset_tolerance_m". Each run lists segment
/// indices in input order; runs are ordered by their first member. The test is local, so
/// far-apart segments that merely share a line (up to a tiny angle) neither join nor tilt each
/// other's fitted line.
std::vector<std::vector<int>> collinear_runs(const std::vector<Segment2>& segments, double offset_tolerance_m,
                                             double angle_tolerance_rad);

/// A group's reference line: point on the line and unit direction (length-weighted mean).
struct GroupLine {
  Vec2 origin_m = Vec2::Zero();
  Vec2 direction = Vec2::UnitX();
  Vec2 at(double t) const { return origin_m + t * direction; }
  double param(const Vec2& p) const { return (p - origin_m).dot(direction); }
};
GroupLine fit_group_line(const std::vector<Segment2>& segments, const std::vector<int>& members);

}  // namespace floorcast
