// Small hand-built plans shared by the floorplans tests.
#pragma once

#include "floorcast/floorplans/floor_plan.hpp"

namespace floorcast::test {

/// A closed rectangular room [0, w] x [0, h] (wall centrelines), walls of thickness t.
inline FloorPlan box_room(double w = 5.0, double h = 4.0, double t = 0.2) {
  FloorPlan p;
  p.name = "box";
  p.walls = {
      {"south", {0, 0}, {w, 0}, t, WallMaterial::kSolid, 0.0, {}},
      {"east", {w, 0}, {w, h}, t, WallMaterial::kSolid, 0.0, {}},
      {"north", {w, h}, {0, h}, t, WallMaterial::kSolid, 0.0, {}},
      {"west", {0, h}, {0, 0}, t, WallMaterial::kSolid, 0.0, {}},
  };
  return p;
}

/// The box room with one of every element kind.
inline FloorPlan furnished_room() {
  FloorPlan p = box_room(6.0, 4.0, 0.2);
  p.name = "furnished";
  p.level = 2;
  p.walls[1].material = WallMaterial::kGlass;
  p.walls[1].thickness_m = 0.05;
  p.walls[1].glass_sill_m = 0.1;
  p.walls[1].glass_head_m = 2.4;
  p.doors.push_back({"d1", "south", {2.0, 0.0}, 0.9, false});
  p.doors.push_back({"d2", "north", {4.5, 4.0}, 1.0, true});
  p.windows.push_back({"win1", "west", {0.0, 2.0}, 1.2, 0.9, 2.1});
  p.obstacles.push_back({"desk", ObstacleKind::kBox, {3.0, 2.0}, {1.6, 0.8}, 0.3, 0.75});
  p.obstacles.push_back({"pillar", ObstacleKind::kPillar, {1.5, 3.0}, {0.4, 0.4}, 0.0, 3.0});
  return p;
}

}  // namespace floorcast::test
