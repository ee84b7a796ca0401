// Is an imported plan what its source says? The free-space rule of the importers of mapped spaces
// (imdf, osm, geojson; floorplans/README.md, "Free space") and the check every such import reports.
//
// The source's spaces (rooms, corridors, areas, halls, units, ...) are the plan's room labels.
// Free space is their union: walls stand where a wall is mapped or a space meets unmapped space,
// and a region the walls enclose but no space covers (a courtyard ringed by rooms, an atrium void)
// is labelled "unmapped" (rooms.hpp) and is not floor. check_faithfulness() then compares the plan
// with the spaces on one raster: how much of the mapped area (less the wall bodies) is free floor,
// per space kind; how much free floor no space covers; which spaces are sealed (connected to no
// other space with every door open) or not reachable from the largest connected free region.
// Pure algorithms: no I/O.
#pragma once

#include <string>
#include <vector>

#include "floorcast/floorplans/floor_plan.hpp"

namespace floorcast {

struct FaithfulnessOptions {
  /// Raster resolution (m/px); coarser for levels whose raster would exceed max_cells.
  double resolution_m_per_px = 0.1;
  double max_cells = 2.0e7;
  /// Enclosed unmapped regions smaller than this are slivers between outlines that do not quite
  /// meet (left as they are, counted as free floor outside every space).
  double min_unmapped_area_m2 = 0.25;
  /// Warn when more than this share of the mapped area not under walls is not free floor
  /// (corridors outside the walls), overall or for a space kind.
  double max_missing_share = 0.05;
  /// Warn when more than this share of the free floor lies in no mapped space.
  double max_unmapped_free_share = 0.05;
  /// Warn when spaces connected to no other space (no door, no open boundary) hold more than this
  /// share of the mapped area (a source without openings: every unit a sealed box).
  double max_sealed_area_share = 0.25;
  /// Per-kind shares warn only for kinds with at least this much mapped area (m^2).
  double min_kind_area_m2 = 20.0;
};

/// The figures of one space kind (cells attributed to the smallest space containing them).
struct KindFaithfulness {
  std::string kind;
  int spaces = 0;
  double source_area_m2 = 0.0;  ///< sum of the kind's polygon areas (outer ring less holes)
  double mapped_area_m2 = 0.0;  ///< raster cells whose smallest space has this kind
  double wall_area_m2 = 0.0;    ///< of those, under walls, glass or closed doors
  double free_area_m2 = 0.0;    ///< of those, free floor
  double free_share = 1.0;      ///< free / (mapped - wall); 1 when nothing is mapped
};

struct FaithfulnessReport {
  bool applicable = false;  ///< the plan has source spaces (room labels other than "unmapped")
  double resolution_m_per_px = 0.0;
  int spaces = 0;
  double source_area_m2 = 0.0;          ///< sum of the spaces' areas as drawn (nested spaces twice)
  double mapped_area_m2 = 0.0;          ///< their union
  double wall_area_m2 = 0.0;            ///< of the union, under walls, glass and closed doors
  double free_area_m2 = 0.0;            ///< the plan's free floor (valid area)
  double free_in_mapped_m2 = 0.0;
  double free_outside_mapped_m2 = 0.0;  ///< free floor no space covers
  double free_share = 1.0;              ///< free_in_mapped / (mapped - wall)
  double unmapped_area_m2 = 0.0;        ///< regions labelled "unmapped" (enclosed, not floor)
  int unmapped_regions = 0;
  std::vector<KindFaithfulness> kinds;  ///< by kind name
  /// Spaces whose free floor touches no other space's with every door open (in the source: no
  /// opening, no open boundary), outside the largest connected free region, with their ids (all of
  /// them, in plan order).
  int sealed_spaces = 0;
  double sealed_area_m2 = 0.0;
  std::vector<std::string> sealed_ids;
  /// Spaces with no free floor in the largest connected free region (doors open): not reachable
  /// from the main circulation. Includes the sealed ones.
  int unreachable_spaces = 0;
  double unreachable_area_m2 = 0.0;
  /// Spaces with less than half of their area (less walls) free: outside the free space.
  std::vector<std::string> spaces_outside_free;
  /// Levels of the source that hold no space at all (the importer fills it; e.g. a level of
  /// pillar outlines only).
  std::vector<std::string> levels_without_spaces;
  /// Above the thresholds of FaithfulnessOptions, one line each (the importer adds its own).
  std::vector<std::string> warnings;
};

/// Regions of the plan's valid area (enclosed by its walls) that no space covers, as rooms of kind
/// "unmapped" (ids "unmapped1", ...; polygons traced on the raster, reaching into the walls around
/// them). Regions under min_unmapped_area_m2 are left out. Without spaces: none.
std::vector<Room> unmapped_regions(const FloorPlan& plan, const FaithfulnessOptions& options = {});

/// The faithfulness figures of a plan whose room labels are its source's spaces (warnings filled
/// from the thresholds). Not applicable (applicable = false, nothing else filled) without spaces.
FaithfulnessReport check_faithfulness(const FloorPlan& plan, const FaithfulnessOptions& options = {});

/// One line: "free 1,234 m^2 = 98.7% of the mapped 1,300 m^2 less walls; ...".
std::string faithfulness_summary(const FaithfulnessReport& report);

}  // namespace floorcast
