// Parameters of the observation module as JSON (written next to results) and JSON overrides.
#include <cmath>
#include <functional>
#include <variant>

#include "floorcast/core/json_text.hpp"
#include "floorcast/core/limits.hpp"
#include "floorcast/core/params.hpp"
#include "floorcast/observe/observation_module.hpp"

namespace floorcast {
namespace {

/// A string-valued (enum) parameter.
struct EnumField {
  std::function<std::string()> get;
  std::function<void(const std::string&)> set;
};
using FieldRef = std::variant<bool*, int*, double*, std::uint64_t*, std::vector<double>*, EnumField>;

struct Field {
  const char* section;  ///< nullptr = top level
  const char* key;
  FieldRef ref;
  /// Allowed range of a numeric field (of every element of a list), inclusive.
  double lo = 0.0;
  double hi = 0.0;
};

std::vector<Field> fields(ObservationParams& p) {
  auto& b = p.back_projection;
  auto& s = p.scale;
  auto& g = p.ground;
  auto& sl = p.slice;
  auto& se = p.segments;
  auto& l = p.lidar;
  auto& vp = p.lidar.voxel_plane;
  auto& rg = p.lidar.pcl;
  return {
      {nullptr, "path",
       EnumField{[&p] { return to_string(p.path); }, [&p](const std::string& v) { p.path = parse_observation_path(v); }}},
      {"back_projection", "remove_depth_edges", &b.remove_depth_edges},
      {"back_projection", "canny_low", &b.canny_low, 0, 1000},
      {"back_projection", "canny_high", &b.canny_high, 0, 1000},
      {"back_projection", "edge_dilation_px", &b.edge_dilation_px, 0, 50},
      {"back_projection", "mask_glass", &b.mask_glass},
      {"back_projection", "max_view_depth_m", &b.max_view_depth_m, 0.01, 1000},
      {"back_projection", "min_confidence", &b.min_confidence, 0, 2},
      {"back_projection", "pixel_stride", &b.pixel_stride, 1, 64},
      {"scale", "mode",
       EnumField{[&s] { return to_string(s.mode); }, [&s](const std::string& v) { s.mode = parse_scale_alignment(v); }}},
      {"scale", "max_points_per_cloud", &s.max_points_per_cloud, 10, 10000000},
      {"scale", "min_overlap_points", &s.min_overlap_points, 1, 10000000},
      {"scale", "min_overlap_fraction", &s.min_overlap_fraction, 0, 1},
      {"scale", "max_neighbours_per_view", &s.max_neighbours_per_view, 0, 360},
      {"scale", "min_scale", &s.min_scale, 0.01, 1},
      {"scale", "max_scale", &s.max_scale, 1, 100},
      {"scale", "reference_view", &s.reference_view, 0, 359},
      {"scale", "max_rounds", &s.max_rounds, 1, 1000},
      {"scale", "round_tolerance", &s.round_tolerance, 0, 10},
      {"scale", "round_trust_region", &s.round_trust_region, 1e-6, 10},
      {"scale", "ray_ratio_init", &s.ray_ratio_init},
      {"scale", "max_iterations", &s.max_iterations, 1, 10000},
      {"scale", "gradient_epsilon", &s.gradient_epsilon, 0, 1},
      {"scale", "relative_epsilon", &s.relative_epsilon, 0, 1},
      {"scale", "camera_height_m", &s.camera_height_m, 0.05, 50},
      {"scale", "seed", &s.seed},
      {"ground", "point_stride", &g.point_stride, 1, 1000},
      {"ground", "voxel_m", &g.voxel_m, 0.001, 10},
      {"ground", "lowest_fraction", &g.lowest_fraction, 0.001, 1},
      {"ground", "normal_k", &g.normal_k, 3, 1000},
      {"ground", "max_normal_tilt_deg", &g.max_normal_tilt_deg, 0, 90},
      {"ground", "ransac_distance_m", &g.ransac_distance_m, 0.0001, 10},
      {"ground", "ransac_iterations", &g.ransac_iterations, 1, 10000000},
      {"ground", "min_inlier_fraction", &g.min_inlier_fraction, 0, 1},
      {"ground", "height_bin_m", &g.height_bin_m, 0.0001, 10},
      {"ground", "refine_height", &g.refine_height},
      {"slice", "merge_voxel_m", &sl.merge_voxel_m, 0, 10},
      {"slice", "subsample_voxel_m", &sl.subsample_voxel_m, 0, 10},
      {"slice", "band_half_heights_m", &sl.band_half_heights_m, 0.001, 50},
      {"slice", "max_range_m", &sl.max_range_m, 0.1, 1000},
      {"segments", "resolution_m_per_px", &se.resolution_m_per_px, 0.005, 10},
      {"segments", "canny_before_hough", &se.canny_before_hough},
      {"segments", "hough_rho_px", &se.hough_rho_px, 0.1, 100},
      {"segments", "hough_theta_deg", &se.hough_theta_deg, 0.01, 90},
      {"segments", "hough_threshold", &se.hough_threshold, 1, 1000000},
      {"segments", "hough_min_length_px", &se.hough_min_length_px, 0, 1000000.0},
      {"segments", "hough_max_gap_px", &se.hough_max_gap_px, 0, 1000000.0},
      {"segments", "refine_segments", &se.refine_segments},
      {"segments", "refine_band_m", &se.refine_band_m, 0, 10},
      {"segments", "merge_collinear", &se.merge_collinear},
      {"segments", "merge_tolerance_m", &se.merge_tolerance_m, 0, 10},
      {"segments", "merge_tolerance_deg", &se.merge_tolerance_deg, 0, 90},
      {"segments", "num_rays", &se.num_rays, 0, 3600},
      {"segments", "ray_tolerance_deg", &se.ray_tolerance_deg, 0, 180},
      {"lidar_back_projection", "remove_depth_edges", &l.back_projection.remove_depth_edges},
      {"lidar_back_projection", "canny_low", &l.back_projection.canny_low, 0, 1000},
      {"lidar_back_projection", "canny_high", &l.back_projection.canny_high, 0, 1000},
      {"lidar_back_projection", "edge_dilation_px", &l.back_projection.edge_dilation_px, 0, 50},
      {"lidar_back_projection", "mask_glass", &l.back_projection.mask_glass},
      {"lidar_back_projection", "max_view_depth_m", &l.back_projection.max_view_depth_m, 0.01, 1000},
      {"lidar_back_projection", "min_confidence", &l.back_projection.min_confidence, 0, 2},
      {"lidar_back_projection", "pixel_stride", &l.back_projection.pixel_stride, 1, 64},
      {"lidar", "voxel_m", &l.voxel_m, 0.001, 10},
      {"lidar", "extractor",
       EnumField{[&l] { return to_string(l.extractor); },
                 [&l](const std::string& v) { l.extractor = parse_plane_extractor(v); }}},
      {"lidar", "max_wall_tilt_deg", &l.max_wall_tilt_deg, 0, 90},
      {"lidar", "min_wall_width_m", &l.min_wall_width_m, 0, 1000},
      {"lidar", "min_wall_height_m", &l.min_wall_height_m, 0, 1000},
      {"lidar", "require_camera_height", &l.require_camera_height},
      {"lidar", "wall_band_half_height_m", &l.wall_band_half_height_m, 0, 50},
      {"lidar", "max_range_m", &l.max_range_m, 0.1, 1000},
      {"lidar_pcl", "normal_k", &rg.normal_k, 3, 1000},
      {"lidar_pcl", "neighbours_k", &rg.neighbours_k, 1, 1000},
      {"lidar_pcl", "smoothness_deg", &rg.smoothness_deg, 0, 180},
      {"lidar_pcl", "curvature_threshold", &rg.curvature_threshold, 0, 1000},
      {"lidar_pcl", "min_cluster_points", &rg.min_cluster_points, 1, 100000000},
      {"lidar_voxelplane", "voxel_size_m", &vp.voxel_size_m, 0.01, 100},
      {"lidar_voxelplane", "min_points_per_voxel", &vp.min_points_per_voxel, 3, 1000000},
      {"lidar_voxelplane", "max_subdivisions", &vp.max_subdivisions, 0, 8},
      {"lidar_voxelplane", "max_thickness_m", &vp.max_thickness_m, 0, 10},
      {"lidar_voxelplane", "max_eigen_ratio", &vp.max_eigen_ratio, 0, 1},
      {"lidar_voxelplane", "adaptive_weights", &vp.adaptive_weights},
      {"lidar_voxelplane", "weight_alpha", &vp.weight_alpha, 0, 1000000.0},
      {"lidar_voxelplane", "weight_beta", &vp.weight_beta, 0, 1000000.0},
      {"lidar_voxelplane", "growth_max_normal_deg", &vp.growth_max_normal_deg, 0, 180},
      {"lidar_voxelplane", "growth_max_offset_m", &vp.growth_max_offset_m, 0, 100},
      {"lidar_voxelplane", "merge_undergrown", &vp.merge_undergrown},
      {"lidar_voxelplane", "merge_max_normal_deg", &vp.merge_max_normal_deg, 0, 180},
      {"lidar_voxelplane", "merge_depth_tol_deg", &vp.merge_depth_tol_deg, 0, 180},
      {"lidar_voxelplane", "merge_radius_factor", &vp.merge_radius_factor, 0, 100},
      {"lidar_voxelplane", "min_plane_points", &vp.min_plane_points, 3, 1000000000},
  };
}

nlohmann::ordered_json field_value(const FieldRef& ref) {
  return std::visit(
      [](const auto& r) -> nlohmann::ordered_json {
        using T = std::decay_t<decltype(r)>;
        if constexpr (std::is_same_v<T, EnumField>) {
          return r.get();
        } else {
          return *r;
        }
      },
      ref);
}

std::string range_text(double lo, double hi) {
  return "[" + nlohmann::json(lo).dump() + ", " + nlohmann::json(hi).dump() + "]";
}

void set_field(const Field& field, const nlohmann::json& v, const std::string& name) {
  auto bad = [&](const std::string& expected) {
    throw ParameterError("observation parameters: \"" + name + "\": expected " + expected + ", got " + json_excerpt(v),
                         name);
  };
  auto in_range = [&](double x) { return std::isfinite(x) && x >= field.lo && x <= field.hi; };
  std::visit(
      [&](const auto& r) {
        using T = std::decay_t<decltype(r)>;
        if constexpr (std::is_same_v<T, EnumField>) {
          if (!v.is_string()) bad("a string");
          try {
            r.set(v.get<std::string>());
          } catch (const InputError& e) {
            throw ParameterError("observation parameters: \"" + name + "\": " + e.what(), name);
          }
        } else if constexpr (std::is_same_v<T, bool*>) {
          if (!v.is_boolean()) bad("true or false");
          *r = v.get<bool>();
        } else if constexpr (std::is_same_v<T, int*>) {
          if (!v.is_number_integer()) bad("an integer in " + range_text(field.lo, field.hi));
          const double x = v.is_number_unsigned() ? static_cast<double>(v.get<std::uint64_t>())
                                                  : static_cast<double>(v.get<long long>());
          if (!in_range(x)) bad("an integer in " + range_text(field.lo, field.hi));
          *r = static_cast<int>(x);
        } else if constexpr (std::is_same_v<T, std::uint64_t*>) {
          if (!v.is_number_unsigned() && !(v.is_number_integer() && v.get<long long>() >= 0)) bad("a non-negative integer");
          *r = v.get<std::uint64_t>();
        } else if constexpr (std::is_same_v<T, double*>) {
          if (!v.is_number() || !in_range(v.get<double>())) bad("a number in " + range_text(field.lo, field.hi));
          *r = v.get<double>();
        } else {
          if (!v.is_array() || v.empty()) bad("a non-empty array of numbers in " + range_text(field.lo, field.hi));
          std::vector<double> out;
          for (const auto& e : v) {
            if (!e.is_number() || !in_range(e.get<double>())) {
              bad("a non-empty array of numbers in " + range_text(field.lo, field.hi));
            }
            out.push_back(e.get<double>());
          }
          *r = out;
        }
      },
      field.ref);
}

/// The range check of one field's current value (for structs filled in code, not from JSON).
void check_field(const Field& field) {
  const std::string name = field.section ? std::string(field.section) + "." + field.key : std::string(field.key);
  const nlohmann::json value = field_value(field.ref);
  if (value.is_number() || value.is_array()) set_field(field, value, name);
}

}  // namespace

void validate(const ObservationParams& params) {
  ObservationParams copy = params;
  for (const Field& f : fields(copy)) check_field(f);
  auto fail = [](const std::string& key, const std::string& why) {
    throw ParameterError("observation parameters: \"" + key + "\": " + why, key);
  };
  for (const auto& [section, bp] : {std::pair<const char*, const BackProjectionParams*>{"back_projection", &params.back_projection},
                                    {"lidar_back_projection", &params.lidar.back_projection}}) {
    if (bp->canny_low > bp->canny_high) {
      fail(std::string(section) + ".canny_low", "must not exceed canny_high (" + nlohmann::json(bp->canny_high).dump() + ")");
    }
  }
  check_limit("max_rays", params.segments.num_rays, "observation parameters: segments.num_rays", "rays");
  if (!(params.scale.min_scale < params.scale.max_scale)) {
    fail("scale.min_scale", "must be below scale.max_scale (" + nlohmann::json(params.scale.max_scale).dump() + ")");
  }
}

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

nlohmann::ordered_json to_json(const ObservationParams& params) {
  ObservationParams copy = params;
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (const Field& f : fields(copy)) {
    if (f.section) {
      j[f.section][f.key] = field_value(f.ref);
    } else {
      j[f.key] = field_value(f.ref);
    }
  }
  return j;
}

void apply_overrides(ObservationParams& params, const nlohmann::json& overrides) {
  if (!overrides.is_object()) throw InputError("observation parameters: overrides must be a JSON object");
  const std::vector<Field> fs = fields(params);
  for (const auto& [key, value] : overrides.items()) {
    bool is_section = false;
    for (const Field& f : fs) {
      if (f.section && key == f.section) is_section = true;
    }
    if (is_section) {
      if (!value.is_object()) throw ParameterError("observation parameters: \"" + key + "\" must be an object", key);
      for (const auto& [sub, v] : value.items()) {
        const Field* hit = nullptr;
        for (const Field& f : fs) {
          if (f.section && key == f.section && sub == f.key) hit = &f;
        }
        if (!hit) throw ParameterError("observation parameters: unknown key \"" + key + "." + sub + "\"", key + "." + sub);
        set_field(*hit, v, key + "." + sub);
      }
      continue;
    }
    const Field* hit = nullptr;
    for (const Field& f : fs) {
      if (!f.section && key == f.key) hit = &f;
    }
    if (!hit) throw ParameterError("observation parameters: unknown key \"" + key + "\"", key);
    set_field(*hit, value, key);
  }
  validate(params);
}

nlohmann::ordered_json to_json(const ObservationDiagnostics& d) {
  nlohmann::ordered_json j;
  j["path"] = d.path;
  j["scale_alignment"] = d.scale_alignment;
  j["views_total"] = d.views_total;
  j["views_used"] = d.views_used;
  j["views_dropped_far"] = d.views_dropped_far;
  j["views_dropped_no_ground"] = d.views_dropped_no_ground;
  j["view_scales"] = d.view_scales;
  j["relative_scales"] = d.relative_scales;
  j["global_scale"] = d.global_scale;
  nlohmann::ordered_json rel;
  rel["pairs"] = nlohmann::ordered_json::array();
  for (const auto& [a, b] : d.relative.pairs) rel["pairs"].push_back({a, b});
  rel["initial_scales"] = d.relative.initial_scales;
  rel["objective_initial"] = d.relative.objective_initial;
  rel["objective_final"] = d.relative.objective_final;
  rel["rounds"] = d.relative.rounds;
  rel["round_steps"] = d.relative.round_steps;
  rel["iterations"] = d.relative.iterations;
  rel["evaluations"] = d.relative.evaluations;
  rel["status"] = d.relative.status;
  j["relative_alignment"] = rel;
  nlohmann::ordered_json g;
  g["found"] = d.ground.found;
  if (!d.ground.reason.empty()) g["reason"] = d.ground.reason;
  g["height_m"] = d.ground.height_m;
  g["height_after_scaling_m"] = d.ground_height_after_m;
  g["plane"] = {d.ground.plane[0], d.ground.plane[1], d.ground.plane[2], d.ground.plane[3]};
  g["points"] = d.ground.points;
  g["candidates"] = d.ground.candidates;
  g["inliers"] = d.ground.inliers;
  j["ground"] = g;
  j["points_back_projected"] = d.points_back_projected;
  j["pixels_edge_removed"] = d.pixels_edge_removed;
  j["pixels_glass_removed"] = d.pixels_glass_removed;
  j["points_merged"] = d.points_merged;
  j["points_subsampled"] = d.points_subsampled;
  j["points_in_slice"] = d.points_in_slice;
  j["band_half_height_m"] = d.band_half_height_m;
  j["planes_total"] = d.planes_total;
  j["wall_planes"] = d.wall_planes;
  j["warnings"] = d.warnings;
  return j;
}

}  // namespace floorcast
