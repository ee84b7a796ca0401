// Stage parameters at the edge: strict reading of JSON overrides into a stage's parameter struct
// (every key read by name, type and range checked, unknown keys refused), the quantities every
// stage of one experiment shares, and their one JSON form.
//
//   void MyParams::apply_overrides(const nlohmann::json& overrides) {
//     ParamReader r(overrides, "matcher kernel");
//     r.read("alpha", alpha, 0.0, 1e6);
//     r.read_enum("mode", mode, {{"a", Mode::kA}, {"b", Mode::kB}});
//     r.finish();                       // refuses keys nobody read
//   }
//
// Errors are ParameterError: an InputError that also carries the dotted key, so a scenario
// loader can point at the file, line and column where that key was written.
#pragma once

#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "floorcast/core/blocking.hpp"
#include "floorcast/core/types.hpp"

namespace floorcast {

/// Bad parameter value or unknown parameter key: an InputError that also carries the dotted key
/// it is about (relative to the parameter set), so a loader can point at where it was written.
/// ParamReader's messages read "<who>: parameter \"<key>\": <reason>" or
/// "<who>: unknown parameter \"<key>\" (known: ...)"; JsonReader's "<source>: <key>: <reason>".
class ParameterError : public InputError {
 public:
  ParameterError(const std::string& message, std::string key) : InputError(message), key_(std::move(key)) {}
  /// Dotted key relative to the parameter set, e.g. "alpha" or "scale.min_scale".
  const std::string& key() const { return key_; }

 private:
  std::string key_;
};

/// How a ParamReader treats keys that are absent: overrides keep the current value (a parameter
/// set read over its defaults); records need every key (a file written by floorcast, read back).
enum class ReadMode { kOverrides, kRecord };

/// Reads keys from an overrides object; every key must be read exactly by name and have the
/// right type and range, and finish() refuses keys nobody read. `prefix` is prepended to keys in
/// errors (for nested sections: "scale."). In record mode an absent key is an error too, and
/// messages read "<who>: <key>: <reason>" (who = the file).
class ParamReader {
 public:
  ParamReader(const nlohmann::json& overrides, std::string who, std::string prefix = "",
              ReadMode mode = ReadMode::kOverrides);

  void read(const char* key, double& value, double lo, double hi);
  void read(const char* key, int& value, int lo, int hi);
  void read(const char* key, std::uint64_t& value);
  void read(const char* key, bool& value);
  void read(const char* key, std::string& value);
  /// A non-empty array of numbers in [lo, hi].
  void read(const char* key, std::vector<double>& value, double lo, double hi);
  /// A string naming one of `choices`.
  template <class E>
  void read_enum(const char* key, E& value, const std::vector<std::pair<const char*, E>>& choices) {
    if (!take(key)) return;
    const nlohmann::json& x = j_.at(key);
    std::string list;
    for (const auto& [name, v] : choices) list += (list.empty() ? "" : ", ") + std::string(name);
    if (!x.is_string()) fail(key, "expected one of " + list);
    for (const auto& [name, v] : choices) {
      if (x.get<std::string>() == name) {
        value = v;
        return;
      }
    }
    fail(key, "expected one of " + list + ", got \"" + x.get<std::string>() + "\"");
  }
  /// A nested section read by `fn(ParamReader&)`; keys in its errors are "<key>.<sub>".
  template <class F>
  void section(const char* key, F&& fn) {
    if (!take(key)) return;
    const nlohmann::json& x = j_.at(key);
    if (!x.is_object()) fail(key, "expected an object");
    ParamReader sub(x, who_, prefix_ + key + ".", mode_);
    fn(sub);
    sub.finish();
  }
  /// An array of objects, each read by `fn(ParamReader&, index)`; keys in errors are
  /// "<key>[i].<sub>". Returns false (calling nothing) when the key is absent (overrides).
  template <class F>
  bool objects(const char* key, F&& fn) {
    if (!take(key)) return false;
    const nlohmann::json& x = j_.at(key);
    if (!x.is_array()) fail(key, "expected an array of objects");
    for (std::size_t i = 0; i < x.size(); ++i) {
      const std::string at = std::string(key) + "[" + std::to_string(i) + "]";
      if (!x[i].is_object()) fail(at, "expected an object");
      ParamReader sub(x[i], who_, prefix_ + at + ".", mode_);
      fn(sub, i);
      sub.finish();
    }
    return true;
  }
  /// Any JSON value (kept as is: an opaque block such as a stage's overrides).
  void read(const char* key, nlohmann::json& value);
  void read(const char* key, nlohmann::ordered_json& value);
  /// A list of strings.
  void read(const char* key, std::vector<std::string>& value);
  /// A list of integers (any length, empty included).
  void read(const char* key, std::vector<int>& value);
  /// A list of finite numbers of any length (empty included): a series recorded per step.
  void read_series(const char* key, std::vector<double>& value);
  /// True when the overrides hold `key` (does not mark it read).
  bool has(const char* key) const { return j_.contains(key); }
  /// Marks an optional key as known (so finish() lists it), whether present or not; true when
  /// present (then read it).
  bool optional(const char* key) {
    seen_.emplace_back(key);
    return j_.contains(key);
  }
  ReadMode mode() const { return mode_; }
  /// Refuses keys nobody read, listing the known ones.
  void finish() const;
  [[noreturn]] void fail(const std::string& key, const std::string& why) const;

 private:
  bool take(const char* key);
  const nlohmann::json& j_;
  std::string who_;
  std::string prefix_;
  ReadMode mode_ = ReadMode::kOverrides;
  std::set<std::string> read_;
  std::vector<std::string> seen_;
};

/// The name of `value` among `choices` (for to_json).
template <class E>
const char* enum_name(E value, const std::vector<std::pair<const char*, E>>& choices) {
  for (const auto& [name, v] : choices) {
    if (v == value) return name;
  }
  return "?";
}

/// PALMS+ sec. 4.4's map of a building: closed door leaves block and every open door is drawn
/// closed, glass blocks, furniture is not drawn, the plan is cut at 1.5 m (camera height).
inline BlockingOptions closed_door_map() {
  BlockingOptions b;
  b.closed_doors_block = true;
  b.open_doors_block = true;
  b.glass_blocks = true;
  b.obstacles_block = false;
  b.cut_height_m = 1.5;
  return b;
}

/// Quantities every stage of one experiment must agree on, set once (a scenario's `shared`
/// block, or a command's options) and handed to each stage, which uses them unless its own
/// parameters override them explicitly.
struct SharedParams {
  /// Localization range: perfect observations see, and matchers use, geometry within it
  /// (PALMS+ sec. 4.4 and its configs `max_dist: 10`).
  double range_m = 10.0;
  /// What blocks in the map the matchers draw and in perfect observations.
  BlockingOptions blocking = closed_door_map();
};

/// Its fields are shared_fields() (core/fields.hpp).
nlohmann::ordered_json to_json(const SharedParams& shared);
/// Strict: keys range_m, doors_closed, glass_blocks, obstacles_block, cut_height_m.
void apply_overrides(SharedParams& shared, const nlohmann::json& overrides, const std::string& who = "shared");

}  // namespace floorcast
