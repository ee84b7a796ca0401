#include "floorcast/floorplans/io.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "floorcast/core/file_io.hpp"
#include "floorcast/core/json_text.hpp"
#include "floorcast/core/limits.hpp"

namespace floorcast {
namespace {

using Json = nlohmann::json;
using OrderedJson = nlohmann::ordered_json;

std::string quoted(const std::string& s) { return "\"" + printable_text(s, 80) + "\""; }

/// Names one element in messages: `walls[3] (id "w3")`.
std::string element_name(const char* array, std::size_t index, const std::string& id) {
  std::string name = std::string(array) + "[" + std::to_string(index) + "]";
  if (!id.empty()) name += " (id " + quoted(id) + ")";
  return name;
}

class Reader {
 public:
  Reader(const Json& object, std::string source, std::string where)
      : object_(object), source_(std::move(source)), where_(std::move(where)) {
    if (!object_.is_object()) fail("expected a JSON object, got " + std::string(object_.type_name()));
  }

  [[noreturn]] void fail(const std::string& reason) const {
    throw InputError(source_ + ": " + where_ + ": " + reason);
  }

  /// Refuses any key not in `allowed`.
  void only_keys(std::initializer_list<const char*> allowed) const {
    for (auto it = object_.begin(); it != object_.end(); ++it) {
      const bool known = std::any_of(allowed.begin(), allowed.end(),
                                     [&](const char* k) { return it.key() == k; });
      if (!known) fail("unknown field " + quoted(it.key()));
    }
  }

  bool has(const char* key) const { return object_.contains(key); }

  const Json& get(const char* key) const {
    if (!object_.contains(key)) fail("missing required field " + quoted(key));
    return object_.at(key);
  }

  double number(const char* key) const { return as_number(get(key), key); }
  double number_or(const char* key, double fallback) const {
    return has(key) ? number(key) : fallback;
  }

  std::string string(const char* key) const {
    const Json& v = get(key);
    if (!v.is_string()) fail("field " + quoted(key) + " must be a string, got " + v.type_name());
    return v.get<std::string>();
  }

  bool boolean_or(const char* key, bool fallback) const {
    if (!has(key)) return fallback;
    const Json& v = get(key);
    if (!v.is_boolean()) fail("field " + quoted(key) + " must be true or false, got " + v.type_name());
    return v.get<bool>();
  }

  int integer(const char* key) const {
    const Json& v = get(key);
    if (!v.is_number_integer()) fail("field " + quoted(key) + " must be an integer, got " + json_excerpt(v));
    const auto value = v.get<long long>();
    if (value < -1000000 || value > 1000000) fail("field " + quoted(key) + " is out of range: " + json_excerpt(v));
    return static_cast<int>(value);
  }

  Vec2 point(const char* key) const {
    const Json& v = get(key);
    if (!v.is_array() || v.size() != 2) {
      fail("field " + quoted(key) + " must be an array [x, y] of two numbers, got " + json_excerpt(v));
    }
    return {as_number(v[0], key), as_number(v[1], key)};
  }

 private:
  double as_number(const Json& v, const char* key) const {
    if (!v.is_number()) fail("field " + quoted(key) + " must be a number, got " + json_excerpt(v));
    const double x = v.get<double>();
    if (!std::isfinite(x)) fail("field " + quoted(key) + " is not a finite number");
    return x;
  }

