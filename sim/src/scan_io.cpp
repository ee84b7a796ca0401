#include "floorcast/sim/scan_io.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>

#include "floorcast/core/file_io.hpp"
#include "floorcast/core/pose_json.hpp"
#include "floorcast/core/scan_io.hpp"
#include "floorcast/core/json_reader.hpp"
#include "floorcast/core/json_text.hpp"

namespace floorcast {
namespace {

using nlohmann::ordered_json;


constexpr int kSimulationFormatVersion = 1;


ordered_json params_json_impl(const ScanParams& p) {
  const ScanGeometry& g = p.geometry;
  const SensorParams& s = p.sensor;
  ordered_json j;
  j["preset"] = p.preset;
  j["geometry"] = {{"num_views", g.num_views},         {"view_step_deg", g.view_step_deg},
                   {"hfov_deg", g.hfov_deg},           {"width_px", g.width_px},
                   {"height_px", g.height_px},         {"pitch_deg", g.pitch_deg},
                   {"camera_height_m", g.camera_height_m}, {"rotation_radius_m", g.rotation_radius_m}};
  ordered_json sensor;
  sensor["kind"] = sensor_kind_name(s.kind);
  sensor["min_range_m"] = s.min_range_m;
  sensor["max_range_m"] = s.max_range_m;
  sensor["glass"] = {{"p_see_through", s.glass.p_see_through},
                     {"p_reflect", s.glass.p_reflect},
                     {"per_pixel", s.glass.per_pixel},
                     {"max_interactions", s.glass.max_interactions}};
  const LidarModel& l = s.lidar;
  sensor["lidar"] = {{"sigma_base_m", l.sigma_base_m},
                     {"sigma_quad_per_m", l.sigma_quad_per_m},
                     {"sigma_z0_m", l.sigma_z0_m},
                     {"lateral_sigma_px", l.lateral_sigma_px},
                     {"dropout_prob", l.dropout_prob},
                     {"grazing_start_deg", l.grazing_start_deg},
                     {"grazing_dropout_prob", l.grazing_dropout_prob},
                     {"medium_incidence_deg", l.medium_incidence_deg},
                     {"low_incidence_deg", l.low_incidence_deg},
                     {"medium_range_fraction", l.medium_range_fraction},
                     {"low_range_fraction", l.low_range_fraction},
                     {"edge_threshold_rel", l.edge_threshold_rel}};
  const MonoModel& m = s.mono;
  sensor["mono"] = {{"model", m.model},
                    {"scan_scale_mean_ln", m.scan_scale_mean_ln},
                    {"scan_scale_sigma_ln", m.scan_scale_sigma_ln},
                    {"scale_sigma_ln", m.scale_sigma_ln},
                    {"shift_sigma_m", m.shift_sigma_m},
                    {"compression_knee_m", m.compression_knee_m},
                    {"compression_ceiling_m", m.compression_ceiling_m},
                    {"warp_sigma_ln", m.warp_sigma_ln},
                    {"warp_grid_x", m.warp_grid_x},
                    {"warp_grid_y", m.warp_grid_y},
                    {"noise_sigma_rel", m.noise_sigma_rel},
                    {"flying_pixel_prob", m.flying_pixel_prob},
                    {"flying_pixel_width_px", m.flying_pixel_width_px},
                    {"edge_threshold_rel", m.edge_threshold_rel},
                    {"edge_bleed_px", m.edge_bleed_px},
                    {"textureless_prob", m.textureless_prob},
                    {"textureless_sigma_ln", m.textureless_sigma_ln},
                    {"no_ground_prob", m.no_ground_prob}};
  sensor["tracker"] = {{"rotation_sigma_deg", s.tracker.rotation_sigma_deg},
                       {"translation_sigma_m", s.tracker.translation_sigma_m}};
  j["sensor"] = sensor;
  j["setting"] = scan_setting_name(p.setting);
  j["center_view"] = p.center_view;
  j["seed"] = p.seed;
  return j;
}

ScanParams params_from_json_impl(const JsonReader& r) {
  ScanParams p;
  r.only({"preset", "geometry", "sensor", "setting", "center_view", "seed"});
  p.preset = r.string("preset");
  {
    const JsonReader g = r.object("geometry");
    g.only({"num_views", "view_step_deg", "hfov_deg", "width_px", "height_px", "pitch_deg", "camera_height_m",
            "rotation_radius_m"});
    p.geometry.num_views = static_cast<int>(g.integer("num_views", 1, 360));
    p.geometry.view_step_deg = g.number("view_step_deg", -360.0, 360.0);
    p.geometry.hfov_deg = g.number("hfov_deg", 1.0, 170.0);
    p.geometry.width_px = static_cast<int>(g.integer("width_px", 1, 8192));
    p.geometry.height_px = static_cast<int>(g.integer("height_px", 1, 8192));
    p.geometry.pitch_deg = g.number("pitch_deg", -89.0, 89.0);
    p.geometry.camera_height_m = g.number("camera_height_m", 0.01, 50.0);
    p.geometry.rotation_radius_m = g.number("rotation_radius_m", 0.0, 2.0);
  }
  {
    const JsonReader s = r.object("sensor");
    s.only({"kind", "min_range_m", "max_range_m", "glass", "lidar", "mono", "tracker"});
    if (!parse_sensor_kind(s.string("kind"), p.sensor.kind)) s.fail_key("kind", "expected perfect, lidar or mono");
    p.sensor.min_range_m = s.number("min_range_m", 0.0, 10.0);
    p.sensor.max_range_m = s.number("max_range_m", 0.1, 65.0);
    const JsonReader g = s.object("glass");
    g.only({"p_see_through", "p_reflect", "per_pixel", "max_interactions"});
    p.sensor.glass.p_see_through = g.number("p_see_through", 0.0, 1.0);
    p.sensor.glass.p_reflect = g.number("p_reflect", 0.0, 1.0);
    p.sensor.glass.per_pixel = g.boolean("per_pixel");
    p.sensor.glass.max_interactions = static_cast<int>(g.integer("max_interactions", 0, 16));
    const JsonReader l = s.object("lidar");
    l.only({"sigma_base_m", "sigma_quad_per_m", "sigma_z0_m", "lateral_sigma_px", "dropout_prob", "grazing_start_deg",
            "grazing_dropout_prob", "medium_incidence_deg", "low_incidence_deg", "medium_range_fraction",
            "low_range_fraction", "edge_threshold_rel"});
    LidarModel& lm = p.sensor.lidar;
    lm.sigma_base_m = l.number("sigma_base_m", 0.0, 1.0);
    lm.sigma_quad_per_m = l.number("sigma_quad_per_m", 0.0, 1.0);
    lm.sigma_z0_m = l.number("sigma_z0_m", 0.0, 10.0);
    lm.lateral_sigma_px = l.number("lateral_sigma_px", 0.0, 10.0);
    lm.dropout_prob = l.number("dropout_prob", 0.0, 1.0);
    lm.grazing_start_deg = l.number("grazing_start_deg", 0.0, 90.0);
    lm.grazing_dropout_prob = l.number("grazing_dropout_prob", 0.0, 1.0);
    lm.medium_incidence_deg = l.number("medium_incidence_deg", 0.0, 90.0);
    lm.low_incidence_deg = l.number("low_incidence_deg", 0.0, 90.0);
    lm.medium_range_fraction = l.number("medium_range_fraction", 0.0, 1.0);
    lm.low_range_fraction = l.number("low_range_fraction", 0.0, 1.0);
    lm.edge_threshold_rel = l.number("edge_threshold_rel", 0.0, 10.0);
    const JsonReader m = s.object("mono");
    m.only({"model", "scan_scale_mean_ln", "scan_scale_sigma_ln", "scale_sigma_ln", "shift_sigma_m",
            "compression_knee_m", "compression_ceiling_m", "warp_sigma_ln", "warp_grid_x", "warp_grid_y",
            "noise_sigma_rel", "flying_pixel_prob", "flying_pixel_width_px", "edge_threshold_rel", "edge_bleed_px",
            "textureless_prob", "textureless_sigma_ln", "no_ground_prob"});
    MonoModel& mm = p.sensor.mono;
    // Folders written before the network-shaped model (no "model" key) hold the former model:
    // the components they do not list were off.
    const bool former = !m.has("model");
    mm.model = former ? "per_view_lognormal" : m.string("model");
    if (mm.model.empty() || mm.model.size() > 64) m.fail_key("model", "must be a name of 1 to 64 characters");
    mm.scan_scale_mean_ln = m.number_or("scan_scale_mean_ln", -2.0, 2.0, 0.0);
    mm.scan_scale_sigma_ln = m.number_or("scan_scale_sigma_ln", 0.0, 2.0, 0.0);
    mm.scale_sigma_ln = m.number("scale_sigma_ln", 0.0, 2.0);
    mm.shift_sigma_m = m.number_or("shift_sigma_m", 0.0, 5.0, 0.0);
    mm.compression_knee_m = m.number_or("compression_knee_m", 0.0, 100.0, 0.0);
    mm.compression_ceiling_m = m.number_or("compression_ceiling_m", 0.0, 1000.0, 0.0);
    mm.warp_sigma_ln = m.number("warp_sigma_ln", 0.0, 1.0);
    mm.warp_grid_x = static_cast<int>(m.integer("warp_grid_x", 2, 32));
    mm.warp_grid_y = static_cast<int>(m.integer("warp_grid_y", 2, 32));
    mm.noise_sigma_rel = m.number("noise_sigma_rel", 0.0, 0.5);
    mm.flying_pixel_prob = m.number("flying_pixel_prob", 0.0, 1.0);
    mm.flying_pixel_width_px = static_cast<int>(m.integer("flying_pixel_width_px", 1, 16));
    mm.edge_threshold_rel = m.number("edge_threshold_rel", 0.0, 10.0);
    mm.edge_bleed_px = m.has("edge_bleed_px") ? static_cast<int>(m.integer("edge_bleed_px", 0, 16)) : 0;
    mm.textureless_prob = m.number_or("textureless_prob", 0.0, 1.0, 0.0);
    mm.textureless_sigma_ln = m.number_or("textureless_sigma_ln", 0.0, 2.0, 0.0);
    mm.no_ground_prob = m.number_or("no_ground_prob", 0.0, 1.0, 0.0);
    if (!former) {
      // A current file lists every key: a missing one is an error, not a silent default.
      for (const char* key : {"scan_scale_mean_ln", "scan_scale_sigma_ln", "shift_sigma_m", "compression_knee_m",
                              "compression_ceiling_m", "edge_bleed_px", "textureless_prob", "textureless_sigma_ln",
                              "no_ground_prob"}) {
        if (!m.has(key)) m.fail_key(key, "missing");
      }
    }
    const JsonReader t = s.object("tracker");
    t.only({"rotation_sigma_deg", "translation_sigma_m"});
    p.sensor.tracker.rotation_sigma_deg = t.number("rotation_sigma_deg", 0.0, 45.0);
    p.sensor.tracker.translation_sigma_m = t.number("translation_sigma_m", 0.0, 5.0);
  }
  if (!parse_scan_setting(r.string("setting"), p.setting)) r.fail_key("setting", "expected full, partial or single");
  p.center_view = static_cast<int>(r.integer("center_view", 0, p.geometry.num_views - 1));
  p.seed = r.uint64("seed");
  try {
    validate_scan_params(p);
  } catch (const InputError& e) {
    r.fail(e.what());
  }
  return p;
}

}  // namespace

std::string simulation_json_text(const SimulatedScan& sim) {
  ordered_json j;
  j["format"] = "floorcast-simulation";
  j["format_version"] = kSimulationFormatVersion;
  j["frames"] = "world: plan metres, z up; T_world_scan places the scan frame (core/scan.hpp) in the world";
  j["setting"] = scan_setting_name(sim.params.setting);
  j["seed"] = sim.params.seed;
  ordered_json truth;
  truth["T_world_scan"] = {{"x_m", sim.truth.T_world_scan.x_m},
                           {"y_m", sim.truth.T_world_scan.y_m},
                           {"yaw_rad", sim.truth.T_world_scan.yaw_rad}};
  truth["camera_height_m"] = sim.truth.camera_height_m;
  truth["view_depth_scale"] = sim.truth.view_depth_scale;
  truth["scan_depth_scale"] = sim.truth.scan_depth_scale;
  truth["view_depth_shift_m"] = sim.truth.view_depth_shift_m;
  truth["view_floor_masked"] = sim.truth.view_floor_masked;
  ordered_json trues = ordered_json::array();
  for (const Eigen::Isometry3d& T : sim.truth.T_scan_camera_true) trues.push_back(pose_matrix_json(T));
  truth["T_scan_camera_true"] = trues;
  if (!sim.truth.plan_hash.empty()) truth["plan_hash"] = sim.truth.plan_hash;
  j["ground_truth"] = truth;
  j["params"] = scan_params_to_json(sim.params);
  return j.dump(2) + "\n";
}

void save_simulated_scan(const std::string& dir, const SimulatedScan& sim) {
  save_scan(dir, sim.scan);
  write_text_file_atomic(dir + "/simulation.json", simulation_json_text(sim));
}

std::optional<SimulationRecord> load_simulation_record(const std::string& dir, std::size_t num_views) {
  // Wave-1 folders (scan.json version 1) kept the simulator's fields inside scan.json.
  const std::string scan_json = dir + "/scan.json";
  const std::string sim_json = dir + "/simulation.json";
  const bool legacy = !std::filesystem::is_regular_file(sim_json);
  const std::string path = legacy ? scan_json : sim_json;
  if (legacy && !std::filesystem::is_regular_file(scan_json)) return std::nullopt;
  const nlohmann::json j = read_json_file(path);
  const JsonReader r(j, path, "");
  if (legacy) {
    if (!r.has("ground_truth")) return std::nullopt;
  } else {
    r.only({"format", "format_version", "frames", "setting", "seed", "ground_truth", "params"});
    if (r.string("format") != "floorcast-simulation") r.fail_key("format", "expected \"floorcast-simulation\"");
    if (r.integer("format_version", 0, 1000000) != kSimulationFormatVersion) {
      r.fail_key("format_version",
                 "unsupported (this floorcast reads version " + std::to_string(kSimulationFormatVersion) + ")");
    }
  }
  SimulationRecord sim;
  sim.params = params_from_json_impl(r.object("params"));
  if (r.uint64("seed") != sim.params.seed) r.fail_key("seed", "differs from params.seed");
  ScanSetting setting;
  if (!parse_scan_setting(r.string("setting"), setting)) r.fail_key("setting", "expected full, partial or single");
  if (setting != sim.params.setting) r.fail_key("setting", "differs from params.setting");

  const JsonReader t = r.object("ground_truth");
  t.only({"T_world_scan", "camera_height_m", "view_depth_scale", "scan_depth_scale", "view_depth_shift_m",
          "view_floor_masked", "T_scan_camera_true", "plan_hash"});
  if (t.has("plan_hash")) sim.truth.plan_hash = t.string("plan_hash");
  const JsonReader p = t.object("T_world_scan");
  p.only({"x_m", "y_m", "yaw_rad"});
  sim.truth.T_world_scan.x_m = p.number("x_m", -1e5, 1e5);
  sim.truth.T_world_scan.y_m = p.number("y_m", -1e5, 1e5);
  sim.truth.T_world_scan.yaw_rad = p.number("yaw_rad", -100.0, 100.0);
  sim.truth.camera_height_m = t.number("camera_height_m", 0.0, 50.0);
  const std::size_t n = num_views;
  const std::vector<double> scales = t.numbers("view_depth_scale", static_cast<int>(n));
  for (std::size_t k = 0; k < scales.size(); ++k) {
    if (!(scales[k] > 0.0)) t.fail_key("view_depth_scale[" + std::to_string(k) + "]", "must be positive");
  }
  sim.truth.view_depth_scale = scales;
  // Written since the network-shaped monocular model; absent in older folders (no shift, no
  // shared scale, no masked floors then).
  sim.truth.scan_depth_scale = t.number_or("scan_depth_scale", 1e-6, 1e6, 1.0);
  sim.truth.view_depth_shift_m =
      t.has("view_depth_shift_m") ? t.numbers("view_depth_shift_m", static_cast<int>(n)) : std::vector<double>(n, 0.0);
  sim.truth.view_floor_masked.assign(n, false);
  if (t.has("view_floor_masked")) {
    const nlohmann::json& masked = t.raw("view_floor_masked");
    if (!masked.is_array() || masked.size() != n) t.fail_key("view_floor_masked", "expected one boolean per view");
    for (std::size_t k = 0; k < n; ++k) {
      if (!masked[k].is_boolean()) t.fail_key("view_floor_masked[" + std::to_string(k) + "]", "expected true or false");
      sim.truth.view_floor_masked[k] = masked[k].get<bool>();
    }
  }
  const nlohmann::json& trues = t.raw("T_scan_camera_true");
  if (!trues.is_array() || trues.size() != n) t.fail_key("T_scan_camera_true", "expected one 4x4 matrix per view");
  for (std::size_t k = 0; k < trues.size(); ++k) {
    sim.truth.T_scan_camera_true.push_back(
        pose_matrix_from_json(t, trues[k], "T_scan_camera_true[" + std::to_string(k) + "]"));
  }
  return sim;
}

SimulatedScan load_simulated_scan(const std::string& dir) {
  SimulatedScan sim;
  sim.scan = load_scan(dir);
  std::optional<SimulationRecord> record = load_simulation_record(dir, sim.scan.views.size());
  if (!record) throw InputError(dir + ": not a simulated scan (no simulation.json): its ground truth is unknown");
  sim.truth = std::move(record->truth);
  sim.params = std::move(record->params);
  return sim;
}

ordered_json scan_params_to_json(const ScanParams& params) { return params_json_impl(params); }

ScanParams scan_params_from_json(const nlohmann::json& json, const std::string& source) {
  return params_from_json_impl(JsonReader(json, source, ""));
}

namespace {

/// Every key of `overrides` must exist in `base` (recursively for objects).
void check_override_keys(const nlohmann::json& base, const nlohmann::json& overrides, const std::string& source,
                         const std::string& path) {
  if (!overrides.is_object()) throw InputError(source + ": " + (path.empty() ? "overrides" : path) + ": expected an object");
  for (auto it = overrides.begin(); it != overrides.end(); ++it) {
    const std::string child = path.empty() ? it.key() : path + "." + it.key();
    if (!base.contains(it.key())) throw ParameterError(source + ": " + child + ": unknown scan parameter", child);
    if (base.at(it.key()).is_object()) check_override_keys(base.at(it.key()), it.value(), source, child);
  }
}

}  // namespace

void apply_scan_overrides(ScanParams& params, const nlohmann::json& overrides, const std::string& source) {
  // sensor.mono.model selects a preset of the monocular error model first; the other keys of the
  // same overrides then change single values of it, whatever their order.
  if (overrides.is_object() && overrides.contains("sensor") && overrides["sensor"].is_object() &&
      overrides["sensor"].contains("mono") && overrides["sensor"]["mono"].is_object() &&
      overrides["sensor"]["mono"].contains("model")) {
    const nlohmann::json& name = overrides["sensor"]["mono"]["model"];
    const std::string key = "sensor.mono.model";
    if (!name.is_string()) throw ParameterError(source + ": " + key + ": expected a string", key);
    try {
      params.sensor.mono = mono_model_preset(name.get<std::string>());
    } catch (const InputError& e) {
      throw ParameterError(source + ": " + key + ": " + e.what(), key);
    }
  }
  nlohmann::json j = scan_params_to_json(params);
  check_override_keys(j, overrides, source, "");
  j.merge_patch(overrides);
  params = scan_params_from_json(j, source);
}

}  // namespace floorcast
