#include "floorcast/sim/scan_params.hpp"
#include "floorcast/core/image_io.hpp"
#include "floorcast/core/limits.hpp"

#include <cmath>
#include <sstream>

#include "floorcast/core/types.hpp"

namespace floorcast {

const std::vector<std::string>& scan_preset_names() {
  static const std::vector<std::string> names{"perfect", "lidar", "mono", "phone", "depth_camera"};
  return names;
}

ScanParams scan_preset(const std::string& name) {
  ScanParams p;
  p.preset = name;
  if (name == "mono" || name == "perfect") {
    // ScanGeometry defaults are the PALMS+ Structured3D views.
    if (name == "mono") {
      p.sensor.kind = SensorKind::kMono;
      p.sensor.max_range_m = 40.0;
      p.sensor.glass.p_see_through = 0.5;
      p.sensor.glass.p_reflect = 0.1;
    } else {
      p.sensor.kind = SensorKind::kPerfect;
      p.sensor.max_range_m = 65.0;
    }
    return p;
  }
  if (name == "phone") {
    p.geometry.num_views = 18;
    p.geometry.view_step_deg = 20.0;
    p.geometry.hfov_deg = 60.0;
    p.geometry.width_px = 480;
    p.geometry.height_px = 640;
    p.geometry.pitch_deg = -10.0;
    p.sensor.kind = SensorKind::kMono;
    p.sensor.max_range_m = 40.0;
    p.sensor.glass.p_see_through = 0.5;
    p.sensor.glass.p_reflect = 0.1;
    p.sensor.tracker.rotation_sigma_deg = 0.5;
    p.sensor.tracker.translation_sigma_m = 0.01;
    return p;
  }
  if (name == "lidar") {
    p.geometry.num_views = 18;
    p.geometry.view_step_deg = 20.0;
    p.geometry.hfov_deg = 60.0;
    p.geometry.width_px = 256;
    p.geometry.height_px = 192;
    p.geometry.pitch_deg = -10.0;
    p.sensor.kind = SensorKind::kLidar;
    p.sensor.max_range_m = 5.0;
    p.sensor.glass.p_see_through = 0.6;
    p.sensor.glass.p_reflect = 0.15;
    p.sensor.tracker.rotation_sigma_deg = 0.5;
    p.sensor.tracker.translation_sigma_m = 0.01;
    return p;
  }
  if (name == "depth_camera") {
    // A metric depth camera rotated in place, as VoxelPlane-Reloc uses them (mToF: 100 x 75 deg;
    // L515: 70 x 55 deg; both metric): the Kinect-style axial noise of the lidar model, 10 m range.
    p.geometry.num_views = 12;
    p.geometry.view_step_deg = 30.0;
    p.geometry.hfov_deg = 90.0;
    p.geometry.width_px = 320;
    p.geometry.height_px = 240;
    p.geometry.pitch_deg = -10.0;
    p.sensor.kind = SensorKind::kLidar;
    p.sensor.max_range_m = 10.0;
    p.sensor.glass.p_see_through = 0.6;
    p.sensor.glass.p_reflect = 0.15;
    p.sensor.tracker.rotation_sigma_deg = 0.5;
    p.sensor.tracker.translation_sigma_m = 0.01;
    return p;
  }
  std::string known;
  for (const std::string& n : scan_preset_names()) known += (known.empty() ? "" : ", ") + n;
  throw InputError("unknown sensor preset \"" + name + "\" (known: " + known + ")");
}

const std::vector<std::string>& mono_model_names() {
  static const std::vector<std::string> names{"depth_pro", "unidepth_v2", "metric3d_v2", "depth_anything_v2",
                                              "per_view_lognormal"};
  return names;
}

MonoModel mono_model_preset(const std::string& name) {
  // Image-level log scale error sigma_img from the network's zero-shot delta1 on iBims-1 (the
  // whole error taken as log-normal: sigma_total = ln 1.25 / Phi^-1((1 + delta1) / 2)) minus a
  // within-image part of 0.06 (warp, texture-less faces, noise), split evenly (in variance)
  // between the scan-shared and the per-view scale. Numbers and sources: sim/README.md.
  const auto image_level = [](MonoModel& m, double per_part_sigma_ln) {
    m.scan_scale_sigma_ln = per_part_sigma_ln;
    m.scale_sigma_ln = per_part_sigma_ln;
  };
  MonoModel m;  // the member initialisers are "depth_pro"
  m.model = name;
  if (name == "depth_pro") return m;
  if (name == "unidepth_v2") {
    image_level(m, 0.070);
    m.edge_bleed_px = 2;
    return m;
  }
  if (name == "metric3d_v2") {
    image_level(m, 0.152);
    m.edge_bleed_px = 3;
    return m;
  }
  if (name == "depth_anything_v2") {
    image_level(m, 0.142);
    m.edge_bleed_px = 2;
    m.compression_knee_m = 10.0;
    m.compression_ceiling_m = 20.0;
    return m;
  }
  if (name == "per_view_lognormal") {
    m.scan_scale_sigma_ln = 0.0;
    m.scale_sigma_ln = 0.12;
    m.shift_sigma_m = 0.0;
    m.edge_bleed_px = 0;
    m.textureless_prob = 0.0;
    m.no_ground_prob = 0.0;
    return m;
  }
  std::string known;
  for (const std::string& n : mono_model_names()) known += (known.empty() ? "" : ", ") + n;
  throw InputError("unknown monocular depth model \"" + name + "\" (known: " + known + ")");
}

const char* sensor_kind_name(SensorKind kind) {
  switch (kind) {
    case SensorKind::kPerfect: return "perfect";
    case SensorKind::kLidar: return "lidar";
    case SensorKind::kMono: return "mono";
  }
  return "unknown";
}

const char* scan_setting_name(ScanSetting setting) {
  switch (setting) {
    case ScanSetting::kFull: return "full";
    case ScanSetting::kPartial: return "partial";
    case ScanSetting::kSingle: return "single";
  }
  return "unknown";
}

bool parse_sensor_kind(const std::string& s, SensorKind& kind) {
  for (SensorKind k : {SensorKind::kPerfect, SensorKind::kLidar, SensorKind::kMono}) {
    if (s == sensor_kind_name(k)) {
      kind = k;
      return true;
    }
  }
  return false;
}

bool parse_scan_setting(const std::string& s, ScanSetting& setting) {
  for (ScanSetting k : {ScanSetting::kFull, ScanSetting::kPartial, ScanSetting::kSingle}) {
    if (s == scan_setting_name(k)) {
      setting = k;
      return true;
    }
  }
  return false;
}

std::vector<int> setting_views(const ScanGeometry& geometry, ScanSetting setting, int center_view) {
  const int n = geometry.num_views;
  std::vector<int> out;
  if (n <= 0) return out;
  const int c = ((center_view % n) + n) % n;
  switch (setting) {
    case ScanSetting::kFull:
      for (int k = 0; k < n; ++k) out.push_back(k);
      break;
    case ScanSetting::kPartial:
      if (n < 3) {
        for (int k = 0; k < n; ++k) out.push_back(k);
      } else {
        for (int k = -1; k <= 1; ++k) out.push_back(((c + k) % n + n) % n);
      }
      break;
    case ScanSetting::kSingle:
      out.push_back(c);
      break;
  }
  return out;
}

namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw InputError("scan parameters: " + what);
}

