// The generator's layout assembler: rooms (polygons) + connections -> walls, doors, windows.
//
// Every room edge lies on a line; edges of all rooms are grouped by line, each line is cut at
// every edge endpoint into elementary intervals, and each interval learns which room lies on its
// left and on its right (or the outside). The pair decides the wall: exterior, corridor wall,
// partition, glass, or none (open connection). Consecutive intervals with the same wall kind are
// merged into one wall, so a corridor wall runs past many rooms and partitions meet it in T
// junctions. Doors are placed on the run two rooms share, windows on a room's exterior runs.
#include "generate_layout.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "floorcast/floorplans/io.hpp"
#include "floorcast/core/union_find.hpp"
#include "floorcast/core/math.hpp"

namespace floorcast::generate_detail {

// ---- Random numbers -------------------------------------------------------------------------

std::uint64_t Rng::next_u64() {
  std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

double Rng::uniform01() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }

double Rng::uniform(double lo, double hi) { return lo + (hi - lo) * uniform01(); }

int Rng::integer(int lo, int hi) {
  if (hi <= lo) return lo;
  const std::uint64_t span = static_cast<std::uint64_t>(hi - lo) + 1;
  return lo + static_cast<int>(next_u64() % span);
}

bool Rng::bernoulli(double p) { return uniform01() < p; }

Rng Rng::fork(std::uint64_t stream) const { return Rng(mix_seed(state_, stream)); }

std::uint64_t mix_seed(std::uint64_t seed, std::uint64_t salt) {
  Rng r(seed ^ (salt * 0xD1B54A32D192ED03ULL));
  r.next_u64();
  return r.next_u64();
}

double snap(double x, double q) { return std::round(x / q) * q; }

// ---- Exact rotations --------------------------------------------------------------------------

Frame rotated_frame(const Vec2& origin, int degrees) {
  if (degrees % 15 != 0) throw std::logic_error("rotated_frame: angle must be a multiple of 15 degrees");
  int d = degrees % 360;
  if (d < 0) d += 360;
  const double s2 = std::sqrt(2.0), s3 = std::sqrt(3.0), s6 = std::sqrt(6.0);
  // cos/sin of 0, 15, ..., 75 degrees.
  const double cs[6][2] = {{1.0, 0.0},
                           {(s6 + s2) / 4.0, (s6 - s2) / 4.0},
                           {s3 / 2.0, 0.5},
                           {std::sqrt(0.5), std::sqrt(0.5)},
                           {0.5, s3 / 2.0},
                           {(s6 - s2) / 4.0, (s6 + s2) / 4.0}};
  const int quadrant = d / 90;
  const int rest = (d % 90) / 15;
  double c = cs[rest][0], s = cs[rest][1];
  for (int q = 0; q < quadrant; ++q) {
    const double c2 = -s, s2q = c;
    c = c2;
    s = s2q;
  }
  Frame f;
  f.origin = origin;
  f.c = c;
  f.s = s;
  f.yaw_rad = static_cast<double>(degrees) * (kPi / 180.0);
  return f;
}

// ---- Window styles ----------------------------------------------------------------------------

WindowSpec standard_windows(const BuildingStyle& style) {
  WindowSpec w;
  w.width_m = style.window_width_m;
  w.sill_m = style.window_sill_m;
  w.head_m = style.window_head_m;
  w.pier_m = style.window_pier_m;
  w.margin_m = style.window_margin_m;
  return w;
}

WindowSpec small_windows(const BuildingStyle& style) {
  WindowSpec w = standard_windows(style);
  w.width_m = 0.6;
  w.sill_m = 1.4;
  return w;
}

WindowSpec hallway_end_windows(const BuildingStyle& style) {
  WindowSpec w = standard_windows(style);
  w.width_m = 1.2;
  w.margin_m = 0.4;
  return w;
}

WindowSpec no_windows() { return WindowSpec{}; }

// ---- Layout -----------------------------------------------------------------------------------

double signed_area(const std::vector<Vec2>& poly) {
  double a = 0.0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec2& p = poly[i];
    const Vec2& q = poly[(i + 1) % poly.size()];
    a += p.x() * q.y() - q.x() * p.y();
  }
  return 0.5 * a;
}

namespace {

double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

double round4(double x) {
  const double r = std::round(x * 1.0e4) / 1.0e4;
  return r == 0.0 ? 0.0 : r;  // no negative zero in files
}
Vec2 round4(const Vec2& p) { return {round4(p.x()), round4(p.y())}; }

std::pair<int, int> key_of(int a, int b) { return {std::min(a, b), std::max(a, b)}; }

/// Kinds whose walls to rooms are corridor walls (thicker than partitions).
bool is_circulation(const std::string& kind) {
  return kind == "hallway" || kind == "lobby" || kind == "atrium" || kind == "vestibule" || kind == "hall";
}

}  // namespace

int Layout::add_room(const std::string& id, const std::string& kind, std::vector<Vec2> polygon_m,
                     const WindowSpec& windows) {
  if (polygon_m.size() < 3) throw std::logic_error("generator: room " + id + " has fewer than 3 corners");
  if (signed_area(polygon_m) < 0.0) std::reverse(polygon_m.begin(), polygon_m.end());
  for (const LayoutRoom& r : rooms_) {
    if (r.id == id) throw std::logic_error("generator: duplicate room id " + id);
  }
  rooms_.push_back({id, kind, std::move(polygon_m), windows});
  return static_cast<int>(rooms_.size()) - 1;
}

void Layout::set_room_polygon(int index, std::vector<Vec2> polygon_m) {
  LayoutRoom& r = rooms_.at(static_cast<std::size_t>(index));
  if (polygon_m.size() < 3) throw std::logic_error("generator: room " + r.id + " has fewer than 3 corners");
  if (signed_area(polygon_m) < 0.0) std::reverse(polygon_m.begin(), polygon_m.end());
  r.polygon_m = std::move(polygon_m);
}

