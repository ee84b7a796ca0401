// Importers for the formats real floor plans come in (documented in floorplans/README.md,
// section "Importers"):
//   csv   PALMS wall segments, one `x1,y1,x2,y2` per line, metres;
//   s3d   Structured3D annotation_3d.json (room wall planes -> walls, door/window planes ->
//         openings);
//   png   occupancy image (F3Loc style: 255 free, anything else occupied) at a given m/px,
//         vectorised into walls with measured thickness;
//   imdf  Indoor Mapping Data Format folder (level/unit/opening.geojson), one level, WGS84
//         projected onto the local tangent plane;
//   osm   OpenStreetMap Simple Indoor Tagging XML, one level, WGS84 projected likewise.
// Every importer runs cleanup_floor_plan() (cleanup.hpp) and then validate_floor_plan() before it
// returns, so a returned plan is always valid. Errors throw InputError naming the file, the
// element (line number, feature index and id, way/node id, JSON path) and the reason.
//
// This is file I/O: the implementations live in src/import_*.cpp (the floorplans io part). Each
// format also has an in-memory entry point for tests.
#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "floorcast/floorplans/cleanup.hpp"
#include "floorcast/floorplans/faithfulness.hpp"
#include "floorcast/floorplans/floor_plan.hpp"

namespace floorcast {

enum class ImportFormat { kCsv, kS3d, kPng, kImdf, kOsm, kGeojson };

/// "csv", "s3d", "png", "imdf", "osm", "geojson" -> format; throws InputError listing the valid names.
ImportFormat parse_import_format(const std::string& name);
const char* import_format_name(ImportFormat format);

struct ImportOptions {
  /// Level to import. imdf: a level's `ordinal` (or its feature id, to pick one of several
  /// buildings' levels that share an ordinal); osm: a level=* value such as "0", "-1", "0.5".
  /// Required when the source holds more than one level. csv/s3d/png: just sets plan.level.
  std::optional<std::string> level;
  /// imdf: the building (feature id, or its name in any language) whose level `level` names by
  /// ordinal, for archives holding several buildings whose ordinals coincide.
  std::optional<std::string> building;
  /// csv and s3d: the source's length unit, "m", "cm", "mm", "ft" or "in" (default: metres for csv,
  /// millimetres for s3d). Giving it also turns off the unit check (below), as does `scale`.
  std::optional<std::string> units;
  /// csv and s3d: a factor applied to the source's coordinates after `units` (e.g. a drawing's
  /// scale). Unit check: without `units` and `scale`, a plan whose extent or wall lengths say it is
  /// not in the assumed unit (millimetres or centimetres read as metres: a level kilometres wide;
  /// feet: door openings of 2.6-3.3 "m") is refused with a message suggesting --units/--scale.
  std::optional<double> scale;
  /// png only, required: metres per pixel of the image.
  std::optional<double> resolution_m_per_px;
  /// png only: world coordinates (metres) of the image's bottom-left corner.
  Vec2 png_origin_m = Vec2::Zero();
  /// imdf/osm/geojson: the coordinate reference system of the source's positions (GeoFrame), e.g.
  /// "EPSG:32632"; overrides a GeoJSON `crs` member. Unset: the declared one, else WGS84.
  std::optional<std::string> crs;
  /// Thickness of imported walls. Unset: 0.10 m for csv, imdf and osm (PALMS rasters draw
  /// walls about 0.1 m wide); 0.02 m for s3d, whose walls are room surfaces (the wall's axis is
  /// the annotated surface). png measures each wall's thickness from the image.
  std::optional<double> wall_thickness_m;
  /// osm/geojson: width of a door node without a usable width=* tag (m).
  double default_door_width_m = 0.9;
  /// osm/geojson: side of a square column from an indoor=column node without width=* (m).
  double default_column_size_m = 0.4;
  /// Imported doors are closed (default: open, i.e. a gap in the wall, as PALMS cuts them).
  bool doors_closed = false;
  /// Plan name (default: derived from the source file name).
  std::string name;
  /// Clean-up tolerances; png raises snap_tolerance_m to at least 1.5 px, the angle tolerance to
  /// at least 3 degrees and the thickness tolerance to at least 1 px (pixel-level noise of fitted
  /// lines and measured thicknesses).
  CleanupOptions cleanup;

  /// s3d: also import the building's exterior surfaces (semantics type "outwall"). Default off:
  /// only room surfaces, what an observer inside can see.
  bool s3d_include_outwall = false;

