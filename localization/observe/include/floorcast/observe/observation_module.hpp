// The observation module: from a rotating scan (depth views with poses) to observed wall segments
// in the observer's frame, as PALMS+ (monocular depth, sec. 3.2 and supplementary) and PALMS
// (LiDAR vertical planes, sec. III-A) do it. Every step is switchable for ablations.
//
// Mono path (PALMS+):  back-project each view (edge pixels, glass and far views removed)
//   -> per-view relative scales by L-BFGS-B on the robust nearest-neighbour distance between
//      overlapping neighbouring views (eq. 2-3) -> merge (0.01 m voxel) -> ground plane (RANSAC)
//      -> global scale so the camera is 1.5 m above it -> subsample (0.1 m voxel) -> slice a band
//      around camera height -> 2D raster (0.1 m) -> probabilistic Hough -> segments.
// LiDAR path (PALMS): back-project -> merge/subsample -> vertical planes (PCL region growing or
//   the VoxelPlane-Reloc extractor) -> each vertical plane becomes a segment spanning its extent.
//
// Frames: scan frame of core/scan.hpp (origin at the camera centre, gravity aligned, z up, floor at
// z = -camera height); output segments in the 2D observer frame (scan x, y).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "floorcast/core/fields.hpp"
#include "floorcast/core/observation.hpp"
#include "floorcast/core/scan.hpp"
#include "floorcast/core/types.hpp"
#include "floorcast/observe/bev_predictor.hpp"
#include "floorcast/observe/observe_planes.hpp"

