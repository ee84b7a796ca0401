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
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "floorcast/core/math.hpp"
#include "floorcast/floorplans/import.hpp"
#include "geojson_reader.hpp"
#include "import_common.hpp"

namespace floorcast {
namespace {

using Json = nlohmann::json;
using import_detail::fmt;
using import_detail::quoted;

using import_detail::GeoJsonFile;
using import_detail::LonLat;
using import_detail::Ring;

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

/// Every text of a LABELS object, label_text()'s first.
std::vector<std::string> label_texts(const Json& props, const char* key) {
  std::vector<std::string> out;
  const std::string first = label_text(props, key);
  if (!first.empty()) out.push_back(first);
  if (!props.contains(key) || !props[key].is_object()) return out;
  for (auto it = props[key].begin(); it != props[key].end(); ++it) {
    if (it.value().is_string() && it.value().get<std::string>() != first) out.push_back(it.value().get<std::string>());
  }
  return out;
}

/// Chains an opening's line strings (a MultiLineString drawn in pieces) into polylines: a piece
/// continues another when their ends meet within `tol_m` (either direction).
std::vector<std::vector<Vec2>> chain_lines(std::vector<std::vector<Vec2>> parts, double tol_m) {
  std::vector<std::vector<Vec2>> out;
  std::vector<bool> used(parts.size(), false);
  for (std::size_t s = 0; s < parts.size(); ++s) {
    if (used[s]) continue;
    used[s] = true;
    std::vector<Vec2> line = parts[s];
    for (bool grown = true; grown;) {
      grown = false;
      for (std::size_t k = 0; k < parts.size(); ++k) {
        if (used[k]) continue;
        std::vector<Vec2>& p = parts[k];
        if ((p.front() - line.back()).norm() <= tol_m) {
          line.insert(line.end(), p.begin() + 1, p.end());
        } else if ((p.back() - line.back()).norm() <= tol_m) {
          line.insert(line.end(), p.rbegin() + 1, p.rend());
        } else if ((p.back() - line.front()).norm() <= tol_m) {
          line.insert(line.begin(), p.begin(), p.end() - 1);
        } else if ((p.front() - line.front()).norm() <= tol_m) {
          line.insert(line.begin(), p.rbegin(), p.rend() - 1);
        } else {
          continue;
        }
        used[k] = true;
        grown = true;
      }
    }
    out.push_back(std::move(line));
  }
  return out;
}

}  // namespace

ImportResult import_imdf_texts(const std::string& level_geojson, const std::string& unit_geojson,
                               const std::string& opening_geojson, const std::string& source,
                               const ImportOptions& options) {
  return import_imdf_texts(level_geojson, unit_geojson, opening_geojson, std::string(), source, options);
}

ImportResult import_imdf_texts(const std::string& level_geojson, const std::string& unit_geojson,
                               const std::string& opening_geojson, const std::string& building_geojson,
                               const std::string& source, const ImportOptions& options) {
  const double thickness = import_detail::wall_thickness_or(options, 0.10, source);
  const GeoJsonFile levels(level_geojson, source + "/level.geojson", "level");
  const GeoJsonFile units(unit_geojson, source + "/unit.geojson", "unit");

  // Levels.
  // Buildings (optional file): id -> names, for --building and for messages.
  struct Building {
    std::string id;
    std::vector<std::string> names;
  };
  std::vector<Building> buildings;
  if (!building_geojson.empty()) {
    const GeoJsonFile bf(building_geojson, source + "/building.geojson", "building");
    for (std::size_t i = 0; i < bf.size(); ++i) {
      Building b{bf.id(i), label_texts(bf.properties(i), "name")};
      if (!b.id.empty()) buildings.push_back(std::move(b));
    }
  }
  auto building_name = [&](const std::string& id) {
    for (const Building& b : buildings) {
      if (b.id == id && !b.names.empty()) return b.names.front();  // English when there is one
    }
    return id;
  };

  struct Level {
    std::size_t index;
    std::string id;
    long long ordinal;
    std::string name;
    std::vector<std::string> building_ids;
  };
  std::vector<Level> all_levels;
  for (std::size_t i = 0; i < levels.size(); ++i) {
    const Json& p = levels.properties(i);
    const std::string id = levels.id(i);
    if (id.empty()) levels.fail(i, "missing string \"id\"");
    if (!p.contains("ordinal") || !p["ordinal"].is_number_integer()) levels.fail(i, "properties.ordinal must be an integer");
    Level l{i, id, p["ordinal"].get<long long>(), label_text(p, "name"), {}};
    if (l.name.empty()) l.name = label_text(p, "short_name");
    if (p.contains("building_ids") && p["building_ids"].is_array()) {
      for (const Json& b : p["building_ids"]) {
        if (b.is_string()) l.building_ids.push_back(b.get<std::string>());
      }
    }
    all_levels.push_back(std::move(l));
  }
  if (all_levels.empty()) throw InputError(levels.name() + ": no levels");
  auto describe = [&](const Level& l) {
    std::string s = "ordinal " + std::to_string(l.ordinal) + " (id " + quoted(l.id);
    if (!l.name.empty()) s += ", " + quoted(l.name);
    for (const std::string& b : l.building_ids) s += ", building " + quoted(building_name(b));
    return s + ")";
  };
  auto list_levels = [&](const std::vector<const Level*>& among) {
    std::vector<const Level*> sorted = among;
    std::stable_sort(sorted.begin(), sorted.end(), [](const Level* a, const Level* b) { return a->ordinal < b->ordinal; });
    std::string s;
    for (const Level* l : sorted) s += (s.empty() ? "" : "; ") + describe(*l);
    return s;
  };
  // Levels of the chosen building (--building: its id or any of its names), else all.
  std::vector<const Level*> candidates;
  std::string building_id;
  if (options.building) {
    const std::string& want = *options.building;
    std::set<std::string> ids;
    for (const Building& b : buildings) {
      if (b.id == want || std::find(b.names.begin(), b.names.end(), want) != b.names.end()) ids.insert(b.id);
    }
    for (const Level& l : all_levels) {
      for (const std::string& b : l.building_ids) {
        if (b == want) ids.insert(b);
      }
    }
    if (ids.empty()) {
      std::set<std::string> known;
      for (const Level& l : all_levels) {
        for (const std::string& b : l.building_ids) known.insert(quoted(building_name(b)) + " (id " + quoted(b) + ")");
      }
      std::string list;
      for (const std::string& k : known) list += (list.empty() ? "" : "; ") + k;
      throw InputError(source + ": --building " + quoted(want) + " names no building with levels" +
                       (building_geojson.empty() ? " (no building.geojson: give a building id)" : "") +
                       "; buildings: " + (list.empty() ? "none (levels carry no building_ids)" : list));
    }
    if (ids.size() > 1) {
      throw InputError(source + ": --building " + quoted(want) + " names " + std::to_string(ids.size()) +
                       " buildings; give its id");
    }
    building_id = *ids.begin();
    for (const Level& l : all_levels) {
      if (std::find(l.building_ids.begin(), l.building_ids.end(), building_id) != l.building_ids.end()) candidates.push_back(&l);
    }
  } else {
    for (const Level& l : all_levels) candidates.push_back(&l);
  }
  const Level* selected = nullptr;
  if (options.level) {
    for (const Level* l : candidates) {
      if (l->id == *options.level) selected = l;
    }
    if (!selected) {
      char* end = nullptr;
      const long long ordinal = std::strtoll(options.level->c_str(), &end, 10);
      if (options.level->empty() || *end != '\0') {
        throw InputError(source + ": --level " + quoted(*options.level) +
                         " is neither a level ordinal (integer) nor a level id; available levels: " + list_levels(candidates));
      }
      std::vector<const Level*> matches;
      for (const Level* l : candidates) {
        if (l->ordinal == ordinal) matches.push_back(l);
      }
      if (matches.empty()) {
        throw InputError(source + ": no level with ordinal " + std::to_string(ordinal) +
                         (options.building ? " in building " + quoted(*options.building) : std::string()) +
                         "; available levels: " + list_levels(candidates));
      }
      if (matches.size() > 1) {
        throw InputError(source + ": ordinal " + std::to_string(ordinal) + " is ambiguous, " +
                         std::to_string(matches.size()) + " levels have it (" + list_levels(matches) +
                         "); pass --building NAME_OR_ID or --level LEVEL_ID");
      }
      selected = matches.front();
    }
  } else if (candidates.size() == 1) {
    selected = candidates.front();
  } else {
    throw InputError(source + ": " + std::to_string(candidates.size()) +
                     " levels, choose one with --level ORDINAL (with --building when buildings share ordinals) or "
                     "--level LEVEL_ID; available levels: " + list_levels(candidates));
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
  // Coordinates: --crs, else the CRS level.geojson declares, else WGS84 (IMDF's own); the local
  // plane about the level's centroid.
  ImportResult result;
  GeoFrame frame(options.crs.value_or(levels.crs()), source);
  if (options.crs && !levels.crs().empty() && *options.crs != levels.crs()) {
    result.notes.push_back(levels.name() + " declares the coordinate reference system " + quoted(levels.crs()) + "; --crs " +
                           quoted(*options.crs) + " used instead");
  }
  frame.set_origin_deg(frame.to_geographic_deg({lon0, lat0}, levels.where(selected->index) + " (centroid)"));
  const std::string* where = &source;
  auto project = [&](const LonLat& p) { return frame.to_local_m(frame.to_geographic_deg({p.lon, p.lat}, *where)); };

  std::set<std::string> open_categories(options.imdf_open_unit_categories.begin(), options.imdf_open_unit_categories.end());
  std::set<std::string> void_categories(options.imdf_void_unit_categories.begin(), options.imdf_void_unit_categories.end());
  int void_units = 0;
  std::vector<import_detail::BoundaryEdge> edges;
  int unit_count = 0;
  std::vector<Room> rooms;
  for (std::size_t i = 0; i < units.size(); ++i) {
    const std::string level_id = units.string_property(i, "level_id", true);
    if (level_id != selected->id) continue;
    const std::string category = units.string_property(i, "category", true);
    ++unit_count;
    std::vector<bool> outer;
    const std::vector<Ring> rings = units.polygon_rings(i, &outer);
    const std::string fid = units.id(i);
    const std::string unit_where = units.where(i);
    where = &unit_where;
    const bool no_space = void_categories.count(category) > 0;
    void_units += no_space ? 1 : 0;
    for (std::size_t r = 0; r < rings.size(); ++r) {
      const Ring& ring = rings[r];
      for (std::size_t k = 0; k + 1 < ring.size(); ++k) {
        import_detail::BoundaryEdge e;
        e.segment_m = {project(ring[k]), project(ring[k + 1])};
        e.owner = static_cast<int>(i);
        e.walled = true;
        e.open = open_categories.count(category) > 0;
        edges.push_back(e);
      }
      // The unit as a room label (its category is the kind); holes go to the polygon before them.
      std::vector<Vec2> poly;
      for (std::size_t k = 0; k + 1 < ring.size(); ++k) poly.push_back(project(ring[k]));
      if (no_space) {
        continue;  // a void or building mass: walls around it, no room label (not floor)
      } else if (outer[r]) {
        Room room;
        room.id = "unit-" + (fid.empty() ? std::to_string(i) : fid);
        int n = 2;
        for (const Room& other : rooms) n += other.id.rfind(room.id, 0) == 0 ? 1 : 0;
        if (n > 2) room.id += "-" + std::to_string(n - 1);
        room.kind = category;
        room.polygon_m = std::move(poly);
        rooms.push_back(std::move(room));
      } else if (!rooms.empty()) {
        rooms.back().holes_m.push_back(std::move(poly));
      }
    }
  }
  if (unit_count == 0) throw InputError(units.name() + ": no units on level " + describe(*selected));

  const auto pieces = import_detail::classify_boundaries(edges, options.cleanup.snap_tolerance_m, options.cleanup.angle_tolerance_rad);
  FloorPlan plan;
  plan.level = static_cast<int>(std::clamp<long long>(selected->ordinal, -1000000, 1000000));
  import_detail::append_walls(plan, pieces.walls, thickness);
  plan.rooms = std::move(rooms);

  int opening_count = 0;
  if (!opening_geojson.empty()) {
    const GeoJsonFile openings(opening_geojson, source + "/opening.geojson", "opening");
    const double reach = 0.5 * thickness + options.cleanup.opening_attach_tolerance_m;
    for (std::size_t i = 0; i < openings.size(); ++i) {
      const std::string level_id = openings.string_property(i, "level_id", true);
      if (level_id != selected->id) continue;
      ++opening_count;
      // A LineString, or a MultiLineString whose pieces are chained where their ends meet; each
      // resulting polyline is one opening from its first to its last point.
      std::vector<std::vector<Vec2>> parts;
      const std::string opening_where = openings.where(i);
      where = &opening_where;
      for (const Ring& line : openings.line_strings(i)) {
        std::vector<Vec2> part;
        for (const LonLat& q : line) part.push_back(project(q));
        parts.push_back(std::move(part));
      }
      const bool multi = parts.size() > 1;
      const std::vector<std::vector<Vec2>> lines = chain_lines(std::move(parts), options.cleanup.snap_tolerance_m);
      if (multi) import_detail::count_repair(result, "multilinestring_openings_joined");
      for (std::size_t li = 0; li < lines.size(); ++li) {
        const Vec2 a = lines[li].front(), b = lines[li].back();
        const Vec2 center = 0.5 * (a + b);
        const std::string label = openings.where(i) + (lines.size() > 1 ? " line " + std::to_string(li) : std::string());
        if ((b - a).norm() < 0.05) {
          result.notes.push_back(label + ": opening shorter than 5 cm, skipped");
          import_detail::count_repair(result, "degenerate_openings_skipped");
          continue;
        }
        const double d_wall = import_detail::distance_to_segments(center, pieces.walls);
        if (d_wall > reach) {
          const double d_open = import_detail::distance_to_segments(center, pieces.open);
          if (d_open <= reach) {
            result.notes.push_back(label + ": opening on an open boundary (no wall), skipped");
          } else {
            result.notes.push_back(label + ": opening is not on any unit boundary of the level (nearest wall " +
                                   fmt(d_wall) + " m away), skipped");
          }
          continue;
        }
        Door d;
        const std::string fid = openings.id(i);
        d.id = "opening-" + (fid.empty() ? std::to_string(i) : fid) + (lines.size() > 1 ? "-" + std::to_string(li + 1) : "");
        d.center_m = center;
        d.width_m = (b - a).norm();
        d.closed = options.doors_closed;
        // The wall it is drawn along: the nearest wall within reach running in the opening's
        // direction (within 10 degrees), so that an opening near a corner goes into its own wall,
        // not across the perpendicular one. None found: clean-up places it on the nearest wall.
        const Vec2 u = (b - a) / (b - a).norm();
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t w = 0; w < pieces.walls.size(); ++w) {
          const Segment2& s = pieces.walls[w];
          const double len = s.length_m();
          if (len <= 0.0) continue;
          const Vec2 v = (s.b_m - s.a_m) / len;
          if (std::abs(u.x() * v.y() - u.y() * v.x()) > std::sin(10.0 * kPi / 180.0)) continue;
          const Vec2 r = center - s.a_m;
          const double along = r.dot(v), across = std::abs(v.x() * r.y() - v.y() * r.x());
          if (across > reach || along < -0.5 * d.width_m || along > len + 0.5 * d.width_m) continue;
          if (across < best) {
            best = across;
            d.wall_id = plan.walls[w].id;
          }
        }
        plan.doors.push_back(std::move(d));
      }
    }
  }

  const import_detail::OpeningsReport inferred =
      import_detail::check_openings(plan, pieces.walls, options.infer_openings, options.default_door_width_m,
                                    0.5 * thickness + options.cleanup.opening_attach_tolerance_m, result.notes);
  import_detail::count_repair(result, "openings_inferred", inferred.inferred);
  for (const Level& l : all_levels) {
    bool any = false;
    for (std::size_t i = 0; i < units.size() && !any; ++i) any = units.string_property(i, "level_id", true) == l.id;
    if (!any) result.faithfulness.levels_without_spaces.push_back(describe(l) + " (no units)");
  }

  result.level_description = describe(*selected);
  if (!frame.geographic() || !options.crs.value_or(levels.crs()).empty()) result.level_description += ", " + frame.description();
  result.source_counts = {{"levels", static_cast<int>(all_levels.size())},
                          {"units_on_level", unit_count},
                          {"unit_edges", static_cast<int>(edges.size())},
                          {"openings_on_level", opening_count},
                          {"void_or_structure_units", void_units}};
  std::string default_name = import_detail::stem_of(source);
  if (!selected->name.empty()) default_name += " " + selected->name;
  return import_detail::finish_import(std::move(plan), source, default_name, options, std::move(result), nullptr, true);
}

}  // namespace floorcast