int Layout::add_rect(const std::string& id, const std::string& kind, const Frame& frame, double x0, double y0,
                     double x1, double y1, const WindowSpec& windows) {
  if (!(x1 > x0 && y1 > y0)) throw std::logic_error("generator: empty rectangle for room " + id);
  return add_room(id, kind,
                  {frame.to_world(x0, y0), frame.to_world(x1, y0), frame.to_world(x1, y1), frame.to_world(x0, y1)},
                  windows);
}

void Layout::add_door(int a, int b, double width_m, bool closed, const Vec2& preferred_m) {
  doors_.push_back({a, b, width_m, closed, preferred_m});
}

void Layout::set_open(int a, int b) {
  Rule r;
  r.open = true;
  rules_[key_of(a, b)] = r;
}

void Layout::set_solid(int a, int b) { rules_[key_of(a, b)] = Rule{}; }

void Layout::set_glass(int a, int b, double sill_m, std::optional<double> head_m,
                       std::optional<Vec2> outward_normal) {
  Rule r;
  r.glass = true;
  r.sill_m = sill_m;
  r.head_m = head_m;
  r.outward_normal = outward_normal;
  if (b == kOutside) {
    facades_[a].push_back(r);
  } else if (a == kOutside) {
    facades_[b].push_back(r);
  } else {
    rules_[key_of(a, b)] = r;
  }
}

void Layout::add_free_wall(const std::string& id, Wall wall) {
  wall.id = id;
  free_walls_.push_back(std::move(wall));
}

void Layout::add_obstacle(const std::string& name, ObstacleKind kind, const Vec2& center_m, const Vec2& size_m,
                          double yaw_rad, double height_m) {
  Obstacle o;
  o.kind = kind;
  o.center_m = center_m;
  o.size_m = size_m;
  o.yaw_rad = yaw_rad;
  o.height_m = height_m;
  obstacles_.push_back({name, o});
}

namespace {

struct WallSpec {
  int kind = 0;  // 0 none (open), 1 solid, 2 glass
  bool exterior = false;
  double thickness_m = 0.0;
  double sill_m = 0.0;
  std::optional<double> head_m;

  bool operator==(const WallSpec& o) const {
    return kind == o.kind && exterior == o.exterior && thickness_m == o.thickness_m && sill_m == o.sill_m &&
           head_m == o.head_m;
  }
  bool operator!=(const WallSpec& o) const { return !(*this == o); }
};

/// A maximal stretch of one line where the same two rooms face each other through one wall.
struct Run {
  int wall = -1;          // index into plan.walls
  double t0 = 0.0, t1 = 0.0;
  Vec2 origin = Vec2::Zero();
  Vec2 dir = Vec2::Zero();
  Vec2 normal_from_first = Vec2::Zero();  // unit normal pointing from key.first's side to key.second's
};

struct Span {
  double t0, t1;
};

/// Points of [lo, hi] not inside any of the open intervals `forbidden`.
std::vector<Span> allowed_spans(double lo, double hi, std::vector<Span> forbidden) {
  std::vector<Span> out;
  if (lo > hi) return out;
  std::sort(forbidden.begin(), forbidden.end(), [](const Span& a, const Span& b) { return a.t0 < b.t0; });
  double cursor = lo;
  for (const Span& f : forbidden) {
    if (f.t1 <= cursor) continue;
    if (f.t0 >= hi) break;
    if (f.t0 >= cursor) out.push_back({cursor, f.t0});
    cursor = std::max(cursor, f.t1);
  }
  if (cursor <= hi) out.push_back({cursor, hi});
  return out;
}

}  // namespace

