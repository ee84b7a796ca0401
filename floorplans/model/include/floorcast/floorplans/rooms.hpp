// Room labels of a plan (FloorPlan::rooms): which room a point lies in, the transitional room
// kinds, and a raster of room indices for sampling by kind.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "floorcast/core/grid.hpp"
#include "floorcast/floorplans/floor_plan.hpp"

namespace floorcast {

/// True if p lies inside the closed polygon (even-odd rule; any orientation, non-convex allowed).
bool point_in_polygon(const std::vector<Vec2>& polygon_m, const Vec2& p);

/// Inside the outer boundary and outside every hole.
bool room_contains(const Room& room, const Vec2& p);

/// Area of the outer boundary minus the holes (m^2).
double room_area_m2(const Room& room);

/// Index of the room containing p; where rooms nest, the smallest one (ties: the first). -1 if none.
int room_at(const std::vector<Room>& rooms, const Vec2& p);

/// CV_32S raster on `grid`: per cell, room_at() of the cell centre (-1: no room).
cv::Mat room_index_raster(const std::vector<Room>& rooms, const GridSpec& grid);

/// CV_8U raster on `grid`: 255 where the cell centre lies inside one of the rooms `select` accepts
/// (all rooms without it), outer ring less holes; the union, not the smallest room (OpenCV fillPoly
/// at 1/16 cell, so cells whose centre lies on an outline may go either way).
cv::Mat rooms_mask(const std::vector<Room>& rooms, const GridSpec& grid,
                   const std::function<bool(const Room&)>& select = {});

/// The reserved room kind "unmapped": a region enclosed by walls where the source mapped no space
/// (a courtyard or an atrium void ringed by rooms, a region closed off by wall ways only). It is
/// not floor: valid_area_mask() (and the free area, observation sampling and matcher candidates
/// built on it) excludes it. Importers write it (floorplans/README.md, "Free space").
inline constexpr const char* kUnmappedRoomKind = "unmapped";
bool is_unmapped_kind(const std::string& kind);

/// Transitional spaces, where PALMS+ sec. 4.4 placed its observation points (hallways,
/// intersections, lobbies): the room kinds floorcast counts as transitional, generated and imported
/// vocabularies alike: hallway, corridor, walkway (IMDF), lobby, foyer, entrance, atrium, lounge
/// (an open niche off a corridor), hall, vestibule, circulation (the unmapped part of an OSM level
/// outline).
const std::vector<std::string>& transitional_room_kinds();
bool is_transitional_kind(const std::string& kind);

/// Expands a kinds list: the word "transitional" stands for transitional_room_kinds().
std::vector<std::string> expand_room_kinds(const std::vector<std::string>& kinds);

}  // namespace floorcast
