// Scenario YAML reading, validation (file:line:col + key in every message), defaults, sweeps.
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "floorcast/floorplans/io.hpp"
#include "floorcast/core/hash.hpp"
#include "floorcast/core/json_text.hpp"
#include "floorcast/core/limits.hpp"
#include "floorcast/core/params.hpp"
#include "floorcast/core/types.hpp"
#include "floorcast/sim/odometry.hpp"
#include "floorcast/sim/scan_io.hpp"
#include "floorcast/track/tracker.hpp"
#include "floorcast/scenarios/scenario.hpp"

namespace floorcast {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using OJson = nlohmann::ordered_json;

/// A YAML document converted to JSON, remembering where each dotted key came from.
struct Located {
  OJson value;
  std::map<std::string, YAML::Mark> marks;  // dotted path -> position
};

std::string mark_text(const std::string& source, const YAML::Mark& mark) {
  if (mark.line < 0) return source;
  return source + ":" + std::to_string(mark.line + 1) + ":" + std::to_string(mark.column + 1);
}

/// Is `s` a YAML integer ([-+]?[0-9]+) or real ([-+]?(digits[.digits]|.digits)([eE][-+]?digits)?)?
/// Hand-written: std::regex recurses per character and overflows the stack on long scalars.
enum class NumberKind { kNone, kInteger, kReal };
NumberKind number_kind(const std::string& s) {
  std::size_t i = 0;
  const std::size_t n = s.size();
  auto digits = [&] {
    const std::size_t start = i;
    while (i < n && s[i] >= '0' && s[i] <= '9') ++i;
    return i - start;
  };
  if (i < n && (s[i] == '+' || s[i] == '-')) ++i;
  const std::size_t int_digits = digits();
  if (i == n) return int_digits > 0 ? NumberKind::kInteger : NumberKind::kNone;
  std::size_t frac_digits = 0;
  if (s[i] == '.') {
    ++i;
    frac_digits = digits();
  }
  if (int_digits == 0 && frac_digits == 0) return NumberKind::kNone;
  if (i < n && (s[i] == 'e' || s[i] == 'E')) {
    ++i;
    if (i < n && (s[i] == '+' || s[i] == '-')) ++i;
    if (digits() == 0) return NumberKind::kNone;
  }
  return i == n ? NumberKind::kReal : NumberKind::kNone;
}

/// Converts a YAML document to JSON with bounded work: nesting depth (max_nesting_depth), nodes
/// after alias expansion (max_yaml_nodes: "billion laughs"), recursive aliases refused; keys must
/// be unique scalars, text valid UTF-8, numbers finite. Errors carry file:line:column.
class YamlConverter {
 public:
  YamlConverter(std::string source, std::map<std::string, YAML::Mark>& marks)
      : source_(std::move(source)),
        marks_(marks),
        max_depth_(input_limits().max_nesting_depth),
        max_nodes_(input_limits().max_yaml_nodes) {}

  void convert(const YAML::Node& node, const std::string& path, OJson& out) {
    if (++nodes_ > max_nodes_) {
      throw LimitError(mark_text(source_, node.Mark()) + ": the document expands (aliases counted each time they are "
                           "used) to more than " + std::to_string(static_cast<long long>(max_nodes_)) +
                           " nodes: exceeds the limit max_yaml_nodes (raise it with "
                           "FLOORCAST_LIMITS=max_yaml_nodes=N; docs/limits.md)",
                       "max_yaml_nodes");
    }
    for (const YAML::Node& a : ancestors_) {
      if (a.is(node)) {
        throw InputError(mark_text(source_, node.Mark()) + ": " + (path.empty() ? std::string("document") : path) +
                         ": recursive alias (a node that contains itself)");
      }
    }
    const bool collection = node.Type() == YAML::NodeType::Map || node.Type() == YAML::NodeType::Sequence;
    if (collection && static_cast<double>(ancestors_.size() + 1) > max_depth_) {
      throw LimitError(mark_text(source_, node.Mark()) + ": nesting deeper than " +
                           std::to_string(static_cast<long long>(max_depth_)) +
                           " levels exceeds the limit max_nesting_depth (raise it with "
                           "FLOORCAST_LIMITS=max_nesting_depth=N; docs/limits.md)",
                       "max_nesting_depth");
    }
    marks_.emplace(path, node.Mark());
    switch (node.Type()) {
      case YAML::NodeType::Map: {
        ancestors_.push_back(node);
        out = OJson::object();
        for (const auto& kv : node) {
          if (kv.first.Type() != YAML::NodeType::Scalar) {
            throw InputError(mark_text(source_, kv.first.Mark()) + ": " + (path.empty() ? std::string("document") : path) +
                             ": mapping keys must be plain text");
          }
          const std::string key = kv.first.Scalar();
          check_text(key, kv.first.Mark());
          const std::string child = path.empty() ? key : path + "." + key;
          if (out.contains(key)) {
            throw InputError(mark_text(source_, kv.first.Mark()) + ": " + child + ": duplicate key \"" + key + "\"");
          }
          OJson v;
          convert(kv.second, child, v);
          marks_[child] = kv.first.Mark();  // messages about a key point at the key
          out[key] = std::move(v);
        }
        ancestors_.pop_back();
        break;
      }
      case YAML::NodeType::Sequence: {
        ancestors_.push_back(node);
        out = OJson::array();
        std::size_t i = 0;
        for (const auto& item : node) {
          OJson v;
          convert(item, path + "[" + std::to_string(i) + "]", v);
          out.push_back(std::move(v));
          ++i;
        }
        ancestors_.pop_back();
        break;
      }
      case YAML::NodeType::Scalar:
        out = scalar(node, path);
        break;
      default:
        out = nullptr;
    }
  }

 private:
  void check_text(const std::string& text, const YAML::Mark& mark) const {
    std::size_t bad = 0;
    if (!valid_utf8(text, &bad)) {
      throw InputError(mark_text(source_, mark) + ": text is not valid UTF-8 (byte " + std::to_string(bad) + " of \"" +
                       printable_text(text, 60) + "\")");
    }
  }