GeneratedBuilding Layout::assemble(const std::string& name) const {
  const BuildingStyle& st = style_;

  // ---- 1. Edges grouped by line.
  struct Edge {
    int room;
    Vec2 p, q, u, n;
  };
  std::vector<Edge> edges;
  for (std::size_t r = 0; r < rooms_.size(); ++r) {
    const auto& poly = rooms_[r].polygon_m;
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const Vec2 p = poly[i], q = poly[(i + 1) % poly.size()];
      const double len = (q - p).norm();
      if (len < 1e-6) continue;
      const Vec2 u = (q - p) / len;
      edges.push_back({static_cast<int>(r), p, q, u, Vec2(-u.y(), u.x())});
    }
  }
  UnionFind sets(edges.size());
  for (std::size_t i = 0; i < edges.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      const Edge& a = edges[i];
      const Edge& b = edges[j];
      if (std::abs(cross(a.u, b.u)) > 1e-6) continue;
      if (std::abs(a.n.dot(b.p - a.p)) > 1e-5 || std::abs(a.n.dot(b.q - a.p)) > 1e-5) continue;
      sets.unite(static_cast<int>(i), static_cast<int>(j));
    }
  }
  std::map<int, std::vector<int>> clusters;  // root (smallest edge index) -> edges
  for (std::size_t i = 0; i < edges.size(); ++i) clusters[sets.find(static_cast<int>(i))].push_back(static_cast<int>(i));

  FloorPlan plan;
  plan.name = name;
  std::map<std::pair<int, int>, std::vector<Run>> runs;
  std::vector<std::vector<Span>> openings;  // per wall, in its line's parameter

  auto spec_for = [&](int left, int right, const Vec2& n_left_to_right) {
    WallSpec s;
    if (left == kOutside || right == kOutside) {
      const int room = left == kOutside ? right : left;
      const Vec2 outward = left == kOutside ? Vec2(-n_left_to_right) : n_left_to_right;
      s.kind = 1;
      s.exterior = true;
      s.thickness_m = st.exterior_thickness_m;
      auto it = facades_.find(room);
      if (it != facades_.end()) {
        for (const Rule& r : it->second) {
          if (r.outward_normal && outward.dot(*r.outward_normal) < 0.99) continue;
          s.kind = 2;
          s.thickness_m = st.glass_thickness_m;
          s.sill_m = r.sill_m;
          s.head_m = r.head_m;
          break;
        }
      }
      return s;
    }
    auto it = rules_.find(key_of(left, right));
    const std::string& kind_l = rooms_[static_cast<std::size_t>(left)].kind;
    const std::string& kind_r = rooms_[static_cast<std::size_t>(right)].kind;
    const bool hall_l = kind_l == "hallway", hall_r = kind_r == "hallway";
    const bool circ_l = hall_l || is_circulation(kind_l), circ_r = hall_r || is_circulation(kind_r);
    if (it != rules_.end()) {
      if (it->second.open) return s;  // kind 0
      if (it->second.glass) {
        s.kind = 2;
        s.thickness_m = st.glass_thickness_m;
        s.sill_m = it->second.sill_m;
        s.head_m = it->second.head_m;
        return s;
      }
    } else if (hall_l && hall_r) {
      return s;  // hallway pieces join openly unless told otherwise
    }
    s.kind = 1;
    s.thickness_m = (circ_l || circ_r) ? st.corridor_wall_thickness_m : st.partition_thickness_m;
    return s;
  };

  // +1 if doors between `left` and `right` should swing into `left`, -1 into `right`, 0 either.
  auto swing_preference = [this](int left, int right) {
    if (left == kOutside) return 1.0;
    if (right == kOutside) return -1.0;
    const bool circ_l = is_circulation(rooms_[static_cast<std::size_t>(left)].kind);
    const bool circ_r = is_circulation(rooms_[static_cast<std::size_t>(right)].kind);
    if (circ_l == circ_r) return 0.0;
    return circ_l ? -1.0 : 1.0;
  };

  int wall_counter = 0;
  for (const auto& [root, members] : clusters) {
    (void)root;
    const Edge& ref = edges[static_cast<std::size_t>(members.front())];
    const Vec2 o = ref.p, d = ref.u, n = ref.n;
    struct Entry {
      double t0, t1;
      int room;
      bool left;
    };
    std::vector<Entry> entries;
    std::vector<double> ts;
    for (int ei : members) {
      const Edge& e = edges[static_cast<std::size_t>(ei)];
      const double tp = d.dot(e.p - o), tq = d.dot(e.q - o);
      // Rooms are counter-clockwise: the interior is on the left of p->q.
      entries.push_back({std::min(tp, tq), std::max(tp, tq), e.room, e.u.dot(d) > 0.0});
      ts.push_back(tp);
      ts.push_back(tq);
    }
    std::sort(ts.begin(), ts.end());
    std::vector<double> breaks;
    for (double t : ts) {
      if (breaks.empty() || t - breaks.back() > 1e-6) breaks.push_back(t);
    }

    struct Piece {
      double t0, t1;
      int left, right;
      WallSpec spec;
    };
    std::vector<Piece> pieces;
    for (std::size_t k = 0; k + 1 < breaks.size(); ++k) {
      const double a = breaks[k], b = breaks[k + 1], mid = 0.5 * (a + b);
      int left = -2, right = -2;
      for (const Entry& e : entries) {
        if (!(e.t0 < mid && e.t1 > mid)) continue;
        int& slot = e.left ? left : right;
        if (slot != -2) {
          throw std::logic_error("generator: rooms " + rooms_[static_cast<std::size_t>(slot)].id + " and " +
                                 rooms_[static_cast<std::size_t>(e.room)].id + " overlap");
        }
        slot = e.room;
      }
      if (left == -2 && right == -2) continue;
      if (left == -2) left = kOutside;
      if (right == -2) right = kOutside;
      if (left == right) throw std::logic_error("generator: room " + rooms_[static_cast<std::size_t>(left)].id + " touches itself");
      // n points to the left side; from left to right is -n.
      pieces.push_back({a, b, left, right, spec_for(left, right, -n)});
    }

    // Merge consecutive pieces with the same wall kind into walls.
    std::size_t i = 0;
    while (i < pieces.size()) {
      if (pieces[i].spec.kind == 0) {
        ++i;
        continue;
      }
      std::size_t j = i + 1;
      while (j < pieces.size() && pieces[j].spec == pieces[i].spec && std::abs(pieces[j].t0 - pieces[j - 1].t1) < 1e-9) ++j;
      const WallSpec& s = pieces[i].spec;
      Wall w;
      ++wall_counter;
      w.id = (s.kind == 2 ? "glass" : s.exterior ? "ext" : "wall") + std::to_string(wall_counter);
      w.a_m = round4(o + pieces[i].t0 * d);
      w.b_m = round4(o + pieces[j - 1].t1 * d);
      w.thickness_m = s.thickness_m;
      if (s.kind == 2) {
        w.material = WallMaterial::kGlass;
        w.glass_sill_m = s.sill_m;
        w.glass_head_m = s.head_m;
      }
      // Orient the wall so that its doors (drawn swinging to the left of a->b) open into rooms
      // rather than hallways, and out of the building for exterior doors.
      double left_score = 0.0;
      for (std::size_t k = i; k < j; ++k) {
        left_score += (pieces[k].t1 - pieces[k].t0) * swing_preference(pieces[k].left, pieces[k].right);
      }
      if (left_score < 0.0) std::swap(w.a_m, w.b_m);
      const int wall_index = static_cast<int>(plan.walls.size());
      plan.walls.push_back(std::move(w));
      openings.emplace_back();
      // Runs per room pair inside this wall.
      std::size_t k = i;
      while (k < j) {
        std::size_t m = k + 1;
        while (m < j && pieces[m].left == pieces[k].left && pieces[m].right == pieces[k].right) ++m;
        const auto key = key_of(pieces[k].left, pieces[k].right);
        Run run;
        run.wall = wall_index;
        run.t0 = pieces[k].t0;
        run.t1 = pieces[m - 1].t1;
        run.origin = o;
        run.dir = d;
        run.normal_from_first = key.first == pieces[k].left ? Vec2(-n) : n;
        runs[key].push_back(run);
        k = m;
      }
      i = j;
    }
  }

  // ---- 2. Doors.
  std::map<std::string, int> used_ids;
  auto unique_id = [&used_ids](const std::string& base) {
    const int count = used_ids[base]++;
    return count == 0 ? base : base + "_" + std::to_string(count + 1);
  };
  auto room_name = [this](int r) { return r == kOutside ? std::string("outside") : rooms_[static_cast<std::size_t>(r)].id; };
  for (const LayoutRoom& r : rooms_) used_ids[r.id] = 1;  // never reuse a room id for an element
  for (const Wall& w : plan.walls) used_ids[w.id] = 1;

  const double door_gap = 0.3;  // solid wall between two openings of one wall
  for (const DoorRequest& req : doors_) {
    const auto key = key_of(req.a, req.b);
    auto it = runs.find(key);
    if (it == runs.end()) {
      throw std::logic_error("generator: door between " + room_name(req.a) + " and " + room_name(req.b) +
                             ": the rooms share no wall");
    }
    const double w = req.width_m;
    double best_dist = std::numeric_limits<double>::infinity();
    const Run* best_run = nullptr;
    double best_t = 0.0;
    for (const Run& run : it->second) {
      const double lo = run.t0 + st.door_jamb_m + 0.5 * w, hi = run.t1 - st.door_jamb_m - 0.5 * w;
      std::vector<Span> forbidden;
      for (const Span& s : openings[static_cast<std::size_t>(run.wall)]) {
        forbidden.push_back({s.t0 - door_gap - 0.5 * w, s.t1 + door_gap + 0.5 * w});
      }
      const double tp = run.dir.dot(req.preferred_m - run.origin);
      for (const Span& a : allowed_spans(lo, hi, forbidden)) {
        const double t = std::clamp(tp, a.t0, a.t1);
        const double dist = (run.origin + t * run.dir - req.preferred_m).norm();
        if (dist < best_dist - 1e-9) {
          best_dist = dist;
          best_run = &run;
          best_t = t;
        }
      }
    }
    if (!best_run) {
      std::string runs_text;
      for (const Run& run : it->second) {
        const Vec2 p0 = run.origin + run.t0 * run.dir, p1 = run.origin + run.t1 * run.dir;
        runs_text += " (" + std::to_string(p0.x()) + "," + std::to_string(p0.y()) + ")-(" + std::to_string(p1.x()) +
                     "," + std::to_string(p1.y()) + ") with " +
                     std::to_string(openings[static_cast<std::size_t>(run.wall)].size()) + " openings on its wall;";
      }
      throw std::logic_error("generator: door (" + std::to_string(w) + " m) between " + room_name(req.a) + " and " +
                             room_name(req.b) + " does not fit in their shared wall:" + runs_text);
    }
    openings[static_cast<std::size_t>(best_run->wall)].push_back({best_t - 0.5 * w, best_t + 0.5 * w});
    Door door;
    door.id = unique_id("door_" + room_name(req.a) + "_" + room_name(req.b));
    door.wall_id = plan.walls[static_cast<std::size_t>(best_run->wall)].id;
    door.center_m = round4(best_run->origin + best_t * best_run->dir);
    door.width_m = w;
    door.closed = req.closed;
    plan.doors.push_back(std::move(door));
  }

  // ---- 3. Windows on exterior solid runs.
  for (std::size_t r = 0; r < rooms_.size(); ++r) {
    const WindowSpec& ws = rooms_[r].windows;
    if (ws.width_m <= 0.0) continue;
    auto it = runs.find(key_of(kOutside, static_cast<int>(r)));
    if (it == runs.end()) continue;
    int count = 0;
    for (const Run& run : it->second) {
      const Wall& wall = plan.walls[static_cast<std::size_t>(run.wall)];
      if (wall.material != WallMaterial::kSolid) continue;
      std::vector<Span> forbidden;
      for (const Span& s : openings[static_cast<std::size_t>(run.wall)]) forbidden.push_back({s.t0 - ws.pier_m, s.t1 + ws.pier_m});
      for (const Span& a : allowed_spans(run.t0 + ws.margin_m, run.t1 - ws.margin_m, forbidden)) {
        const double len = a.t1 - a.t0;
        const int n = static_cast<int>(std::floor((len + ws.pier_m + 1e-9) / (ws.width_m + ws.pier_m)));
        if (n < 1) continue;
        const double total = n * ws.width_m + (n - 1) * ws.pier_m;
        double t = 0.5 * (a.t0 + a.t1) - 0.5 * total + 0.5 * ws.width_m;
        for (int k = 0; k < n; ++k, t += ws.width_m + ws.pier_m) {
          Window win;
          win.id = unique_id("win_" + rooms_[r].id + "_" + std::to_string(++count));
          win.wall_id = wall.id;
          win.center_m = round4(run.origin + t * run.dir);
          win.width_m = ws.width_m;
          win.sill_m = ws.sill_m;
          win.head_m = ws.head_m;
          openings[static_cast<std::size_t>(run.wall)].push_back({t - 0.5 * ws.width_m, t + 0.5 * ws.width_m});
          plan.windows.push_back(std::move(win));
        }
      }
    }
  }

  // ---- 4. Free-standing walls and obstacles.
  for (Wall w : free_walls_) {
    w.id = unique_id(w.id);
    w.a_m = round4(w.a_m);
    w.b_m = round4(w.b_m);
    plan.walls.push_back(std::move(w));
  }
  for (const ObstacleRequest& req : obstacles_) {
    Obstacle o = req.obstacle;
    o.id = unique_id(req.name);
    o.center_m = round4(o.center_m);
    o.size_m = round4(o.size_m);
    o.height_m = round4(o.height_m);
    plan.obstacles.push_back(std::move(o));
  }

  validate_floor_plan(plan, "generated building \"" + name + "\"");

  GeneratedBuilding out;
  out.plan = std::move(plan);
  for (const LayoutRoom& r : rooms_) {
    GeneratedRoom g;
    g.id = r.id;
    g.kind = r.kind;
    for (const Vec2& p : r.polygon_m) g.polygon_m.push_back(round4(p));
    out.rooms.push_back(std::move(g));
  }
  out.plan.rooms = out.rooms;  // the labels travel with the plan file (sampling by room kind)
  return out;
}

