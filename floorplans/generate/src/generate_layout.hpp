// Internal to the generator: seeded random numbers, exact rotations, and the layout assembler
// that turns room polygons + connections into walls, doors and windows.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "floorcast/floorplans/generate.hpp"

namespace floorcast::generate_detail {

/// splitmix64: a tiny, well-mixed 64-bit generator. Every draw is defined here bit for bit, so
/// the generated buildings never depend on the standard library.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next_u64();
  /// Uniform in [0, 1): the top 53 bits times 2^-53.
  double uniform01();
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi);
  /// Uniform integer in [lo, hi] (inclusive).
  int integer(int lo, int hi);
  bool bernoulli(double p);
  /// An independent stream derived from this generator's seed and `stream`.
  Rng fork(std::uint64_t stream) const;

 private:
  std::uint64_t state_;
};

/// Mixes a seed with an archetype/stream salt.
std::uint64_t mix_seed(std::uint64_t seed, std::uint64_t salt);

/// Rounds x to a multiple of q.
double snap(double x, double q);

/// A local frame: world = origin + x * (c, s) + y * (-s, c). Rotations come from exact constants.
struct Frame {
  Vec2 origin = Vec2::Zero();
  double c = 1.0;
  double s = 0.0;

  Vec2 to_world(double x, double y) const {
    return {origin.x() + x * c - y * s, origin.y() + x * s + y * c};
  }
  Vec2 direction(double x, double y) const { return {x * c - y * s, x * s + y * c}; }
  /// Angle of the local x axis, given the degrees it was built from.
  double yaw_rad = 0.0;
};

/// Frame rotated by a multiple of 15 degrees, cosine and sine from square roots only.
Frame rotated_frame(const Vec2& origin, int degrees);

constexpr int kOutside = -1;

/// How a room's exterior walls get windows (width 0 = no windows).
struct WindowSpec {
  double width_m = 0.0;
  double sill_m = 0.9;
  double head_m = 2.1;
  double pier_m = 1.0;
  double margin_m = 0.5;
};

/// Signed area of a polygon (positive when counter-clockwise), m^2.
double signed_area(const std::vector<Vec2>& poly);

WindowSpec standard_windows(const BuildingStyle& style);
WindowSpec small_windows(const BuildingStyle& style);    ///< bathrooms: narrow, high sill
WindowSpec hallway_end_windows(const BuildingStyle& style);
WindowSpec no_windows();

struct LayoutRoom {
  std::string id;
  std::string kind;
  std::vector<Vec2> polygon_m;  ///< counter-clockwise
  WindowSpec windows;
};

class Layout {
 public:
  explicit Layout(BuildingStyle style) : style_(std::move(style)) {}

  const BuildingStyle& style() const { return style_; }

  /// Adds a room (polygon in world coordinates, any orientation; stored counter-clockwise).
  int add_room(const std::string& id, const std::string& kind, std::vector<Vec2> polygon_m,
               const WindowSpec& windows);
  /// Adds the rectangle [x0, x1] x [y0, y1] of a local frame as a room.
  int add_rect(const std::string& id, const std::string& kind, const Frame& frame, double x0, double y0,
               double x1, double y1, const WindowSpec& windows);

  /// A door between rooms a and b (b may be kOutside), placed on their shared boundary as close
  /// to `preferred_m` as the wall junctions and other openings allow.
  void add_door(int a, int b, double width_m, bool closed, const Vec2& preferred_m);
  /// No wall between a and b (hallway junctions, open kitchens, lobbies).
  void set_open(int a, int b);
  /// A solid wall between a and b even where both are hallways (fire compartments).
  void set_solid(int a, int b);
  /// A glass partition between a and b (b may be kOutside: a glass facade). With b = kOutside,
  /// `outward_normal` restricts the facade to exterior edges facing that direction.
  void set_glass(int a, int b, double sill_m = 0.0, std::optional<double> head_m = std::nullopt,
                 std::optional<Vec2> outward_normal = std::nullopt);

  /// A free-standing wall (screens, partial partitions); id assigned at assembly.
  void add_free_wall(const std::string& id, Wall wall);
  /// A clutter obstacle; `name` is made unique at assembly.
  void add_obstacle(const std::string& name, ObstacleKind kind, const Vec2& center_m, const Vec2& size_m,
                    double yaw_rad, double height_m);

  const LayoutRoom& room(int index) const { return rooms_[static_cast<std::size_t>(index)]; }
  /// Replaces a room's outline (world coordinates, any orientation; stored counter-clockwise).
  void set_room_polygon(int index, std::vector<Vec2> polygon_m);
  int room_count() const { return static_cast<int>(rooms_.size()); }

  /// Builds walls from the shared room edges, places doors and windows, validates.
  /// Throws std::logic_error if the layout is inconsistent (overlapping rooms, a door whose rooms
  /// share no long enough wall): that is a generator bug, never a user error.
  GeneratedBuilding assemble(const std::string& name) const;