  OJson scalar(const YAML::Node& node, const std::string& path) const {
    const std::string& s = node.Scalar();
    check_text(s, node.Mark());
    if (node.Tag() == "!") return s;  // quoted: always a string
    if (s == "true") return true;
    if (s == "false") return false;
    if (s == "null" || s == "~" || s.empty()) return nullptr;
    const NumberKind kind = number_kind(s);
    if (kind == NumberKind::kNone) return s;
    const std::string where = mark_text(source_, node.Mark()) + ": " + (path.empty() ? std::string("document") : path);
    errno = 0;
    if (kind == NumberKind::kInteger) {
      char* end = nullptr;
      const long long v = std::strtoll(s.c_str(), &end, 10);
      if (errno == ERANGE) {
        throw InputError(where + ": integer " + printable_text(s, 40) + " is out of range (at most 19 digits)");
      }
      return v;
    }
    const double v = std::strtod(s.c_str(), nullptr);
    if (!std::isfinite(v) || (errno == ERANGE && std::abs(v) > 1.0)) {
      throw InputError(where + ": number " + printable_text(s, 40) + " is out of range (beyond +-1.8e308)");
    }
    return v;
  }

  std::string source_;
  std::map<std::string, YAML::Mark>& marks_;
  double max_depth_;
  double max_nodes_;
  double nodes_ = 0;
  std::vector<YAML::Node> ancestors_;
};

/// A label made of letters, digits, _ . - only.
bool is_label(const std::string& s) {
  if (s.empty()) return false;
  for (const char c : s) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '.' && c != '-') return false;
  }
  return true;
}

class Checker {
 public:
  Checker(std::string source, const std::map<std::string, YAML::Mark>& marks) : source_(std::move(source)), marks_(marks) {}

  [[noreturn]] void fail(const std::string& path, const std::string& reason) const {
    std::string where = source_;
    // The closest known mark: the path itself or its nearest ancestor.
    std::string p = path;
    while (true) {
      auto it = marks_.find(p);
      if (it != marks_.end() && it->second.line >= 0) {
        where += ":" + std::to_string(it->second.line + 1) + ":" + std::to_string(it->second.column + 1);
        break;
      }
      const auto cut = p.find_last_of(".[");
      if (cut == std::string::npos || p.empty()) break;
      p = p.substr(0, cut);
    }
    throw InputError(where + ": " + (path.empty() ? std::string("scenario") : path) + ": " + reason);
  }

  void only_keys(const OJson& obj, const std::string& path, const std::vector<std::string>& allowed) const {
    if (!obj.is_object()) fail(path, std::string("must be a mapping, got ") + obj.type_name());
    for (auto it = obj.begin(); it != obj.end(); ++it) {
      if (std::find(allowed.begin(), allowed.end(), it.key()) == allowed.end()) {
        std::string list;
        for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
        fail(join(path, it.key()), "unknown key \"" + it.key() + "\" (expected one of: " + list + ")");
      }
    }
  }

  static std::string join(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }

  std::string string_in(const OJson& obj, const std::string& path, const char* key, const std::string& fallback,
                        const std::vector<std::string>& choices = {}) const {
    if (!obj.contains(key)) return fallback;
    const OJson& v = obj.at(key);
    const std::string p = join(path, key);
    if (!v.is_string()) fail(p, std::string("must be a string, got ") + json_excerpt(v));
    const std::string s = v.get<std::string>();
    if (!choices.empty() && std::find(choices.begin(), choices.end(), s) == choices.end()) {
      std::string list;
      for (const auto& c : choices) list += (list.empty() ? "" : ", ") + c;
      fail(p, "must be one of " + list + ", got \"" + s + "\"");
    }
    return s;
  }

  double number_in(const OJson& obj, const std::string& path, const char* key, double fallback, double lo, double hi) const {
    if (!obj.contains(key)) return fallback;
    const OJson& v = obj.at(key);
    const std::string p = join(path, key);
    if (!v.is_number()) fail(p, std::string("must be a number, got ") + json_excerpt(v));
    const double x = v.get<double>();
    if (!std::isfinite(x) || x < lo || x > hi) {
      std::ostringstream os;
      os << "must be in [" << lo << ", " << hi << "], got " << json_excerpt(v);
      fail(p, os.str());
    }
    return x;
  }

  long long integer_in(const OJson& obj, const std::string& path, const char* key, long long fallback, long long lo,
                       long long hi) const {
    if (!obj.contains(key)) return fallback;
    const OJson& v = obj.at(key);
    const std::string p = join(path, key);
    if (!v.is_number_integer()) fail(p, std::string("must be an integer, got ") + json_excerpt(v));
    const long long x = v.get<long long>();
    if (x < lo || x > hi) fail(p, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + json_excerpt(v));
    return x;
  }

  bool bool_in(const OJson& obj, const std::string& path, const char* key, bool fallback) const {
    if (!obj.contains(key)) return fallback;
    const OJson& v = obj.at(key);
    if (!v.is_boolean()) fail(join(path, key), std::string("must be true or false, got ") + json_excerpt(v));
    return v.get<bool>();
  }

 private:
  std::string source_;
  const std::map<std::string, YAML::Mark>& marks_;
};



const std::vector<std::string> kArchetypes = {"apartment", "office", "campus", "angled"};

/// Absolute path of a file named in a scenario: as is when absolute, else relative to the
/// scenario's folder, then to the source tree root; empty when not found.
std::string find_file(const std::string& file, const std::string& base_dir, const std::string& source_root) {
  const fs::path p(file);
  const std::vector<fs::path> candidates =
      p.is_absolute() ? std::vector<fs::path>{p} : std::vector<fs::path>{fs::path(base_dir) / p, fs::path(source_root) / p};
  for (const auto& c : candidates) {
    if (fs::is_regular_file(c)) return fs::weakly_canonical(c).string();
  }
  return {};
}

/// True if the building's points can be placed by room kind: generated (rooms built in), a rooms
/// file, or a plan file with a non-empty "rooms" array.
bool has_room_labels(const BuildingSpec& b) {
  if (!b.archetype.empty() || !b.rooms_file.empty()) return true;
  const nlohmann::json j = read_json_file(b.file);  // depth- and size-limited; a broken plan is reported here
  return j.is_object() && j.contains("rooms") && j["rooms"].is_array() && !j["rooms"].empty();
}

