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
#include <optional>
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

/// Irregularity of rows of rooms and their corridors, calibrated on the real development plans
/// (`floorcast plan stats` on ../shared/realplans; results/realplans_vs_generated.md). With
/// `enabled = false` an archetype lays out rows of identical module rooms along featureless
/// corridors: the repetitive hard case (`office_repetitive`, ...), byte for byte the buildings
/// generated before the calibration.
struct RoomVariety {
  bool enabled = true;
  /// Room areas (m^2) as equal-probability quantiles (0.1, 0.2, ..., 1.0; drawn by linear
  /// interpolation): the pooled non-transitional room areas of the 16 small real levels (TUM
  /// StudiTUM, RWTH PLT, SPbSTU No. 3; 303 rooms) from their 10% quantile up, the top capped at
  /// 120 m^2 (larger real rooms are lecture halls, laid out separately). A row room's width along
  /// its corridor is area / depth, clamped to [room_width_min_m, room_width_max_m].
  std::vector<double> room_area_quantiles_m2 = {6.6, 15.8, 20.8, 22.4, 26.3, 33.4, 44.0, 61.6, 74.3, 120.0};
  double room_width_min_m = 2.4;
  double room_width_max_m = 14.0;
  /// A room's door sits in a recess (alcove) cut from the room's corridor side: the corridor gets
  /// jogs and niches. Width and depth drawn uniformly in these ranges; the recess is flush with
  /// one of the room's partitions or at least 1 m from both.
  double recess_probability = 0.35;
  double recess_width_min_m = 1.6;
  double recess_width_max_m = 4.5;
  double recess_depth_min_m = 0.8;
  double recess_depth_max_m = 2.0;
  /// A room on the facade is shallower than its row (a notch in the outline).
  double notch_probability = 0.25;
  double notch_depth_min_m = 1.0;
  double notch_depth_max_m = 2.5;
  /// A room is entered from its neighbour in the row, not from the corridor (fewer corridor doors).
  double suite_probability = 0.15;
  /// Per row: a dead-end side corridor across the row (to the facade where there is one).
  double stub_probability = 0.35;
  double stub_width_min_m = 1.6;
  double stub_width_max_m = 2.6;
  /// A wide room (kind of a two-module room) gets a glass wall to the corridor. The real plans
  /// carry no glass; kept low so corridors stay mostly solid.
  double glass_wall_probability = 0.15;
  /// Cores (stairs, lifts, toilets) and fire partitions at random positions along a wing instead
  /// of fixed ones.
  bool irregular_cores = true;

  static RoomVariety none() {
    RoomVariety v;
    v.enabled = false;
    return v;
  }
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
/// The defaults are calibrated on the real development plans (RoomVariety; areas within the small
/// real levels' range); `repetitive()` is the hard case of rows of identical offices.
struct OfficeParams {
  BuildingStyle style;
  double target_area_min_m2 = 1000.0;  ///< the wings are sized for a free area drawn in this range
  double target_area_max_m2 = 2200.0;
  double room_depth_min_m = 4.8;       ///< office depth (corridor wall to facade)
  double room_depth_max_m = 6.8;
  double corridor_width_min_m = 2.2;   ///< real small levels: median corridor width 2.5-3.8 m
  double corridor_width_max_m = 3.0;
  double module_width_min_m = 3.4;     ///< width of the standard (repeated) office
  double module_width_max_m = 3.8;
  double second_wing_share_min = 0.35; ///< share of the total wing length in the second wing
  double second_wing_share_max = 0.45;
  double meeting_room_probability = 0.12;  ///< a room group becomes a glass-walled meeting room
  double lounge_probability = 0.5;     ///< per wing: an open lounge niche off the corridor
  RoomVariety variety;

