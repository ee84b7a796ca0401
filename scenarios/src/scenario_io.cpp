// Scenario YAML reading, validation (file:line:col + key in every message), defaults, sweeps.
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "floorcast/floorplans/io.hpp"
#include "floorcast/core/hash.hpp"
#include "floorcast/core/types.hpp"
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

Json scalar_to_json(const YAML::Node& node) {
  const std::string& s = node.Scalar();
  if (node.Tag() == "!") return s;  // quoted: always a string
  static const std::regex integer(R"([-+]?[0-9]+)");
  static const std::regex real(R"([-+]?([0-9]+\.[0-9]*|\.[0-9]+|[0-9]+)([eE][-+]?[0-9]+)?)");
  if (s == "true") return true;
  if (s == "false") return false;
  if (s == "null" || s == "~" || s.empty()) return nullptr;
  if (std::regex_match(s, integer)) {
    try {
      return std::stoll(s);
    } catch (...) {
      return s;
    }
  }
  if (std::regex_match(s, real)) return std::stod(s);
  return s;
}

void convert(const YAML::Node& node, const std::string& path, OJson& out, std::map<std::string, YAML::Mark>& marks) {
  marks[path] = node.Mark();
  switch (node.Type()) {
    case YAML::NodeType::Map:
      out = OJson::object();
      for (const auto& kv : node) {
        const std::string key = kv.first.as<std::string>();
        const std::string child = path.empty() ? key : path + "." + key;
        marks[child] = kv.first.Mark();
        OJson v;
        convert(kv.second, child, v, marks);
        marks[child] = kv.first.Mark();  // messages about a key point at the key
        out[key] = std::move(v);
      }
      break;
    case YAML::NodeType::Sequence: {
      out = OJson::array();
      std::size_t i = 0;
      for (const auto& item : node) {
        OJson v;
        convert(item, path + "[" + std::to_string(i) + "]", v, marks);
        out.push_back(std::move(v));
        ++i;
      }
      break;
    }
    case YAML::NodeType::Scalar:
      out = scalar_to_json(node);
      break;
    default:
      out = nullptr;
  }
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
    if (!v.is_string()) fail(p, std::string("must be a string, got ") + v.dump());
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
    if (!v.is_number()) fail(p, std::string("must be a number, got ") + v.dump());
    const double x = v.get<double>();
    if (!std::isfinite(x) || x < lo || x > hi) {
      std::ostringstream os;
      os << "must be in [" << lo << ", " << hi << "], got " << v.dump();
      fail(p, os.str());
    }
    return x;
  }

  long long integer_in(const OJson& obj, const std::string& path, const char* key, long long fallback, long long lo,
                       long long hi) const {
    if (!obj.contains(key)) return fallback;
    const OJson& v = obj.at(key);
    const std::string p = join(path, key);
    if (!v.is_number_integer()) fail(p, std::string("must be an integer, got ") + v.dump());
    const long long x = v.get<long long>();
    if (x < lo || x > hi) fail(p, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + v.dump());
    return x;
  }

  bool bool_in(const OJson& obj, const std::string& path, const char* key, bool fallback) const {
    if (!obj.contains(key)) return fallback;
    const OJson& v = obj.at(key);
    if (!v.is_boolean()) fail(join(path, key), std::string("must be true or false, got ") + v.dump());
    return v.get<bool>();
  }

 private:
  std::string source_;
  const std::map<std::string, YAML::Mark>& marks_;
};



const std::vector<std::string> kArchetypes = {"apartment", "office", "campus", "angled"};

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
      chk.only_keys(list[i], path, {"file", "generate", "seed", "label"});
      if (list[i].contains("file") == list[i].contains("generate")) chk.fail(path, "give exactly one of \"file\" or \"generate\"");
      file = chk.string_in(list[i], path, "file", "");
      b.archetype = chk.string_in(list[i], path, "generate", "", kArchetypes);
      b.seed = static_cast<std::uint64_t>(chk.integer_in(list[i], path, "seed", 1, 0, (1LL << 53)));
      b.label = chk.string_in(list[i], path, "label", "");
      if (b.archetype.empty() && list[i].contains("seed")) chk.fail(path + ".seed", "only generated buildings take a seed");
    }
    if (!file.empty()) {
      fs::path p(file);
      std::vector<fs::path> candidates;
      if (p.is_absolute()) candidates = {p};
      else candidates = {fs::path(base_dir) / p, fs::path(source_root) / p};
      bool found = false;
      for (const auto& c : candidates) {
        if (fs::is_regular_file(c)) {
          b.file = fs::weakly_canonical(c).string();
          found = true;
          break;
        }
      }
      if (!found) chk.fail(path, "plan file \"" + file + "\" not found (looked in " + base_dir + " and " + source_root + ")");
      if (b.label.empty()) b.label = fs::path(b.file).stem().string();
    } else if (b.label.empty()) {
      b.label = b.archetype + "_" + std::to_string(b.seed);
    }
    static const std::regex label_re("[A-Za-z0-9_.-]+");
    if (!std::regex_match(b.label, label_re)) chk.fail(path, "label \"" + b.label + "\" may only contain letters, digits, _ . -");
    if (!labels.insert(b.label).second) chk.fail(path, "duplicate building label \"" + b.label + "\"");
    out.push_back(b);
  }
  return out;
}