std::vector<BuildingSpec> parse_buildings(const OJson& root, const Checker& chk, const std::string& base_dir,
                                          const std::string& source_root) {
  if (!root.contains("buildings")) chk.fail("buildings", "missing required key");
  const OJson& list = root.at("buildings");
  if (!list.is_array() || list.empty()) chk.fail("buildings", "must be a non-empty list of plan files or generator specs");
  std::vector<BuildingSpec> out;
  std::set<std::string> labels;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string path = "buildings[" + std::to_string(i) + "]";
    BuildingSpec b;
    std::string file;
    if (list[i].is_string()) {
      file = list[i].get<std::string>();
    } else {
      chk.only_keys(list[i], path, {"file", "generate", "seed", "label", "rooms"});
      if (list[i].contains("file") == list[i].contains("generate")) chk.fail(path, "give exactly one of \"file\" or \"generate\"");
      file = chk.string_in(list[i], path, "file", "");
      b.archetype = chk.string_in(list[i], path, "generate", "", kArchetypes);
      b.seed = static_cast<std::uint64_t>(chk.integer_in(list[i], path, "seed", 1, 0, (1LL << 53)));
      b.label = chk.string_in(list[i], path, "label", "");
      if (b.archetype.empty() && list[i].contains("seed")) chk.fail(path + ".seed", "only generated buildings take a seed");
      const std::string rooms = chk.string_in(list[i], path, "rooms", "");
      if (!rooms.empty()) {
        if (!b.archetype.empty()) chk.fail(path + ".rooms", "generated buildings carry their rooms themselves");
        b.rooms_file = find_file(rooms, base_dir, source_root);
        if (b.rooms_file.empty()) {
          chk.fail(path + ".rooms", "rooms file \"" + rooms + "\" not found (looked in " + base_dir + " and " + source_root + ")");
        }
      }
    }
    if (!file.empty()) {
      b.file = find_file(file, base_dir, source_root);
      if (b.file.empty()) chk.fail(path, "plan file \"" + file + "\" not found (looked in " + base_dir + " and " + source_root + ")");
      if (b.label.empty()) b.label = fs::path(b.file).stem().string();
    } else if (b.label.empty()) {
      b.label = b.archetype + "_" + std::to_string(b.seed);
    }
    if (!is_label(b.label)) chk.fail(path, "label \"" + b.label + "\" may only contain letters, digits, _ . -");
    if (!labels.insert(b.label).second) chk.fail(path, "duplicate building label \"" + b.label + "\"");
    out.push_back(b);
  }
  return out;
}

const std::vector<std::string> kObservationKeys = {"source", "max_range_m", "doors_closed", "rays", "sensor",
                                                   "sensor_params", "setting", "path", "scale_alignment",
                                                   "extractor", "mask_glass", "observe_params", "seed"};

/// Runs `fn`; a ParameterError (a stage refusing one of its parameters) becomes a failure at the
/// scenario key `prefix + e.key()`, with the file, line and column where it was written.
template <class F>
void at_key(const Checker& chk, const std::string& prefix, F&& fn) {
  try {
    fn();
  } catch (const ParameterError& e) {
    chk.fail(e.key().empty() ? prefix : Checker::join(prefix, e.key()), e.what());
  } catch (const InputError& e) {
    chk.fail(prefix, e.what());
  }
}

/// Parses an observation mapping (user form) into typed stage parameters. `resolved` receives the
/// user form with every default filled in (written next to results; re-parsed by merges).
ObservationSpec parse_observation(const OJson& obj, const Checker& chk, const std::string& path,
                                  const SharedParams& shared, OJson* resolved) {
  chk.only_keys(obj, path, kObservationKeys);
  ObservationSpec o;
  const std::string source = chk.string_in(obj, path, "source", "perfect", {"perfect", "scan"});
  o.source = source == "scan" ? ObservationSource::kScan : ObservationSource::kPerfect;
  // Perfect observer: shared range and blocking, then the explicit keys.
  o.perfect.apply_shared(shared);
  o.perfect.max_range_m = chk.number_in(obj, path, "max_range_m", o.perfect.max_range_m, 0.5, 1000.0);
  o.perfect.blocking.open_doors_block = chk.bool_in(obj, path, "doors_closed", o.perfect.blocking.open_doors_block);
  o.perfect.num_rays = static_cast<int>(chk.integer_in(obj, path, "rays", o.perfect.num_rays, 4, 3600));
  // Scan: sensor preset, its overrides, the setting.
  const std::string sensor = chk.string_in(obj, path, "sensor", "mono", scan_preset_names());
  const OJson sensor_params = obj.contains("sensor_params") ? obj.at("sensor_params") : OJson::object();
  if (!sensor_params.is_object()) chk.fail(Checker::join(path, "sensor_params"), "must be a mapping");
  const std::string setting = chk.string_in(obj, path, "setting", "full", {"full", "partial", "single"});
  at_key(chk, Checker::join(path, "sensor_params"), [&] {
    o.scan = scan_preset(sensor);
    apply_scan_overrides(o.scan, sensor_params, "sensor_params");
    parse_scan_setting(setting, o.scan.setting);
    validate_scan_params(o.scan);
  });
  // Observation module: path, scale alignment, extractor, glass masking, then its overrides.
  const std::string obs_path = chk.string_in(obj, path, "path", "mono", {"mono", "lidar"});
  const std::string scale = chk.string_in(obj, path, "scale_alignment", "full", {"full", "ground", "none"});
  const std::string extractor =
      chk.string_in(obj, path, "extractor", to_string(LidarPathParams{}.extractor), {"pcl", "voxelplane"});
  const bool mask_glass = chk.bool_in(obj, path, "mask_glass", false);
  const OJson observe_params = obj.contains("observe_params") ? obj.at("observe_params") : OJson::object();
  if (!observe_params.is_object()) chk.fail(Checker::join(path, "observe_params"), "must be a mapping");
  o.observe.path = parse_observation_path(obs_path);
  o.observe.scale.mode = parse_scale_alignment(scale);
  o.observe.back_projection.mask_glass = mask_glass;
  o.observe.lidar.back_projection.mask_glass = mask_glass;
  o.observe.lidar.extractor = parse_plane_extractor(extractor);
  at_key(chk, Checker::join(path, "observe_params"), [&] { apply_overrides(o.observe, observe_params); });
  o.seed = static_cast<std::uint64_t>(chk.integer_in(obj, path, "seed", static_cast<long long>(o.seed), 0, (1LL << 53)));
  if (resolved) {
    OJson& j = *resolved;
    j = OJson::object();
    j["source"] = source;
    j["max_range_m"] = o.perfect.max_range_m;
    j["doors_closed"] = o.perfect.blocking.open_doors_block;
    j["rays"] = o.perfect.num_rays;
    j["sensor"] = sensor;
    j["sensor_params"] = sensor_params;
    j["setting"] = setting;
    j["path"] = obs_path;
    j["scale_alignment"] = scale;
    j["extractor"] = extractor;
    j["mask_glass"] = mask_glass;
    j["observe_params"] = observe_params;
    j["seed"] = o.seed;
  }
  return o;
}

