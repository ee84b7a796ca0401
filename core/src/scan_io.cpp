#include "floorcast/core/scan_io.hpp"

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>

#include "floorcast/core/file_io.hpp"
#include "floorcast/core/image_io.hpp"
#include "floorcast/core/json_reader.hpp"
#include "floorcast/core/json_text.hpp"
#include "floorcast/core/limits.hpp"
#include "floorcast/core/pose_json.hpp"

namespace floorcast {
namespace {

using nlohmann::ordered_json;

constexpr double kDepthUnitM = 0.001;

std::string view_file(std::size_t k, const char* what) { return scan_view_file(k, what); }

cv::Mat read_png(const std::string& path, int expected_type, int width, int height, const std::string& what) {
  if (!std::filesystem::is_regular_file(path)) throw InputError(path + ": " + what + " image missing");
  const cv::Mat m = read_image(path);
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

/// A colour image as 8-bit BGR: grey and BGRA files are converted (8-bit only).
cv::Mat read_colour(const std::string& path, int width, int height) {
  const cv::Mat m = read_image(path);
  if (m.depth() != CV_8U || (m.channels() != 1 && m.channels() != 3 && m.channels() != 4)) {
    throw InputError(path + ": colour image must be 8-bit grey, BGR or BGRA (got type " + std::to_string(m.type()) + ")");
  }
  if (m.cols != width || m.rows != height) {
    throw InputError(path + ": colour image is " + std::to_string(m.cols) + "x" + std::to_string(m.rows) +
                     " but the intrinsics say " + std::to_string(width) + "x" + std::to_string(height));
  }
  if (m.channels() == 3) return m;
  cv::Mat bgr(m.rows, m.cols, CV_8UC3);
  if (m.channels() == 1) {
    const int from_to[] = {0, 0, 0, 1, 0, 2};
    cv::mixChannels(&m, 1, &bgr, 1, from_to, 3);
  } else {
    const int from_to[] = {0, 0, 1, 1, 2, 2};
    cv::mixChannels(&m, 1, &bgr, 1, from_to, 3);
  }
  return bgr;
}

}  // namespace

std::string scan_view_file(std::size_t k, const std::string& kind) {
  std::ostringstream s;
  s << "view_" << std::setw(3) << std::setfill('0') << k << "_" << kind << ".png";
  return s.str();
}

std::string scan_json_text(const Scan& scan) {
  ordered_json j;
  j["format"] = "floorcast-scan";
  j["format_version"] = kScanFormatVersion;
  j["sensor"] = scan.sensor;
  j["depth_unit_m"] = kDepthUnitM;
  j["frames"] =
      "scan: origin at the camera centre, gravity aligned, +x = heading, z up; "
      "camera: OpenCV (x right, y down, z forward); depth = z-depth, 0 = no return";
  ordered_json views = ordered_json::array();
  for (std::size_t k = 0; k < scan.views.size(); ++k) {
    const DepthView& v = scan.views[k];
    ordered_json jv;
    jv["view_index"] = v.view_index;
    jv["intrinsics"] = {{"width_px", v.intrinsics.width_px}, {"height_px", v.intrinsics.height_px},
                        {"fx_px", v.intrinsics.fx_px},       {"fy_px", v.intrinsics.fy_px},
                        {"cx_px", v.intrinsics.cx_px},       {"cy_px", v.intrinsics.cy_px}};
    jv["T_scan_camera"] = pose_matrix_json(v.T_scan_camera);
    if (!v.depth_m.empty()) jv["depth"] = view_file(k, "depth");
    if (!v.rgb.empty()) jv["rgb"] = view_file(k, "rgb");
    if (!v.glass_mask.empty()) jv["glass_mask"] = view_file(k, "glass");
    if (!v.confidence.empty()) jv["confidence"] = view_file(k, "confidence");
    views.push_back(jv);
  }
  j["views"] = views;
  return j.dump(2) + "\n";
}

void save_scan(const std::string& dir, const Scan& scan) {
  create_directories_or_throw(dir);
  for (std::size_t k = 0; k < scan.views.size(); ++k) {
    const DepthView& v = scan.views[k];
    const std::string where = dir + ": views[" + std::to_string(k) + "]";
    if (!v.rgb.empty()) {
      if (v.rgb.type() != CV_8UC3 || v.rgb.cols != v.intrinsics.width_px || v.rgb.rows != v.intrinsics.height_px) {
        throw InputError(where + ": colour image must be CV_8UC3 of the intrinsics' size");
      }
      write_png(dir + "/" + view_file(k, "rgb"), v.rgb);
    }
    if (v.depth_m.empty()) {
      if (v.rgb.empty()) throw InputError(where + ": a view needs a depth or a colour image");
      continue;
    }
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
    if (!v.glass_mask.empty()) {
      if (v.glass_mask.type() != CV_8U || v.glass_mask.size() != v.depth_m.size()) {
        throw InputError(where + ": glass mask must be CV_8U of the depth's size");
      }
      write_png(dir + "/" + view_file(k, "glass"), v.glass_mask);
    }
    if (!v.confidence.empty()) {
      if (v.confidence.type() != CV_8U || v.confidence.size() != v.depth_m.size()) {
        throw InputError(where + ": confidence must be CV_8U of the depth's size");
      }
      write_png(dir + "/" + view_file(k, "confidence"), v.confidence);
    }
  }
  write_text_file_atomic(dir + "/scan.json", scan_json_text(scan));
}

ScanDescription parse_scan_description(const std::string& json_text, const std::string& json_path,
                                       bool require_depth) {
  const nlohmann::json j = parse_json_text(json_text, json_path);
  const JsonReader r(j, json_path, "");
  if (!r.has("format") || r.string("format") != "floorcast-scan") r.fail_key("format", "expected \"floorcast-scan\"");
  const long long version = r.integer("format_version", 0, 1000000);
  if (version == 1) {
    // Wave-1 folders kept the simulator's fields in scan.json; they are sim's business.
    r.only({"format", "format_version", "sensor", "setting", "seed", "depth_unit_m", "frames", "ground_truth",
            "params", "views"});
  } else if (version == kScanFormatVersion) {
    r.only({"format", "format_version", "sensor", "depth_unit_m", "frames", "views"});
  } else {
    r.fail_key("format_version", "unsupported (this floorcast reads versions 1 and " +
                                     std::to_string(kScanFormatVersion) + ")");
  }
  ScanDescription d;
  d.depth_unit_m = r.has("depth_unit_m") ? r.number("depth_unit_m", 1e-6, 1.0) : kDepthUnitM;
  Scan& scan = d.scan;
  if (r.has("sensor")) scan.sensor = r.string("sensor");

  const nlohmann::json& jviews = r.raw("views");
  if (!jviews.is_array() || jviews.empty()) r.fail_key("views", "expected a non-empty array");
  check_limit("max_views", static_cast<double>(jviews.size()), json_path + ": views", "views");
  double pixels = 0.0;
  for (std::size_t k = 0; k < jviews.size(); ++k) {
    const JsonReader v(jviews[k], json_path, "views[" + std::to_string(k) + "]");
    v.only({"view_index", "intrinsics", "T_scan_camera", "depth", "glass_mask", "confidence", "rgb"});
    DepthView view;
    view.view_index = v.has("view_index") ? static_cast<int>(v.integer("view_index", 0, 100000)) : static_cast<int>(k);
    const JsonReader in = v.object("intrinsics");
    in.only({"width_px", "height_px", "fx_px", "fy_px", "cx_px", "cy_px"});
    view.intrinsics.width_px = static_cast<int>(in.integer("width_px", 1, 8192));
    view.intrinsics.height_px = static_cast<int>(in.integer("height_px", 1, 8192));
    view.intrinsics.fx_px = in.number("fx_px", 1e-3, 1e7);
    view.intrinsics.fy_px = in.number("fy_px", 1e-3, 1e7);
    view.intrinsics.cx_px = in.number("cx_px", -1e5, 1e5);
    view.intrinsics.cy_px = in.number("cy_px", -1e5, 1e5);
    view.T_scan_camera = pose_matrix_from_json(v, v.raw("T_scan_camera"), "T_scan_camera");
    check_image_size(view.intrinsics.width_px, view.intrinsics.height_px, json_path + ": views[" + std::to_string(k) + "]");
    pixels += static_cast<double>(view.intrinsics.width_px) * view.intrinsics.height_px;
    auto file = [&](const std::string& key) {
      if (!v.has(key)) return std::string();
      const std::string name = v.string(key);
      if (name.empty() || name.find('/') != std::string::npos || name.find('\\') != std::string::npos || name == "." ||
          name == "..") {
        v.fail_key(key, "must be a plain file name inside the scan folder");
      }
      return name;
    };
    if (!v.has("depth") && require_depth) {
      v.fail_key("depth", "missing (a scan without depth images needs depth maps from elsewhere: floorcast observe "
                          "SCAN_DIR --depth-dir DIR)");
    }
    ScanDescription::Files f;
    f.depth = file("depth");
    f.rgb = file("rgb");
    f.glass_mask = file("glass_mask");
    f.confidence = file("confidence");
    view.rgb_file = f.rgb;
    d.files.push_back(f);
    scan.views.push_back(std::move(view));
  }
  // Every view's images are decoded at once: their pixels together are one scan's points.
  check_limit("max_points", pixels, json_path + ": pixels of all views", "pixels");
  return d;
}

Scan load_scan(const std::string& dir, const ScanLoadOptions& options) {
  const std::string json_path = dir + "/scan.json";
  if (!std::filesystem::is_directory(dir)) throw InputError(dir + ": not a scan folder (no such directory)");
  if (!std::filesystem::is_regular_file(json_path)) throw InputError(json_path + ": missing (not a scan folder?)");
  ScanDescription d = parse_scan_description(read_text_file(json_path), json_path, options.require_depth);
  Scan& scan = d.scan;
  for (std::size_t k = 0; k < scan.views.size(); ++k) {
    DepthView& view = scan.views[k];
    const ScanDescription::Files& f = d.files[k];
    const int W = view.intrinsics.width_px, H = view.intrinsics.height_px;
    if (!f.depth.empty()) {
      const cv::Mat mm = read_png(dir + "/" + f.depth, CV_16U, W, H, "depth");
      mm.convertTo(view.depth_m, CV_32F, d.depth_unit_m);
    }
    if (!f.rgb.empty()) {
      const std::string path = dir + "/" + f.rgb;
      if (options.load_rgb) {
        view.rgb = read_colour(path, W, H);
      } else if (!std::filesystem::is_regular_file(path)) {
        throw InputError(path + ": colour image missing");
      }
    }
    if (!f.glass_mask.empty()) view.glass_mask = read_png(dir + "/" + f.glass_mask, CV_8U, W, H, "glass mask");
    if (!f.confidence.empty()) {
      view.confidence = read_png(dir + "/" + f.confidence, CV_8U, W, H, "confidence");
      double lo = 0.0, hi = 0.0;
      cv::minMaxLoc(view.confidence, &lo, &hi);
      if (hi > 2.0) throw InputError(dir + "/" + f.confidence + ": confidence values must be 0, 1 or 2");
    }
  }
  return std::move(d.scan);
}

}  // namespace floorcast
