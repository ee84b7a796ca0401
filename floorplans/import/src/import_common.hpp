// Private helpers shared by the importers (src/import_*.cpp).
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "floorcast/floorplans/import.hpp"

namespace floorcast::import_detail {

/// Shortest text for a number in messages.
std::string fmt(double v);
std::string quoted(const std::string& s);

/// File name without folders and extension ("a/b/plan.csv" -> "plan").
std::string stem_of(const std::string& path);

/// The unit check of check_plan_units(): metres per source unit used, the format's native unit,
/// and the remedy to suggest ("--units" or "--resolution").
struct UnitCheck {
  double unit_m = 1.0;
  std::string native_unit = "m";
  std::string remedy = "--units";
};

/// Runs cleanup and validation on an imported plan and fills the result. `default_name` is used
/// when options.name is empty. With `units`, the validated plan then gets the unit check.
ImportResult finish_import(FloorPlan plan, const std::string& source, const std::string& default_name,
                           const ImportOptions& options, ImportResult partial, const UnitCheck* units = nullptr);

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

/// Metres per source unit for csv/s3d: options.units (default `native_unit`) times options.scale.
/// Throws InputError naming the option on an unknown unit or a bad factor.
double source_unit_m(const ImportOptions& options, const std::string& native_unit, const std::string& source);

/// Unit check of a freshly read plan (before clean-up), skipped when the user gave --units or
/// --scale: refuses a plan whose extent or wall lengths say it is in another unit than assumed,
/// with a message suggesting the fix (`remedy`: "--units/--scale" or "--resolution").
/// `unit_m`: metres per source unit used; `native_unit`: the format's default unit;
/// `too_large_only`: only the "kilometres wide" check (before clean-up).
void check_plan_units(const FloorPlan& plan, const std::string& source, double unit_m, const std::string& native_unit,
                      const std::string& remedy, bool too_large_only);

/// Adds `n` to the named repair count (kept in first-use order; zero counts are not added).
void count_repair(ImportResult& result, const std::string& name, int n = 1);

// ---- Geographic sources -------------------------------------------------------------------------

struct LonLat {
  double lon = 0.0, lat = 0.0;
  bool operator==(const LonLat& o) const { return lon == o.lon && lat == o.lat; }
  bool operator<(const LonLat& o) const { return lon < o.lon || (lon == o.lon && lat < o.lat); }
};
using Ring = std::vector<LonLat>;
using Tags = std::map<std::string, std::string>;

/// One OSM-style indoor element, read from OSM XML (a way or a multipolygon relation) or from an
/// OSM-derived GeoJSON feature, in WGS84.
struct IndoorFeature {
  std::string what;  ///< names it in messages: "way 12", "relation 7", "file: features[3] (id "12")"
  std::string id;    ///< short id for room labels: "way12", "relation7", "f3"
  Tags tags;
  /// Rings (areas: closed, first = last; lines: open) and which are inner rings (holes).
  std::vector<Ring> rings;
  std::vector<bool> inner;
  bool area = false;      ///< area geometry (closed way, multipolygon, GeoJSON (Multi)Polygon)
  bool unclosed = false;  ///< an area whose ring does not close (a data defect: skipped with a note)
};
struct IndoorPoint {
  std::string what;  ///< "node 5", "file: features[2] (id "5")"
  std::string id;    ///< "node5", "f2"
  Tags tags;
  LonLat at;
};
struct IndoorData {
  std::vector<IndoorFeature> features;
  std::vector<IndoorPoint> points;
  std::vector<std::pair<std::string, int>> source_counts;  ///< what the parser read
};

/// Imports one level of OSM Simple Indoor Tagging data (the OSM XML and the OSM-derived GeoJSON
/// importers share this; semantics in floorplans/README.md). `name_stem` prefixes the plan name.
ImportResult import_indoor(const IndoorData& data, const std::string& source, const std::string& name_stem,
                           const ImportOptions& options);

}  // namespace floorcast::import_detail
