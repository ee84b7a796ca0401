// The floor-plan model: walls, doors, windows/glass, clutter obstacles. Units: metres.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "floorcast/core/types.hpp"

namespace floorcast {

enum class WallMaterial { kSolid, kGlass };

/// A straight wall: the rectangle of width thickness_m centred on segment a_m-b_m.
struct Wall {
  std::string id;
  Vec2 a_m = Vec2::Zero();
  Vec2 b_m = Vec2::Zero();
  double thickness_m = 0.15;
  WallMaterial material = WallMaterial::kSolid;
  /// Glass walls only: the glass panel spans [glass_sill_m, glass_head_m] above the floor; solid
  /// wall below the sill and above the head. Without a head the glass reaches the ceiling.
  double glass_sill_m = 0.0;
  std::optional<double> glass_head_m;

  Segment2 centerline() const { return {a_m, b_m}; }
  double length_m() const { return (b_m - a_m).norm(); }
  /// Unit direction a->b.
  Vec2 direction() const { return (b_m - a_m) / length_m(); }
};

/// A door opening in a wall. Its span is centred on the projection of center_m onto the wall.
struct Door {
  std::string id;
  std::string wall_id;
  Vec2 center_m = Vec2::Zero();
  double width_m = 0.9;
  bool closed = false;
};

/// A glass window in a (solid) wall, spanning [sill_m, head_m] above the floor.
struct Window {
  std::string id;
  std::string wall_id;
  Vec2 center_m = Vec2::Zero();
  double width_m = 1.2;
  double sill_m = 0.9;
  double head_m = 2.1;
};

enum class ObstacleKind { kBox, kPillar };

/// Clutter standing on the floor: an oriented box (size = width along the box's x, depth along
/// its y) or a round pillar (size.x() = diameter).
struct Obstacle {
  std::string id;
  ObstacleKind kind = ObstacleKind::kBox;
  Vec2 center_m = Vec2::Zero();
  Vec2 size_m = Vec2(1.0, 1.0);
  double yaw_rad = 0.0;
  double height_m = 1.0;
};

/// A labelled space of the plan: a room, corridor, lobby, ... (what a generator laid out or an
/// importer read from OSM indoor=* / IMDF unit categories). Not geometry a sensor sees: walls do
/// that. Rooms label the free space, e.g. to sample observation points in transitional spaces.
/// Rooms may nest (an OSM level outline around its rooms): a point belongs to the smallest room
/// containing it (rooms.hpp).
struct Room {
  std::string id;
  std::string kind;                        ///< "hallway", "corridor", "office", "walkway", ...
  std::vector<Vec2> polygon_m;             ///< outer boundary (any orientation, not closed)
  std::vector<std::vector<Vec2>> holes_m;  ///< inner boundaries (courtyards, shafts)
};

struct FloorPlan {
  static constexpr int kFormatVersion = 1;

  std::string name;
  int level = 0;
  std::vector<Wall> walls;
  std::vector<Door> doors;
  std::vector<Window> windows;
  std::vector<Obstacle> obstacles;
  /// Optional room labels (ids unique among rooms; not part of the geometry).
  std::vector<Room> rooms;

  /// Index of the wall with this id, or -1.
  int wall_index(const std::string& wall_id) const;
};

/// An opening (door or window) resolved onto its wall: arc-length interval [t0_m, t1_m] along
/// the wall from a_m.
struct OpeningSpan {
  int wall_index = -1;
  double t0_m = 0.0;
  double t1_m = 0.0;
};

/// Resolves a door or window centre onto its wall (projection onto the centreline).
OpeningSpan opening_span(const FloorPlan& plan, const std::string& wall_id, const Vec2& center_m,
                         double width_m);
/// The same for the wall at `wall_index` (from a WallIdIndex; -1 gives an unresolved span).
OpeningSpan opening_span(const FloorPlan& plan, int wall_index, const Vec2& center_m, double width_m);

/// Wall positions by id, built once, for code that looks up many (FloorPlan::wall_index scans
/// every wall: one lookup per door on a plan of 1,000,000 walls was 1e10 steps). The first wall
/// of an id wins, as with wall_index.
class WallIdIndex {
 public:
  explicit WallIdIndex(const FloorPlan& plan);
  /// Position of the wall with this id in plan.walls, or -1.
  int find(const std::string& wall_id) const;

 private:
  std::unordered_map<std::string, int> index_;
};

/// Axis-aligned bounding box of all wall rectangles and obstacles: [xmin, ymin, xmax, ymax].
Eigen::Vector4d plan_bbox_m(const FloorPlan& plan);

/// Counts used by `floorcast plan info`.
struct PlanCounts {
  int walls = 0;
  int glass_walls = 0;
  int doors = 0;
  int doors_closed = 0;
  int windows = 0;
  int obstacles = 0;
};
PlanCounts plan_counts(const FloorPlan& plan);

/// Stable 64-bit FNV-1a hash of the plan's canonical JSON; used as a cache key.
std::uint64_t plan_hash(const FloorPlan& plan);

}  // namespace floorcast
