// OpenStreetMap Simple Indoor Tagging (SIT), .osm XML (parsed with pugixml). SIT semantics used:
//   indoor=room      a space enclosed by walls: its outline is a wall;
//   indoor=corridor  a room made for walking: its outline is a wall, except where it borders
//                    another corridor or an indoor=area (corridors are split into pieces for
//                    naming and routing, and open onto halls mapped as areas);
//   indoor=area      a space without walls: its outline is not a wall;
//   indoor=wall      a wall not already given by a room's outline (open or closed way);
//   indoor=column    a structural column: its outline is a wall (blocks sight);
//   door=* (any value, including door=no, an opening without a leaf) and indoor=door nodes:
//                    a door on the wall segment the node lies on;
//   level=* / repeat_on=*: "0", "-1", "1;2", "0-2", "-3--1", "0.5"; a feature is on every level
//                    listed or inside a listed range. A feature without level=* is on level 0.
//   Spaces may be closed ways or type=multipolygon relations (outer and inner member ways).
// Elements marked action="delete" (JOSM files) or visible="false" are ignored.
// Projection: local tangent plane about the mean of the selected features' nodes.
#include <pugixml.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>
#include <sstream>

#include "floorcast/floorplans/import.hpp"
#include "import_common.hpp"

namespace floorcast {
namespace {

using import_detail::fmt;
using import_detail::quoted;
using Ranges = std::vector<std::pair<double, double>>;

enum class Kind { kNone, kRoom, kCorridor, kArea, kWall, kColumn };

Kind kind_of(const std::string& indoor) {
  if (indoor == "room") return Kind::kRoom;
  if (indoor == "corridor") return Kind::kCorridor;
  if (indoor == "area") return Kind::kArea;
  if (indoor == "wall") return Kind::kWall;
  if (indoor == "column") return Kind::kColumn;
  return Kind::kNone;
}

const char* kind_name(Kind k) {
  switch (k) {
    case Kind::kRoom: return "room";
    case Kind::kCorridor: return "corridor";
    case Kind::kArea: return "area";
    case Kind::kWall: return "wall";
    case Kind::kColumn: return "column";
    case Kind::kNone: break;
  }
  return "none";
}

struct Node {
  double lat = 0.0, lon = 0.0;
  std::map<std::string, std::string> tags;
};
struct Way {
  std::vector<long long> nodes;
  std::map<std::string, std::string> tags;
};
struct Member {
  std::string type, role;
  long long ref = 0;
};
struct Relation {
  std::vector<Member> members;
  std::map<std::string, std::string> tags;
};

bool skipped(const pugi::xml_node& e) {
  const std::string action = e.attribute("action").as_string();
  const std::string visible = e.attribute("visible").as_string("true");
  return action == "delete" || visible == "false";
}

std::map<std::string, std::string> read_tags(const pugi::xml_node& e) {
  std::map<std::string, std::string> tags;
  for (pugi::xml_node t : e.children("tag")) tags[t.attribute("k").as_string()] = t.attribute("v").as_string();
  return tags;
}

std::string tag(const std::map<std::string, std::string>& tags, const std::string& key) {
  auto it = tags.find(key);
  return it == tags.end() ? std::string() : it->second;
}

bool parse_id(const char* text, long long& out) {
  if (!text || !*text) return false;
  char* end = nullptr;
  out = std::strtoll(text, &end, 10);
  return *end == '\0';
}

bool parse_coordinate(const char* text, double& out) {
  if (!text || !*text) return false;
  char* end = nullptr;
  out = std::strtod(text, &end);
  return *end == '\0' && std::isfinite(out);
}

/// "0.9", "0.9 m", "0.9m", "90 cm" -> metres.
bool parse_width(const std::string& text, double& out) {
  std::string t = text;
  while (!t.empty() && std::isspace(static_cast<unsigned char>(t.back()))) t.pop_back();
  double scale = 1.0;
  if (t.size() > 2 && t.compare(t.size() - 2, 2, "cm") == 0) {
    scale = 0.01;
    t.resize(t.size() - 2);
  } else if (t.size() > 1 && t.back() == 'm') {
    t.pop_back();
  }
  while (!t.empty() && std::isspace(static_cast<unsigned char>(t.back()))) t.pop_back();
  if (t.empty()) return false;
  char* end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  if (*end != '\0' || !std::isfinite(v) || v <= 0.0) return false;
  out = v * scale;
  return true;
}

bool on_level(const Ranges& ranges, double level) {
  for (const auto& [lo, hi] : ranges) {
    if (level >= lo - 1e-9 && level <= hi + 1e-9) return true;
  }
  return false;
}

}  // namespace

ImportResult import_osm_xml(const std::string& xml_text, const std::string& source, const ImportOptions& options) {
  const double thickness = import_detail::wall_thickness_or(options, 0.10, source);
  pugi::xml_document doc;
  const pugi::xml_parse_result parsed = doc.load_buffer(xml_text.data(), xml_text.size());
  if (!parsed) {
    throw InputError(source + ": malformed XML: " + parsed.description() + " at byte " + std::to_string(parsed.offset));
  }
  const pugi::xml_node osm = doc.child("osm");
  if (!osm) throw InputError(source + ": not an OSM XML file (no <osm> root element)");

  std::map<long long, Node> nodes;
  std::map<long long, Way> ways;
  std::map<long long, Relation> relations;
  for (pugi::xml_node e : osm.children("node")) {
    if (skipped(e)) continue;
    long long id = 0;
    if (!parse_id(e.attribute("id").as_string(), id)) {
      throw InputError(source + ": <node> at byte " + std::to_string(e.offset_debug()) + ": missing or invalid id");
    }
    Node n;
    if (!parse_coordinate(e.attribute("lat").as_string(), n.lat) || !parse_coordinate(e.attribute("lon").as_string(), n.lon) ||
        std::abs(n.lat) > 90.0 || std::abs(n.lon) > 180.0) {
      throw InputError(source + ": node " + std::to_string(id) + ": missing or invalid lat/lon (lat " +
                       quoted(e.attribute("lat").as_string()) + ", lon " + quoted(e.attribute("lon").as_string()) + ")");
    }
    n.tags = read_tags(e);
    nodes[id] = std::move(n);
  }
  for (pugi::xml_node e : osm.children("way")) {
    if (skipped(e)) continue;
    long long id = 0;
    if (!parse_id(e.attribute("id").as_string(), id)) {
      throw InputError(source + ": <way> at byte " + std::to_string(e.offset_debug()) + ": missing or invalid id");
    }
    Way w;
    for (pugi::xml_node nd : e.children("nd")) {
      long long ref = 0;
      if (!parse_id(nd.attribute("ref").as_string(), ref)) {
        throw InputError(source + ": way " + std::to_string(id) + ": <nd> with missing or invalid ref");
      }
      w.nodes.push_back(ref);
    }
    w.tags = read_tags(e);
    ways[id] = std::move(w);
  }
  for (pugi::xml_node e : osm.children("relation")) {
    if (skipped(e)) continue;
    long long id = 0;
    if (!parse_id(e.attribute("id").as_string(), id)) {
      throw InputError(source + ": <relation> at byte " + std::to_string(e.offset_debug()) + ": missing or invalid id");
    }
    Relation r;
    for (pugi::xml_node m : e.children("member")) {
      Member mem;
      mem.type = m.attribute("type").as_string();
      mem.role = m.attribute("role").as_string();
      if (!parse_id(m.attribute("ref").as_string(), mem.ref)) {
        throw InputError(source + ": relation " + std::to_string(id) + ": <member> with missing or invalid ref");
      }
      r.members.push_back(mem);
    }
    r.tags = read_tags(e);
    relations[id] = std::move(r);
  }

  // Levels of a tagged element: level=* plus repeat_on=*; none -> level 0.
  auto levels_of = [&](const std::map<std::string, std::string>& tags, const std::string& what, bool& has_level) {
    Ranges all;
    has_level = false;
    for (const char* key : {"level", "repeat_on"}) {
      const std::string v = tag(tags, key);
      if (v.empty()) continue;
      Ranges r;
      if (!parse_osm_levels(v, r)) {
        throw InputError(source + ": " + what + ": " + key + "=" + quoted(v) +
                         " is not a level value (expected e.g. 0, -1, 1;2, 0-2, -3--1, 0.5)");
      }
      all.insert(all.end(), r.begin(), r.end());
      has_level = true;
    }
    if (all.empty()) all.emplace_back(0.0, 0.0);
    return all;
  };

  // Indoor features: ways and multipolygon relations.
  struct Feature {
    std::string what;   // "way 12" / "relation 7"
    Kind kind = Kind::kNone;
    Ranges levels;
    std::vector<long long> way_ids;  // the ways whose edges it draws
  };
  std::vector<Feature> features;
  for (const auto& [id, w] : ways) {
    const Kind k = kind_of(tag(w.tags, "indoor"));
    if (k == Kind::kNone) continue;
    Feature f;
    f.what = "way " + std::to_string(id);
    f.kind = k;
    bool has = false;
    f.levels = levels_of(w.tags, f.what, has);
    f.way_ids = {id};
    features.push_back(std::move(f));
  }
  for (const auto& [id, r] : relations) {
    const Kind k = kind_of(tag(r.tags, "indoor"));
    if (k == Kind::kNone || k == Kind::kWall || tag(r.tags, "type") != "multipolygon") continue;
    Feature f;
    f.what = "relation " + std::to_string(id);
    f.kind = k;
    bool has = false;
    f.levels = levels_of(r.tags, f.what, has);
    for (const Member& m : r.members) {
      if (m.type != "way") continue;
      if (!ways.count(m.ref)) {
        throw InputError(source + ": " + f.what + ": member way " + std::to_string(m.ref) + " is not in the file");
      }
      // A member way without its own level inherits the relation's.
      f.way_ids.push_back(m.ref);
    }
    features.push_back(std::move(f));
  }
  if (features.empty()) {
    throw InputError(source + ": no Simple Indoor Tagging features (ways or multipolygons with indoor=room, corridor, "
                              "area, wall or column)");
  }

  // Level selection.
  std::set<double> available;
  for (const Feature& f : features) {
    for (const auto& [lo, hi] : f.levels) {
      available.insert(lo);
      available.insert(hi);
      for (double v = std::ceil(lo); v <= hi; v += 1.0) available.insert(v);
    }
  }
  auto list_levels = [&] {
    std::string s;
    for (double v : available) s += (s.empty() ? "" : ", ") + fmt(v);
    return s;
  };
  double level = 0.0;
  if (options.level) {
    Ranges r;
    if (!parse_osm_levels(*options.level, r) || r.size() != 1 || r[0].first != r[0].second) {
      throw InputError(source + ": --level " + quoted(*options.level) + " must be one level value such as 0, -1 or 0.5");
    }
    level = r[0].first;
    bool any = false;
    for (const Feature& f : features) any = any || on_level(f.levels, level);
    if (!any) throw InputError(source + ": no indoor features on level " + fmt(level) + "; available levels: " + list_levels());
  } else if (available.size() == 1) {
    level = *available.begin();
  } else {
    throw InputError(source + ": indoor features on " + std::to_string(available.size()) +
                     " levels, choose one with --level; available levels: " + list_levels());
  }

  // Selected features and the nodes they use.
  std::vector<const Feature*> selected;
  std::set<long long> used_nodes;
  for (const Feature& f : features) {
    if (!on_level(f.levels, level)) continue;
    selected.push_back(&f);
    for (long long wid : f.way_ids) {
      const Way& w = ways.at(wid);
      if (w.nodes.size() < 2) throw InputError(source + ": way " + std::to_string(wid) + ": fewer than 2 nodes");
      if ((f.kind == Kind::kRoom || f.kind == Kind::kCorridor || f.kind == Kind::kArea || f.kind == Kind::kColumn) &&
          f.what.rfind("way", 0) == 0 && w.nodes.front() != w.nodes.back()) {
        throw InputError(source + ": way " + std::to_string(wid) + ": indoor=" + kind_name(f.kind) +
                         " must be a closed way (first node = last node)");
      }
      for (long long nid : w.nodes) {
        if (!nodes.count(nid)) {
          throw InputError(source + ": way " + std::to_string(wid) + ": refers to node " + std::to_string(nid) +
                           " which is not in the file");
        }
        used_nodes.insert(nid);
      }
    }
  }
  // Door nodes on this level: a door=* / indoor=door node with a matching level, or without a
  // level of its own on a selected way.
  std::vector<long long> door_nodes;
  for (const auto& [nid, n] : nodes) {
    const bool is_door = n.tags.count("door") > 0 || tag(n.tags, "indoor") == "door";
    if (!is_door) continue;
    bool has_level = false;
    const Ranges lv = levels_of(n.tags, "node " + std::to_string(nid), has_level);
    if (has_level ? on_level(lv, level) : used_nodes.count(nid) > 0) door_nodes.push_back(nid);
  }

  double lat0 = 0.0, lon0 = 0.0;
  for (long long nid : used_nodes) {
    lat0 += nodes.at(nid).lat;
    lon0 += nodes.at(nid).lon;
  }
  lat0 /= static_cast<double>(std::max<std::size_t>(used_nodes.size(), 1));
  lon0 /= static_cast<double>(std::max<std::size_t>(used_nodes.size(), 1));
  const LocalTangentPlane ltp(lat0, lon0);
  auto project = [&](long long nid) {
    const Node& n = nodes.at(nid);
    return ltp.to_local_m(n.lat, n.lon);
  };

  std::vector<import_detail::BoundaryEdge> edges;
  std::map<Kind, int> kind_counts;
  for (std::size_t fi = 0; fi < selected.size(); ++fi) {
    const Feature& f = *selected[fi];
    ++kind_counts[f.kind];
    for (long long wid : f.way_ids) {
      const Way& w = ways.at(wid);
      for (std::size_t k = 0; k + 1 < w.nodes.size(); ++k) {
        import_detail::BoundaryEdge e;
        e.segment_m = {project(w.nodes[k]), project(w.nodes[k + 1])};
        e.owner = static_cast<int>(fi);
        e.walled = f.kind != Kind::kArea;
        e.open = f.kind == Kind::kCorridor || f.kind == Kind::kArea;
        edges.push_back(e);
      }
    }
  }
  const auto pieces = import_detail::classify_boundaries(edges, options.cleanup.snap_tolerance_m, options.cleanup.angle_tolerance_rad);

  ImportResult result;
  FloorPlan plan;
  plan.level = static_cast<int>(std::floor(level));
  if (static_cast<double>(plan.level) != level) {
    result.notes.push_back("level " + fmt(level) + " is not an integer; the plan's level is " + std::to_string(plan.level));
  }
  import_detail::append_walls(plan, pieces.walls, thickness);
  const double reach = 0.5 * thickness + options.cleanup.opening_attach_tolerance_m;
  for (long long nid : door_nodes) {
    const Vec2 p = project(nid);
    const std::string what = "node " + std::to_string(nid);
    const double d_wall = import_detail::distance_to_segments(p, pieces.walls);
    if (d_wall > reach) {
      if (import_detail::distance_to_segments(p, pieces.open) <= reach) {
        result.notes.push_back(what + ": door on an open boundary (corridor/area outline, no wall), skipped");
      } else {
        result.notes.push_back(what + ": door is not on any wall of level " + fmt(level) + " (nearest wall " +
                               fmt(d_wall) + " m away), skipped");
      }
      continue;
    }
    Door d;
    d.id = "node" + std::to_string(nid);
    d.center_m = p;
    d.width_m = options.default_door_width_m;
    const std::string width = tag(nodes.at(nid).tags, "width");
    if (!width.empty()) {
      double wv = 0.0;
      if (parse_width(width, wv)) {
        d.width_m = wv;
      } else {
        result.notes.push_back(what + ": width=" + quoted(width) + " is not a length, door width " +
                               fmt(options.default_door_width_m) + " m used");
      }
    }
    d.closed = options.doors_closed;
    plan.doors.push_back(std::move(d));
  }

  result.level_description = "level " + fmt(level);
  result.source_counts = {{"nodes", static_cast<int>(nodes.size())},
                          {"ways", static_cast<int>(ways.size())},
                          {"rooms", kind_counts[Kind::kRoom]},
                          {"corridors", kind_counts[Kind::kCorridor]},
                          {"areas", kind_counts[Kind::kArea]},
                          {"walls", kind_counts[Kind::kWall]},
                          {"columns", kind_counts[Kind::kColumn]},
                          {"doors", static_cast<int>(door_nodes.size())}};
  return import_detail::finish_import(std::move(plan), source, import_detail::stem_of(source) + " level " + fmt(level),
                                      options, std::move(result));
}

}  // namespace floorcast
