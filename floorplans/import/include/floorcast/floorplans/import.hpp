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

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "floorcast/floorplans/cleanup.hpp"
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
};

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

/// Local tangent plane about a WGS84 origin: exact geodetic -> ECEF -> east/north conversion
/// (ellipsoid height 0), so distances use the ellipsoid's radii of curvature at the origin.
class LocalTangentPlane {
 public:
  LocalTangentPlane(double lat0_deg, double lon0_deg);
  /// (east, north) metres of a WGS84 point.
  Vec2 to_local_m(double lat_deg, double lon_deg) const;
  /// Meridional radius of curvature M(lat) and prime-vertical radius N(lat), metres.
  static double meridian_radius_m(double lat_deg);
  static double prime_vertical_radius_m(double lat_deg);

 private:
  Eigen::Vector3d origin_ecef_;
  Eigen::Matrix3d R_enu_ecef_;
};

/// One OSM level=* / repeat_on=* value as closed ranges: "1" -> [1,1]; "1;3" -> [1,1],[3,3];
/// "-2--1" -> [-2,-1]; "0.5" -> [0.5,0.5]; "2~4" -> [2,4] (the range form of OSM-derived
/// GeoJSON exports). Returns false if the value is not of that form.
bool parse_osm_levels(const std::string& value, std::vector<std::pair<double, double>>& ranges);

}  // namespace floorcast
