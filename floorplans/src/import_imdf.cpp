// Indoor Mapping Data Format (OGC Community Standard 20-094, IMDF 1.0). Facts used:
//   every .geojson file is a GeoJSON FeatureCollection; features have "id", "feature_type",
//   "geometry" and "properties"; positions are [longitude, latitude] (WGS84);
//   level: POLYGONAL geometry, properties.ordinal (integer), .name / .short_name (LABELS: language
//   tag -> text), .category;
//   unit: POLYGONAL geometry, properties.category (UNIT-CATEGORY), .level_id;
//   opening: LINE-STRING geometry along a unit boundary, properties.category, .level_id, .door.
// Walls: unit boundaries of the selected level (polygon rings, holes included), shared edges
// merged; a boundary shared only by units of imdf_open_unit_categories is open (no wall).
// Doors: one per opening, centred on its line string, as wide as it is long.
// Projection: local tangent plane about the selected level's centroid.
#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "floorcast/floorplans/import.hpp"
#include "import_common.hpp"

namespace floorcast {
namespace {

using Json = nlohmann::json;
using import_detail::fmt;
using import_detail::quoted;

struct LonLat {
  double lon = 0.0, lat = 0.0;
};
using Ring = std::vector<LonLat>;

class GeoJsonFile {
 public:
  GeoJsonFile(const std::string& text, std::string name, const char* expected_type)
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
  }

  std::size_t size() const { return root_["features"].size(); }
  const Json& feature(std::size_t i) const {
    const Json& f = root_["features"][i];
    if (!f.is_object()) fail(i, "feature must be a JSON object");
    return f;
  }

  std::string id(std::size_t i) const {
    const Json& f = root_["features"][i];
    if (f.is_object() && f.contains("id") && f["id"].is_string()) return f["id"].get<std::string>();
    return {};
  }

  std::string where(std::size_t i) const {
    std::string w = name_ + ": features[" + std::to_string(i) + "]";
    const std::string fid = id(i);
    if (!fid.empty()) w += " (id " + quoted(fid) + ")";
    return w;
  }

  [[noreturn]] void fail(std::size_t i, const std::string& reason) const {
    throw InputError(where(i) + ": " + reason);
  }

  /// Checks feature_type and returns properties (object).
  const Json& properties(std::size_t i) const {
    const Json& f = feature(i);
    if (f.contains("feature_type") && f["feature_type"].is_string() && f["feature_type"] != expected_type_) {
      fail(i, "feature_type is " + quoted(f["feature_type"].get<std::string>()) + ", expected " + quoted(expected_type_));
    }
    if (!f.contains("properties") || !f["properties"].is_object()) fail(i, "missing \"properties\" object");
    return f["properties"];
  }

  std::string string_property(std::size_t i, const char* key, bool required) const {
    const Json& p = properties(i);
    if (!p.contains(key) || p[key].is_null()) {
      if (required) fail(i, std::string("missing properties.") + key);
      return {};
    }
    if (!p[key].is_string()) fail(i, std::string("properties.") + key + " must be a string, got " + p[key].dump());
    return p[key].get<std::string>();
  }

  LonLat position(std::size_t i, const Json& v, const std::string& path) const {
    if (!v.is_array() || v.size() < 2 || !v[0].is_number() || !v[1].is_number()) {
      fail(i, "geometry position " + path + " must be [longitude, latitude], got " + v.dump());
    }
    LonLat p{v[0].get<double>(), v[1].get<double>()};
    if (!std::isfinite(p.lon) || !std::isfinite(p.lat) || std::abs(p.lon) > 180.0 || std::abs(p.lat) > 90.0) {
      fail(i, "geometry position " + path + " is not a WGS84 [longitude, latitude]: " + v.dump());
    }
    return p;
  }