/// Every parameter of the stages a cell runs (written next to results).
OJson stage_parameters(const ObservationSpec& o) {
  OJson j;
  if (o.source == ObservationSource::kPerfect) {
    j["perfect_observer"] = o.perfect.to_json();
  } else {
    j["sensor"] = scan_params_to_json(o.scan);
    j["observation_module"] = to_json(o.observe);
  }
  return j;
}

std::vector<MatcherSpec> parse_matchers(const OJson& obj, const Checker& chk, const SharedParams& shared) {
  if (!obj.is_object() || obj.empty()) chk.fail("matchers", "must be a non-empty mapping label -> {matcher: NAME, ...parameters}");
  std::vector<MatcherSpec> out;
  for (auto it = obj.begin(); it != obj.end(); ++it) {
    const std::string path = "matchers." + it.key();
    if (!is_label(it.key())) chk.fail(path, "label may only contain letters, digits, _ . -");
    if (!it.value().is_object()) chk.fail(path, "must be a mapping {matcher: NAME, ...parameters}");
    MatcherSpec m;
    m.label = it.key();
    if (!it.value().contains("matcher")) chk.fail(path, "missing required key \"matcher\"");
    const std::string name = chk.string_in(it.value(), path, "matcher", "");
    Json overrides = Json::object();
    for (auto p = it.value().begin(); p != it.value().end(); ++p)
      if (p.key() != "matcher") overrides[p.key()] = p.value();
    try {
      m.config = make_matcher_config(name, overrides, shared);
    } catch (const ParameterError& e) {
      chk.fail(Checker::join(path, e.key()), e.what());
    } catch (const InputError& e) {
      chk.fail(Checker::join(path, "matcher"), e.what());
    }
    out.push_back(std::move(m));
  }
  return out;
}

const std::vector<std::string> kSequentialKeys = {"walk", "odometry", "schedule", "trackers"};

/// Sequential blocks of a scenario or cell tree (nullopt when it has none). Trackers name a
/// matcher label of `matchers` for their posteriors.
std::optional<SequentialSpec> parse_sequential(const OJson& tree, const Checker& chk, const std::vector<MatcherSpec>& matchers) {
  bool any = false;
  for (const std::string& k : kSequentialKeys) any = any || tree.contains(k);
  if (!any) return std::nullopt;
  SequentialSpec q;
  if (tree.contains("walk")) at_key(chk, "walk", [&] { q.walk.apply_overrides(tree.at("walk")); });
  if (tree.contains("odometry")) at_key(chk, "odometry", [&] { q.odometry.apply_overrides(tree.at("odometry")); });
  if (tree.contains("schedule")) {
    const OJson& s = tree.at("schedule");
    chk.only_keys(s, "schedule", {"initial", "every_steps", "every_m"});
    q.schedule.initial = chk.bool_in(s, "schedule", "initial", q.schedule.initial);
    q.schedule.every_steps = static_cast<int>(chk.integer_in(s, "schedule", "every_steps", q.schedule.every_steps, 0, 1000000));
    q.schedule.every_m = chk.number_in(s, "schedule", "every_m", q.schedule.every_m, 0.0, 1e6);
  }
  if (!q.schedule.initial) chk.fail("schedule.initial", "sequential scenarios start from an initial observation (PALMS: scan, then walk)");
  if (!tree.contains("trackers")) chk.fail("trackers", "a sequential scenario needs trackers: label -> {tracker: pf|hist, matcher: LABEL, ...}");
  const OJson& ts = tree.at("trackers");
  if (!ts.is_object() || ts.empty()) chk.fail("trackers", "must be a non-empty mapping label -> {tracker: NAME, matcher: LABEL, ...parameters}");
  for (auto it = ts.begin(); it != ts.end(); ++it) {
    const std::string path = "trackers." + it.key();
    if (!is_label(it.key())) chk.fail(path, "label may only contain letters, digits, _ . -");
    if (!it.value().is_object()) chk.fail(path, "must be a mapping {tracker: NAME, matcher: LABEL, ...parameters}");
    TrackerSpec t;
    t.label = it.key();
    if (!it.value().contains("tracker")) chk.fail(path, "missing required key \"tracker\"");
    t.tracker = chk.string_in(it.value(), path, "tracker", "");
    t.matcher = chk.string_in(it.value(), path, "matcher", matchers.empty() ? "" : matchers.front().label);
    bool known = false;
    for (const MatcherSpec& m : matchers) known = known || m.label == t.matcher;
    if (!known) chk.fail(Checker::join(path, "matcher"), "no matcher labelled \"" + t.matcher + "\" in matchers");
    Json overrides = Json::object();
    for (auto p = it.value().begin(); p != it.value().end(); ++p)
      if (p.key() != "tracker" && p.key() != "matcher") overrides[p.key()] = p.value();
    // The walk's odometry error flows to every tracker (what a walk folder states for its
    // odometry): the cell's odometry model's, with the tracker's own `odometry` keys on top.
    overrides = with_odometry(overrides, odometry_uncertainty(q.odometry));
    try {
      t.parameters = resolve_tracker_parameters(t.tracker, overrides);
    } catch (const ParameterError& e) {
      chk.fail(Checker::join(path, e.key()), e.what());
    } catch (const InputError& e) {
      chk.fail(Checker::join(path, "tracker"), e.what());
    }
    q.trackers.push_back(std::move(t));
  }
  return q;
}