namespace floorcast {

enum class ObservationPath { kMono, kLidar };
/// PALMS+ Table 4: Full (overlap + ground), Ground (per-view scale from each view's own ground
/// plane; views without one are dropped), None (depth used as measured).
enum class ScaleAlignment { kFull, kGround, kNone };

std::string to_string(ObservationPath path);           ///< "mono" | "lidar"
std::string to_string(ScaleAlignment mode);            ///< "full" | "ground" | "none"
ObservationPath parse_observation_path(const std::string& s);   ///< throws InputError
ScaleAlignment parse_scale_alignment(const std::string& s);     ///< throws InputError

/// Turning depth images into points (both paths).
struct BackProjectionParams {
  /// PALMS+ code: Canny(10, 20) on the depth normalised to 8 bit, edges dilated, pixels removed
  /// (flying pixels at depth discontinuities).
  bool remove_depth_edges = true;
  double canny_low = 10.0;
  double canny_high = 20.0;
  int edge_dilation_px = 1;  ///< dilation radius: a (2r+1)^2 square, 0 = no dilation
  /// PALMS+* setting: drop pixels the view's glass mask marks (see-through, glass returns).
  bool mask_glass = false;
  /// PALMS+: a view whose maximum kept depth is >= this is dropped (sky through a window).
  double max_view_depth_m = 100.0;
  /// Pixels whose confidence is below this are dropped (views without a confidence map keep all).
  int min_confidence = 0;
  /// Use every n-th pixel in both directions (1 = all pixels).
  int pixel_stride = 1;
};

/// Per-view relative scale alignment (PALMS+ eq. 2-3) and the global scale from the ground.
struct ScaleAlignmentParams {
  ScaleAlignment mode = ScaleAlignment::kFull;
  /// Each view's cloud is subsampled (uniformly, seeded) to at most this many points; the
  /// overlap sub-clouds of its pairs are taken from them (PALMS+: <= 5000 points per cloud).
  int max_points_per_cloud = 5000;
  /// Two views are neighbours when each has at least min_overlap_points points, and at least
  /// min_overlap_fraction of its points, inside the other's view frustum (adjacent views of a
  /// rotating scan; views that only share the floor at the user's feet are not neighbours).
  int min_overlap_points = 200;
  double min_overlap_fraction = 0.1;
  /// ... and, when > 0, only each view's this many largest overlaps are candidates (2 = the ring
  /// of adjacent views). 0 (default): every pair that overlaps enough; on an 18-view phone scan
  /// the ring alone lets scale errors accumulate around the loop (median error 5.8% vs 3.2%).
  int max_neighbours_per_view = 0;
  double min_scale = 0.5;  ///< L-BFGS-B bounds on the relative scales (PALMS+ joint: [0.5, 1.5])
  double max_scale = 1.5;
  int reference_view = 0;  ///< index among the kept views whose scale is fixed to 1
  /// Nearest neighbours and the min-max normalisation of eq. 3 are frozen at the current scales,
  /// the resulting smooth problem is solved with L-BFGS-B, and this repeats (ICP style) until no
  /// scale moves by more than round_tolerance or max_rounds is reached.
  int max_rounds = 30;
  double round_tolerance = 2e-3;
  double round_trust_region = 0.05;  ///< max change of a scale within one round
  /// Starting point (ours, not in PALMS+): in a rotating scan neighbouring views see the same
  /// rays, so the median ratio of their depths along shared rays estimates each pair's relative
  /// scale; a least-squares fit of the log ratios over the pair graph gives the initial scales.
  /// false = start at 1 (PALMS+).
  bool ray_ratio_init = true;
  int max_iterations = 8;          ///< L-BFGS-B iterations per round (re-association follows)
  double gradient_epsilon = 1e-5;  ///< L-BFGS-B projected-gradient tolerance
  double relative_epsilon = 1e-6;  ///< ... and relative objective decrease over 3 iterations
  /// Canonical camera height above the ground plane the global scale enforces (PALMS+: 1.5 m).
  double camera_height_m = 1.5;
  std::uint64_t seed = 1;  ///< the per-view subsampling (same seed, same points, any thread count)
};

/// Ground plane detection (PALMS+ code).
struct GroundPlaneParams {
  /// The observe pipeline hands the search every point_stride-th back-projected point of each
  /// view (it voxelises at voxel_m anyway; a 4x thinner 640x480 view still fills 5 cm floor
  /// voxels out to ~10 m).
  int point_stride = 4;
  double voxel_m = 0.05;          ///< the search runs on the cloud subsampled with this voxel
  double lowest_fraction = 0.10;  ///< candidates: the lowest 10% of points by height
  int normal_k = 30;              ///< normals from k nearest neighbours
  double max_normal_tilt_deg = 15.0;  ///< candidate normals within 15 deg of vertical
  double ransac_distance_m = 0.1;
  int ransac_iterations = 1000;
  double min_inlier_fraction = 0.01;  ///< rejected when inliers < 1% of all points
  double height_bin_m = 0.05;         ///< ground height = mode of inlier heights in these bins
  /// Refinement (not in PALMS+): the height becomes the mean of the inlier heights within one bin
  /// of the mode bin's centre, removing the +-bin/2 quantisation. false = bin centre (PALMS+).
  bool refine_height = true;
};

/// Merging, slicing and segment extraction (mono path) in the observer frame.
struct SliceParams {
  double merge_voxel_m = 0.01;      ///< PALMS+: merged cloud voxelised at 0.01 m (0 = off)
  double subsample_voxel_m = 0.1;   ///< then subsampled at 0.1 m (0 = off)
  /// Half heights of the band around camera height, tried in order until one is not empty
  /// (PALMS+ code: 0.2 m, then 0.5 m, then 2.0 m).
  std::vector<double> band_half_heights_m = {0.2, 0.5, 2.0};
  double max_range_m = 25.0;  ///< points farther (horizontally) are ignored (PALMS+: ~25 m range)
};

struct SegmentExtractionParams {
  double resolution_m_per_px = 0.1;
  /// Canny on the binary raster before the Hough transform (PALMS+ paper). Off by default: on a
  /// raster of 1-px wall traces Canny outlines both sides of each trace, doubling every wall
  /// half a pixel off (see localization/observe/README.md for the measurement).
  bool canny_before_hough = false;
  double hough_rho_px = 1.0;
  double hough_theta_deg = 1.0;
  int hough_threshold = 5;
  double hough_min_length_px = 5.0;
  double hough_max_gap_px = 5.0;
  /// Refinement (not in PALMS+): each Hough segment is re-fitted (total least squares) to the 2D
  /// points within refine_band_m of it (three passes, halving the band), its ends projected on
  /// the fitted line, trimmed to the supporting points and grown along the line over supporting
  /// points with gaps up to the Hough max gap. Removes the raster quantisation (half a pixel in
  /// position, up to several degrees for short pieces of 2-px traces) and Hough's fragmentation.
  bool refine_segments = true;
  double refine_band_m = 0.15;
  /// Also not in PALMS+: a segment lying on a longer one (within merge_tolerance_m and
  /// merge_tolerance_deg) is merged into it (union of extents when they overlap or the gap is at
  /// most the Hough max gap). Hough returns several overlapping pieces per wall trace.
  bool merge_collinear = true;
  double merge_tolerance_m = 0.05;
  double merge_tolerance_deg = 2.0;
  /// F3Loc-style ranges on equiangular rays from the 2D points: per ray the nearest point within
  /// ray_tolerance_deg of its direction (max range when none). 0 rays = none.
  int num_rays = 36;
  double ray_tolerance_deg = 2.0;
};

/// LiDAR back-projection defaults: no depth-edge removal (PALMS uses ARKit's planes directly;
/// per-pixel sensor noise would make Canny mark most of a LiDAR depth map).
/// Low-confidence pixels (ARKit confidence 0: glass-affected, grazing, at the range limit) are
/// dropped, as ARKit-based plane detection does.
inline BackProjectionParams lidar_back_projection_defaults() {
  BackProjectionParams p;
  p.remove_depth_edges = false;
  p.min_confidence = 1;
  return p;
}

/// LiDAR path: vertical planes to segments.
struct LidarPathParams {
  BackProjectionParams back_projection = lidar_back_projection_defaults();
  double voxel_m = 0.05;  ///< the merged LiDAR cloud is subsampled with this voxel
  /// VoxelPlane by default: on 24 simulated iPhone-LiDAR scans of the shipped apartment and
  /// office it recovers 0.76 of the wall length visible within 5 m vs 0.64 for PCL region
  /// growing (precision 0.92 vs 0.94), in ~1/6 of the time (`floorcast bench walls`,
  /// localization/observe/README.md). PCL's curvature threshold (0.1) stops region growth on walls
  /// beyond ~3.5 m, where the axial noise (2-3 cm) makes the normals' curvature exceed it.
  PlaneExtractorKind extractor = PlaneExtractorKind::kVoxelPlane;
  PclRegionGrowingParams pcl;
  VoxelPlaneParams voxel_plane;
  /// A plane is vertical (a wall) when its normal is within this angle of horizontal.
  double max_wall_tilt_deg = 10.0;
  double min_wall_width_m = 0.3;   ///< horizontal extent of a kept wall plane
  double min_wall_height_m = 0.5;  ///< vertical extent of a kept wall plane
  /// A kept wall plane must reach into the band +-wall_band_half_height_m around camera height
  /// (z = 0), where floor plans cut buildings (and where the mono path slices): desks and other
  /// low furniture are not walls. false = every vertical plane (PALMS with ARKit planes).
  bool require_camera_height = true;
  double wall_band_half_height_m = 0.2;
  double max_range_m = 25.0;       ///< points farther (horizontally) are ignored
};

/// 3D plane patches for plane matchers (Observation2D::planes): every plane the extractor finds,
/// as its normal, offset, enclosing sphere and occupied cells of an l x l grid of the plane
/// (core/plane_patch.hpp).
struct PlanePatchParams {
  /// LiDAR path: patches of the planes it extracts anyway (walls, floor, ceiling, furniture).
  bool lidar = true;
  /// Mono path: the voxel-plane extractor (lidar.voxel_plane settings) on the scaled, merged
  /// cloud, every mono_point_stride-th point of each view voxelised at mono_voxel_m (an extra
  /// extraction; off by default).
  bool mono = false;
  int mono_point_stride = 4;
  double mono_voxel_m = 0.05;
  double cell_m = 0.25;           ///< l (VoxelPlane-Reloc's grid patches)
  int min_points_per_cell = 2;    ///< a cell is part of the patch with this many points
  double min_area_m2 = 0.25;      ///< smaller patches are left out
};

struct ObservationParams {
  ObservationPath path = ObservationPath::kMono;
  BackProjectionParams back_projection;  ///< mono path (the LiDAR path has its own)
  ScaleAlignmentParams scale;
  GroundPlaneParams ground;
  SliceParams slice;
  SegmentExtractionParams segments;
  LidarPathParams lidar;
  /// The semantic BEV (off by default): a simulated predictor or the views' own BEVs
  /// (bev_predictor.hpp), for the BEV matcher.
  BevPredictorParams bev;
  PlanePatchParams planes;
};

/// The field list of every observation-module parameter (core/fields.hpp): sections path,
/// back_projection, scale, ground, slice, segments, lidar_back_projection, lidar, lidar_pcl,
/// lidar_voxelplane; ranges, rules and docs (docs/parameters.md).
const FieldList<ObservationParams>& observation_fields();
/// The field list of the VoxelPlane extractor's parameters (section lidar_voxelplane above;
/// `bench planes` writes them with its results).
const FieldList<VoxelPlaneParams>& voxel_plane_fields();
/// Every parameter with its value, for writing next to results.
nlohmann::ordered_json to_json(const ObservationParams& params);
/// Fills params from a JSON object of overrides with the same keys as to_json (nested objects
/// for the sub-structs); unknown keys or bad values throw ParameterError naming the key, after
/// the rules across fields are checked (validate()).
void apply_overrides(ObservationParams& params, const nlohmann::json& overrides);
/// Range of every numeric parameter (NaN and inf never pass) and the orderings (canny_low <=
/// canny_high, min_scale < max_scale); throws ParameterError naming the key. The observation
/// module calls it on entry, so parameters set in code are held to the same ranges.
void validate(const ObservationParams& params);

// ---------------------------------------------------------------------------------------------
// Building blocks (exposed for tests, benches and ablations).

using PointCloud3f = std::vector<Eigen::Vector3f>;

/// One view's points: camera-frame points (scale 1) and the view's pose.
struct ViewCloud {
  int view_index = -1;                  ///< index into Scan::views
  Eigen::Isometry3d T_scan_camera = Eigen::Isometry3d::Identity();
  CameraIntrinsics intrinsics;
  PointCloud3f points_camera;           ///< camera frame, metres as measured
  double max_depth_m = 0.0;
  cv::Mat depth_m;                      ///< the view's depth image (shared, not copied)
  std::size_t pixels_valid = 0;         ///< pixels with a return
  std::size_t pixels_edge_removed = 0;  ///< removed as depth edges
  std::size_t pixels_glass_removed = 0;
  std::size_t pixels_low_confidence = 0;
};

struct BackProjectionResult {
  std::vector<ViewCloud> views;     ///< kept views, in scan order
  std::vector<int> dropped_views;   ///< views dropped for max depth >= max_view_depth_m
};

/// Back-projects every view of a scan (parallel over views, deterministic).
BackProjectionResult back_project_scan(const Scan& scan, const BackProjectionParams& params);

/// Pixels of a depth image on depth edges (CV_8U 255), as the PALMS+ code finds them.
cv::Mat depth_edge_mask(const cv::Mat& depth_m, const BackProjectionParams& params);

/// A view cloud in the scan frame with its depth scaled by `scale` (about the camera centre).
PointCloud3f view_points_scan(const ViewCloud& view, double scale);

struct RelativeScaleResult {
  std::vector<double> scales;                 ///< one per view, reference = 1
  std::vector<double> initial_scales;         ///< the starting point (ray depth ratios or 1)
  std::vector<std::pair<int, int>> pairs;     ///< neighbouring view pairs used (indices into views)
  double objective_initial = 0.0;
  double objective_final = 0.0;
  int rounds = 0;       ///< association rounds
  std::vector<double> round_steps;  ///< largest scale change of each round's inner solve
  double setup_s = 0.0;        ///< overlaps, sampling, kd-trees (wall seconds; not in to_json)
  double association_s = 0.0;  ///< nearest-neighbour searches, all rounds
  double solve_s = 0.0;        ///< L-BFGS-B inner solves, all rounds
  int iterations = 0;   ///< L-BFGS-B iterations, all rounds
  int evaluations = 0;  ///< objective evaluations, all rounds
  bool converged = false;
  std::string status;                         ///< solver outcome in words
};

/// PALMS+ eq. 2-3: relative depth scales of the views, minimising the robust nearest-neighbour
/// distance between overlapping neighbouring clouds with L-BFGS-B (LBFGSpp).
RelativeScaleResult estimate_relative_scales(const std::vector<ViewCloud>& views,
                                             const ScaleAlignmentParams& params);

/// The PALMS+ eq. 3 objective for given scales (both directions of every pair), as optimised;
/// exposed so tests can compare the analytic gradient with finite differences.
double relative_scale_objective(const std::vector<ViewCloud>& views,
                                const std::vector<std::pair<int, int>>& pairs,
                                const std::vector<double>& scales, const ScaleAlignmentParams& params,
                                std::vector<double>* gradient = nullptr);

struct GroundPlaneResult {
  bool found = false;
  std::string reason;                    ///< why not found
  double height_m = 0.0;                 ///< ground z in the cloud's frame (negative below camera)
  Eigen::Vector4d plane = Eigen::Vector4d::Zero();  ///< RANSAC plane ax+by+cz+d=0, c > 0
  std::size_t candidates = 0;            ///< lowest points with near-vertical normals
  std::size_t inliers = 0;
  std::size_t points = 0;                ///< points searched
};

/// PALMS+ ground plane on a scan-frame cloud (voxelised at params.voxel_m first).
GroundPlaneResult detect_ground_plane(const PointCloud3f& points_scan, const GroundPlaneParams& params);

/// Voxel-grid subsampling: one point per occupied voxel at the centroid of its points, voxels in
/// sorted key order (deterministic). voxel_m <= 0 returns the input.
PointCloud3f voxel_downsample(const PointCloud3f& points, double voxel_m);

/// voxel_downsample(voxel_downsample(points, fine_m), coarse_m) in one sort when coarse_m is a
/// whole multiple of fine_m (fine voxels nest in coarse ones; equal up to float rounding at cell
/// borders); otherwise the two passes. `fine_count` receives the size of the fine cloud.
PointCloud3f voxel_downsample_two_level(const PointCloud3f& points, double fine_m, double coarse_m,
                                        std::size_t* fine_count = nullptr);

/// Points of the band |z| <= half around camera height (z = 0) within max_range_m horizontally,
/// projected to 2D (observer frame).
std::vector<Eigen::Vector2d> slice_points(const PointCloud3f& cloud, double half, double max_range_m);

/// The points that can contribute to slice_points(voxelised cloud, half, max_range_m) when the
/// cloud is voxelised with voxel_m (0 = not voxelised): the voxel layers within two voxels of the
/// band, and the horizontal range plus four voxels. Whole voxels are kept, so voxelising this slab
/// gives the same slice as voxelising everything.
PointCloud3f slice_slab(const PointCloud3f& cloud, double half, double voxel_m, double max_range_m);

struct SegmentExtractionResult {
  std::vector<Segment2> segments_m;  ///< observer frame
  std::vector<double> ray_ranges_m;
  cv::Mat raster;                    ///< CV_8U raster the Hough transform saw (row r = +y)
  double origin_x_m = 0.0;           ///< raster cell (0, 0) lower-left corner
  double origin_y_m = 0.0;
};

/// 2D points (observer frame) -> raster -> probabilistic Hough -> segments (+ refinement, rays).
SegmentExtractionResult extract_segments_2d(const std::vector<Eigen::Vector2d>& points_m,
                                            const SegmentExtractionParams& params,
                                            double max_range_m);

/// Orients a segment so the observer (the origin) is on its left, like perfect observations (free
/// space on each segment's left).
inline void orient_observer_left(Segment2& s) {
  const Vec2 d = s.b_m - s.a_m;
  if (d.x() * (-s.a_m.y()) - d.y() * (-s.a_m.x()) < 0.0) std::swap(s.a_m, s.b_m);
}

/// Ranges along num_rays equiangular rays (ray i at i * 360/num_rays deg CCW from +x): the
/// nearest point within tolerance_deg of the ray's direction, max_range_m when none.
std::vector<double> ray_ranges_2d(const std::vector<Eigen::Vector2d>& points_m, int num_rays,
                                  double tolerance_deg, double max_range_m);

/// Patches of extracted planes (params.cell_m grid, points of `cloud`), larger than
/// params.min_area_m2, in the planes' order.
std::vector<PlanePatch> plane_patches(const PointCloud3f& cloud, const std::vector<Plane3>& planes,
                                      const PlanePatchParams& params);

/// Vertical planes of a scan-frame cloud as wall segments (LiDAR path).
struct WallPlaneResult {
  std::vector<Segment2> segments_m;
  std::vector<Plane3> planes;       ///< all extracted planes
  std::vector<int> wall_planes;     ///< indices of planes kept as walls
};
WallPlaneResult extract_wall_segments(const PointCloud3f& points_scan, const LidarPathParams& params);

// ---------------------------------------------------------------------------------------------
// The whole module.

struct ObservationDiagnostics {
  std::string path;
  std::string scale_alignment;
  std::size_t views_total = 0;
  std::vector<int> views_used;          ///< scan view indices kept
  std::vector<int> views_dropped_far;   ///< dropped for max depth >= threshold
  std::vector<int> views_dropped_no_ground;  ///< Ground setting: views without a ground plane
  /// Final depth scale applied to each used view (relative x global), same order as views_used.
  std::vector<double> view_scales;
  std::vector<double> relative_scales;  ///< from the overlap alignment (1 when not run)
  double global_scale = 1.0;
  RelativeScaleResult relative;         ///< solver details (empty when not run)
  GroundPlaneResult ground;             ///< on the relatively aligned, unscaled cloud
  double ground_height_after_m = 0.0;   ///< ground z after all scaling (mono: -camera height)
  std::size_t points_back_projected = 0;
  std::size_t pixels_edge_removed = 0;
  std::size_t pixels_glass_removed = 0;
  /// Mono path: after the merge voxel and after the subsample voxel, counted in the slab of whole
  /// voxels around the slice band that was voxelised (the rest cannot reach the slice).
  /// LiDAR path: both the voxelised cloud.
  std::size_t points_merged = 0;
  std::size_t points_subsampled = 0;
  std::size_t points_in_slice = 0;
  double band_half_height_m = 0.0;      ///< band actually used (after fallbacks)
  std::size_t planes_total = 0;         ///< LiDAR path (and the mono path with planes.mono)
  std::size_t wall_planes = 0;          ///< LiDAR path
  /// BEV (when params.bev.enabled): views that gave columns, of them with their own BEV, columns,
  /// and the error model's draw counts.
  std::vector<int> bev_views_used;
  std::vector<int> bev_views_brought;
  int bev_columns = 0;
  std::map<std::string, int> bev_events;
  /// Degradations the caller should know about (no ground plane -> global scale 1, empty slice
  /// bands, every view dropped, ...). Nothing is dropped or defaulted without a line here.
  std::vector<std::string> warnings;
};

struct ObservationResult {
  Observation2D observation;
  ObservationDiagnostics diagnostics;
  /// Wall-clock seconds per stage ("back_project", "scale_alignment" (with sub-stages
  /// "scale_alignment.setup|association|solve"), "ground", "merge", "voxelise", "slice",
  /// "segments", "planes", ...) and in total. Timings live here only, so diagnostics are
  /// reproducible bytes.
  std::map<std::string, double> stage_s;
  double total_s = 0.0;
};

/// Runs the observation module on one scan. Throws InputError for malformed scans (no views,
/// depth images that do not match their intrinsics). A scan that yields nothing usable (every
/// view dropped, empty slice) gives an empty observation and says why in diagnostics.warnings.
ObservationResult observe_scan(const Scan& scan, const ObservationParams& params = {});

nlohmann::ordered_json to_json(const ObservationDiagnostics& diagnostics);

}  // namespace floorcast