  /// Rings of a Polygon / MultiPolygon geometry (outer rings and holes).
  std::vector<Ring> polygon_rings(std::size_t i, std::vector<bool>* is_outer = nullptr) const {
    const Json& f = feature(i);
    if (!f.contains("geometry") || !f["geometry"].is_object()) fail(i, "missing geometry");
    const Json& g = f["geometry"];
    const std::string type = g.contains("type") && g["type"].is_string() ? g["type"].get<std::string>() : "";
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

  Ring line_string(std::size_t i) const {
    const Json& f = feature(i);
    if (!f.contains("geometry") || !f["geometry"].is_object()) fail(i, "missing geometry");
    const Json& g = f["geometry"];
    if (!g.contains("type") || g["type"] != "LineString") fail(i, "geometry must be a LineString");
    if (!g.contains("coordinates") || !g["coordinates"].is_array() || g["coordinates"].size() < 2) {
      fail(i, "LineString needs at least 2 positions");
    }
    Ring r;
    for (std::size_t k = 0; k < g["coordinates"].size(); ++k) r.push_back(position(i, g["coordinates"][k], "[" + std::to_string(k) + "]"));
    return r;
  }

  const std::string& name() const { return name_; }

 private:
  std::string name_;
  const char* expected_type_;
  Json root_;
};

/// First text of a LABELS object ({"en": "Ground"}), or empty.
std::string label_text(const Json& props, const char* key) {
  if (!props.contains(key) || !props[key].is_object()) return {};
  const Json& labels = props[key];
  if (labels.contains("en") && labels["en"].is_string()) return labels["en"].get<std::string>();
  for (auto it = labels.begin(); it != labels.end(); ++it) {
    if (it.value().is_string()) return it.value().get<std::string>();
  }
  return {};
}

}  // namespace

ImportResult import_imdf_texts(const std::string& level_geojson, const std::string& unit_geojson,
                               const std::string& opening_geojson, const std::string& source,
                               const ImportOptions& options) {
  const double thickness = import_detail::wall_thickness_or(options, 0.10, source);
  const GeoJsonFile levels(level_geojson, source + "/level.geojson", "level");
  const GeoJsonFile units(unit_geojson, source + "/unit.geojson", "unit");

  // Levels.
  struct Level {
    std::size_t index;
    std::string id;
    long long ordinal;
    std::string name;
  };
  std::vector<Level> all_levels;
  for (std::size_t i = 0; i < levels.size(); ++i) {
    const Json& p = levels.properties(i);
    const std::string id = levels.id(i);
    if (id.empty()) levels.fail(i, "missing string \"id\"");
    if (!p.contains("ordinal") || !p["ordinal"].is_number_integer()) levels.fail(i, "properties.ordinal must be an integer");
    Level l{i, id, p["ordinal"].get<long long>(), label_text(p, "name")};
    if (l.name.empty()) l.name = label_text(p, "short_name");
    all_levels.push_back(std::move(l));
  }
  if (all_levels.empty()) throw InputError(levels.name() + ": no levels");
  auto describe = [](const Level& l) {
    std::string s = "ordinal " + std::to_string(l.ordinal) + " (id " + quoted(l.id);
    if (!l.name.empty()) s += ", " + quoted(l.name);
    return s + ")";
  };
  auto list_levels = [&] {
    std::vector<const Level*> sorted;
    for (const Level& l : all_levels) sorted.push_back(&l);
    std::stable_sort(sorted.begin(), sorted.end(), [](const Level* a, const Level* b) { return a->ordinal < b->ordinal; });
    std::string s;
    for (const Level* l : sorted) s += (s.empty() ? "" : "; ") + describe(*l);
    return s;
  };
  const Level* selected = nullptr;
  if (options.level) {
    for (const Level& l : all_levels) {
      if (l.id == *options.level) selected = &l;
    }
    if (!selected) {
      char* end = nullptr;
      const long long ordinal = std::strtoll(options.level->c_str(), &end, 10);
      if (options.level->empty() || *end != '\0') {
        throw InputError(source + ": --level " + quoted(*options.level) +
                         " is neither a level ordinal (integer) nor a level id; available levels: " + list_levels());
      }
      std::vector<const Level*> matches;
      for (const Level& l : all_levels) {
        if (l.ordinal == ordinal) matches.push_back(&l);
      }
      if (matches.empty()) {
        throw InputError(source + ": no level with ordinal " + std::to_string(ordinal) + "; available levels: " + list_levels());
      }
      if (matches.size() > 1) {
        std::string s;
        for (const Level* l : matches) s += (s.empty() ? "" : "; ") + describe(*l);
        throw InputError(source + ": ordinal " + std::to_string(ordinal) + " is ambiguous, " +
                         std::to_string(matches.size()) + " levels have it (" + s + "); pass --level LEVEL_ID");
      }
      selected = matches.front();
    }
  } else if (all_levels.size() == 1) {
    selected = &all_levels.front();
  } else {
    throw InputError(source + ": " + std::to_string(all_levels.size()) +
                     " levels, choose one with --level ORDINAL (or --level LEVEL_ID); available levels: " + list_levels());
  }

  // Projection origin: area centroid of the level's outer rings (planar in degrees; any nearby
  // origin gives the same metric plan up to a translation).
  std::vector<bool> outer;
  const std::vector<Ring> level_rings = levels.polygon_rings(selected->index, &outer);
  // Relative to the first vertex: raw degrees would cancel catastrophically in the cross products.
  const double ref_lon = level_rings.front().front().lon, ref_lat = level_rings.front().front().lat;
  double area = 0.0, cx = 0.0, cy = 0.0, mx = 0.0, my = 0.0;
  int count = 0;
  for (std::size_t r = 0; r < level_rings.size(); ++r) {
    if (!outer[r]) continue;
    const Ring& ring = level_rings[r];
    for (std::size_t k = 0; k + 1 < ring.size(); ++k) {
      const double x0 = ring[k].lon - ref_lon, y0 = ring[k].lat - ref_lat;
      const double x1 = ring[k + 1].lon - ref_lon, y1 = ring[k + 1].lat - ref_lat;
      const double cr = x0 * y1 - x1 * y0;
      area += cr;
      cx += (x0 + x1) * cr;
      cy += (y0 + y1) * cr;
      mx += x0;
      my += y0;
      ++count;
    }
  }
  double lon0 = ref_lon + mx / std::max(count, 1), lat0 = ref_lat + my / std::max(count, 1);
  if (std::abs(area) > 1e-18) {
    lon0 = ref_lon + cx / (3.0 * area);
    lat0 = ref_lat + cy / (3.0 * area);
  }
  const LocalTangentPlane ltp(lat0, lon0);
  auto project = [&](const LonLat& p) { return ltp.to_local_m(p.lat, p.lon); };

  std::set<std::string> open_categories(options.imdf_open_unit_categories.begin(), options.imdf_open_unit_categories.end());
  std::vector<import_detail::BoundaryEdge> edges;
  int unit_count = 0;
  for (std::size_t i = 0; i < units.size(); ++i) {
    const std::string level_id = units.string_property(i, "level_id", true);
    if (level_id != selected->id) continue;
    const std::string category = units.string_property(i, "category", true);
    ++unit_count;
    for (const Ring& ring : units.polygon_rings(i)) {
      for (std::size_t k = 0; k + 1 < ring.size(); ++k) {
        import_detail::BoundaryEdge e;
        e.segment_m = {project(ring[k]), project(ring[k + 1])};
        e.owner = static_cast<int>(i);
        e.walled = true;
        e.open = open_categories.count(category) > 0;
        edges.push_back(e);
      }
    }
  }
  if (unit_count == 0) throw InputError(units.name() + ": no units on level " + describe(*selected));

  const auto pieces = import_detail::classify_boundaries(edges, options.cleanup.snap_tolerance_m, options.cleanup.angle_tolerance_rad);
  ImportResult result;
  FloorPlan plan;
  plan.level = static_cast<int>(std::clamp<long long>(selected->ordinal, -1000000, 1000000));
  import_detail::append_walls(plan, pieces.walls, thickness);

  int opening_count = 0;
  if (!opening_geojson.empty()) {
    const GeoJsonFile openings(opening_geojson, source + "/opening.geojson", "opening");
    const double reach = 0.5 * thickness + options.cleanup.opening_attach_tolerance_m;
    for (std::size_t i = 0; i < openings.size(); ++i) {
      const std::string level_id = openings.string_property(i, "level_id", true);
      if (level_id != selected->id) continue;
      ++opening_count;
      const Ring line = openings.line_string(i);
      const Vec2 a = project(line.front()), b = project(line.back());
      const Vec2 center = 0.5 * (a + b);
      const double d_wall = import_detail::distance_to_segments(center, pieces.walls);
      if (d_wall > reach) {
        const double d_open = import_detail::distance_to_segments(center, pieces.open);
        if (d_open <= reach) {
          result.notes.push_back(openings.where(i) + ": opening on an open boundary (no wall), skipped");
        } else {
          result.notes.push_back(openings.where(i) + ": opening is not on any unit boundary of the level (nearest wall " +
                                 fmt(d_wall) + " m away), skipped");
        }
        continue;
      }
      Door d;
      const std::string fid = openings.id(i);
      d.id = "opening-" + (fid.empty() ? std::to_string(i) : fid);
      d.center_m = center;
      d.width_m = (b - a).norm();
      d.closed = options.doors_closed;
      plan.doors.push_back(std::move(d));
    }
  }

  result.level_description = describe(*selected);
  result.source_counts = {{"levels", static_cast<int>(all_levels.size())},
                          {"units_on_level", unit_count},
                          {"unit_edges", static_cast<int>(edges.size())},
                          {"openings_on_level", opening_count}};
  std::string default_name = import_detail::stem_of(source);
  if (!selected->name.empty()) default_name += " " + selected->name;
  return import_detail::finish_import(std::move(plan), source, default_name, options, std::move(result));
}

}  // namespace floorcast