 private:
  struct DoorRequest {
    int a, b;
    double width_m;
    bool closed;
    Vec2 preferred_m;
  };
  struct Rule {
    bool open = false;
    bool glass = false;
    double sill_m = 0.0;
    std::optional<double> head_m;
    std::optional<Vec2> outward_normal;
  };
  struct ObstacleRequest {
    std::string name;
    Obstacle obstacle;
  };

  BuildingStyle style_;
  std::vector<LayoutRoom> rooms_;
  std::vector<DoorRequest> doors_;
  std::map<std::pair<int, int>, Rule> rules_;        ///< key (min, max) room index
  std::map<int, std::vector<Rule>> facades_;          ///< glass facades per room
  std::vector<Wall> free_walls_;
  std::vector<ObstacleRequest> obstacles_;
};

// ---- Helpers shared by the archetypes ------------------------------------------------------

/// How a row of rooms along a hallway is cut and furnished.
struct RowFill {
  double module_m = 3.6;              ///< width of the standard room
  double p_double = 0.2;              ///< a room spans two modules
  double p_triple = 0.05;             ///< a room spans three modules
  std::string kind_single = "office";
  std::string kind_double = "meeting";
  std::string kind_triple = "classroom";
  double glass_double_probability = 0.0;  ///< a two-module room gets a glass wall to the hallway
  double min_room_m = 1.8;            ///< leftovers narrower than this widen the last room
  /// Calibrated variety (room widths from the real area distribution, recesses, notches, suites,
  /// stubs); null or disabled: rows of module rooms, exactly as before the calibration.
  const RoomVariety* variety = nullptr;
};

/// A strip of a wing's local frame to be cut into rooms facing a hallway.
struct RowStrip {
  Frame frame;
  double x0 = 0.0, x1 = 0.0;   ///< along the hallway
  double y0 = 0.0, y1 = 0.0;   ///< across; the hallway lies at y1 (facing +1) or y0 (facing -1)
  int facing = 1;
  int hallway = -1;
  /// Optional: the hallway split into pieces along x (fire doors). Each entry is (x where the
  /// piece starts, room index); sorted by x. Doors go to the piece in front of them.
  std::vector<std::pair<double, int>> hallway_pieces;
  std::string id_prefix;
  WindowSpec windows;
  /// The side away from the hallway is the building's facade (rooms may be shallower there:
  /// outline notches; stubs end in a window).
  bool far_side_is_facade = false;
  /// ... only from this local x on (e.g. where another wing's rooms end).
  double facade_from_x = -1e300;
};

/// Cuts the strip into rooms of 1-3 modules (leftover narrower than min_room_m widens the last
/// room, else it becomes a storage room), adds a door per room (two for three-module rooms) to the
/// hallway, furniture if the style asks for it. Returns the room indices.
std::vector<int> fill_row(Layout& layout, const RowStrip& strip, const RowFill& fill, Rng& rng);

/// One rectangular room [x0, x1] x [y0, y1] of a frame with the hallway on its `facing` side
/// (+1: y1, -1: y0) and a door to it centred near local x = door_x; furnished if the style says so.
int add_facing_room(Layout& layout, const std::string& id, const std::string& kind, const Frame& frame, double x0,
                    double y0, double x1, double y1, int facing, int hallway, const WindowSpec& windows,
                    double door_x, double door_width_m, bool closed, Rng& rng);

/// Free sub-intervals of a strip [x0, x1] after taking out reserved intervals.
struct Interval1 {
  double x0 = 0.0, x1 = 0.0;
};
/// Reserved intervals of one strip of rooms; refuses overlaps and slivers narrower than min_gap_m.
class StripReservations {
 public:
  StripReservations(double x0, double x1, double min_gap_m) : x0_(x0), x1_(x1), min_gap_m_(min_gap_m) {}
  bool fits(double x0, double x1) const;
  bool reserve(double x0, double x1);
  /// Splits the strip at x (e.g. under a fire partition): no room will straddle it. False (and
  /// no cut) if it would leave a sliver.
  bool cut(double x);
  std::vector<Interval1> free_intervals() const;
  double x0() const { return x0_; }
  double x1() const { return x1_; }

 private:
  bool fits_interval(double x0, double x1) const;
  double x0_, x1_, min_gap_m_;
  std::vector<Interval1> taken_;
};

/// Furniture for a rectangular room of the strip's frame: [x0, x1] x [y0, y1] with the hallway on
/// the `facing` side.
void furnish_room(Layout& layout, const std::string& room_id, const std::string& kind, const Frame& frame,
                  double x0, double y0, double x1, double y1, int facing, Rng& rng);

/// Stair flights and a landing as obstacles in a stairwell [x0,x1]x[y0,y1] of a frame.
void add_stairs(Layout& layout, const std::string& name, const Frame& frame, double x0, double y0, double x1,
                double y1);

}  // namespace floorcast::generate_detail
