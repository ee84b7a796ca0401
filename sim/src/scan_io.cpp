#include "floorcast/sim/scan_io.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "floorcast/floorplans/io.hpp"
#include "json_reader.hpp"

namespace floorcast {
namespace {

using nlohmann::ordered_json;
using detail::JsonReader;

constexpr int kScanFormatVersion = 1;
constexpr double kDepthUnitM = 0.001;

std::string view_file(std::size_t k, const char* what) {
  std::ostringstream s;
  s << "view_" << std::setw(3) << std::setfill('0') << k << "_" << what << ".png";
  return s.str();
}

ordered_json pose_matrix_json(const Eigen::Isometry3d& T) {
  ordered_json rows = ordered_json::array();
  for (int r = 0; r < 4; ++r) {
    ordered_json row = ordered_json::array();
    for (int c = 0; c < 4; ++c) row.push_back(T.matrix()(r, c));
    rows.push_back(row);
  }
  return rows;
}

Eigen::Isometry3d pose_matrix_from_json(const JsonReader& parent, const nlohmann::json& j, const std::string& key) {
  const std::string path = parent.child_path(key);
  auto fail = [&](const std::string& why) { throw InputError(parent.source() + ": " + path + ": " + why); };
  if (!j.is_array() || j.size() != 4) fail("expected a 4x4 matrix (array of 4 rows)");
  Eigen::Matrix4d M;
  for (int r = 0; r < 4; ++r) {
    const nlohmann::json& row = j[static_cast<std::size_t>(r)];
    if (!row.is_array() || row.size() != 4) fail("row " + std::to_string(r) + " must have 4 numbers");
    for (int c = 0; c < 4; ++c) {
      const nlohmann::json& v = row[static_cast<std::size_t>(c)];
      if (!v.is_number() || !std::isfinite(v.get<double>())) fail("entries must be finite numbers");
      M(r, c) = v.get<double>();
    }
  }
  if ((M.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).norm() > 1e-9) fail("last row must be [0, 0, 0, 1]");
  const Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).norm() > 1e-6 || R.determinant() < 0.0) {
    fail("rotation part is not a rotation matrix");
  }
  if (M.topRightCorner<3, 1>().norm() > 1e5) fail("translation absurdly large");
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.matrix() = M;
  return T;
}

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
  sensor["mono"] = {{"scale_sigma_ln", m.scale_sigma_ln},
                    {"warp_sigma_ln", m.warp_sigma_ln},
                    {"warp_grid_x", m.warp_grid_x},
                    {"warp_grid_y", m.warp_grid_y},
                    {"noise_sigma_rel", m.noise_sigma_rel},
                    {"flying_pixel_prob", m.flying_pixel_prob},
                    {"flying_pixel_width_px", m.flying_pixel_width_px},
                    {"edge_threshold_rel", m.edge_threshold_rel}};
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
    m.only({"scale_sigma_ln", "warp_sigma_ln", "warp_grid_x", "warp_grid_y", "noise_sigma_rel", "flying_pixel_prob",
            "flying_pixel_width_px", "edge_threshold_rel"});
    MonoModel& mm = p.sensor.mono;
    mm.scale_sigma_ln = m.number("scale_sigma_ln", 0.0, 2.0);
    mm.warp_sigma_ln = m.number("warp_sigma_ln", 0.0, 1.0);
    mm.warp_grid_x = static_cast<int>(m.integer("warp_grid_x", 2, 32));
    mm.warp_grid_y = static_cast<int>(m.integer("warp_grid_y", 2, 32));
    mm.noise_sigma_rel = m.number("noise_sigma_rel", 0.0, 0.5);
    mm.flying_pixel_prob = m.number("flying_pixel_prob", 0.0, 1.0);
    mm.flying_pixel_width_px = static_cast<int>(m.integer("flying_pixel_width_px", 1, 16));
    mm.edge_threshold_rel = m.number("edge_threshold_rel", 0.0, 10.0);
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

