// Parameters of the observation module as JSON (written next to results) and JSON overrides.
#include <cmath>

#include "floorcast/core/json_text.hpp"
#include "floorcast/core/limits.hpp"
#include "floorcast/core/fields.hpp"
#include "floorcast/core/params.hpp"
#include "floorcast/observe/observation_module.hpp"

namespace floorcast {
namespace {

const std::vector<std::pair<const char*, ObservationPath>> kPathNames = {{"mono", ObservationPath::kMono},
                                                                         {"lidar", ObservationPath::kLidar}};
const std::vector<std::pair<const char*, ScaleAlignment>> kScaleNames = {
    {"full", ScaleAlignment::kFull}, {"ground", ScaleAlignment::kGround}, {"none", ScaleAlignment::kNone}};
const std::vector<std::pair<const char*, PlaneExtractorKind>> kExtractorNames = {
    {"pcl", PlaneExtractorKind::kPclRegionGrowing}, {"voxelplane", PlaneExtractorKind::kVoxelPlane}};

const FieldList<BackProjectionParams>& back_projection_fields() {
  using P = BackProjectionParams;
  static const FieldList<P> f =
      FieldList<P>("back projection")
          .flag("remove_depth_edges", &P::remove_depth_edges,
                "remove flying pixels at depth discontinuities (PALMS+ code: Canny on the 8-bit depth, dilated)")
          .number("canny_low", &P::canny_low, 0, 1000, "Canny low threshold (PALMS+ code: 10)")
          .number("canny_high", &P::canny_high, 0, 1000, "Canny high threshold (PALMS+ code: 20)")
          .integer("edge_dilation_px", &P::edge_dilation_px, 0, 50, "edge dilation radius, px (0 = none)")
          .flag("mask_glass", &P::mask_glass, "drop pixels the view's glass mask marks (PALMS+*)")
          .number("max_view_depth_m", &P::max_view_depth_m, 0.01, 1000,
                  "a view whose largest kept depth reaches this is dropped, m (sky through a window)")
          .integer("min_confidence", &P::min_confidence, 0, 2, "pixels of lower confidence are dropped")
          .integer("pixel_stride", &P::pixel_stride, 1, 64, "use every n-th pixel in both directions")
          .check([](const P& p, const ParamReader& r) {
            if (p.canny_low > p.canny_high) {
              r.fail("canny_low", "must not exceed canny_high (" + nlohmann::json(p.canny_high).dump() + ")");
            }
          });
  return f;
}

const FieldList<ScaleAlignmentParams>& scale_fields() {
  using P = ScaleAlignmentParams;
  static const FieldList<P> f =
      FieldList<P>("scale alignment")
          .choice("mode", &P::mode, kScaleNames, "PALMS+ Table 4: full (overlap + ground), ground, none")
          .integer("max_points_per_cloud", &P::max_points_per_cloud, 10, 10000000,
                   "each view's cloud subsampled to at most this many points (PALMS+: 5000)")
          .integer("min_overlap_points", &P::min_overlap_points, 1, 10000000,
                   "neighbour views: points of each inside the other's frustum")
          .number("min_overlap_fraction", &P::min_overlap_fraction, 0, 1, "neighbour views: fraction of each inside the other's frustum")
          .integer("max_neighbours_per_view", &P::max_neighbours_per_view, 0, 360,
                   "only each view's largest overlaps are candidates (0 = every pair that overlaps enough)")
          .number("min_scale", &P::min_scale, 0.01, 1, "L-BFGS-B lower bound on relative scales (PALMS+: 0.5)")
          .number("max_scale", &P::max_scale, 1, 100, "L-BFGS-B upper bound on relative scales (PALMS+: 1.5)")
          .integer("reference_view", &P::reference_view, 0, 359, "index among the kept views whose scale is fixed to 1")
          .integer("max_rounds", &P::max_rounds, 1, 1000, "re-association rounds (ICP style)")
          .number("round_tolerance", &P::round_tolerance, 0, 10, "stop when no scale moves more than this in a round")
          .number("round_trust_region", &P::round_trust_region, 1e-6, 10, "largest change of a scale within one round")
          .flag("ray_ratio_init", &P::ray_ratio_init,
                "start from the median depth ratios along shared rays (ours; false = start at 1 as PALMS+)")
          .integer("max_iterations", &P::max_iterations, 1, 10000, "L-BFGS-B iterations per round")
          .number("gradient_epsilon", &P::gradient_epsilon, 0, 1, "L-BFGS-B projected-gradient tolerance")
          .number("relative_epsilon", &P::relative_epsilon, 0, 1, "L-BFGS-B relative objective decrease over 3 iterations")
          .number("camera_height_m", &P::camera_height_m, 0.05, 50,
                  "camera height above the ground the global scale enforces, m (PALMS+: 1.5)")
          .unsigned_integer("seed", &P::seed, "per-view subsampling seed")
          .check([](const P& p, const ParamReader& r) {
            if (!(p.min_scale < p.max_scale)) {
              r.fail("min_scale", "must be below scale.max_scale (" + nlohmann::json(p.max_scale).dump() + ")");
            }
          });
  return f;
}

const FieldList<GroundPlaneParams>& ground_fields() {
  using P = GroundPlaneParams;
  static const FieldList<P> f =
      FieldList<P>("ground plane")
          .integer("point_stride", &P::point_stride, 1, 1000, "every n-th back-projected point of each view is searched")
          .number("voxel_m", &P::voxel_m, 0.001, 10, "the search runs on the cloud subsampled with this voxel, m")
          .number("lowest_fraction", &P::lowest_fraction, 0.001, 1, "candidates: this lowest fraction of points by height")
          .integer("normal_k", &P::normal_k, 3, 1000, "normals from k nearest neighbours")
          .number("max_normal_tilt_deg", &P::max_normal_tilt_deg, 0, 90, "candidate normals within this of vertical, deg")
          .number("ransac_distance_m", &P::ransac_distance_m, 0.0001, 10, "RANSAC inlier distance, m")
          .integer("ransac_iterations", &P::ransac_iterations, 1, 10000000, "RANSAC iterations")
          .number("min_inlier_fraction", &P::min_inlier_fraction, 0, 1, "rejected when inliers are fewer than this of all points")
          .number("height_bin_m", &P::height_bin_m, 0.0001, 10, "ground height = mode of inlier heights in bins of this, m")
          .flag("refine_height", &P::refine_height, "mean of the inlier heights around the mode bin (ours; false = bin centre)");
  return f;
}

const FieldList<SliceParams>& slice_fields() {
  using P = SliceParams;
  static const FieldList<P> f =
      FieldList<P>("slice")
          .number("merge_voxel_m", &P::merge_voxel_m, 0, 10, "merged cloud voxel, m (PALMS+: 0.01; 0 = off)")
          .number("subsample_voxel_m", &P::subsample_voxel_m, 0, 10, "then subsampled with this voxel, m (PALMS+: 0.1; 0 = off)")
          .numbers("band_half_heights_m", &P::band_half_heights_m, 0.001, 50,
                   "half heights of the band around camera height, tried in order (PALMS+ code: 0.2, 0.5, 2.0), m")
          .number("max_range_m", &P::max_range_m, 0.1, 1000, "points farther horizontally are ignored, m");
  return f;
}

const FieldList<SegmentExtractionParams>& segment_fields() {
  using P = SegmentExtractionParams;
  static const FieldList<P> f =
      FieldList<P>("segments")
          .number("resolution_m_per_px", &P::resolution_m_per_px, 0.005, 10, "2D raster resolution, m/px")
          .flag("canny_before_hough", &P::canny_before_hough, "Canny on the raster before the Hough transform (PALMS+ paper)")
          .number("hough_rho_px", &P::hough_rho_px, 0.1, 100, "Hough distance resolution, px")
          .number("hough_theta_deg", &P::hough_theta_deg, 0.01, 90, "Hough angle resolution, deg")
          .integer("hough_threshold", &P::hough_threshold, 1, 1000000, "Hough accumulator threshold")
          .number("hough_min_length_px", &P::hough_min_length_px, 0, 1000000.0, "shortest Hough segment, px")
          .number("hough_max_gap_px", &P::hough_max_gap_px, 0, 1000000.0, "largest gap bridged by Hough, px")
          .flag("refine_segments", &P::refine_segments, "re-fit each segment to its supporting points (ours)")
          .number("refine_band_m", &P::refine_band_m, 0, 10, "points within this of a segment support it, m")
          .flag("merge_collinear", &P::merge_collinear, "merge segments lying on longer ones (ours)")
          .number("merge_tolerance_m", &P::merge_tolerance_m, 0, 10, "collinear merge distance, m")
          .number("merge_tolerance_deg", &P::merge_tolerance_deg, 0, 90, "collinear merge angle, deg")
          .integer("num_rays", &P::num_rays, 0, 3600, "F3Loc-style ranges on this many equiangular rays (0 = none)")
          .number("ray_tolerance_deg", &P::ray_tolerance_deg, 0, 180, "a ray takes the nearest point within this of its direction, deg")
          .check([](const P& p, const ParamReader&) {
            check_limit("max_rays", p.num_rays, "observation parameters: segments.num_rays", "rays");
          });
  return f;
}

const FieldList<LidarPathParams>& lidar_fields() {
  using P = LidarPathParams;
  static const FieldList<P> f =
      FieldList<P>("lidar")
          .number("voxel_m", &P::voxel_m, 0.001, 10, "the merged LiDAR cloud is subsampled with this voxel, m")
          .choice("extractor", &P::extractor, kExtractorNames,
                  "vertical planes by PCL region growing or the VoxelPlane-Reloc extractor")
          .number("max_wall_tilt_deg", &P::max_wall_tilt_deg, 0, 90, "a wall's normal is within this of horizontal, deg")
          .number("min_wall_width_m", &P::min_wall_width_m, 0, 1000, "horizontal extent of a kept wall plane, m")
          .number("min_wall_height_m", &P::min_wall_height_m, 0, 1000, "vertical extent of a kept wall plane, m")
          .flag("require_camera_height", &P::require_camera_height,
                "a kept wall must reach the band around camera height (false = every vertical plane)")
          .number("wall_band_half_height_m", &P::wall_band_half_height_m, 0, 50, "half height of that band, m")
          .number("max_range_m", &P::max_range_m, 0.1, 1000, "points farther horizontally are ignored, m");
  return f;
}

const FieldList<PclRegionGrowingParams>& pcl_fields() {
  using P = PclRegionGrowingParams;
  static const FieldList<P> f =
      FieldList<P>("lidar pcl")
          .integer("normal_k", &P::normal_k, 3, 1000, "neighbours for the normals")
          .integer("neighbours_k", &P::neighbours_k, 1, 1000, "neighbours for growing")
          .number("smoothness_deg", &P::smoothness_deg, 0, 180, "largest normal difference between neighbours, deg")
          .number("curvature_threshold", &P::curvature_threshold, 0, 1000, "region growing curvature threshold")
          .integer("min_cluster_points", &P::min_cluster_points, 1, 100000000, "smallest region, points");
  return f;
}

const FieldList<BevPredictorParams>& bev_predictor_fields() {
  using P = BevPredictorParams;
  std::string presets;
  for (const std::string& n : bev_predictor_presets()) presets += (presets.empty() ? "" : " | ") + n;
  static const FieldList<P> f =
      FieldList<P>("bev predictor")
          .flag("enabled", &P::enabled,
                "make the observation's BEVs: from each view's own BEV file, else from its column semantics through the error model")
          // Read before the error-model keys (declaration order): a preset sets every value, the
          // other keys of the same overrides then change single values of it.
          .custom(
              "preset", [](nlohmann::ordered_json& j, const P& p) { j["preset"] = p.preset; },
              [](ParamReader& r, P& p) {
                std::string name = p.preset;
                r.read("preset", name);
                try {
                  p.error = bev_error_preset(name);
                } catch (const InputError& e) {
                  r.fail("preset", e.what());
                }
                p.preset = name;
              },
              presets.c_str(), "error-model preset (the thesis' Figs. 5.1-5.4; values assumed, bev_predictor.hpp)")
          .number("depth_sigma_ln", [](auto& p) -> auto& { return p.error.depth_sigma_ln; }, 0, 5,
                  "spread of a predicted range (log sigma) at 0 m")
          .number("depth_sigma_ln_per_m", [](auto& p) -> auto& { return p.error.depth_sigma_ln_per_m; }, 0, 5,
                  "growth of the range spread per metre of range (log sigma per m)")
          .number("view_scale_sigma_ln", [](auto& p) -> auto& { return p.error.view_scale_sigma_ln; }, 0, 5,
                  "per view: every range times exp(N(0, s^2))")
          .number("element_offset_sigma_ln", [](auto& p) -> auto& { return p.error.element_offset_sigma_ln; }, 0, 5,
                  "per element: its range times exp(N(0, s^2))")
          .number("window_as_wall", [](auto& p) -> auto& { return p.error.window_as_wall; }, 0, 1,
                  "P(a window is predicted as a wall and stops the ray)")
          .number("wall_as_window", [](auto& p) -> auto& { return p.error.wall_as_window; }, 0, 1, "P(a wall is predicted as a window)")
          .number("door_missed", [](auto& p) -> auto& { return p.error.door_missed; }, 0, 1, "P(a door is not predicted)")
          .number("closed_door_as_wall", [](auto& p) -> auto& { return p.error.closed_door_as_wall; }, 0, 1,
                  "P(a closed door leaf is predicted as a wall)")
          .number("furniture_as_wall", [](auto& p) -> auto& { return p.error.furniture_as_wall; }, 0, 1,
                  "P(furniture at camera height is predicted as a wall)")
          .number("occluded_spread", [](auto& p) -> auto& { return p.error.occluded_spread; }, 0, 1,
                  "share of an unseen element's mass spread beyond its occluder")
          .number("peak_mass", [](auto& p) -> auto& { return p.error.peak_mass; }, 0, 1, "class mass of an element over its bins")
          .number("floor_mass", [](auto& p) -> auto& { return p.error.floor_mass; }, 0, 1,
                  "mass of every (column, bin) spread over all classes")
          .integer("depth_bins", &P::depth_bins, 1, 63, "log-spaced depth bins (the bev matcher's must be the same)")
          .number("min_depth_m", &P::min_depth_m, 0.01, 100, "first depth bin edge, m")
          .number("max_depth_m", &P::max_depth_m, 0.1, 1000, "last depth bin edge, m (the range)")
          .number("column_step_deg", &P::column_step_deg, 0.1, 180,
                  "a BEV column every this many degrees of azimuth, from the view whose heading is nearest")
          .unsigned_integer("seed", &P::seed, "seed of the error model's draws")
          .check([](const P& p, const ParamReader& r) {
            if (!(p.min_depth_m < p.max_depth_m)) {
              r.fail("min_depth_m", "must be below max_depth_m (" + nlohmann::json(p.max_depth_m).dump() + ")");
            }
          });
  return f;
}

const FieldList<PlanePatchParams>& plane_patch_fields() {
  using P = PlanePatchParams;
  static const FieldList<P> f =
      FieldList<P>("planes")
          .flag("lidar", &P::lidar, "LiDAR path: patches of the planes it extracts anyway (walls, floor, ceiling, furniture)")
          .flag("mono", &P::mono, "mono path: the voxel-plane extractor (lidar_voxelplane settings) on the scaled, merged cloud (an extra extraction)")
          .integer("mono_point_stride", &P::mono_point_stride, 1, 1000, "mono path: every n-th point of each view")
          .number("mono_voxel_m", &P::mono_voxel_m, 0.001, 10, "mono path: the points voxelised at this, m")
          .number("cell_m", &P::cell_m, 0.01, 10, "l, the patches' grid cell edge (VoxelPlane-Reloc's l x l patches), m")
          .integer("min_points_per_cell", &P::min_points_per_cell, 1, 1000000, "a cell is part of the patch with this many points")
          .number("min_area_m2", &P::min_area_m2, 0, 1000000, "smaller patches are left out, m^2");
  return f;
}

}  // namespace

const FieldList<VoxelPlaneParams>& voxel_plane_fields() {
  using P = VoxelPlaneParams;
  static const FieldList<P> f =
      FieldList<P>("lidar voxelplane")
          .number("voxel_size_m", &P::voxel_size_m, 0.01, 100, "voxel edge, m")
          .integer("min_points_per_voxel", &P::min_points_per_voxel, 3, 1000000, "points a voxel needs")
          .integer("max_subdivisions", &P::max_subdivisions, 0, 8, "octree splits of non-planar voxels (0 = uniform grid)")
          .number("max_thickness_m", &P::max_thickness_m, 0, 10, "planar voxel: spread along the normal at most this, m")
          .number("max_eigen_ratio", &P::max_eigen_ratio, 0, 1, "planar voxel: smallest/middle eigenvalue at most this")
          .flag("adaptive_weights", &P::adaptive_weights, "the adaptive weights of VoxelPlane-Reloc eq. 2")
          .number("weight_alpha", &P::weight_alpha, 0, 1000000.0, "eq. 2 alpha")
          .number("weight_beta", &P::weight_beta, 0, 1000000.0, "eq. 2 beta")
          .number("growth_max_normal_deg", &P::growth_max_normal_deg, 0, 180, "voxel growth: normal difference, deg")
          .number("growth_max_offset_m", &P::growth_max_offset_m, 0, 100, "voxel growth: centre distance to the plane, m")
          .flag("merge_undergrown", &P::merge_undergrown, "merge under-grown planes into larger ones")
          .number("merge_max_normal_deg", &P::merge_max_normal_deg, 0, 180, "merge: normal difference, deg")
          .number("merge_depth_tol_deg", &P::merge_depth_tol_deg, 0, 180, "merge: centroid line off the plane, deg")
          .number("merge_radius_factor", &P::merge_radius_factor, 0, 100, "merge: centroid distance in plane radii")
          .integer("min_plane_points", &P::min_plane_points, 3, 1000000000, "planes with fewer points are not reported");
  return f;
}

const FieldList<ObservationParams>& observation_fields() {
  using P = ObservationParams;
  static const FieldList<P> f =
      FieldList<P>("observation parameters")
          .choice("path", &P::path, kPathNames, "mono (PALMS+ depth -> Hough) or lidar (PALMS vertical planes)")
          .section("back_projection", &P::back_projection, back_projection_fields())
          .section("scale", &P::scale, scale_fields())
          .section("ground", &P::ground, ground_fields())
          .section("slice", &P::slice, slice_fields())
          .section("segments", &P::segments, segment_fields())
          .section("lidar_back_projection", [](auto& p) -> auto& { return p.lidar.back_projection; }, back_projection_fields())
          .section("lidar", &P::lidar, lidar_fields())
          .section("lidar_pcl", [](auto& p) -> auto& { return p.lidar.pcl; }, pcl_fields())
          .section("lidar_voxelplane", [](auto& p) -> auto& { return p.lidar.voxel_plane; }, voxel_plane_fields())
          .section("bev", &P::bev, bev_predictor_fields())
          .section("planes", &P::planes, plane_patch_fields());
  return f;
}

void validate(const ObservationParams& params) { observation_fields().validate(params); }

std::string to_string(ObservationPath path) { return path == ObservationPath::kLidar ? "lidar" : "mono"; }

std::string to_string(ScaleAlignment mode) {
  switch (mode) {
    case ScaleAlignment::kFull: return "full";
    case ScaleAlignment::kGround: return "ground";
    case ScaleAlignment::kNone: return "none";
  }
  return "full";
}

ObservationPath parse_observation_path(const std::string& s) {
  if (s == "mono") return ObservationPath::kMono;
  if (s == "lidar") return ObservationPath::kLidar;
  throw InputError("observation path \"" + s + "\": expected mono or lidar");
}

ScaleAlignment parse_scale_alignment(const std::string& s) {
  if (s == "full") return ScaleAlignment::kFull;
  if (s == "ground") return ScaleAlignment::kGround;
  if (s == "none") return ScaleAlignment::kNone;
  throw InputError("scale alignment \"" + s + "\": expected full, ground or none");
}

nlohmann::ordered_json to_json(const ObservationParams& params) { return observation_fields().write(params); }

void apply_overrides(ObservationParams& params, const nlohmann::json& overrides) {
  observation_fields().read(params, overrides);
  validate(params);  // the rules of sections the overrides did not touch (limits may have changed)
}

namespace {

constexpr double kAny = 1e300;  // diagnostics: any finite value

const FieldList<RelativeScaleResult>& relative_alignment_fields() {
  using R = RelativeScaleResult;
  static const FieldList<R> f =
      FieldList<R>("relative alignment")
          .custom(
              "pairs",
              [](nlohmann::ordered_json& j, const R& r) {
                j["pairs"] = nlohmann::ordered_json::array();
                for (const auto& [a, b] : r.pairs) j["pairs"].push_back({a, b});
              },
              [](ParamReader& r, R& v) {
                nlohmann::json pairs;
                r.read("pairs", pairs);
                v.pairs.clear();
                for (const auto& p : pairs) v.pairs.emplace_back(p.at(0).get<int>(), p.at(1).get<int>());
              },
              "[[view, view], ...]", "neighbouring view pairs used (indices into the kept views)")
          .series("initial_scales", &R::initial_scales, "starting point (ray depth ratios or 1)")
          .number("objective_initial", &R::objective_initial, -kAny, kAny, "eq. 3 objective at the start")
          .number("objective_final", &R::objective_final, -kAny, kAny, "eq. 3 objective at the end")
          .integer("rounds", &R::rounds, 0, 1 << 30, "association rounds")
          .series("round_steps", &R::round_steps, "largest scale change of each round's inner solve")
          .integer("iterations", &R::iterations, 0, 1 << 30, "L-BFGS-B iterations, all rounds")
          .integer("evaluations", &R::evaluations, 0, 1 << 30, "objective evaluations, all rounds")
          .text("status", &R::status, "solver outcome in words");
  return f;
}

/// The ground plane with the height after all scaling (ObservationDiagnostics::ground_height_after_m)
/// after its height.
const FieldList<ObservationDiagnostics>& ground_result_fields() {
  using D = ObservationDiagnostics;
  static const FieldList<D> f =
      FieldList<D>("ground")
          .flag("found", [](auto& d) -> auto& { return d.ground.found; }, "a ground plane was found")
          .text("reason", [](auto& d) -> auto& { return d.ground.reason; }, "why not")
          .optional([](const D& d) { return !d.ground.reason.empty(); })
          .number("height_m", [](auto& d) -> auto& { return d.ground.height_m; }, -kAny, kAny,
                  "ground z in the relatively aligned, unscaled cloud, m")
          .number("height_after_scaling_m", &D::ground_height_after_m, -kAny, kAny, "ground z after all scaling, m")
          .custom(
              "plane",
              [](nlohmann::ordered_json& j, const D& d) {
                j["plane"] = {d.ground.plane[0], d.ground.plane[1], d.ground.plane[2], d.ground.plane[3]};
              },
              [](ParamReader& r, D& d) {
                std::vector<double> v;
                r.read("plane", v, -kAny, kAny);
                if (v.size() != 4) r.fail("plane", "expected 4 numbers");
                d.ground.plane = Eigen::Vector4d(v[0], v[1], v[2], v[3]);
              },
              "[a, b, c, d]", "RANSAC plane ax + by + cz + d = 0, c > 0")
          .unsigned_integer("points", [](auto& d) -> auto& { return d.ground.points; }, "points searched")
          .unsigned_integer("candidates", [](auto& d) -> auto& { return d.ground.candidates; },
                            "lowest points with near-vertical normals")
          .unsigned_integer("inliers", [](auto& d) -> auto& { return d.ground.inliers; }, "RANSAC inliers");
  return f;
}

/// The BEV block (when BEVs were made).
const FieldList<ObservationDiagnostics>& bev_result_fields() {
  using D = ObservationDiagnostics;
  static const FieldList<D> f =
      FieldList<D>("bev")
          .integers("views_used", &D::bev_views_used, "views that gave BEV columns")
          .integers("views_brought", &D::bev_views_brought, "of them, views with a BEV file of their own")
          .integer("columns", &D::bev_columns, 0, 1 << 30, "columns of the BEVs")
          .custom(
              "events",
              [](nlohmann::ordered_json& j, const D& d) {
                j["events"] = nlohmann::ordered_json::object();
                for (const auto& [k, v] : d.bev_events) j["events"][k] = v;
              },
              [](ParamReader& r, D& d) {
                nlohmann::json events;
                r.read("events", events);
                if (!events.is_object()) r.fail("events", "expected an object of counts");
                d.bev_events.clear();
                for (auto it = events.begin(); it != events.end(); ++it) {
                  if (!it.value().is_number_integer()) r.fail("events." + it.key(), "expected an integer");
                  d.bev_events[it.key()] = it.value().get<int>();
                }
              },
              "{event: count}", "draw counts of the error model (window_as_wall, door_missed, ...)");
  return f;
}

const FieldList<ObservationDiagnostics>& diagnostics_fields() {
  using D = ObservationDiagnostics;
  static const FieldList<D> f =
      FieldList<D>("observation diagnostics")
          .text("path", &D::path, "mono or lidar")
          .text("scale_alignment", &D::scale_alignment, "full, ground or none")
          .unsigned_integer("views_total", &D::views_total, "views of the scan")
          .integers("views_used", &D::views_used, "scan view indices kept")
          .integers("views_dropped_far", &D::views_dropped_far, "dropped for their largest depth")
          .integers("views_dropped_no_ground", &D::views_dropped_no_ground, "ground setting: views without a ground plane")
          .series("view_scales", &D::view_scales, "final depth scale of each used view")
          .series("relative_scales", &D::relative_scales, "from the overlap alignment (1 when not run)")
          .number("global_scale", &D::global_scale, -kAny, kAny, "scale that puts the camera at its height")
          .section("relative_alignment", &D::relative, relative_alignment_fields())
          .section("ground", [](auto& d) -> auto& { return d; }, ground_result_fields())
          .unsigned_integer("points_back_projected", &D::points_back_projected, "points of all views")
          .unsigned_integer("pixels_edge_removed", &D::pixels_edge_removed, "pixels removed at depth edges")
          .unsigned_integer("pixels_glass_removed", &D::pixels_glass_removed, "pixels removed by glass masks")
          .unsigned_integer("points_merged", &D::points_merged, "after the merge voxel")
          .unsigned_integer("points_subsampled", &D::points_subsampled, "after the subsample voxel")
          .unsigned_integer("points_in_slice", &D::points_in_slice, "points in the band at camera height")
          .number("band_half_height_m", &D::band_half_height_m, -kAny, kAny, "band actually used, m")
          .unsigned_integer("planes_total", &D::planes_total, "LiDAR path: planes extracted")
          .unsigned_integer("wall_planes", &D::wall_planes, "LiDAR path: planes kept as walls")
          .section("bev", [](auto& d) -> auto& { return d; }, bev_result_fields())
          .optional([](const D& d) { return !d.bev_views_used.empty() || d.bev_columns > 0; })
          .texts("warnings", &D::warnings, "degradations the caller should know about");
  return f;
}

}  // namespace

nlohmann::ordered_json to_json(const ObservationDiagnostics& d) { return diagnostics_fields().write(d); }

}  // namespace floorcast