  const Json& object_;
  std::string source_;
  std::string where_;
};

const Json& array_field(const Json& root, const char* key, const std::string& source, bool required) {
  static const Json kEmpty = Json::array();
  if (!root.contains(key)) {
    if (required) throw InputError(source + ": missing required field " + quoted(key));
    return kEmpty;
  }
  const Json& v = root.at(key);
  if (!v.is_array()) {
    throw InputError(source + ": field " + quoted(key) + " must be an array, got " + v.type_name());
  }
  return v;
}

std::string format_extent(double w, double h) {
  std::ostringstream os;
  os << w << " m x " << h << " m";
  return os.str();
}

void check_point(const Vec2& p, const PlanLimits& limits, const std::function<void(const std::string&)>& fail,
                 const char* what) {
  if (!std::isfinite(p.x()) || !std::isfinite(p.y())) fail(std::string(what) + " is not finite");
  if (std::abs(p.x()) > limits.max_abs_coordinate_m || std::abs(p.y()) > limits.max_abs_coordinate_m) {
    std::ostringstream os;
    os << what << " (" << p.x() << ", " << p.y() << ") is absurdly far from the origin (limit "
       << limits.max_abs_coordinate_m << " m)";
    fail(os.str());
  }
}

void check_range(double value, double lo, double hi, const std::function<void(const std::string&)>& fail,
                 const char* what, bool lo_inclusive = false) {
  std::ostringstream os;
  if (!std::isfinite(value)) {
    os << what << " is not finite";
    fail(os.str());
  }
  const bool below = lo_inclusive ? value < lo : value <= lo;
  if (below || value > hi) {
    os << what << " = " << value << " m is outside " << (lo_inclusive ? "[" : "(") << lo << ", " << hi << "]";
    fail(os.str());
  }
}

}  // namespace

void validate_floor_plan(const FloorPlan& plan, const std::string& source, const PlanLimits& limits) {
  if (plan.walls.empty()) throw InputError(source + ": plan has no walls");
  check_limit("max_plan_elements",
              static_cast<double>(plan.walls.size() + plan.doors.size() + plan.windows.size() + plan.obstacles.size() +
                                  plan.rooms.size()),
              source + ": plan elements (walls, doors, windows, obstacles, rooms)");

  auto check_text = [&](const std::string& text, const std::string& what) {
    std::size_t bad = 0;
    if (!valid_utf8(text, &bad)) {
      throw InputError(source + ": " + what + " is not valid UTF-8 (byte " + std::to_string(bad) + " of \"" +
                       printable_text(text, 60) + "\")");
    }
  };
  check_text(plan.name, "name");

  std::map<std::string, std::string> seen_ids;  // id -> element name
  auto check_id = [&](const std::string& id, const std::string& name) {
    if (id.empty()) throw InputError(source + ": " + name + ": empty id");
    check_text(id, name + ": id");
    auto [it, inserted] = seen_ids.emplace(id, name);
    if (!inserted) throw InputError(source + ": " + name + ": duplicate id " + quoted(id) + " (also used by " + it->second + ")");
  };

  for (std::size_t i = 0; i < plan.walls.size(); ++i) {
    const Wall& w = plan.walls[i];
    const std::string name = element_name("walls", i, w.id);
    auto fail = [&](const std::string& reason) { throw InputError(source + ": " + name + ": " + reason); };
    check_id(w.id, name);
    check_point(w.a_m, limits, fail, "endpoint a");
    check_point(w.b_m, limits, fail, "endpoint b");
    const double len = w.length_m();
    if (len < limits.min_wall_length_m) {
      std::ostringstream os;
      os << "wall is degenerate: length " << len << " m (minimum " << limits.min_wall_length_m << " m)";
      fail(os.str());
    }
    if (len > limits.max_wall_length_m) {
      std::ostringstream os;
      os << "wall length " << len << " m is absurd (limit " << limits.max_wall_length_m << " m)";
      fail(os.str());
    }
    check_range(w.thickness_m, limits.min_thickness_m, limits.max_thickness_m, fail, "thickness_m", true);
    if (w.material == WallMaterial::kGlass) {
      check_range(w.glass_sill_m, 0.0, limits.max_height_m, fail, "glass_sill_m", true);
      if (w.glass_head_m) {
        check_range(*w.glass_head_m, 0.0, limits.max_height_m, fail, "glass_head_m");
        if (*w.glass_head_m <= w.glass_sill_m) fail("glass_head_m must be above glass_sill_m");
      }
    } else if (w.glass_sill_m != 0.0 || w.glass_head_m) {
      fail("glass_sill_m/glass_head_m given for a solid wall");
    }
  }

  // Openings per wall, to refuse overlaps.
  struct Span { double t0, t1; std::string name; };
  std::vector<std::vector<Span>> spans(plan.walls.size());
  const WallIdIndex wall_ids(plan);
  auto check_opening = [&](const std::string& name, const std::string& wall_id, const Vec2& center,
                           double width) {
    auto fail = [&](const std::string& reason) { throw InputError(source + ": " + name + ": " + reason); };
    check_point(center, limits, fail, "center");
    check_range(width, limits.min_opening_width_m, limits.max_opening_width_m, fail, "width_m", true);
    const int wi = wall_ids.find(wall_id);
    if (wi < 0) fail("refers to unknown wall " + quoted(wall_id));
    const Wall& w = plan.walls[static_cast<std::size_t>(wi)];
    const Vec2 d = w.direction();
    const Vec2 rel = center - w.a_m;
    const double along = rel.dot(d);
    const double across = std::abs(d.x() * rel.y() - d.y() * rel.x());
    const double tolerance = 0.5 * w.thickness_m + limits.opening_on_wall_tolerance_m;
    if (across > tolerance) {
      std::ostringstream os;
      os << "does not lie on wall " << quoted(wall_id) << ": centre is " << across
         << " m from the wall axis (tolerance " << tolerance << " m)";
      fail(os.str());
    }
    const double t0 = along - 0.5 * width, t1 = along + 0.5 * width;
    constexpr double kEps = 1e-6;
    if (t0 < -kEps || t1 > w.length_m() + kEps) {
      std::ostringstream os;
      os << "does not lie on wall " << quoted(wall_id) << ": its span [" << t0 << ", " << t1
         << "] m along the wall leaves the wall [0, " << w.length_m() << "]";
      fail(os.str());
    }
    spans[static_cast<std::size_t>(wi)].push_back({t0, t1, name});
    return wi;
  };

  for (std::size_t i = 0; i < plan.doors.size(); ++i) {
    const Door& d = plan.doors[i];
    const std::string name = element_name("doors", i, d.id);
    check_id(d.id, name);
    check_opening(name, d.wall_id, d.center_m, d.width_m);
  }
  for (std::size_t i = 0; i < plan.windows.size(); ++i) {
    const Window& win = plan.windows[i];
    const std::string name = element_name("windows", i, win.id);
    auto fail = [&](const std::string& reason) { throw InputError(source + ": " + name + ": " + reason); };
    check_id(win.id, name);
    const int wi = check_opening(name, win.wall_id, win.center_m, win.width_m);
    if (plan.walls[static_cast<std::size_t>(wi)].material == WallMaterial::kGlass) {
      fail("a window cannot be placed in glass wall " + quoted(win.wall_id));
    }
    check_range(win.sill_m, 0.0, limits.max_height_m, fail, "sill_m", true);
    check_range(win.head_m, 0.0, limits.max_height_m, fail, "head_m");
    if (win.head_m <= win.sill_m) fail("head_m must be above sill_m");
  }
  for (std::size_t wi = 0; wi < spans.size(); ++wi) {
    auto& s = spans[wi];
    std::sort(s.begin(), s.end(), [](const Span& x, const Span& y) { return x.t0 < y.t0; });
    for (std::size_t k = 1; k < s.size(); ++k) {
      if (s[k].t0 < s[k - 1].t1 - 1e-9) {
        throw InputError(source + ": " + s[k].name + ": overlaps " + s[k - 1].name + " on wall " +
                         quoted(plan.walls[wi].id));
      }
    }
  }

  for (std::size_t i = 0; i < plan.obstacles.size(); ++i) {
    const Obstacle& o = plan.obstacles[i];
    const std::string name = element_name("obstacles", i, o.id);
    auto fail = [&](const std::string& reason) { throw InputError(source + ": " + name + ": " + reason); };
    check_id(o.id, name);
    check_point(o.center_m, limits, fail, "center");
    check_range(o.size_m.x(), 0.0, limits.max_wall_length_m, fail, "size_m[0]");
    check_range(o.size_m.y(), 0.0, limits.max_wall_length_m, fail, "size_m[1]");
    check_range(o.height_m, 0.0, limits.max_height_m, fail, "height_m");
    if (!std::isfinite(o.yaw_rad)) fail("yaw_rad is not finite");
  }

  std::set<std::string> room_ids;
  for (std::size_t i = 0; i < plan.rooms.size(); ++i) {
    const Room& room = plan.rooms[i];
    const std::string name = element_name("rooms", i, room.id);
    auto fail = [&](const std::string& reason) { throw InputError(source + ": " + name + ": " + reason); };
    if (room.id.empty()) fail("empty id");
    check_text(room.id, name + ": id");
    check_text(room.kind, name + ": kind");
    if (!room_ids.insert(room.id).second) fail("duplicate room id " + quoted(room.id));
    if (room.kind.empty()) fail("empty kind");
    auto check_ring = [&](const std::vector<Vec2>& ring, const std::string& what) {
      if (ring.size() < 3) fail(what + " needs at least 3 points, got " + std::to_string(ring.size()));
      check_limit("max_vertices_per_element", static_cast<double>(ring.size()), source + ": " + name + ": " + what,
                  "vertices");
      for (const Vec2& v : ring) check_point(v, limits, fail, (what + " point").c_str());
    };
    check_ring(room.polygon_m, "polygon");
    for (std::size_t h = 0; h < room.holes_m.size(); ++h) check_ring(room.holes_m[h], "holes[" + std::to_string(h) + "]");
  }
  // Every raster over the plan scales with its extent (walls and obstacles).
  const Eigen::Vector4d box = plan_bbox_m(plan);
  const double w = box[2] - box[0], h = box[3] - box[1];
  check_limit("max_plan_extent_m", std::max(w, h), source + ": plan extent " + format_extent(w, h) + ": longer side",
              "m");
}

FloorPlan parse_floor_plan_json(const std::string& json_text, const std::string& source,
                                const PlanLimits& limits) {
  const Json root = parse_json_text(json_text, source);
  if (!root.is_object()) throw InputError(source + ": top level must be a JSON object");

  Reader top(root, source, "plan");
  top.only_keys({"format_version", "name", "level", "walls", "doors", "windows", "obstacles", "rooms"});
  const int version = top.integer("format_version");
  if (version != FloorPlan::kFormatVersion) {
    throw InputError(source + ": unsupported format_version " + std::to_string(version) +
                     " (this floorcast reads " + std::to_string(FloorPlan::kFormatVersion) + ")");
  }

  FloorPlan plan;
  plan.name = top.has("name") ? top.string("name") : std::string();
  plan.level = top.has("level") ? top.integer("level") : 0;

  const Json& walls = array_field(root, "walls", source, true);
  // Counted before any element is built (validate_floor_plan checks the same on the result).
  check_limit("max_plan_elements",
              static_cast<double>(walls.size() + array_field(root, "doors", source, false).size() +
                                  array_field(root, "windows", source, false).size() +
                                  array_field(root, "obstacles", source, false).size()),
              source + ": plan elements (walls, doors, windows, obstacles)");
  for (std::size_t i = 0; i < walls.size(); ++i) {
    const std::string id = walls[i].is_object() && walls[i].contains("id") && walls[i]["id"].is_string()
                               ? walls[i]["id"].get<std::string>() : std::string();
    Reader r(walls[i], source, element_name("walls", i, id));
    r.only_keys({"id", "a", "b", "thickness_m", "material", "glass_sill_m", "glass_head_m"});
    Wall w;
    w.id = r.string("id");
    w.a_m = r.point("a");
    w.b_m = r.point("b");
    w.thickness_m = r.number_or("thickness_m", w.thickness_m);
    if (r.has("material")) {
      const std::string m = r.string("material");
      if (m == "solid") w.material = WallMaterial::kSolid;
      else if (m == "glass") w.material = WallMaterial::kGlass;
      else r.fail("material must be \"solid\" or \"glass\", got " + quoted(m));
    }
    w.glass_sill_m = r.number_or("glass_sill_m", 0.0);
    if (r.has("glass_head_m")) w.glass_head_m = r.number("glass_head_m");
    if (w.material == WallMaterial::kSolid && (r.has("glass_sill_m") || r.has("glass_head_m"))) {
      r.fail("glass_sill_m/glass_head_m given for a solid wall");
    }
    plan.walls.push_back(std::move(w));
  }

  auto element_id = [](const Json& e) {
    return e.is_object() && e.contains("id") && e["id"].is_string() ? e["id"].get<std::string>() : std::string();
  };

  const Json& doors = array_field(root, "doors", source, false);
  for (std::size_t i = 0; i < doors.size(); ++i) {
    Reader r(doors[i], source, element_name("doors", i, element_id(doors[i])));
    r.only_keys({"id", "wall", "center", "width_m", "closed"});
    Door d;
    d.id = r.string("id");
    d.wall_id = r.string("wall");
    d.center_m = r.point("center");
    d.width_m = r.number("width_m");
    d.closed = r.boolean_or("closed", false);
    plan.doors.push_back(std::move(d));
  }

  const Json& windows = array_field(root, "windows", source, false);
  for (std::size_t i = 0; i < windows.size(); ++i) {
    Reader r(windows[i], source, element_name("windows", i, element_id(windows[i])));
    r.only_keys({"id", "wall", "center", "width_m", "sill_m", "head_m"});
    Window w;
    w.id = r.string("id");
    w.wall_id = r.string("wall");
    w.center_m = r.point("center");
    w.width_m = r.number("width_m");
    w.sill_m = r.number_or("sill_m", w.sill_m);
    w.head_m = r.number_or("head_m", w.head_m);
    plan.windows.push_back(std::move(w));
  }

  const Json& obstacles = array_field(root, "obstacles", source, false);
  for (std::size_t i = 0; i < obstacles.size(); ++i) {
    Reader r(obstacles[i], source, element_name("obstacles", i, element_id(obstacles[i])));
    r.only_keys({"id", "kind", "center", "size_m", "yaw_rad", "height_m"});
    Obstacle o;
    o.id = r.string("id");
    const std::string kind = r.string("kind");
    if (kind == "box") o.kind = ObstacleKind::kBox;
    else if (kind == "pillar") o.kind = ObstacleKind::kPillar;
    else r.fail("kind must be \"box\" or \"pillar\", got " + quoted(kind));
    o.center_m = r.point("center");
    o.size_m = r.point("size_m");
    o.yaw_rad = r.number_or("yaw_rad", 0.0);
    o.height_m = r.number("height_m");
    plan.obstacles.push_back(std::move(o));
  }

  const Json& rooms = array_field(root, "rooms", source, false);
  for (std::size_t i = 0; i < rooms.size(); ++i) {
    const std::string where = element_name("rooms", i, element_id(rooms[i]));
    Reader r(rooms[i], source, where);
    r.only_keys({"id", "kind", "polygon", "holes"});
    Room room;
    room.id = r.string("id");
    room.kind = r.string("kind");
    auto ring = [&](const Json& v, const std::string& what) {
      if (!v.is_array()) r.fail(what + " must be an array of [x, y] points, got " + v.type_name());
      std::vector<Vec2> out;
      for (const Json& p : v) {
        if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number()) {
          r.fail(what + ": every point must be an array [x, y] of two numbers, got " + p.dump());
        }
        out.emplace_back(p[0].get<double>(), p[1].get<double>());
      }
      return out;
    };
    room.polygon_m = ring(r.get("polygon"), "field \"polygon\"");
    if (r.has("holes")) {
      const Json& holes = r.get("holes");
      if (!holes.is_array()) r.fail("field \"holes\" must be an array of rings");
      for (std::size_t h = 0; h < holes.size(); ++h) room.holes_m.push_back(ring(holes[h], "holes[" + std::to_string(h) + "]"));
    }
    plan.rooms.push_back(std::move(room));
  }