void write_png(const std::string& path, const cv::Mat& image) {
  std::vector<unsigned char> bytes;
  bool ok = false;
  try {
    ok = cv::imencode(".png", image, bytes);
  } catch (const cv::Exception& e) {
    throw InputError(path + ": cannot encode PNG: " + e.what());
  }
  if (!ok) throw InputError(path + ": cannot encode PNG");
  write_text_file_atomic(path, std::string(bytes.begin(), bytes.end()));
}

cv::Mat read_png(const std::string& path, int expected_type, int width, int height, const std::string& what) {
  if (!std::filesystem::is_regular_file(path)) throw InputError(path + ": " + what + " image missing");
  cv::Mat m;
  try {
    m = cv::imread(path, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    throw InputError(path + ": cannot decode " + what + " image: " + e.what());
  }
  if (m.empty()) throw InputError(path + ": cannot decode " + what + " image (not a PNG?)");
  if (m.type() != expected_type) {
    throw InputError(path + ": " + what + " image must be single-channel " +
                     (expected_type == CV_16U ? "16-bit" : "8-bit") + " (got type " + std::to_string(m.type()) + ")");
  }
  if (m.cols != width || m.rows != height) {
    throw InputError(path + ": " + what + " image is " + std::to_string(m.cols) + "x" + std::to_string(m.rows) +
                     " but the intrinsics say " + std::to_string(width) + "x" + std::to_string(height));
  }
  return m;
}

}  // namespace

std::string scan_json_text(const Scan& scan) {
  ordered_json j;
  j["format"] = "floorcast-scan";
  j["format_version"] = kScanFormatVersion;
  j["sensor"] = scan.sensor;
  j["setting"] = scan.setting;
  j["seed"] = scan.params.seed;
  j["depth_unit_m"] = kDepthUnitM;
  j["frames"] =
      "world: plan metres, z up; scan: origin at the camera centre, gravity aligned, +x = heading, z up; "
      "camera: OpenCV (x right, y down, z forward); depth = z-depth, 0 = no return";
  ordered_json truth;
  truth["T_world_scan"] = {{"x_m", scan.truth.T_world_scan.x_m},
                           {"y_m", scan.truth.T_world_scan.y_m},
                           {"yaw_rad", scan.truth.T_world_scan.yaw_rad}};
  truth["camera_height_m"] = scan.truth.camera_height_m;
  truth["view_depth_scale"] = scan.truth.view_depth_scale;
  ordered_json trues = ordered_json::array();
  for (const Eigen::Isometry3d& T : scan.truth.T_scan_camera_true) trues.push_back(pose_matrix_json(T));
  truth["T_scan_camera_true"] = trues;
  j["ground_truth"] = truth;
  j["params"] = scan_params_to_json(scan.params);
  ordered_json views = ordered_json::array();
  for (std::size_t k = 0; k < scan.views.size(); ++k) {
    const DepthView& v = scan.views[k];
    ordered_json jv;
    jv["view_index"] = v.view_index;
    jv["intrinsics"] = {{"width_px", v.intrinsics.width_px}, {"height_px", v.intrinsics.height_px},
                        {"fx_px", v.intrinsics.fx_px},       {"fy_px", v.intrinsics.fy_px},
                        {"cx_px", v.intrinsics.cx_px},       {"cy_px", v.intrinsics.cy_px}};
    jv["T_scan_camera"] = pose_matrix_json(v.T_scan_camera);
    jv["depth"] = view_file(k, "depth");
    jv["glass_mask"] = view_file(k, "glass");
    if (!v.confidence.empty()) jv["confidence"] = view_file(k, "confidence");
    views.push_back(jv);
  }
  j["views"] = views;
  return j.dump(2) + "\n";
}

