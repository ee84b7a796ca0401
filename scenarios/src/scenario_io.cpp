// Scenario YAML reading, validation (file:line:col + key in every message), defaults, sweeps.
#include <yaml-cpp/eventhandler.h>
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
#include "floorcast/core/fields.hpp"
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

/// Where the documents of a YAML text start, at most `limit` of them (events only: no nodes built).
std::vector<YAML::Mark> yaml_document_starts(const std::string& text, std::size_t limit) {
  struct Starts final : YAML::EventHandler {
    std::vector<YAML::Mark> marks;
    void OnDocumentStart(const YAML::Mark& mark) override { marks.push_back(mark); }
    void OnDocumentEnd() override {}
    void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
    void OnAlias(const YAML::Mark&, YAML::anchor_t) override {}
    void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t, const std::string&) override {}
    void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {}
    void OnSequenceEnd() override {}
    void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {}
    void OnMapEnd() override {}
  } starts;
  std::istringstream in(text);
  YAML::Parser parser(in);
  while (starts.marks.size() < limit && parser.HandleNextDocument(starts)) {
  }
  return starts.marks;
}

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
        std::vector<YAML::Node> merged;  // values of merge keys (<<), applied after the map's own keys
        for (const auto& kv : node) {
          if (kv.first.Type() == YAML::NodeType::Scalar && kv.first.Scalar() == "<<" && kv.first.Tag() == "?") {
            merged.push_back(kv.second);
            continue;
          }
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
        // YAML 1.1 merge keys (`<<: *defaults`, `<<: [*a, *b]`): the merged maps' keys that the map
        // does not set itself, the earlier map first (yaml-cpp reads "<<" as an ordinary key).
        for (const YAML::Node& m : merged) {
          std::vector<YAML::Node> sources;
          if (m.Type() == YAML::NodeType::Sequence) {
            for (const auto& item : m) sources.push_back(item);
          } else {
            sources.push_back(m);  // a mapping; anything else is refused below
          }
          for (const YAML::Node& src : sources) {
            if (src.Type() != YAML::NodeType::Map) {
              throw InputError(mark_text(source_, src.Mark()) + ": " + (path.empty() ? std::string("document") : path) +
                               ": a merge key (<<) takes a mapping or a list of mappings (e.g. <<: *defaults)");
            }
            OJson v;
            convert(src, path, v);
            for (auto it = v.begin(); it != v.end(); ++it) {
              if (!out.contains(it.key())) out[it.key()] = it.value();
            }
          }
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

/// Absolute path of a file or folder named in a scenario: as is when absolute, else relative to
/// the scenario's folder, then to the source tree root; empty when not found.
std::string find_file(const std::string& file, const std::string& base_dir, const std::string& source_root) {
  const fs::path p(file);
  const std::vector<fs::path> candidates =
      p.is_absolute() ? std::vector<fs::path>{p} : std::vector<fs::path>{fs::path(base_dir) / p, fs::path(source_root) / p};
  std::error_code ec;
  for (const auto& c : candidates) {
    // Any kind: the callers name what a found path is when it is the wrong kind (a folder used to be
    // reported as "not found").
    if (fs::exists(c, ec)) return fs::weakly_canonical(c).string();
  }
  return {};
}

/// Refuses a found path that is not a regular file, naming what it is (a folder used to be
/// reported as "not found").
void require_file(const Checker& chk, const std::string& path, const std::string& what, const std::string& found) {
  std::error_code ec;
  if (fs::is_directory(found, ec)) chk.fail(path, what + " \"" + found + "\" is a folder, expected a file");
  if (!fs::is_regular_file(found, ec)) chk.fail(path, what + " \"" + found + "\" is not a regular file (a FIFO, device or socket)");
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
        require_file(chk, path + ".rooms", "rooms file", b.rooms_file);
        b.rooms_given = rooms;
        b.rooms_hash = hex64(fnv1a64(read_text_file(b.rooms_file)));
      }
    }
    if (!file.empty()) {
      b.file = find_file(file, base_dir, source_root);
      if (b.file.empty()) chk.fail(path, "plan file \"" + file + "\" not found (looked in " + base_dir + " and " + source_root + ")");
      require_file(chk, path, "plan file", b.file);
      b.file_given = file;
      b.file_hash = hex64(fnv1a64(read_text_file(b.file)));
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

/// Choices among names (the enum is the name itself).
std::vector<std::pair<const char*, std::string>> name_choices(const std::vector<std::string>& names) {
  std::vector<std::pair<const char*, std::string>> out;
  for (const std::string& n : names) out.emplace_back(n.c_str(), n);
  return out;
}

/// An observation mapping as the scenario writes it (observation.*, scenarios/README.md), every
/// default filled in: what the resolved configuration records and merges re-parse.
struct ObservationUser {
  std::string source = "perfect";
  double max_range_m = 10.0;  ///< default: the shared range
  bool doors_closed = true;   ///< default: the shared blocking
  int rays = PerfectObservationParams{}.num_rays;
  int bev_columns = PerfectObservationParams{}.bev_columns;
  std::string sensor = "mono";
  OJson sensor_params = OJson::object();
  std::string setting = "full";
  std::string path = "mono";
  std::string scale_alignment = "full";
  std::string extractor = to_string(LidarPathParams{}.extractor);
  bool mask_glass = false;
  OJson observe_params = OJson::object();
  std::uint64_t seed = 1;
  std::string depth_dir;  ///< as the scenario names it
  std::string depth_kind = "z";
  double depth_unit_m = DepthFileOptions{}.integer_unit_m;
};

const FieldList<ObservationUser>& observation_user_fields() {
  using O = ObservationUser;
  static const std::vector<std::string> kSources = {"perfect", "scan"}, kSettings = {"full", "partial", "single"},
                                        kPaths = {"mono", "lidar"}, kScales = {"full", "ground", "none"},
                                        kExtractors = {"pcl", "voxelplane"}, kDepthKinds = {"z", "range"};
  auto with_depth_dir = [](const O& o) { return !o.depth_dir.empty(); };
  static const FieldList<O> f =
      FieldList<O>("observation")
          .choice("source", &O::source, name_choices(kSources),
                  "perfect: exact visible walls from the plan (PALMS+ sec. 4.4 proxy); scan: simulate a scan, then "
                  "the observation module")
          .number("max_range_m", &O::max_range_m, 0.5, 1000.0, "perfect: visible geometry within this range, m")
          .flag("doors_closed", &O::doors_closed, "perfect: open doors occlude as if closed")
          .integer("rays", &O::rays, 4, 3600, "perfect: equiangular rays (F3Loc: 36)")
          .integer("bev_columns", &O::bev_columns, 0, 3600,
                   "perfect: equiangular columns of the perfect BEVs (the thesis' one-hot plan rendering, for the bev "
                   "matcher); 0 = none")
          .choice("sensor", &O::sensor, name_choices(scan_preset_names()), "scan: the sensor preset")
          .json("sensor_params", &O::sensor_params, "scan: sensor parameter overrides")
          .choice("setting", &O::setting, name_choices(kSettings), "scan: views used (PALMS+ settings)")
          .choice("path", &O::path, name_choices(kPaths), "observation module path")
          .choice("scale_alignment", &O::scale_alignment, name_choices(kScales), "mono scale alignment (PALMS+ Table 4)")
          .choice("extractor", &O::extractor, name_choices(kExtractors), "LiDAR plane extractor")
          .flag("mask_glass", &O::mask_glass, "drop glass-affected pixels (PALMS+*)")
          .json("observe_params", &O::observe_params, "observation-module parameter overrides")
          .unsigned_integer("seed", &O::seed, "simulator seed (combined with building and point index)")
          .text("depth_dir", &O::depth_dir,
                "scan: depth maps made elsewhere replace the simulated depth, one folder per unit as `floorcast "
                "export` lays out its scans: DIR/<cell>/<building>/scans/pNNNN (walk steps: .../pNNNN/step_SSSS)")
          .optional(with_depth_dir)
          .choice("depth_kind", &O::depth_kind, name_choices(kDepthKinds), "depth_dir: z-depth or range maps")
          .optional(with_depth_dir)
          .number("depth_unit_m", &O::depth_unit_m, 1e-6, 1.0, "depth_dir: metres per unit of 16-bit maps")
          .optional(with_depth_dir)
          .check([](const O& o, const ParamReader& r) {
            if (!o.depth_dir.empty() && o.source != "scan") {
              r.fail("depth_dir", "needs source: scan (depth maps replace the depth of simulated scans)");
            }
            if (!o.sensor_params.is_object()) r.fail("sensor_params", "must be a mapping");
            if (!o.observe_params.is_object()) r.fail("observe_params", "must be a mapping");
            if (o.seed > (1ULL << 53)) r.fail("seed", "must be in [0, 9007199254740992]");
          });
  return f;
}

/// The scenario's folder and the source tree, where relative file names are looked up (empty for
/// a resolved scenario, whose names are absolute already).
struct FileBases {
  std::string base_dir, source_root;
};

/// Parses an observation mapping (user form) into typed stage parameters. `resolved` receives the
/// user form with every default filled in (written next to results; re-parsed by merges).
ObservationSpec parse_observation(const OJson& obj, const Checker& chk, const std::string& path,
                                  const SharedParams& shared, OJson* resolved, const FileBases& files = {}) {
  ObservationSpec o;
  // Perfect observer: shared range and blocking, then the explicit keys.
  o.perfect.apply_shared(shared);
  ObservationUser user;
  user.max_range_m = o.perfect.max_range_m;
  user.doors_closed = o.perfect.blocking.open_doors_block;
  user.rays = o.perfect.num_rays;
  user.bev_columns = o.perfect.bev_columns;
  at_key(chk, path, [&] { observation_user_fields().read(user, Json(obj)); });
  o.source = user.source == "scan" ? ObservationSource::kScan : ObservationSource::kPerfect;
  o.perfect.max_range_m = user.max_range_m;
  o.perfect.blocking.open_doors_block = user.doors_closed;
  o.perfect.num_rays = user.rays;
  o.perfect.bev_columns = user.bev_columns;
  // Scan: sensor preset, its overrides, the setting.
  at_key(chk, Checker::join(path, "sensor_params"), [&] {
    o.scan = scan_preset(user.sensor);
    apply_scan_overrides(o.scan, user.sensor_params, "sensor_params");
    parse_scan_setting(user.setting, o.scan.setting);
    validate_scan_params(o.scan);
  });
  // Observation module: path, scale alignment, extractor, glass masking, then its overrides.
  o.observe.path = parse_observation_path(user.path);
  o.observe.scale.mode = parse_scale_alignment(user.scale_alignment);
  o.observe.back_projection.mask_glass = user.mask_glass;
  o.observe.lidar.back_projection.mask_glass = user.mask_glass;
  o.observe.lidar.extractor = parse_plane_extractor(user.extractor);
  o.observe.bev.max_depth_m = shared.range_m;  // the BEV's last bin edge: the shared range, as the bev matcher's
  at_key(chk, Checker::join(path, "observe_params"), [&] { apply_overrides(o.observe, user.observe_params); });
  o.seed = user.seed;
  if (!user.depth_dir.empty()) {
    // Found like building files; a resolved scenario (merges, reports) keeps the name as given.
    o.depth_dir_given = user.depth_dir;
    o.depth_dir = user.depth_dir;
    if (!files.base_dir.empty()) {
      o.depth_dir = find_file(user.depth_dir, files.base_dir, files.source_root);
      if (o.depth_dir.empty()) {
        chk.fail(Checker::join(path, "depth_dir"), "folder \"" + user.depth_dir + "\" not found (looked in " +
                                                        files.base_dir + " and " + files.source_root + ")");
      }
      std::error_code ec;
      if (!fs::is_directory(o.depth_dir, ec)) {
        chk.fail(Checker::join(path, "depth_dir"), "\"" + o.depth_dir + "\" is not a folder (depth maps are read from a folder)");
      }
    }
    o.depth_file.kind = parse_depth_kind(user.depth_kind);
    o.depth_file.integer_unit_m = user.depth_unit_m;
  }
  if (resolved) *resolved = observation_user_fields().write(user);
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

std::vector<MatcherSpec> parse_matchers(const OJson& obj, const Checker& chk, const SharedParams& shared,
                                        const FileBases& files = {}) {
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
    // An external program's files (its script, a model) are found like building files: an element
    // of `command` naming an existing file relative to the scenario's folder or the source tree
    // becomes its absolute path, so the run works from any working directory.
    if (name == "external" && !files.base_dir.empty() && overrides.contains("command") && overrides["command"].is_array()) {
      for (Json& e : overrides["command"]) {
        if (!e.is_string() || e.get<std::string>().empty() || fs::path(e.get<std::string>()).is_absolute()) continue;
        const std::string found = find_file(e.get<std::string>(), files.base_dir, files.source_root);
        std::error_code ec;
        if (!found.empty() && fs::is_regular_file(found, ec)) e = found;
      }
    }
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
  if (tree.contains("schedule")) at_key(chk, "schedule", [&] { schedule_fields().read(q.schedule, Json(tree.at("schedule"))); });
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
    const std::string name = chk.string_in(it.value(), path, "tracker", "");
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
      t.config = make_tracker_config(name, overrides);
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
  j["schedule"] = schedule_fields().write(q.schedule);
  OJson ts = OJson::object();
  for (const TrackerSpec& t : q.trackers) {
    OJson one;
    one["tracker"] = t.config->name();
    one["matcher"] = t.matcher;
    const OJson params = t.config->parameters();
    for (auto it = params.begin(); it != params.end(); ++it) one[it.key()] = it.value();
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
      bool known = false;
      for (const FieldInfo& f : observation_user_fields().describe()) known = known || f.key == sub;
      if (!known &&
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

constexpr std::uint64_t kMaxSeed = 1ULL << 53;  // seeds stay exact in JSON numbers

const FieldList<SamplingSpec>& sampling_fields() {
  using S = SamplingSpec;
  static const std::vector<std::string> kRegions = {"transitional", "transitional_or_uniform", "uniform", "kinds"};
  static const FieldList<S> f =
      FieldList<S>("sampling")
          .integer("count", &S::count, 1, 1000000, "observation points per building")
          .unsigned_integer("seed", &S::seed, "sampling seed")
          .number("clearance_m", &S::clearance_m, 0.0, 10.0, "minimum distance of a point from any wall or obstacle, m")
          .flag("random_yaw", &S::random_yaw, "random true heading per point (else 0)")
          .choice("region", &S::region, name_choices(kRegions),
                  "where points go: transitional rooms (PALMS+ sec. 4.4), the whole free space, or rooms of region_kinds")
          .texts("region_kinds", &S::region_kinds, "room kinds for region kinds (\"transitional\" expands)")
          .optional([](const S& s) { return !s.region_kinds.empty(); })
          .integer("negatives", &S::negatives, 0, 1000000,
                   "negative samples per building: observations made at the points of the other buildings (round robin), "
                   "matched against this building's plan and scored with rejection; needs two or more buildings")
          .optional([](const S& s) { return s.negatives > 0; })
          .check([](const S& s, const ParamReader& r) {
            if (s.seed > kMaxSeed) r.fail("seed", "must be in [0, 9007199254740992]");
            for (std::size_t i = 0; i < s.region_kinds.size(); ++i) {
              if (s.region_kinds[i].empty()) r.fail("region_kinds[" + std::to_string(i) + "]", "must be a room kind (a string)");
            }
          });
  return f;
}

const FieldList<ScoringParams>& scoring_fields() {
  using S = ScoringParams;
  static const FieldList<S> f =
      FieldList<S>("scoring")
          .numbers("recall_thresholds_m", &S::recall_thresholds_m, 0.0, 1e3, "position thresholds for recall, m (PALMS+ Table 1)")
          .number("combined_threshold_m", &S::combined_threshold_m, 1e-3, 1e3, "combined recall: position threshold, m")
          .number("combined_threshold_deg", &S::combined_threshold_deg, 0.0, 180.0, "combined recall: heading threshold, deg")
          .integer("top_k", &S::top_k, 1, 100, "top-K recall at the combined position threshold")
          .integer("bootstrap_resamples", &S::bootstrap_resamples, 0, 100000, "bootstrap resamples for 95% intervals (0: none)")
          .unsigned_integer("bootstrap_seed", &S::bootstrap_seed, "bootstrap seed")
          .check([](const S& s, const ParamReader& r) {
            for (std::size_t i = 0; i < s.recall_thresholds_m.size(); ++i) {
              if (!(s.recall_thresholds_m[i] > 0.0)) {
                r.fail("recall_thresholds_m[" + std::to_string(i) + "]", "must be a number in (0, 1000] metres");
              }
            }
            if (s.bootstrap_seed > kMaxSeed) r.fail("bootstrap_seed", "must be in [0, 9007199254740992]");
          });
  return f;
}

const FieldList<OutputSpec>& output_fields() {
  static const FieldList<OutputSpec> f =
      FieldList<OutputSpec>("output").integer("heatmaps", &OutputSpec::heatmaps, 0, 1000,
                                              "posterior overlays drawn for the first N points of each building");
  return f;
}

/// A building as the resolved configuration records it: the plan and rooms files as the scenario
/// names them with the hashes of their bytes (the configuration hash covers those, never paths).
const FieldList<BuildingSpec>& resolved_building_fields() {
  using B = BuildingSpec;
  auto from_file = [](const B& b) { return !b.file.empty(); };
  auto generated = [](const B& b) { return b.file.empty(); };
  auto with_rooms = [](const B& b) { return !b.rooms_file.empty(); };
  static const FieldList<B> f =
      FieldList<B>("building")
          .text("label", &B::label, "name in unit ids and tables")
          .text("file", &B::file_given, "plan file as the scenario names it")
          .optional(from_file)
          .text("file_hash", &B::file_hash, "hash of the plan file's bytes")
          .optional(from_file)
          .text("generate", &B::archetype, "generator archetype")
          .optional(generated)
          .unsigned_integer("seed", &B::seed, "generator seed")
          .optional(generated)
          .text("rooms", &B::rooms_given, "rooms file as the scenario names it")
          .optional(with_rooms)
          .text("rooms_hash", &B::rooms_hash, "hash of the rooms file's bytes")
          .optional(with_rooms)
          .text("sampling_region", &B::sampling_region, "how its points are placed (resolved at load)")
          .optional([](const B&) { return true; });
  return f;
}

const FieldList<PaperReference>& paper_fields() {
  using P = PaperReference;
  static const FieldList<P> f =
      FieldList<P>("paper")
          .text("label", &P::label, "row label, e.g. \"PALMS+ paper, kernel\"")
          .text("source", &P::source, "where the numbers are from")
          .text("cell", &P::cell, "the cell id it compares with; empty = every cell")
          .custom(
              "values", [](OJson& j, const P& p) { j["values"] = p.values; },
              [](ParamReader& r, P& p) {
                Json values;
                r.read("values", values);
                if (!values.is_object()) r.fail("values", "needs a mapping metric -> number");
                p.values.clear();
                for (auto it = values.begin(); it != values.end(); ++it) {
                  if (!it.value().is_number()) r.fail("values." + it.key(), "must be a number");
                  p.values[it.key()] = it.value().get<double>();
                }
              },
              "{metric: number}", "published values (recalls as fractions)");
  return f;
}

}  // namespace

std::vector<std::pair<std::string, std::vector<FieldInfo>>> scenario_block_fields() {
  ObservationUser observation;
  observation.max_range_m = SharedParams{}.range_m;
  observation.doors_closed = SharedParams{}.blocking.open_doors_block;
  return {{"sampling", sampling_fields().describe()},
          {"observation", observation_user_fields().describe(observation)},
          {"scoring", scoring_fields().describe()},
          {"output", output_fields().describe()}};
}

Scenario parse_scenario(const std::string& yaml_text, const std::string& source, const std::string& base_dir,
                        const std::string& source_root) {
  YAML::Node doc;
  try {
    // Every document is counted: a second one is refused rather than silently ignored. Not with
    // YAML::LoadAll: yaml-cpp 0.7's parser returns an empty document without consuming anything
    // for a stray ',' at the top level (a fuzzing finding: a scenario whose third line began with
    // a comma made LoadAll append empty documents until 18 GB were gone), so the documents are
    // counted up to two, and a document that starts where the last one started is an error.
    const std::vector<YAML::Mark> starts = yaml_document_starts(yaml_text, 2);
    if (starts.size() > 1) {
      if (starts[1].pos == starts[0].pos) {
        const std::size_t at = static_cast<std::size_t>(std::max(0, starts[1].pos));
        throw InputError(mark_text(source, starts[1]) + ": malformed YAML: the parser cannot go on at " +
                         (at < yaml_text.size() ? "'" + printable_text(yaml_text.substr(at, 1)) + "'" : std::string("the end")) +
                         " (a stray ',' or flow indicator outside [] or {}?)");
      }
      throw InputError(mark_text(source, starts[1]) + ": a scenario file holds one YAML document, this one has more");
    }
    if (!starts.empty()) doc = YAML::Load(yaml_text);
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
    at_key(chk, "sampling", [&] { sampling_fields().read(s.sampling, Json(o)); });
    if (s.sampling.negatives > 0 && s.buildings.size() < 2) {
      chk.fail("sampling.negatives", "negative samples are observations made in the scenario's other buildings: list at "
                                     "least two buildings");
    }
    if (o.contains("region_kinds") && s.sampling.region_kinds.empty()) {
      chk.fail("sampling.region_kinds", "must be a non-empty list of room kinds");
    }
    if (!o.contains("region") && !s.sampling.region_kinds.empty()) s.sampling.region = "kinds";
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
  if (root.contains("scoring")) at_key(chk, "scoring", [&] { scoring_fields().read(s.scoring, Json(root.at("scoring"))); });
  if (root.contains("output")) at_key(chk, "output", [&] { output_fields().read(s.output, Json(root.at("output"))); });
  if (root.contains("paper")) {
    const OJson& list = root.at("paper");
    if (!list.is_array()) chk.fail("paper", "must be a list of {label, source, cell, values}");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string path = "paper[" + std::to_string(i) + "]";
      PaperReference ref;
      at_key(chk, path, [&] {
        const Json item(list[i]);
        ParamReader r(item, "paper", "");
        paper_fields().read_into(r, ref);
        if (!r.has("values")) r.fail("values", "needs \"values\": a mapping metric -> number");
        r.finish();
      });
      if (ref.label.empty()) chk.fail(path, "missing required key \"label\"");
      s.paper.push_back(std::move(ref));
    }
  }

  s.shared = parse_shared(root, chk);
  const OJson base_observation = root.contains("observation") ? root.at("observation") : OJson::object();
  (void)parse_observation(base_observation, chk, "observation", s.shared, nullptr, {base_dir, source_root});  // validates the base
  if (!root.contains("matchers")) chk.fail("matchers", "missing required key");
  const OJson base_matchers = root.at("matchers");
  (void)parse_sequential(root, chk, parse_matchers(base_matchers, chk, s.shared, {base_dir, source_root}));

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
                                    static_cast<double>(s.sampling.count + s.sampling.negatives)}),
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
      cell.observation =
          parse_observation(tree["observation"], chk, "observation", s.shared, &resolved_observation, {base_dir, source_root});
      resolved_observations.push_back(std::move(resolved_observation));
      cell.matchers = parse_matchers(tree["matchers"], chk, s.shared, {base_dir, source_root});
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
  for (const auto& b : s.buildings) r["buildings"].push_back(resolved_building_fields().write(b));
  r["sampling"] = sampling_fields().write(s.sampling);
  r["scoring"] = scoring_fields().write(s.scoring);
  r["output"] = output_fields().write(s.output);
  r["shared"] = to_json(s.shared);
  if (!s.paper.empty()) {
    r["paper"] = OJson::array();
    for (const auto& p : s.paper) r["paper"].push_back(paper_fields().write(p));
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
  s.hash = scenario_hash(Json(r));
  return s;
}

std::string scenario_hash(const Json& resolved) {
  // Canonical (sorted-key) form without the files' locations: their content counts by hash.
  Json h = resolved;
  if (h.is_object() && h.contains("buildings") && h["buildings"].is_array()) {
    for (Json& b : h["buildings"]) {
      if (!b.is_object()) continue;
      b.erase("file");
      b.erase("rooms");
    }
  }
  // An external program's files count by name (the absolute paths the loader resolved them to
  // become their file names); its `version` says when its answers change.
  if (h.is_object() && h.contains("cells") && h["cells"].is_array()) {
    for (Json& c : h["cells"]) {
      if (!c.is_object() || !c.contains("matchers") || !c["matchers"].is_object()) continue;
      for (auto& [label, m] : c["matchers"].items()) {
        (void)label;
        if (!m.is_object() || m.value("matcher", std::string()) != "external" || !m.contains("command") ||
            !m["command"].is_array())
          continue;
        for (Json& e : m["command"])
          if (e.is_string() && fs::path(e.get<std::string>()).is_absolute()) e = fs::path(e.get<std::string>()).filename().string();
      }
    }
  }
  return hex64(fnv1a64(h.dump()));
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
      spec.sampling_region = "uniform";  // runs written before it was recorded
      resolved_building_fields().read_record(spec, b, source + ": buildings");
      spec.file = spec.file_given;
      spec.rooms_file = spec.rooms_given;
      s.buildings.push_back(spec);
    }
    const Json& sm = resolved.at("sampling");
    sampling_fields().read(s.sampling, sm);
    if (!sm.contains("region")) s.sampling.region = s.sampling.region_kinds.empty() ? "uniform" : "kinds";
    scoring_fields().read_record(s.scoring, resolved.at("scoring"), source + ": scoring");
    output_fields().read_record(s.output, resolved.at("output"), source + ": output");
    if (resolved.contains("shared")) apply_overrides(s.shared, resolved.at("shared"), source + ": shared");
    if (resolved.contains("paper")) {
      for (const Json& p : resolved.at("paper")) {
        PaperReference ref;
        paper_fields().read_record(ref, p, source + ": paper");
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
    s.hash = scenario_hash(resolved);
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
