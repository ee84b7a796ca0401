#include "floorcast/core/scan_io.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>

#include "floorcast/core/depth_io.hpp"
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
  if (std::error_code ec; !std::filesystem::exists(path, ec)) throw InputError(path + ": " + what + " image missing");
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

std::string view_named_file(std::size_t k, const char* suffix) {
  std::ostringstream s;
  s << "view_" << std::setw(3) << std::setfill('0') << k << "_" << suffix;
  return s.str();
}

/// The scan-level "bev" block: the class set and depth range every view's BEV file shares (the
/// bin count comes from each file's shape).
struct BevGeometry {
  BevClasses classes = BevClasses::kSemantic;
  double min_depth_m = 0.0;
  double max_depth_m = 0.0;
};

}  // namespace

std::string column_semantics_json_text(const std::vector<std::vector<SemanticHit>>& columns) {
  ordered_json j;
  j["format"] = "floorcast-column-semantics";
  j["format_version"] = 1;
  ordered_json cols = ordered_json::array();
  for (const std::vector<SemanticHit>& hits : columns) {
    ordered_json c = ordered_json::array();
    for (const SemanticHit& h : hits) c.push_back({semantic_class_name(h.label), std::round(h.range_m * 1e4) / 1e4});
    cols.push_back(c);
  }
  j["columns"] = cols;
  return j.dump() + "\n";
}

std::vector<std::vector<SemanticHit>> parse_column_semantics(const std::string& text, const std::string& source,
                                                             int width_px) {
  const nlohmann::json j = parse_json_text(text, source);
  const JsonReader r(j, source, "");
  r.only({"format", "format_version", "columns"});
  if (r.string("format") != "floorcast-column-semantics") r.fail_key("format", "expected \"floorcast-column-semantics\"");
  if (r.integer("format_version", 0, 1000000) != 1) r.fail_key("format_version", "unsupported (this floorcast reads version 1)");
  const nlohmann::json& cols = r.raw("columns");
  if (!cols.is_array() || static_cast<int>(cols.size()) != width_px) {
    r.fail_key("columns", "expected one entry per image column (" + std::to_string(width_px) + ")");
  }
  std::vector<std::vector<SemanticHit>> out(cols.size());
  for (std::size_t u = 0; u < cols.size(); ++u) {
    const std::string key = "columns[" + std::to_string(u) + "]";
    const nlohmann::json& c = cols[u];
    if (!c.is_array()) r.fail_key(key, "expected an array of [class, range_m] pairs");
    if (c.size() > 256) r.fail_key(key, "more than 256 hits");
    for (std::size_t i = 0; i < c.size(); ++i) {
      const std::string hk = key + "[" + std::to_string(i) + "]";
      const nlohmann::json& h = c[i];
      SemanticHit hit;
      if (!h.is_array() || h.size() != 2 || !h[0].is_string() || !h[1].is_number()) {
        r.fail_key(hk, "expected [class, range_m]");
      }
      if (!semantic_class_from_name(h[0].get<std::string>(), hit.label)) {
        r.fail_key(hk, "unknown class \"" + printable_text(h[0].get<std::string>(), 40) +
                           "\" (known: wall, window, door_open, door_closed, furniture)");
      }
      hit.range_m = h[1].get<double>();
      if (!std::isfinite(hit.range_m) || hit.range_m < 0.0 || hit.range_m > 1e5) r.fail_key(hk, "range must be in [0, 1e5] m");
      if (!out[u].empty() && hit.range_m < out[u].back().range_m) r.fail_key(hk, "hits must be nearest first");
      if (!out[u].empty() && out[u].back().label == SemanticClass::kWall) r.fail_key(hk, "a hit after the wall that stops the ray");
      out[u].push_back(hit);
    }
  }
  return out;
}