  /// The pre-calibration office (`office_repetitive`, floorplans/buildings/office.json).
  static OfficeParams repetitive() {
    OfficeParams p;
    p.target_area_min_m2 = 1900.0;
    p.target_area_max_m2 = 2700.0;
    p.room_depth_min_m = 5.6;
    p.room_depth_max_m = 6.2;
    p.corridor_width_min_m = 2.0;
    p.corridor_width_max_m = 2.4;
    p.variety = RoomVariety::none();
    return p;
  }
};

/// Campus: ~8,000-15,000 m^2. Calibrated (default, `layout = kSpine`): the large real teaching
/// building's layout, see CampusLayout. `layout = kBlocks` (and repetitive()): a large block with three long east-west hallways crossed by
/// north-south hallways (intersections every ~45 m), rows of classrooms and offices, a lobby with
/// a glass facade opening onto the main hallway, a glass-walled atrium with pillars, great halls
/// and lecture halls with seating, stair/toilet cores, lounges and exits.
/// The defaults are calibrated on the large real development levels (SPbSTU main building L0-L2,
/// Grenoble mall L-1..L1; `floorcast plan stats`, results/realplans_vs_generated.md, "How the
/// calibration was done"): deep classrooms along wide hallways, room areas from the large levels'
/// distribution, a few halls of several hundred m^2, cross hallways only where the long hallways
/// need a connection. `repetitive()` is the hard case of rows of identical rooms in rows of one
/// depth along 3 m hallways with the full grid of cross hallways (the campus before any
/// calibration).
/// How the campus's hallways and rooms are arranged.
enum class CampusLayout {
  /// A near-square block: three long parallel hallways, cross hallways, back-to-back inner blocks
  /// of rooms between them (most rooms without a facade), halls inside the blocks.
  kBlocks,
  /// The large real teaching building (SPbSTU main L0-L2): one long spine corridor with a side
  /// wing across each end (an H / Z footprint), every room along a corridor and on a facade,
  /// corridors lined with rooms on both sides or on one side only (windows opposite), halls
  /// projecting from the facades and closing the wing ends, a lobby in the middle of the spine.
  kSpine,
};

struct CampusParams {
  BuildingStyle style = campus_style();
  /// Spine by default: its structure is inside the large real levels' range where the blocks'
  /// is not (circulation share 0.20-0.25 vs blocks 0.27-0.30, real 0.04-0.25; room area on a
  /// facade 0.98 vs 0.45, real 0.89-0.97; results/realplans_vs_generated.md). repetitive(): blocks.
  CampusLayout layout = CampusLayout::kSpine;
  double target_area_min_m2 = 9500.0;  ///< the block is sized for a free area drawn in this range
  double target_area_max_m2 = 12500.0;
  /// Depth of the rows of rooms (hallway wall to facade or to the next row). Large real levels:
  /// the longer side of rooms under 200 m^2 has its median at 12.0 m, 30-90% quantiles 8.3-13.8 m
  /// (SPbSTU main: classrooms 3.9 m x 12 m along the hallways), not one depth per building.
  double room_depth_min_m = 8.5;
  double room_depth_max_m = 13.0;
  /// Each of the six rows draws its own depth in the range (else one depth for every row).
  bool depth_per_row = true;
  /// Large real levels: median corridor width 4.0-5.0 m on SPbSTU main L0-L2 (1.8-6.6 m with the
  /// Grenoble mall).
  double hallway_width_min_m = 4.0;
  double hallway_width_max_m = 5.0;
  double module_width_min_m = 3.8;     ///< width of the standard (repeated) room (repetitive rows)
  double module_width_max_m = 4.2;
  double segment_length_m = 48.0;      ///< aimed-at distance between cross hallways
  /// Lecture halls span an inner block (two rows deep). Large real levels: SPbSTU main L0 / L1 /
  /// L2 hold 8 / 11 / 11 rooms of 200 m^2 or more (auditoriums, large classrooms; 204-696 m^2,
  /// median 316 m^2, leaving out the largest two of each level), i.e. 6-9 per 10,500 m^2; lengths of
  /// 9-22 m give 190-550 m^2 at the blocks' 19-25 m depth. Halls that do not fit are left out.
  int lecture_halls_min = 5;
  int lecture_halls_max = 8;
  double lecture_hall_length_min_m = 9.0;
  double lecture_hall_length_max_m = 22.0;
  /// Great (assembly) halls: lecture halls of a floor area drawn in this range (the length follows
  /// from the block depth), placed first. Large real levels: the two largest rooms of SPbSTU main
  /// L0 / L1 / L2 are 1,041 + 696 / 836 + 572 / 750 + 645 m^2 (the Grenoble mall's largest shops
  /// 1,168-1,584 m^2).
  int great_halls = 2;
  double great_hall_area_min_m2 = 570.0;
  double great_hall_area_max_m2 = 1050.0;
  double atrium_length_min_m = 22.0;
  double atrium_length_max_m = 30.0;
  double lobby_length_min_m = 14.0;
  double lobby_length_max_m = 20.0;
  double cross_hallway_exit_probability = 0.6;  ///< a cross hallway reaches the facade (else stairwell)
  /// A cross hallway crosses an inner block (between two long hallways) with this probability;
  /// every inner block keeps one crossing at a random cross hallway, and the rows run on where a
  /// crossing is left out (1: the full grid, as in repetitive()). Large real levels: the
  /// transitional rooms take 0.04-0.25 of the room area (SPbSTU main 0.08-0.25); with 4-5 m
  /// hallways the campus's three long hallways, atrium and lobby alone take ~0.25 and the full grid
  /// 0.30-0.34, so only the crossings connectivity needs are kept.
  double inner_crossing_probability = 0.0;
  double lounge_probability = 0.4;     ///< per segment: an open lounge niche off a hallway (blocks)
  RoomVariety variety = campus_variety();  ///< calibrated by default; none() in repetitive()