void save_scan(const std::string& dir, const Scan& scan) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir)) {
    throw InputError(dir + ": cannot create directory" + (ec ? ": " + ec.message() : std::string()));
  }
  for (std::size_t k = 0; k < scan.views.size(); ++k) {
    const DepthView& v = scan.views[k];
    const std::string where = dir + ": views[" + std::to_string(k) + "]";
    if (v.depth_m.type() != CV_32F || v.depth_m.cols != v.intrinsics.width_px ||
        v.depth_m.rows != v.intrinsics.height_px) {
      throw InputError(where + ": depth must be CV_32F of the intrinsics' size");
    }
    cv::Mat mm(v.depth_m.rows, v.depth_m.cols, CV_16U);
    for (int r = 0; r < mm.rows; ++r) {
      const float* src = v.depth_m.ptr<float>(r);
      auto* dst = mm.ptr<std::uint16_t>(r);
      for (int c = 0; c < mm.cols; ++c) {
        const double d = src[c];
        const double q = std::round(d / kDepthUnitM);
        dst[c] = (!(d > 0.0) || q > 65535.0) ? std::uint16_t{0} : static_cast<std::uint16_t>(std::max(1.0, q));
      }
    }
    write_png(dir + "/" + view_file(k, "depth"), mm);
    cv::Mat glass = v.glass_mask;
    if (glass.empty()) glass = cv::Mat::zeros(v.depth_m.size(), CV_8U);
    if (glass.type() != CV_8U || glass.size() != v.depth_m.size()) throw InputError(where + ": glass mask must be CV_8U of the depth's size");
    write_png(dir + "/" + view_file(k, "glass"), glass);
    if (!v.confidence.empty()) {
      if (v.confidence.type() != CV_8U || v.confidence.size() != v.depth_m.size()) {
        throw InputError(where + ": confidence must be CV_8U of the depth's size");
      }
      write_png(dir + "/" + view_file(k, "confidence"), v.confidence);
    }
  }
  write_text_file_atomic(dir + "/scan.json", scan_json_text(scan));
}