bool finite_in(double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; }

}  // namespace

void validate_scan_params(const ScanParams& p) {
  const ScanGeometry& g = p.geometry;
  require(g.num_views >= 1 && g.num_views <= 360, "num_views must be in [1, 360]");
  require(finite_in(g.view_step_deg, -360.0, 360.0), "view_step_deg must be in [-360, 360]");
  require(finite_in(g.hfov_deg, 1.0, 170.0), "hfov_deg must be in [1, 170]");
  require(g.width_px >= 1 && g.width_px <= 8192 && g.height_px >= 1 && g.height_px <= 8192,
          "width_px and height_px must be in [1, 8192]");
  check_image_size(g.width_px, g.height_px, "scan parameters: a view (width_px x height_px)");
  check_limit("max_views", g.num_views, "scan parameters: num_views", "views");
  require(finite_in(g.pitch_deg, -89.0, 89.0), "pitch_deg must be in [-89, 89]");
  require(finite_in(g.camera_height_m, 0.01, 50.0), "camera_height_m must be in [0.01, 50]");
  require(finite_in(g.rotation_radius_m, 0.0, 2.0), "rotation_radius_m must be in [0, 2]");
  const SensorParams& s = p.sensor;
  require(finite_in(s.min_range_m, 0.0, 10.0), "min_range_m must be in [0, 10]");
  require(finite_in(s.max_range_m, 0.1, 65.0), "max_range_m must be in [0.1, 65] (16-bit millimetre PNG)");
  require(s.min_range_m < s.max_range_m, "min_range_m must be below max_range_m");
  require(finite_in(s.glass.p_see_through, 0.0, 1.0) && finite_in(s.glass.p_reflect, 0.0, 1.0) &&
              s.glass.p_see_through + s.glass.p_reflect <= 1.0 + 1e-12,
          "glass probabilities must be in [0, 1] and sum to at most 1");
  require(s.glass.max_interactions >= 0 && s.glass.max_interactions <= 16, "glass max_interactions must be in [0, 16]");
  const LidarModel& l = s.lidar;
  require(finite_in(l.sigma_base_m, 0.0, 1.0) && finite_in(l.sigma_quad_per_m, 0.0, 1.0) &&
              finite_in(l.sigma_z0_m, 0.0, 10.0),
          "lidar sigma parameters must be in [0, 1] (z0 in [0, 10])");
  require(finite_in(l.lateral_sigma_px, 0.0, 10.0), "lidar lateral_sigma_px must be in [0, 10]");
  require(finite_in(l.dropout_prob, 0.0, 1.0) && finite_in(l.grazing_dropout_prob, 0.0, 1.0),
          "lidar dropout probabilities must be in [0, 1]");
  require(finite_in(l.grazing_start_deg, 0.0, 90.0) && finite_in(l.medium_incidence_deg, 0.0, 90.0) &&
              finite_in(l.low_incidence_deg, 0.0, 90.0),
          "lidar angles must be in [0, 90]");
  require(finite_in(l.medium_range_fraction, 0.0, 1.0) && finite_in(l.low_range_fraction, 0.0, 1.0),
          "lidar range fractions must be in [0, 1]");
  require(finite_in(l.edge_threshold_rel, 0.0, 10.0), "lidar edge_threshold_rel must be in [0, 10]");
  const MonoModel& m = s.mono;
  require(finite_in(m.scale_sigma_ln, 0.0, 2.0), "mono scale_sigma_ln must be in [0, 2]");
  require(finite_in(m.warp_sigma_ln, 0.0, 1.0), "mono warp_sigma_ln must be in [0, 1]");
  require(m.warp_grid_x >= 2 && m.warp_grid_x <= 32 && m.warp_grid_y >= 2 && m.warp_grid_y <= 32,
          "mono warp grid must be in [2, 32] per axis");
  require(finite_in(m.noise_sigma_rel, 0.0, 0.5), "mono noise_sigma_rel must be in [0, 0.5]");
  require(finite_in(m.flying_pixel_prob, 0.0, 1.0), "mono flying_pixel_prob must be in [0, 1]");
  require(m.flying_pixel_width_px >= 1 && m.flying_pixel_width_px <= 16, "mono flying_pixel_width_px must be in [1, 16]");
  require(finite_in(m.edge_threshold_rel, 0.0, 10.0), "mono edge_threshold_rel must be in [0, 10]");
  require(std::isfinite(m.scan_scale_mean_ln) && std::abs(m.scan_scale_mean_ln) <= 2.0,
          "mono scan_scale_mean_ln must be in [-2, 2]");
  require(finite_in(m.scan_scale_sigma_ln, 0.0, 2.0), "mono scan_scale_sigma_ln must be in [0, 2]");
  require(finite_in(m.shift_sigma_m, 0.0, 5.0), "mono shift_sigma_m must be in [0, 5]");
  require(finite_in(m.compression_knee_m, 0.0, 100.0) && finite_in(m.compression_ceiling_m, 0.0, 1000.0),
          "mono compression_knee_m must be in [0, 100] and compression_ceiling_m in [0, 1000]");
  require(m.compression_knee_m > 0.0 ? m.compression_ceiling_m > m.compression_knee_m : m.compression_ceiling_m == 0.0,
          "mono compression_ceiling_m must exceed compression_knee_m (both 0 = off)");
  require(m.edge_bleed_px >= 0 && m.edge_bleed_px <= 16, "mono edge_bleed_px must be in [0, 16]");
  require(finite_in(m.textureless_prob, 0.0, 1.0), "mono textureless_prob must be in [0, 1]");
  require(finite_in(m.textureless_sigma_ln, 0.0, 2.0), "mono textureless_sigma_ln must be in [0, 2]");
  require(finite_in(m.no_ground_prob, 0.0, 1.0), "mono no_ground_prob must be in [0, 1]");
  require(finite_in(s.tracker.rotation_sigma_deg, 0.0, 45.0) && finite_in(s.tracker.translation_sigma_m, 0.0, 5.0),
          "tracker noise must be in [0, 45] deg and [0, 5] m");
  require(p.center_view >= 0 && p.center_view < g.num_views, "center_view must be a view index in [0, num_views)");
}

}  // namespace floorcast
