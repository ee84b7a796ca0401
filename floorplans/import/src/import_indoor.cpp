// One level of OSM Simple Indoor Tagging (SIT) data, shared by the OSM XML and the OSM-derived
// GeoJSON importers. SIT semantics used (floorplans/README.md, "OSM Simple Indoor Tagging"):
//   indoor=room      a space enclosed by walls: its outline is a wall;
//   indoor=corridor  a room made for walking: its outline is a wall, except where it borders
//                    another corridor or an indoor=area;
//   indoor=area      a space without walls: its outline is not a wall;
//   indoor=wall      a wall (open or closed way); material=glass makes it a glass wall;
//   indoor=column    a structural column: a closed outline is a wall; a node is a square pillar;
//   indoor=elevator  a lift car/shaft: walled like a room;
//   indoor=level     the level's outline (maplibre-gl-indoor exports): the building envelope, a
//                    wall; the part no room, corridor or area covers is circulation space;
//   wall=no          on any space: its outline draws no wall;
//   door=* / indoor=door / entrance=* points: a door on the wall the point lies on;
//   level=* / repeat_on=*: "0", "-1", "1;2", "0-2", "-3--1", "0.5", "2~4".
// Rooms: every closed space becomes a room label (FloorPlan::rooms) with a kind for sampling:
// corridor, area, elevator, circulation (level outline), stairs (stairs=yes), or the room=* value
// (shop, toilets, office, ...), else shop / amenity values, else "room".
#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <set>

#include <opencv2/imgproc.hpp>

#include "floorcast/core/limits.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/floorplans/import.hpp"
#include "floorcast/floorplans/rooms.hpp"
#include "import_common.hpp"