Scan load_scan(const std::string& dir) {
  const std::string json_path = dir + "/scan.json";
  if (!std::filesystem::is_directory(dir)) throw InputError(dir + ": not a scan folder (no such directory)");
  if (!std::filesystem::is_regular_file(json_path)) throw InputError(json_path + ": missing (not a scan folder?)");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(read_text_file(json_path));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(json_path + ": malformed JSON: " + e.what());
  }
  const JsonReader r(j, json_path, "");
  r.only({"format", "format_version", "sensor", "setting", "seed", "depth_unit_m", "frames", "ground_truth", "params",
          "views"});
  if (r.string("format") != "floorcast-scan") r.fail_key("format", "expected \"floorcast-scan\"");
  if (r.integer("format_version", 0, 1000000) != kScanFormatVersion) {
    r.fail_key("format_version", "unsupported (this floorcast reads version " + std::to_string(kScanFormatVersion) + ")");
  }
  const double unit = r.number("depth_unit_m", 1e-6, 1.0);
  Scan scan;
  scan.sensor = r.string("sensor");
  scan.setting = r.string("setting");
  scan.params = params_from_json_impl(r.object("params"));
  if (r.uint64("seed") != scan.params.seed) r.fail_key("seed", "differs from params.seed");
  ScanSetting setting;
  if (!parse_scan_setting(scan.setting, setting)) r.fail_key("setting", "expected full, partial or single");

  const nlohmann::json& jviews = r.raw("views");
  if (!jviews.is_array() || jviews.empty()) r.fail_key("views", "expected a non-empty array");
  for (std::size_t k = 0; k < jviews.size(); ++k) {
    const JsonReader v(jviews[k], json_path, "views[" + std::to_string(k) + "]");
    v.only({"view_index", "intrinsics", "T_scan_camera", "depth", "glass_mask", "confidence"});
    DepthView view;
    view.view_index = static_cast<int>(v.integer("view_index", 0, 100000));
    const JsonReader in = v.object("intrinsics");
    in.only({"width_px", "height_px", "fx_px", "fy_px", "cx_px", "cy_px"});
    view.intrinsics.width_px = static_cast<int>(in.integer("width_px", 1, 8192));
    view.intrinsics.height_px = static_cast<int>(in.integer("height_px", 1, 8192));
    view.intrinsics.fx_px = in.number("fx_px", 1e-3, 1e7);
    view.intrinsics.fy_px = in.number("fy_px", 1e-3, 1e7);
    view.intrinsics.cx_px = in.number("cx_px", -1e5, 1e5);
    view.intrinsics.cy_px = in.number("cy_px", -1e5, 1e5);
    view.T_scan_camera = pose_matrix_from_json(v, v.raw("T_scan_camera"), "T_scan_camera");
    const int W = view.intrinsics.width_px, H = view.intrinsics.height_px;
    auto file = [&](const std::string& key) {
      const std::string name = v.string(key);
      if (name.empty() || name.find('/') != std::string::npos || name.find('\\') != std::string::npos) {
        v.fail_key(key, "must be a plain file name inside the scan folder");
      }
      return dir + "/" + name;
    };
    const cv::Mat mm = read_png(file("depth"), CV_16U, W, H, "depth");
    mm.convertTo(view.depth_m, CV_32F, unit);
    view.glass_mask = read_png(file("glass_mask"), CV_8U, W, H, "glass mask");
    if (v.has("confidence")) {
      view.confidence = read_png(file("confidence"), CV_8U, W, H, "confidence");
      double lo = 0.0, hi = 0.0;
      cv::minMaxLoc(view.confidence, &lo, &hi);
      if (hi > 2.0) throw InputError(file("confidence") + ": confidence values must be 0, 1 or 2");
    }
    scan.views.push_back(std::move(view));
  }

  const JsonReader t = r.object("ground_truth");
  t.only({"T_world_scan", "camera_height_m", "view_depth_scale", "T_scan_camera_true"});
  const JsonReader p = t.object("T_world_scan");
  p.only({"x_m", "y_m", "yaw_rad"});
  scan.truth.T_world_scan.x_m = p.number("x_m", -1e5, 1e5);
  scan.truth.T_world_scan.y_m = p.number("y_m", -1e5, 1e5);
  scan.truth.T_world_scan.yaw_rad = p.number("yaw_rad", -100.0, 100.0);
  scan.truth.camera_height_m = t.number("camera_height_m", 0.0, 50.0);
  const std::vector<double> scales = t.numbers("view_depth_scale", static_cast<int>(scan.views.size()));
  for (std::size_t k = 0; k < scales.size(); ++k) {
    if (!(scales[k] > 0.0)) t.fail_key("view_depth_scale[" + std::to_string(k) + "]", "must be positive");
  }
  scan.truth.view_depth_scale = scales;
  const nlohmann::json& trues = t.raw("T_scan_camera_true");
  if (!trues.is_array() || trues.size() != scan.views.size()) {
    t.fail_key("T_scan_camera_true", "expected one 4x4 matrix per view");
  }
  for (std::size_t k = 0; k < trues.size(); ++k) {
    scan.truth.T_scan_camera_true.push_back(
        pose_matrix_from_json(t, trues[k], "T_scan_camera_true[" + std::to_string(k) + "]"));
  }
  return scan;
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
    if (!base.contains(it.key())) throw InputError(source + ": " + child + ": unknown scan parameter");
    if (base.at(it.key()).is_object()) check_override_keys(base.at(it.key()), it.value(), source, child);
  }
}

}  // namespace

void apply_scan_overrides(ScanParams& params, const nlohmann::json& overrides, const std::string& source) {
  nlohmann::json j = scan_params_to_json(params);
  check_override_keys(j, overrides, source, "");
  j.merge_patch(overrides);
  params = scan_params_from_json(j, source);
}

}  // namespace floorcast
