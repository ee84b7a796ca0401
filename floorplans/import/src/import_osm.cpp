// OpenStreetMap Simple Indoor Tagging (SIT), .osm XML (parsed with pugixml): nodes, ways and
// multipolygon relations become the indoor elements import_indoor() reads (semantics there and in
// floorplans/README.md). A multipolygon's member ways are chained into rings by their end nodes.
// Elements marked action="delete" (JOSM files) or visible="false" are ignored.
#include <pugixml.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>
#include <sstream>

#include "floorcast/core/limits.hpp"
#include "floorcast/floorplans/import.hpp"
#include "import_common.hpp"

namespace floorcast {
namespace {

using import_detail::fmt;
using import_detail::quoted;
using Ranges = std::vector<std::pair<double, double>>;

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

/// Chains ways (node lists) into rings by their end nodes; returns the rings and whether each closed.
std::vector<std::pair<std::vector<long long>, bool>> chain_rings(std::vector<std::vector<long long>> ways) {
  std::vector<std::pair<std::vector<long long>, bool>> out;
  std::vector<bool> used(ways.size(), false);
  for (std::size_t start = 0; start < ways.size(); ++start) {
    if (used[start] || ways[start].size() < 2) continue;
    used[start] = true;
    std::vector<long long> ring = ways[start];
    bool grown = true;
    while (ring.front() != ring.back() && grown) {
      grown = false;
      for (std::size_t k = 0; k < ways.size(); ++k) {
        if (used[k] || ways[k].size() < 2) continue;
        const std::vector<long long>& w = ways[k];
        if (w.front() == ring.back()) {
          ring.insert(ring.end(), w.begin() + 1, w.end());
        } else if (w.back() == ring.back()) {
          ring.insert(ring.end(), w.rbegin() + 1, w.rend());
        } else {
          continue;
        }
        used[k] = true;
        grown = true;
        break;
      }
    }
    const bool closed = ring.size() >= 4 && ring.front() == ring.back();
    out.emplace_back(std::move(ring), closed);
  }
  return out;
}

}  // namespace

ImportResult import_osm_xml(const std::string& xml_text, const std::string& source, const ImportOptions& options) {
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
    // WGS84 unless --crs gives another system (then GeoFrame checks the numbers when a node is used).
    if (!parse_coordinate(e.attribute("lat").as_string(), n.lat) || !parse_coordinate(e.attribute("lon").as_string(), n.lon) ||
        (!options.crs && (std::abs(n.lat) > 90.0 || std::abs(n.lon) > 180.0))) {
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
    check_limit("max_vertices_per_element", static_cast<double>(w.nodes.size()),
                source + ": way " + std::to_string(id), "nodes");
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

  import_detail::IndoorData data;
  auto lonlat = [&](long long nid, const std::string& what) {
    auto it = nodes.find(nid);
    if (it == nodes.end()) {
      throw InputError(source + ": " + what + ": refers to node " + std::to_string(nid) + " which is not in the file");
    }
    return import_detail::LonLat{it->second.lon, it->second.lat};
  };
  auto ring_of = [&](const std::vector<long long>& ids, const std::string& what) {
    import_detail::Ring ring;
    for (long long nid : ids) ring.push_back(lonlat(nid, what));
    return ring;
  };
  auto is_indoor = [](const std::map<std::string, std::string>& tags) {
    const std::string v = tag(tags, "indoor");
    return !v.empty() && v != "yes" && v != "no" && v != "door";
  };
  for (const auto& [id, w] : ways) {
    if (!is_indoor(w.tags)) continue;
    import_detail::IndoorFeature f;
    f.what = source + ": way " + std::to_string(id);
    f.id = "way" + std::to_string(id);
    f.tags = w.tags;
    if (w.nodes.size() < 2) throw InputError(f.what + ": fewer than 2 nodes");
    f.rings.push_back(ring_of(w.nodes, f.what));
    f.inner.push_back(false);
    // indoor=wall is a line; with area=yes a closed way is the wall's footprint (its thickness).
    f.area = tag(w.tags, "indoor") != "wall" || tag(w.tags, "area") == "yes";
    f.unclosed = f.area && (w.nodes.front() != w.nodes.back() || w.nodes.size() < 4);
    data.features.push_back(std::move(f));
  }
  // IndoorOSM (Goetz & Zipf 2011): spaces are ways tagged buildingpart=room|corridor|hall|
  // verticalpassage, grouped per storey by relations type=level (level=N; or the role level_N in a
  // type=building relation) with the level's outline as the member of role "shell". They are read
  // as their Simple Indoor Tagging equivalents: room -> indoor=room, corridor -> indoor=corridor,
  // hall -> indoor=area (kind "hall"), verticalpassage -> indoor=room (stairway: stairs=yes,
  // elevator: indoor=elevator, else kind from buildingpart:verticalpassage), shell -> indoor=level;
  // a way's levels are those of the level relations holding it (plus a verticalpassage's
  // buildingpart:verticalpassage:floorrange), unless it carries level=* itself.
  std::map<long long, std::string> building_role_level;  // level relation id -> N from "level_N"
  for (const auto& [id, r] : relations) {
    if (tag(r.tags, "type") != "building") continue;
    for (const Member& m : r.members) {
      if (m.type == "relation" && m.role.rfind("level_", 0) == 0) building_role_level[m.ref] = m.role.substr(6);
    }
  }
  std::map<long long, std::set<std::string>> way_levels;
  std::set<long long> shells;
  for (const auto& [id, r] : relations) {
    if (tag(r.tags, "type") != "level") continue;
    std::string lv = tag(r.tags, "level");
    if (lv.empty() && building_role_level.count(id)) lv = building_role_level[id];
    if (lv.empty()) continue;
    for (const Member& m : r.members) {
      if (m.type != "way") continue;
      way_levels[m.ref].insert(lv);
      if (m.role == "shell") shells.insert(m.ref);
    }
  }
  int indoorosm_parts = 0;
  for (const auto& [id, w] : ways) {
    const std::string part = tag(w.tags, "buildingpart");
    const bool shell = shells.count(id) > 0 || part == "shell";
    if (is_indoor(w.tags) || (part.empty() && !shell)) continue;
    import_detail::IndoorFeature f;
    f.what = source + ": way " + std::to_string(id) + " (IndoorOSM buildingpart=" + (part.empty() ? "shell" : part) + ")";
    f.id = "way" + std::to_string(id);
    f.tags = w.tags;
    if (shell) {
      f.tags["indoor"] = "level";
    } else if (part == "room") {
      f.tags["indoor"] = "room";
    } else if (part == "corridor") {
      f.tags["indoor"] = "corridor";
    } else if (part == "hall") {
      f.tags["indoor"] = "area";
      f.kind = "hall";
    } else if (part == "verticalpassage") {
      const std::string vp = tag(w.tags, "buildingpart:verticalpassage");
      f.tags["indoor"] = vp == "elevator" ? "elevator" : "room";
      if (vp == "stairway" || vp == "stairs") f.tags["stairs"] = "yes";
      else if (!vp.empty() && vp != "elevator") f.kind = vp;
      else if (vp.empty()) f.kind = "verticalpassage";
    } else {
      continue;  // buildingpart values without a space meaning here
    }
    if (tag(w.tags, "level").empty()) {
      std::string levels;
      for (const std::string& lv : way_levels[id]) levels += (levels.empty() ? "" : ";") + lv;
      std::string range = tag(w.tags, "buildingpart:verticalpassage:floorrange");
      std::replace(range.begin(), range.end(), ' ', ';');
      std::replace(range.begin(), range.end(), ',', ';');
      while (!range.empty() && range.back() == ';') range.pop_back();
      if (!range.empty()) levels += (levels.empty() ? "" : ";") + range;
      if (!levels.empty()) f.tags["level"] = levels;
    }
    if (w.nodes.size() < 2) throw InputError(f.what + ": fewer than 2 nodes");
    f.rings.push_back(ring_of(w.nodes, f.what));
    f.inner.push_back(false);
    f.area = true;
    f.unclosed = w.nodes.front() != w.nodes.back() || w.nodes.size() < 4;
    data.features.push_back(std::move(f));
    ++indoorosm_parts;
  }
  for (const auto& [id, r] : relations) {
    if (!is_indoor(r.tags) || tag(r.tags, "indoor") == "wall" || tag(r.tags, "type") != "multipolygon") continue;
    import_detail::IndoorFeature f;
    f.what = source + ": relation " + std::to_string(id);
    f.id = "relation" + std::to_string(id);
    f.tags = r.tags;
    f.area = true;
    for (const char* role : {"outer", "inner"}) {
      std::vector<std::vector<long long>> member_ways;
      for (const Member& m : r.members) {
        if (m.type != "way") continue;
        const bool inner = m.role == "inner";
        if (inner != (std::string(role) == "inner")) continue;
        auto it = ways.find(m.ref);
        if (it == ways.end()) {
          throw InputError(f.what + ": member way " + std::to_string(m.ref) + " is not in the file");
        }
        member_ways.push_back(it->second.nodes);
      }
      for (auto& [ids, closed] : chain_rings(member_ways)) {
        f.rings.push_back(ring_of(ids, f.what));
        f.inner.push_back(std::string(role) == "inner");
        f.unclosed = f.unclosed || !closed;
      }
    }
    if (f.rings.empty()) continue;
    data.features.push_back(std::move(f));
  }
  for (const auto& [id, n] : nodes) {
    if (n.tags.empty()) continue;
    import_detail::IndoorPoint p;
    p.what = source + ": node " + std::to_string(id);
    p.id = "node" + std::to_string(id);
    p.tags = n.tags;
    p.at = {n.lon, n.lat};
    data.points.push_back(std::move(p));
  }
  data.source_counts = {{"nodes", static_cast<int>(nodes.size())}, {"ways", static_cast<int>(ways.size())}};
  if (indoorosm_parts > 0) data.source_counts.emplace_back("indoorosm_buildingparts", indoorosm_parts);
  std::map<std::string, int> keys;
  for (const auto& [id, w] : ways) {
    for (const auto& [k, v] : w.tags) ++keys[k];
  }
  for (const auto& [id, r] : relations) {
    for (const auto& [k, v] : r.tags) ++keys[k];
  }
  data.frequent_keys.assign(keys.begin(), keys.end());
  std::stable_sort(data.frequent_keys.begin(), data.frequent_keys.end(),
                   [](const auto& a, const auto& b) { return a.second > b.second; });
  return import_detail::import_indoor(data, source, import_detail::stem_of(source), options);
}

}  // namespace floorcast