  // ---- Spine layout (layout = kSpine). Measured on SPbSTU main L0-L2 (imported from
  // ../shared/realplans; results/realplans_vs_generated.md, "The layout of the large real levels").
  // Rows use room_depth_*, hallways hallway_width_*, rooms the variety, segments segment_length_m,
  // the lobby lobby_length_*, great_halls and great_hall_area_*, lecture_halls_min/max (the wing
  // end halls among them).
  /// Length of each side wing over the spine's length. SPbSTU main: spine ~210 m between the wings,
  /// wings ~100-115 m.
  double wing_length_ratio_min = 0.45;
  double wing_length_ratio_max = 0.60;
  /// Where the spine meets a wing: the share of the wing's length on its shorter side (the west
  /// wing reaches further north, the east wing further south). SPbSTU main: ~0.4.
  double wing_junction_share_min = 0.30;
  double wing_junction_share_max = 0.50;
  /// Per corridor segment one side is lined with rooms, the other with this probability (else it
  /// is a facade with windows). SPbSTU main L0-L2: 24-30% of the corridor boundary is facade, about
  /// half of the corridor length has rooms on one side only.
  double second_side_loaded_probability = 0.5;
  /// Lecture halls projecting from the facade side of a row (along the corridor x out from it).
  /// SPbSTU main: 14.6-29.1 m x 13.3-18.1 m (204-480 m^2).
  double spine_hall_length_min_m = 14.5;
  double spine_hall_length_max_m = 29.0;
  double spine_hall_depth_min_m = 13.0;
  double spine_hall_depth_max_m = 18.0;
  /// Great halls' side along the corridor (the depth follows from the area). SPbSTU main: the
  /// largest halls are 22.8-27.8 m across (48.4 x 25.1, 32.1 x 24.8, 43.8 x 25.1 m, ...).
  double great_hall_width_min_m = 23.0;
  double great_hall_width_max_m = 28.0;
  /// Wing ends closed by a hall across the wing's full width (counted among the lecture halls).
  /// SPbSTU main: 3-4 of the 4 wing ends on every level (14 m deep, 204-324 m^2).
  double wing_end_hall_probability = 0.85;

