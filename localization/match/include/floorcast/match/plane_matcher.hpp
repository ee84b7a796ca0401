// The VoxelPlane-Reloc plane relocalization matcher (Suo et al. 2024, "VoxelPlane-Reloc: an
// indoor scene voxel plane relocalization algorithm", sec. "Plane matching").
//
// Map planes P^M: every planar surface of the plan's 3D extrusion (floorplans/extrusion.hpp, the
// geometry the simulator renders: wall sides with their lintels and closed door leaves, glass
// panes, floor, ceiling; obstacles when they block), one per connected coplanar surface, with the
// paper's descriptors: enclosing sphere (centre, radius) and area on an l x l grid of the plane.
// Precomputed once per plan, with every pair of wall planes close enough to be seen together.
//
// Submap planes P^S: Observation2D::planes (the observation module's voxel-plane extraction, or
// perfect 3-D planes), in the observer's gravity-aligned 3D frame.
//
// Relocalization, as in the paper:
//  1. Incremental input: the ground plane and the largest planes of distinct orientation first
//     (initial_planes), one more plane at a time until a transform is accepted.
//  2. Triplet selection: the ground plane is matched first (normals within tau_g of vertical:
//     the submap ground to the map floor); the planes of a triplet pairwise within
//     [min_angle_deg, max_angle_deg]; the map planes of a triplet close together (sphere distance
//     no more than the submap planes' centre distance plus a tolerance); map plane area >=
//     area_ratio x submap plane area (cells of l x l).
//  3. Transform: rotation from the normal pairs (quaternion: eigenvector of Horn's 4x4 matrix,
//     the paper's eq. 6, 8-9), translation by least squares on the offsets (eq. 7). With the
//     ground matched the transform is gravity aligned: yaw from the normals, z from the ground,
//     (x, y) from the other two offsets.
//  4. Evaluation: map-plane projection inliers p(i, j) (eq. 10), submap overlap o(i, j) (eq. 11),
//     scene uniqueness (>= tau_m submap planes agree with map planes under the transform, and
//     the majority of them), pair weights w_a (eq. 12-13) and the kernel density over the triplet
//     transforms (eq. 14); its maximum over the accepted transforms is the pose.
// The output is the common MatchResult: the best pose and the top-K modes of the density, "not
// localized" (no modes) when no triplet passes, and the density on the plan grid as the posterior.
//
// Frames: world = plan metres, z up from the floor; submap = observer frame, z up from the sensor.
// T_world_observer maps observer points to world points.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "floorcast/core/fields.hpp"
#include "floorcast/core/params.hpp"
#include "floorcast/core/plane_patch.hpp"
#include "floorcast/floorplans/extrusion.hpp"
#include "floorcast/match/matcher.hpp"

