#include "floorcast/core/observation_io.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <functional>
#include <tuple>

#include "floorcast/core/fields.hpp"
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

namespace {

/// A key a file must hold with exactly this value (format, version, frame).
template <class T>
std::pair<std::function<void(ordered_json&, const ObservationRecord&)>, std::function<void(ParamReader&, ObservationRecord&)>>
constant(const char* key, T value, const char* expected) {
  return {[key, value](ordered_json& j, const ObservationRecord&) { j[key] = value; },
          [key, value, expected](ParamReader& r, ObservationRecord&) {
            nlohmann::json v;
            r.read(key, v);
            if (v != nlohmann::json(value)) r.fail(key, expected);
          }};
}

const std::vector<std::pair<const char*, BevClasses>> kBevClassNames = {{"semantic", BevClasses::kSemantic},
                                                                        {"occupancy", BevClasses::kOccupancy}};

/// One BEV as the observation schema's "bev" entries hold it (validated: BevPrediction::check).
const FieldList<BevPrediction>& bev_fields() {
  using B = BevPrediction;
  static const FieldList<B> f =
      FieldList<B>("bev")
          .choice("classes", &B::classes, kBevClassNames, "class set: the thesis' semantic classes or Table 4.3's occupancy")
          .custom(
              "class_names", [](ordered_json& j, const B& b) { j["class_names"] = bev_class_names(b.classes); },
              [](ParamReader& r, B& b) {
                if (!r.optional("class_names")) return;
                nlohmann::json names;
                r.read("class_names", names);
                if (names != nlohmann::json(bev_class_names(b.classes))) {
                  r.fail("class_names", "expected " + nlohmann::json(bev_class_names(b.classes)).dump() + " for these classes");
                }
              },
              "texts", "optional: the class of each index (checked against classes)")
          .integer("depth_bins", [](auto& b) -> auto& { return b.bins.count; }, 1, 255, "D log-spaced depth bins")
          .number("min_depth_m", [](auto& b) -> auto& { return b.bins.min_m; }, 1e-6, 1e5, "near edge of bin 0, m")
          .number("max_depth_m", [](auto& b) -> auto& { return b.bins.max_m; }, 1e-6, 1e5, "far edge of the last bin, m")
          .custom(
              "column_azimuth_rad", [](ordered_json& j, const B& b) { j["column_azimuth_rad"] = b.column_azimuth_rad; },
              [](ParamReader& r, B& b) { r.read("column_azimuth_rad", b.column_azimuth_rad, -100.0, 100.0); },
              "numbers", "W columns' azimuths, observer frame, rad")
          .custom(
              "probabilities",
              [](ordered_json& j, const B& b) {
                ordered_json p = ordered_json::array();
                for (const float v : b.probabilities) p.push_back(std::round(static_cast<double>(v) * 1e6) / 1e6);
                j["probabilities"] = p;
              },
              [](ParamReader& r, B& b) {
                nlohmann::json p;
                r.read("probabilities", p);
                if (!p.is_array()) r.fail("probabilities", "expected an array of W x D x C numbers");
                const double expected = static_cast<double>(b.column_azimuth_rad.size()) * b.bins.count * b.num_classes();
                if (static_cast<double>(p.size()) != expected) {
                  r.fail("probabilities", "has " + std::to_string(p.size()) + " numbers, expected W x D x C = " +
                                              std::to_string(static_cast<long long>(expected)));
                }
                b.probabilities.reserve(p.size());
                for (const nlohmann::json& v : p) {
                  if (!v.is_number()) r.fail("probabilities", "expected numbers");
                  b.probabilities.push_back(static_cast<float>(v.get<double>()));
                }
              },
              "numbers", "W x D x C, index (w * D + d) * C + c, rounded to 1e-6")
          .check([](const B& b, const ParamReader& r) {
            try {
              b.check("BEV");
            } catch (const InputError& e) {
              r.fail("probabilities", e.what());
            }
          });
  return f;
}

/// A 3-vector written as [x, y, z]; read back as finite coordinates within 1e5 m.
ordered_json vec3_json(const Eigen::Vector3d& v) { return ordered_json::array({v.x(), v.y(), v.z()}); }

Eigen::Vector3d vec3_from_json(const ParamReader& r, const nlohmann::json& v, const std::string& key) {
  if (!v.is_array() || v.size() != 3) r.fail(key, "expected [x, y, z]");
  Eigen::Vector3d out;
  for (std::size_t a = 0; a < 3; ++a) {
    if (!v[a].is_number() || !std::isfinite(v[a].get<double>()) || std::abs(v[a].get<double>()) > 1e5) {
      r.fail(key, "expected finite coordinates within 1e5 m");
    }
    out[static_cast<Eigen::Index>(a)] = v[a].get<double>();
  }
  return out;
}

/// A 3-vector member of a plane patch.
template <class Get>
std::pair<std::function<void(ordered_json&, const PlanePatch&)>, std::function<void(ParamReader&, PlanePatch&)>> vec3_field(
    const char* key, Get get) {
  return {[key, get](ordered_json& j, const PlanePatch& p) { j[key] = vec3_json(get(p)); },
          [key, get](ParamReader& r, PlanePatch& p) {
            nlohmann::json v;
            r.read(key, v);
            get(p) = vec3_from_json(r, v, key);
          }};
}

/// One plane patch of an observation (core/plane_patch.hpp).
const FieldList<PlanePatch>& plane_patch_fields() {
  using P = PlanePatch;
  const auto normal = vec3_field("normal", [](auto& p) -> auto& { return p.normal; });
  const auto centroid = vec3_field("centroid_m", [](auto& p) -> auto& { return p.centroid_m; });
  static const FieldList<P> f =
      FieldList<P>("plane patch")
          .custom("normal", normal.first, normal.second, "[x, y, z]",
                  "unit normal towards the observer's side (into free space)")
          .number("offset_m", &P::offset_m, -1e5, 0.0, "normal . p = offset_m on the plane (<= 0: the observer is on the normal's side), m")
          .custom("centroid_m", centroid.first, centroid.second, "[x, y, z]", "centre of the supporting points, m")
          .number("radius_m", &P::radius_m, 0.0, 1e5, "largest distance of a supporting point from the centre (enclosing sphere), m")
          .integer("support_points", &P::support_points, 0, 2000000000, "measured points supporting the patch (0: built from geometry)")
          .custom(
              "cells_m",
              [](ordered_json& j, const P& p) {
                ordered_json cells = ordered_json::array();
                for (const Eigen::Vector3d& c : p.cells_m) cells.push_back(vec3_json(c));
                j["cells_m"] = cells;
              },
              [](ParamReader& r, P& p) {
                nlohmann::json cells;
                r.read("cells_m", cells);
                if (!cells.is_array()) r.fail("cells_m", "expected an array of [x, y, z]");
                p.cells_m.clear();
                for (std::size_t c = 0; c < cells.size(); ++c) {
                  p.cells_m.push_back(vec3_from_json(r, cells[c], "cells_m[" + std::to_string(c) + "]"));
                }
              },
              "[[x, y, z], ...]", "centres of the occupied cells of the patch's l x l grid, m")
          .check([](const P& p, const ParamReader& r) {
            if (std::abs(p.normal.norm() - 1.0) > 1e-3) r.fail("normal", "expected a unit vector");
          });
  return f;
}

const FieldList<ObservationRecord>& observation_fields() {
  using R = ObservationRecord;
  const auto format = constant("format", "floorcast-observation", "expected \"floorcast-observation\"");
  const auto version = constant("format_version", kObservationFormatVersion, "unsupported (this floorcast reads version 1)");
  const auto frame = constant("frame", "observer", "expected \"observer\"");
  static const FieldList<R> f =
      FieldList<R>("observation")
          .custom("format", format.first, format.second, "text", "\"floorcast-observation\"")
          .custom("format_version", version.first, version.second, "integer", "1")
          .custom("frame", frame.first, frame.second, "text", "\"observer\": coordinates in the observer's frame")
          .text("source", &R::source, "what made the observation")
          .optional([](const R&) { return true; })
          .number("max_range_m", [](auto& r) -> auto& { return r.observation.max_range_m; }, 1e-6, 1e5,
                  "range the observation covers, m")
          .custom(
              "segments_m",
              [](ordered_json& j, const R& rec) {
                ordered_json segs = ordered_json::array();
                for (const Segment2& s : rec.observation.segments_m) segs.push_back({s.a_m.x(), s.a_m.y(), s.b_m.x(), s.b_m.y()});
                j["segments_m"] = segs;
              },
              [](ParamReader& r, R& rec) {
                nlohmann::json segs;
                r.read("segments_m", segs);
                if (!segs.is_array()) r.fail("segments_m", "expected an array of [ax, ay, bx, by]");
                for (std::size_t i = 0; i < segs.size(); ++i) {
                  const std::string key = "segments_m[" + std::to_string(i) + "]";
                  const nlohmann::json& s = segs[i];
                  if (!s.is_array() || s.size() != 4) r.fail(key, "expected [ax, ay, bx, by]");
                  double v[4];
                  for (std::size_t k = 0; k < 4; ++k) {
                    if (!s[k].is_number() || !std::isfinite(s[k].get<double>())) r.fail(key, "expected finite numbers");
                    v[k] = s[k].get<double>();
                    if (std::abs(v[k]) > 1e5) r.fail(key, "coordinate absurdly large");
                  }
                  rec.observation.segments_m.push_back({Vec2(v[0], v[1]), Vec2(v[2], v[3])});
                }
              },
              "[[ax, ay, bx, by], ...]", "observed wall segments, observer frame, m")
          .custom(
              "segment_labels",
              [](ordered_json& j, const R& rec) {
                if (rec.segment_labels.empty()) return;
                ordered_json labels = ordered_json::array();
                for (SurfaceLabel l : rec.segment_labels) labels.push_back(surface_label_name(l));
                j["segment_labels"] = labels;
              },
              [](ParamReader& r, R& rec) {
                if (!r.optional("segment_labels")) return;
                nlohmann::json labels;
                r.read("segment_labels", labels);
                if (!labels.is_array() || labels.size() != rec.observation.segments_m.size()) {
                  r.fail("segment_labels", "expected one label per segment");
                }
                for (std::size_t i = 0; i < labels.size(); ++i) {
                  SurfaceLabel l;
                  if (!labels[i].is_string() || !surface_label_from_name(labels[i].get<std::string>(), l)) {
                    r.fail("segment_labels[" + std::to_string(i) + "]", "expected wall, door_closed, glass or obstacle");
                  }
                  rec.segment_labels.push_back(l);
                }
              },
              "[label, ...]", "optional: wall, door_closed, glass or obstacle per segment")
          .custom(
              "ray_ranges_m",
              [](ordered_json& j, const R& rec) {
                // Left out when there are none: the reader refuses fewer than 4 rays.
                if (!rec.observation.ray_ranges_m.empty()) j["ray_ranges_m"] = rec.observation.ray_ranges_m;
              },
              [](ParamReader& r, R& rec) {
                if (!r.optional("ray_ranges_m")) return;
                nlohmann::json rays;
                r.read("ray_ranges_m", rays);
                if (!rays.is_array()) r.fail("ray_ranges_m", "expected an array of numbers");
                if (rays.size() < 4) {
                  r.fail("ray_ranges_m", "has " + std::to_string(rays.size()) +
                                             " rays; equiangular rays come in at least 4 (leave the key out when there are none)");
                }
                const double max_range_m = rec.observation.max_range_m;
                for (std::size_t i = 0; i < rays.size(); ++i) {
                  const std::string key = "ray_ranges_m[" + std::to_string(i) + "]";
                  if (!rays[i].is_number()) r.fail(key, "expected a number");
                  const double v = rays[i].get<double>();
                  if (!std::isfinite(v)) r.fail(key, "not finite");
                  if (v < 0.0 || v > max_range_m * (1.0 + 1e-12)) r.fail(key, "must be in [0, max_range_m]");
                  rec.observation.ray_ranges_m.push_back(v);
                }
              },
              "[range, ...]", "optional: ranges along equiangular rays (ray i at 360 i / n deg), m")
          .number("plane_cell_m", [](auto& r) -> auto& { return r.observation.plane_cell_m; }, 1e-3, 100.0,
                  "optional, with planes: cell edge of every patch's grid, m")
          .optional([](const R& rec) { return !rec.observation.planes.empty(); })
          .list("planes", [](auto& r) -> auto& { return r.observation.planes; }, plane_patch_fields())
          .optional([](const R& rec) { return !rec.observation.planes.empty(); })
          .custom(
              "bev",
              [](ordered_json& j, const R& rec) {
                if (rec.observation.bev.empty()) return;
                ordered_json bevs = ordered_json::array();
                for (const BevPrediction& b : rec.observation.bev) bevs.push_back(bev_fields().write(b));
                j["bev"] = bevs;
              },
              [](ParamReader& r, R& rec) {
                if (!r.optional("bev")) return;
                r.objects("bev", [&](ParamReader& in, std::size_t i) {
                  BevPrediction b;
                  bev_fields().read_into(in, b);
                  for (const BevPrediction& other : rec.observation.bev) {
                    if (other.classes == b.classes) {
                      r.fail("bev[" + std::to_string(i) + "]", std::string("a second ") + bev_classes_name(b.classes) + " BEV");
                    }
                  }
                  rec.observation.bev.push_back(std::move(b));
                });
              },
              "[{classes, class_names, depth_bins, min_depth_m, max_depth_m, column_azimuth_rad, probabilities}, ...]",
              "optional: BEV predictions (core/bev.hpp), at most one per class set")
          .custom(
              "ground_truth",
              [](ordered_json& j, const R& rec) {
                if (!rec.T_world_observer) return;
                j["ground_truth"] = {{"x_m", rec.T_world_observer->x_m},
                                     {"y_m", rec.T_world_observer->y_m},
                                     {"yaw_rad", rec.T_world_observer->yaw_rad}};
              },
              [](ParamReader& r, R& rec) {
                if (!r.optional("ground_truth")) return;
                static const FieldList<Pose2> pose = FieldList<Pose2>("ground truth")
                                                         .number("x_m", &Pose2::x_m, -1e5, 1e5, "world x, m")
                                                         .number("y_m", &Pose2::y_m, -1e5, 1e5, "world y, m")
                                                         .number("yaw_rad", &Pose2::yaw_rad, -100.0, 100.0, "heading, rad");
                Pose2 p;
                r.section("ground_truth", [&](ParamReader& g) { pose.read_into(g, p); });
                rec.T_world_observer = p;
              },
              "{x_m, y_m, yaw_rad}", "optional: the true pose of the observer")
          .custom(
              "metadata",
              [](ordered_json& j, const R& rec) {
                if (rec.metadata.empty()) return;
                ordered_json meta = ordered_json::object();
                for (const auto& [k, v] : rec.metadata) meta[k] = v;
                j["metadata"] = meta;
              },
              [](ParamReader& r, R& rec) {
                if (!r.optional("metadata")) return;
                nlohmann::json m;
                r.read("metadata", m);
                if (!m.is_object()) r.fail("metadata", "expected an object of strings");
                for (auto it = m.begin(); it != m.end(); ++it) {
                  if (!it.value().is_string()) r.fail("metadata." + it.key(), "expected a string");
                  rec.metadata[it.key()] = it.value().get<std::string>();
                }
              },
              "{key: text}", "optional: notes of the tool that made it");
  return f;
}

}  // namespace