  validate_floor_plan(plan, source, limits);
  return plan;
}

std::string floor_plan_to_json(const FloorPlan& plan) {
  auto point = [](const Vec2& p) { return OrderedJson::array({p.x(), p.y()}); };
  OrderedJson root;
  root["format_version"] = FloorPlan::kFormatVersion;
  root["name"] = plan.name;
  root["level"] = plan.level;
  OrderedJson walls = OrderedJson::array();
  for (const Wall& w : plan.walls) {
    OrderedJson j;
    j["id"] = w.id;
    j["a"] = point(w.a_m);
    j["b"] = point(w.b_m);
    j["thickness_m"] = w.thickness_m;
    j["material"] = w.material == WallMaterial::kGlass ? "glass" : "solid";
    if (w.material == WallMaterial::kGlass) {
      j["glass_sill_m"] = w.glass_sill_m;
      if (w.glass_head_m) j["glass_head_m"] = *w.glass_head_m;
    }
    walls.push_back(std::move(j));
  }
  root["walls"] = std::move(walls);
  OrderedJson doors = OrderedJson::array();
  for (const Door& d : plan.doors) {
    OrderedJson j;
    j["id"] = d.id;
    j["wall"] = d.wall_id;
    j["center"] = point(d.center_m);
    j["width_m"] = d.width_m;
    j["closed"] = d.closed;
    doors.push_back(std::move(j));
  }
  root["doors"] = std::move(doors);
  OrderedJson windows = OrderedJson::array();
  for (const Window& w : plan.windows) {
    OrderedJson j;
    j["id"] = w.id;
    j["wall"] = w.wall_id;
    j["center"] = point(w.center_m);
    j["width_m"] = w.width_m;
    j["sill_m"] = w.sill_m;
    j["head_m"] = w.head_m;
    windows.push_back(std::move(j));
  }
  root["windows"] = std::move(windows);
  OrderedJson obstacles = OrderedJson::array();
  for (const Obstacle& o : plan.obstacles) {
    OrderedJson j;
    j["id"] = o.id;
    j["kind"] = o.kind == ObstacleKind::kPillar ? "pillar" : "box";
    j["center"] = point(o.center_m);
    j["size_m"] = point(o.size_m);
    j["yaw_rad"] = o.yaw_rad;
    j["height_m"] = o.height_m;
    obstacles.push_back(std::move(j));
  }
  root["obstacles"] = std::move(obstacles);
  // Rooms only when there are any: plans without labels keep their bytes (and hashes).
  if (!plan.rooms.empty()) {
    OrderedJson rooms = OrderedJson::array();
    for (const Room& room : plan.rooms) {
      OrderedJson j;
      j["id"] = room.id;
      j["kind"] = room.kind;
      OrderedJson poly = OrderedJson::array();
      for (const Vec2& v : room.polygon_m) poly.push_back(point(v));
      j["polygon"] = std::move(poly);
      if (!room.holes_m.empty()) {
        OrderedJson holes = OrderedJson::array();
        for (const auto& hole : room.holes_m) {
          OrderedJson h = OrderedJson::array();
          for (const Vec2& v : hole) h.push_back(point(v));
          holes.push_back(std::move(h));
        }
        j["holes"] = std::move(holes);
      }
      rooms.push_back(std::move(j));
    }
    root["rooms"] = std::move(rooms);
  }
  return root.dump(2) + "\n";
}

FloorPlan load_floor_plan(const std::string& path, const PlanLimits& limits) {
  return parse_floor_plan_json(read_text_file(path), input_name(path), limits);
}

void save_floor_plan(const FloorPlan& plan, const std::string& path) {
  write_text_file_atomic(path, floor_plan_to_json(plan));
}

}  // namespace floorcast