namespace floorcast {

/// How the triplet weights of eq. 13 use the pair weights of eq. 12.
enum class PlanePairWeights {
  kInverseFrequency,  ///< w_a = sum o(i,j) w_a(i,j): the text ("the less frequently a plane appears, the higher its weight")
  kAsPrinted,         ///< w_a = sum o(i,j) / w_a(i,j): eq. 13 as printed (frequent planes weigh more)
  kOverlap,           ///< w_a = sum o(i,j): no pair weights
};

struct PlaneMatcherParams {
  // --- Shared quantities.
  /// Map planes and submap planes farther than this (horizontally) from the observer are not
  /// used; pairs of map planes farther apart than twice this are never matched together.
  double max_range_m = 10.0;
  /// What the map contains (doors_closed: open doors drawn closed; glass_blocks: glass panes are
  /// map planes; obstacles_block: obstacle faces are map planes; cut_height_m: only for drawing).
  BlockingOptions blocking = closed_door_map();
  // --- The map.
  /// The 3D building the map planes come from (as the simulator extrudes it).
  ExtrusionParams extrusion;
  /// l: edge of the grid cells areas, projections and overlaps are counted on (metres).
  double cell_m = 0.25;
  /// Map planes smaller than this are left out (jamb and soffit slivers).
  double min_map_plane_area_m2 = 0.2;
  // --- Submap input.
  /// Submap planes smaller than this are not used.
  double min_plane_area_m2 = 0.5;
  /// At most this many submap planes (largest first) take part.
  int max_planes = 12;
  /// Incremental input (the paper's; false = VR-NI: every plane at once).
  bool incremental = true;
  int initial_planes = 5;
  // --- Triplet selection.
  /// Ground plane constraint (false with orthogonal_constraint false = VR-NG).
  bool ground_constraint = true;
  double tau_g_deg = 10.0;
  /// Orthogonal plane constraint: the planes of a triplet pairwise within [min, max] degrees.
  bool orthogonal_constraint = true;
  double min_angle_deg = 40.0;
  double max_angle_deg = 140.0;
  /// Map and submap pairs must agree in their (signed) angle within this tolerance (ours: the
  /// rotation of a pair whose angles disagree cannot fit both).
  double angle_tolerance_deg = 5.0;
  /// Sphere distance limit: map planes of a triplet at most (submap centre distance + this) apart.
  bool sphere_constraint = true;
  double sphere_tolerance_m = 0.5;
  /// Area relation: map plane cells >= area_ratio x submap plane cells.
  bool area_constraint = true;
  double area_ratio = 0.7;
  // --- Evaluation.
  /// Map plane projection strategy (eq. 10; false = VR-NP): share of a submap plane's cells
  /// that land on the matched map plane (within projection_tolerance_m of it, on its extent
  /// grown by the same tolerance), for each triplet pair at least min_projection.
  bool projection = true;
  double projection_tolerance_m = 0.15;
  double min_projection = 0.6;
  /// Submap plane overlap strategy (eq. 11; false = VR-NO): o(i, j) of each triplet pair at least
  /// min_overlap (and o weighs the triplet, eq. 13).
  bool overlap = true;
  double min_overlap = 0.5;
  /// Scene uniqueness (false = VR-NS): at least tau_m submap planes agree with a map plane under
  /// the transform (normal within match_normal_deg, offset within match_offset_m, projection
  /// share at least min_projection); and always a majority of the planes.
  bool uniqueness = true;
  int tau_m = 5;
  double match_normal_deg = 5.0;
  double match_offset_m = 0.15;
  // --- Pose density (eq. 12-14).
  PlanePairWeights pair_weights = PlanePairWeights::kInverseFrequency;
  /// Kernel of eq. 14: I_a = diag(1 / sigma^2) / 2 over (x, y, z) and the rotation vector.
  double sigma_xy_m = 0.25;
  double sigma_yaw_deg = 3.0;
  /// The kernel is cut to 0 beyond this many sigmas (in the Mahalanobis distance).
  double kernel_cutoff = 4.0;
  /// Refine each mode's transform by least squares over every plane pair that agrees with it
  /// (ours; false = the triplet's transform).
  bool refine = true;
  // --- The posterior grid.
  double resolution_m = 0.1;
  double grid_margin_m = 1.0;
  int yaw_bins = 72;
  /// Triplet hypotheses evaluated per match at most (a guard for the unconstrained ablations;
  /// when reached the counters say so).
  int max_hypotheses = 2000000;

  void apply_shared(const SharedParams& shared);
  /// The field list (core/fields.hpp): keys, ranges, docs; to_json and apply_overrides use it.
  static const FieldList<PlaneMatcherParams>& fields();
  nlohmann::ordered_json to_json() const;
  /// Applies overrides (keys as in to_json); throws ParameterError naming the key.
  void apply_overrides(const nlohmann::json& overrides);
};

/// The kind of a plane relative to gravity (frames with z up).
enum class PlaneKind { kGround, kCeiling, kWall, kOther };

/// A map plane: a connected planar surface of the extrusion with the paper's descriptors and its
/// extent as a grid of l x l cells in the plane's own (u, v) axes (plane_cell_basis).
struct MapPlane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< outward (into free space)
  double offset_m = 0.0;                              ///< normal . p
  Eigen::Vector3d centroid_m = Eigen::Vector3d::Zero();
  double radius_m = 0.0;
  MeshLabel label = MeshLabel::kWall;  ///< kWall, kGlass, kClutter, kFloor, kCeiling
  PlaneKind kind = PlaneKind::kWall;
  int cells = 0;        ///< occupied cells (area = cells x l^2)
  double cell_m = 0.25; ///< l
  Eigen::Matrix3d basis = Eigen::Matrix3d::Identity();  ///< [u v n]
  int i0 = 0, j0 = 0;   ///< grid cell (i0, j0) is mask (0, 0); cell (i, j) spans u in [i l, (i+1) l)
  int width = 0, height = 0;
  std::vector<std::uint8_t> mask;     ///< width x height, 1 = occupied (row j - j0, column i - i0)
  std::vector<std::uint8_t> grown;    ///< mask dilated by projection_tolerance_m
  std::vector<Eigen::Vector3f> cell_centres_m;  ///< occupied cells, world frame
  /// Is world point p on this plane's (grown) extent? Only the in-plane position is tested.
  bool covers(const Eigen::Vector3d& p_world, bool use_grown = true) const;
};

