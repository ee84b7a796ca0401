#include "floorcast/core/observation_io.hpp"

#include <nlohmann/json.hpp>

#include "floorcast/core/file_io.hpp"
#include "floorcast/core/json_reader.hpp"
#include "floorcast/core/json_text.hpp"
#include "floorcast/core/limits.hpp"

namespace floorcast {
namespace {

using nlohmann::ordered_json;
constexpr int kObservationFormatVersion = 1;

}  // namespace

const char* surface_label_name(SurfaceLabel label) {
  switch (label) {
    case SurfaceLabel::kWall: return "wall";
    case SurfaceLabel::kDoorClosed: return "door_closed";
    case SurfaceLabel::kGlass: return "glass";
    case SurfaceLabel::kObstacle: return "obstacle";
  }
  return "unknown";
}

bool surface_label_from_name(const std::string& name, SurfaceLabel& label) {
  for (SurfaceLabel l : {SurfaceLabel::kWall, SurfaceLabel::kDoorClosed, SurfaceLabel::kGlass, SurfaceLabel::kObstacle}) {
    if (name == surface_label_name(l)) {
      label = l;
      return true;
    }
  }
  return false;
}

std::string observation_to_json_text(const ObservationRecord& rec) {
  const Observation2D& o = rec.observation;
  ordered_json j;
  j["format"] = "floorcast-observation";
  j["format_version"] = kObservationFormatVersion;
  j["frame"] = "observer";
  j["source"] = rec.source;
  j["max_range_m"] = o.max_range_m;
  ordered_json segs = ordered_json::array();
  for (const Segment2& s : o.segments_m) segs.push_back({s.a_m.x(), s.a_m.y(), s.b_m.x(), s.b_m.y()});
  j["segments_m"] = segs;
  if (!rec.segment_labels.empty()) {
    ordered_json labels = ordered_json::array();
    for (SurfaceLabel l : rec.segment_labels) labels.push_back(surface_label_name(l));
    j["segment_labels"] = labels;
  }
  j["ray_ranges_m"] = o.ray_ranges_m;
  if (rec.T_world_observer) {
    j["ground_truth"] = {{"x_m", rec.T_world_observer->x_m},
                         {"y_m", rec.T_world_observer->y_m},
                         {"yaw_rad", rec.T_world_observer->yaw_rad}};
  }
  if (!rec.metadata.empty()) {
    ordered_json meta = ordered_json::object();
    for (const auto& [k, v] : rec.metadata) meta[k] = v;
    j["metadata"] = meta;
  }
  return j.dump(2) + "\n";
}

ObservationRecord parse_observation_json(const std::string& text, const std::string& source_name) {
  const nlohmann::json j = parse_json_text(text, source_name);
  const JsonReader r(j, source_name, "");
  r.only({"format", "format_version", "frame", "source", "max_range_m", "segments_m", "segment_labels", "ray_ranges_m",
          "ground_truth", "metadata"});
  if (r.string("format") != "floorcast-observation") r.fail_key("format", "expected \"floorcast-observation\"");
  if (r.integer("format_version", 0, 1000000) != kObservationFormatVersion) {
    r.fail_key("format_version", "unsupported (this floorcast reads version 1)");
  }
  if (r.string("frame") != "observer") r.fail_key("frame", "expected \"observer\"");
  ObservationRecord rec;
  rec.source = r.has("source") ? r.string("source") : std::string();
  Observation2D& o = rec.observation;
  o.max_range_m = r.number("max_range_m", 1e-6, 1e5);
  const nlohmann::json& segs = r.raw("segments_m");
  if (!segs.is_array()) r.fail_key("segments_m", "expected an array of [ax, ay, bx, by]");
  check_limit("max_segments", static_cast<double>(segs.size()), source_name + ": segments_m", "segments");
  for (std::size_t i = 0; i < segs.size(); ++i) {
    const std::string key = "segments_m[" + std::to_string(i) + "]";
    const nlohmann::json& s = segs[i];
    if (!s.is_array() || s.size() != 4) r.fail_key(key, "expected [ax, ay, bx, by]");
    double v[4];
    for (std::size_t k = 0; k < 4; ++k) {
      if (!s[k].is_number() || !std::isfinite(s[k].get<double>())) r.fail_key(key, "expected finite numbers");
      v[k] = s[k].get<double>();
      if (std::abs(v[k]) > 1e5) r.fail_key(key, "coordinate absurdly large");
    }
    o.segments_m.push_back({Vec2(v[0], v[1]), Vec2(v[2], v[3])});
  }
  if (r.has("segment_labels")) {
    const nlohmann::json& labels = r.raw("segment_labels");
    if (!labels.is_array() || labels.size() != o.segments_m.size()) {
      r.fail_key("segment_labels", "expected one label per segment");
    }
    for (std::size_t i = 0; i < labels.size(); ++i) {
      SurfaceLabel l;
      if (!labels[i].is_string() || !surface_label_from_name(labels[i].get<std::string>(), l)) {
        r.fail_key("segment_labels[" + std::to_string(i) + "]", "expected wall, door_closed, glass or obstacle");
      }
      rec.segment_labels.push_back(l);
    }
  }
  if (r.has("ray_ranges_m")) {
    const nlohmann::json& rays = r.raw("ray_ranges_m");
    if (rays.is_array()) {
      check_limit("max_rays", static_cast<double>(rays.size()), source_name + ": ray_ranges_m", "rays");
      if (rays.size() < 4) {
        r.fail_key("ray_ranges_m", "has " + std::to_string(rays.size()) +
                                       " rays; equiangular rays come in at least 4 (leave the key out when there are none)");
      }
    }
    o.ray_ranges_m = r.numbers("ray_ranges_m", -1);
    for (std::size_t i = 0; i < o.ray_ranges_m.size(); ++i) {
      if (o.ray_ranges_m[i] < 0.0 || o.ray_ranges_m[i] > o.max_range_m * (1.0 + 1e-12)) {
        r.fail_key("ray_ranges_m[" + std::to_string(i) + "]", "must be in [0, max_range_m]");
      }
    }
  }
  if (r.has("ground_truth")) {
    const JsonReader g = r.object("ground_truth");
    g.only({"x_m", "y_m", "yaw_rad"});
    rec.T_world_observer = Pose2{g.number("x_m", -1e5, 1e5), g.number("y_m", -1e5, 1e5), g.number("yaw_rad", -100.0, 100.0)};
  }
  if (r.has("metadata")) {
    const nlohmann::json& m = r.raw("metadata");
    if (!m.is_object()) r.fail_key("metadata", "expected an object of strings");
    for (auto it = m.begin(); it != m.end(); ++it) {
      if (!it.value().is_string()) r.fail_key("metadata." + it.key(), "expected a string");
      rec.metadata[it.key()] = it.value().get<std::string>();
    }
  }
  return rec;
}

void save_observation(const std::string& path, const ObservationRecord& record) {
  write_text_file_atomic(path, observation_to_json_text(record));
}

ObservationRecord load_observation(const std::string& path) {
  return parse_observation_json(read_text_file(path), path);
}

}  // namespace floorcast