namespace floorcast::import_detail {
namespace {

using Ranges = std::vector<std::pair<double, double>>;

enum class Kind { kNone, kRoom, kCorridor, kArea, kWall, kColumn, kElevator, kLevel, kDoor, kWindow };

Kind kind_of(const std::string& indoor) {
  if (indoor == "room") return Kind::kRoom;
  if (indoor == "corridor") return Kind::kCorridor;
  if (indoor == "area") return Kind::kArea;
  if (indoor == "wall") return Kind::kWall;
  if (indoor == "column") return Kind::kColumn;
  if (indoor == "elevator") return Kind::kElevator;
  if (indoor == "level") return Kind::kLevel;
  if (indoor == "door") return Kind::kDoor;      // a door drawn as a line or polygon (GeoJSON)
  if (indoor == "window") return Kind::kWindow;  // likewise
  return Kind::kNone;
}

const char* kind_name(Kind k) {
  switch (k) {
    case Kind::kRoom: return "room";
    case Kind::kCorridor: return "corridor";
    case Kind::kArea: return "area";
    case Kind::kWall: return "wall";
    case Kind::kColumn: return "column";
    case Kind::kElevator: return "elevator";
    case Kind::kLevel: return "level";
    case Kind::kDoor: return "door";
    case Kind::kWindow: return "window";
    case Kind::kNone: break;
  }
  return "none";
}

std::string tag(const Tags& tags, const std::string& key) {
  auto it = tags.find(key);
  return it == tags.end() ? std::string() : it->second;
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

/// A tag value as a room kind: lower case, spaces and dashes as underscores.
std::string as_kind(std::string v) {
  for (char& c : v) {
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (c == ' ' || c == '-') c = '_';
  }
  return v;
}

std::string room_kind(Kind k, const Tags& tags) {
  switch (k) {
    case Kind::kCorridor: return "corridor";
    case Kind::kArea: return "area";
    case Kind::kElevator: return "elevator";
    case Kind::kLevel: return "circulation";
    default: break;
  }
  if (tag(tags, "stairs") == "yes" || tag(tags, "highway") == "steps") return "stairs";
  for (const char* key : {"room", "shop", "amenity"}) {
    const std::string v = tag(tags, key);
    if (v.empty() || v == "yes") continue;
    return std::string(key) == "shop" ? "shop" : as_kind(v);
  }
  if (!tag(tags, "shop").empty()) return "shop";
  return "room";
}

bool is_door_point(const Tags& tags) {
  if (tags.count("door") || tag(tags, "indoor") == "door") return true;
  const std::string e = tag(tags, "entrance");
  return !e.empty() && e != "no";
}

/// Dominant wall direction modulo 90 degrees (length-weighted, 1-degree bins, refined by the
/// mean of its bin): columns are squared to the building.
double dominant_direction_rad(const std::vector<Segment2>& walls) {
  constexpr int kBins = 90;
  // Direction modulo 90 degrees and its 1-degree bin.
  auto folded = [](const Segment2& s, int& bin) {
    const Vec2 d = s.b_m - s.a_m;
    double a = std::fmod(std::atan2(d.y(), d.x()), 0.5 * kPi);
    if (a < 0.0) a += 0.5 * kPi;
    bin = std::min(kBins - 1, static_cast<int>(a / (0.5 * kPi) * kBins));
    return a;
  };
  std::vector<double> weight(kBins, 0.0);
  for (const Segment2& s : walls) {
    int b = 0;
    folded(s, b);
    weight[static_cast<std::size_t>(b)] += s.length_m();
  }
  int best = 0;
  for (int b = 1; b < kBins; ++b) {
    if (weight[static_cast<std::size_t>(b)] > weight[static_cast<std::size_t>(best)]) best = b;
  }
  // Circular mean (period 90 degrees) of the walls in the best bin and its neighbours.
  double sx = 0.0, sy = 0.0;
  for (const Segment2& s : walls) {
    int b = 0;
    const double a = folded(s, b);
    const int diff = std::min(std::abs(b - best), kBins - std::abs(b - best));
    if (diff > 1) continue;
    sx += s.length_m() * std::cos(4.0 * a);
    sy += s.length_m() * std::sin(4.0 * a);
  }
  if (sx == 0.0 && sy == 0.0) return 0.0;
  double a = 0.25 * std::atan2(sy, sx);
  if (a < 0.0) a += 0.5 * kPi;
  return a;
}

}  // namespace

ImportResult import_indoor(const IndoorData& data, const std::string& source, const std::string& name_stem,
                           const ImportOptions& options) {
  const double thickness = wall_thickness_or(options, 0.10, source);
  if (!(options.default_column_size_m > 0.0) || options.default_column_size_m > 5.0) {
    throw InputError(source + ": default column size " + fmt(options.default_column_size_m) + " m is outside (0, 5]");
  }

  // Levels of a tagged element: level=* plus repeat_on=*; none -> level 0.
  auto levels_of = [&](const Tags& tags, const std::string& what, bool& has_level) {
    Ranges all;
    has_level = false;
    for (const char* key : {"level", "repeat_on"}) {
      const std::string v = tag(tags, key);
      if (v.empty()) continue;
      Ranges r;
      if (!parse_osm_levels(v, r)) {
        throw InputError(what + ": " + key + "=" + quoted(v) +
                         " is not a level value (expected e.g. 0, -1, 1;2, 0-2, -3--1, 0.5, 2~4)");
      }
      // A range is expanded level by level below (the levels on offer): bounded before that.
      for (const auto& [lo, hi] : r) {
        check_limit("max_level_range", std::floor(hi) - std::ceil(lo) + 1.0, what + ": " + key + "=" + quoted(v), "levels");
      }
      all.insert(all.end(), r.begin(), r.end());
      has_level = true;
    }
    if (all.empty()) all.emplace_back(0.0, 0.0);
    return all;
  };

  struct Feature {
    const IndoorFeature* f;
    Kind kind;
    Ranges levels;
  };
  std::vector<Feature> features;
  for (const IndoorFeature& f : data.features) {
    const Kind k = kind_of(tag(f.tags, "indoor"));
    if (k == Kind::kNone) continue;
    bool has = false;
    features.push_back({&f, k, levels_of(f.tags, f.what, has)});
  }
  struct Point {
    const IndoorPoint* p;
    Ranges levels;
    bool has_level;
  };
  std::vector<Point> doors_in, columns_in;
  for (const IndoorPoint& p : data.points) {
    const bool door = is_door_point(p.tags);
    const bool column = tag(p.tags, "indoor") == "column";
    if (!door && !column) continue;
    bool has = false;
    Ranges lv = levels_of(p.tags, p.what, has);
    (door ? doors_in : columns_in).push_back({&p, std::move(lv), has});
  }
  if (features.empty()) {
    std::string found;
    for (std::size_t k = 0; k < data.frequent_keys.size() && k < 8; ++k) {
      found += (k ? ", " : "") + data.frequent_keys[k].first + "=* (" + std::to_string(data.frequent_keys[k].second) + ")";
    }
    throw InputError(source + ": no indoor features of a schema floorcast reads: neither Simple Indoor Tagging (ways, "
                              "multipolygons or polygons with indoor=room, corridor, area, wall, column, elevator or level) "
                              "nor IndoorOSM (buildingpart=room, corridor, hall, verticalpassage or shell ways in type=level "
                              "relations); the file's most frequent tags: " + (found.empty() ? std::string("none") : found));
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

  // Spaces: what may be floor (free space is their union).
  auto is_space_kind = [](Kind k) {
    return k == Kind::kRoom || k == Kind::kCorridor || k == Kind::kArea || k == Kind::kElevator || k == Kind::kLevel;
  };
  ImportResult result;
  for (double v : available) {
    bool any = false;
    int others = 0;
    for (const Feature& f : features) {
      if (!on_level(f.levels, v)) continue;
      if (is_space_kind(f.kind) && !f.f->unclosed) any = true;
      else ++others;
    }
    if (!any) {
      result.faithfulness.levels_without_spaces.push_back("level " + fmt(v) + " (" + std::to_string(others) +
                                                          " wall, column or unclosed features, no space)");
    }
  }
  // Selected features; areas whose outline does not close are skipped (a data defect of one
  // element, not of the level).
  std::vector<const Feature*> selected;
  std::set<LonLat> vertices;
  for (const Feature& f : features) {
    if (!on_level(f.levels, level)) continue;
    const bool needs_area = f.kind != Kind::kWall && f.kind != Kind::kDoor && f.kind != Kind::kWindow;
    if (needs_area && f.f->unclosed) {
      result.notes.push_back(f.f->what + ": indoor=" + kind_name(f.kind) +
                             " is not closed (its first and last nodes differ), skipped");
      count_repair(result, "unclosed_areas_skipped");
      continue;
    }
    selected.push_back(&f);
    for (const Ring& ring : f.f->rings) vertices.insert(ring.begin(), ring.end());
  }
  if (selected.empty()) {
    std::string why;
    for (const std::string& n : result.notes) why += (why.empty() ? " (" : "; ") + n;
    throw InputError(source + ": no usable indoor features on level " + fmt(level) + (why.empty() ? "" : why + ")"));
  }
  const bool any_space = std::any_of(features.begin(), features.end(),
                                     [&](const Feature& f) { return is_space_kind(f.kind) && !f.f->unclosed; });
  if (!any_space) {
    result.notes.push_back("the source maps no spaces (only walls and columns): the free space is what its walls "
                           "enclose, and there is no faithfulness check");
  } else if (std::none_of(selected.begin(), selected.end(), [&](const Feature* f) { return is_space_kind(f->kind); })) {
    std::string with;
    for (double v : available) {
      for (const Feature& f : features) {
        if (on_level(f.levels, v) && is_space_kind(f.kind) && !f.f->unclosed) {
          with += (with.empty() ? "" : ", ") + fmt(v);
          break;
        }
      }
    }
    throw InputError(source + ": level " + fmt(level) + " maps no space (indoor=room, corridor, area, elevator or level): only " +
                     std::to_string(selected.size()) + " wall or column feature(s), so nothing on it is floor" +
                     (with.empty() ? std::string() : "; levels with spaces: " + with));
  }

  // Coordinates: the source's CRS (--crs, else declared, else WGS84) to longitude/latitude, then
  // the local plane about the mean of the selected features' distinct vertices.
  GeoFrame frame(options.crs.value_or(data.crs), source);
  if (options.crs && !data.crs.empty() && *options.crs != data.crs) {
    result.notes.push_back("the source declares the coordinate reference system " + quoted(data.crs) + "; --crs " +
                           quoted(*options.crs) + " used instead");
  }
  std::map<LonLat, Vec2> geographic;
  for (const Feature* f : selected) {
    for (const Ring& ring : f->f->rings) {
      for (const LonLat& v : ring) {
        if (!geographic.count(v)) geographic.emplace(v, frame.to_geographic_deg({v.lon, v.lat}, f->f->what));
      }
    }
  }
  Vec2 origin = Vec2::Zero();
  for (const auto& [raw, g] : geographic) origin += g;
  origin /= static_cast<double>(std::max<std::size_t>(geographic.size(), 1));
  frame.set_origin_deg(origin);
  auto project_at = [&](const LonLat& p, const std::string& what) {
    auto it = geographic.find(p);
    return frame.to_local_m(it != geographic.end() ? it->second : frame.to_geographic_deg({p.lon, p.lat}, what));
  };
  auto project = [&](const LonLat& p) { return project_at(p, source); };

  std::vector<BoundaryEdge> edges;
  std::vector<Segment2> glass;
  std::vector<WallPolygon> wall_polygons;
  struct OpeningLine {
    const IndoorFeature* f;
    Vec2 a, b;
    bool window;
  };
  std::vector<OpeningLine> opening_lines;
  std::map<Kind, int> kind_counts;
  FloorPlan plan;
  for (std::size_t fi = 0; fi < selected.size(); ++fi) {
    const Feature& f = *selected[fi];
    ++kind_counts[f.kind];
    const bool no_wall = tag(f.f->tags, "wall") == "no";
    const bool is_glass = f.kind == Kind::kWall && tag(f.f->tags, "material") == "glass";
    if (f.kind == Kind::kWall && f.f->area) {
      // A wall drawn with its thickness (a polygon): walls_from_polygons below.
      WallPolygon wp{f.f->what, "wallpolygon-" + f.f->id, {}, is_glass};
      for (const Ring& ring : f.f->rings) {
        std::vector<Vec2> local;
        for (const LonLat& v : ring) local.push_back(project(v));
        wp.rings.push_back(std::move(local));
      }
      wall_polygons.push_back(std::move(wp));
      continue;
    }
    if (f.kind == Kind::kDoor || f.kind == Kind::kWindow) {
      // An opening drawn as a line (its two ends) or a polygon (its minimum-area rectangle's long
      // side through the middle): centred on it, as wide as it is long.
      std::vector<cv::Point2f> pts;
      for (const Ring& ring : f.f->rings) {
        for (const LonLat& v : ring) {
          const Vec2 q = project(v);
          pts.emplace_back(static_cast<float>(q.x()), static_cast<float>(q.y()));
        }
      }
      if (pts.size() < 2) continue;
      OpeningLine line{f.f, {}, {}, f.kind == Kind::kWindow};
      if (f.f->area) {
        const cv::RotatedRect box = cv::minAreaRect(pts);
        const double angle = box.angle * kPi / 180.0;
        Vec2 u(std::cos(angle), std::sin(angle));
        double half = 0.5 * box.size.width;
        if (box.size.height > box.size.width) {
          u = Vec2(-u.y(), u.x());
          half = 0.5 * box.size.height;
        }
        const Vec2 c(box.center.x, box.center.y);
        line.a = c - half * u;
        line.b = c + half * u;
      } else {
        line.a = project(f.f->rings.front().front());
        line.b = project(f.f->rings.back().back());
      }
      opening_lines.push_back(line);
      continue;
    }
    for (const Ring& ring : f.f->rings) {
      for (std::size_t k = 0; k + 1 < ring.size(); ++k) {
        const Segment2 s{project(ring[k]), project(ring[k + 1])};
        if (is_glass) {
          glass.push_back(s);
          continue;
        }
        BoundaryEdge e;
        e.segment_m = s;
        e.owner = static_cast<int>(fi);
        e.walled = f.kind != Kind::kArea && !no_wall;
        e.open = f.kind == Kind::kCorridor || f.kind == Kind::kArea || no_wall;
        edges.push_back(e);
      }
    }
    // Room labels from closed spaces (outer rings; inner rings are the holes of the outer ring
    // containing them).
    if (f.kind == Kind::kWall || f.kind == Kind::kColumn || !f.f->area) continue;
    std::vector<Room> rooms;
    for (std::size_t r = 0; r < f.f->rings.size(); ++r) {
      if (f.f->inner[r] || f.f->rings[r].size() < 4) continue;
      Room room;
      room.id = f.f->id + (rooms.empty() ? "" : "-" + std::to_string(rooms.size() + 1));
      room.kind = f.f->kind.empty() ? room_kind(f.kind, f.f->tags) : f.f->kind;
      for (std::size_t k = 0; k + 1 < f.f->rings[r].size(); ++k) room.polygon_m.push_back(project(f.f->rings[r][k]));
      rooms.push_back(std::move(room));
    }
    for (std::size_t r = 0; r < f.f->rings.size(); ++r) {
      if (!f.f->inner[r] || f.f->rings[r].size() < 4) continue;
      std::vector<Vec2> hole;
      for (std::size_t k = 0; k + 1 < f.f->rings[r].size(); ++k) hole.push_back(project(f.f->rings[r][k]));
      for (Room& room : rooms) {
        if (point_in_polygon(room.polygon_m, hole.front())) {
          room.holes_m.push_back(hole);
          break;
        }
      }
    }
    for (Room& room : rooms) plan.rooms.push_back(std::move(room));
  }
  auto pieces = classify_boundaries(edges, options.cleanup.snap_tolerance_m, options.cleanup.angle_tolerance_rad);
  // Free space is the union of the spaces: an unwalled outline (indoor=area, wall=no, corridor
  // pieces) that borders unmapped space is a wall there.
  const WalledAtUnmapped walled = wall_unmapped_sides(pieces, plan.rooms);
  if (walled.pieces > 0) {
    count_repair(result, "open_outlines_walled_at_unmapped", walled.pieces);
    result.notes.push_back(fmt(std::round(walled.length_m * 100.0) / 100.0) + " m of unwalled space outline (indoor=area, wall=no, "
                           "corridor pieces) in " + std::to_string(walled.pieces) +
                           " piece(s) borders unmapped space: walls there (free space is the union of the mapped spaces)");
  }

  plan.level = static_cast<int>(std::floor(level));
  if (static_cast<double>(plan.level) != level) {
    result.notes.push_back("level " + fmt(level) + " is not an integer; the plan's level is " + std::to_string(plan.level));
  }
  append_walls(plan, pieces.walls, thickness);
  append_walls(plan, glass, thickness);
  for (std::size_t k = pieces.walls.size(); k < plan.walls.size(); ++k) plan.walls[k].material = WallMaterial::kGlass;
  int rectangle_walls = 0, traced_walls = 0;
  if (!wall_polygons.empty()) {
    for (Wall& w : walls_from_polygons(wall_polygons, options, result.notes, rectangle_walls, traced_walls)) {
      plan.walls.push_back(std::move(w));
    }
  }
  // Openings drawn as lines: doors and windows without a wall yet (the clean-up puts each on the
  // wall carrying its centre).
  int line_doors = 0, line_windows = 0;
  for (const OpeningLine& line : opening_lines) {
    const double width = (line.b - line.a).norm();
    if (width < 0.05) {
      result.notes.push_back(line.f->what + ": opening shorter than 5 cm, skipped");
      continue;
    }
    if (line.window) {
      Window w;
      w.id = line.f->id;
      w.center_m = 0.5 * (line.a + line.b);
      w.width_m = width;
      plan.windows.push_back(std::move(w));
      ++line_windows;
    } else {
      Door d;
      d.id = line.f->id;
      d.center_m = 0.5 * (line.a + line.b);
      d.width_m = width;
      d.closed = options.doors_closed;
      plan.doors.push_back(std::move(d));
      ++line_doors;
    }
  }

  // Columns mapped as nodes: square pillars (a wall as long as it is thick) squared to the
  // building's dominant wall direction.
  int column_count = 0;
  if (!columns_in.empty()) {
    std::vector<Segment2> all = pieces.walls;
    all.insert(all.end(), glass.begin(), glass.end());
    const double a = dominant_direction_rad(all);
    const Vec2 u(std::cos(a), std::sin(a));
    for (const Point& c : columns_in) {
      if (!(c.has_level ? on_level(c.levels, level) : vertices.count(c.p->at) > 0)) continue;
      double size = options.default_column_size_m;
      for (const char* key : {"width", "diameter"}) {
        const std::string v = tag(c.p->tags, key);
        double s = 0.0;
        if (!v.empty() && parse_width(v, s) && s <= 5.0) {
          size = s;
          break;
        }
      }
      const Vec2 at = project_at(c.p->at, c.p->what);
      Wall w;
      w.id = "column-" + c.p->id;
      w.a_m = at - 0.5 * size * u;
      w.b_m = at + 0.5 * size * u;
      w.thickness_m = size;
      plan.walls.push_back(std::move(w));
      ++column_count;
    }
  }

  // Doors on this level: a door point with a matching level, or without a level of its own on a
  // vertex of a selected feature.
  const double reach = 0.5 * thickness + options.cleanup.opening_attach_tolerance_m;
  std::vector<Segment2> door_walls = pieces.walls;
  door_walls.insert(door_walls.end(), glass.begin(), glass.end());
  int door_count = 0;
  for (const Point& dp : doors_in) {
    if (!(dp.has_level ? on_level(dp.levels, level) : vertices.count(dp.p->at) > 0)) continue;
    ++door_count;
    const Vec2 p = project_at(dp.p->at, dp.p->what);
    const std::string& what = dp.p->what;
    const double d_wall = distance_to_segments(p, door_walls);
    if (d_wall > reach) {
      if (distance_to_segments(p, pieces.open) <= reach) {
        result.notes.push_back(what + ": door on an open boundary (corridor/area outline, no wall), skipped");
      } else {
        result.notes.push_back(what + ": door is not on any wall of level " + fmt(level) + " (nearest wall " +
                               fmt(d_wall) + " m away), skipped");
      }
      continue;
    }
    Door d;
    d.id = dp.p->id;
    d.center_m = p;
    d.width_m = options.default_door_width_m;
    const std::string width = tag(dp.p->tags, "width");
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

  const OpeningsReport openings =
      check_openings(plan, door_walls, options.infer_openings, options.default_door_width_m, reach, result.notes);
  count_repair(result, "openings_inferred", openings.inferred);

  result.level_description = "level " + fmt(level);
  if (!frame.geographic() || !options.crs.value_or(data.crs).empty()) result.level_description += ", " + frame.description();
  result.source_counts = data.source_counts;
  for (const auto& [k, name] : std::vector<std::pair<Kind, const char*>>{{Kind::kRoom, "rooms"},
                                                                         {Kind::kCorridor, "corridors"},
                                                                         {Kind::kArea, "areas"},
                                                                         {Kind::kWall, "walls"},
                                                                         {Kind::kColumn, "columns"},
                                                                         {Kind::kElevator, "elevators"},
                                                                         {Kind::kLevel, "level_outlines"}}) {
    result.source_counts.emplace_back(name, kind_counts[k]);
  }
  result.source_counts.emplace_back("column_nodes", column_count);
  if (!wall_polygons.empty()) {
    result.source_counts.emplace_back("wall_polygons", static_cast<int>(wall_polygons.size()));
    result.source_counts.emplace_back("wall_polygon_rectangles", rectangle_walls);
  }
  if (!opening_lines.empty()) {
    result.source_counts.emplace_back("door_lines", line_doors);
    result.source_counts.emplace_back("window_lines", line_windows);
  }
  result.source_counts.emplace_back("doors", door_count);
  return finish_import(std::move(plan), source, name_stem + " level " + fmt(level), options, std::move(result), nullptr, true);
}

}  // namespace floorcast::import_detail