const std::vector<std::string> kObservationKeys = {"source", "max_range_m", "doors_closed", "rays", "sensor",
                                                   "sensor_params", "setting", "path", "scale_alignment",
                                                   "extractor", "mask_glass", "observe_params", "seed"};

ObservationSpec parse_observation(const OJson& obj, const Checker& chk, const std::string& path) {
  ObservationSpec o;
  chk.only_keys(obj, path, kObservationKeys);
  o.source = chk.string_in(obj, path, "source", o.source, {"perfect", "scan"});
  o.max_range_m = chk.number_in(obj, path, "max_range_m", o.max_range_m, 0.5, 1000.0);
  o.doors_closed = chk.bool_in(obj, path, "doors_closed", o.doors_closed);
  o.rays = static_cast<int>(chk.integer_in(obj, path, "rays", o.rays, 4, 3600));
  o.sensor = chk.string_in(obj, path, "sensor", o.sensor, {"perfect", "lidar", "mono", "phone"});
  if (obj.contains("sensor_params")) {
    if (!obj.at("sensor_params").is_object()) chk.fail(Checker::join(path, "sensor_params"), "must be a mapping");
    o.sensor_params = obj.at("sensor_params");
  }
  o.setting = chk.string_in(obj, path, "setting", o.setting, {"full", "partial", "single"});
  o.path = chk.string_in(obj, path, "path", o.path, {"mono", "lidar"});
  o.scale_alignment = chk.string_in(obj, path, "scale_alignment", o.scale_alignment, {"full", "ground", "none"});
  o.extractor = chk.string_in(obj, path, "extractor", o.extractor, {"pcl", "voxelplane"});
  o.mask_glass = chk.bool_in(obj, path, "mask_glass", o.mask_glass);
  if (obj.contains("observe_params")) {
    if (!obj.at("observe_params").is_object()) chk.fail(Checker::join(path, "observe_params"), "must be a mapping");
    o.observe_params = obj.at("observe_params");
  }
  o.seed = static_cast<std::uint64_t>(chk.integer_in(obj, path, "seed", static_cast<long long>(o.seed), 0, (1LL << 53)));
  return o;
}

OJson observation_to_json(const ObservationSpec& o) {
  OJson j;
  j["source"] = o.source;
  j["max_range_m"] = o.max_range_m;
  j["doors_closed"] = o.doors_closed;
  j["rays"] = o.rays;
  j["sensor"] = o.sensor;
  j["sensor_params"] = o.sensor_params;
  j["setting"] = o.setting;
  j["path"] = o.path;
  j["scale_alignment"] = o.scale_alignment;
  j["extractor"] = o.extractor;
  j["mask_glass"] = o.mask_glass;
  j["observe_params"] = o.observe_params;
  j["seed"] = o.seed;
  return j;
}