OJson sequential_to_json(const SequentialSpec& q) {
  OJson j;
  j["walk"] = q.walk.to_json();
  j["odometry"] = q.odometry.to_json();
  j["schedule"] = {{"initial", q.schedule.initial}, {"every_steps", q.schedule.every_steps}, {"every_m", q.schedule.every_m}};
  OJson ts = OJson::object();
  for (const TrackerSpec& t : q.trackers) {
    OJson one;
    one["tracker"] = t.tracker;
    one["matcher"] = t.matcher;
    for (auto it = t.parameters.begin(); it != t.parameters.end(); ++it) one[it.key()] = it.value();
    ts[t.label] = one;
  }
  j["trackers"] = ts;
  return j;
}

SharedParams parse_shared(const OJson& root, const Checker& chk) {
  SharedParams shared;
  if (root.contains("shared")) at_key(chk, "shared", [&] { apply_overrides(shared, root.at("shared"), "shared"); });
  return shared;
}

/// Sets a dotted key ("observation.setting", "matchers.kernel.alpha") in a JSON tree.
void set_dotted(OJson& root, const std::string& key, const OJson& value) {
  OJson* node = &root;
  std::size_t start = 0;
  while (true) {
    const auto dot = key.find('.', start);
    const std::string part = key.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (dot == std::string::npos) {
      (*node)[part] = value;
      return;
    }
    node = &(*node)[part];
    start = dot + 1;
  }
}

struct Axis {
  std::vector<std::string> keys;
  std::vector<std::vector<OJson>> values;  // values[v][k]: value v of key k
};

std::vector<Axis> parse_sweep(const OJson& sweep, const Checker& chk, const OJson& matchers) {
  std::vector<Axis> axes;
  auto check_key = [&](const std::string& key, const std::string& path) {
    if (key.rfind("observation.", 0) == 0) {
      const std::string sub = key.substr(12);
      if (std::find(kObservationKeys.begin(), kObservationKeys.end(), sub) == kObservationKeys.end() &&
          sub.rfind("sensor_params.", 0) != 0 && sub.rfind("observe_params.", 0) != 0)
        chk.fail(path, "cannot sweep \"" + key + "\": unknown observation key");
      return;
    }
    if (key.rfind("matchers.", 0) == 0) {
      const std::string rest = key.substr(9);
      const auto dot = rest.find('.');
      if (dot == std::string::npos) chk.fail(path, "sweep key \"" + key + "\" must name a matcher parameter: matchers.LABEL.PARAM");
      const std::string label = rest.substr(0, dot);
      if (!matchers.contains(label)) chk.fail(path, "sweep key \"" + key + "\": no matcher labelled \"" + label + "\"");
      if (rest.substr(dot + 1) == "matcher") chk.fail(path, "sweep key \"" + key + "\": sweep matcher parameters, not the matcher name");
      return;
    }
    for (const std::string& k : kSequentialKeys) {
      if (key.rfind(k + ".", 0) == 0) return;  // checked when the cells are parsed
    }
    chk.fail(path, "cannot sweep \"" + key + "\": sweep keys start with observation., matchers., walk., odometry., schedule. or trackers.");
  };
  auto add_axis = [&](const OJson& group, const std::string& path) {
    if (!group.is_object() || group.empty()) chk.fail(path, "a sweep axis is a mapping key -> list of values");
    Axis axis;
    std::size_t n = 0;
    for (auto it = group.begin(); it != group.end(); ++it) {
      const std::string p = path.empty() ? it.key() : path + "." + it.key();
      check_key(it.key(), p);
      if (!it.value().is_array() || it.value().empty()) chk.fail(p, "must be a non-empty list of values");
      if (axis.keys.empty()) n = it.value().size();
      else if (it.value().size() != n)
        chk.fail(p, "zipped sweep keys must have the same number of values (" + std::to_string(n) + ")");
      axis.keys.push_back(it.key());
    }
    axis.values.assign(n, {});
    for (std::size_t v = 0; v < n; ++v)
      for (const auto& k : axis.keys) axis.values[v].push_back(group.at(k)[v]);
    axes.push_back(std::move(axis));
  };
  if (sweep.is_object()) {
    // Map form: every key is its own axis.
    for (auto it = sweep.begin(); it != sweep.end(); ++it) {
      OJson single;
      single[it.key()] = it.value();
      add_axis(single, "sweep");
    }
  } else if (sweep.is_array()) {
    // List form: each item is an axis; several keys in one item are zipped.
    for (std::size_t i = 0; i < sweep.size(); ++i) add_axis(sweep[i], "sweep[" + std::to_string(i) + "]");
  } else {
    chk.fail("sweep", "must be a mapping (independent axes) or a list of mappings (zipped keys per axis)");
  }
  std::set<std::string> seen;
  for (const auto& a : axes)
    for (const auto& k : a.keys)
      if (!seen.insert(k).second) chk.fail("sweep", "key \"" + k + "\" appears in two axes");
  return axes;
}

}  // namespace