  /// Outlines and doors of the spine layout's halls (great, projecting and wing end halls),
  /// measured on SPbSTU main L0-L2's 30 rooms of 200 m^2 or more (results/realplans_vs_generated.md,
  /// "Halls"): 15 of 30 are not rectangles (area / minimum-area rectangle 0.68-0.96, median 0.86;
  /// 6-16 corners, 0-4 of them reflex), 19 / 6 / 5 have 1 / 2 / 3 or more doors, a door's centre
  /// lies 0.09-0.50 of its side's length from the nearest corner (median ~0.25).
  struct HallVariety {
    /// false: every hall a plain rectangle with the same two double doors at 1/4 and 3/4 of its
    /// corridor side (one at the middle of a wing end): the spine campus before this calibration,
    /// byte-identical.
    bool enabled = true;
    double shaped_probability = 0.5;  ///< a hall's far side (away from its corridor) is not straight
    /// A shaped hall's two far corners are each cut by a rectangular notch with this probability,
    /// and its far wall carries a bay (a stage or projection recess outward) with bay_probability;
    /// at least one of the three. Corner notch + bay: the 8-16-corner halls of SPbSTU main.
    double corner_notch_probability = 0.5;
    double bay_probability = 0.5;
    double notch_width_share_min = 0.15;  ///< of the hall's side along the corridor
    double notch_width_share_max = 0.30;
    double notch_depth_share_min = 0.15;  ///< of the hall's depth away from the corridor
    double notch_depth_share_max = 0.35;
    double bay_width_share_min = 0.20;
    double bay_width_share_max = 0.35;
    double bay_depth_min_m = 2.0;
    double bay_depth_max_m = 5.0;
    /// Doors on the corridor side of a great or projecting hall: 1, 2, 3 with these relative
    /// weights, each in its own equal part of the side, its centre at least door_corner_share_min
    /// of the side from a corner. A wing end hall keeps its one door at the corridor's end. SPbSTU
    /// main: 19, 6, 5 of 30 halls have 1, 2, 3 or more doors; with ~40% of the campus's halls at
    /// the wing ends (one door each), these weights give ~0.62 / 0.20 / 0.17 over all halls.
    std::vector<double> door_count_weights = {7.0, 6.0, 5.0};
    double door_corner_share_min = 0.10;
    /// Halls with chamfered corners: sides at 45 degrees to the building's axes. SPbSTU main: 10 of
    /// 30 halls have sides oblique to the plan's main axes, 3 [2-8] per such hall, 5.3 [1.5-10.3] m
    /// long (polygonal apses, chamfered far corners; scripts/realplans_vs_generated.py, "Halls"). A
    /// chamfered hall draws one side length from [chamfer_length_min_m, chamfer_length_max_m] and
    /// cuts the convex corners of its outline away from its corridor side where the cut reaches at
    /// most 0.45 of both sides it shortens, each with chamfer_corner_probability, at least two (the
    /// length shortened to fit two where it fits fewer; no cut under 0.5 m); a cut is given back
    /// where another room comes within 0.3 m of the sides it removes (halls touch their row rooms
    /// and each other). Drawn from a random stream of their own: 0 gives the campus before this
    /// byte for byte, and any value the same building but for the outlines of the chamfered halls
    /// and where their seat rows start.
    double chamfer_probability = 1.0 / 3.0;
    double chamfer_corner_probability = 0.75;
    double chamfer_length_min_m = 1.5;
    double chamfer_length_max_m = 10.0;
  };
  HallVariety hall_variety;

  /// The pre-calibration campus (`campus_repetitive`, floorplans/buildings/campus.json): identical
  /// module rooms, 7-8 m deep rows, 2.8-3.2 m hallways, 2-3 lecture halls of 18-24 m.
  static CampusParams repetitive() {
    CampusParams p;
    p.layout = CampusLayout::kBlocks;
    p.room_depth_min_m = 7.0;
    p.room_depth_max_m = 8.0;
    p.depth_per_row = false;
    p.hallway_width_min_m = 2.8;
    p.hallway_width_max_m = 3.2;
    p.lecture_halls_min = 2;
    p.lecture_halls_max = 3;
    p.lecture_hall_length_min_m = 18.0;
    p.lecture_hall_length_max_m = 24.0;
    p.great_halls = 0;
    p.inner_crossing_probability = 1.0;
    p.variety = RoomVariety::none();
    return p;
  }

  static BuildingStyle campus_style() {
    BuildingStyle s;
    s.window_width_m = 1.8;
    s.window_pier_m = 1.2;
    return s;
  }

