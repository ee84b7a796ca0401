// Perfect observations: the error-free proxy of PALMS+ sec. 4.4. From a point of the floor plan,
// the wall surfaces visible within a range, as 2D segments in the observer's frame, plus
// F3Loc-style ranges along equiangular rays. Exact 2D visibility (angular sweep over the
// blocking outline), not sampling. Optionally the "perfect 3-D planes": every planar surface of
// the plan's extrusion (floorplans/extrusion.hpp: walls, closed doors, glass, floor, ceiling) as
// seen from the camera, as plane patches in the observer's 3D frame; visibility in 3D by ray
// casting to samples on a grid of half the patch cell.
#pragma once

#include <memory>
#include <vector>

#include <nlohmann/json.hpp>

#include "floorcast/core/fields.hpp"

#include "floorcast/core/observation.hpp"
#include "floorcast/core/params.hpp"
#include "floorcast/floorplans/extrusion.hpp"
#include "floorcast/floorplans/geometry.hpp"
#include "floorcast/floorplans/semantic_rays.hpp"

namespace floorcast {

struct PerfectObservationParams {
  double max_range_m = 10.0;    ///< PALMS+ sec. 4.4: 10 m
  /// What occludes (keys doors_closed, glass_blocks, obstacles_block, cut_height_m): open doors
  /// treated as closed (PALMS+ sec. 4.4: all doors closed), glass walls and windows are walls,
  /// clutter does not occlude, cut at camera height.
  BlockingOptions blocking = closed_door_map();
  int num_rays = 36;            ///< equiangular rays (F3Loc: 36; 180 also used); 0 = none
  /// Perfect bird's-eye views (core/bev.hpp), one per class set (semantic and occupancy), on
  /// bev_columns equiangular columns around the observer (column i at 2 pi i / bev_columns in the
  /// observer frame; 0 = none): the thesis' one-hot ray casting of the plan at the blocking cut
  /// height (floorplans/semantic_rays.hpp), the upper bound of any BEV predictor.
  int bev_columns = 0;
  int bev_depth_bins = 32;        ///< log-spaced depth bins
  double bev_min_depth_m = 0.3;   ///< first bin edge; the last is max_range_m
  /// Perfect 3-D planes: the visible planar surfaces as plane patches (Observation2D::planes).
  bool planes = true;
  double plane_cell_m = 0.25;    ///< cell edge of the patches (VoxelPlane-Reloc's l)
  double camera_height_m = 1.5;  ///< the observer's eye above the floor (the scan frame's origin)
  /// Patches smaller than this (visible area) are left out (slivers of jambs and soffits).
  double min_plane_area_m2 = 0.25;
  /// The 3D building: wall (= ceiling) height and door height, as the simulator extrudes it.
  ExtrusionParams extrusion;

  /// The field list (core/fields.hpp): keys, ranges, docs; to_json and apply_overrides use it.
  static const FieldList<PerfectObservationParams>& fields();
  nlohmann::ordered_json to_json() const;
  /// Strict overrides (keys as in to_json); throws ParameterError naming the key.
  void apply_overrides(const nlohmann::json& overrides);
  /// Takes the experiment's shared range and blocking flags.
  void apply_shared(const SharedParams& shared);
};

/// Prepares a plan's outline once, then observes from any number of poses.
class PerfectObserver {
 public:
  PerfectObserver(const FloorPlan& plan, const PerfectObservationParams& params = {});
  ~PerfectObserver();
  PerfectObserver(PerfectObserver&&) noexcept;
  PerfectObserver& operator=(PerfectObserver&&) noexcept;

  /// Visible wall segments within max_range (observer frame, metres; each oriented with free
  /// space on its left), ray ranges (max_range where nothing is hit) and, with params.planes, the
  /// visible plane patches within max_range (horizontal distance).
  Observation2D observe(const Pose2& T_world_observer) const;

  /// The visible plane patches alone (observer frame, z up from the camera).
  std::vector<PlanePatch> visible_planes(const Pose2& T_world_observer) const;

  /// Visible segments in the world frame, with their labels.
  std::vector<LabeledSegment> visible_world_segments(const Vec2& position_m) const;

  /// Ranges along num_rays equiangular rays starting at world angle start_rad.
  std::vector<double> ray_ranges(const Vec2& position_m, double start_rad, int num_rays) const;

  /// The perfect BEV of `classes` on `columns` equiangular columns (empty when columns is 0).
  BevPrediction bev(const Pose2& T_world_observer, BevClasses classes, int columns) const;

  const std::vector<LabeledSegment>& outline() const { return outline_; }
  const PerfectObservationParams& params() const { return params_; }

 private:
  PerfectObservationParams params_;
  std::vector<LabeledSegment> outline_;
  SemanticPlanLines semantic_lines_, occupancy_lines_;
  struct Planes;
  std::unique_ptr<Planes> planes_;  ///< the 3D scene and its planes (params.planes only)
};

}  // namespace floorcast