// ---- Rows of rooms ----------------------------------------------------------------------------

namespace {

/// Local-frame helper for a room with the hallway on one side: u runs along the hallway (x),
/// v is the depth measured from the hallway wall into the room.
struct RoomBox {
  const Frame& frame;
  double x0, y0, x1, y1;
  int facing;

  double width() const { return x1 - x0; }
  double depth() const { return y1 - y0; }
  /// Local y of depth v (0 at the hallway wall).
  double y_at(double v) const { return facing > 0 ? y1 - v : y0 + v; }
  Vec2 world(double u, double v) const { return frame.to_world(x0 + u, y_at(v)); }
};

void box(Layout& layout, const std::string& name, const RoomBox& b, double u, double v, double size_u,
         double size_v, double height) {
  layout.add_obstacle(name, ObstacleKind::kBox, b.world(u, v), Vec2(size_u, size_v), b.frame.yaw_rad, height);
}

}  // namespace

void furnish_room(Layout& layout, const std::string& room_id, const std::string& kind, const Frame& frame, double x0,
                  double y0, double x1, double y1, int facing, Rng& rng) {
  const RoomBox b{frame, x0, y0, x1, y1, facing};
  const double W = b.width(), D = b.depth();
  const double wall = 0.2;  // clearance from wall centrelines
  if (kind == "office") {
    if (W < 2.4 || D < 3.5) return;
    const double du = rng.uniform(-0.3, 0.3);
    box(layout, room_id + "_desk", b, 0.5 * W + du, D - wall - 0.45, std::min(1.6, W - 0.8), 0.8, 0.75);
    const bool left = rng.bernoulli(0.5);
    box(layout, room_id + "_cabinet", b, left ? wall + 0.25 : W - wall - 0.25, 0.55 * D + 0.3, 0.45, 1.2, 1.9);
  } else if (kind == "meeting") {
    if (W < 3.5 || D < 3.5) return;
    box(layout, room_id + "_table", b, 0.5 * W, 0.55 * D, W - 2.0, std::min(1.2, D - 2.6), 0.75);
  } else if (kind == "classroom") {
    if (W < 5.0 || D < 5.0) return;
    for (double v = 2.0; v + 0.6 < D - 1.3; v += 1.4) {
      box(layout, room_id + "_desks", b, 0.5 * W + 0.3, v, W - 2.2, 0.6, 0.75);
    }
    box(layout, room_id + "_lectern", b, 0.5 * W, D - wall - 0.8, 1.4, 0.7, 0.9);
  } else if (kind == "lab") {
    if (W < 5.0 || D < 5.0) return;
    const double len = D - 2.8;
    for (double u = 1.6; u < W - 1.4; u += 2.6) box(layout, room_id + "_bench", b, u, 1.6 + 0.5 * len, 0.9, len, 0.9);
  } else if (kind == "storage") {
    if (D < 2.0 || W < 1.4) return;
    box(layout, room_id + "_shelf", b, W - wall - 0.25, 0.5 * D + 0.5, 0.5, D - 1.6, 2.0);
  } else if (kind == "lounge") {
    if (W < 3.0 || D < 3.0) return;
    box(layout, room_id + "_sofa", b, 0.5 * W, D - wall - 0.5, std::min(2.2, W - 1.0), 0.9, 0.8);
    layout.add_obstacle(room_id + "_table", ObstacleKind::kPillar, b.world(0.5 * W, D - 2.0), Vec2(0.8, 0.8), 0.0, 0.7);
  } else if (kind == "toilet") {
    if (W < 2.0 || D < 3.0) return;
    box(layout, room_id + "_counter", b, 0.5 * W, wall + 0.3 + 1.2, W - 1.6 > 0.8 ? W - 1.6 : 0.8, 0.55, 0.85);
    // Cubicle partitions (2 m high) along the back wall.
    for (double u = 1.0; u < W - 0.6; u += 1.0) {
      box(layout, room_id + "_cubicle", b, u, D - wall - 0.75, 0.05, 1.5, 2.0);
    }
  } else if (kind == "kitchen") {
    if (W < 2.4 || D < 3.0) return;
    box(layout, room_id + "_counter", b, 0.5 * W, D - wall - 0.3, W - 2.0 * wall - 0.1, 0.6, 0.9);
    layout.add_obstacle(room_id + "_table", ObstacleKind::kPillar, b.world(0.5 * W, 0.5 * D), Vec2(0.9, 0.9), 0.0, 0.75);
  } else if (kind == "cafeteria") {
    for (double v = 2.5; v < D - 1.5; v += 2.4) {
      for (double u = 2.0; u < W - 1.5; u += 3.0) {
        box(layout, room_id + "_table", b, u, v, 1.8, 0.8, 0.75);
      }
    }
  }
}