/// The map planes of a plan and the pairs of wall planes that can be seen together.
struct PlaneMap {
  double cell_m = 0.25;
  std::vector<MapPlane> planes;
  std::vector<int> floors;  ///< indices of floor planes
  std::vector<int> walls;   ///< indices of wall-kind planes (vertical)
  /// For each plane, the other planes whose sphere distance is at most 2 x max range, ascending.
  std::vector<std::vector<int>> neighbours;
  /// The same neighbours that are not horizontal (|n_xy| >= 0.2), as (azimuth of the normal in
  /// radians, index), by azimuth: the pairs a rotation about the vertical can map onto.
  std::vector<std::vector<std::pair<double, int>>> neighbours_by_azimuth;
  std::size_t bytes() const;
};

/// Builds the map planes (no file I/O). Throws InputError for bad extrusion parameters.
PlaneMap build_plane_map(const FloorPlan& plan, const PlaneMatcherParams& params);

/// One hypothesis: a submap-to-map plane triplet and its transform.
struct PlaneHypothesis {
  std::array<int, 3> submap{{-1, -1, -1}};  ///< indices into the submap planes
  std::array<int, 3> map{{-1, -1, -1}};     ///< indices into PlaneMap::planes
  Eigen::Isometry3d T_world_observer = Eigen::Isometry3d::Identity();
  std::array<double, 3> projection{{0, 0, 0}};  ///< p(i, j) of the three pairs (eq. 10)
  std::array<double, 3> overlap{{0, 0, 0}};     ///< o(i, j) (eq. 11)
  int agreeing_planes = 0;   ///< submap planes that agree with a map plane under the transform
  double weight = 0.0;       ///< w_a (eq. 13)
  double density = 0.0;      ///< P at this transform (eq. 14, unnormalised)
};

/// Rotation R (R n_S ~ n_M) from normal pairs: the unit quaternion maximising sum n_M . R n_S,
/// the eigenvector of the largest eigenvalue of Horn's 4x4 matrix (the paper's eq. 6, 8, 9).
Eigen::Matrix3d rotation_from_normals(const std::vector<Eigen::Vector3d>& n_submap,
                                      const std::vector<Eigen::Vector3d>& n_map);
/// Translation t minimising sum (d_M - d_S - n_M . t)^2 (eq. 7; n_M = R n_S) by SVD; rank-
/// deficient directions get the minimum-norm solution.
Eigen::Vector3d translation_from_offsets(const std::vector<Eigen::Vector3d>& n_map,
                                         const std::vector<double>& d_map, const std::vector<double>& d_submap);
/// Gravity-aligned transform (rotation about z only) from plane pairs: yaw by least squares on
/// the horizontal parts of the normals, then the translation as above.
Eigen::Isometry3d gravity_aligned_transform(const std::vector<PlanePatch>& submap, const std::vector<const MapPlane*>& map);
/// The same from normals and offsets (n_submap[k], d_submap[k] paired with n_map[k], d_map[k]).
Eigen::Isometry3d gravity_aligned_transform(const std::vector<Eigen::Vector3d>& n_submap, const std::vector<double>& d_submap,
                                            const std::vector<Eigen::Vector3d>& n_map, const std::vector<double>& d_map);

/// The pose of the observer in the plan from a 3D transform (x, y and the yaw of its x axis).
Pose2 planar_pose(const Eigen::Isometry3d& T_world_observer);

class PlaneMatcher final : public Matcher {
 public:
  PlaneMatcher(const FloorPlan& plan, const PlaneMatcherParams& params = {});
  ~PlaneMatcher() override;
  std::string name() const override { return "planes"; }
  nlohmann::ordered_json parameters() const override { return params_.to_json(); }
  double precompute_s() const override { return precompute_s_; }
  std::size_t precompute_bytes() const override;
  BlockingOptions blocking() const override { return params_.blocking; }
  using Matcher::match;
  MatchResult match(const Observation2D& observation, const MatchRequest& request) const override;

  const PlaneMap& map() const { return *map_; }
  const PlaneMatcherParams& params() const { return params_; }

  /// Every triplet hypothesis that passes the evaluation, with weights and densities, for the
  /// observation's planes; `brute_force` enumerates every ordered map triplet for every submap
  /// triplet with no pruning but the evaluation (tests compare it with the pruned search).
  std::vector<PlaneHypothesis> hypotheses(const Observation2D& observation, bool brute_force = false) const;

 private:
  struct Search;
  /// Pair weights, triplet weights and densities of the accepted hypotheses (eq. 12-14).
  void weigh(std::vector<PlaneHypothesis>& hypotheses) const;
  PlaneMatcherParams params_;
  std::shared_ptr<const PlaneMap> map_;
  GridSpec grid_;
  cv::Mat valid_;  ///< where an observer may stand (matcher_valid_mask)
  double precompute_s_ = 0.0;
};

}  // namespace floorcast