  /// Room variety of the large real levels: row-room areas as equal-probability quantiles (0.1,
  /// ..., 1.0) of the pooled non-transitional rooms of SPbSTU main L0-L2 and the Grenoble mall
  /// L-1..L1 (315 rooms; 10-80% quantiles 15.2, 30.2, 42.7, 46.8, 46.8, 66.4, 108.0, 154.2 m^2),
  /// the top capped at 170 m^2 (what a row room of the widest width holds; the real 90% quantile,
  /// 253 m^2, and larger rooms are the halls, laid out separately). Every other feature as
  /// calibrated on the small levels.
  static RoomVariety campus_variety() {
    RoomVariety v;
    v.room_area_quantiles_m2 = {15.2, 30.2, 42.7, 46.8, 46.8, 66.4, 108.0, 154.2, 170.0, 170.0};
    return v;
  }
};

/// Angled: a non-Manhattan building. An irregular convex lobby hub (glass facades, entrance)
/// with three double-loaded corridor wings pointing west (180 deg), at 30 deg and at -45 deg, so
/// walls run at 0/90, 30/120 and 45/135 degrees.
/// The defaults are calibrated on the real development plans (RoomVariety, shorter wings);
/// `repetitive()` is the hard case of rows of identical offices.
struct AngledParams {
  BuildingStyle style;
  double wing_length_min_m = 22.0;
  double wing_length_max_m = 40.0;
  double room_depth_min_m = 4.8;
  double room_depth_max_m = 6.8;
  double corridor_width_min_m = 2.2;
  double corridor_width_max_m = 3.0;
  double module_width_min_m = 3.4;
  double module_width_max_m = 3.8;
  double meeting_room_probability = 0.15;
  /// Wing directions (degrees, CCW from +x). Must be multiples of 15 degrees, at least 60 apart.
  std::vector<int> wing_directions_deg = {180, 30, -45};
  /// The lobby hub is sized so every facade edge between two wings keeps at least this length.
  double hub_facade_min_m = 2.5;
  /// Calibrated: also a U-shaped stair core standing in the lobby (irregular_cores).
  RoomVariety variety;

  /// The pre-calibration angled building (`angled_repetitive`, floorplans/buildings/angled.json).
  static AngledParams repetitive() {
    AngledParams p;
    p.wing_length_min_m = 36.0;
    p.wing_length_max_m = 56.0;
    p.hub_facade_min_m = 4.0;
    p.room_depth_min_m = 5.6;
    p.room_depth_max_m = 6.4;
    p.corridor_width_min_m = 2.0;
    p.corridor_width_max_m = 2.4;
    p.variety = RoomVariety::none();
    return p;
  }
};

/// A room of a generated building: id, kind ("hallway", "office", "lobby", "atrium",
/// "lecture_hall", ...), polygon (wall centrelines, counter-clockwise). Useful for room labels,
/// hallway vs room, sampling poses per room.
using GeneratedRoom = Room;

struct GeneratedBuilding {
  FloorPlan plan;
  std::vector<GeneratedRoom> rooms;
};

/// The calibrated archetypes (default parameters) and the repetitive hard cases (`repetitive()`
/// parameters: the buildings shipped as floorplans/buildings/office.json, campus.json, angled.json).
enum class Archetype { kApartment, kOffice, kCampus, kAngled, kOfficeRepetitive, kCampusRepetitive, kAngledRepetitive };

/// "apartment", "office", "campus", "angled", "office_repetitive", "campus_repetitive",
/// "angled_repetitive".
const char* archetype_name(Archetype archetype);
std::vector<Archetype> all_archetypes();
/// Parses an archetype name; throws InputError listing the valid names.
Archetype parse_archetype(const std::string& name);

GeneratedBuilding generate_apartment(std::uint64_t seed, const ApartmentParams& params = {});
GeneratedBuilding generate_office(std::uint64_t seed, const OfficeParams& params = {});
GeneratedBuilding generate_campus(std::uint64_t seed, const CampusParams& params = {});
GeneratedBuilding generate_angled(std::uint64_t seed, const AngledParams& params = {});

/// The archetype with its default parameters (repetitive archetypes: `repetitive()`). The plan is validated (validate_floor_plan) before
/// it is returned.
GeneratedBuilding generate_building(Archetype archetype, std::uint64_t seed);

/// Changes to an archetype's parameters (`plan generate`'s options); unset: the archetype's.
struct ArchetypeOverrides {
  std::optional<CampusLayout> campus_layout;  ///< campus archetypes only
  std::optional<bool> campus_hall_variety;    ///< campus archetypes only: CampusParams::HallVariety::enabled
  /// campus archetypes only: false sets CampusParams::HallVariety::chamfer_probability to 0
  std::optional<bool> campus_hall_chamfers;
};
GeneratedBuilding generate_building(Archetype archetype, std::uint64_t seed, const ArchetypeOverrides& overrides);

}  // namespace floorcast