Scenario parse_scenario(const std::string& yaml_text, const std::string& source, const std::string& base_dir,
                        const std::string& source_root) {
  YAML::Node doc;
  try {
    // Every document is read: a second one is refused rather than silently ignored.
    const std::vector<YAML::Node> docs = YAML::LoadAll(yaml_text);
    if (docs.size() > 1) {
      throw InputError(mark_text(source, docs[1].Mark()) + ": a scenario file holds one YAML document, this one has " +
                       std::to_string(docs.size()));
    }
    if (!docs.empty()) doc = docs.front();
  } catch (const YAML::Exception& e) {
    throw InputError(source + ":" + std::to_string(e.mark.line + 1) + ":" + std::to_string(e.mark.column + 1) +
                     ": malformed YAML: " + printable_text(e.msg));
  }
  Located loc;
  YamlConverter(source, loc.marks).convert(doc, "", loc.value);
  const Checker chk(source, loc.marks);
  const OJson& root = loc.value;
  if (!root.is_object()) chk.fail("", "top level must be a mapping");
  chk.only_keys(root, "", {"name", "description", "buildings", "sampling", "shared", "observation", "matchers",
                           "walk", "odometry", "schedule", "trackers", "scoring", "output", "sweep", "paper"});

  Scenario s;
  s.source_file = source;
  s.name = chk.string_in(root, "", "name", fs::path(source).stem().string());
  s.description = chk.string_in(root, "", "description", "");
  s.buildings = parse_buildings(root, chk, base_dir, source_root);

  if (root.contains("sampling")) {
    const OJson& o = root.at("sampling");
    chk.only_keys(o, "sampling", {"count", "seed", "clearance_m", "random_yaw", "region", "region_kinds"});
    s.sampling.count = static_cast<int>(chk.integer_in(o, "sampling", "count", s.sampling.count, 1, 1000000));
    s.sampling.seed = static_cast<std::uint64_t>(chk.integer_in(o, "sampling", "seed", 1, 0, (1LL << 53)));
    s.sampling.clearance_m = chk.number_in(o, "sampling", "clearance_m", s.sampling.clearance_m, 0.0, 10.0);
    s.sampling.random_yaw = chk.bool_in(o, "sampling", "random_yaw", s.sampling.random_yaw);
    if (o.contains("region_kinds")) {
      const OJson& k = o.at("region_kinds");
      if (!k.is_array() || k.empty()) chk.fail("sampling.region_kinds", "must be a non-empty list of room kinds");
      for (std::size_t i = 0; i < k.size(); ++i) {
        if (!k[i].is_string() || k[i].get<std::string>().empty()) {
          chk.fail("sampling.region_kinds[" + std::to_string(i) + "]", "must be a room kind (a string)");
        }
        s.sampling.region_kinds.push_back(k[i].get<std::string>());
      }
    }
    s.sampling.region = chk.string_in(o, "sampling", "region", s.sampling.region_kinds.empty() ? "transitional" : "kinds",
                                      {"transitional", "transitional_or_uniform", "uniform", "kinds"});
    if (s.sampling.region == "kinds" && s.sampling.region_kinds.empty()) {
      chk.fail("sampling.region", "\"kinds\" needs sampling.region_kinds");
    }
    if (s.sampling.region != "kinds" && !s.sampling.region_kinds.empty()) {
      chk.fail("sampling.region_kinds", "only with sampling.region: kinds");
    }
  }
  for (BuildingSpec& b : s.buildings) {
    if (s.sampling.region != "transitional" && s.sampling.region != "transitional_or_uniform") b.sampling_region = s.sampling.region;
    else b.sampling_region = has_room_labels(b) ? s.sampling.region : "uniform_unlabelled";
  }
  if (root.contains("scoring")) {
    const OJson& o = root.at("scoring");
    chk.only_keys(o, "scoring", {"recall_thresholds_m", "combined_threshold_m", "combined_threshold_deg", "top_k",
                                 "bootstrap_resamples", "bootstrap_seed"});
    if (o.contains("recall_thresholds_m")) {
      const OJson& t = o.at("recall_thresholds_m");
      if (!t.is_array() || t.empty()) chk.fail("scoring.recall_thresholds_m", "must be a non-empty list of metres");
      s.scoring.recall_thresholds_m.clear();
      for (std::size_t i = 0; i < t.size(); ++i) {
        if (!t[i].is_number() || !(t[i].get<double>() > 0.0 && t[i].get<double>() <= 1e3))
          chk.fail("scoring.recall_thresholds_m[" + std::to_string(i) + "]", "must be a number in (0, 1000] metres");
        s.scoring.recall_thresholds_m.push_back(t[i].get<double>());
      }
    }
    s.scoring.combined_threshold_m = chk.number_in(o, "scoring", "combined_threshold_m", s.scoring.combined_threshold_m, 1e-3, 1e3);
    s.scoring.combined_threshold_deg = chk.number_in(o, "scoring", "combined_threshold_deg", s.scoring.combined_threshold_deg, 0.0, 180.0);
    s.scoring.top_k = static_cast<int>(chk.integer_in(o, "scoring", "top_k", s.scoring.top_k, 1, 100));
    s.scoring.bootstrap_resamples = static_cast<int>(chk.integer_in(o, "scoring", "bootstrap_resamples", s.scoring.bootstrap_resamples, 0, 100000));
    s.scoring.bootstrap_seed = static_cast<std::uint64_t>(chk.integer_in(o, "scoring", "bootstrap_seed", static_cast<long long>(s.scoring.bootstrap_seed), 0, (1LL << 53)));
  }
  if (root.contains("output")) {
    const OJson& o = root.at("output");
    chk.only_keys(o, "output", {"heatmaps"});
    s.output.heatmaps = static_cast<int>(chk.integer_in(o, "output", "heatmaps", s.output.heatmaps, 0, 1000));
  }

  if (root.contains("paper")) {
    const OJson& list = root.at("paper");
    if (!list.is_array()) chk.fail("paper", "must be a list of {label, source, cell, values}");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string path = "paper[" + std::to_string(i) + "]";
      chk.only_keys(list[i], path, {"label", "source", "cell", "values"});
      PaperReference ref;
      ref.label = chk.string_in(list[i], path, "label", "");
      if (ref.label.empty()) chk.fail(path, "missing required key \"label\"");
      ref.source = chk.string_in(list[i], path, "source", "");
      ref.cell = chk.string_in(list[i], path, "cell", "");
      if (!list[i].contains("values") || !list[i].at("values").is_object())
        chk.fail(path, "needs \"values\": a mapping metric -> number");
      for (auto it = list[i].at("values").begin(); it != list[i].at("values").end(); ++it) {
        if (!it.value().is_number()) chk.fail(path + ".values." + it.key(), "must be a number");
        ref.values[it.key()] = it.value().get<double>();
      }
      s.paper.push_back(std::move(ref));
    }
  }

  s.shared = parse_shared(root, chk);
  const OJson base_observation = root.contains("observation") ? root.at("observation") : OJson::object();
  (void)parse_observation(base_observation, chk, "observation", s.shared, nullptr);  // validates the base
  if (!root.contains("matchers")) chk.fail("matchers", "missing required key");
  const OJson base_matchers = root.at("matchers");
  (void)parse_sequential(root, chk, parse_matchers(base_matchers, chk, s.shared));

  std::vector<Axis> axes;
  if (root.contains("sweep")) axes = parse_sweep(root.at("sweep"), chk, base_matchers);
  for (const auto& a : axes) {
    for (const auto& k : a.keys) s.sweep_keys.push_back(k);
    s.sweep_axes.push_back(a.keys);
  }

  // Cartesian product over axes, first axis slowest; its size is checked before any cell exists
  // (as a double: 2^64 cells must not wrap around to 0).
  std::vector<double> axis_sizes;
  for (const auto& a : axes) axis_sizes.push_back(static_cast<double>(a.values.size()));
  at_key(chk, "sweep", [&] { check_limit("max_sweep_cells", saturating_product(axis_sizes), "sweep cells", "cells"); });
  std::size_t total = 1;
  for (const auto& a : axes) total *= a.values.size();
  at_key(chk, root.contains("sampling") ? "sampling.count" : "buildings", [&] {
    check_limit("max_units",
                saturating_product({static_cast<double>(total), static_cast<double>(s.buildings.size()),
                                    static_cast<double>(s.sampling.count)}),
                "work units (" + std::to_string(total) + " sweep cells x " + std::to_string(s.buildings.size()) +
                    " buildings x " + std::to_string(s.sampling.count) + " points)",
                "units");
  });
  std::vector<OJson> resolved_observations;
  for (std::size_t c = 0; c < total; ++c) {
    OJson tree;
    tree["observation"] = base_observation;
    tree["matchers"] = base_matchers;
    for (const std::string& k : kSequentialKeys)
      if (root.contains(k)) tree[k] = root.at(k);
    CellSpec cell;
    cell.index = static_cast<int>(c);
    char id[24];
    std::snprintf(id, sizeof id, "c%03zu", c);
    cell.id = id;
    cell.axes = OJson::object();
    std::size_t rest = c;
    std::vector<std::size_t> choice(axes.size());
    for (std::size_t a = axes.size(); a-- > 0;) {
      choice[a] = rest % axes[a].values.size();
      rest /= axes[a].values.size();
    }
    for (std::size_t a = 0; a < axes.size(); ++a)
      for (std::size_t k = 0; k < axes[a].keys.size(); ++k) {
        set_dotted(tree, axes[a].keys[k], axes[a].values[choice[a]][k]);
        cell.axes[axes[a].keys[k]] = axes[a].values[choice[a]][k];
      }
    const std::string where = axes.empty() ? "" : " (sweep cell " + cell.id + ")";
    try {
      OJson resolved_observation;
      cell.observation = parse_observation(tree["observation"], chk, "observation", s.shared, &resolved_observation);
      resolved_observations.push_back(std::move(resolved_observation));
      cell.matchers = parse_matchers(tree["matchers"], chk, s.shared);
      cell.sequential = parse_sequential(tree, chk, cell.matchers);
    } catch (const InputError& e) {
      throw InputError(std::string(e.what()) + where);
    }
    s.cells.push_back(std::move(cell));
  }

  // The resolved configuration: every default filled in.
  OJson& r = s.resolved;
  r["name"] = s.name;
  r["description"] = s.description;
  r["buildings"] = OJson::array();
  for (const auto& b : s.buildings) {
    OJson j;
    j["label"] = b.label;
    if (!b.file.empty()) j["file"] = b.file;
    else {
      j["generate"] = b.archetype;
      j["seed"] = b.seed;
    }
    if (!b.rooms_file.empty()) j["rooms"] = b.rooms_file;
    j["sampling_region"] = b.sampling_region;
    r["buildings"].push_back(j);
  }
  r["sampling"] = {{"count", s.sampling.count}, {"seed", s.sampling.seed}, {"clearance_m", s.sampling.clearance_m},
                   {"random_yaw", s.sampling.random_yaw}, {"region", s.sampling.region}};
  if (!s.sampling.region_kinds.empty()) r["sampling"]["region_kinds"] = s.sampling.region_kinds;
  r["scoring"] = {{"recall_thresholds_m", s.scoring.recall_thresholds_m},
                  {"combined_threshold_m", s.scoring.combined_threshold_m},
                  {"combined_threshold_deg", s.scoring.combined_threshold_deg},
                  {"top_k", s.scoring.top_k},
                  {"bootstrap_resamples", s.scoring.bootstrap_resamples},
                  {"bootstrap_seed", s.scoring.bootstrap_seed}};
  r["output"] = {{"heatmaps", s.output.heatmaps}};
  r["shared"] = to_json(s.shared);
  if (!s.paper.empty()) {
    r["paper"] = OJson::array();
    for (const auto& p : s.paper) {
      OJson j;
      j["label"] = p.label;
      j["source"] = p.source;
      j["cell"] = p.cell;
      j["values"] = p.values;
      r["paper"].push_back(j);
    }
  }
  r["sweep_keys"] = s.sweep_keys;
  r["sweep_axes"] = s.sweep_axes;
  r["cells"] = OJson::array();
  for (std::size_t ci = 0; ci < s.cells.size(); ++ci) {
    const CellSpec& c = s.cells[ci];
    OJson j;
    j["id"] = c.id;
    j["axes"] = c.axes;
    j["observation"] = resolved_observations[ci];
    OJson m = OJson::object();
    for (const auto& spec : c.matchers) {
      OJson one;
      one["matcher"] = spec.config->name();
      const OJson params = spec.config->parameters();
      for (auto it = params.begin(); it != params.end(); ++it) one[it.key()] = it.value();
      m[spec.label] = one;
    }
    j["matchers"] = m;
    j["parameters"] = stage_parameters(c.observation);
    if (c.sequential) {
      const OJson q = sequential_to_json(*c.sequential);
      for (auto it = q.begin(); it != q.end(); ++it) j[it.key()] = it.value();
    }
    r["cells"].push_back(j);
  }
  s.hash = hex64(fnv1a64(Json(r).dump()));  // canonical (sorted-key) form
  return s;
}