void add_stairs(Layout& layout, const std::string& name, const Frame& frame, double x0, double y0, double x1,
                double y1) {
  // Two flights side by side along the longer axis, a landing at each end of it.
  const bool along_x = (x1 - x0) >= (y1 - y0);
  const double len = along_x ? x1 - x0 : y1 - y0;
  const double wid = along_x ? y1 - y0 : x1 - x0;
  const double inset = 0.2;
  const double landing = std::min(1.5, 0.25 * len);
  const double flight_len = len - 2.0 * landing - 2.0 * inset;
  const double flight_w = 0.5 * (wid - 2.0 * inset) - 0.1;
  if (flight_len < 1.0 || flight_w < 0.6) return;
  const double c_len = 0.5 * len;
  for (int k = 0; k < 2; ++k) {
    const double c_w = inset + 0.5 * flight_w + k * (flight_w + 0.2);
    const Vec2 local = along_x ? Vec2(x0 + c_len, y0 + c_w) : Vec2(x0 + c_w, y0 + c_len);
    const Vec2 size = along_x ? Vec2(flight_len, flight_w) : Vec2(flight_w, flight_len);
    layout.add_obstacle(name + "_flight", ObstacleKind::kBox, frame.to_world(local.x(), local.y()), size,
                        frame.yaw_rad, 1.1);
  }
}

