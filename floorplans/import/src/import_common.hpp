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
/// when options.name is empty. With `units`, the validated plan then gets the unit check. Then the
/// free-space rule (enclosed regions no space covers become "unmapped"), the faithfulness check,
/// and the room-sized free region check: a refusal for `mapped_spaces` sources (imdf, osm,
/// geojson), a warning for the others; --strict turns warnings into a refusal.
ImportResult finish_import(FloorPlan plan, const std::string& source, const std::string& default_name,
                           const ImportOptions& options, ImportResult partial, const UnitCheck* units = nullptr,
                           bool mapped_spaces = false);

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

/// The free-space rule at the outlines (floorplans/README.md, "Free space"): an outline piece that
/// is not a wall (an indoor=area or wall=no outline, a boundary between corridors) becomes a wall
/// where it borders unmapped space, i.e. where no space lies within `offset_m` on one of its sides.
/// `spaces` are the level's spaces (room labels). Returns the length turned into walls (m) and the
/// number of pieces; `pieces.open` keeps the rest.
struct WalledAtUnmapped {
  double length_m = 0.0;
  int pieces = 0;
};
WalledAtUnmapped wall_unmapped_sides(BoundaryPieces& pieces, const std::vector<Room>& spaces, double offset_m = 0.15);

/// Openings of the level's rooms (floorplans/README.md, "Openings"): a room is a space whose kind
/// is neither transitional nor "area" (its outline is walled); it has an opening when a door lies on
/// its outline (within `reach_m`) or a stretch of its outline is no wall (farther than `reach_m`
/// from every wall). With `infer`, each room without one gets a door (id "inferred-<room id>",
/// `width_m` wide, narrower down to 0.6 m on a short boundary, 0.2 m from its ends) at the middle of
/// the longest stretch of its outline that lies on a wall and has a transitional space on its
/// other side (0.15 m beyond it); rooms without such a stretch stay sealed. Notes name what was
/// found and done.
struct OpeningsReport {
  int rooms = 0;
  int rooms_without = 0;  ///< before inference
  int inferred = 0;
  int left_sealed = 0;    ///< without an opening after inference (all of rooms_without without it)
};
OpeningsReport check_openings(FloorPlan& plan, const std::vector<Segment2>& walls, bool infer, double width_m,
                              double reach_m, std::vector<std::string>& notes);

/// A wall drawn as a polygon with its thickness (GeoJSON Polygon with indoor=wall or type=wall,
/// ...), in plan metres: outer ring first, then holes.
struct WallPolygon {
  std::string what;  ///< names it in notes
  std::string id;
  std::vector<std::vector<Vec2>> rings;
  bool glass = false;
};
/// Walls of wall polygons: a rectangle (opposite sides parallel, adjacent perpendicular, within 1
/// degree) is one wall along its long axis, as thick as its short side (a polygon over 5 m thick is
/// skipped with a note); every other shape (L and T pieces, a floor's walls as one polygon with the
/// rooms as holes) is drawn on a 2 cm raster (coarser above 20 million cells) and vectorised like an
/// occupancy image (vectorize_occupancy), each wall's thickness measured. Counts both kinds.
std::vector<Wall> walls_from_polygons(const std::vector<WallPolygon>& polygons, const ImportOptions& options,
                                      std::vector<std::string>& notes, int& rectangles, int& traced);

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

/// A source position as read: longitude/latitude degrees, or easting/northing of a projected CRS
/// (GeoFrame converts it).
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
  /// Room kind of the space when the schema says more than its indoor=* value (IndoorOSM
  /// buildingpart=hall -> "hall"); empty: from the tags.
  std::string kind;
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
  std::string crs;  ///< the coordinate reference system the source declares (empty: WGS84)
  /// The most frequent tag keys of the source's ways and relations (for the message when it holds
  /// no indoor schema the importer reads), most frequent first.
  std::vector<std::pair<std::string, int>> frequent_keys;
};

/// Imports one level of OSM Simple Indoor Tagging data (the OSM XML and the OSM-derived GeoJSON
/// importers share this; semantics in floorplans/README.md). `name_stem` prefixes the plan name.
ImportResult import_indoor(const IndoorData& data, const std::string& source, const std::string& name_stem,
                           const ImportOptions& options);

}  // namespace floorcast::import_detail