BevPrediction read_view_bev(const std::string& path, const CameraIntrinsics& intrinsics, BevClasses classes,
                            double min_depth_m, double max_depth_m) {
  if (!std::filesystem::is_regular_file(path)) throw InputError(path + ": BEV file missing");
  const NpyArray a = read_npy(path);
  const int C = bev_class_count(classes);
  if (a.shape.size() != 3 || a.shape[0] < 1 || a.shape[1] < 1 || a.shape[1] > 255 ||
      a.shape[2] != static_cast<std::size_t>(C)) {
    std::string shape;
    for (const std::size_t n : a.shape) shape += (shape.empty() ? "" : ", ") + std::to_string(n);
    throw InputError(path + ": BEV must have shape (W, D, C) with 1 <= D <= 255 and C = " + std::to_string(C) + " (" +
                     bev_classes_name(classes) + " classes), got (" + shape + ")");
  }
  check_limit("max_rays", static_cast<double>(a.shape[0]), path + ": BEV columns", "columns");
  BevPrediction b;
  b.classes = classes;
  b.bins.count = static_cast<int>(a.shape[1]);
  b.bins.min_m = min_depth_m;
  b.bins.max_m = max_depth_m;
  b.bins.check(path);
  const std::size_t n = a.shape[0] * a.shape[1] * a.shape[2];
  b.probabilities.resize(n);
  if (a.dtype == "<f4") {
    std::memcpy(b.probabilities.data(), a.data.data(), n * sizeof(float));
  } else if (a.dtype == "<f8") {
    for (std::size_t i = 0; i < n; ++i) {
      double v;
      std::memcpy(&v, a.data.data() + i * sizeof(double), sizeof(double));
      b.probabilities[i] = static_cast<float>(v);
    }
  } else {
    throw InputError(path + ": BEV must be float32 or float64 (got dtype " + a.dtype + ")");
  }
  const std::size_t W = a.shape[0], D = a.shape[1];
  for (std::size_t cell = 0; cell < W * D; ++cell) {
    float* p = b.probabilities.data() + cell * static_cast<std::size_t>(C);
    double sum = 0.0;
    for (int c = 0; c < C; ++c) {
      if (!std::isfinite(p[c]) || p[c] < 0.0f || p[c] > 1.0f + 1e-6f) {
        throw InputError(path + ": BEV value at column " + std::to_string(cell / D) + ", bin " + std::to_string(cell % D) +
                         " is not a probability in [0, 1] (logits need a softmax over the class axis first)");
      }
      sum += p[c];
    }
    if (std::abs(sum - 1.0) > 1e-2) {
      throw InputError(path + ": BEV values at column " + std::to_string(cell / D) + ", bin " + std::to_string(cell % D) +
                       " sum to " + std::to_string(sum) + ", not 1: each (column, bin) must be a distribution over the classes");
    }
    for (int c = 0; c < C; ++c) p[c] = static_cast<float>(p[c] / sum);
  }
  b.column_azimuth_rad.resize(W);
  for (std::size_t w = 0; w < W; ++w) {
    const double u = (static_cast<double>(w) + 0.5) * intrinsics.width_px / static_cast<double>(W) - 0.5;
    b.column_azimuth_rad[w] = std::atan((intrinsics.cx_px - u) / intrinsics.fx_px);
  }
  return b;
}

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
    if (!v.column_semantics.empty()) jv["semantics"] = view_named_file(k, "semantics.json");
    if (!v.bev.empty()) jv["bev"] = view_named_file(k, "bev.npy");
    views.push_back(jv);
  }
  for (const DepthView& v : scan.views) {
    if (v.bev.empty()) continue;
    j["bev"] = {{"classes", bev_classes_name(v.bev.classes)},
                {"class_names", bev_class_names(v.bev.classes)},
                {"min_depth_m", v.bev.bins.min_m},
                {"max_depth_m", v.bev.bins.max_m}};
    break;
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
    if (!v.column_semantics.empty()) {
      if (static_cast<int>(v.column_semantics.size()) != v.intrinsics.width_px) {
        throw InputError(where + ": column semantics need one entry per image column");
      }
      write_text_file_atomic(dir + "/" + view_named_file(k, "semantics.json"), column_semantics_json_text(v.column_semantics));
    }
    if (!v.bev.empty()) {
      const BevPrediction& b = v.bev;
      const DepthView& first = *std::find_if(scan.views.begin(), scan.views.end(), [](const DepthView& x) { return !x.bev.empty(); });
      if (b.classes != first.bev.classes || b.bins.min_m != first.bev.bins.min_m || b.bins.max_m != first.bev.bins.max_m) {
        throw InputError(where + ": every view's BEV must share one class set and depth range");
      }
      b.check(where + ": BEV");
      write_npy(dir + "/" + view_named_file(k, "bev.npy"),
                {static_cast<std::size_t>(b.num_columns()), static_cast<std::size_t>(b.bins.count),
                 static_cast<std::size_t>(b.num_classes())},
                b.probabilities);
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
    r.only({"format", "format_version", "sensor", "depth_unit_m", "frames", "bev", "views"});
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
    v.only({"view_index", "intrinsics", "T_scan_camera", "depth", "glass_mask", "confidence", "rgb", "semantics", "bev"});
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
    f.semantics = file("semantics");
    f.bev = file("bev");
    if (!f.bev.empty() && !r.has("bev")) {
      v.fail_key("bev", "a view BEV needs the scan-level \"bev\" block (classes, min_depth_m, max_depth_m)");
    }
    view.rgb_file = f.rgb;
    d.files.push_back(f);
    scan.views.push_back(std::move(view));
  }
  if (r.has("bev")) {
    const JsonReader b = r.object("bev");
    b.only({"classes", "class_names", "min_depth_m", "max_depth_m"});
    if (!bev_classes_from_name(b.string("classes"), d.bev_classes)) b.fail_key("classes", "expected \"semantic\" or \"occupancy\"");
    if (b.has("class_names") && b.raw("class_names") != nlohmann::json(bev_class_names(d.bev_classes))) {
      b.fail_key("class_names", "expected " + nlohmann::json(bev_class_names(d.bev_classes)).dump() + " for these classes");
    }
    d.bev_min_depth_m = b.number("min_depth_m", 1e-6, 1e5);
    d.bev_max_depth_m = b.number("max_depth_m", 1e-6, 1e5);
    if (!(d.bev_max_depth_m > d.bev_min_depth_m)) b.fail_key("max_depth_m", "must exceed min_depth_m");
  }
  // Every view's images are decoded at once: their pixels together are one scan's points.
  check_limit("max_points", pixels, json_path + ": pixels of all views", "pixels");
  return d;
}

Scan load_scan(const std::string& dir, const ScanLoadOptions& options) {
  const std::string json_path = dir + "/scan.json";
  if (!std::filesystem::is_directory(dir)) throw InputError(dir + ": not a scan folder (no such directory)");
  // Missing: not a scan folder; a FIFO, device or folder there is named by read_text_file.
  if (std::error_code ec; !std::filesystem::exists(json_path, ec)) throw InputError(json_path + ": missing (not a scan folder?)");
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
    if (!f.semantics.empty()) {
      const std::string path = dir + "/" + f.semantics;
      if (!std::filesystem::is_regular_file(path)) throw InputError(path + ": column semantics missing");
      view.column_semantics = parse_column_semantics(read_text_file(path), path, W);
    }
    if (!f.bev.empty()) view.bev = read_view_bev(dir + "/" + f.bev, view.intrinsics, d.bev_classes, d.bev_min_depth_m, d.bev_max_depth_m);
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