Scenario scenario_from_resolved(const Json& resolved, const std::string& source) {
  const std::map<std::string, YAML::Mark> no_marks;
  const Checker chk(source, no_marks);
  try {
    Scenario s;
    s.source_file = source;
    s.name = resolved.at("name").get<std::string>();
    s.description = resolved.at("description").get<std::string>();
    for (const Json& b : resolved.at("buildings")) {
      BuildingSpec spec;
      spec.label = b.at("label").get<std::string>();
      if (b.contains("file")) spec.file = b.at("file").get<std::string>();
      else {
        spec.archetype = b.at("generate").get<std::string>();
        spec.seed = b.at("seed").get<std::uint64_t>();
      }
      if (b.contains("rooms")) spec.rooms_file = b.at("rooms").get<std::string>();
      spec.sampling_region = b.value("sampling_region", std::string("uniform"));
      s.buildings.push_back(spec);
    }
    const Json& sm = resolved.at("sampling");
    s.sampling.count = sm.at("count").get<int>();
    s.sampling.seed = sm.at("seed").get<std::uint64_t>();
    s.sampling.clearance_m = sm.at("clearance_m").get<double>();
    s.sampling.random_yaw = sm.at("random_yaw").get<bool>();
    if (sm.contains("region_kinds")) s.sampling.region_kinds = sm.at("region_kinds").get<std::vector<std::string>>();
    s.sampling.region = sm.value("region", std::string(s.sampling.region_kinds.empty() ? "uniform" : "kinds"));
    const Json& sc = resolved.at("scoring");
    s.scoring.recall_thresholds_m = sc.at("recall_thresholds_m").get<std::vector<double>>();
    s.scoring.combined_threshold_m = sc.at("combined_threshold_m").get<double>();
    s.scoring.combined_threshold_deg = sc.at("combined_threshold_deg").get<double>();
    s.scoring.top_k = sc.at("top_k").get<int>();
    s.scoring.bootstrap_resamples = sc.at("bootstrap_resamples").get<int>();
    s.scoring.bootstrap_seed = sc.at("bootstrap_seed").get<std::uint64_t>();
    s.output.heatmaps = resolved.at("output").at("heatmaps").get<int>();
    if (resolved.contains("shared")) apply_overrides(s.shared, resolved.at("shared"), source + ": shared");
    if (resolved.contains("paper")) {
      for (const Json& p : resolved.at("paper")) {
        PaperReference ref;
        ref.label = p.at("label").get<std::string>();
        ref.source = p.at("source").get<std::string>();
        ref.cell = p.at("cell").get<std::string>();
        ref.values = p.at("values").get<std::map<std::string, double>>();
        s.paper.push_back(ref);
      }
    }
    s.sweep_keys = resolved.at("sweep_keys").get<std::vector<std::string>>();
    if (resolved.contains("sweep_axes")) {
      s.sweep_axes = resolved.at("sweep_axes").get<std::vector<std::vector<std::string>>>();
    } else {  // written before axes were recorded: one axis per key
      for (const std::string& k : s.sweep_keys) s.sweep_axes.push_back({k});
    }
    int index = 0;
    for (const Json& c : resolved.at("cells")) {
      CellSpec cell;
      cell.index = index++;
      cell.id = c.at("id").get<std::string>();
      // The axes in the scenario's order (the stored JSON may have sorted them), as a run has them.
      cell.axes = OJson::object();
      for (const std::string& k : s.sweep_keys)
        if (c.at("axes").contains(k)) cell.axes[k] = c.at("axes").at(k);
      cell.observation = parse_observation(c.at("observation"), chk, "observation", s.shared, nullptr);
      cell.matchers = parse_matchers(c.at("matchers"), chk, s.shared);
      cell.sequential = parse_sequential(c, chk, cell.matchers);
      s.cells.push_back(std::move(cell));
    }
    if (s.cells.empty() || s.buildings.empty()) throw InputError(source + ": resolved scenario has no cells or buildings");
    s.resolved = resolved;
    s.hash = hex64(fnv1a64(resolved.dump()));
    return s;
  } catch (const Json::exception& e) {
    throw InputError(source + ": not a resolved scenario: " + e.what());
  }
}