namespace {

/// Draw from equal-probability quantiles q[0] (u = 0) .. q[n-1] (u = 1), linear in between.
double draw_quantiles(const std::vector<double>& q, double u) {
  if (q.empty()) return 0.0;
  if (q.size() == 1) return q.front();
  const double pos = u * static_cast<double>(q.size() - 1);
  const std::size_t lo = std::min(static_cast<std::size_t>(pos), q.size() - 2);
  return q[lo] + (pos - static_cast<double>(lo)) * (q[lo + 1] - q[lo]);
}

/// The hallway (piece) in front of local x interval [xa, xb] of a strip.
int hallway_in_front(const RowStrip& s, double xa, double xb) {
  if (s.hallway_pieces.empty()) return s.hallway;
  std::size_t best = 0;
  double best_overlap = -1e300;
  for (std::size_t m = 0; m < s.hallway_pieces.size(); ++m) {
    const double p0 = s.hallway_pieces[m].first;
    const double p1 = m + 1 < s.hallway_pieces.size() ? s.hallway_pieces[m + 1].first : 1e300;
    const double o = std::min(xb, p1) - std::max(xa, p0);
    if (o > best_overlap) {
      best_overlap = o;
      best = m;
    }
  }
  return s.hallway_pieces[best].second;
}

/// fill_row with RoomVariety: widths from the real room-area distribution, door recesses, outline
/// notches, suites and a dead-end stub.
std::vector<int> fill_row_varied(Layout& layout, const RowStrip& s, const RowFill& f, const RoomVariety& v,
                                 Rng& rng) {
  const BuildingStyle& st = layout.style();
  std::vector<int> out;
  const double len = s.x1 - s.x0;
  const double depth = s.y1 - s.y0;
  if (len <= 1e-6) return out;
  const double w_door = st.door_width_m;
  const double wmin = v.room_width_min_m;

  // A dead-end stub across the row, splitting it into two runs of rooms.
  struct Piece {
    double x0, x1;
    bool stub;
  };
  std::vector<Piece> pieces;
  const double stub_w = snap(rng.uniform(v.stub_width_min_m, v.stub_width_max_m), 0.1);
  const bool want_stub = rng.bernoulli(v.stub_probability) && len >= stub_w + 4.0 * wmin && depth >= 3.0;
  if (want_stub) {
    const double sx0 = snap(rng.uniform(s.x0 + 2.0 * wmin, s.x1 - 2.0 * wmin - stub_w), 0.1);
    pieces.push_back({s.x0, sx0, false});
    pieces.push_back({sx0, sx0 + stub_w, true});
    pieces.push_back({sx0 + stub_w, s.x1, false});
  } else {
    pieces.push_back({s.x0, s.x1, false});
  }

  const double hall_y = s.facing > 0 ? s.y1 : s.y0;
  int counter = 0;
  for (const Piece& piece : pieces) {
    if (piece.stub) {
      const std::string id = s.id_prefix + ".stub";
      out.push_back(layout.add_rect(id, "hallway", s.frame, piece.x0, s.y0, piece.x1, s.y1,
                                    s.far_side_is_facade ? hallway_end_windows(st) : no_windows()));
      continue;
    }
    // Widths: area / depth from the real distribution; the last room takes what is left.
    std::vector<double> widths;
    const double plen = piece.x1 - piece.x0;
    double used = 0.0;
    while (plen - used > 1e-6) {
      const double area = draw_quantiles(v.room_area_quantiles_m2, rng.uniform01());
      double w = snap(std::clamp(area / depth, wmin, v.room_width_max_m), 0.1);
      const double rest = plen - used;
      if (rest - w < wmin) w = rest;
      widths.push_back(w);
      used += w;
    }
    int prev_room = -1;
    double x = piece.x0;
    for (std::size_t i = 0; i < widths.size(); ++i) {
      const double xa = x, xb = (i + 1 == widths.size()) ? piece.x1 : x + widths[i];
      x = xb;
      const double w = xb - xa;
      std::string kind = w < 2.6 ? "storage" : w <= 7.0 ? f.kind_single : w <= 11.0 ? f.kind_double : f.kind_triple;
      char buf[16];
      std::snprintf(buf, sizeof buf, "%02d", ++counter);
      const std::string id = s.id_prefix + "." + buf;
      // Depth: a notch at the facade.
      double notch = 0.0;
      if (s.far_side_is_facade && xa >= s.facade_from_x - 1e-9 && rng.bernoulli(v.notch_probability)) {
        notch = snap(rng.uniform(v.notch_depth_min_m, v.notch_depth_max_m), 0.1);
        if (depth - notch < 3.5) notch = 0.0;
      }
      // A recess on the hallway side holding the door.
      double ra = 0.0, rb = 0.0, rdep = 0.0;
      if (rng.bernoulli(v.recess_probability)) {
        const double rw = snap(rng.uniform(v.recess_width_min_m, v.recess_width_max_m), 0.1);
        const double rd = snap(rng.uniform(v.recess_depth_min_m, v.recess_depth_max_m), 0.1);
        // Flush with a partition or at least 1 m from both (no slivers of room beside it).
        const int where = rng.integer(0, 2);
        if (w >= rw + 1.0 && depth - notch - rd >= 2.5 && rw >= w_door + 2.0 * st.door_jamb_m + 0.1) {
          if (where == 0) {
            ra = xa;
            rb = xa + rw;
          } else if (where == 1 || w < rw + 2.0) {
            ra = xb - rw;
            rb = xb;
          } else {
            ra = std::clamp(snap(rng.uniform(xa + 1.0, xb - 1.0 - rw), 0.1), xa + 1.0, xb - 1.0 - rw);
            rb = ra + rw;
          }
          rdep = rd;
        }
      }
      // Local y of the hallway wall (h), the far wall (far) and the recess back (back).
      const double h = hall_y;
      const double far = s.facing > 0 ? s.y0 + notch : s.y1 - notch;
      const double back = s.facing > 0 ? h - rdep : h + rdep;
      std::vector<Vec2> poly;
      poly.push_back(s.frame.to_world(xa, far));
      poly.push_back(s.frame.to_world(xb, far));
      if (!(rdep > 0.0 && rb == xb)) poly.push_back(s.frame.to_world(xb, h));
      if (rdep > 0.0) {  // skip corners that coincide with the room's own (flush recess)
        if (rb != xb) poly.push_back(s.frame.to_world(rb, h));
        poly.push_back(s.frame.to_world(rb, back));
        poly.push_back(s.frame.to_world(ra, back));
        if (ra != xa) poly.push_back(s.frame.to_world(ra, h));
      }
      if (!(rdep > 0.0 && ra == xa)) poly.push_back(s.frame.to_world(xa, h));
      const bool glass = kind == f.kind_double && rng.bernoulli(v.glass_wall_probability);
      if (glass) kind = "meeting";
      const int room = layout.add_room(id, kind, poly, s.windows);
      out.push_back(room);
      const int hall = hallway_in_front(s, xa, xb);
      const bool closed = kind == "storage" || rng.bernoulli(st.room_door_closed_probability);
      const bool suite = prev_room >= 0 && rng.bernoulli(v.suite_probability);
      if (rdep > 0.0) {
        const int recess =
            layout.add_rect(id + "_alcove", "hallway", s.frame, ra, std::min(h, back), rb, std::max(h, back), no_windows());
        layout.add_door(room, recess, w_door, closed, s.frame.to_world(0.5 * (ra + rb), back));
      } else if (suite) {
        layout.add_door(room, prev_room, w_door, closed, s.frame.to_world(xa, 0.5 * (h + far)));
      } else {
        const double inset = st.door_jamb_m + 0.2 + 0.5 * w_door;
        const double xd = w > 2.0 * inset ? snap(rng.uniform(xa + inset, xb - inset), 0.05) : 0.5 * (xa + xb);
        layout.add_door(room, hall, std::min(w_door, w - 2.0 * st.door_jamb_m - 0.05), closed, s.frame.to_world(xd, h));
        if (w > 7.0) {  // large rooms: a second door
          const double xd2 = xd - xa > 0.5 * w ? xa + inset : xb - inset;
          layout.add_door(room, hall, w_door, rng.bernoulli(st.room_door_closed_probability), s.frame.to_world(xd2, h));
        }
      }
      if (glass && rdep <= 0.0) layout.set_glass(room, hall);
      if (st.furniture) {
        // Furniture in the part of the room behind the recess line and inside the notch.
        const double fy0 = s.facing > 0 ? far : back;
        const double fy1 = s.facing > 0 ? back : far;
        furnish_room(layout, id, kind, s.frame, xa, fy0, xb, fy1, s.facing, rng);
      }
      prev_room = room;
    }
  }
  return out;
}

}  // namespace

