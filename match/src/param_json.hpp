// Strict reading of matcher parameter overrides from JSON (internal).
#pragma once

#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "floorcast/core/types.hpp"

namespace floorcast::detail {

/// Reads keys from an overrides object; every key must be read exactly by name and have the
/// right type, and finish() refuses keys nobody read. Errors name the matcher and the key.
class ParamReader {
 public:
  ParamReader(const nlohmann::json& overrides, std::string who) : j_(overrides), who_(std::move(who)) {
    if (!j_.is_object()) throw InputError(who_ + ": parameter overrides must be a JSON object");
  }

  void read(const char* key, double& v, double lo, double hi) {
    if (!take(key)) return;
    const auto& x = j_.at(key);
    if (!x.is_number()) fail(key, "expected a number");
    const double d = x.get<double>();
    if (!(d >= lo && d <= hi)) fail(key, "value " + x.dump() + " outside [" + num(lo) + ", " + num(hi) + "]");
    v = d;
  }
  void read(const char* key, int& v, int lo, int hi) {
    if (!take(key)) return;
    const auto& x = j_.at(key);
    if (!x.is_number_integer()) fail(key, "expected an integer");
    const long long d = x.get<long long>();
    if (d < lo || d > hi) fail(key, "value " + x.dump() + " outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    v = static_cast<int>(d);
  }
  void read(const char* key, bool& v) {
    if (!take(key)) return;
    const auto& x = j_.at(key);
    if (!x.is_boolean()) fail(key, "expected true or false");
    v = x.get<bool>();
  }
  void read(const char* key, std::string& v) {
    if (!take(key)) return;
    const auto& x = j_.at(key);
    if (!x.is_string()) fail(key, "expected a string");
    v = x.get<std::string>();
  }
  void read(const char* key, std::vector<double>& v, double lo, double hi) {
    if (!take(key)) return;
    const auto& x = j_.at(key);
    if (!x.is_array() || x.empty()) fail(key, "expected a non-empty array of numbers");
    std::vector<double> out;
    for (const auto& e : x) {
      if (!e.is_number()) fail(key, "expected a non-empty array of numbers");
      const double d = e.get<double>();
      if (!(d >= lo && d <= hi)) fail(key, "value " + e.dump() + " outside [" + num(lo) + ", " + num(hi) + "]");
      out.push_back(d);
    }
    v = out;
  }
  void finish() const {
    for (auto it = j_.begin(); it != j_.end(); ++it) {
      if (!read_.count(it.key())) {
        std::string known;
        for (const auto& k : seen_) known += (known.empty() ? "" : ", ") + k;
        throw InputError(who_ + ": unknown parameter \"" + it.key() + "\" (known: " + known + ")");
      }
    }
  }
  [[noreturn]] void fail(const std::string& key, const std::string& why) const {
    throw InputError(who_ + ": parameter \"" + key + "\": " + why);
  }

 private:
  bool take(const char* key) {
    seen_.emplace_back(key);
    if (!j_.contains(key)) return false;
    read_.insert(key);
    return true;
  }
  static std::string num(double d) {
    nlohmann::json j = d;
    return j.dump();
  }
  const nlohmann::json& j_;
  std::string who_;
  std::set<std::string> read_;
  std::vector<std::string> seen_;
};

}  // namespace floorcast::detail