Scenario load_scenario(const std::string& path, const std::string& source_root) {
  const std::string text = read_text_file(path);
  const std::string base = fs::absolute(fs::path(path)).parent_path().string();
  return parse_scenario(text, path, base, source_root);
}

std::vector<Room> load_rooms_file(const std::string& path) {
  const nlohmann::json j = read_json_file(path);
  if (!j.is_object() || !j.contains("rooms") || !j["rooms"].is_array()) {
    throw InputError(path + ": not a rooms file (expected an object with a \"rooms\" array)");
  }
  std::vector<Room> out;
  std::size_t index = 0;
  for (const auto& room : j["rooms"]) {
    const std::string where = path + ": rooms[" + std::to_string(index++) + "]";
    if (!room.is_object() || !room.contains("kind") || !room["kind"].is_string() || !room.contains("polygon") ||
        !room["polygon"].is_array()) {
      throw InputError(where + ": expected \"kind\" (string) and \"polygon\" (array of [x, y])");
    }
    check_limit("max_vertices_per_element", static_cast<double>(room["polygon"].size()), where + ": polygon", "vertices");
    Room r;
    r.kind = room["kind"].get<std::string>();
    if (room.contains("id") && room["id"].is_string()) r.id = room["id"].get<std::string>();
    for (const auto& p : room["polygon"]) {
      if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number()) {
        throw InputError(where + ": polygon points must be [x, y] numbers");
      }
      r.polygon_m.emplace_back(p[0].get<double>(), p[1].get<double>());
    }
    if (r.polygon_m.size() < 3) throw InputError(where + ": polygon with fewer than 3 points");
    out.push_back(std::move(r));
  }
  return out;
}

}  // namespace floorcast
