// Private helpers shared by the importers (src/import_*.cpp).
#pragma once

#include <string>
#include <vector>

#include "floorcast/floorplans/import.hpp"

namespace floorcast::import_detail {

/// Shortest text for a number in messages.
std::string fmt(double v);
std::string quoted(const std::string& s);

/// File name without folders and extension ("a/b/plan.csv" -> "plan").
std::string stem_of(const std::string& path);

/// Runs cleanup and validation on an imported plan and fills the result. `default_name` is used
/// when options.name is empty.
ImportResult finish_import(FloorPlan plan, const std::string& source, const std::string& default_name,
                           const ImportOptions& options, ImportResult partial);

/// Wall thickness for formats with a fixed default.
double wall_thickness_or(const ImportOptions& options, double fallback_m, const std::string& source);

/// Integer plan level from options.level for formats without levels (csv, s3d, png).
int plain_level(const ImportOptions& options, const std::string& source);

/// A space outline edge (osm rooms/corridors/areas, imdf units) or an explicit wall.
struct BoundaryEdge {
  Segment2 segment_m;
  int owner = -1;       ///< the space (or wall) it belongs to
  bool walled = true;   ///< the owner's outline is a wall (room, corridor, unit, wall way)
  bool open = false;    ///< the owner is open to neighbours of the same open kind
};

/// Which parts of the space outlines are walls. A piece of outline is a wall iff some walled
/// owner draws it, unless two or more distinct owners draw it and all of them are open.
struct BoundaryPieces {
  std::vector<Segment2> walls;
  std::vector<Segment2> open;  ///< outline pieces that are not walls
};
BoundaryPieces classify_boundaries(const std::vector<BoundaryEdge>& edges, double tolerance_m,
                                   double angle_tolerance_rad);

/// Appends one wall per segment, ids "w1", "w2", ... continuing the plan's wall count.
void append_walls(FloorPlan& plan, const std::vector<Segment2>& segments, double thickness_m);

/// Distance from p to the nearest of the segments (infinity if none).
double distance_to_segments(const Vec2& p, const std::vector<Segment2>& segments);

}  // namespace floorcast::import_detail
