// Strict reading of JSON objects with error messages that name the file and the element: every
// component's io part reads its files with it (one strict reader in floorcast).
#pragma once

#include <cmath>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "floorcast/core/params.hpp"
#include "floorcast/core/types.hpp"

namespace floorcast {

class JsonReader {
 public:
  JsonReader(const nlohmann::json& j, std::string source, std::string path)
      : j_(j), source_(std::move(source)), path_(std::move(path)) {
    if (!j_.is_object()) fail("expected an object");
  }

  [[noreturn]] void fail(const std::string& reason) const {
    throw ParameterError(source_ + ": " + (path_.empty() ? std::string("top level") : path_) + ": " + reason, path_);
  }
  /// Throws a ParameterError carrying the element's dotted path (relative to the document).
  [[noreturn]] void fail_key(const std::string& key, const std::string& reason) const {
    throw ParameterError(source_ + ": " + child_path(key) + ": " + reason, child_path(key));
  }

  std::string child_path(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
  const std::string& source() const { return source_; }
  bool has(const std::string& key) const { return j_.contains(key); }
  const nlohmann::json& raw(const std::string& key) const {
    if (!j_.contains(key)) fail_key(key, "missing");
    return j_.at(key);
  }

  /// Refuses keys outside `known`.
  void only(std::initializer_list<const char*> known) const {
    std::set<std::string> k;
    for (const char* s : known) k.insert(s);
    for (auto it = j_.begin(); it != j_.end(); ++it) {
      if (!k.count(it.key())) fail_key(it.key(), "unknown key");
    }
  }

  JsonReader object(const std::string& key) const { return JsonReader(raw(key), source_, child_path(key)); }

  double number(const std::string& key, double lo, double hi) const {
    const nlohmann::json& v = raw(key);
    if (!v.is_number()) fail_key(key, "expected a number");
    const double x = v.get<double>();
    if (!std::isfinite(x)) fail_key(key, "not finite");
    if (x < lo || x > hi) {
      fail_key(key, "value " + nlohmann::json(x).dump() + " outside [" + nlohmann::json(lo).dump() + ", " +
                        nlohmann::json(hi).dump() + "]");
    }
    return x;
  }
  double number_or(const std::string& key, double lo, double hi, double fallback) const {
    return has(key) ? number(key, lo, hi) : fallback;
  }
  long long integer(const std::string& key, long long lo, long long hi) const {
    const nlohmann::json& v = raw(key);
    if (!v.is_number_integer()) fail_key(key, "expected an integer");
    const long long x = v.get<long long>();
    if (x < lo || x > hi) fail_key(key, "value " + std::to_string(x) + " outside [" + std::to_string(lo) + ", " +
                                            std::to_string(hi) + "]");
    return x;
  }
  std::uint64_t uint64(const std::string& key) const {
    const nlohmann::json& v = raw(key);
    if (!v.is_number_unsigned() && !(v.is_number_integer() && v.get<long long>() >= 0)) {
      fail_key(key, "expected a non-negative integer");
    }
    return v.get<std::uint64_t>();
  }
  bool boolean(const std::string& key) const {
    const nlohmann::json& v = raw(key);
    if (!v.is_boolean()) fail_key(key, "expected true or false");
    return v.get<bool>();
  }
  std::string string(const std::string& key) const {
    const nlohmann::json& v = raw(key);
    if (!v.is_string()) fail_key(key, "expected a string");
    return v.get<std::string>();
  }
  /// An array of exactly n finite numbers (n < 0: any length).
  std::vector<double> numbers(const std::string& key, int n) const {
    const nlohmann::json& v = raw(key);
    if (!v.is_array()) fail_key(key, "expected an array of numbers");
    if (n >= 0 && static_cast<int>(v.size()) != n) fail_key(key, "expected " + std::to_string(n) + " numbers");
    std::vector<double> out;
    out.reserve(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (!v[i].is_number()) fail_key(key + "[" + std::to_string(i) + "]", "expected a number");
      const double x = v[i].get<double>();
      if (!std::isfinite(x)) fail_key(key + "[" + std::to_string(i) + "]", "not finite");
      out.push_back(x);
    }
    return out;
  }

 private:
  const nlohmann::json& j_;
  std::string source_;
  std::string path_;
};

}  // namespace floorcast
