// Procedural buildings: deterministic floor plans of four archetypes (apartment, office, campus,
// angled) for localization research. Same archetype + seed + parameters -> the same plan, byte for
// byte, on any machine: the generator uses its own seeded random numbers (splitmix64 with explicit
// float conversion, no std:: distributions) and exact trigonometric constants (no libm sin/cos).
//
// Every building is a set of rooms (closed polygons) whose shared edges become walls: exterior
// walls around the envelope, corridor walls, partitions between rooms, glass partitions and
// facades. Rooms are connected by doors (some closed) or open connections (hallway junctions,
// lobbies); with all doors open the building interior is one connected free space.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "floorcast/floorplans/floor_plan.hpp"

namespace floorcast {

/// Wall, door and window dimensions shared by every archetype.
struct BuildingStyle {
  double exterior_thickness_m = 0.30;        ///< envelope walls
  double corridor_wall_thickness_m = 0.15;   ///< walls between a hallway and a room
  double partition_thickness_m = 0.10;       ///< walls between two rooms
  double glass_thickness_m = 0.05;           ///< glass partitions and glass facades
  double door_width_m = 0.9;                 ///< single doors (0.8 - 1.0 m)
  double double_door_width_m = 1.8;          ///< double doors (lecture halls, entrances, fire doors)
  /// Minimum solid wall between a door edge and the wall junction ending its run.
  double door_jamb_m = 0.2;
  double window_width_m = 1.5;               ///< ordinary windows
  double window_pier_m = 1.0;                ///< solid wall between neighbouring windows
  double window_margin_m = 0.5;              ///< solid wall between a window and a wall junction
  double window_sill_m = 0.9;
  double window_head_m = 2.1;
  /// Share of ordinary room doors that are closed (stairwells, elevators, storage and exits are
  /// always closed; toilets mostly).
  double room_door_closed_probability = 0.3;
  /// Furnish rooms with clutter obstacles (desks, cabinets, beds, seating rows, stairs, pillars).
  bool furniture = true;
};

/// Apartment: ~80-150 m^2 of free floor area. A front band (kitchen + living room, the living room
/// with a glazed corner facade), an entrance hall with a storage closet, a back band of bedrooms
/// and a bathroom (with a glass shower screen).
struct ApartmentParams {
  BuildingStyle style = apartment_style();
  double width_min_m = 11.5;          ///< building extent along x (wall centrelines)
  double width_max_m = 13.5;
  double front_depth_min_m = 4.8;     ///< kitchen + living band
  double front_depth_max_m = 6.0;
  double hall_width_min_m = 1.4;      ///< entrance hall band
  double hall_width_max_m = 1.6;
  double back_depth_min_m = 3.5;      ///< bedrooms + bath band
  double back_depth_max_m = 4.2;
  double kitchen_width_min_m = 3.0;
  double kitchen_width_max_m = 3.8;
  double bath_width_min_m = 2.2;
  double bath_width_max_m = 2.8;
  double storage_width_m = 1.4;       ///< closet at the end of the hall
  double open_kitchen_probability = 0.5;  ///< kitchen open to the living room (no wall)