std::vector<int> fill_row(Layout& layout, const RowStrip& s, const RowFill& f, Rng& rng) {
  if (f.variety && f.variety->enabled) return fill_row_varied(layout, s, f, *f.variety, rng);
  const BuildingStyle& st = layout.style();
  const double len = s.x1 - s.x0;
  std::vector<int> out;
  if (len <= 1e-6) return out;  // any longer strip becomes rooms: never leave a hole
  const int units = static_cast<int>(std::floor((len + 1e-9) / f.module_m));
  std::vector<int> groups;
  for (int remaining = units; remaining > 0;) {
    const double r = rng.uniform01();
    int g = 1;
    if (r < f.p_triple && remaining >= 3) g = 3;
    else if (r < f.p_triple + f.p_double && remaining >= 2) g = 2;
    groups.push_back(g);
    remaining -= g;
  }
  std::vector<double> widths;
  for (int g : groups) widths.push_back(g * f.module_m);
  const double leftover = len - units * f.module_m;
  int storage_index = -1;
  if (widths.empty()) {  // shorter than a module: one room (named like a leftover)
    widths.push_back(len);
    groups.push_back(0);
  } else if (leftover < f.min_room_m) {
    widths.back() += leftover;
  } else {
    const bool at_start = rng.bernoulli(0.5);
    storage_index = at_start ? 0 : static_cast<int>(widths.size());
    widths.insert(widths.begin() + storage_index, leftover);
    groups.insert(groups.begin() + storage_index, 0);
  }

  const double hall_y = s.facing > 0 ? s.y1 : s.y0;
  // The hallway (piece) a door at local x between xa and xb should open into.
  auto hallway_for = [&s, &st](double x_door, double xa, double xb, double width) {
    if (s.hallway_pieces.empty()) return s.hallway;
    std::size_t k = 0;
    while (k + 1 < s.hallway_pieces.size() && s.hallway_pieces[k + 1].first <= x_door) ++k;
    auto overlap = [&](std::size_t m) {
      const double p0 = s.hallway_pieces[m].first;
      const double p1 = m + 1 < s.hallway_pieces.size() ? s.hallway_pieces[m + 1].first : 1e300;
      return std::min(xb, p1) - std::max(xa, p0);
    };
    if (overlap(k) >= width + 2.0 * st.door_jamb_m + 0.05) return s.hallway_pieces[k].second;
    std::size_t best = k;
    for (std::size_t m = 0; m < s.hallway_pieces.size(); ++m) {
      if (overlap(m) > overlap(best)) best = m;
    }
    return s.hallway_pieces[best].second;
  };
  const double w_door = st.door_width_m;
  const double door_inset = st.door_jamb_m + 0.35 + 0.5 * w_door;  // from the partition to the door centre
  double x = s.x0;
  for (std::size_t i = 0; i < widths.size(); ++i) {
    const double xa = x, xb = (i + 1 == widths.size()) ? s.x1 : x + widths[i];
    x = xb;
    const int g = groups[i];
    // A leftover narrower than a module: a small office if it is wide enough, else storage.
    std::string kind = g == 0   ? (xb - xa >= 2.8 ? f.kind_single : "storage")
                       : g == 1 ? f.kind_single
                       : g == 2 ? f.kind_double
                                : f.kind_triple;
    const bool glass = g == 2 && rng.bernoulli(f.glass_double_probability);
    if (glass) kind = "meeting";
    char buf[16];
    std::snprintf(buf, sizeof buf, "%02d", static_cast<int>(i + 1));
    const std::string id = s.id_prefix + "." + buf;
    const int room = layout.add_rect(id, kind, s.frame, xa, s.y0, xb, s.y1, s.windows);
    out.push_back(room);
    const bool mirrored = (i % 2) == 1;
    auto door = [&](double xd, double width, bool closed) {
      layout.add_door(room, hallway_for(xd, xa, xb, width), width, closed, s.frame.to_world(xd, hall_y));
    };
    if (glass) layout.set_glass(room, hallway_for(0.5 * (xa + xb), xa, xb, w_door));
    if (g == 0) {
      door(0.5 * (xa + xb), std::min(w_door, 0.8), kind == "storage" || rng.bernoulli(st.room_door_closed_probability));
    } else if (g == 3) {
      door(xa + door_inset, w_door, rng.bernoulli(st.room_door_closed_probability));
      door(xb - door_inset, w_door, rng.bernoulli(st.room_door_closed_probability));
    } else {
      door(mirrored ? xa + door_inset : xb - door_inset, w_door, rng.bernoulli(st.room_door_closed_probability));
    }
    if (st.furniture) furnish_room(layout, id, kind, s.frame, xa, s.y0, xb, s.y1, s.facing, rng);
  }
  return out;
}

