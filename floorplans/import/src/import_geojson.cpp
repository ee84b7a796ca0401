// OSM-derived GeoJSON: a FeatureCollection as osmtogeojson (or an indoor map viewer's export, e.g.
// maplibre-gl-indoor) writes OpenStreetMap data. Each feature's OSM tags are its properties
// (flat, or under properties.tags in older osmtogeojson output; numbers and booleans are read as
// their text); Polygon/MultiPolygon features are areas (first ring of each polygon outer, the
// others holes), LineString/MultiLineString features are lines (indoor=wall), Point features are
// nodes (doors, columns). Levels may also be written as ranges "2~2", "-1~4". The indoor
// semantics are import_indoor()'s, exactly as for OSM XML.
#include <algorithm>
#include <cctype>
#include <map>
#include <nlohmann/json.hpp>

#include "floorcast/floorplans/import.hpp"
#include "geojson_reader.hpp"
#include "import_common.hpp"

namespace floorcast {

ImportResult import_geojson_text(const std::string& text, const std::string& source, const ImportOptions& options) {
  using Json = nlohmann::json;
  const import_detail::GeoJsonFile file(text, source, nullptr);
  import_detail::IndoorData data;
  int points = 0, lines = 0, areas = 0, other = 0;
  std::map<std::string, int> keys;
  for (std::size_t i = 0; i < file.size(); ++i) {
    const Json& f = file.feature(i);
    if (!f.contains("properties") || f["properties"].is_null()) {
      ++other;
      continue;
    }
    const Json& props = file.properties(i);
    const Json& tag_source = props.contains("tags") && props["tags"].is_object() ? props["tags"] : props;
    import_detail::Tags tags;
    for (auto it = tag_source.begin(); it != tag_source.end(); ++it) {
      const Json& v = it.value();
      if (v.is_string()) {
        tags[it.key()] = v.get<std::string>();
      } else if (v.is_number() || v.is_boolean()) {
        tags[it.key()] = v.dump();
      }
    }
    for (const auto& [k, v] : tags) ++keys[k];
    // Wall-polygon / door-line exports (CAD, BIM and indoor-map tools) without OSM tags: the
    // element's class under a common key (type, category, class, layer, kind, feature_type).
    if (!tags.count("indoor")) {
      for (const char* key : {"type", "category", "class", "layer", "kind", "feature_type"}) {
        auto it = tags.find(key);
        if (it == tags.end()) continue;
        std::string v = it->second;
        std::transform(v.begin(), v.end(), v.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
        if (v == "wall" || v == "walls") tags["indoor"] = "wall";
        else if (v == "door" || v == "doors" || v == "opening" || v == "entrance") tags["indoor"] = "door";
        else if (v == "window" || v == "windows") tags["indoor"] = "window";
        else continue;
        break;
      }
    }
    const std::string fid = file.id(i);
    const std::string what = file.where(i);
    const std::string short_id = "f" + std::to_string(i) + (fid.empty() ? "" : "-" + fid);
    const std::string type = file.geometry_type(i);
    if (type == "Point") {
      ++points;
      import_detail::IndoorPoint p;
      p.what = what;
      p.id = short_id;
      p.tags = std::move(tags);
      p.at = file.point(i);
      data.points.push_back(std::move(p));
    } else if (type == "LineString" || type == "MultiLineString") {
      ++lines;
      import_detail::IndoorFeature feat;
      feat.what = what;
      feat.id = short_id;
      feat.tags = std::move(tags);
      feat.rings = file.line_strings(i);
      feat.inner.assign(feat.rings.size(), false);
      // A line drawing a space (indoor=room as a LineString) is an area that does not close
      // unless its ends meet.
      const std::string indoor = feat.tags.count("indoor") ? feat.tags.at("indoor") : std::string();
      feat.area = !indoor.empty() && indoor != "wall" && indoor != "door" && indoor != "window";
      for (const import_detail::Ring& r : feat.rings) {
        feat.unclosed = feat.unclosed || r.size() < 4 || !(r.front() == r.back());
      }
      data.features.push_back(std::move(feat));
    } else if (type == "Polygon" || type == "MultiPolygon") {
      ++areas;
      import_detail::IndoorFeature feat;
      feat.what = what;
      feat.id = short_id;
      feat.tags = std::move(tags);
      std::vector<bool> outer;
      feat.rings = file.polygon_rings(i, &outer);
      for (bool o : outer) feat.inner.push_back(!o);
      feat.area = true;
      data.features.push_back(std::move(feat));
    } else {
      ++other;  // null geometry, GeometryCollection: nothing indoor to draw
    }
  }
  data.crs = file.crs();
  data.frequent_keys.assign(keys.begin(), keys.end());
  std::stable_sort(data.frequent_keys.begin(), data.frequent_keys.end(),
                   [](const auto& a, const auto& b) { return a.second > b.second; });
  data.source_counts = {{"features", static_cast<int>(file.size())},
                        {"points", points},
                        {"lines", lines},
                        {"polygons", areas},
                        {"other", other}};
  return import_detail::import_indoor(data, source, import_detail::stem_of(source), options);
}

}  // namespace floorcast
