#include "floorcast/core/params.hpp"

#include <cmath>

namespace floorcast {
namespace {

std::string num(double d) { return nlohmann::json(d).dump(); }

}  // namespace

ParamReader::ParamReader(const nlohmann::json& overrides, std::string who, std::string prefix)
    : j_(overrides), who_(std::move(who)), prefix_(std::move(prefix)) {
  if (!j_.is_object()) {
    if (prefix_.empty()) throw InputError(who_ + ": parameter overrides must be a JSON object");
    fail(prefix_.substr(0, prefix_.size() - 1), "expected an object");
  }
}

bool ParamReader::take(const char* key) {
  seen_.emplace_back(key);
  if (!j_.contains(key)) return false;
  read_.insert(key);
  return true;
}

void ParamReader::fail(const std::string& key, const std::string& why) const {
  const std::string full = (key.rfind(prefix_, 0) == 0 && !prefix_.empty()) ? key : prefix_ + key;
  throw ParameterError(who_ + ": parameter \"" + full + "\": " + why, full);
}

void ParamReader::read(const char* key, double& value, double lo, double hi) {
  if (!take(key)) return;
  const nlohmann::json& x = j_.at(key);
  if (!x.is_number()) fail(key, "expected a number");
  const double d = x.get<double>();
  if (!std::isfinite(d)) fail(key, "not a finite number");
  if (!(d >= lo && d <= hi)) fail(key, "value " + x.dump() + " outside [" + num(lo) + ", " + num(hi) + "]");
  value = d;
}

void ParamReader::read(const char* key, int& value, int lo, int hi) {
  if (!take(key)) return;
  const nlohmann::json& x = j_.at(key);
  if (!x.is_number_integer()) fail(key, "expected an integer");
  const long long d = x.get<long long>();
  if (d < lo || d > hi) {
    fail(key, "value " + x.dump() + " outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }
  value = static_cast<int>(d);
}

void ParamReader::read(const char* key, std::uint64_t& value) {
  if (!take(key)) return;
  const nlohmann::json& x = j_.at(key);
  if (!x.is_number_unsigned() && !(x.is_number_integer() && x.get<long long>() >= 0)) {
    fail(key, "expected a non-negative integer");
  }
  value = x.get<std::uint64_t>();
}

void ParamReader::read(const char* key, bool& value) {
  if (!take(key)) return;
  const nlohmann::json& x = j_.at(key);
  if (!x.is_boolean()) fail(key, "expected true or false");
  value = x.get<bool>();
}

void ParamReader::read(const char* key, std::string& value) {
  if (!take(key)) return;
  const nlohmann::json& x = j_.at(key);
  if (!x.is_string()) fail(key, "expected a string");
  value = x.get<std::string>();
}

void ParamReader::read(const char* key, std::vector<double>& value, double lo, double hi) {
  if (!take(key)) return;
  const nlohmann::json& x = j_.at(key);
  if (!x.is_array() || x.empty()) fail(key, "expected a non-empty array of numbers");
  std::vector<double> out;
  for (const nlohmann::json& e : x) {
    if (!e.is_number() || !std::isfinite(e.get<double>())) fail(key, "expected a non-empty array of finite numbers");
    const double d = e.get<double>();
    if (!(d >= lo && d <= hi)) fail(key, "value " + e.dump() + " outside [" + num(lo) + ", " + num(hi) + "]");
    out.push_back(d);
  }
  value = std::move(out);
}

void ParamReader::finish() const {
  for (auto it = j_.begin(); it != j_.end(); ++it) {
    if (!read_.count(it.key())) {
      std::string known;
      for (const std::string& k : seen_) known += (known.empty() ? "" : ", ") + k;
      const std::string full = prefix_ + it.key();
      throw ParameterError(who_ + ": unknown parameter \"" + full + "\" (known: " + known + ")", full);
    }
  }
}

void write_blocking(nlohmann::ordered_json& j, const BlockingOptions& b) {
  j["doors_closed"] = b.open_doors_block;
  j["glass_blocks"] = b.glass_blocks;
  j["obstacles_block"] = b.obstacles_block;
  j["cut_height_m"] = b.cut_height_m;
}

void read_blocking(ParamReader& r, BlockingOptions& b) {
  r.read("doors_closed", b.open_doors_block);
  r.read("glass_blocks", b.glass_blocks);
  r.read("obstacles_block", b.obstacles_block);
  r.read("cut_height_m", b.cut_height_m, 0.0, 100.0);
}

nlohmann::ordered_json to_json(const SharedParams& shared) {
  nlohmann::ordered_json j;
  j["range_m"] = shared.range_m;
  write_blocking(j, shared.blocking);
  return j;
}

void apply_overrides(SharedParams& shared, const nlohmann::json& overrides, const std::string& who) {
  ParamReader r(overrides, who);
  r.read("range_m", shared.range_m, 0.1, 1000.0);
  read_blocking(r, shared.blocking);
  r.finish();
}

}  // namespace floorcast
