#include "geojson_reader.hpp"

#include <cmath>

#include "floorcast/core/limits.hpp"

namespace floorcast::import_detail {

GeoJsonFile::GeoJsonFile(const std::string& text, std::string name, const char* expected_type)
    : name_(std::move(name)), expected_type_(expected_type) {
  try {
    root_ = Json::parse(text);
  } catch (const Json::exception& e) {
    throw InputError(name_ + ": malformed JSON: " + e.what());
  }
  if (!root_.is_object() || !root_.contains("type") || root_["type"] != "FeatureCollection") {
    throw InputError(name_ + ": expected a GeoJSON FeatureCollection");
  }
  if (!root_.contains("features") || !root_["features"].is_array()) {
    throw InputError(name_ + ": FeatureCollection has no \"features\" array");
  }
  if (root_.contains("crs") && !root_["crs"].is_null()) {
    const Json& c = root_["crs"];
    const std::string type = c.is_object() && c.contains("type") && c["type"].is_string() ? c["type"].get<std::string>() : "";
    const Json* props = c.is_object() && c.contains("properties") && c["properties"].is_object() ? &c["properties"] : nullptr;
    if (type == "name" && props && props->contains("name") && (*props)["name"].is_string()) {
      crs_ = (*props)["name"].get<std::string>();
    } else if (type == "EPSG" && props && props->contains("code") && (*props)["code"].is_number_integer()) {
      crs_ = "EPSG:" + std::to_string((*props)["code"].get<long long>());
    } else {
      throw InputError(name_ + ": crs " + c.dump() +
                       " is not a named CRS ({\"type\": \"name\", \"properties\": {\"name\": \"EPSG:NNNN\"}}); "
                       "give the coordinate reference system with --crs");
    }
  }
}

const GeoJsonFile::Json& GeoJsonFile::feature(std::size_t i) const {
  const Json& f = root_["features"][i];
  if (!f.is_object()) fail(i, "feature must be a JSON object");
  return f;
}

std::string GeoJsonFile::id(std::size_t i) const {
  const Json& f = root_["features"][i];
  if (!f.is_object() || !f.contains("id")) return {};
  const Json& v = f["id"];
  if (v.is_string()) return v.get<std::string>();
  if (v.is_number_integer()) return v.dump();
  return {};
}

std::string GeoJsonFile::where(std::size_t i) const {
  std::string w = name_ + ": features[" + std::to_string(i) + "]";
  const std::string fid = id(i);
  if (!fid.empty()) w += " (id " + quoted(fid) + ")";
  return w;
}

void GeoJsonFile::fail(std::size_t i, const std::string& reason) const { throw InputError(where(i) + ": " + reason); }

const GeoJsonFile::Json& GeoJsonFile::properties(std::size_t i) const {
  const Json& f = feature(i);
  if (expected_type_ && f.contains("feature_type") && f["feature_type"].is_string() && f["feature_type"] != expected_type_) {
    fail(i, "feature_type is " + quoted(f["feature_type"].get<std::string>()) + ", expected " + quoted(expected_type_));
  }
  if (!f.contains("properties") || !f["properties"].is_object()) fail(i, "missing \"properties\" object");
  return f["properties"];
}

std::string GeoJsonFile::string_property(std::size_t i, const char* key, bool required) const {
  const Json& p = properties(i);
  if (!p.contains(key) || p[key].is_null()) {
    if (required) fail(i, std::string("missing properties.") + key);
    return {};
  }
  if (!p[key].is_string()) fail(i, std::string("properties.") + key + " must be a string, got " + p[key].dump());
  return p[key].get<std::string>();
}

std::string GeoJsonFile::geometry_type(std::size_t i) const {
  const Json& f = feature(i);
  if (!f.contains("geometry") || !f["geometry"].is_object()) return {};
  const Json& g = f["geometry"];
  return g.contains("type") && g["type"].is_string() ? g["type"].get<std::string>() : std::string();
}

LonLat GeoJsonFile::position(std::size_t i, const Json& v, const std::string& path) const {
  if (!v.is_array() || v.size() < 2 || !v[0].is_number() || !v[1].is_number()) {
    fail(i, "geometry position " + path + " must be [longitude, latitude], got " + v.dump());
  }
  LonLat p{v[0].get<double>(), v[1].get<double>()};
  if (!std::isfinite(p.lon) || !std::isfinite(p.lat)) fail(i, "geometry position " + path + " is not finite: " + v.dump());
  return p;
}

std::vector<Ring> GeoJsonFile::polygon_rings(std::size_t i, std::vector<bool>* is_outer) const {
  const Json& f = feature(i);
  if (!f.contains("geometry") || !f["geometry"].is_object()) fail(i, "missing geometry");
  const Json& g = f["geometry"];
  const std::string type = geometry_type(i);
  if (!g.contains("coordinates") || !g["coordinates"].is_array()) fail(i, "geometry has no coordinates array");
  std::vector<const Json*> polygons;
  if (type == "Polygon") {
    polygons.push_back(&g["coordinates"]);
  } else if (type == "MultiPolygon") {
    for (const Json& p : g["coordinates"]) polygons.push_back(&p);
  } else {
    fail(i, "geometry must be a Polygon or MultiPolygon, got " + quoted(type));
  }
  std::vector<Ring> rings;
  for (std::size_t pi = 0; pi < polygons.size(); ++pi) {
    const Json& poly = *polygons[pi];
    if (!poly.is_array() || poly.empty()) fail(i, "polygon " + std::to_string(pi) + " has no rings");
    for (std::size_t ri = 0; ri < poly.size(); ++ri) {
      const Json& ring = poly[ri];
      if (!ring.is_array() || ring.size() < 3) {
        fail(i, "polygon " + std::to_string(pi) + " ring " + std::to_string(ri) + " needs at least 3 positions");
      }
      // Bounded before the clean-up sees it (a 200,000-vertex unit ran ~1 min before validation refused it).
      check_limit("max_vertices_per_element", static_cast<double>(ring.size()),
                  where(i) + ": polygon " + std::to_string(pi) + " ring " + std::to_string(ri), "vertices");
      Ring r;
      for (std::size_t k = 0; k < ring.size(); ++k) {
        r.push_back(position(i, ring[k], "[" + std::to_string(pi) + "][" + std::to_string(ri) + "][" + std::to_string(k) + "]"));
      }
      // GeoJSON rings are closed (last = first); an unclosed ring is closed implicitly.
      if (r.front().lon != r.back().lon || r.front().lat != r.back().lat) r.push_back(r.front());
      rings.push_back(std::move(r));
      if (is_outer) is_outer->push_back(ri == 0);
    }
  }
  return rings;
}

std::vector<Ring> GeoJsonFile::line_strings(std::size_t i) const {
  const Json& f = feature(i);
  if (!f.contains("geometry") || !f["geometry"].is_object()) fail(i, "missing geometry");
  const Json& g = f["geometry"];
  const std::string type = geometry_type(i);
  if (!g.contains("coordinates") || !g["coordinates"].is_array()) fail(i, "geometry has no coordinates array");
  std::vector<const Json*> parts;
  if (type == "LineString") {
    parts.push_back(&g["coordinates"]);
  } else if (type == "MultiLineString") {
    for (const Json& p : g["coordinates"]) parts.push_back(&p);
  } else {
    fail(i, "geometry must be a LineString or MultiLineString, got " + quoted(type));
  }
  std::vector<Ring> out;
  for (std::size_t pi = 0; pi < parts.size(); ++pi) {
    const Json& line = *parts[pi];
    const std::string prefix = parts.size() > 1 ? "[" + std::to_string(pi) + "]" : "";
    if (!line.is_array() || line.size() < 2) {
      fail(i, (parts.size() > 1 ? "line " + std::to_string(pi) + " " : std::string("LineString ")) + "needs at least 2 positions");
    }
    check_limit("max_vertices_per_element", static_cast<double>(line.size()), where(i) + prefix, "vertices");
    Ring r;
    for (std::size_t k = 0; k < line.size(); ++k) r.push_back(position(i, line[k], prefix + "[" + std::to_string(k) + "]"));
    out.push_back(std::move(r));
  }
  return out;
}

LonLat GeoJsonFile::point(std::size_t i) const {
  const Json& f = feature(i);
  if (!f.contains("geometry") || !f["geometry"].is_object()) fail(i, "missing geometry");
  const Json& g = f["geometry"];
  if (geometry_type(i) != "Point" || !g.contains("coordinates")) fail(i, "geometry must be a Point");
  return position(i, g["coordinates"], "");
}

}  // namespace floorcast::import_detail