int add_facing_room(Layout& layout, const std::string& id, const std::string& kind, const Frame& frame, double x0,
                    double y0, double x1, double y1, int facing, int hallway, const WindowSpec& windows,
                    double door_x, double door_width_m, bool closed, Rng& rng) {
  const int room = layout.add_rect(id, kind, frame, x0, y0, x1, y1, windows);
  layout.add_door(room, hallway, door_width_m, closed, frame.to_world(door_x, facing > 0 ? y1 : y0));
  if (layout.style().furniture) furnish_room(layout, id, kind, frame, x0, y0, x1, y1, facing, rng);
  return room;
}

bool StripReservations::fits(double x0, double x1) const {
  if (x1 <= x0) return false;
  return fits_interval(x0, x1);
}

bool StripReservations::cut(double x) {
  if (x <= x0_ || x >= x1_ || !fits_interval(x, x)) return false;
  taken_.push_back({x, x});
  return true;
}

bool StripReservations::fits_interval(double x0, double x1) const {
  const double eps = 1e-6;
  if (x0 < x0_ - eps || x1 > x1_ + eps) return false;
  std::vector<Interval1> all = taken_;
  all.push_back({x0, x1});
  std::sort(all.begin(), all.end(), [](const Interval1& a, const Interval1& b) { return a.x0 < b.x0; });
  double cursor = x0_;
  for (const Interval1& t : all) {
    const double gap = t.x0 - cursor;
    if (gap < -eps) return false;
    if (gap > eps && gap < min_gap_m_) return false;
    cursor = t.x1;
  }
  const double tail = x1_ - cursor;
  return !(tail > eps && tail < min_gap_m_);
}

bool StripReservations::reserve(double x0, double x1) {
  if (!fits(x0, x1)) return false;
  taken_.push_back({x0, x1});
  return true;
}

std::vector<Interval1> StripReservations::free_intervals() const {
  std::vector<Interval1> all = taken_;
  std::sort(all.begin(), all.end(), [](const Interval1& a, const Interval1& b) { return a.x0 < b.x0; });
  std::vector<Interval1> out;
  double cursor = x0_;
  for (const Interval1& t : all) {
    if (t.x0 - cursor > 1e-6) out.push_back({cursor, t.x0});
    cursor = t.x1;
  }
  if (x1_ - cursor > 1e-6) out.push_back({cursor, x1_});
  return out;
}

}  // namespace floorcast::generate_detail