std::string observation_to_json_text(const ObservationRecord& rec) { return observation_fields().write(rec).dump(2) + "\n"; }

ObservationRecord parse_observation_json(const std::string& text, const std::string& source_name) {
  const nlohmann::json j = parse_json_text(text, source_name);
  // The sizes are checked against the limits before any element is read.
  for (const auto& [key, limit, unit] : {std::tuple{"segments_m", "max_segments", "segments"},
                                         std::tuple{"ray_ranges_m", "max_rays", "rays"}}) {
    if (j.is_object() && j.contains(key) && j.at(key).is_array()) {
      check_limit(limit, static_cast<double>(j.at(key).size()), source_name + ": " + key, unit);
    }
  }
  if (j.is_object() && j.contains("bev") && j.at("bev").is_array()) {
    for (std::size_t i = 0; i < j.at("bev").size(); ++i) {
      const nlohmann::json& b = j.at("bev")[i];
      if (b.is_object() && b.contains("column_azimuth_rad") && b.at("column_azimuth_rad").is_array()) {
        check_limit("max_rays", static_cast<double>(b.at("column_azimuth_rad").size()),
                    source_name + ": bev[" + std::to_string(i) + "].column_azimuth_rad", "columns");
      }
    }
  }
  if (j.is_object() && j.contains("planes") != j.contains("plane_cell_m")) {
    throw ParameterError(source_name + ": planes: planes and plane_cell_m come together", "planes");
  }
  if (j.is_object() && j.contains("planes") && j.at("planes").is_array()) {
    const nlohmann::json& planes = j.at("planes");
    check_limit("max_segments", static_cast<double>(planes.size()), source_name + ": planes", "planes");
    double cells_total = 0.0;
    for (const nlohmann::json& p : planes) {
      if (p.is_object() && p.contains("cells_m") && p.at("cells_m").is_array()) {
        cells_total += static_cast<double>(p.at("cells_m").size());
      }
    }
    check_limit("max_points", cells_total, source_name + ": planes[].cells_m", "cells");
  }
  ObservationRecord rec;
  observation_fields().read_record(rec, j, source_name);
  for (PlanePatch& p : rec.observation.planes) {
    if (std::abs(p.normal.norm() - 1.0) > 1e-12) p.normal.normalize();  // exactly unit, as written when it was
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