  static BuildingStyle apartment_style() {
    BuildingStyle s;
    s.corridor_wall_thickness_m = 0.12;
    s.partition_thickness_m = 0.10;
    s.window_width_m = 1.4;
    s.room_door_closed_probability = 0.4;
    return s;
  }
};

/// Office: ~1,500-3,000 m^2. An L-shaped slab of two double-loaded corridor wings with rows of
/// identical offices, glass-walled meeting rooms, a core (stairwell, elevator, toilets) per wing,
/// stairwells and exits at the wing ends, an entrance vestibule with a glass facade at the corner
/// junction, and double fire doors across the corridors.
struct OfficeParams {
  BuildingStyle style;
  double target_area_min_m2 = 1900.0;  ///< the wings are sized for a free area drawn in this range
  double target_area_max_m2 = 2700.0;
  double room_depth_min_m = 5.6;       ///< office depth (corridor wall to facade)
  double room_depth_max_m = 6.2;
  double corridor_width_min_m = 2.0;
  double corridor_width_max_m = 2.4;
  double module_width_min_m = 3.4;     ///< width of the standard (repeated) office
  double module_width_max_m = 3.8;
  double second_wing_share_min = 0.35; ///< share of the total wing length in the second wing
  double second_wing_share_max = 0.45;
  double meeting_room_probability = 0.12;  ///< a room group becomes a glass-walled meeting room
  double lounge_probability = 0.5;     ///< per wing: an open lounge niche off the corridor
};

/// Campus: ~8,000-15,000 m^2. A large block with three long east-west hallways crossed by
/// north-south hallways (intersections every ~45 m), rows of identical classrooms and offices,
/// a lobby with a glass facade opening onto the main hallway, a glass-walled atrium with pillars,
/// large lecture halls with seating, stair/toilet cores, lounges and exits.
struct CampusParams {
  BuildingStyle style = campus_style();
  double target_area_min_m2 = 9500.0;  ///< the block is sized for a free area drawn in this range
  double target_area_max_m2 = 12500.0;
  double room_depth_min_m = 7.0;
  double room_depth_max_m = 8.0;
  double hallway_width_min_m = 2.8;
  double hallway_width_max_m = 3.2;
  double module_width_min_m = 3.8;     ///< width of the standard (repeated) room
  double module_width_max_m = 4.2;
  double segment_length_m = 48.0;      ///< aimed-at distance between cross hallways
  int lecture_halls_min = 2;
  int lecture_halls_max = 3;
  double lecture_hall_length_min_m = 18.0;
  double lecture_hall_length_max_m = 24.0;
  double atrium_length_min_m = 22.0;
  double atrium_length_max_m = 30.0;
  double lobby_length_min_m = 14.0;
  double lobby_length_max_m = 20.0;
  double cross_hallway_exit_probability = 0.6;  ///< a cross hallway reaches the facade (else stairwell)
  double lounge_probability = 0.4;     ///< per segment: an open lounge niche off a hallway

  static BuildingStyle campus_style() {
    BuildingStyle s;
    s.window_width_m = 1.8;
    s.window_pier_m = 1.2;
    return s;
  }
};

/// Angled: a non-Manhattan building. An irregular convex lobby hub (glass facades, entrance)
/// with three double-loaded corridor wings pointing west (180 deg), at 30 deg and at -45 deg, so
/// walls run at 0/90, 30/120 and 45/135 degrees.
struct AngledParams {
  BuildingStyle style;
  double wing_length_min_m = 36.0;
  double wing_length_max_m = 56.0;
  double room_depth_min_m = 5.6;
  double room_depth_max_m = 6.4;
  double corridor_width_min_m = 2.0;
  double corridor_width_max_m = 2.4;
  double module_width_min_m = 3.4;
  double module_width_max_m = 3.8;
  double meeting_room_probability = 0.15;
  /// Wing directions (degrees, CCW from +x). Must be multiples of 15 degrees, at least 60 apart.
  std::vector<int> wing_directions_deg = {180, 30, -45};
};

/// A room of a generated building: id, kind ("hallway", "office", "lobby", "atrium",
/// "lecture_hall", ...), polygon (wall centrelines, counter-clockwise). Useful for room labels,
/// hallway vs room, sampling poses per room.
using GeneratedRoom = Room;

struct GeneratedBuilding {
  FloorPlan plan;
  std::vector<GeneratedRoom> rooms;
};

enum class Archetype { kApartment, kOffice, kCampus, kAngled };

/// "apartment", "office", "campus", "angled".
const char* archetype_name(Archetype archetype);
std::vector<Archetype> all_archetypes();
/// Parses an archetype name; throws InputError listing the valid names.
Archetype parse_archetype(const std::string& name);

GeneratedBuilding generate_apartment(std::uint64_t seed, const ApartmentParams& params = {});
GeneratedBuilding generate_office(std::uint64_t seed, const OfficeParams& params = {});
GeneratedBuilding generate_campus(std::uint64_t seed, const CampusParams& params = {});
GeneratedBuilding generate_angled(std::uint64_t seed, const AngledParams& params = {});

/// The archetype with its default parameters. The plan is validated (validate_floor_plan) before
/// it is returned.
GeneratedBuilding generate_building(Archetype archetype, std::uint64_t seed);

}  // namespace floorcast
