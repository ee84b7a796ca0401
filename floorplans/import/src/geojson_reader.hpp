// Private to the importers: a GeoJSON FeatureCollection with messages that name the feature
// (index and id), shared by the IMDF and the OSM-derived GeoJSON importers.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "import_common.hpp"

namespace floorcast::import_detail {

class GeoJsonFile {
 public:
  using Json = nlohmann::json;

  /// `expected_type`: the IMDF feature_type every feature must have (nullptr: no check).
  GeoJsonFile(const std::string& text, std::string name, const char* expected_type);

  std::size_t size() const { return root_["features"].size(); }
  const Json& feature(std::size_t i) const;

  /// The feature's "id" as text (strings as they are, numbers printed), or empty.
  std::string id(std::size_t i) const;
  /// `NAME: features[i] (id "X")`.
  std::string where(std::size_t i) const;
  [[noreturn]] void fail(std::size_t i, const std::string& reason) const;

  /// Checks feature_type and returns properties (object).
  const Json& properties(std::size_t i) const;
  /// properties.KEY as a string; empty when absent or null (an error when required).
  std::string string_property(std::size_t i, const char* key, bool required) const;

  /// The geometry's "type" ("" when the geometry is null or has none).
  std::string geometry_type(std::size_t i) const;

  /// A position as written ([x, y], finite numbers); GeoFrame checks it against the CRS.
  LonLat position(std::size_t i, const Json& v, const std::string& path) const;
  /// Rings of a Polygon / MultiPolygon geometry (outer rings and holes), closed (last = first).
  std::vector<Ring> polygon_rings(std::size_t i, std::vector<bool>* is_outer = nullptr) const;
  /// Parts of a LineString (one) or MultiLineString (several) geometry.
  std::vector<Ring> line_strings(std::size_t i) const;
  /// A Point geometry.
  LonLat point(std::size_t i) const;

  const std::string& name() const { return name_; }
  /// The coordinate reference system the file declares in a top-level "crs" member (GeoJSON 2008:
  /// {"type": "name", "properties": {"name": "EPSG:32632"}} or {"type": "EPSG", "properties":
  /// {"code": 32632}}), as text for PROJ; empty when none (RFC 7946: WGS84). A linked CRS is refused.
  const std::string& crs() const { return crs_; }

 private:
  std::string name_;
  const char* expected_type_;
  Json root_;
  std::string crs_;
};

}  // namespace floorcast::import_detail