  /// imdf: unit categories whose shared boundaries are not walls. A boundary shared by two or more
  /// units that all have one of these categories is open (IMDF splits large walkways into several
  /// units for naming). Default {"walkway"}. Every other unit boundary is a wall.
  std::vector<std::string> imdf_open_unit_categories = {"walkway"};
  /// imdf: unit categories that are no space to stand in: voids (opentobelow, an atrium's hole in
  /// the floor) and building mass drawn as units (column, structure and the wall materials brick,
  /// concrete, drywall, glass, wood). Their outlines are walls like every unit's; they are not
  /// room labels, so what they enclose is unmapped, not floor.
  std::vector<std::string> imdf_void_unit_categories = {"opentobelow", "column", "structure", "brick",
                                                        "concrete",    "drywall", "glass",    "wood"};

  /// imdf/osm/geojson (sources of mapped spaces): free space is the union of the level's spaces, so
  /// a region the walls enclose but no space covers (a courtyard, an atrium void) is labelled
  /// "unmapped" and is not floor. With this set it stays free floor (as before issue 23), and the
  /// faithfulness check says how much of it there is.
  bool unmapped_is_floor = false;
  /// imdf/osm/geojson: a room (a walled space that is not a corridor, hall or area) without any
  /// opening in the source gets a door on the longest stretch of wall it shares with a transitional
  /// space (heuristic in floorplans/README.md, "Openings"); counted as openings_inferred. Without
  /// it such rooms stay sealed, and a note says how many there are.
  bool infer_openings = false;
  /// Thresholds of the faithfulness check every import of mapped spaces reports.
  FaithfulnessOptions faithfulness;
  /// Warnings (faithfulness above its thresholds, a level without spaces) become refusals.
  bool strict = false;