std::vector<MatcherSpec> parse_matchers(const OJson& obj, const Checker& chk) {
  if (!obj.is_object() || obj.empty()) chk.fail("matchers", "must be a non-empty mapping label -> {matcher: NAME, ...parameters}");
  std::vector<MatcherSpec> out;
  static const std::regex label_re("[A-Za-z0-9_.-]+");
  for (auto it = obj.begin(); it != obj.end(); ++it) {
    const std::string path = "matchers." + it.key();
    if (!std::regex_match(it.key(), label_re)) chk.fail(path, "label may only contain letters, digits, _ . -");
    if (!it.value().is_object()) chk.fail(path, "must be a mapping {matcher: NAME, ...parameters}");
    MatcherSpec m;
    m.label = it.key();
    if (!it.value().contains("matcher")) chk.fail(path, "missing required key \"matcher\"");
    m.name = chk.string_in(it.value(), path, "matcher", "");
    for (auto p = it.value().begin(); p != it.value().end(); ++p)
      if (p.key() != "matcher") m.overrides[p.key()] = p.value();
    out.push_back(std::move(m));
  }
  return out;
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
    chk.fail(path, "cannot sweep \"" + key + "\": sweep keys start with observation. or matchers.");
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
    doc = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw InputError(source + ":" + std::to_string(e.mark.line + 1) + ":" + std::to_string(e.mark.column + 1) +
                     ": malformed YAML: " + e.msg);
  }
  Located loc;
  convert(doc, "", loc.value, loc.marks);
  const Checker chk(source, loc.marks);
  const OJson& root = loc.value;
  if (!root.is_object()) chk.fail("", "top level must be a mapping");
  chk.only_keys(root, "", {"name", "description", "buildings", "sampling", "observation", "matchers", "scoring",
                           "output", "sweep", "paper"});

  Scenario s;
  s.source_file = source;
  s.name = chk.string_in(root, "", "name", fs::path(source).stem().string());
  s.description = chk.string_in(root, "", "description", "");
  s.buildings = parse_buildings(root, chk, base_dir, source_root);

  if (root.contains("sampling")) {
    const OJson& o = root.at("sampling");
    chk.only_keys(o, "sampling", {"count", "seed", "clearance_m", "random_yaw"});
    s.sampling.count = static_cast<int>(chk.integer_in(o, "sampling", "count", s.sampling.count, 1, 1000000));
    s.sampling.seed = static_cast<std::uint64_t>(chk.integer_in(o, "sampling", "seed", 1, 0, (1LL << 53)));
    s.sampling.clearance_m = chk.number_in(o, "sampling", "clearance_m", s.sampling.clearance_m, 0.0, 10.0);
    s.sampling.random_yaw = chk.bool_in(o, "sampling", "random_yaw", s.sampling.random_yaw);
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
        if (!t[i].is_number() || t[i].get<double>() <= 0.0)
          chk.fail("scoring.recall_thresholds_m[" + std::to_string(i) + "]", "must be a positive number");
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

  const OJson base_observation = root.contains("observation") ? root.at("observation") : OJson::object();
  (void)parse_observation(base_observation, chk, "observation");  // validates the base
  if (!root.contains("matchers")) chk.fail("matchers", "missing required key");
  const OJson base_matchers = root.at("matchers");
  (void)parse_matchers(base_matchers, chk);

  std::vector<Axis> axes;
  if (root.contains("sweep")) axes = parse_sweep(root.at("sweep"), chk, base_matchers);
  for (const auto& a : axes)
    for (const auto& k : a.keys) s.sweep_keys.push_back(k);

  // Cartesian product over axes, first axis slowest.
  std::size_t total = 1;
  for (const auto& a : axes) total *= a.values.size();
  if (total > 100000) chk.fail("sweep", "expands to " + std::to_string(total) + " cells (limit 100000)");
  for (std::size_t c = 0; c < total; ++c) {
    OJson tree;
    tree["observation"] = base_observation;
    tree["matchers"] = base_matchers;
    CellSpec cell;
    cell.index = static_cast<int>(c);
    char id[16];
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
      cell.observation = parse_observation(tree["observation"], chk, "observation");
      cell.matchers = parse_matchers(tree["matchers"], chk);
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
    r["buildings"].push_back(j);
  }
  r["sampling"] = {{"count", s.sampling.count}, {"seed", s.sampling.seed}, {"clearance_m", s.sampling.clearance_m},
                   {"random_yaw", s.sampling.random_yaw}};
  r["scoring"] = {{"recall_thresholds_m", s.scoring.recall_thresholds_m},
                  {"combined_threshold_m", s.scoring.combined_threshold_m},
                  {"combined_threshold_deg", s.scoring.combined_threshold_deg},
                  {"top_k", s.scoring.top_k},
                  {"bootstrap_resamples", s.scoring.bootstrap_resamples},
                  {"bootstrap_seed", s.scoring.bootstrap_seed}};
  r["output"] = {{"heatmaps", s.output.heatmaps}};
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
  r["cells"] = OJson::array();
  for (const auto& c : s.cells) {
    OJson j;
    j["id"] = c.id;
    j["axes"] = c.axes;
    j["observation"] = observation_to_json(c.observation);
    OJson m = OJson::object();
    for (const auto& spec : c.matchers) {
      OJson one;
      one["matcher"] = spec.name;
      for (auto it = spec.overrides.begin(); it != spec.overrides.end(); ++it) one[it.key()] = it.value();
      m[spec.label] = one;
    }
    j["matchers"] = m;
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
      s.buildings.push_back(spec);
    }
    const Json& sm = resolved.at("sampling");
    s.sampling.count = sm.at("count").get<int>();
    s.sampling.seed = sm.at("seed").get<std::uint64_t>();
    s.sampling.clearance_m = sm.at("clearance_m").get<double>();
    s.sampling.random_yaw = sm.at("random_yaw").get<bool>();
    const Json& sc = resolved.at("scoring");
    s.scoring.recall_thresholds_m = sc.at("recall_thresholds_m").get<std::vector<double>>();
    s.scoring.combined_threshold_m = sc.at("combined_threshold_m").get<double>();
    s.scoring.combined_threshold_deg = sc.at("combined_threshold_deg").get<double>();
    s.scoring.top_k = sc.at("top_k").get<int>();
    s.scoring.bootstrap_resamples = sc.at("bootstrap_resamples").get<int>();
    s.scoring.bootstrap_seed = sc.at("bootstrap_seed").get<std::uint64_t>();
    s.output.heatmaps = resolved.at("output").at("heatmaps").get<int>();
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
    int index = 0;
    for (const Json& c : resolved.at("cells")) {
      CellSpec cell;
      cell.index = index++;
      cell.id = c.at("id").get<std::string>();
      cell.axes = c.at("axes");
      cell.observation = parse_observation(c.at("observation"), chk, "observation");
      cell.matchers = parse_matchers(c.at("matchers"), chk);
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

}  // namespace floorcast