  /// png: occupied connected components smaller than this many pixels are noise and dropped.
  int png_min_component_px = 4;
  /// png: skeleton branches with a free end shorter than max(this, 1.5 x the local half
  /// thickness) are spurs of the thinning, not walls (pixels).
  double png_min_branch_px = 3.0;
  /// png: Douglas-Peucker tolerance when splitting skeleton chains into straight walls (pixels).
  double png_polyline_epsilon_px = 1.5;
  /// png: occupied regions thicker than this are solid mass, not walls (an occupied exterior
  /// around the building, filled shafts): only a band as thick as the image's walls along their
  /// free boundary is kept as wall, the rest becomes empty (m).
  double png_max_wall_thickness_m = 1.0;
};

/// What an import produced and did.
struct ImportResult {
  FloorPlan plan;
  CleanupReport cleanup;
  /// Which level was imported (e.g. `ordinal 0 (level id "L0", "Ground")`); empty if the format
  /// has no levels and none was given.
  std::string level_description;
  /// Counts of what was read from the source, in reading order, e.g. {"segments", 120}.
  std::vector<std::pair<std::string, int>> source_counts;
  /// Elements skipped on purpose, one line each with the reason (never silent).
  std::vector<std::string> notes;
  /// What the importer repaired or skipped before clean-up, by name (e.g. {"unclosed_ways_skipped",
  /// 1}); the clean-up's own counts are in `cleanup`. Each has notes naming the elements.
  std::vector<std::pair<std::string, int>> repairs;
  /// Sources of mapped spaces (imdf, osm, geojson): is the plan what the source says
  /// (faithfulness.hpp)? Not applicable for csv, s3d and png.
  FaithfulnessReport faithfulness;
  /// What looks wrong beyond the thresholds (the faithfulness warnings and the importer's own);
  /// the import still succeeds unless ImportOptions::strict.
  std::vector<std::string> warnings;
};

/// The import report (`floorcast plan import --report`): output, name, level, source counts,
/// cleanup counts, repairs, plan counts, notes.
nlohmann::ordered_json import_report_json(const ImportResult& result, const std::string& output);

/// Imports a file (csv/s3d/osm: a file; png: an image file; imdf: a folder).
ImportResult import_floor_plan(const std::string& path, ImportFormat format, const ImportOptions& options = {});

/// In-memory entry points (`source` names the input in messages).
ImportResult import_csv_text(const std::string& text, const std::string& source, const ImportOptions& options = {});
ImportResult import_s3d_json(const std::string& json_text, const std::string& source,
                             const ImportOptions& options = {});
/// `image`: 8-bit, 1, 3 or 4 channels; a pixel is free iff all its colour channels are 255.
ImportResult import_png_image(const cv::Mat& image, const std::string& source, const ImportOptions& options);
/// `opening_geojson` may be empty (no openings file).
ImportResult import_imdf_texts(const std::string& level_geojson, const std::string& unit_geojson,
                               const std::string& opening_geojson, const std::string& source,
                               const ImportOptions& options = {});
ImportResult import_osm_xml(const std::string& xml_text, const std::string& source, const ImportOptions& options = {});
/// OSM-derived GeoJSON (osmtogeojson-style FeatureCollection: tags as flat properties or under
/// properties.tags; levels also written as ranges like "2~2").
ImportResult import_geojson_text(const std::string& text, const std::string& source, const ImportOptions& options = {});
/// `building_geojson` may be empty (no building file: --building matches building ids only).
ImportResult import_imdf_texts(const std::string& level_geojson, const std::string& unit_geojson,
                               const std::string& opening_geojson, const std::string& building_geojson,
                               const std::string& source, const ImportOptions& options = {});

/// Vectorises an occupancy mask (CV_8U, non-zero = occupied; row 0 is the top of the image) into
/// walls in metres (image bottom-left corner at png_origin_m, y up). Walls are not cleaned up.
/// `notes` receives what was dropped (noise components).
std::vector<Wall> vectorize_occupancy(const cv::Mat& occupied, double resolution_m_per_px,
                                      const ImportOptions& options, std::vector<std::string>* notes = nullptr);

/// Coordinates of a geographic source (imdf, osm, geojson) -> plan metres, through PROJ. The source
/// is WGS84 longitude/latitude unless a coordinate reference system is declared (a GeoJSON `crs`
/// member) or given (--crs): any CRS PROJ reads ("EPSG:32632", "urn:ogc:def:crs:EPSG::2056", WKT,
/// a PROJ string), geographic (longitude, latitude in degrees) or projected (easting, northing).
/// A projected source is first converted to longitude/latitude on its own datum (an exact inverse
/// projection; no datum shift, which only moves a building as a whole), then every point goes onto
/// the local tangent plane of that datum's ellipsoid about an origin: geodetic -> geocentric ->
/// topocentric east/north (PROJ's cart and topocentric operations, height 0). x = east, y = north,
/// metres. Over a building (< 1 km) the plane departs from distances on the ellipsoid by less than a
/// millimetre. Errors are InputErrors naming `what`; PROJ prints nothing.
class GeoFrame {
 public:
  /// `crs` empty: WGS84 longitude/latitude.
  explicit GeoFrame(const std::string& crs = std::string(), const std::string& what = "coordinates");
  ~GeoFrame();
  GeoFrame(GeoFrame&&) noexcept;
  GeoFrame& operator=(GeoFrame&&) noexcept;
  GeoFrame(const GeoFrame&) = delete;
  GeoFrame& operator=(const GeoFrame&) = delete;

  /// Geographic source (positions are longitude, latitude in degrees), else projected.
  bool geographic() const;
  /// "WGS 84 longitude/latitude (default)", "WGS 84 / UTM zone 32N (EPSG:32632)", ...
  const std::string& description() const;
  /// A source position (x = longitude or easting, y = latitude or northing) as (longitude,
  /// latitude) degrees on the source's datum. Throws InputError naming `where` when it is not a
  /// position of the CRS (a geographic source outside [-180, 180] x [-90, 90], with the hint to
  /// declare the projected CRS the numbers look like; a point PROJ cannot convert).
  Vec2 to_geographic_deg(const Vec2& source_xy, const std::string& where) const;
  /// The local plane's origin (longitude, latitude degrees on the source's datum).
  void set_origin_deg(const Vec2& lonlat_deg);
  /// (east, north) metres of a (longitude, latitude) point, after set_origin_deg().
  Vec2 to_local_m(const Vec2& lonlat_deg) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One OSM level=* / repeat_on=* value as closed ranges: "1" -> [1,1]; "1;3" -> [1,1],[3,3];
/// "-2--1" -> [-2,-1]; "0.5" -> [0.5,0.5]; "2~4" -> [2,4] (the range form of OSM-derived
/// GeoJSON exports). Returns false if the value is not of that form.
bool parse_osm_levels(const std::string& value, std::vector<std::pair<double, double>>& ranges);

}  // namespace floorcast
